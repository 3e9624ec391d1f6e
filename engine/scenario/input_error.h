// The one error type for bad user input (design.md, principle 4): it names the place
// (file:line:column, or file:line for CSV), the key, the offending value and what was expected.
// main() catches it, prints what() and exits with code 2.
#pragma once

#include <stdexcept>
#include <string>
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
  // '<hint>'?]". Empty parts are left out.
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

// The closest of `candidates` to `word` by edit distance, if close enough to be a likely typo
// (distance <= max(2, |word|/3)), else the only candidate that starts with `word` (3+ letters);
// empty otherwise.
std::string did_you_mean(const std::string& word, const std::vector<std::string>& candidates);

}  // namespace gearmc
