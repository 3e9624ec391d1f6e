// Tests of the artefact-form and scale-resolution effects (engine/effects/artefact_form.h,
// scale_resolution.h) and of the coordinate-grid stage (engine/apps/diagnose/coordinate_grid.h):
// each effect against a hand calculation of its formula; artefact_form's closed-form signature
// against the numerical derivative of apply(); scale_resolution's zero signature and its point law
// against the mean and variance of apply() over many points (seeded, bounds at 4 standard errors:
// a 6e-5 chance each for a correct implementation); its keys' errors located; the grid stage on
// latched, unlatched and round-nominal coordinates; and the diagnosis naming each effect on
// readings simulated with it hidden (P1's master and 10 × 5 grid, probing noise 0.3 µm,
// simulation and null seeds 1–3: deterministic), the form reported as the artefact's (asked for
// with --candidates: it is not a default candidate, engine/apps/diagnose/candidates.h).
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>

#include "core/input_error.h"
#include "engine/apps/diagnose/coordinate_grid.h"
#include "engine/apps/diagnose/diagnosis.h"
#include "engine/effects/artefact_form.h"
#include "engine/effects/effect_config.h"
#include "engine/effects/scale_resolution.h"
#include "engine/readings/readings_csv.h"
#include "engine/run/simulate.h"
#include "engine/scenario/scenario.h"
#include "tests/support/run_gearmc.h"
#include "tests/support/text_files.h"

#include "tests/support/effect_chain.h"
#include "tests/support/temp_paths.h"

using ::gearmc::testing_support::fresh_temp_path;

namespace gearmc {
namespace {

using testing_support::chain;
using testing_support::reading_change;

constexpr const char* kRanges =
    "profile_from_mm: 30, profile_to_mm: 50, face_from_mm: -10, face_to_mm: 10";

TEST(ArtefactForm, LegendreTermsOnTheFlanksOwnSideAndCoordinates) {
  // r_b 30 mm, p = (√2925, 0, 5): roll length √(2925 − 900) = 45 mm, x = 2 (45 − 30)/20 − 1 = 0.5;
  // z = 5 on [−10, 10]: y = 0.5. P₂(0.5) = (0.75 − 1)/2 = −0.125, P₃(0.5) = (0.625 − 1.5)/2 =
  // −0.4375. Left: 1.0 (−0.125) + 0.8 (−0.4375) − 0.6 (−0.125) + 0.4 (−0.4375) = −0.575 µm.
  // Right flank at the same place: 2.0 (−0.125) = −0.25 µm (the left terms do not act on it).
  const EffectChain c = chain(std::string("artefact_form: {left_profile_2_um: 1.0, "
                                          "left_profile_3_um: 0.8, left_helix_2_um: -0.6, "
                                          "left_helix_3_um: 0.4, right_profile_2_um: 2.0, ") +
                              kRanges + "}\n");
  PointContext p;
  p.p = Eigen::Vector3d(std::sqrt(2925.0), 0.0, 5.0);
  p.n = Eigen::Vector3d(0.6, 0.8, 0.0);
  p.base_radius_mm = 30.0;
  p.side = FlankSide::kLeft;
  EXPECT_NEAR(reading_change(c, p), -0.575, 1e-9);
  p.side = FlankSide::kRight;
  EXPECT_NEAR(reading_change(c, p), -0.25, 1e-9);
  // At the ends of the ranges every P_k is ±1: the coefficients are µm at the ends. Roll length
  // 50 (p_x = √3400), z = 10: left 1.0 + 0.8 − 0.6 + 0.4 = 1.6 µm.
  p.side = FlankSide::kLeft;
  p.p = Eigen::Vector3d(std::sqrt(3400.0), 0.0, 10.0);
  EXPECT_NEAR(reading_change(c, p), 1.6, 1e-9);
  // The closed-form signature is the derivative of apply() (every parameter, both sides).
  const ArtefactFormEffect e({}, FormRanges{30.0, 50.0, -10.0, 10.0});
  const std::vector<double> at = {0.3, -0.2, 0.1, 0.5, -0.4, 0.2, 0.7, -0.1};
  for (FlankSide side : {FlankSide::kLeft, FlankSide::kRight}) {
    p.side = side;
    p.p = Eigen::Vector3d(41.0, 17.0, -3.0);
    double closed[8], numeric[8];
    e.signature(p, at, closed);
    e.MeasurementEffect::signature(p, at, numeric);
    for (int i = 0; i < 8; ++i) EXPECT_NEAR(closed[i], numeric[i], 1e-7) << i;
  }
}

TEST(ArtefactForm, KeysAreRequiredAndRangeCheckedWithTheirPlace) {
  const auto message = [](const std::string& yaml) -> std::string {
    try {
      chain(yaml);
    } catch (const InputError& e) {
      return e.what();
    }
    return "no error";
  };
  // A range missing: the key and what it is.
  std::string m = message(
      "artefact_form: {left_profile_2_um: 1, profile_from_mm: 30, profile_to_mm: 50, "
      "face_from_mm: -10}\n");
  EXPECT_NE(m.find("effects.yaml:1:"), std::string::npos) << m;
  EXPECT_NE(m.find("face_to_mm"), std::string::npos) << m;
  // from ≥ to: located at the `to` value.
  m = message(
      "artefact_form:\n  profile_from_mm: 50\n  profile_to_mm: 30\n  face_from_mm: 0\n"
      "  face_to_mm: 10\n");
  EXPECT_NE(m.find("effects.yaml:3:"), std::string::npos) << m;
  EXPECT_NE(m.find("profile_to_mm"), std::string::npos) << m;
  // A term beyond its valid range (±1000 µm): the key and the value.
  m = message(std::string("artefact_form: {right_helix_3_um: 5000, ") + kRanges + "}\n");
  EXPECT_NE(m.find("right_helix_3_um"), std::string::npos) << m;
  EXPECT_NE(m.find("5000"), std::string::npos) << m;
  // A negative scale step.
  m = message("scale_resolution: {x_um: -0.1}\n");
  EXPECT_NE(m.find("effects.yaml:1:"), std::string::npos) << m;
  EXPECT_NE(m.find("x_um"), std::string::npos) << m;
}

TEST(ScaleResolution, CoordinatesLatchOnEachAxisGrid) {
  // c = p + R n = (30.30004, 40.40016, 20.0000049) mm with x 0.1 µm, y 1 µm, z not latched:
  // 30.30004 / 1e-4 = 303000.4 → 30.3; 40.40016 / 1e-3 = 40400.16 → 40.4; z unchanged. Along
  // n = (0.6, 0.8, 0): 1000 (−0.00004 · 0.6 − 0.00016 · 0.8) = −0.152 µm.
  const EffectChain c = chain("scale_resolution: {x_um: 0.1, y_um: 1}\n");
  PointContext p;
  p.n = Eigen::Vector3d(0.6, 0.8, 0.0);
  p.p = Eigen::Vector3d(30.30004, 40.40016, 20.0000049) - 0.5 * p.n;
  EXPECT_NEAR(reading_change(c, p), -0.152, 1e-9);
  // The readout comes last whatever the scenario's order: with noise the recorded coordinates
  // still lie on the grid.
  for (const char* yaml : {"scale_resolution: {x_um: 1, y_um: 1}\nnoise: {sigma_um: 0.3}\n",
                           "noise: {sigma_um: 0.3}\nscale_resolution: {x_um: 1, y_um: 1}\n"}) {
    const EffectChain both = chain(yaml);
    RandomStream rng(7, 0, StreamPurpose::kEffectNoise, 0);
    const Eigen::Vector3d start = p.p + 0.5 * p.n;
    const Eigen::Vector3d got = both.apply(p, both.nominal(), start, rng);
    for (int a = 0; a < 2; ++a) {
      EXPECT_NEAR(got[a] * 1e3, std::round(got[a] * 1e3), 1e-9) << yaml << a;
    }
    EXPECT_GT(std::abs(got.z() - start.z()), 0.0) << yaml;  // z: the noise, not latched
  }
}

TEST(ScaleResolution, ZeroMeanAndTheStatedVarianceOverTheGridPhase) {
  // 20 000 points uniform in a 100 mm box with unit normals of random azimuth and elevation
  // (stream seed 11), steps 1 µm on every axis: the reading change has mean 0 (the closed-form
  // signature: no first-order change) and variance Σ n_i² s²/12 = 1/12 µm² (the point law).
  // Standard errors: of the mean √(1/12/20000) = 0.00204 µm; of the variance about
  // (1/12) √(0.8/20000) = 0.00053 µm² (a uniform's excess kurtosis −1.2); bounds 4 SE.
  const EffectChain c = chain("scale_resolution: {x_um: 1, y_um: 1, z_um: 1}\n");
  const ScaleResolutionEffect& e = dynamic_cast<const ScaleResolutionEffect&>(c.effect(0));
  RandomStream rng(11, 0, StreamPurpose::kEffectNoise, 0);
  const int n = 20000;
  double sum = 0.0, sum2 = 0.0;
  for (int k = 0; k < n; ++k) {
    PointContext p;
    p.p = Eigen::Vector3d(rng.uniform(-50, 50), rng.uniform(-50, 50), rng.uniform(-50, 50));
    const double az = rng.uniform(0, 2 * M_PI), el = std::asin(rng.uniform(-1, 1));
    p.n = Eigen::Vector3d(std::cos(el) * std::cos(az), std::cos(el) * std::sin(az), std::sin(el));
    const double d = reading_change(c, p);
    sum += d;
    sum2 += d * d;
    if (k == 0) {
      double s[3];
      e.signature(p, c.nominal()[0], s);
      EXPECT_EQ(s[0], 0.0);
      EXPECT_EQ(s[2], 0.0);
    }
  }
  const double mean = sum / n, var = sum2 / n - mean * mean;
  EXPECT_LE(std::abs(mean), 4 * 0.00204) << mean;
  EXPECT_LE(std::abs(var - 1.0 / 12.0), 4 * 0.00053) << var;
  EXPECT_NEAR(c.point_law(c.nominal()).variance_um2(), 1.0 / 12.0, 1e-15);
}

Readings grid_readings(double step_um, bool round_nominal) {
  // 400 points on a circle of 60 mm, normals radial, z = 5 j mm; c latched when step_um > 0.
  Readings r;
  RandomStream rng(3, 0, StreamPurpose::kEffectNoise, 0);
  for (int k = 0; k < 400; ++k) {
    ReadingRow row;
    const double t = 0.0157 * k + 0.001 * rng.uniform();
    row.n = Eigen::Vector3d(std::cos(t), std::sin(t), 0.0);
    row.p = 60.0 * row.n + Eigen::Vector3d(0, 0, 5.0 * (k % 5));
    if (round_nominal) row.p.x() = std::round(row.p.x());
    row.c =
        row.p + 0.5 * row.n + 0.0003 * Eigen::Vector3d(rng.normal(), rng.normal(), rng.normal());
    if (round_nominal) row.c.x() = row.p.x();  // exactly the plan's round value, no noise
    for (int a = 0; a < 3; ++a) row.c[a] = latch_to_grid_mm(row.c[a], step_um);
    r.rows.push_back(row);
  }
  return r;
}

TEST(CoordinateGrid, FindsTheLatchedStepAndNothingWithoutLatching) {
  const std::vector<bool> none;
  // Latched on 0.5 µm: found on x and y, z not observable (n_z = 0); spread √(0.25/12) = 0.144 µm
  // ≥ 0.25 · 0.3 µm: named; not named when the model has the same steps.
  CoordinateGrid g = detect_coordinate_grid(grid_readings(0.5, false), none, {0, 0, 0}, 0.3, 0.25);
  ASSERT_TRUE(g.ran);
  EXPECT_EQ(g.points, "recorded_centres");
  EXPECT_NEAR(g.axes[0].step_um, 0.5, 1e-12);
  EXPECT_NEAR(g.axes[1].step_um, 0.5, 1e-12);
  EXPECT_FALSE(g.axes[2].observable);
  EXPECT_NEAR(g.rms_um, std::sqrt(0.25 / 12.0), 1e-12);
  EXPECT_TRUE(g.named);
  EXPECT_LT(g.false_alarm, 1e-20);
  g = detect_coordinate_grid(grid_readings(0.5, false), none, {0.5, 0.5, 0}, 0.3, 0.25);
  EXPECT_TRUE(g.in_model);
  EXPECT_FALSE(g.named);
  // A step not of the 1-2-5 series: 0.3 µm.
  g = detect_coordinate_grid(grid_readings(0.3, false), none, {0, 0, 0}, 0.3, 0.25);
  EXPECT_NEAR(g.axes[0].step_um, 0.3, 1e-12);
  // 0.05 µm: found, but its spread 0.014 µm is below the practical size: reported, not named.
  g = detect_coordinate_grid(grid_readings(0.05, false), none, {0, 0, 0}, 0.3, 0.25);
  EXPECT_NEAR(g.axes[0].step_um, 0.05, 1e-12);
  EXPECT_FALSE(g.named);
  // Not latched: no grid.
  g = detect_coordinate_grid(grid_readings(0.0, false), none, {0, 0, 0}, 0.3, 0.25);
  EXPECT_FALSE(g.found());
  EXPECT_FALSE(g.named);
  // Nominal x on whole mm, recorded exactly there (y and z as before): x lies on every grid up to
  // 1 mm only because the plan does; not taken as a latching (without that rule: 10 µm).
  g = detect_coordinate_grid(grid_readings(0.0, true), none, {0, 0, 0}, 0.3, 0.25);
  EXPECT_FALSE(g.found());
}

Scenario with_effects(const std::string& effects_yaml) {
  Scenario s = reference_scenario();
  s.effects = std::make_shared<const EffectChain>(chain(effects_yaml));
  return s;
}

// P1's base radius r_b = m z cos α / 2 = 5.6 · 24 · cos 20° / 2 mm (the involute's base circle).
const double kP1BaseRadiusMm = 0.5 * 5.6 * 24.0 * std::cos(20.0 * M_PI / 180.0);

// P1's measured range (roll length and z of the 10 × 5 grid's nominal points, as the candidate
// takes it from the points): filled in by the first test that simulates.
std::string measured_ranges(const Readings& readings, double base_radius_mm) {
  double l0 = 1e9, l1 = -1e9, z0 = 1e9, z1 = -1e9;
  for (const ReadingRow& row : readings.rows) {
    const double r2 = row.p.x() * row.p.x() + row.p.y() * row.p.y();
    const double l = std::sqrt(r2 - base_radius_mm * base_radius_mm);
    l0 = std::min(l0, l);
    l1 = std::max(l1, l);
    z0 = std::min(z0, row.p.z());
    z1 = std::max(z1, row.p.z());
  }
  char text[200];
  std::snprintf(text, sizeof text,
                "profile_from_mm: %.17g, profile_to_mm: %.17g, face_from_mm: %.17g, "
                "face_to_mm: %.17g",
                l0, l1, z0, z1);
  return text;
}

TEST(DiagnoseFormAndResolution, TheFormIsNamedAsTheArtefactsAndFitted) {
  // Truth: left flanks' profile P₂ 1.0 µm (the battery's size at 1×) on the measured range, so
  // that the fitted term is the truth's; each estimate within 4 standard errors.
  SimulateOptions o;
  o.master = true;
  const Scenario plain = with_effects("noise: {sigma_um: 0.3}\n");  // seed 1
  const std::string ranges = measured_ranges(simulate_readings(plain, o).readings, kP1BaseRadiusMm);
  for (std::uint64_t seed : {1, 2, 3}) {
    Scenario form_truth = with_effects("artefact_form: {left_profile_2_um: 1.0, " + ranges +
                                       "}\nnoise: {sigma_um: 0.3}\n");
    form_truth.seed = seed;
    const Readings readings = simulate_readings(form_truth, o).readings;
    DiagnoseOptions options;
    options.selection.seed = seed;
    options.candidates.only = candidate_effect_names();  // the whole library with the form
    const Diagnosis d = diagnose(plain, readings, options);
    EXPECT_EQ(d.named_effect_text(), "artefact_form") << "seed " << seed;
    ASSERT_FALSE(d.effects.empty());
    const FittedEffect& e = d.effects.front();
    for (const FittedValue& v : e.parameters) {
      const double truth = v.name == "left_profile_2_um" ? 1.0 : 0.0;
      ASSERT_TRUE(v.estimable) << v.name;
      EXPECT_LE(std::abs(v.value - truth), 4.0 * v.std_error) << v.name << " seed " << seed;
    }
    EXPECT_LE(d.gap_after.rms_um, 1.1 * 0.3);
    EXPECT_FALSE(d.unexplained_structure);
    ASSERT_EQ(e.settings.size(), 4u);
  }
}

TEST(DiagnoseFormAndResolution, TheScaleResolutionIsReadOffTheCoordinates) {
  // Truth: 1 µm steps on every axis (an older CMM; the battery's size at 1×). Named with the
  // steps exactly (x, y; z changes no reading on a spur gear), the noise floor widened by 1/12 µm².
  for (std::uint64_t seed : {1, 2, 3}) {
    SimulateOptions o;
    o.master = true;
    Scenario truth =
        with_effects("scale_resolution: {x_um: 1, y_um: 1, z_um: 1}\nnoise: {sigma_um: 0.3}\n");
    truth.seed = seed;
    const Readings readings = simulate_readings(truth, o).readings;
    DiagnoseOptions options;
    options.selection.seed = seed;
    const Scenario plain = with_effects("noise: {sigma_um: 0.3}\n");
    const Diagnosis d = diagnose(plain, readings, options);
    EXPECT_EQ(d.named_effect_text(), "scale_resolution") << "seed " << seed;
    ASSERT_FALSE(d.effects.empty());
    const FittedEffect& e = d.effects.back();
    EXPECT_EQ(e.name, "scale_resolution");
    EXPECT_NEAR(e.parameters[0].value, 1.0, 1e-12);
    EXPECT_NEAR(e.parameters[1].value, 1.0, 1e-12);
    EXPECT_FALSE(e.parameters[2].estimable);
    EXPECT_NEAR(d.noise.sigma_um, std::sqrt(0.09 + 1.0 / 12.0), 1e-12);
    // With the effect in the model: no gap.
    const Diagnosis again = diagnose(
        with_effects("scale_resolution: {x_um: 1, y_um: 1, z_um: 1}\nnoise: {sigma_um: 0.3}\n"),
        readings, options);
    EXPECT_EQ(again.named_effect_text(), "none") << "seed " << seed;
  }
}

TEST(DiagnoseFormAndResolution, CliToldAsTheArtefactsFormKeptApartInFittedYamlAndBadKeysExitTwo) {
  // As a user runs it: simulate P1's master with the right flanks' helix P₃ 1 µm (on the measured
  // range) and noise 0.3 µm, diagnose against P1 with the noise only (seed 1).
  namespace fs = std::filesystem;
  using testing_support::read_text;
  using testing_support::run_gearmc;
  using testing_support::write_text;
  const fs::path dir = fresh_temp_path("form_cli");
  fs::remove_all(dir);
  fs::create_directories(dir);
  const std::string reference =
      read_text(fs::path(GEARMC_SOURCE_DIR) / "scenarios" / "p1_reference.yaml");
  write_text(dir / "model.yaml", reference + "\neffects:\n  noise: {sigma_um: 0.3}\n");
  auto r = run_gearmc("simulate " + (dir / "model.yaml").string() + " --master --out " +
                      (dir / "plan.csv").string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string ranges =
      measured_ranges(read_readings((dir / "plan.csv").string()), kP1BaseRadiusMm);
  write_text(dir / "truth.yaml", reference +
                                     "\neffects:\n  artefact_form: {right_helix_3_um: 1.0, " +
                                     ranges + "}\n  noise: {sigma_um: 0.3}\n");
  r = run_gearmc("simulate " + (dir / "truth.yaml").string() + " --master --out " +
                 (dir / "form.csv").string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  std::string all;
  for (const std::string& name : candidate_effect_names()) all += (all.empty() ? "" : ",") + name;
  r = run_gearmc("diagnose --model " + (dir / "model.yaml").string() + " --measured " +
                 (dir / "form.csv").string() + " --out " + (dir / "first").string() +
                 " --candidates " + all);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("gap: the artefact's form, not a CMM error: artefact_form"),
            std::string::npos)
      << r.out;
  const nlohmann::json j = nlohmann::json::parse(read_text(dir / "first" / "diagnosis.json"));
  EXPECT_EQ(j.at("named_effect"), "artefact_form");
  EXPECT_EQ(j.at("effects").at(0).at("kind"), "artefact");
  EXPECT_EQ(j.at("coordinate_grid").at("named"), false);
  const std::string html = read_text(dir / "first" / "report.html");
  EXPECT_NE(html.find("Gap found: the artefact&#39;s form, not a CMM error"), std::string::npos);
  // fitted.yaml: the separate entry with the note, its ranges; a second diagnosis finds no gap.
  const std::string fitted = read_text(dir / "first" / "fitted.yaml");
  EXPECT_NE(fitted.find("# Note: artefact_form is the master gear's own profile and helix form"),
            std::string::npos)
      << fitted;
  const Scenario s = load_scenario_file((dir / "first" / "fitted.yaml").string());
  const int form = s.effects->find("artefact_form");
  ASSERT_GE(form, 0);
  const auto& written = dynamic_cast<const ArtefactFormEffect&>(s.effects->effect(form));
  EXPECT_GT(written.ranges().profile_to_mm, written.ranges().profile_from_mm);
  r = run_gearmc("diagnose --model " + (dir / "first" / "fitted.yaml").string() + " --measured " +
                 (dir / "form.csv").string() + " --out " + (dir / "second").string() +
                 " --candidates " + all);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("no gap"), std::string::npos) << r.out;
  // A bad key in the model: exit 2 at its place, nothing written.
  write_text(dir / "bad.yaml", reference + "\neffects:\n  scale_resolution: {x_um: -1}\n");
  r = run_gearmc("diagnose --model " + (dir / "bad.yaml").string() + " --measured " +
                 (dir / "form.csv").string() + " --out " + (dir / "bad").string());
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("bad.yaml:"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("x_um"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir / "bad"));
  fs::remove_all(dir);
}

}  // namespace
}  // namespace gearmc
