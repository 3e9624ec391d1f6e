// Tests of the rotary-table and stylus-bending effects (engine/effects/rotary_table.h,
// stylus_bending.h): each against a hand calculation of its formula, the closed-form signatures
// against the numerical derivative of apply(), the scenario keys' range checks (located errors),
// and the diagnosis on readings simulated with each hidden (P1's master and 10 × 5 grid on all 24
// teeth, probing noise 0.3 µm, simulation and null-simulation seeds 1–3: deterministic):
// rotary_table is named with its parameter within 4 standard errors of the truth; stylus bending
// with a vertical stylus is exactly a stylus radius error on a spur gear, and the diagnosis says
// so (stylus_radius named, ambiguous with stylus_bending).
#include <gtest/gtest.h>

#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <numbers>
#include <stdexcept>

#include "core/input_error.h"
#include "engine/apps/diagnose/diagnosis.h"
#include "engine/effects/effect_config.h"
#include "engine/effects/rotary_table.h"
#include "engine/effects/stylus_bending.h"
#include "engine/run/simulate.h"
#include "tests/support/run_gearmc.h"
#include "tests/support/text_files.h"

#include "tests/support/effect_chain.h"
#include "tests/support/temp_paths.h"

using ::gearmc::testing_support::fresh_temp_path;

namespace gearmc {
namespace {

using testing_support::reading_change;

EffectChain chain(const std::string& yaml) { return testing_support::chain(yaml, "e.yaml"); }

PointContext at(const Eigen::Vector3d& p, const Eigen::Vector3d& n, int tooth, int teeth) {
  PointContext c;
  c.p = p;
  c.n = n.normalized();
  c.contact_normal = c.n;
  c.tooth = tooth;
  c.teeth = teeth;
  c.stylus_radius_mm = 0.5;
  return c;
}

TEST(RotaryTable, TableAngleIsTheToothsCentreLine) {
  // θ_k = 2π (k − 1) / z: tooth 1 at 0, tooth 7 of 24 at 90°.
  EXPECT_EQ(table_angle_rad(at({1, 0, 0}, {1, 0, 0}, 1, 24)), 0.0);
  EXPECT_NEAR(table_angle_rad(at({1, 0, 0}, {1, 0, 0}, 7, 24)), std::numbers::pi / 2, 1e-15);
  // Without the number of teeth there is no table angle: an error, not a silent 0.
  EXPECT_THROW(table_angle_rad(at({1, 0, 0}, {1, 0, 0}, 3, 0)), std::logic_error);
}

TEST(RotaryTable, RadialAxialAndAngularErrorsByHand) {
  // Tooth 4 of 24: θ = 45°. p = (50, 0, 5), n = (0, 1, 0), R 0.5: c = (50, 0.5, 5).
  // radial_cos 2 µm: ρ = 2 cos 45° = √2 µm along e_r = (1, 1)/√2; along n: √2/√2 = 1 µm.
  // angular_sin_2 3″: δ = 3 sin 90° = 3″ = 3π/648000 rad = 1.4544410e-5 rad; (e_z × c)·n =
  // c_x = 50 mm; 1000 · 50 · 1.4544410e-5 = 0.72722052 µm. angular_cos_2 (cos 90° = 0) and the
  // axial parts (n_z = 0) add nothing. Sum 1.72722052 µm.
  const EffectChain c = chain(
      "rotary_table: {radial_cos_um: 2, angular_sin_2_arcsec: 3, angular_cos_2_arcsec: 7, "
      "axial_cos_um: 5}\n");
  EXPECT_NEAR(reading_change(c, at({50, 0, 5}, {0, 1, 0}, 4, 24)), 1.72722052, 1e-7);
  // Axial on a face (n = e_z): axial_cos 1.5 µm at 45° → 1.5 cos 45° = 1.06066017 µm.
  const EffectChain axial = chain("rotary_table: {axial_cos_um: 1.5}\n");
  EXPECT_NEAR(reading_change(axial, at({50, 0, 5}, {0, 0, 1}, 4, 24)), 1.06066017, 1e-8);
  // Tooth 1 (θ = 0): radial_sin (sin 0 = 0) does nothing, angular_cos_1 1″ on the point
  // (60, 10, 0), n = (0.6, 0.8, 0): c = (60.3, 10.4, 0), (e_z × c)·n = −10.4·0.6 + 60.3·0.8 =
  // 42.0 mm, 1000 · 42 · π/648000 = 0.20362174 µm.
  const EffectChain one = chain("rotary_table: {radial_sin_um: 4, angular_cos_1_arcsec: 1}\n");
  EXPECT_NEAR(reading_change(one, at({60, 10, 0}, {0.6, 0.8, 0}, 1, 24)), 0.20362174, 1e-8);
}

TEST(RotaryTable, SignatureIsTheDerivativeOfApply) {
  std::vector<EffectParameter> parameters(8);
  const RotaryTableEffect e(parameters);
  const std::vector<double> values = {1.5, -0.7, 0.4, 0.9, 2.0, -1.0, 0.5, 3.0};
  for (int tooth : {1, 5, 13, 22}) {
    const PointContext p = at({55, -12, 30}, {0.3, 0.9, 0.2}, tooth, 24);
    double closed[8], numeric[8];
    e.signature(p, values, closed);
    e.MeasurementEffect::signature(p, values, numeric);
    for (int i = 0; i < 8; ++i) EXPECT_NEAR(closed[i], numeric[i], 1e-7) << tooth << " " << i;
  }
}

TEST(StylusBending, DeflectionFollowsSinSquaredOfTheAngleToTheStylus) {
  // δ₉₀ 0.8 µm. Vertical stylus: a horizontal approach bends it fully (−0.8 µm), one at 45° to
  // the axis half as much (sin² 45° = 0.5: −0.4 µm), one along the axis not at all.
  const EffectChain c = chain("stylus_bending: {deflection_um: 0.8}\n");
  EXPECT_NEAR(reading_change(c, at({40, 5, 3}, {0.6, 0.8, 0}, 1, 24)), -0.8, 1e-9);
  EXPECT_NEAR(reading_change(c, at({40, 5, 3}, {1, 0, 1}, 1, 24)), -0.4, 1e-9);
  EXPECT_NEAR(reading_change(c, at({40, 5, 3}, {0, 0, 1}, 1, 24)), 0.0, 1e-12);
  // Stylus along X: n = (0.6, 0.8, 0) makes sin²γ = 1 − 0.36 = 0.64: −0.512 µm.
  const EffectChain x = chain("stylus_bending: {deflection_um: 0.8, stylus_axis: x}\n");
  EXPECT_NEAR(reading_change(x, at({40, 5, 3}, {0.6, 0.8, 0}, 1, 24)), -0.512, 1e-9);
  const StylusBendingEffect e(EffectParameter{}, Eigen::Vector3d(0.2, 0.1, 1.0));
  const std::vector<double> values = {0.6};
  for (const Eigen::Vector3d& n :
       {Eigen::Vector3d(0.6, 0.8, 0), Eigen::Vector3d(0.3, -0.4, 0.7), Eigen::Vector3d(0, 0, 1)}) {
    double closed[1], numeric[1];
    const PointContext p = at({40, 5, 3}, n, 1, 24);
    e.signature(p, values, closed);
    e.MeasurementEffect::signature(p, values, numeric);
    EXPECT_NEAR(closed[0], numeric[0], 1e-7) << n.transpose();
  }
}

void expect_error(const std::string& yaml, const std::string& part) {
  try {
    chain(yaml);
    ADD_FAILURE() << "no error for:\n" << yaml;
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(part), std::string::npos) << e.what();
  }
}

TEST(RotaryTable, KeysAreRangeCheckedWithTheirPlace) {
  expect_error("rotary_table: {radial_cos_um: 5000}\n",
               "e.yaml:1:31: rotary_table.radial_cos_um: got '5000', expected a number from "
               "-1000 to 1000 µm");
  expect_error("rotary_table:\n  angular_sin_2_arcsec: 4000\n",
               "e.yaml:2:25: rotary_table.angular_sin_2_arcsec: got '4000', expected a number "
               "from -3600 to 3600 arcsec");
  expect_error("rotary_table: {angular_3_arcsec: 1}\n", "rotary_table.angular_3_arcsec");
  expect_error("stylus_bending: {deflection_um: 2000}\n",
               "e.yaml:1:33: stylus_bending.deflection_um: got '2000'");
  expect_error("stylus_bending: {stylus_axis: w}\n",
               "stylus_bending.stylus_axis: got 'w', expected one of z, x, y");
}

TEST(RotaryTable, ABadValueInAScenarioIsExitTwoWithItsPlaceAndNoOutput) {
  // The command as a user runs it: P1's scenario with a radial runout given in nm by mistake.
  namespace fs = std::filesystem;
  const fs::path dir = fresh_temp_path("rotary_bad");
  fs::remove_all(dir);
  fs::create_directories(dir);
  const std::string reference =
      testing_support::read_text(fs::path(GEARMC_SOURCE_DIR) / "scenarios" / "p1_reference.yaml");
  testing_support::write_text(dir / "bad.yaml",
                              reference + "\neffects:\n  rotary_table: {radial_cos_um: 2000}\n");
  const auto r = testing_support::run_gearmc("simulate " + (dir / "bad.yaml").string() +
                                             " --master --out " + (dir / "r.csv").string());
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("bad.yaml:"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("rotary_table.radial_cos_um: got '2000'"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir / "r.csv"));
  fs::remove_all(dir);
}

TEST(RotaryTable, SimulateDiagnoseAndTheFittedModelClosesTheGap) {
  // The commands as a user runs them: readings of P1's master simulated with a radial runout
  // (1.2, −0.8) µm and a twice-per-turn positioning error 1″ plus noise 0.3 µm (seed 4),
  // diagnosed against the noise-only model: rotary_table is named, fitted.yaml carries it under
  // the effect's own keys, and the same readings against fitted.yaml show no gap.
  namespace fs = std::filesystem;
  const fs::path dir = fresh_temp_path("rotary_cli");
  fs::remove_all(dir);
  fs::create_directories(dir);
  const std::string reference =
      testing_support::read_text(fs::path(GEARMC_SOURCE_DIR) / "scenarios" / "p1_reference.yaml");
  testing_support::write_text(
      dir / "truth.yaml",
      reference +
          "\neffects:\n  rotary_table: {radial_cos_um: 1.2, radial_sin_um: -0.8, "
          "angular_sin_2_arcsec: 1.0}\n  noise: {sigma_um: 0.3}\n");
  testing_support::write_text(dir / "model.yaml",
                              reference + "\neffects:\n  noise: {sigma_um: 0.3}\n");
  const auto p = [&](const char* name) { return (dir / name).string(); };
  auto r = testing_support::run_gearmc("simulate " + p("truth.yaml") + " --master --seed 4 --out " +
                                       p("r.csv"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  r = testing_support::run_gearmc("diagnose --model " + p("model.yaml") + " --measured " +
                                  p("r.csv") + " --out " + p("out") + " --seed 4");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("gap: rotary_table"), std::string::npos) << r.out;
  const std::string fitted = testing_support::read_text(dir / "out" / "fitted.yaml");
  EXPECT_NE(fitted.find("radial_cos_um"), std::string::npos) << fitted;
  EXPECT_NE(fitted.find("angular_sin_2_arcsec"), std::string::npos) << fitted;
  r = testing_support::run_gearmc("diagnose --model " + p("out/fitted.yaml") + " --measured " +
                                  p("r.csv") + " --out " + p("again") + " --seed 4");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("no gap"), std::string::npos) << r.out;
  fs::remove_all(dir);
}

Scenario with_effects(const std::string& effects_yaml) {
  Scenario s = reference_scenario();
  s.effects = std::make_shared<const EffectChain>(chain(effects_yaml));
  return s;
}

Diagnosis simulate_and_diagnose(const std::string& hidden, std::uint64_t seed) {
  SimulateOptions o;
  o.master = true;
  Scenario truth = with_effects(hidden + "noise: {sigma_um: 0.3}\n");
  truth.seed = seed;
  const Readings readings = simulate_readings(truth, o).readings;
  DiagnoseOptions options;
  options.selection.seed = seed;
  return diagnose(with_effects("noise: {sigma_um: 0.3}\n"), readings, options);
}

struct Hidden {
  const char* yaml;
  const char* label;
  const char* parameter;
  double truth;
};

class DiagnoseRotaryTable : public ::testing::TestWithParam<Hidden> {};

TEST_P(DiagnoseRotaryTable, IsNamedAndFitted) {
  // Seeds 1, 2, 3. Each estimate within 4 standard errors (a 6e-5 chance per seed for an unbiased
  // estimate); the gap closes to the noise (RMS after ≤ 1.1 × 0.3 µm).
  const Hidden& h = GetParam();
  for (std::uint64_t seed : {1, 2, 3}) {
    const Diagnosis d = simulate_and_diagnose(h.yaml, seed);
    EXPECT_EQ(d.named_effect_text(), "rotary_table") << "seed " << seed;
    ASSERT_FALSE(d.effects.empty());
    const FittedEffect& e = d.effects.front();
    bool found = false;
    for (const FittedValue& v : e.parameters) {
      if (v.name != h.parameter) continue;
      found = true;
      ASSERT_TRUE(v.estimable);
      EXPECT_LE(std::abs(v.value - h.truth), 4.0 * v.std_error)
          << v.value << " ± " << v.std_error << ", truth " << h.truth << ", seed " << seed;
    }
    EXPECT_TRUE(found) << h.parameter;
    EXPECT_LE(d.gap_after.rms_um, 1.1 * 0.3);
    // The angular part's ambiguity with the gear's own pitch is said.
    bool pitch_note = false;
    for (const std::string& n : d.notes) pitch_note |= n.find("pitch deviations") != n.npos;
    EXPECT_TRUE(pitch_note);
  }
}

void PrintTo(const Hidden& h, std::ostream* os) { *os << h.label; }

// The battery's sizes at 1× (scripts/diagnose-battery).
INSTANTIATE_TEST_SUITE_P(Library, DiagnoseRotaryTable,
                         ::testing::Values(Hidden{"rotary_table: {radial_cos_um: 2.0}\n", "radial",
                                                  "radial_cos_um", 2.0},
                                           Hidden{"rotary_table: {angular_sin_2_arcsec: 1.0}\n",
                                                  "angular2", "angular_sin_2_arcsec", 1.0}),
                         [](const ::testing::TestParamInfo<Hidden>& p) {
                           return std::string(p.param.label);
                         });

TEST(DiagnoseStylusBending, OnASpurGearIsTheStylusRadiusErrorAndSaysSo) {
  // A vertical stylus approaches every spur-gear flank across its axis: sin²γ = 1, the signature
  // is −1 everywhere, the same column as stylus_radius. The diagnosis cannot prefer either; ties
  // go to the library's order, so it names stylus_radius with error_um = δ₉₀ (0.5 µm hidden,
  // within 4 SE) and lists stylus_bending as ambiguous, with the measurement that separates them.
  for (std::uint64_t seed : {1, 2}) {
    const Diagnosis d = simulate_and_diagnose("stylus_bending: {deflection_um: 0.5}\n", seed);
    EXPECT_EQ(d.named_effect_text(), "stylus_radius") << "seed " << seed;
    ASSERT_FALSE(d.effects.empty());
    bool ambiguous = false;
    for (const Ambiguity& a : d.effects.front().ambiguous) {
      if (a.with != "stylus_bending") continue;
      ambiguous = true;
      EXPECT_NE(a.separate_by.find("elevations"), std::string::npos) << a.separate_by;
    }
    EXPECT_TRUE(ambiguous) << "seed " << seed;
    for (const FittedValue& v : d.effects.front().parameters) {
      if (v.name == "error_um") {
        EXPECT_LE(std::abs(v.value - 0.5), 4.0 * v.std_error);
      }
    }
  }
}

}  // namespace
}  // namespace gearmc
