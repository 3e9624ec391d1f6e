// Provenance of an output (see provenance.h).
#include "core/provenance.h"

#include <chrono>
#include <cstdint>
#include <cstdio>
#include <ctime>

#include "core/version.h"

namespace gearmc {

std::string fnv1a64_text(std::string_view bytes) {
  // FNV-1a, 64 bit: offset basis 14695981039346656037, prime 1099511628211.
  std::uint64_t h = 14695981039346656037ull;
  for (unsigned char c : bytes) {
    h ^= c;
    h *= 1099511628211ull;
  }
  char text[32];
  std::snprintf(text, sizeof text, "fnv1a64:%016llx", static_cast<unsigned long long>(h));
  return text;
}

std::string command_line_text(int argc, const char* const* argv) {
  std::string line;
  for (int i = 0; i < argc; ++i) {
    const std::string_view a = argv[i];
    if (i > 0) line += ' ';
    const bool plain = !a.empty() && a.find_first_not_of(
                                         "abcdefghijklmnopqrstuvwxyz"
                                         "ABCDEFGHIJKLMNOPQRSTUVWXYZ"
                                         "0123456789-_./=:,+@%") == std::string_view::npos;
    if (plain) {
      line += a;
    } else {
      line += '\'';
      for (char c : a) line += c == '\'' ? std::string("'\\''") : std::string(1, c);
      line += '\'';
    }
  }
  return line;
}

Provenance make_provenance(std::string command_line, std::string input_path,
                           std::string_view input_text) {
  Provenance p;
  p.version = gearmc_version();
  p.git_hash = gearmc_git_hash();
  const std::time_t now = std::chrono::system_clock::to_time_t(std::chrono::system_clock::now());
  std::tm utc{};
  gmtime_r(&now, &utc);
  char stamp[32];
  std::strftime(stamp, sizeof stamp, "%Y-%m-%dT%H:%M:%SZ", &utc);
  p.created_utc = stamp;
  p.command_line = std::move(command_line);
  p.input_path = std::move(input_path);
  if (!p.input_path.empty() || !input_text.empty()) p.input_hash = fnv1a64_text(input_text);
  return p;
}

nlohmann::ordered_json provenance_json(const Provenance& p) {
  return {{"gearmc", p.version},       {"git", p.git_hash},     {"created_utc", p.created_utc},
          {"command", p.command_line}, {"input", p.input_path}, {"input_hash", p.input_hash}};
}

std::string provenance_line(const Provenance& p) {
  std::string line = "gearmc " + p.version + " (git " + p.git_hash + "), " + p.created_utc;
  if (!p.command_line.empty()) line += ", command: " + p.command_line;
  if (!p.input_path.empty()) line += ", input: " + p.input_path + " (" + p.input_hash + ")";
  return line;
}

}  // namespace gearmc
