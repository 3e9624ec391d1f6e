// The `effects:` section of a scenario (README "Measurement effects"): which effects are on,
// their parameters (a number, or a law drawn once per gear: {uniform: [lo, hi]} or
// {normal: [mean, sd]}) and settings, read strictly into an EffectChain.
// Engine-internal (exposes the YAML reader).
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "core/yaml_reader.h"
#include "engine/effects/measurement_effect.h"

namespace gearmc {

// Effect names the section accepts, in the order the README lists them.
const std::vector<std::string>& effect_names();

// Reads `effects:` (a map from effect name to its map of parameters); throws InputError with
// file:line:column for unknown effects or keys, wrong types and out-of-range values.
// An effect with `enabled: false` is left out. Every parameter is checked against its plausible
// range (effect_ranges()); values outside the usual range append a warning to `warnings`.
EffectChain parse_effects(const YamlValue& section, std::vector<std::string>* warnings = nullptr);

}  // namespace gearmc
