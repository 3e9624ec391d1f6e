// Tests of scenario parsing on good input: the reference scenario file parses to P1's gear and
// tolerances (Pechenin, Rusanov, Bolotov 2018, Table 1), and the defaults and every section's keys
// are read into their values. Bad input: scenario_error_test.cpp.
#include <gtest/gtest.h>

#include <cstdint>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>

#include "core/input_error.h"
#include "engine/scenario/scenario.h"
#include "tests/support/scenario_input.h"

#ifndef GEARMC_SOURCE_DIR
#error "GEARMC_SOURCE_DIR (the repository root) must be defined"
#endif

namespace gearmc {
namespace {

using testing_support::kGear;

// ---- the reference scenario -----------------------------------------------------------------

TEST(ScenarioTest, ReferenceFileParsesToP1Values) {
  const std::string path = std::string(GEARMC_SOURCE_DIR) + "/scenarios/p1_reference.yaml";
  const Scenario s = load_scenario_file(path);
  EXPECT_EQ(s.name, "p1_reference");
  EXPECT_EQ(s.source_path, path);
  std::ifstream in(path);
  std::ostringstream text;
  text << in.rdbuf();
  EXPECT_EQ(s.source_text, text.str());
  EXPECT_EQ(s.seed, 1u);

  // P1 Table 1: z 24, m 5.6 mm, alpha 20 deg, x 0.90116, b 78.89 mm, ISO 53 profile A rack.
  EXPECT_EQ(s.gear.teeth, 24);
  EXPECT_DOUBLE_EQ(s.gear.module_mm, 5.6);
  EXPECT_DOUBLE_EQ(s.gear.pressure_angle_deg, 20.0);
  EXPECT_DOUBLE_EQ(s.gear.profile_shift, 0.90116);
  EXPECT_DOUBLE_EQ(s.gear.face_width_mm, 78.89);
  EXPECT_DOUBLE_EQ(s.gear.rack.addendum, 1.0);
  EXPECT_DOUBLE_EQ(s.gear.rack.dedendum, 1.25);
  EXPECT_DOUBLE_EQ(s.gear.rack.root_radius, 0.38);
  EXPECT_FALSE(s.gear.tip_diameter_mm.has_value());
  EXPECT_FALSE(s.gear.root_diameter_mm.has_value());

  // P1 Table 1 tolerances, GOST 1643-81 grade 6-5-5.
  EXPECT_EQ(s.tolerances.standard, ToleranceStandard::kGost1643_81);
  EXPECT_EQ(s.tolerances.grade, "6-5-5");
  const std::map<ToleranceKind, double> expected_overrides = {
      {ToleranceKind::kRunout, 50.0},
      {ToleranceKind::kBasePitch, 9.0},
      {ToleranceKind::kProfileTotal, 8.0},
      {ToleranceKind::kThicknessUpper, 110.0},
      {ToleranceKind::kThicknessTolerance, 100.0}};
  EXPECT_EQ(s.tolerances.overrides_um, expected_overrides);

  EXPECT_TRUE(s.deviations.random);
  for (const DeviationDistribution* law :
       {&s.deviations.eccentricity, &s.deviations.pitch, &s.deviations.thickness,
        &s.deviations.profile_slope, &s.deviations.profile_form, &s.deviations.helix_slope,
        &s.deviations.helix_form}) {
    EXPECT_EQ(law->law, DeviationDistribution::Law::kUniform);
    EXPECT_DOUBLE_EQ(law->k, 3.0);
  }
  EXPECT_EQ(s.deviations.profile_form_control_points, 8);
  EXPECT_EQ(s.deviations.helix_form_control_points, 6);
  EXPECT_TRUE(s.normal_expression_um.empty());
}

TEST(ScenarioTest, ParseScenarioKeepsTextAndSourceName) {
  const std::string text = "name: mine\nseed: 42\n" + kGear;
  const Scenario s = parse_scenario(text, "<memory>");
  EXPECT_EQ(s.name, "mine");
  EXPECT_EQ(s.seed, 42u);
  EXPECT_EQ(s.source_path, "<memory>");
  EXPECT_EQ(s.source_text, text);
}

// ---- defaults and every key -----------------------------------------------------------------

TEST(ScenarioTest, DefaultsOfAMinimalScenario) {
  const Scenario s = parse_scenario(kGear, "some/dir/my_case.yaml");
  EXPECT_EQ(s.name, "my_case");  // the file's stem
  EXPECT_EQ(s.seed, 1u);
  EXPECT_DOUBLE_EQ(s.gear.pressure_angle_deg, 20.0);
  EXPECT_DOUBLE_EQ(s.gear.profile_shift, 0.0);
  const BasicRack iso53;
  EXPECT_DOUBLE_EQ(s.gear.rack.addendum, iso53.addendum);
  EXPECT_DOUBLE_EQ(s.gear.rack.dedendum, iso53.dedendum);
  EXPECT_DOUBLE_EQ(s.gear.rack.root_radius, iso53.root_radius);
  EXPECT_EQ(s.tolerances.standard, ToleranceStandard::kGost1643_81);
  EXPECT_EQ(s.tolerances.grade, "6-5-5");
  EXPECT_TRUE(s.tolerances.overrides_um.empty());
  EXPECT_TRUE(s.deviations.random);
  EXPECT_EQ(s.deviations.pitch.law, DeviationDistribution::Law::kUniform);
  EXPECT_DOUBLE_EQ(s.deviations.pitch.k, 3.0);
  EXPECT_EQ(s.deviations.profile_form_control_points, 8);
  EXPECT_EQ(s.deviations.helix_form_control_points, 6);
  EXPECT_TRUE(s.normal_expression_um.empty());
}

TEST(ScenarioTest, ReadsEveryGearKey) {
  const Scenario s = parse_scenario(
      "gear:\n"
      "  teeth: 30\n"
      "  module_mm: 2\n"
      "  pressure_angle_deg: 25\n"
      "  profile_shift: -0.2\n"
      "  face_width_mm: 20\n"
      "  tip_diameter_mm: 63.5\n"
      "  root_diameter_mm: 54.5\n"
      "  basic_rack: {addendum: 1, dedendum: 1.4, root_radius: 0.25}\n"
      "tolerances: {standard: iso_1328_1_2013, grade: 6}\n",  // outside the GOST table held
      "t.yaml");
  EXPECT_EQ(s.gear.teeth, 30);
  EXPECT_DOUBLE_EQ(s.gear.module_mm, 2.0);
  EXPECT_DOUBLE_EQ(s.gear.pressure_angle_deg, 25.0);
  EXPECT_DOUBLE_EQ(s.gear.profile_shift, -0.2);
  EXPECT_DOUBLE_EQ(s.gear.face_width_mm, 20.0);
  EXPECT_EQ(s.gear.tip_diameter_mm, 63.5);
  EXPECT_EQ(s.gear.root_diameter_mm, 54.5);
  EXPECT_DOUBLE_EQ(s.gear.rack.dedendum, 1.4);
  EXPECT_DOUBLE_EQ(s.gear.rack.root_radius, 0.25);
}

TEST(ScenarioTest, ReadsDeviationLawsGroupOverridesAndExpression) {
  const Scenario s = parse_scenario(kGear +
                                        "deviations:\n"
                                        "  random: false\n"
                                        "  distribution: normal\n"
                                        "  k: 2\n"
                                        "  pitch: {distribution: uniform}\n"
                                        "  thickness: {k: 4}\n"
                                        "  profile: {k: 2.5, control_points: 12}\n"
                                        "  helix: {distribution: uniform, control_points: 4}\n"
                                        "  normal_um: \"2*sin(2*_pi*L/5) + 0.1*(z-39.445)\"\n",
                                    "t.yaml");
  const DeviationModel& d = s.deviations;
  using Law = DeviationDistribution::Law;
  EXPECT_FALSE(d.random);
  EXPECT_EQ(d.eccentricity.law, Law::kNormal);  // the default law
  EXPECT_DOUBLE_EQ(d.eccentricity.k, 2.0);
  EXPECT_EQ(d.pitch.law, Law::kUniform);  // law overridden, k inherited
  EXPECT_DOUBLE_EQ(d.pitch.k, 2.0);
  EXPECT_EQ(d.thickness.law, Law::kNormal);  // k overridden, law inherited
  EXPECT_DOUBLE_EQ(d.thickness.k, 4.0);
  for (const DeviationDistribution* law : {&d.profile_slope, &d.profile_form}) {
    EXPECT_EQ(law->law, Law::kNormal);
    EXPECT_DOUBLE_EQ(law->k, 2.5);
  }
  for (const DeviationDistribution* law : {&d.helix_slope, &d.helix_form}) {
    EXPECT_EQ(law->law, Law::kUniform);
    EXPECT_DOUBLE_EQ(law->k, 2.0);
  }
  EXPECT_EQ(d.profile_form_control_points, 12);
  EXPECT_EQ(d.helix_form_control_points, 4);
  EXPECT_EQ(s.normal_expression_um, "2*sin(2*_pi*L/5) + 0.1*(z-39.445)");
}

TEST(ScenarioTest, ReadsIsoTolerancesAndGrades) {
  const Scenario iso = parse_scenario(kGear +
                                          "tolerances:\n"
                                          "  standard: iso_1328_1_2013\n"
                                          "  grade: 5\n"
                                          "  overrides_um: {f_H_alpha: 6.5, F_p: 20, f_p: 5}\n",
                                      "t.yaml");
  EXPECT_EQ(iso.tolerances.standard, ToleranceStandard::kIso1328_1_2013);
  EXPECT_EQ(iso.tolerances.grade, "5");
  const std::map<ToleranceKind, double> expected = {{ToleranceKind::kProfileSlope, 6.5},
                                                    {ToleranceKind::kCumulativePitch, 20.0},
                                                    {ToleranceKind::kSinglePitch, 5.0}};
  EXPECT_EQ(iso.tolerances.overrides_um, expected);

  EXPECT_EQ(parse_scenario(kGear + "tolerances: {grade: 7}\n", "t.yaml").tolerances.grade, "7");
  // Contact grade 12 is not in the GOST table held: F_beta is given.
  EXPECT_EQ(
      parse_scenario(kGear + "tolerances: {grade: 8-7-12, overrides_um: {F_beta: 40}}\n", "t.yaml")
          .tolerances.grade,
      "8-7-12");
  // E_Hs may be 0 (a magnitude); the largest seed fits.
  EXPECT_EQ(parse_scenario(kGear + "tolerances: {overrides_um: {E_Hs: 0}}\n", "t.yaml")
                .tolerances.overrides_um.at(ToleranceKind::kThicknessUpper),
            0.0);
  EXPECT_EQ(parse_scenario("seed: 18446744073709551615\n" + kGear, "t.yaml").seed,
            std::numeric_limits<std::uint64_t>::max());
}

TEST(ScenarioTest, NumberSyntaxAcceptedForRealValues) {
  // Integers, exponents, a leading '+' are numbers; the scalar is read exactly.
  const Scenario s = parse_scenario(
      "gear: {teeth: +24, module_mm: 56e-1, face_width_mm: 78.890, profile_shift: -.5}\n", "t");
  EXPECT_EQ(s.gear.teeth, 24);
  EXPECT_DOUBLE_EQ(s.gear.module_mm, 5.6);
  EXPECT_DOUBLE_EQ(s.gear.face_width_mm, 78.89);
  EXPECT_DOUBLE_EQ(s.gear.profile_shift, -0.5);
}

// ---- probing, stylus, run ---------------------------------------------------------------------

TEST(ScenarioTest, ProbingStylusAndRunSections) {
  const Scenario d = parse_scenario(kGear, "t.yaml");
  // Defaults are P1's set-up (docs/sources.md): N 10, M 5, 5 % margins, all teeth, both flanks,
  // R 0.5 mm, 50 gears.
  EXPECT_EQ(d.probing.grid.points_along_profile, 10);
  EXPECT_EQ(d.probing.grid.sections_across_face, 5);
  EXPECT_DOUBLE_EQ(d.probing.grid.margin_fraction, 0.05);
  EXPECT_TRUE(d.probing.teeth.empty());
  EXPECT_TRUE(d.probing.left && d.probing.right);
  EXPECT_DOUBLE_EQ(d.stylus_radius_mm, 0.5);
  EXPECT_EQ(d.gears, 50);

  const Scenario s = parse_scenario(kGear +
                                        "probing:\n"
                                        "  points_along_profile: 20\n"
                                        "  sections_across_face: 7\n"
                                        "  margin_fraction: 0.1\n"
                                        "  profile_spacing: arc_length\n"
                                        "  teeth: [1, 5, 24]\n"
                                        "  flanks: R\n"
                                        "stylus: {radius_mm: 1.5}\n"
                                        "run: {gears: 7}\n",
                                    "t.yaml");
  EXPECT_EQ(s.probing.grid.points_along_profile, 20);
  EXPECT_EQ(s.probing.grid.sections_across_face, 7);
  EXPECT_DOUBLE_EQ(s.probing.grid.margin_fraction, 0.1);
  EXPECT_EQ(s.probing.grid.spacing, ProfileSpacing::kArcLength);
  EXPECT_EQ(s.probing.teeth, (std::vector<int>{1, 5, 24}));
  EXPECT_FALSE(s.probing.left);
  EXPECT_TRUE(s.probing.right);
  EXPECT_DOUBLE_EQ(s.stylus_radius_mm, 1.5);
  EXPECT_EQ(s.gears, 7);
}

}  // namespace
}  // namespace gearmc
