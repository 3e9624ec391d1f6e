// Helical gears in scenarios: `gear: helix_angle_deg` and `hand` read as docs/scenarios.md says,
// `gearmc geometry` prints the helical gear's dimensions (ISO 21771, evaluated independently in
// tests/gears/helical_reference.py), `gearmc export-plan` puts the plan on the helicoid, and
// every command runs on it, and its mesh lies on the helicoid.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <numbers>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

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

// The issue's example gear (z 31, m_n 4, alpha_n 20°, beta 15° right, x 0.2, b 40).
std::string helical_yaml(const std::string& gear_extra) {
  return "name: helical\n"
         "gear:\n"
         "  teeth: 31\n"
         "  module_mm: 4\n"
         "  pressure_angle_deg: 20\n"
         "  helix_angle_deg: 15\n" +
         gear_extra +
         "  profile_shift: 0.2\n"
         "  face_width_mm: 40\n"
         "tolerances: {standard: iso_1328_1_2013, grade: 6}\n";
}

// Distance (mm, along the arc of its radius) of a point from the nominal involute helicoid of
// the example gear in right hand, independent of gearmc's flank code: un-screwing the point
// (turning it by -z tan(beta) / r about the axis; ISO 21771's screw of a helical gear) must land
// on the transverse involute of the section z = 0, whose polar angle at radius rho is the tooth's
// centre +/- psi(rho), psi = s_t / d + inv(alpha_t) - inv(alpha_rho), cos(alpha_rho) = r_b / rho
// (ISO 21771 §5.3, half the transverse tooth thickness angle). Values from
// tests/gears/helical_reference.py: d 128.374246370850, d_b 120.128927774273, s_t
// 7.107727627888, alpha_t 20.646896487046°. `side` +1 for R, -1 for L; tooth 0: the nearest.
double helicoid_offset_mm(double x0, double y0, double z, int tooth, double side) {
  const double kPi = std::numbers::pi;
  const double d = 128.374246370850, r_b = 120.128927774273 / 2, s_t = 7.107727627888;
  const double alpha_t = 20.646896487046 * kPi / 180;
  const double inv_t = std::tan(alpha_t) - alpha_t;
  const double turn = std::tan(15.0 * kPi / 180) / (d / 2);  // rad per mm of z, right hand
  const double back = -z * turn;
  const double x = std::cos(back) * x0 - std::sin(back) * y0;
  const double y = std::sin(back) * x0 + std::cos(back) * y0;
  const double rho = std::hypot(x, y);
  const double alpha_r = std::acos(r_b / rho);
  const double psi = s_t / d + inv_t - (std::tan(alpha_r) - alpha_r);
  const double centre = (tooth - 1) * 2 * kPi / 31;
  const double period = tooth == 0 ? 2 * kPi / 31 : 2 * kPi;
  return std::abs(std::remainder(std::atan2(y, x) - centre - side * psi, period)) * rho;
}

TEST(HelicalScenario, GeometryPrintsTheTransverseAndHelixValues) {
  const fs::path dir = fresh_temp_path("helical_geometry");
  fs::create_directories(dir);
  write_text(dir / "h.yaml", helical_yaml("  hand: right\n"));
  const auto r = run_gearmc("geometry " + (dir / "h.yaml").string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const nlohmann::json j = nlohmann::json::parse(r.out);
  // tests/gears/helical_reference.py (ISO 21771 in Python): printed to the nanometre / 1e-9°.
  EXPECT_NEAR(j["helix"]["transverse_module_m_t_mm"].get<double>(), 4.141104721640, 1e-6);
  EXPECT_NEAR(j["helix"]["transverse_pressure_angle_alpha_t_deg"].get<double>(), 20.646896487046,
              1e-9);
  EXPECT_NEAR(j["helix"]["base_helix_angle_beta_b_deg"].get<double>(), 14.076095421662, 1e-9);
  EXPECT_NEAR(j["helix"]["lead_p_z_mm"].get<double>(), 1505.134557972064, 1e-6);
  EXPECT_EQ(j["helix"]["hand"], "right");
  EXPECT_NEAR(j["geometry_mm"]["reference_diameter_d"].get<double>(), 128.374246370850, 1e-6);
  EXPECT_NEAR(j["geometry_mm"]["base_diameter_d_b"].get<double>(), 120.128927774273, 1e-6);
  EXPECT_NEAR(j["geometry_mm"]["tip_diameter_d_a"].get<double>(), 137.974246370850, 1e-6);
  EXPECT_NEAR(j["geometry_mm"]["tooth_thickness_s"].get<double>(), 7.107727627888, 1e-6);
  // p_bn = pi m_n cos(alpha_n) (ISO 21771), 11.808526... mm, from the transverse p_bt cos(beta_b).
  EXPECT_NEAR(j["helix"]["normal_base_pitch_p_bn_mm"].get<double>(),
              3.14159265358979 * 4 * 0.93969262078591, 1e-6);
}

TEST(HelicalScenario, SpurScenarioHasNoHelixBlock) {
  const auto r = run_gearmc("geometry");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_FALSE(nlohmann::json::parse(r.out).contains("helix"));
}

TEST(HelicalScenario, HandIsRequiredWithAHelixAngleAndRefusedWithout) {
  const fs::path dir = fresh_temp_path("helical_hand");
  fs::create_directories(dir);
  write_text(dir / "no_hand.yaml", helical_yaml(""));
  const auto none = run_gearmc("geometry " + (dir / "no_hand.yaml").string());
  EXPECT_EQ(none.exit_code, 2);
  EXPECT_NE(none.err.find("no_hand.yaml:6:3: gear.hand"), std::string::npos) << none.err;
  EXPECT_NE(none.err.find("'right' or 'left' with helix_angle_deg 15"), std::string::npos)
      << none.err;
  std::string spur = helical_yaml("  hand: left\n");
  spur.replace(spur.find("helix_angle_deg: 15"), 19, "helix_angle_deg: 0");
  write_text(dir / "spur_hand.yaml", spur);
  const auto spur_hand = run_gearmc("geometry " + (dir / "spur_hand.yaml").string());
  EXPECT_EQ(spur_hand.exit_code, 2);
  EXPECT_NE(spur_hand.err.find("spur_hand.yaml:7:9: gear.hand: got 'left'"), std::string::npos)
      << spur_hand.err;
  write_text(dir / "sideways.yaml", helical_yaml("  hand: up\n"));
  const auto sideways = run_gearmc("geometry " + (dir / "sideways.yaml").string());
  EXPECT_EQ(sideways.exit_code, 2);
  EXPECT_NE(sideways.err.find("gear.hand: got 'up'"), std::string::npos) << sideways.err;
}

// Internal gears are a known key whose message says they are not modelled yet (not "unknown
// key"); `internal: false` is the default and accepted. Design modifications are read, placed at
// their key when wrong; a linear end relief (kinks across the face) and a linear tip relief are
// read and `geometry` says their shapes.
TEST(HelicalScenario, ImpossibleRingGearsAreRefusedAndModificationsRead) {
  const fs::path dir = fresh_temp_path("helical_next");
  fs::create_directories(dir);
  write_text(dir / "external.yaml", helical_yaml("  hand: right\n  internal: false\n"));
  EXPECT_EQ(run_gearmc("geometry " + (dir / "external.yaml").string()).exit_code, 0);
  // The example's data as a ring gear: its tip circle d - 2 m_n (1 + x) = 118.77 mm falls inside
  // the base circle d_b = 120.13 mm (tests/gears/helical_reference.py): no involute to measure.
  write_text(dir / "ring.yaml", helical_yaml("  hand: right\n  internal: true\n"));
  const auto ring = run_gearmc("geometry " + (dir / "ring.yaml").string());
  EXPECT_EQ(ring.exit_code, 2);
  EXPECT_NE(ring.err.find("ring.yaml:2:1: gear: expected parameters that make a gear, but tip "
                          "diameter 118.774 mm"),
            std::string::npos)
      << ring.err;
  EXPECT_NE(ring.err.find("of the internal gear is not above the base diameter 120.129 mm"),
            std::string::npos)
      << ring.err;
  // A negative tooth count is an internal gear (ISO 21771); with `internal: false` it is a
  // contradiction, said at the key.
  std::string negative = helical_yaml("  hand: right\n  internal: false\n");
  negative.replace(negative.find("teeth: 31"), 9, "teeth: -31");
  write_text(dir / "negative.yaml", negative);
  const auto contradiction = run_gearmc("geometry " + (dir / "negative.yaml").string());
  EXPECT_EQ(contradiction.exit_code, 2);
  EXPECT_NE(contradiction.err.find("negative.yaml:8:13: gear.internal: got 'false', expected true "
                                   "or no `internal` key with teeth -31"),
            std::string::npos)
      << contradiction.err;
  const std::string modified =
      "  hand: right\n  modifications:\n"
      "    tip_relief: {amount_um: 10, length_mm: 3}\n"
      "    end_relief: {amount_um: 8, length_mm: 4, shape: circular}\n"
      "    helix_crowning_um: 5\n";
  write_text(dir / "relief.yaml", helical_yaml(modified));
  const auto relief = run_gearmc("geometry " + (dir / "relief.yaml").string());
  ASSERT_EQ(relief.exit_code, 0) << relief.err;
  // `geometry` says where each modification starts: the tip relief 3 mm of roll below the tip,
  // at the diameter 2 sqrt(r_b² + L²) of that roll length (d_b from
  // tests/gears/helical_reference.py); the end relief leaves z 4 … 36 mm unrelieved.
  const nlohmann::json g = nlohmann::json::parse(relief.out);
  const double L_a = g["geometry_mm"]["tip_roll_length_L_a"].get<double>();
  const double start = g["modifications"]["tip_relief"]["starts_at_roll_length_mm"].get<double>();
  EXPECT_NEAR(start, L_a - 3.0, 1e-6);
  const double r_b = 120.128927774273 / 2;
  EXPECT_NEAR(g["modifications"]["tip_relief"]["starts_at_diameter_mm"].get<double>(),
              2 * std::sqrt(r_b * r_b + start * start), 1e-5);
  EXPECT_EQ(g["modifications"]["end_relief"]["unrelieved_z_mm"],
            nlohmann::json::parse("[4.0, 36.0]"));
  EXPECT_EQ(g["modifications"]["helix_crowning_um"], 5.0);
  EXPECT_FALSE(g["modifications"].contains("root_relief"));
  std::string linear = modified;
  linear.replace(linear.find("shape: circular"), 15, "shape: linear");
  write_text(dir / "linear.yaml", helical_yaml(linear));
  const auto kink = run_gearmc("geometry " + (dir / "linear.yaml").string());
  ASSERT_EQ(kink.exit_code, 0) << kink.err;
  EXPECT_EQ(nlohmann::json::parse(kink.out)["modifications"]["end_relief"]["shape"], "linear");
  EXPECT_EQ(g["modifications"]["end_relief"]["shape"], "circular");
  std::string linear_tip = modified;
  linear_tip.replace(linear_tip.find("length_mm: 3}"), 13, "length_mm: 3, shape: linear}");
  write_text(dir / "linear_tip.yaml", helical_yaml(linear_tip));
  const auto tip = run_gearmc("geometry " + (dir / "linear_tip.yaml").string());
  ASSERT_EQ(tip.exit_code, 0) << tip.err;
  EXPECT_EQ(nlohmann::json::parse(tip.out)["modifications"]["tip_relief"]["shape"], "linear");
  std::string no_length = modified;
  no_length.replace(no_length.find(", length_mm: 3"), 14, "");
  write_text(dir / "no_length.yaml", helical_yaml(no_length));
  const auto missing = run_gearmc("geometry " + (dir / "no_length.yaml").string());
  EXPECT_EQ(missing.exit_code, 2);
  EXPECT_NE(missing.err.find("gear.modifications.tip_relief.length_mm"), std::string::npos)
      << missing.err;
  std::string too_long = modified;
  too_long.replace(too_long.find("length_mm: 4"), 12, "length_mm: 30");
  write_text(dir / "too_long.yaml", helical_yaml(too_long));
  const auto long_relief = run_gearmc("geometry " + (dir / "too_long.yaml").string());
  EXPECT_EQ(long_relief.exit_code, 2);
  EXPECT_NE(long_relief.err.find("more than half the face width"), std::string::npos)
      << long_relief.err;
}

// Every command takes a helical gear: run (with the gear parameters), check, sweep, simulate,
// export-mesh and diagnose exit 0 and write their outputs.
TEST(HelicalScenario, EveryCommandRunsOnAHelicalGear) {
  const fs::path dir = fresh_temp_path("helical_commands");
  fs::create_directories(dir);
  const std::string s = (dir / "h.yaml").string();
  write_text(s, helical_yaml("  hand: left\n") +
                    "probing: {points_along_profile: 6, sections_across_face: 4}\n"
                    "run: {gears: 4}\n"
                    "evaluation: {parameters: all}\n"
                    "claims:\n"
                    "  - {name: flank_max, quantity: delta_rcomp.flank_max, statistic: {quantile: "
                    "0.9}, at_most_um: 50}\n");
  const std::string out = (dir / "out").string();
  const std::pair<std::string, std::string> commands[] = {
      {"run " + s + " --out " + out + "_run", out + "_run/summary.json"},
      {"check " + s + " --out " + out + "_check", out + "_check/check.json"},
      {"sweep " + s + " --vary stylus.radius_mm=0.5,1 --out " + out + "_sweep",
       out + "_sweep/sweep.json"},
      {"simulate " + s + " --gears 1 --out " + out + ".csv", out + ".csv"},
      {"export-mesh " + s + " --gear 0 --out " + out + ".stl", out + ".stl"},
      {"diagnose --model " + s + " --measured " + out + ".csv --out " + out + "_diagnose",
       out + "_diagnose/diagnosis.json"},
  };
  for (const auto& [args, written] : commands) {
    const auto r = run_gearmc(args);
    EXPECT_EQ(r.exit_code, 0) << args << "\n" << r.err;
    EXPECT_TRUE(fs::exists(written)) << args;
  }
  const nlohmann::json summary = nlohmann::json::parse(read_text(out + "_run/summary.json"));
  EXPECT_EQ(summary["failed_contacts"], 0);
  EXPECT_EQ(summary["contacts"], 4 * 31 * 2 * 6 * 4);
}

// `gearmc export-plan` on a helical gear: the DMIS program holds every planned point on the
// involute helicoid. Independent of gearmc's flank code: un-screwing a point (turning it by
// -z tan(beta) / r about the axis, right hand; ISO 21771's screw of a helical gear) must land on
// the transverse involute of the section z = 0, whose polar angle at radius r is the tooth's
// centre +/- psi(r), psi(r) = s_t / d + inv(alpha_t) - inv(alpha_r), cos(alpha_r) = r_b / r
// (ISO 21771 §5.3, half the transverse tooth thickness angle), values from
// tests/gears/helical_reference.py; every normal is unit, with the axial component
// -/+ sin(beta_b) = sin(15°) cos(20°) (− on an R flank of a right-hand gear).
TEST(HelicalScenario, ExportPlanPutsThePlanOnTheHelicoid) {
  const fs::path dir = fresh_temp_path("helical_plan");
  fs::create_directories(dir);
  const std::string s = (dir / "h.yaml").string();
  write_text(s, helical_yaml("  hand: right\n"));
  const std::string file = (dir / "plan.dmi").string();
  const auto r = run_gearmc("export-plan " + s + " --out " + file);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string text = read_text(file);
  EXPECT_NE(text.find("helix 15 deg right hand"), std::string::npos);
  const double sin_beta_b =
      std::sin(15.0 * std::numbers::pi / 180) * std::cos(20.0 * std::numbers::pi / 180);
  static const std::regex feature(R"(^F\(T(\d+)([LR])_I\d+_J\d+\)=FEAT/POINT,CART,(.*)$)");
  std::istringstream in(text);
  int points = 0;
  double worst_angle = 0.0, worst_normal = 0.0;
  for (std::string line; std::getline(in, line);) {
    std::smatch m;
    if (!std::regex_match(line, m, feature)) continue;
    std::vector<double> v;
    std::stringstream fields(m[3].str());
    for (std::string x; std::getline(fields, x, ',');) v.push_back(std::stod(x));
    ASSERT_EQ(v.size(), 6u);
    const int tooth = std::stoi(m[1].str());
    const double side = m[2].str() == "R" ? 1.0 : -1.0;
    worst_angle = std::max(worst_angle, helicoid_offset_mm(v[0], v[1], v[2], tooth, side));
    const Eigen::Vector3d n(v[3], v[4], v[5]);
    worst_normal = std::max(worst_normal, std::abs(n.norm() - 1.0));
    worst_normal = std::max(worst_normal, std::abs(n.z() - (-side * sin_beta_b)));
    ++points;
  }
  EXPECT_EQ(points, 31 * 2 * 10 * 5);  // every tooth, both flanks, the default 10 x 5 grid
  EXPECT_LT(worst_angle, 2e-6);        // the file's 6 decimals (1 nm) and the printed inputs
  EXPECT_LT(worst_normal, 2e-9);       // 9 decimals
}

// `gearmc export-mesh` of the nominal helical gear (random: false): every vertex between the form
// and the tip circle is a flank vertex and lies on the involute helicoid (helicoid_offset_mm,
// independent of gearmc's flank code), to the file's precision: OpenMesh writes every format in
// single precision (docs/contact.md), 2^-24 of 69 mm = 4 nm per coordinate.
TEST(HelicalScenario, ExportMeshPutsTheFlanksOnTheHelicoid) {
  const fs::path dir = fresh_temp_path("helical_mesh");
  fs::create_directories(dir);
  const std::string s = (dir / "h.yaml").string();
  write_text(s, helical_yaml("  hand: right\n") + "deviations: {random: false}\n");
  const std::string file = (dir / "gear.obj").string();
  const auto r = run_gearmc("export-mesh " + s + " --gear 0 --profile-samples 9 --face-samples 7 " +
                            "--out " + file);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  // tests/gears/helical_reference.py: d_a 137.974246370850; the form circle from L_Ff (below
  // the reference circle: everything above 130 mm and below the tip is flank).
  const double r_tip = 137.974246370850 / 2, r_low = 65.0;
  const double float_mm = 69.0 * std::ldexp(1.0, -24);
  std::istringstream in(read_text(file));
  int flank_vertices = 0;
  double worst = 0.0;
  for (std::string line; std::getline(in, line);) {
    if (line.rfind("v ", 0) != 0) continue;
    std::istringstream v(line.substr(2));
    double x, y, z;
    v >> x >> y >> z;
    const double rho = std::hypot(x, y);
    if (rho < r_low || rho > r_tip - 4 * float_mm) continue;  // the tip land's vertices
    worst = std::max(
        worst, std::min(helicoid_offset_mm(x, y, z, 0, 1.0), helicoid_offset_mm(x, y, z, 0, -1.0)));
    ++flank_vertices;
  }
  EXPECT_GE(flank_vertices, 31 * 2 * 7 * 3);  // at least 3 of the 9 profile samples per flank
  EXPECT_LT(worst, 3 * float_mm);             // the three rounded coordinates
}

// On a helicoid the axial effects are visible (the normal has the axial component -/+ sin beta_b;
// on a spur gear a z scale error moves no reading along the normal): readings of a nominal master
// simulated with a z scale error of 30 ppm, an xz squareness of 40 µrad and 0.1 µm of noise;
// `gearmc diagnose` against the plain model names both and recovers the values within 4 of its
// standard errors (a bound at 6e-5 two-sided per value; fixed seed 1).
TEST(HelicalScenario, DiagnoseFindsTheAxialEffectsOnAHelicoid) {
  const fs::path dir = fresh_temp_path("helical_diagnose");
  fs::create_directories(dir);
  const std::string model = (dir / "model.yaml").string();
  const std::string machine = (dir / "machine.yaml").string();
  write_text(model, helical_yaml("  hand: right\n") + "stylus: {radius_mm: 1.0}\n");
  write_text(machine, helical_yaml("  hand: right\n") +
                          "stylus: {radius_mm: 1.0}\n"
                          "effects:\n"
                          "  squareness: {xy_urad: 0, xz_urad: 40, yz_urad: 0}\n"
                          "  scale: {x_ppm: 0, y_ppm: 0, z_ppm: 30}\n"
                          "  noise: {sigma_um: 0.1}\n");
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
      found[effect["name"].get<std::string>() + "." + name] = {
          value.get<double>(), effect["std_errors"][name].get<double>()};
    }
  }
  ASSERT_TRUE(found.count("scale.z_ppm")) << j["effects"].dump();
  ASSERT_TRUE(found.count("squareness.xz_urad")) << j["effects"].dump();
  const auto [z_ppm, z_se] = found["scale.z_ppm"];
  const auto [xz, xz_se] = found["squareness.xz_urad"];
  EXPECT_NEAR(z_ppm, 30.0, 4 * z_se);
  EXPECT_NEAR(xz, 40.0, 4 * xz_se);
  EXPECT_LT(z_se, 2.0);  // a real measurement of z scale, not a wide guess
}

// The stylus shaft through `run`: a 0.8 mm stem on a 2 mm ball parallel to the axis collides on
// the helical gear (the space turns under it; tests/engine/contact/stylus_shaft_test.cpp checks
// where against brute force and first order), never within the top 2 mm of the face (on this
// gear it clears from 2.5 mm below the top on one flank side, 18.5 mm on the other); a radial
// stem of the same size never does, nor does a gear without `shaft_diameter_mm`; the contacts
// the shaft leaves alone keep their values byte for byte.
TEST(HelicalScenario, AnAxialStylusShaftCollidesWhereTheSpaceTurnsUnderIt) {
  const fs::path dir = fresh_temp_path("helical_shaft");
  fs::create_directories(dir);
  const std::string probing =
      "probing: {points_along_profile: 5, sections_across_face: 9, teeth: [1, 2]}\n"
      "run: {gears: 1}\n";
  std::map<std::string, std::vector<std::vector<std::string>>> rows;  // stylus -> points.csv
  for (const std::string stylus :
       {"{radius_mm: 1.0}", "{radius_mm: 1.0, shaft_diameter_mm: 0.8}",
        "{radius_mm: 1.0, shaft_diameter_mm: 0.8, shaft_axis: radial}"}) {
    const std::string s = (dir / ("s" + std::to_string(rows.size()) + ".yaml")).string();
    write_text(s, helical_yaml("  hand: right\n") + probing + "stylus: " + stylus + "\n");
    const std::string out = (dir / ("out" + std::to_string(rows.size()))).string();
    const auto r = run_gearmc("run " + s + " --points --out " + out);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    std::istringstream csv(read_text(out + "/points.csv"));
    std::string line;
    auto& table = rows[stylus];
    while (std::getline(csv, line)) {
      if (line.empty() || line[0] == '#' || line.rfind("gear,", 0) == 0) continue;
      std::vector<std::string> fields;
      std::stringstream ss(line);
      for (std::string f; std::getline(ss, f, ',');) fields.push_back(f);
      ASSERT_EQ(fields.size(), 23u) << line;
      table.push_back(fields);
    }
  }
  const auto& plain = rows["{radius_mm: 1.0}"];
  const auto& axial = rows["{radius_mm: 1.0, shaft_diameter_mm: 0.8}"];
  const auto& radial = rows["{radius_mm: 1.0, shaft_diameter_mm: 0.8, shaft_axis: radial}"];
  ASSERT_EQ(plain.size(), 2u * 2 * 5 * 9);
  ASSERT_EQ(axial.size(), plain.size());
  ASSERT_EQ(radial.size(), plain.size());
  int shaft = 0;
  for (std::size_t k = 0; k < plain.size(); ++k) {
    EXPECT_EQ(plain[k].back(), "ok");
    EXPECT_EQ(radial[k], plain[k]);  // the radial stem never meets the widening space
    if (axial[k].back() == "shaft") {
      ++shaft;
      EXPECT_LT(std::stod(axial[k][7]), 40.0 - 2.0) << "pz of a shaft collision";
    } else {
      EXPECT_EQ(axial[k], plain[k]);
    }
  }
  EXPECT_GT(shaft, 0);
}

}  // namespace
}  // namespace gearmc
