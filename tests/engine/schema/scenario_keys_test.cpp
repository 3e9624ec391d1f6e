// The scenario key table (engine/schema/scenario_keys.h) against the readers and the C++
// defaults: every number of the scenario's range tables has a key, every numeric key a range;
// a scenario that leaves a key out gets the table's default (read back from the parsed
// Scenario), which is also the default of the struct the C++ API builds; an unknown key is
// refused with the table's keys as the alternatives.
#include <gtest/gtest.h>

#include <set>
#include <string>

#include "core/input_error.h"
#include "engine/effects/measurement_effect.h"
#include "engine/effects/probe_dynamics.h"
#include "engine/effects/probe_lobing.h"
#include "engine/scenario/scenario.h"
#include "engine/schema/parameter_ranges.h"
#include "engine/schema/scenario_keys.h"
#include "gears/deviations.h"
#include "gears/involute_gear.h"
#include "gears/tolerances.h"

namespace gearmc {
namespace {

const std::string kGear = "gear: {teeth: 24, module_mm: 5.6, face_width_mm: 78.89}\n";

TEST(ScenarioKeys, EveryRangedNumberHasAKeyAndEveryNumericKeyARange) {
  std::set<std::string> covered;  // range entries named by a key
  for (const ScenarioKey& k : scenario_keys()) {
    const bool numeric = k.type == KeyType::kNumber || k.type == KeyType::kInteger ||
                         k.type == KeyType::kParameter || k.type == KeyType::kVector3;
    if (!numeric) continue;
    const std::string range_key = k.range_key.empty() ? k.key : k.range_key;
    bool found = false;
    for (const RangeTable* table : all_range_tables()) {
      for (const ParameterRange& r : table->entries) found = found || r.key == range_key;
    }
    if (found) {
      covered.insert(range_key);
    } else {
      // Integers read with bounds of their own (e.g. a harmonic's order 1 … 36), or the seed.
      EXPECT_TRUE(k.type == KeyType::kInteger && (k.integer_min > 0 || k.key == "seed"))
          << k.key << " has neither a range-table entry nor integer bounds";
    }
  }
  for (const RangeTable* table : {&gear_ranges(), &deviation_ranges(), &probing_ranges(),
                                  &effect_ranges(), &machine_ranges()}) {
    for (const ParameterRange& r : table->entries) {
      if (r.key == "probing.points_per_gear") continue;  // a product of keys, not a key
      // The two numbers of the text "A + L/K" (cmm.mpe_e_um), each checked on its own.
      if (r.key == "cmm.mpe_e_um.A" || r.key == "cmm.mpe_e_um.K") continue;
      EXPECT_TRUE(covered.count(r.key)) << r.key << " is in a range table but not a scenario key";
    }
  }
}

TEST(ScenarioKeys, EveryMapAndListHasItsKeysAndEveryChoiceItsDefault) {
  for (const ScenarioKey& k : scenario_keys()) {
    EXPECT_FALSE(k.description.empty()) << k.key;
    if ((k.type == KeyType::kMap || k.type == KeyType::kList) && k.key != "gear.modifications") {
      // tolerances.overrides_um is a kSymbolMap; every other map lists its keys, but for
      // gear.modifications, refused as a whole in this version (its keys come with the model).
      EXPECT_FALSE(child_keys(k.key).empty()) << k.key;
    }
    // A choice's default is one of its choices, or it is required (gear.hand: "required when
    // helix_angle_deg > 0").
    if (k.type == KeyType::kChoice && k.default_text.rfind("required", 0) != 0 &&
        k.default_text != "deviations.distribution") {
      bool listed = false;
      for (const std::string& a : k.allowed) listed = listed || a == k.default_text;
      EXPECT_TRUE(listed) << k.key << ": default " << k.default_text << " is not allowed";
    }
  }
}

TEST(ScenarioKeys, LeftOutKeysGetTheTablesDefaultsWhichAreTheStructDefaults) {
  // A scenario with the required keys only (and every effect present with no parameter).
  const Scenario s = parse_scenario(
      kGear +
          "effects: {probe_lobing: {}, tip_form: {}, thermal_expansion: {}, step_quantization: "
          "{}, noise: {}}\n",
      "defaults.yaml");
  const Scenario plain;
  EXPECT_EQ(s.seed, static_cast<std::uint64_t>(number_default("seed")));
  EXPECT_EQ(plain.seed, s.seed);
  EXPECT_EQ(s.gear.pressure_angle_deg, number_default("gear.pressure_angle_deg"));
  EXPECT_EQ(s.gear.profile_shift, number_default("gear.profile_shift"));
  const BasicRack rack;
  EXPECT_EQ(s.gear.rack.addendum, rack.addendum);
  EXPECT_EQ(s.gear.rack.dedendum, rack.dedendum);
  EXPECT_EQ(s.gear.rack.root_radius, rack.root_radius);
  EXPECT_EQ(rack.addendum, number_default("gear.basic_rack.addendum"));
  EXPECT_EQ(rack.dedendum, number_default("gear.basic_rack.dedendum"));
  EXPECT_EQ(rack.root_radius, number_default("gear.basic_rack.root_radius"));
  EXPECT_EQ(s.tolerances.standard, ToleranceSpec{}.standard);
  EXPECT_EQ(standard_name(s.tolerances.standard), choice_default("tolerances.standard"));
  const DeviationModel model;
  EXPECT_EQ(s.deviations.random, boolean_default("deviations.random"));
  EXPECT_EQ(model.random, s.deviations.random);
  EXPECT_EQ(s.deviations.pitch.k, number_default("deviations.k"));
  EXPECT_EQ(model.pitch.k, s.deviations.pitch.k);
  EXPECT_EQ(model.pitch.law, s.deviations.pitch.law);
  EXPECT_EQ(s.deviations.profile_form_control_points,
            number_default("deviations.profile.control_points"));
  EXPECT_EQ(s.deviations.helix_form_control_points,
            number_default("deviations.helix.control_points"));
  EXPECT_EQ(model.profile_form_control_points, s.deviations.profile_form_control_points);
  EXPECT_EQ(model.helix_form_control_points, s.deviations.helix_form_control_points);
  const ProbingPlanSpec plan;
  EXPECT_EQ(s.probing.grid.points_along_profile, number_default("probing.points_along_profile"));
  EXPECT_EQ(s.probing.grid.sections_across_face, number_default("probing.sections_across_face"));
  EXPECT_EQ(s.probing.grid.margin_fraction, number_default("probing.margin_fraction"));
  EXPECT_EQ(plan.grid.points_along_profile, s.probing.grid.points_along_profile);
  EXPECT_EQ(plan.grid.sections_across_face, s.probing.grid.sections_across_face);
  EXPECT_EQ(plan.grid.margin_fraction, s.probing.grid.margin_fraction);
  EXPECT_EQ(plan.grid.spacing, s.probing.grid.spacing);
  EXPECT_EQ(choice_default("probing.profile_spacing"), "roll_length");
  EXPECT_EQ(s.probing.grid.spacing, ProfileSpacing::kRollLength);
  EXPECT_EQ(plan.left, s.probing.left);
  EXPECT_EQ(plan.right, s.probing.right);
  EXPECT_TRUE(s.probing.left && s.probing.right);
  EXPECT_EQ(choice_default("probing.flanks"), "both");
  EXPECT_EQ(plan.order, s.probing.order);
  EXPECT_EQ(s.probing.teeth.empty(), scenario_key("probing.teeth").default_text == "all");
  EXPECT_EQ(s.stylus_radius_mm, number_default("stylus.radius_mm"));
  EXPECT_EQ(plain.stylus_radius_mm, s.stylus_radius_mm);
  EXPECT_EQ(s.gears, number_default("run.gears"));
  EXPECT_EQ(plain.gears, s.gears);

  // Effects: every parameter left out is the table's default.
  ASSERT_EQ(s.effects->size(), 5u);
  for (std::size_t e = 0; e < s.effects->size(); ++e) {
    const MeasurementEffect& effect = s.effects->effect(e);
    for (const EffectParameter& p : effect.parameters()) {
      const std::string key = "effects." + std::string(effect.name()) + "." + p.name;
      EXPECT_EQ(p.nominal(), number_default(key)) << key;
    }
    if (effect.name() == "probe_lobing") {
      const auto& lobing = dynamic_cast<const ProbeLobingEffect&>(effect);
      EXPECT_EQ(lobing.qualification().strategy, ProbeQualification::kNone);
      EXPECT_EQ(choice_default("effects.probe_lobing.calibration"), "none");
      EXPECT_EQ(lobing.qualification().use, SixDirectionUse::kNearest);
      EXPECT_EQ(lobing.qualification().start_deg,
                number_default("effects.probe_lobing.calibration_start_deg"));
    }
  }
  // The probe model's defaults are ProbeDynamicsParameters'.
  const ProbeDynamicsParameters probe;
  const std::string probe_model = "effects.probe_lobing.from_probe_model.";
  EXPECT_EQ(probe.stylus_length_mm, number_default(probe_model + "stylus_length_mm"));
  EXPECT_EQ(probe.stem_diameter_mm, number_default(probe_model + "stem_diameter_mm"));
  EXPECT_EQ(probe.ball_diameter_mm, number_default(probe_model + "ball_diameter_mm"));
  EXPECT_EQ(probe.trigger_latency_s, number_default(probe_model + "trigger_latency_s"));
  EXPECT_EQ(probe.stem_material.density_kg_m3, probe_materials::kTungstenCarbide.density_kg_m3);
  EXPECT_EQ(choice_default(probe_model + "stem_material"), "tungsten_carbide");
}

TEST(ScenarioKeys, UnknownKeysAreRefusedWithTheTablesKeys) {
  // The readers take their key lists from the table: a key outside it is an input error whose
  // message offers the nearest table key.
  try {
    parse_scenario(kGear + "probing: {flank: L}\n", "typo.yaml");
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("did you mean 'flanks'"), std::string::npos) << e.what();
  }
  try {
    parse_scenario(kGear + "effects: {noise: {sigma: 0.3}}\n", "typo.yaml");
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("did you mean 'sigma_um'"), std::string::npos) << e.what();
  }
  // And a choice outside the table's values.
  try {
    parse_scenario(kGear + "probing: {order: zigzag}\n", "choice.yaml");
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("tooth_by_tooth"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace gearmc
