// What made an output file, written into every output (summary.json, diagnosis.json, the
// reports, the CSV headers) so that a result found later can be traced and reproduced: the
// gearmc version and git commit, the UTC time, the command line and the input file with a
// fingerprint of its content (64-bit FNV-1a of the bytes, Fowler–Noll–Vo, as in
// draft-eastlake-fnv; a change detector, not a cryptographic hash).
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <string_view>

namespace gearmc {

struct Provenance {
  std::string version;       // "0.1.0"
  std::string git_hash;      // build commit, see version.h
  std::string created_utc;   // "2026-11-22T20:55:00Z"
  std::string command_line;  // as typed, arguments with spaces or quotes single-quoted
  std::string input_path;    // the scenario (or model) file; "<built-in>" for the reference
  std::string input_hash;    // "fnv1a64:0123456789abcdef" of the file's text; "" without input
};

// "fnv1a64:" + 16 hex digits of the 64-bit FNV-1a hash of `bytes`.
std::string fnv1a64_text(std::string_view bytes);

// The command line from argv, each argument shell-quoted when it needs it.
std::string command_line_text(int argc, const char* const* argv);

// Now, this build, and the input (`input_text` hashed; empty path and text: no input).
Provenance make_provenance(std::string command_line, std::string input_path,
                           std::string_view input_text);

// {"gearmc": version, "git": hash, "created_utc", "command", "input", "input_hash"}.
nlohmann::ordered_json provenance_json(const Provenance& p);
// One line: "gearmc 0.1.0 (git …), 2026-11-22T20:55:00Z, command: …, input: path (fnv1a64:…)".
std::string provenance_line(const Provenance& p);

}  // namespace gearmc
