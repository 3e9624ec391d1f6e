// Plausible ranges of every physical number a scenario or a readings file gives. Each number
// has a valid range (outside it: an InputError naming the key, the value and the range) and a
// usual range (outside it but valid: a warning at the key), with the reason for both; numbers
// that parse but are almost surely a unit slip (radians for degrees, mm for µm) carry the hint.
// One table per section, so the reference documentation can be generated from them
// (all_range_tables()). The tables are data shared by three readers (scenario, effects and
// readings), so they live with the scenario key table in the lowest engine layer (engine/schema):
// no reader has to reach sideways into another for its ranges, and the reference page has one
// source.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "core/yaml_reader.h"

namespace gearmc {

// Which side of the usual (or valid) range a unit slip lands a value on: a percentage for a
// fraction, nm for µm or a temperature for its difference are too large, mm for µm too small.
// The hint is given only for a value on its side (a lower-tail quantile 0.025 is no percentage).
enum class SlipSide { kEither, kAbove, kBelow };

struct ParameterRange {
  std::string key;              // dotted path as messages show it, e.g. "gear.module_mm"
  std::string unit;             // "mm", "deg", "µm", … ("" for a pure number)
  NumberRange valid;            // outside: InputError
  double usual_min, usual_max;  // outside but valid: a warning
  std::string why;              // the source or reasoning behind both ranges
  std::string slip;             // the likely unit slip of a value outside the usual range
  bool integer = false;         // an integer key (its valid range is still given as numbers)
  SlipSide slip_side = SlipSide::kEither;
  // The slip hint for `value` ("" when the value is not on the slip's side).
  std::string slip_for(double value) const {
    const bool above = value > usual_max || value > valid.max;
    const bool below = value < usual_min || value < valid.min;
    if (slip_side == SlipSide::kAbove && !above) return "";
    if (slip_side == SlipSide::kBelow && !below) return "";
    return slip;
  }
};

struct RangeTable {
  std::string section;  // "gear", "tolerances", …
  std::vector<ParameterRange> entries;
  // The entry of `key`; a missing entry is a programming error (std::logic_error).
  const ParameterRange& at(const std::string& key) const;
};

const RangeTable& gear_ranges();
const RangeTable& tolerance_ranges();  // overrides_um: "tolerance" (any symbol) and "E_Hs"
const RangeTable& deviation_ranges();
const RangeTable& probing_ranges();  // probing, stylus, run
const RangeTable& effect_ranges();   // "effects.<effect>.<parameter>"
const RangeTable& machine_ranges();  // "cmm.<key>" (a CMM from its data sheet)
const RangeTable& claim_ranges();    // "claims.<key>" (gearmc check)
const RangeTable& readings_ranges();
std::vector<const RangeTable*> all_range_tables();

// The reference of every ranged number as Markdown (docs/scenario-keys.md is this text; a test
// keeps the two equal): one table per section with the key, unit, valid range, usual range,
// the reason and the unit-slip hint.
std::string range_reference_markdown();

// Collected warnings: each a whole located message ("file:line:col: key: …").
using InputWarnings = std::vector<std::string>;

// The valid range's wording with the unit and reason, as an InputError's "expected" part.
std::string describe_range(const ParameterRange& range);

// A number checked against `range`: InputError outside the valid range (at `value`), a warning
// appended to `warnings` (when not null) outside the usual range.
double read_ranged(const YamlValue& value, const ParameterRange& range, InputWarnings* warnings);
// The same for an integer key (strict integer syntax first, then the range).
std::int64_t read_ranged_int(const YamlValue& value, const ParameterRange& range,
                             InputWarnings* warnings);
std::optional<std::int64_t> get_ranged_int(const YamlMap& map, const std::string& key,
                                           const ParameterRange& range, InputWarnings* warnings);
std::optional<double> get_ranged(const YamlMap& map, const std::string& key,
                                 const ParameterRange& range, InputWarnings* warnings);

// The same check for a number read elsewhere (a CSV field): `where` and `shown` place and echo
// it. Throws InputError outside the valid range; appends a warning outside the usual one.
void check_ranged(double value, const ParameterRange& range, const InputLocation& where,
                  const std::string& shown, InputWarnings* warnings);

}  // namespace gearmc
