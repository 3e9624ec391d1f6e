// The one error type for bad user input (docs/architecture.md, principle 4): composes its message
// from the place (file:line:column), the dotted key, the offending value, what was expected and an
// optional "did you mean" hint; and the edit-distance search behind those hints.
#include "core/input_error.h"

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

std::string compose_message(const InputLocation& where, const std::string& raw_key,
                            const std::string& raw_value, const std::string& expected,
                            const std::string& raw_hint) {
  const std::string key = shown_input(raw_key, 2 * kShownChars);
  const std::string value = shown_input(raw_value);
  const std::string hint = shown_input(raw_hint);
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

std::string shown_input(std::string_view text, std::size_t max_chars) {
  static constexpr char kHex[] = "0123456789ABCDEF";
  std::string out;
  std::size_t chars = 0;
  std::size_t i = 0;
  const auto byte = [&](std::size_t k) { return static_cast<unsigned char>(text[k]); };
  while (i < text.size()) {
    if (chars >= max_chars) return out + "\u2026";
    const unsigned char b = byte(i);
    std::string piece;
    std::size_t used = 1;
    if (b == '\n') {
      piece = "\\n";
    } else if (b == '\r') {
      piece = "\\r";
    } else if (b == '\t') {
      piece = "\\t";
    } else if (b < 0x20 || b == 0x7F) {
      piece = {'\\', 'x', kHex[b >> 4], kHex[b & 15]};
    } else if (b < 0x80) {
      piece = std::string(1, static_cast<char>(b));
    } else {
      // A well-formed UTF-8 sequence stays as it is; any other byte is shown in hex.
      const std::size_t length = b >= 0xF0 ? 4 : b >= 0xE0 ? 3 : b >= 0xC0 ? 2 : 0;
      bool valid = length > 0 && i + length <= text.size() && b >= 0xC2 && b <= 0xF4;
      for (std::size_t k = 1; valid && k < length; ++k) valid = (byte(i + k) & 0xC0) == 0x80;
      if (valid && length == 3) {
        valid = !(b == 0xE0 && byte(i + 1) < 0xA0) && !(b == 0xED && byte(i + 1) > 0x9F);
      }
      if (valid && length == 4) {
        valid = !(b == 0xF0 && byte(i + 1) < 0x90) && !(b == 0xF4 && byte(i + 1) > 0x8F);
      }
      if (valid) {
        piece = std::string(text.substr(i, length));
        used = length;
      } else {
        piece = {'\\', 'x', kHex[b >> 4], kHex[b & 15]};
      }
    }
    out += piece;
    chars += used > 1 ? 1 : piece.size();  // a UTF-8 character counts as one
    i += used;
  }
  return out;
}

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
