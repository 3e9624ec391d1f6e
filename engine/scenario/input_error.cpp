// The one error type for bad user input (design.md, principle 4): composes its message from the
// place (file:line:column), the dotted key, the offending value, what was expected and an
// optional "did you mean" hint; and the edit-distance search behind those hints.
#include "engine/scenario/input_error.h"

#include <algorithm>
#include <cstddef>
#include <utility>

namespace gearmc {
namespace {

// "file:line:col", "file:line" or "file" (empty parts left out).
std::string location_prefix(const InputLocation& where) {
  std::string prefix = where.file;
  if (where.line > 0) {
    prefix.append(":").append(std::to_string(where.line));
    if (where.column > 0) prefix.append(":").append(std::to_string(where.column));
  }
  return prefix;
}

std::string compose_message(const InputLocation& where, const std::string& key,
                            const std::string& value, const std::string& expected,
                            const std::string& hint) {
  std::string body;
  if (!value.empty()) body = "got '" + value + "'";
  if (!expected.empty()) body += (body.empty() ? "" : ", ") + std::string("expected ") + expected;
  if (!hint.empty())
    body += (body.empty() ? "" : "; ") + std::string("did you mean '") + hint + "'?";
  std::string message;
  for (const std::string& part : {location_prefix(where), key, body}) {
    if (part.empty()) continue;
    message += (message.empty() ? "" : ": ") + part;
  }
  return message;
}

// A free-form message is shown as given when it already starts with the file name; otherwise
// the location is put in front, so every InputError names its place.
std::string place_message(const InputLocation& where, const std::string& message) {
  const std::string prefix = location_prefix(where);
  if (prefix.empty() || message.rfind(where.file, 0) == 0) return message;
  return prefix + ": " + message;
}

// Levenshtein distance (insertions, deletions, substitutions all cost 1), two-row form.
std::size_t edit_distance(const std::string& a, const std::string& b) {
  std::vector<std::size_t> previous(b.size() + 1), current(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) previous[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    current[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t substitution = previous[j - 1] + (a[i - 1] == b[j - 1] ? 0 : 1);
      current[j] = std::min({previous[j] + 1, current[j - 1] + 1, substitution});
    }
    std::swap(previous, current);
  }
  return previous[b.size()];
}

}  // namespace

InputError::InputError(InputLocation where, std::string key, std::string value,
                       std::string expected, std::string hint)
    : std::runtime_error(compose_message(where, key, value, expected, hint)),
      where_(std::move(where)),
      key_(std::move(key)) {}

InputError::InputError(InputLocation where, std::string message)
    : std::runtime_error(place_message(where, message)), where_(std::move(where)) {}

std::string did_you_mean(const std::string& word, const std::vector<std::string>& candidates) {
  const std::size_t limit = std::max<std::size_t>(2, word.size() / 3);
  std::string best;
  std::size_t best_distance = limit + 1;
  for (const std::string& candidate : candidates) {
    const std::size_t distance = edit_distance(word, candidate);
    if (distance < best_distance) {  // strict: the first of equally close candidates wins
      best = candidate;
      best_distance = distance;
    }
  }
  if (!best.empty() || word.size() < 3) return best;
  // A truncated name (radius -> radius_mm, iso_1328_1 -> iso_1328_1_2013): the only candidate
  // that starts with the word.
  for (const std::string& candidate : candidates) {
    if (candidate.rfind(word, 0) == 0) {
      if (!best.empty()) return "";  // ambiguous
      best = candidate;
    }
  }
  return best;
}

}  // namespace gearmc
