// The `cmm:` section and its effects (engine/effects/cmm_effects.h): the section's keys and its
// bad input (one InputError at the key, with file:line:column), the refusal when the prior cannot
// meet the data sheet, one kept machine per gear named alike by both effects, and the effects'
// displacement on hand-made machines against hand-computed values.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <string>

#include "engine/effects/cmm_effects.h"
#include "engine/effects/rotary_table.h"
#include "engine/machine/verification.h"
#include "engine/scenario/scenario.h"
#include "tests/support/run_gearmc.h"
#include "tests/support/scenario_input.h"
#include "tests/support/temp_paths.h"

namespace gearmc {
namespace {

using testing_support::expect_at;
using testing_support::kGear;
using testing_support::parse_error;

const std::string kCmm =
    "cmm:\n"
    "  mpe_e_um: \"1.8 + L/300\"\n"
    "  mpe_p_um: 1.7\n"
    "  machines: 20\n";

TEST(CmmSection, ReadsTheDataSheetAndPutsTwoEffectsInTheChain) {
  const Scenario s = parse_scenario(kGear + kCmm, "t.yaml");
  ASSERT_TRUE(s.cmm);
  EXPECT_EQ(s.cmm->kept.kept.size(), 20u);
  EXPECT_DOUBLE_EQ(s.cmm->mpe_e.at(300.0), 2.8);
  EXPECT_EQ(s.cmm->layout, MachineLayout::kBridge);
  EXPECT_DOUBLE_EQ(s.cmm->stylus_length_mm, 50.0);  // the key table's default
  ASSERT_EQ(s.effects->size(), 2u);
  EXPECT_GE(s.effects->find("cmm_geometry"), 0);
  EXPECT_GE(s.effects->find("cmm_probing"), 0);
  // Without MPE_P: no probing part.
  const Scenario g =
      parse_scenario(kGear + "cmm: {mpe_e_um: \"2.5 + L/250\", machines: 10}\n", "t.yaml");
  EXPECT_EQ(g.effects->size(), 1u);
  EXPECT_LT(g.effects->find("cmm_probing"), 0);
  // The scenario's seed draws the machines.
  const Scenario other = parse_scenario("seed: 2\n" + kGear + kCmm, "t.yaml");
  EXPECT_NE(other.cmm->kept.kept[0].squareness_xy_urad, s.cmm->kept.kept[0].squareness_xy_urad);
}

TEST(CmmSection, BothEffectsMeasureAGearOnTheSameMachineAndEveryMachineIsUsed) {
  const Scenario s = parse_scenario(kGear + kCmm, "t.yaml");
  const int geometry = s.effects->find("cmm_geometry");
  const int probing = s.effects->find("cmm_probing");
  std::vector<int> used(20, 0);
  for (int gear = 0; gear < 1000; ++gear) {
    const EffectValues v = s.effects->draw(s.seed, gear);
    const std::size_t a = cmm_machine_index(*s.cmm, v[static_cast<std::size_t>(geometry)][0]);
    const std::size_t b = cmm_machine_index(*s.cmm, v[static_cast<std::size_t>(probing)][0]);
    ASSERT_EQ(a, b) << gear;
    ++used[a];
  }
  // Uniform over 20 machines: 50 each expected, σ = √(1000 · 0.05 · 0.95) = 6.9; every count
  // within ±4.5 σ (a false alarm for any of the 20 below 1e-4).
  for (int count : used) {
    EXPECT_GT(count, 19);
    EXPECT_LT(count, 81);
  }
}

// A model holding one hand-made machine (and its probe).
std::shared_ptr<CmmModel> one_machine(const KinematicMachine& m, const CmmProbe& probe = {}) {
  auto model = std::make_shared<CmmModel>();
  model->kept.kept = {m};
  model->kept.probes = {probe};
  model->mpe_p_um = 1.0;
  return model;
}

TEST(CmmGeometry, MovesTheCentreByTheHandComputedTipError) {
  // Bridge, travel 700 × 1000 × 600 mm. The x axis: positioning δ_x = c₁ P₁(u) with c₁ = 2 µm,
  // u = q_x / 350 mm, and a constant pitch ε_y = 10 µrad of the x carriage. The stylus 50 mm
  // along −z; the ball centre at (60, 10, 5) mm gives q = (60, 10, 55) mm. The x carriage
  // carries z, so its Abbe arm is t + q_z ẑ = (0, 0, 5) mm: ε × arm = (10 · 5, 0, 0) µrad·mm =
  // 0.05 µm along x. Tip error: (2 · 60/350 + 0.05, 0, 0) µm; on the axis at z = 0 it is zero
  // (the model's face width 0: the datum is the axis's point at z = 0 alone).
  KinematicMachine m;
  m.axes[0].translation_um[0] = {0.0, 2.0};
  m.axes[0].rotation_urad[1] = {10.0};
  const CmmGeometryEffect effect(one_machine(m), false, false);
  PointContext point;
  point.p = Eigen::Vector3d(59.5, 10.0, 5.0);
  point.n = Eigen::Vector3d(1.0, 0.0, 0.0);
  Eigen::Vector3d centre(60.0, 10.0, 5.0);
  RandomStream rng(1, 0, StreamPurpose::kEffectNoise, 0);
  const std::vector<double> values = {0.4};
  effect.apply(point, values, centre, rng);
  EXPECT_NEAR((centre.x() - 60.0) * 1e3, 2.0 * 60.0 / 350.0 + 0.05, 1e-9);
  EXPECT_NEAR(centre.y(), 10.0, 1e-15);
  EXPECT_NEAR(centre.z(), 5.0, 1e-15);
  // The index is not a physical quantity: no signature.
  double out[1] = {1.0};
  effect.signature(point, values, out);
  EXPECT_EQ(out[0], 0.0);
}

TEST(CmmGeometry, TheGearsDatumsTakeTheMachinesErrorOnTheAxis) {
  // The gear's axis and lower face are measured on the same machine: what the machine does on
  // the axis is the datum's. x positioning δ_x = c₂ P₂(u), c₂ = 3 µm, u = q_x/350 mm, reads −1.5 µm
  // on the axis (P₂(0) = −1/2) — a shift of the whole gear, not of its flanks; and a constant
  // pitch ε_y = 10 µrad of the x carriage tilts the measured axis as much as the flanks (the axis
  // seen at z = 0 and z = b = 20 mm). At the ball centre (60, 10, 5) mm: δ_x − datum =
  // 3 (P₂(60/350) − P₂(0)) = 3 · 1.5 · (60/350)² µm, the tilt's 10 · 5 µrad·mm cancelled.
  KinematicMachine m;
  m.axes[0].translation_um[0] = {0.0, 0.0, 3.0};
  m.axes[0].rotation_urad[1] = {10.0};
  const Eigen::Vector3d centre(60.0, 10.0, 5.0), stylus(0.0, 0.0, -50.0);
  const Eigen::Vector3d e = datum_relative_error_um(m, centre, stylus, 20.0);
  const double u = 60.0 / 350.0;
  EXPECT_NEAR(e.x(), 3.0 * 1.5 * u * u, 1e-12);
  EXPECT_NEAR(e.y(), 0.0, 1e-12);
  // The raw tip error has the shift and the tilt's Abbe term.
  EXPECT_NEAR(m.tip_error_um(centre, stylus).x(), 3.0 * (1.5 * u * u - 0.5) + 0.05, 1e-12);
  // The effect applies the datum-relative error.
  auto model = one_machine(m);
  model->face_width_mm = 20.0;
  const CmmGeometryEffect effect(model, false, false);
  PointContext point;
  Eigen::Vector3d moved = centre;
  RandomStream rng(1, 0, StreamPurpose::kEffectNoise, 0);
  const std::vector<double> values = {0.0};
  effect.apply(point, values, moved, rng);
  EXPECT_NEAR((moved.x() - centre.x()) * 1e3, 3.0 * 1.5 * u * u, 1e-9);
}

TEST(CmmGeometry, TheStylusOffsetFollowsTheShaft) {
  const Eigen::Vector3d c(30.0, 40.0, 7.0);  // radius 50 mm, r̂ = (0.6, 0.8, 0)
  EXPECT_TRUE(stylus_offset_mm(c, 50.0, false, false).isApprox(Eigen::Vector3d(0, 0, -50)));
  EXPECT_TRUE(stylus_offset_mm(c, 50.0, true, false).isApprox(Eigen::Vector3d(-30, -40, 0)));
  EXPECT_TRUE(stylus_offset_mm(c, 50.0, true, true).isApprox(Eigen::Vector3d(30, 40, 0)));
}

TEST(CmmProbing, PretravelAlongTheApproachAndTheTouchScatterAsItsLaw) {
  // Two lobes a = 0.5 µm, maximum along x. A flank point with n = −x̂ is approached along +x̂
  // (φ = 0, horizontal): p = 0.5 µm further along the approach, the reading 0.5 µm smaller.
  CmmProbe probe;
  probe.cos_um[0] = 0.5;
  probe.noise_um = 0.3;
  const CmmProbingEffect effect(one_machine(KinematicMachine{}, probe));
  PointContext point;
  point.n = Eigen::Vector3d(-1.0, 0.0, 0.0);
  point.p = Eigen::Vector3d(80.0, 0.0, 10.0);
  point.stylus_radius_mm = 0.5;
  const Eigen::Vector3d start = point.p + point.stylus_radius_mm * point.n;
  Eigen::Vector3d centre = start;
  const std::vector<double> values = {0.0};
  effect.apply_mean(point, values, centre);
  EXPECT_NEAR(reading_um(point, centre), -0.5, 1e-9);
  // Approached along +ŷ (φ = 90°): cos 180° = −1, the reading 0.5 µm larger.
  point.n = Eigen::Vector3d(0.0, -1.0, 0.0);
  centre = point.p + point.stylus_radius_mm * point.n;
  effect.apply_mean(point, values, centre);
  EXPECT_NEAR(reading_um(point, centre), 0.5, 1e-9);
  EXPECT_DOUBLE_EQ(effect.point_law(values).gaussian_variance_um2, 0.09);
}

// ---- the rotary table as part of the machine ------------------------------------------------

TEST(CmmRotaryTable, TheTableIsTheRotaryTableEffectsAndTheGeometryIsTakenWhereTheToothIsProbed) {
  // The table's displacement equals the `rotary_table` effect's with the same eight terms (the
  // effect's own tests check its formula against hand values).
  RotaryTableErrors table;
  table.terms = {0.4, -0.2, 0.3, 0.1, 1.5, -0.5, 0.25, 0.75};
  auto model = one_machine(KinematicMachine{});
  model->table = RotaryTableSpec{1.0, 1.0, 4.0};
  model->tables = {table};
  const CmmRotaryTableEffect cmm_table(model);
  std::vector<EffectParameter> fixed_terms;
  for (double v : table.terms) {
    EffectParameter p;
    p.value = v;
    fixed_terms.push_back(p);
  }
  const RotaryTableEffect effect(fixed_terms);
  PointContext point;
  point.teeth = 24;
  point.tooth = 5;
  point.p = Eigen::Vector3d(40.0, 60.0, 30.0);
  point.n = Eigen::Vector3d(0.6, -0.8, 0.0);
  RandomStream rng(1, 0, StreamPurpose::kEffectNoise, 0);
  Eigen::Vector3d a(40.3, 59.6, 30.0), b = a;
  const std::vector<double> index = {0.0};
  cmm_table.apply(point, index, a, rng);
  effect.apply(point, table.terms, b, rng);
  EXPECT_NEAR((a - b).norm(), 0.0, 1e-15);
  EXPECT_GT((a - Eigen::Vector3d(40.3, 59.6, 30.0)).norm(), 1e-5);

  // The geometry with a table: tooth k is probed after the table turned it by −θ_k, so the same
  // point of two teeth meets the same machine error (turned with the gear) — a machine with an
  // x positioning error P₁ (c₁ = 2 µm) gives tooth 1 and tooth 7 the same reading change. Without
  // the table the two teeth lie in different places of the machine and differ.
  KinematicMachine m;
  m.axes[0].translation_um[0] = {0.0, 2.0};
  auto with_table = one_machine(m);
  with_table->table = RotaryTableSpec{};
  with_table->tables = {RotaryTableErrors{}};
  with_table->face_width_mm = 20.0;
  auto without = one_machine(m);
  without->face_width_mm = 20.0;
  const auto reading_change = [&](const std::shared_ptr<CmmModel>& machine_model, int tooth) {
    const CmmGeometryEffect geometry(machine_model, false, false);
    const double theta = 2.0 * std::numbers::pi * (tooth - 1) / 24.0;
    const Eigen::Matrix3d turn =
        Eigen::AngleAxisd(theta, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    PointContext p;
    p.teeth = 24;
    p.tooth = tooth;
    p.p = turn * Eigen::Vector3d(70.0, 3.0, 10.0);
    p.n = turn * Eigen::Vector3d(0.3, 0.95, 0.0).normalized();
    p.stylus_radius_mm = 0.5;
    Eigen::Vector3d c = p.p + 0.5 * p.n;
    const Eigen::Vector3d start = c;
    geometry.apply(p, index, c, rng);
    return 1e3 * (c - start).dot(p.n);
  };
  EXPECT_NEAR(reading_change(with_table, 1), reading_change(with_table, 7), 1e-12);
  EXPECT_GT(std::abs(reading_change(with_table, 1)), 0.1);
  EXPECT_GT(std::abs(reading_change(without, 1) - reading_change(without, 7)), 0.1);
  // Tooth 1 is probed where it lies (θ = 0): with and without the table alike.
  EXPECT_NEAR(reading_change(with_table, 1), reading_change(without, 1), 1e-12);
}

TEST(CmmRotaryTable, KeptTablesMeetTheirDataSheet) {
  RotaryTableErrors t;
  t.terms[0] = 0.3;
  t.terms[1] = 0.4;  // radial amplitude 0.5 µm: range 1 µm
  t.terms[4] = 1.0;  // angular: cos θ alone, range 2″
  EXPECT_DOUBLE_EQ(t.radial_range_um(), 1.0);
  EXPECT_NEAR(t.angular_range_arcsec(), 2.0, 1e-9);
  EXPECT_TRUE(meets(t, {1.0, 0.0, 2.0 + 1e-9}));
  EXPECT_FALSE(meets(t, {0.99, 0.0, 3.0}));
  const Scenario s = parse_scenario(
      kGear +
          "cmm: {mpe_e_um: \"1.8 + L/300\", machines: 200, rotary_table: {radial_um: 0.5, "
          "axial_um: 0.4, angular_arcsec: 1.5}}\n",
      "t.yaml");
  ASSERT_EQ(s.cmm->tables.size(), 200u);
  EXPECT_GT(s.cmm->tables_drawn, 200);
  for (const RotaryTableErrors& k : s.cmm->tables) EXPECT_TRUE(meets(k, *s.cmm->table));
  EXPECT_GE(s.effects->find("cmm_rotary_table"), 0);
  // A perfect table (no values): the gear turned, no motion errors.
  const Scenario perfect = parse_scenario(
      kGear + "cmm: {mpe_e_um: \"1.8 + L/300\", machines: 200, rotary_table: {}}\n", "t.yaml");
  for (const RotaryTableErrors& k : perfect.cmm->tables) {
    for (double v : k.terms) EXPECT_EQ(v, 0.0);
  }
}

// ---- the commands take the section as any other part of the scenario ------------------------

TEST(CmmCommands, CheckDecidesAClaimOnUAndSweepSeesTheProbe) {
  const std::string dir = testing_support::fresh_temp_path("cmm_commands");
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  const std::string base = kGear +
                           "evaluation: {parameters: [f_pt]}\n"
                           "cmm: {mpe_e_um: \"1.8 + L/300\", mpe_p_um: 1.7, machines: 200}\n";
  {
    // f_pt's U on this machine is about 0.9 µm (docs/cmm.md): "U ≤ 3 µm" holds, "U ≤ 0.3 µm"
    // fails — with the machine in the gears, not without it.
    std::ofstream f(dir + "/c.yaml");
    f << base
      << "claims:\n"
         "  - {name: holds, quantity: parameters.f_pt.error, statistic: U, at_most_um: 3.0}\n"
         "  - {name: fails, quantity: parameters.f_pt.error, statistic: U, at_most_um: 0.3}\n";
  }
  const auto check = testing_support::run_gearmc(
      "check " + dir + "/c.yaml --max-gears 256 --quiet --out " + dir + "/check");
  EXPECT_EQ(check.exit_code, 1) << check.err;  // a claim fails
  std::ifstream j(dir + "/check/check.json");
  const std::string json((std::istreambuf_iterator<char>(j)), std::istreambuf_iterator<char>());
  EXPECT_NE(json.find("\"holds\""), std::string::npos);
  // sweep over MPE_P: f_pt's U grows with the probe the data sheet allows (MPE_P 0.5 → 3 µm).
  {
    std::ofstream f(dir + "/s.yaml");
    f << base;
  }
  const auto sweep = testing_support::run_gearmc(
      "sweep " + dir +
      "/s.yaml --vary cmm.mpe_p_um=0.5,3 --statistic parameters.f_pt.U --gears 100 "
      "--quiet --out " +
      dir + "/sweep");
  ASSERT_EQ(sweep.exit_code, 0) << sweep.err;
  const auto u_at = [&](const std::string& mpe) {
    const std::string marker = "cmm.mpe_p_um=" + mpe + "  parameters.f_pt.U (larger side) = ";
    const auto at = sweep.out.find(marker);
    EXPECT_NE(at, std::string::npos) << sweep.out;
    return at == std::string::npos ? 0.0 : std::stod(sweep.out.substr(at + marker.size()));
  };
  EXPECT_GT(u_at("3"), 1.5 * u_at("0.5"));
}

// ---- the user's verification results --------------------------------------------------------

TEST(CmmVerification, ReadsTheTableAndDrawsMachinesThatAgreeWithIt) {
  const std::string dir = testing_support::fresh_temp_path("cmm_verification");
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  {
    // A machine with a +2 ppm x scale error only: E = 2e-3 (L + 2R) û_x² µm (the length test's
    // gauge is touched from outside, R = 1.5 mm), on the x axis and one diagonal, u = 0.1 µm.
    std::ofstream f(dir + "/v.csv");
    f << "# measured length errors\n\nposition, length_mm, error_um\n";
    const double ux2 = 700.0 * 700.0 / (700.0 * 700.0 + 1000.0 * 1000.0 + 600.0 * 600.0);
    for (double l : {100.0, 300.0, 500.0}) f << "x," << l << "," << 2e-3 * (l + 3.0) << "\n";
    for (double l : {200.0, 600.0, 1000.0}) {
      f << "diagonal_ppp," << l << "," << 2e-3 * (l + 3.0) * ux2 << "\n";
    }
  }
  {
    std::ofstream f(dir + "/s.yaml");
    f << kGear
      << "cmm:\n  mpe_e_um: \"1.8 + L/300\"\n  machines: 200\n  verification: v.csv\n"
         "  verification_u_um: 0.1\n";
  }
  const Scenario s = load_scenario_file(dir + "/s.yaml");
  ASSERT_TRUE(s.cmm->posterior);
  EXPECT_EQ(s.cmm->verification.size(), 6u);
  EXPECT_EQ(s.cmm->verification_path, dir + "/v.csv");
  EXPECT_GT(s.cmm->posterior->p_value, 1e-3);
  EXPECT_TRUE(s.warnings.empty()) << s.warnings.front();
  // The kept machines make the measured x errors within a few u (the prior alone: up to MPE_E,
  // 2.1 … 3.5 µm at these lengths) and a 2 ppm x scale on a length they were not told (600 mm).
  LengthTestOptions test;
  test.stylus_mm = Eigen::Vector3d(0, 0, -50);
  double mean = 0.0;
  for (std::size_t m = 0; m < s.cmm->kept.kept.size(); ++m) {
    const KinematicMachine& k = s.cmm->kept.kept[m];
    for (const VerificationRow& r : s.cmm->verification) {
      EXPECT_NEAR(length_error_um(k, s.cmm->kept.probes[m], r.position, r.length_mm, test),
                  r.error_um, 0.5);
    }
    mean += length_error_um(k, s.cmm->kept.probes[m], 4, 600.0, test);
  }
  mean /= static_cast<double>(s.cmm->kept.kept.size());
  EXPECT_NEAR(mean, 2e-3 * 603.0, 0.15);
  // A table no machine can make — the same length measured +1 µm and −1 µm with u = 0.01 µm:
  // the machines are drawn (they meet the MPE) but a warning names the χ².
  {
    std::ofstream f(dir + "/bad.csv");
    f << "position,length_mm,error_um,u_um\nx,300,1.0,0.01\nx,300,-1.0,0.01\n";
  }
  {
    std::ofstream f(dir + "/bad.yaml");
    f << kGear << "cmm:\n  mpe_e_um: \"1.8 + L/300\"\n  machines: 200\n  verification: bad.csv\n";
  }
  const Scenario bad = load_scenario_file(dir + "/bad.yaml");
  ASSERT_FALSE(bad.warnings.empty());
  EXPECT_NE(bad.warnings.back().find(
                "bad.yaml:8:17: cmm.verification: the measured length errors are unlike"),
            std::string::npos)
      << bad.warnings.back();
  EXPECT_LT(bad.cmm->posterior->p_value, 1e-6);
}

TEST(CmmVerification, ATableInsteadOfTheDataSheet) {
  // No mpe_e_um: the prior's scales come from the table, no MPE_E is passed, the outputs say so.
  const std::string dir = testing_support::fresh_temp_path("cmm_table_only");
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  std::filesystem::copy_file(
      std::string(GEARMC_SOURCE_DIR) + "/scenarios/cmm_verification_example.csv", dir + "/v.csv");
  {
    std::ofstream f(dir + "/s.yaml");
    f << kGear << "cmm:\n  machines: 200\n  verification: v.csv\n";
  }
  const Scenario s = load_scenario_file(dir + "/s.yaml");
  ASSERT_TRUE(s.cmm);
  EXPECT_TRUE(s.cmm->mpe_from_table);
  EXPECT_EQ(s.cmm->kept.kept.size(), 200u);
  EXPECT_EQ(s.cmm->kept.failed_length, 0);  // nothing to fail
  // Neither an MPE nor a table: the missing key named at the section.
  const InputError e = parse_error(kGear + "cmm:\n  machines: 200\n");
  EXPECT_NE(std::string(e.what()).find("mpe_e_um"), std::string::npos) << e.what();
  EXPECT_NE(std::string(e.what()).find("or a verification table"), std::string::npos) << e.what();
}

TEST(CmmVerification, BadTablesAreOneErrorAtTheirLineAndColumn) {
  const Eigen::Vector3d travel(700, 1000, 600);
  const auto error = [&](const std::string& text, std::optional<double> u = std::nullopt) {
    try {
      read_verification_table(text, "v.csv", travel, u);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_EQ(error("position,length_mm,error_um,u_um\nw,100,0.5,0.1\n"),
            "v.csv:2:1: position: got 'w', expected an ISO 10360-2 position: diagonal_ppp, "
            "diagonal_npp, diagonal_pnp, diagonal_ppn, x, y, z");
  EXPECT_NE(error("position,length_mm,error_um,u_um\nx,800,0.5,0.1\n")
                .find("v.csv:2:3: length_mm: got '800', expected a length > 0 within the x line "
                      "through the travel (700 mm)"),
            std::string::npos);
  EXPECT_NE(error("position,length_mm,error_um\nx,100,0.5\n").find("v.csv:1:1: header"),
            std::string::npos);  // no u anywhere
  EXPECT_EQ(error("position,length_mm,error_um\nx,100,0.5\n", 0.2), "no error");
  EXPECT_NE(error("position,length,error_um,u_um\n").find("v.csv:1:10: header: got 'length'"),
            std::string::npos);
  EXPECT_NE(error("position,length_mm,error_um,u_um\nx,100,abc,0.1\n")
                .find("v.csv:2:7: error_um: got 'abc'"),
            std::string::npos);
  EXPECT_NE(error("position,length_mm,error_um,u_um\nx,100,0.5\n").find("v.csv:2:1: row"),
            std::string::npos);
  EXPECT_NE(error("position,length_mm,error_um,u_um\nx,100,0.5,0\n").find("v.csv:2:11: u_um"),
            std::string::npos);
  EXPECT_NE(error("# nothing\n").find("expected a verification table"), std::string::npos);
  EXPECT_NE(error("position,length_mm,error_um,u_um\n").find("no measured length error"),
            std::string::npos);
}

// ---- bad input ----------------------------------------------------------------------------

TEST(CmmSection, BadInputIsOneErrorAtTheKey) {
  // kGear is lines 1–4, `cmm:` line 5, its first key line 6.
  {
    const InputError e = parse_error(kGear + "cmm:\n  mpe_e_um: \"1.8 + L\"\n");
    expect_at(e, 6, 13);
    EXPECT_NE(std::string(e.what()).find("cmm.mpe_e_um: got '1.8 + L', expected MPE_E as"),
              std::string::npos)
        << e.what();
  }
  {
    const InputError e = parse_error(kGear + "cmm:\n  mpe_e: \"1.8 + L/300\"\n");
    expect_at(e, 6, 3);
    EXPECT_NE(std::string(e.what()).find("mpe_e_um"), std::string::npos) << e.what();  // hint
  }
  {
    const InputError e = parse_error(kGear + "cmm:\n  machines: 20\n");
    EXPECT_NE(std::string(e.what()).find("mpe_e_um"), std::string::npos) << e.what();
  }
  {
    const InputError e =
        parse_error(kGear + "cmm:\n  mpe_e_um: \"1.8 + L/300\"\n  travel_mm: [700, 1000]\n");
    expect_at(e, 7, 14);
    EXPECT_NE(std::string(e.what()).find("three numbers"), std::string::npos) << e.what();
  }
  {
    const InputError e =
        parse_error(kGear + "cmm:\n  mpe_e_um: \"1.8 + L/300\"\n  layout: portal\n");
    expect_at(e, 7, 11);
  }
  {
    const InputError e = parse_error(kGear + "cmm:\n  mpe_e_um: \"1.8 + L/300\"\n  machines: 5\n");
    expect_at(e, 7, 13);
  }
  {
    // P1's gear (tip radius 77.8 mm) placed at x = 300 mm on a 700 mm travel leaves it.
    const InputError e = parse_error(kGear +
                                     "cmm:\n  mpe_e_um: \"1.8 + L/300\"\n  placement_mm: [300, "
                                     "0, 0]\n");
    expect_at(e, 7, 17);
    EXPECT_NE(std::string(e.what()).find("inside the travel"), std::string::npos) << e.what();
  }
  {
    // A data sheet the prior cannot meet: refused at the MPE with the counts.
    // (A = 0 leaves nothing for the probe's even lobes and the short lengths.)
    const InputError e = parse_error(kGear + "cmm:\n  mpe_e_um: \"0 + L/300\"\n  mpe_p_um: 0.3\n");
    expect_at(e, 6, 13);
    EXPECT_NE(std::string(e.what()).find("of 2000 drawn machines passed"), std::string::npos)
        << e.what();
  }
}

TEST(CmmSection, TheCommandExitsWithTwoAndWritesNothing) {
  const std::string dir = testing_support::fresh_temp_path("cmm_bad");
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  {
    std::ofstream f(dir + "/s.yaml");
    f << kGear << "cmm:\n  mpe_e_um: \"0 + L/300\"\n  mpe_p_um: 0.3\n";
  }
  const auto r = testing_support::run_gearmc("run " + dir + "/s.yaml --out " + dir + "/out");
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("s.yaml:6:13: cmm.mpe_e_um"), std::string::npos) << r.err;
  EXPECT_FALSE(std::filesystem::exists(dir + "/out"));
}

TEST(CmmSection, DiagnoseRefusesAPopulationOfMachinesAsItsModel) {
  // diagnose compares readings with one machine; a `cmm:` section is every machine that passes
  // the data sheet — refused at the section's key, before anything is read or written.
  const std::string dir = testing_support::fresh_temp_path("cmm_diagnose");
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  {
    std::ofstream f(dir + "/m.yaml");
    f << kGear << kCmm;
  }
  const auto r = testing_support::run_gearmc("diagnose --model " + dir + "/m.yaml --measured " +
                                             dir + "/none.csv --out " + dir + "/out");
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("m.yaml:5:1: cmm: expected a model with definite machine effects"),
            std::string::npos)
      << r.err;
  EXPECT_FALSE(std::filesystem::exists(dir + "/out"));
}

}  // namespace
}  // namespace gearmc
