// Shared by the diagnosis tests: readings of the nominal master (P1's gear, the built-in
// reference's 10 × 5 grid on every flank) simulated from a truth scenario = the reference + some
// effects, the baseline model (the reference with probing noise σ 0.3 µm only), and look-ups in a
// diagnosis's fitted effects.
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "core/yaml_reader.h"
#include "engine/apps/diagnose/diagnosis.h"
#include "engine/effects/effect_config.h"
#include "engine/effects/measurement_effect.h"
#include "engine/run/simulate.h"
#include "engine/scenario/scenario.h"

namespace gearmc::testing_support {

inline constexpr double kNoiseUm = 0.3;  // the battery's probing noise σ 0.3 µm (docs/diagnosis.md)

inline Scenario with_effects(const std::string& effects_yaml) {
  Scenario s = reference_scenario();
  s.effects = std::make_shared<const EffectChain>(
      parse_effects(parse_yaml_document(effects_yaml, "effects.yaml")));
  return s;
}

// Readings of the nominal master (P1's gear, 2 400 points) with the truth's effects.
inline Readings master_readings(Scenario truth, std::uint64_t seed = 1) {
  SimulateOptions o;
  o.master = true;
  truth.seed = seed;
  return simulate_readings(truth, o).readings;
}

// Truth = the reference + `effect_yaml` + noise 0.3 µm.
inline Readings hidden(const std::string& effect_yaml, std::uint64_t seed = 1) {
  return master_readings(with_effects(effect_yaml + "noise: {sigma_um: 0.3}\n"), seed);
}

inline Scenario baseline() { return with_effects("noise: {sigma_um: 0.3}\n"); }

inline const FittedValue& value(const FittedEffect& e, const std::string& name) {
  for (const FittedValue& v : e.parameters) {
    if (v.name == name) return v;
  }
  for (const FittedValue& v : e.coefficients) {
    if (v.name == name) return v;
  }
  ADD_FAILURE() << "no parameter " << name << " in " << e.name;
  static const FittedValue none;
  return none;
}

inline bool contains(const std::vector<std::string>& list, const std::string& name) {
  return std::find(list.begin(), list.end(), name) != list.end();
}

}  // namespace gearmc::testing_support
