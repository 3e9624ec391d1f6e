// Helical gears in scenarios: `gear: helix_angle_deg` and `hand` read as docs/scenarios.md says,
// `gearmc geometry` prints the helical gear's dimensions (ISO 21771, evaluated independently in
// tests/gears/helical_reference.py), `gearmc export-plan` puts the plan on the helicoid, and
// every command that simulates or evaluates a measurement refuses a helical gear with one
// located message and exit 2, leaving nothing behind.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <filesystem>
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

// Internal gears and design modifications are known keys whose message says they are not
// modelled yet (not "unknown key"); `internal: false` is the default and accepted.
TEST(HelicalScenario, InternalGearsAndModificationsAreRefusedAsNotYetModelled) {
  const fs::path dir = fresh_temp_path("helical_next");
  fs::create_directories(dir);
  write_text(dir / "external.yaml", helical_yaml("  hand: right\n  internal: false\n"));
  EXPECT_EQ(run_gearmc("geometry " + (dir / "external.yaml").string()).exit_code, 0);
  write_text(dir / "ring.yaml", helical_yaml("  hand: right\n  internal: true\n"));
  const auto ring = run_gearmc("geometry " + (dir / "ring.yaml").string());
  EXPECT_EQ(ring.exit_code, 2);
  EXPECT_NE(ring.err.find("ring.yaml:8:13: gear.internal: got 'true', expected false: internal "
                          "(ring) gears are not modelled yet"),
            std::string::npos)
      << ring.err;
  write_text(dir / "relief.yaml",
             helical_yaml("  hand: right\n  modifications: {tip_relief: {amount_um: 10}}\n"));
  const auto relief = run_gearmc("geometry " + (dir / "relief.yaml").string());
  EXPECT_EQ(relief.exit_code, 2);
  EXPECT_NE(relief.err.find("gear.modifications"), std::string::npos) << relief.err;
  EXPECT_NE(relief.err.find("are not modelled yet"), std::string::npos) << relief.err;
}

// Every command that probes, meshes or evaluates the gear: exit 2, one message at the helix
// angle's line and column, nothing written.
TEST(HelicalScenario, CommandsThatProbeTheGearRefuseItAtTheHelixAngle) {
  const fs::path dir = fresh_temp_path("helical_refused");
  fs::create_directories(dir);
  const std::string s = (dir / "h.yaml").string();
  write_text(s, helical_yaml("  hand: left\n"));
  const std::string out = (dir / "out").string();
  const std::pair<const char*, std::string> commands[] = {
      {"run", "run " + s + " --out " + out},
      {"check", "check " + s + " --out " + out},
      {"sweep", "sweep " + s + " --vary stylus.radius_mm=0.5,1 --out " + out},
      {"simulate", "simulate " + s + " --out " + out + ".csv"},
      {"export-mesh", "export-mesh " + s + " --gear 0 --out " + out + ".stl"},
      {"diagnose", "diagnose --model " + s + " --measured " + s + " --out " + out},
  };
  for (const auto& [name, args] : commands) {
    const auto r = run_gearmc(args);
    EXPECT_EQ(r.exit_code, 2) << name << "\n" << r.err;
    EXPECT_NE(r.err.find("h.yaml:6:20: gear.helix_angle_deg: got '15', expected 0 for `gearmc " +
                         std::string(name) + "`"),
              std::string::npos)
        << name << "\n"
        << r.err;
    for (const char* ext : {"", ".csv", ".stl", ".dmi"}) {
      EXPECT_FALSE(fs::exists(out + ext)) << name << " left " << out << ext;
    }
  }
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
  // tests/gears/helical_reference.py: d 128.374246370850, d_b 120.128927774273, s_t
  // 7.107727627888, alpha_t 20.646896487046°.
  const double kPi = std::numbers::pi;
  const double d = 128.374246370850, r_b = 120.128927774273 / 2, s_t = 7.107727627888;
  const double alpha_t = 20.646896487046 * kPi / 180;
  const double inv_t = std::tan(alpha_t) - alpha_t;
  const double turn = std::tan(15.0 * kPi / 180) / (d / 2);  // rad per mm of z, right hand
  const double sin_beta_b = std::sin(15.0 * kPi / 180) * std::cos(20.0 * kPi / 180);
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
    const double back = -v[2] * turn;
    const double x = std::cos(back) * v[0] - std::sin(back) * v[1];
    const double y = std::sin(back) * v[0] + std::cos(back) * v[1];
    const double rho = std::hypot(x, y);
    const double alpha_r = std::acos(r_b / rho);
    const double psi = s_t / d + inv_t - (std::tan(alpha_r) - alpha_r);
    const double centre = (tooth - 1) * 2 * kPi / 31;
    const double angle = std::remainder(std::atan2(y, x) - centre - side * psi, 2 * kPi);
    worst_angle = std::max(worst_angle, std::abs(angle) * rho);  // mm along the arc
    const Eigen::Vector3d n(v[3], v[4], v[5]);
    worst_normal = std::max(worst_normal, std::abs(n.norm() - 1.0));
    worst_normal = std::max(worst_normal, std::abs(n.z() - (-side * sin_beta_b)));
    ++points;
  }
  EXPECT_EQ(points, 31 * 2 * 10 * 5);  // every tooth, both flanks, the default 10 x 5 grid
  EXPECT_LT(worst_angle, 2e-6);        // the file's 6 decimals (1 nm) and the printed inputs
  EXPECT_LT(worst_normal, 2e-9);       // 9 decimals
}

}  // namespace
}  // namespace gearmc
