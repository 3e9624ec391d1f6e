// Strict, located conversions of YAML nodes into typed values and the declared-keys mapping
// reader (see yaml_reader.h). Every failure is an InputError naming file:line:column (yaml-cpp
// marks are 0-based; messages are 1-based), the dotted key, the value and what was expected.
#include "core/yaml_reader.h"

#include <yaml-cpp/eventhandler.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <sstream>
#include <system_error>
#include <utility>

#include "core/check.h"
#include "core/number_text.h"

namespace gearmc {
namespace {

InputLocation location_of(const YAML::Mark& mark, const std::string& file) {
  if (mark.is_null()) return {file, 0, 0};
  return {file, mark.line + 1, mark.column + 1};
}

std::string join(const std::vector<std::string>& words, const std::string& separator) {
  std::string out;
  for (const std::string& word : words) out += (out.empty() ? "" : separator) + word;
  return out;
}

// Strict integer syntax: an optional sign and decimal digits, nothing else (no 0x, 0o, 1e3, 2.0,
// "1_000"). Returns false when the text is not of that form; sets *overflow when it is but does
// not fit.
template <typename Int>
bool parse_integer(const std::string& text, Int* value, bool* overflow) {
  *overflow = false;
  const char* begin = text.data();
  const char* end = begin + text.size();
  if (begin != end && *begin == '+') ++begin;
  const char* digits = begin != end && *begin == '-' ? begin + 1 : begin;
  if (digits == end || !std::all_of(digits, end, [](char c) { return c >= '0' && c <= '9'; })) {
    return false;
  }
  const auto result = std::from_chars(begin, end, *value);
  if (result.ec == std::errc::result_out_of_range) {
    *overflow = true;
    return true;
  }
  return result.ec == std::errc() && result.ptr == end;
}

// Strict number syntax: what std::from_chars accepts in general format, with an optional
// leading '+', wholly consumed; finite.
bool parse_number(const std::string& text, double* value) {
  const char* begin = text.data();
  const char* end = begin + text.size();
  if (begin != end && *begin == '+') ++begin;
  if (begin == end || *begin == '+') return false;
  const auto result = std::from_chars(begin, end, *value, std::chars_format::general);
  return result.ec == std::errc() && result.ptr == end && std::isfinite(*value);
}

std::string quoted_note(const YamlValue& value) {
  return value.is_quoted() ? ", written without quotes" : "";
}

// Records where each document of a stream starts; ignores everything else.
class DocumentStarts : public YAML::EventHandler {
 public:
  std::vector<YAML::Mark> starts;
  void OnDocumentStart(const YAML::Mark& mark) override { starts.push_back(mark); }
  void OnDocumentEnd() override {}
  void OnNull(const YAML::Mark&, YAML::anchor_t) override {}
  void OnAlias(const YAML::Mark&, YAML::anchor_t) override {}
  void OnScalar(const YAML::Mark&, const std::string&, YAML::anchor_t,
                const std::string&) override {}
  void OnSequenceStart(const YAML::Mark&, const std::string&, YAML::anchor_t,
                       YAML::EmitterStyle::value) override {}
  void OnSequenceEnd() override {}
  void OnMapStart(const YAML::Mark&, const std::string&, YAML::anchor_t,
                  YAML::EmitterStyle::value) override {}
  void OnMapEnd() override {}
};

}  // namespace

// ---- NumberRange ----------------------------------------------------------------------------

bool NumberRange::contains(double value) const {
  const bool above = min_inclusive ? value >= min : value > min;
  const bool below = max_inclusive ? value <= max : value < max;
  return above && below;
}

std::string NumberRange::describe() const {
  const bool has_min = std::isfinite(min);
  const bool has_max = std::isfinite(max);
  const std::string lower = (min_inclusive ? ">= " : "> ") + shortest_text(min);
  const std::string upper = (max_inclusive ? "<= " : "< ") + shortest_text(max);
  if (has_min && has_max) {
    if (min_inclusive && max_inclusive) {
      return "a number from " + shortest_text(min) + " to " + shortest_text(max);
    }
    return "a number " + lower + " and " + upper;
  }
  if (has_min) return "a number " + lower;
  if (has_max) return "a number " + upper;
  return "a number";
}

std::string describe_integer_range(std::int64_t min, std::int64_t max) {
  constexpr auto kLowest = std::numeric_limits<std::int64_t>::min();
  constexpr auto kHighest = std::numeric_limits<std::int64_t>::max();
  if (min == kLowest && max == kHighest) return "an integer";
  if (min == kLowest) return "an integer <= " + std::to_string(max);
  if (max == kHighest) return "an integer >= " + std::to_string(min);
  return "an integer from " + std::to_string(min) + " to " + std::to_string(max);
}

// ---- YamlValue ------------------------------------------------------------------------------

YamlValue::YamlValue(YAML::Node node, std::string path, std::string file,
                     InputLocation key_location)
    : node_(std::move(node)),
      path_(std::move(path)),
      file_(std::move(file)),
      key_location_(std::move(key_location)) {}

InputLocation YamlValue::location() const {
  const YAML::Mark mark = node_.Mark();
  if (mark.is_null()) return key_location_;
  InputLocation where = location_of(mark, file_);
  // yaml-cpp places the null of `key:` (nothing after the colon) at the next token, often on a
  // later line; the key is the better place then.
  if (node_.IsNull() && key_location_.line > 0 && where.line != key_location_.line) {
    return key_location_;
  }
  return where;
}

bool YamlValue::is_quoted() const {
  const std::string& tag = node_.Tag();
  return node_.IsScalar() && (tag == "!" || tag == "tag:yaml.org,2002:str");
}

std::string YamlValue::shown() const {
  if (!node_.IsDefined() || node_.IsNull()) return "null";
  if (node_.IsScalar()) return node_.Scalar();
  YAML::Emitter emitter;
  emitter.SetSeqFormat(YAML::Flow);
  emitter.SetMapFormat(YAML::Flow);
  emitter << node_;
  return emitter.c_str();
}

InputError YamlValue::error(const std::string& expected, const std::string& hint) const {
  return InputError(location(), path_, shown(), expected, hint);
}

std::string YamlValue::as_string() const {
  if (!node_.IsScalar()) throw error("a string");
  return node_.Scalar();
}

std::int64_t YamlValue::as_int(std::int64_t min, std::int64_t max) const {
  const std::string expected = describe_integer_range(min, max);
  if (!node_.IsScalar() || is_quoted()) throw error(expected + quoted_note(*this));
  std::int64_t value = 0;
  bool overflow = false;
  if (!parse_integer(node_.Scalar(), &value, &overflow) || overflow || value < min || value > max) {
    throw error(expected);
  }
  return value;
}

std::uint64_t YamlValue::as_uint64() const {
  const std::string expected =
      "an integer from 0 to " + std::to_string(std::numeric_limits<std::uint64_t>::max());
  if (!node_.IsScalar() || is_quoted()) throw error(expected + quoted_note(*this));
  std::uint64_t value = 0;
  bool overflow = false;
  if (!parse_integer(node_.Scalar(), &value, &overflow) || overflow) throw error(expected);
  return value;
}

double YamlValue::as_number(const NumberRange& range, const std::string& note) const {
  std::string expected = range.describe();
  if (!note.empty()) expected += " (" + note + ")";
  if (!node_.IsScalar() || is_quoted()) throw error(expected + quoted_note(*this));
  double value = 0.0;
  if (!parse_number(node_.Scalar(), &value) || !range.contains(value)) throw error(expected);
  return value;
}

bool YamlValue::as_bool() const {
  const std::string expected = "true or false";
  if (!node_.IsScalar() || is_quoted()) throw error(expected + quoted_note(*this));
  const std::string& text = node_.Scalar();
  if (text == "true" || text == "True" || text == "TRUE") return true;
  if (text == "false" || text == "False" || text == "FALSE") return false;
  throw error(expected);
}

std::string YamlValue::as_choice(const std::vector<std::string>& choices) const {
  const std::string expected = "one of " + join(choices, ", ");
  if (!node_.IsScalar()) throw error(expected);
  const std::string& text = node_.Scalar();
  if (std::find(choices.begin(), choices.end(), text) != choices.end()) return text;
  throw error(expected, did_you_mean(text, choices));
}

YamlMap YamlValue::as_map(const std::vector<std::string>& keys) const {
  YamlMap map = as_open_map();
  map.restrict_keys(keys);
  return map;
}

YamlMap YamlValue::as_open_map() const {
  if (!node_.IsMap()) throw error("a map of keys and values");
  return YamlMap(*this);
}

std::vector<YamlValue> YamlValue::as_sequence() const {
  if (!node_.IsSequence()) throw error("a sequence (a list)");
  std::vector<YamlValue> items;
  int index = 0;
  for (const YAML::Node& item : node_) {
    InputLocation where = location_of(item.Mark(), file_);
    if (where.line == 0) where = location();
    items.emplace_back(item, path_ + "[" + std::to_string(index++) + "]", file_, where);
  }
  return items;
}

// ---- YamlMap --------------------------------------------------------------------------------

YamlMap::YamlMap(YamlValue self) : self_(std::move(self)) {
  for (auto it = self_.node().begin(); it != self_.node().end(); ++it) {
    InputLocation key_where = location_of(it->first.Mark(), file());
    if (key_where.line == 0) key_where = self_.location();
    const YamlValue key(it->first, path(), file(), key_where);
    if (!it->first.IsScalar()) throw key.error("a plain key (text)");
    const std::string key_text = it->first.Scalar();
    for (const Entry& earlier : entries_) {
      if (earlier.key == key_text) {
        throw InputError(key_where, child_path(key_text), "",
                         "each key only once (it is already given at line " +
                             std::to_string(earlier.value.key_location().line) + ")");
      }
    }
    entries_.push_back({key_text, YamlValue(it->second, child_path(key_text), file(), key_where)});
  }
}

std::string YamlMap::child_path(const std::string& key) const {
  return path().empty() ? key : path() + "." + key;
}

void YamlMap::restrict_keys(const std::vector<std::string>& keys) {
  GEARMC_CHECK(!keys.empty(), "a restricted map needs its allowed keys");
  for (const Entry& entry : entries_) {
    if (std::find(keys.begin(), keys.end(), entry.key) != keys.end()) continue;
    const std::string owner = path().empty() ? "the top level" : path();
    throw InputError(entry.value.key_location(), entry.value.path(), entry.key,
                     "a known key (" + owner + " has: " + join(keys, ", ") + ")",
                     did_you_mean(entry.key, keys));
  }
  allowed_keys_ = keys;
}

void YamlMap::check_lookup(const std::string& key) const {
  // Looking up an undeclared key is a parser bug: it could never be given.
  GEARMC_CHECK(allowed_keys_.empty() || std::find(allowed_keys_.begin(), allowed_keys_.end(),
                                                  key) != allowed_keys_.end(),
               "a key looked up that the map did not declare");
}

bool YamlMap::has(const std::string& key) const { return find(key).has_value(); }

std::optional<YamlValue> YamlMap::find(const std::string& key) const {
  check_lookup(key);
  for (const Entry& entry : entries_) {
    if (entry.key == key) return entry.value;
  }
  return std::nullopt;
}

InputError YamlMap::missing(const std::string& key, const std::string& expected) const {
  return InputError(location(), child_path(key), "", expected + " (required key is missing)");
}

YamlValue YamlMap::require(const std::string& key, const std::string& expected) const {
  std::optional<YamlValue> value = find(key);
  if (!value) throw missing(key, expected);
  return *value;
}

std::optional<std::int64_t> YamlMap::get_int(const std::string& key, std::int64_t min,
                                             std::int64_t max) const {
  const std::optional<YamlValue> value = find(key);
  if (!value) return std::nullopt;
  return value->as_int(min, max);
}

std::int64_t YamlMap::require_int(const std::string& key, std::int64_t min,
                                  std::int64_t max) const {
  return require(key, describe_integer_range(min, max)).as_int(min, max);
}

std::optional<std::uint64_t> YamlMap::get_uint64(const std::string& key) const {
  const std::optional<YamlValue> value = find(key);
  if (!value) return std::nullopt;
  return value->as_uint64();
}

std::optional<double> YamlMap::get_number(const std::string& key, const NumberRange& range,
                                          const std::string& note) const {
  const std::optional<YamlValue> value = find(key);
  if (!value) return std::nullopt;
  return value->as_number(range, note);
}

double YamlMap::require_number(const std::string& key, const NumberRange& range,
                               const std::string& note) const {
  return require(key, range.describe()).as_number(range, note);
}

std::optional<bool> YamlMap::get_bool(const std::string& key) const {
  const std::optional<YamlValue> value = find(key);
  if (!value) return std::nullopt;
  return value->as_bool();
}

std::optional<std::string> YamlMap::get_string(const std::string& key) const {
  const std::optional<YamlValue> value = find(key);
  if (!value) return std::nullopt;
  return value->as_string();
}

std::optional<std::string> YamlMap::get_choice(const std::string& key,
                                               const std::vector<std::string>& choices) const {
  const std::optional<YamlValue> value = find(key);
  if (!value) return std::nullopt;
  return value->as_choice(choices);
}

std::optional<YamlMap> YamlMap::get_map(const std::string& key,
                                        const std::vector<std::string>& keys) const {
  const std::optional<YamlValue> value = find(key);
  if (!value) return std::nullopt;
  return value->as_map(keys);
}

YamlMap YamlMap::require_map(const std::string& key, const std::vector<std::string>& keys) const {
  return require(key, "a map with the keys " + join(keys, ", ")).as_map(keys);
}

// ---- documents ------------------------------------------------------------------------------

YamlValue parse_yaml_document(const std::string& text, const std::string& file) {
  YAML::Node document;
  std::vector<YAML::Mark> starts;
  try {
    document = YAML::Load(text);
    // Where the documents start: the first two are enough. (YAML::LoadAll never returns on
    // a stray ',' at the top level of yaml-cpp 0.7: its parser reports empty documents
    // forever; counting with a bound cannot hang.)
    std::istringstream in(text);
    YAML::Parser parser(in);
    DocumentStarts handler;
    while (handler.starts.size() < 2 && parser.HandleNextDocument(handler)) {
    }
    starts = handler.starts;
  } catch (const YAML::Exception& e) {
    const InputLocation where = location_of(e.mark, file);
    // yaml-cpp quotes the offending character raw (e.g. a newline after a backslash).
    throw InputError(where, "invalid YAML: " + shown_input(e.msg, 2 * kShownChars));
  }
  if (starts.empty()) {  // no text or only comments
    return YamlValue(YAML::Node(), "", file, {file, 1, 1});
  }
  if (starts.size() > 1) {
    throw InputError(location_of(starts[1], file), "", "",
                     "one YAML document, found a second one (a line '---' or a stray ',' "
                     "starts it)");
  }
  InputLocation root_where = location_of(document.Mark(), file);
  if (root_where.line == 0) root_where = {file, 1, 1};
  return YamlValue(document, "", file, root_where);
}

}  // namespace gearmc
