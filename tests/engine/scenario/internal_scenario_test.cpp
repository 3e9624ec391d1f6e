// Internal (ring) gears through every command: scenarios/ring_gear_z72.yaml's gear (z 72
// internal, m 2.5 mm, alpha 20°, b 30 mm; ISO 21771 with signed z: d 180, d_a 175, d_f 186.25,
// d_b = 180 cos 20° = 169.1447 mm) runs through run, check, sweep, simulate, export-mesh,
// export-plan and diagnose; the DMIS plan's points lie on the internal tooth of DIN 3960 (half
// angle s/d - inv(alpha) + inv(alpha_y), written out here); the ISO 1328-1 evaluation states a
// profile slope from the root (form circle, the largest roll length) to the tip; a turned tooth is
// a pitch deviation of r_b a / cos(alpha) on the reference circle; diagnose names the x and y
// scale errors of a machine that measured the ring.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <filesystem>
#include <map>
#include <numbers>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "engine/run/monte_carlo.h"
#include "engine/scenario/scenario.h"
#include "tests/support/run_gearmc.h"
#include "tests/support/temp_paths.h"
#include "tests/support/text_files.h"

namespace gearmc {
namespace {

using testing_support::fresh_temp_path;
using testing_support::read_text;
using testing_support::run_gearmc;
using testing_support::write_text;
namespace fs = std::filesystem;

constexpr double kPi = std::numbers::pi;

std::string ring_yaml(const std::string& extra = "") {
  return "name: ring\nseed: 2\n"
         "gear: {teeth: -72, module_mm: 2.5, pressure_angle_deg: 20, face_width_mm: 30}\n"
         "tolerances: {standard: iso_1328_1_2013, grade: 7}\n"
         "probing: {points_along_profile: 6, sections_across_face: 3}\n"
         "stylus: {radius_mm: 0.5}\n" +
         extra;
}

TEST(InternalScenario, EveryCommandRunsOnARingGear) {
  const fs::path dir = fresh_temp_path("ring_commands");
  fs::create_directories(dir);
  const std::string s = (dir / "ring.yaml").string();
  write_text(s, ring_yaml("run: {gears: 3}\n"
                          "evaluation: {parameters: all}\n"
                          "claims:\n"
                          "  - {name: flank_max, quantity: delta_rcomp.flank_max, statistic: "
                          "{quantile: 0.9}, at_most_um: 50}\n"));
  const std::string out = (dir / "out").string();
  const std::pair<std::string, std::string> commands[] = {
      {"geometry " + s, ""},
      {"run " + s + " --out " + out + "_run", out + "_run/summary.json"},
      {"check " + s + " --out " + out + "_check", out + "_check/check.json"},
      {"sweep " + s + " --vary stylus.radius_mm=0.4,0.5 --out " + out + "_sweep",
       out + "_sweep/sweep.json"},
      {"simulate " + s + " --gears 1 --out " + out + ".csv", out + ".csv"},
      {"export-mesh " + s + " --gear 0 --out " + out + ".stl", out + ".stl"},
      {"export-plan " + s + " --out " + out + ".dmi", out + ".dmi"},
      {"diagnose --model " + s + " --measured " + out + ".csv --out " + out + "_diagnose",
       out + "_diagnose/diagnosis.json"},
  };
  for (const auto& [args, written] : commands) {
    const auto r = run_gearmc(args);
    EXPECT_EQ(r.exit_code, 0) << args << "\n" << r.err;
    if (!written.empty()) {
      EXPECT_TRUE(fs::exists(written)) << args;
    }
  }
  const nlohmann::json summary = nlohmann::json::parse(read_text(out + "_run/summary.json"));
  EXPECT_EQ(summary["failed_contacts"], 0);
  EXPECT_EQ(summary["collisions"], 0);
  EXPECT_EQ(summary["contacts"], 3 * 72 * 2 * 6 * 3);
}

// Every planned point of the DMIS program at the polar angle tooth centre +/- psi(r) of DIN 3960's
// internal tooth, psi(r) = s / d - inv(20°) + inv(alpha_r), cos(alpha_r) = r_b / r, s = pi m / 2;
// every normal unit, horizontal, pointing away from its tooth's centre line (R counter-clockwise)
// and out of the material: the point moved along it lies outside the tooth.
TEST(InternalScenario, ExportPlanPutsThePlanOnTheInternalTooth) {
  const fs::path dir = fresh_temp_path("ring_plan");
  fs::create_directories(dir);
  write_text(dir / "ring.yaml", ring_yaml());
  const std::string file = (dir / "plan.dmi").string();
  const auto r = run_gearmc("export-plan " + (dir / "ring.yaml").string() + " --out " + file);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const double alpha = 20.0 * kPi / 180, d = 180.0, r_b = 90.0 * std::cos(alpha);
  const double s = kPi * 2.5 / 2;
  const auto inv = [](double a) { return std::tan(a) - a; };
  const auto psi = [&](double radius) { return s / d - inv(alpha) + inv(std::acos(r_b / radius)); };
  static const std::regex feature(R"(^F\(T(\d+)([LR])_I\d+_J\d+\)=FEAT/POINT,CART,(.*)$)");
  std::istringstream in(read_text(file));
  int points = 0;
  double worst = 0.0;
  for (std::string line; std::getline(in, line);) {
    std::smatch m;
    if (!std::regex_match(line, m, feature)) continue;
    std::vector<double> v;
    std::stringstream fields(m[3].str());
    for (std::string x; std::getline(fields, x, ',');) v.push_back(std::stod(x));
    ASSERT_EQ(v.size(), 6u);
    const int tooth = std::stoi(m[1].str());
    const double side = m[2].str() == "R" ? 1.0 : -1.0;
    const double radius = std::hypot(v[0], v[1]);
    EXPECT_GT(radius, 175.0 / 2);  // between the tip and the root circle
    EXPECT_LT(radius, 186.25 / 2);
    const double phi = std::remainder(std::atan2(v[1], v[0]) - (tooth - 1) * 2 * kPi / 72, 2 * kPi);
    worst = std::max(worst, radius * std::abs(phi - side * psi(radius)));
    EXPECT_NEAR(std::hypot(std::hypot(v[3], v[4]), v[5]), 1.0, 1e-6);
    EXPECT_NEAR(v[5], 0.0, 1e-12);
    const double tangential = (-v[4] * v[0] + v[3] * v[1]) / radius;  // e_phi . n, negated
    EXPECT_LT(side * tangential, 0.0);
    const double x = v[0] + 0.05 * v[3], y = v[1] + 0.05 * v[4];
    const double phi_out = std::remainder(std::atan2(y, x) - (tooth - 1) * 2 * kPi / 72, 2 * kPi);
    EXPECT_GT(std::abs(phi_out), psi(std::hypot(x, y)));
    ++points;
  }
  EXPECT_EQ(points, 72 * 2 * 6 * 3);
  // The program writes 6 decimals: half a µm along the arc at most.
  EXPECT_LT(worst, 1e-6);
}

const std::vector<ParameterValue>& values(const RunResults& r, GearParameter p, int side) {
  return r.parameters->values[static_cast<int>(p)][side];
}

RunResults run_one_gear(const MonteCarloRun& mc) {
  RunOptions o;
  o.end_gear = 1;
  o.threads = 1;
  return mc.run(o);
}

// A deviation linear in the roll length, -0.5 µm/mm along the outward normal, on every flank.
// The profile evaluation range runs from the form circle (L_Ff, the root: 38.0911 mm, `gearmc
// geometry`) over 95 % of the active profile towards the tip (L_a 22.4448 mm), so the slope
// deviation, the rise from the root end to the tip end (ISO 1328-1 §3.3), is -0.5 x 0.95 x
// (22.4448 - 38.0911) = +7.432 µm: positive, more material towards the tip (with the opposite
// sign the scan's first point, planned on the form circle itself, gave no value: F_alpha then
// missed one of the 24 steps, 0.31 µm). The form deviation and the helix see nothing.
TEST(InternalScenario, ProfileSlopeIsTheRiseFromTheRootToTheTip) {
  const Scenario s = parse_scenario(
      ring_yaml("deviations: {random: false, normal_um: \"-0.5 * (L - 30)\"}\n"
                "evaluation: {parameters: all, profile_points: 25, helix_points: 25}\n"),
      "ring.yaml");
  const MonteCarloRun mc(s);
  const ParameterEvaluator& e = *mc.parameter_evaluator();
  EXPECT_NEAR(e.profile_start_mm(), 38.091087, 1e-5);  // the form circle: the root end
  EXPECT_GT(e.profile_start_mm(), e.profile_end_mm());
  const double expected = -0.5 * 0.95 * (22.444821 - 38.091087);
  const RunResults r = run_one_gear(mc);
  for (int side = 0; side < 2; ++side) {
    ASSERT_EQ(values(r, GearParameter::kfHalpha, side).size(), 72u);
    for (std::size_t k = 0; k < 72; k += 7) {
      EXPECT_NEAR(values(r, GearParameter::kfHalpha, side)[k].true_dense, expected, 1e-4);
      EXPECT_NEAR(values(r, GearParameter::kfHalpha, side)[k].measured, expected, 5e-3);
      EXPECT_NEAR(values(r, GearParameter::kFalpha, side)[k].measured, expected, 5e-3);
      EXPECT_NEAR(values(r, GearParameter::kffalpha, side)[k].measured, 0.0, 5e-3);
      EXPECT_NEAR(values(r, GearParameter::kfHbeta, side)[k].measured, 0.0, 5e-3);
    }
  }
  // The chart's mean line, drawn over L from the range's start to its end, is the deviation
  // itself there: -0.5 (L - 30) µm at L = 38.0911 and at L = 23.2268 mm.
  ASSERT_FALSE(r.parameters->chart.profile.empty());
  for (const FlankTrace& t : r.parameters->chart.profile) {
    EXPECT_NEAR(t.range_start_mm, 38.091087, 1e-5);
    const double at_start = t.measured_line.intercept_um;
    const double at_end =
        at_start + t.measured_line.slope_um_per_mm * (t.range_end_mm - t.range_start_mm);
    EXPECT_NEAR(at_start, -0.5 * (t.range_start_mm - 30), 5e-3);
    EXPECT_NEAR(at_end, -0.5 * (t.range_end_mm - 30), 5e-3);
  }
}

// Tooth 3 turned counter-clockwise by a: its R flank moves along its (counter-clockwise) normal by
// r_b a = 5 µm, its L flank against its normal by the same (normal_um = side * 5 on tooth 3). On
// the reference circle the tooth moves by r a = 5 / cos(20°) = 5.3209 µm: f_pt of the pitch
// 2 -> 3 is +5.3209, of 3 -> 4 is -5.3209, every other 0; F_p = 5.3209 on both flanks.
TEST(InternalScenario, ATurnedToothIsAPitchDeviationOnTheReferenceCircle) {
  const Scenario s = parse_scenario(
      ring_yaml("deviations: {random: false, normal_um: \"(tooth == 3) * side * 5\"}\n"
                "evaluation: {parameters: all}\n"),
      "ring.yaml");
  const MonteCarloRun mc(s);
  const RunResults r = run_one_gear(mc);
  const double arc = 5.0 / std::cos(20.0 * kPi / 180);
  for (int side = 0; side < 2; ++side) {
    const std::vector<ParameterValue>& f_pt = values(r, GearParameter::kfpt, side);
    ASSERT_EQ(f_pt.size(), 72u);
    for (std::size_t k = 0; k < 72; ++k) {
      const double expected = k == 1 ? arc : k == 2 ? -arc : 0.0;  // pitch k+1 -> k+2
      EXPECT_NEAR(f_pt[k].measured, expected, 2e-3) << side << " " << k;
    }
    EXPECT_NEAR(values(r, GearParameter::kFp, side)[0].measured, arc, 2e-3);
  }
}

// A machine with x and y scale errors measures the ring (simulate --master: the nominal gear);
// diagnose, given the nominal model, names both within four standard errors.
TEST(InternalScenario, DiagnoseFindsTheScaleErrorsOnARingGear) {
  const fs::path dir = fresh_temp_path("ring_diagnose");
  fs::create_directories(dir);
  const std::string model = (dir / "model.yaml").string();
  const std::string machine = (dir / "machine.yaml").string();
  write_text(model, ring_yaml());
  write_text(machine, ring_yaml("effects:\n"
                                "  scale: {x_ppm: 20, y_ppm: -10, z_ppm: 0}\n"
                                "  noise: {sigma_um: 0.1}\n"));
  const std::string csv = (dir / "readings.csv").string();
  const auto sim = run_gearmc("simulate " + machine + " --gears 1 --master --out " + csv);
  ASSERT_EQ(sim.exit_code, 0) << sim.err;
  const auto r = run_gearmc("diagnose --model " + model + " --measured " + csv + " --out " +
                            (dir / "diagnosis").string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const nlohmann::json j =
      nlohmann::json::parse(read_text((dir / "diagnosis" / "diagnosis.json").string()));
  std::map<std::string, std::pair<double, double>> found;  // parameter -> value, std. error
  for (const auto& effect : j["effects"]) {
    for (const auto& [name, value] : effect["parameters"].items()) {
      if (!value.is_number()) continue;  // "not_computed": the parameters a spur ring cannot show
      found[effect["name"].get<std::string>() + "." + name] = {
          value.get<double>(), effect["std_errors"][name].get<double>()};
    }
  }
  ASSERT_TRUE(found.count("scale.x_ppm")) << j["effects"].dump();
  ASSERT_TRUE(found.count("scale.y_ppm")) << j["effects"].dump();
  EXPECT_NEAR(found["scale.x_ppm"].first, 20.0, 4 * found["scale.x_ppm"].second);
  EXPECT_NEAR(found["scale.y_ppm"].first, -10.0, 4 * found["scale.y_ppm"].second);
  EXPECT_LT(found["scale.x_ppm"].second, 2.0);
}

}  // namespace
}  // namespace gearmc
