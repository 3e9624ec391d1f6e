// Reading a YAML document into typed, validated values, with file:line:column in every error
// (docs/architecture.md, principles 4 and 5). A YamlValue is one node of the document together with
// its dotted key path ("gear.teeth") and file; it converts itself strictly (integers are digits,
// numbers are finite, booleans are true/false, quoted text is never a number). A YamlMap is a
// mapping whose allowed keys are declared when it is opened, so unknown keys (with a "did you
// mean" hint), duplicate keys, wrong types, out-of-range values and missing required keys all
// become InputErrors in one uniform way. Every section parser of a scenario uses it.
// Engine-internal: only engine sources include it (it exposes yaml-cpp types).
#pragma once

#include <yaml-cpp/yaml.h>

#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "core/input_error.h"

namespace gearmc {

// The allowed values of a real number, with the words used in messages.
struct NumberRange {
  double min = -std::numeric_limits<double>::infinity();
  double max = std::numeric_limits<double>::infinity();
  bool min_inclusive = true;
  bool max_inclusive = true;

  static NumberRange any() { return {}; }
  static NumberRange positive() { return {0.0, kInf, false, true}; }     // > 0
  static NumberRange non_negative() { return {0.0, kInf, true, true}; }  // >= 0
  static NumberRange closed(double lo, double hi) { return {lo, hi, true, true}; }
  static NumberRange open(double lo, double hi) { return {lo, hi, false, false}; }
  // A probability p that a computation can use with its complement: p and 1 − p both at least
  // 1e-9 (1 − 1e-300 is 1 in a double, where a test of level 1 − p has nothing left).
  static NumberRange probability() { return closed(1e-9, 1.0 - 1e-9); }

  bool contains(double value) const;
  // "a number", "a number > 0", "a number >= 0", "a number from -1.5 to 3",
  // "a number > 0 and < 45", …
  std::string describe() const;

 private:
  static constexpr double kInf = std::numeric_limits<double>::infinity();
};

// "an integer", "an integer from 5 to 1000", "an integer >= 0", …
std::string describe_integer_range(std::int64_t min, std::int64_t max);

class YamlMap;

// One node of a document: the YAML node, its dotted key path and where it is.
class YamlValue {
 public:
  // `key_location`: where the key naming this value is (the node itself for a document root).
  YamlValue(YAML::Node node, std::string path, std::string file, InputLocation key_location);

  const YAML::Node& node() const { return node_; }
  const std::string& path() const { return path_; }  // "" for the document root
  const std::string& file() const { return file_; }
  // Where the value is; a null value without text of its own (`key:` and nothing) is placed at
  // its key.
  InputLocation location() const;
  const InputLocation& key_location() const { return key_location_; }

  bool is_null() const { return node_.IsNull(); }
  bool is_scalar() const { return node_.IsScalar(); }
  bool is_map() const { return node_.IsMap(); }
  bool is_sequence() const { return node_.IsSequence(); }
  // Written in quotes (or tagged !!str): text, never a number or a boolean.
  bool is_quoted() const;
  // The value as messages show it: scalars verbatim, null as "null", maps and sequences in
  // flow style (InputError escapes and shortens it, see shown_input).
  std::string shown() const;

  // An InputError at this value: "<file>:<l>:<c>: <path>: got '<shown>', expected <expected>".
  InputError error(const std::string& expected, const std::string& hint = "") const;

  // Conversions; each throws InputError (at the value) when the value is not what is asked for.
  std::string as_string() const;  // any scalar, plain or quoted
  std::int64_t as_int(std::int64_t min = std::numeric_limits<std::int64_t>::min(),
                      std::int64_t max = std::numeric_limits<std::int64_t>::max()) const;
  std::uint64_t as_uint64() const;  // 0 … 2^64 - 1
  // A finite number within `range`; `note` is added to the expectation in parentheses.
  double as_number(const NumberRange& range = NumberRange::any(),
                   const std::string& note = "") const;
  bool as_bool() const;  // true/True/TRUE/false/False/FALSE, unquoted
  // One of `choices` exactly, with a "did you mean" hint otherwise.
  std::string as_choice(const std::vector<std::string>& choices) const;
  // A mapping whose keys must all be among `keys` (in the order messages list them).
  YamlMap as_map(const std::vector<std::string>& keys) const;
  // A mapping with any (distinct, scalar) keys; the caller checks them (see YamlMap::entries).
  YamlMap as_open_map() const;
  // A sequence; element i has the path "<path>[i]".
  std::vector<YamlValue> as_sequence() const;

 private:
  YAML::Node node_;
  std::string path_;
  std::string file_;
  InputLocation key_location_;
};

// A mapping being read. Keys are looked up by name; the typed getters return nullopt when the
// key is absent and throw InputError when it is present but wrong.
class YamlMap {
 public:
  struct Entry {
    std::string key;
    YamlValue value;  // value.key_location() is where the key is
  };

  const std::string& path() const { return self_.path(); }
  const std::string& file() const { return self_.file(); }
  // Where missing-key errors point: the key naming this map (the map itself for the root).
  const InputLocation& location() const { return self_.key_location(); }
  const YamlValue& self() const { return self_; }
  const std::vector<Entry>& entries() const { return entries_; }  // document order

  // Checks that every key is among `keys` (else InputError at the first unknown key, with a
  // "did you mean"); after that only those keys may be looked up.
  void restrict_keys(const std::vector<std::string>& keys);

  bool has(const std::string& key) const;
  std::optional<YamlValue> find(const std::string& key) const;
  // The value of a required key; absent: InputError at location() saying `expected`.
  YamlValue require(const std::string& key, const std::string& expected) const;
  InputError missing(const std::string& key, const std::string& expected) const;
  // The dotted path of a child key.
  std::string child_path(const std::string& key) const;

  // Typed shortcuts: find(key) + the conversion of the same name.
  std::optional<std::int64_t> get_int(
      const std::string& key, std::int64_t min = std::numeric_limits<std::int64_t>::min(),
      std::int64_t max = std::numeric_limits<std::int64_t>::max()) const;
  std::int64_t require_int(const std::string& key,
                           std::int64_t min = std::numeric_limits<std::int64_t>::min(),
                           std::int64_t max = std::numeric_limits<std::int64_t>::max()) const;
  std::optional<std::uint64_t> get_uint64(const std::string& key) const;
  std::optional<double> get_number(const std::string& key,
                                   const NumberRange& range = NumberRange::any(),
                                   const std::string& note = "") const;
  double require_number(const std::string& key, const NumberRange& range = NumberRange::any(),
                        const std::string& note = "") const;
  std::optional<bool> get_bool(const std::string& key) const;
  std::optional<std::string> get_string(const std::string& key) const;
  std::optional<std::string> get_choice(const std::string& key,
                                        const std::vector<std::string>& choices) const;
  std::optional<YamlMap> get_map(const std::string& key,
                                 const std::vector<std::string>& keys) const;
  YamlMap require_map(const std::string& key, const std::vector<std::string>& keys) const;

 private:
  friend class YamlValue;
  explicit YamlMap(YamlValue self);  // reads the entries, rejects duplicate and non-scalar keys
  void check_lookup(const std::string& key) const;

  YamlValue self_;
  std::vector<Entry> entries_;
  std::vector<std::string> allowed_keys_;  // empty = any (an open map)
};

// Parses one YAML document. Syntax errors become InputErrors at yaml-cpp's line and column
// (1-based here); a stream with several documents is an error. An empty document (no text or
// only comments) gives a null root placed at 1:1.
YamlValue parse_yaml_document(const std::string& text, const std::string& file);

}  // namespace gearmc
