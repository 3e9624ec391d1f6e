// Every key a scenario file may hold — maps, lists, strings, booleans, choices and numbers —
// with its type, default and allowed values: the table the scenario readers (scenario.cpp,
// engine/effects/effect_config.cpp) take their key lists, choices and defaults from, so the
// reference page generated from it (docs/scenario-keys.md, scripts/update-docs) cannot drift
// from what is read. The units and ranges of the numbers are in parameter_ranges.h, joined
// here by key.
//
// Keys are dotted paths as messages show them, without list indices: the items of
// `surfaces:` are "surfaces.tooth", …, the harmonics of probe_lobing
// "effects.probe_lobing.harmonics.order", …; the top-level keys have no dot.
#pragma once

#include <optional>
#include <string>
#include <vector>

namespace gearmc {

enum class KeyType {
  kMap,        // a map of the keys below it
  kList,       // a list of maps of the keys below it
  kString,     // free text (a name, a file, an expression, a grade)
  kBoolean,    // true / false
  kChoice,     // one of `allowed`
  kInteger,    // an integer (range: parameter_ranges.h or `integer_min … integer_max`)
  kNumber,     // a number (range: parameter_ranges.h)
  kParameter,  // a number or a per-gear law {uniform: [lo, hi]} / {normal: [mean, sd]}
  kSymbolMap,  // a map from names (the symbols listed in `allowed`) to numbers
  kTeeth,      // `all` or a list of tooth numbers
  kSymbols,    // `all` or a list of names among `allowed`, each once
  kVector3,    // three numbers [x, y, z] (range: parameter_ranges.h, for each)
};

struct ScenarioKey {
  std::string key;
  KeyType type = KeyType::kString;
  // What the reader does without the key: a number the reader uses (default_number), or a
  // sentence ("required", "none", "deviations.distribution", …).
  std::optional<double> default_number;
  std::string default_text;
  // kChoice: the values; kSymbolMap: "<standard>: <its symbols>", one per tolerance standard.
  std::vector<std::string> allowed;
  std::string description;                // what it is, in a few words
  std::string range_key;                  // the parameter_ranges.h entry when not `key`
  long integer_min = 0, integer_max = 0;  // kInteger without a range-table entry
};

// The whole table, in the order of a scenario file (each map's keys in the order the reader
// lists them).
const std::vector<ScenarioKey>& scenario_keys();
// The entry of `key`; a missing entry is a programming error (std::logic_error).
const ScenarioKey& scenario_key(const std::string& key);
// The keys directly under `parent` ("" for the top level), last path component only, in table
// order: the key list a reader passes to YamlValue::as_map.
std::vector<std::string> child_keys(const std::string& parent);
// The values of choice `key`, and its default.
const std::vector<std::string>& key_choices(const std::string& key);
const std::string& choice_default(const std::string& key);
bool boolean_default(const std::string& key);
double number_default(const std::string& key);

// docs/scenario-keys.md: every key of scenario_keys() (type, unit, default, allowed values),
// then the range tables (range_reference_markdown()).
std::string scenario_keys_markdown();

}  // namespace gearmc
