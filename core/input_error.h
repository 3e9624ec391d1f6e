// The one error type for bad user input (docs/architecture.md, principle 4): it names the place
// (file:line:column, or file:line for CSV), the key, the offending value and what was expected.
// main() catches it, prints what() and exits with code 2.
// Public API (docs/api.md): a stable part of the C++ interface, installed with its includes.
#pragma once

#include <cstddef>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace gearmc {

struct InputLocation {
  std::string file;
  int line = 0;    // 1-based; 0 = unknown
  int column = 0;  // 1-based; 0 = unknown
};

class InputError : public std::runtime_error {
 public:
  // Message: "<file>:<line>:<col>: <key>: got '<value>', expected <expected>[; did you mean
  // '<hint>'?]". Empty parts are left out; key, value and hint are shown with shown_input.
  InputError(InputLocation where, std::string key, std::string value, std::string expected,
             std::string hint = "");
  // A message that already says everything (e.g. an unreadable file).
  InputError(InputLocation where, std::string message);

  const InputLocation& where() const { return where_; }
  const std::string& key() const { return key_; }

 private:
  InputLocation where_;
  std::string key_;
};

// Input text as messages echo it: one line of printable text. Control bytes become C escapes
// (\n, \r, \t, else \xNN), bytes that are not UTF-8 become \xNN, valid UTF-8 characters stay;
// more than `max_chars` characters (after escaping) are cut to that many plus "…". Every
// InputError applies it to the value and the key it echoes.
inline constexpr std::size_t kShownChars = 60;
std::string shown_input(std::string_view text, std::size_t max_chars = kShownChars);

// The closest of `candidates` to `word` by edit distance, if close enough to be a likely typo
// (distance <= max(2, |word|/3)), else the only candidate that starts with `word` (3+ letters);
// empty otherwise.
std::string did_you_mean(const std::string& word, const std::vector<std::string>& candidates);

}  // namespace gearmc
