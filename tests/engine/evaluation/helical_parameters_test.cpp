// The ISO 1328-1 parameters of a helical gear through the whole measurement (contact on the
// involute helicoid, evaluation in the transverse plane), against deviations whose parameters
// follow from geometry alone: a pure lead deviation is a helix slope and nothing else, a turned
// tooth is a pitch deviation of the arc it turns on the reference circle, an eccentric gear runs
// out by twice its eccentricity, and a z scale error tilts the helix by a predicted amount.
// The gear is the example (z 31, m_n 4 mm, alpha_n 20°, beta 15° right, x 0.2, b 40);
// its transverse values are the independent ISO 21771 evaluation of
// tests/gears/helical_reference.py (also checked by HelicalScenario.GeometryPrints…).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>
#include <string>

#include "engine/run/monte_carlo.h"
#include "engine/scenario/scenario.h"

namespace gearmc {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kDeg = kPi / 180.0;
// tests/gears/helical_reference.py (ISO 21771).
constexpr double kReferenceDiameterMm = 128.374246370850;
constexpr double kBaseDiameterMm = 120.128927774273;
constexpr double kTransversePressureAngleDeg = 20.646896487046;
constexpr double kBaseHelixAngleDeg = 14.076095421662;
constexpr double kTransverseThicknessMm = 7.107727627888;  // s_t on the reference circle
constexpr int kTeeth = 31;

Scenario helical_scenario(const std::string& extra, const char* hand = "right") {
  return parse_scenario(
      std::string("name: h\nseed: 3\n"
                  "gear: {teeth: 31, module_mm: 4, pressure_angle_deg: 20, helix_angle_deg: 15, "
                  "hand: ") +
          hand +
          ", profile_shift: 0.2, face_width_mm: 40}\n"
          "tolerances: {standard: iso_1328_1_2013, grade: 6}\n"
          "probing: {points_along_profile: 10, sections_across_face: 5, margin_fraction: 0.05}\n"
          "stylus: {radius_mm: 1.0}\n" +
          extra,
      "helical.yaml");
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

// A pure lead deviation: the real gear's transverse sections turn by c z more than the nominal
// ones (a lead of 2 pi / (turn + c) on the same base cylinder). Involutes of one base circle
// turned by an angle a are a distance r_b a apart along their common normal, so the deviation is
// the transverse one +/- r_b c z (+ on R flanks, whose transverse normal points
// counter-clockwise) — linear along the helix, the same at every roll length. ISO 1328-1 §3.4:
// f_Hbeta = +/- r_b c L_beta, f_fbeta = 0, F_beta = |f_Hbeta|, and the profile sees nothing.
TEST(HelicalParameters, PureLeadDeviationIsAHelixSlopeAndNothingElse) {
  // r_b c = 0.2 µm/mm: c = 3.3e-6 rad/mm, a lead of 1505.1 mm made 0.08 % shorter.
  const double rb_c_um_per_mm = 0.2;
  const Scenario s = helical_scenario(
      "deviations: {random: false, normal_um: \"side * 0.2 * z\"}\n"
      "evaluation: {parameters: all, profile_points: 25, helix_points: 25}\n");
  const MonteCarloRun mc(s);
  const ParameterEvaluator& e = *mc.parameter_evaluator();
  const double L_beta = e.helix_end_mm() - e.helix_start_mm();
  EXPECT_NEAR(L_beta, 36.0, 1e-12);  // 40 mm less min(5 % of b, m_n) = 2 mm at each end
  const RunResults r = run_one_gear(mc);
  const double expected = rb_c_um_per_mm * L_beta;
  for (int side = 0; side < 2; ++side) {
    const double sign = side == 1 ? 1.0 : -1.0;
    ASSERT_EQ(values(r, GearParameter::kfHbeta, side).size(), static_cast<size_t>(kTeeth));
    for (std::size_t k = 0; k < kTeeth; ++k) {
      const ParameterValue& slope = values(r, GearParameter::kfHbeta, side)[k];
      // Without the normal-to-transverse conversion the measured slope would be cos(beta_b)
      // = 0.970 of this, 0.2 µm off.
      EXPECT_NEAR(slope.true_dense, sign * expected, 1e-6) << side << " " << k;
      EXPECT_NEAR(slope.measured, sign * expected, 2e-3) << side << " " << k;
      EXPECT_NEAR(values(r, GearParameter::kFbeta, side)[k].measured, expected, 2e-3);
      EXPECT_NEAR(values(r, GearParameter::kffbeta, side)[k].measured, 0.0, 2e-3);
      EXPECT_NEAR(values(r, GearParameter::kfHalpha, side)[k].measured, 0.0, 2e-3);
      EXPECT_NEAR(values(r, GearParameter::kffalpha, side)[k].measured, 0.0, 2e-3);
      EXPECT_NEAR(values(r, GearParameter::kFalpha, side)[k].measured, 0.0, 2e-3);
    }
  }
  EXPECT_GT(expected, 7.0);  // visible: 0.2 µm/mm over 36 mm
}

// Tooth 3 turned counter-clockwise by an angle a: its R flank moves along its (counter-clockwise)
// transverse normal by r_b a, its L flank against its normal by the same. On the reference
// circle of the transverse section the tooth moves by the arc r a = (r / r_b) r_b a =
// r_b a / cos(alpha_t): f_pt of the pitch 2 -> 3 is +r a, of 3 -> 4 is -r a, every other 0, and
// F_p = r a, on both flanks. (With the normal pressure angle instead of alpha_t the arc would be
// 0.02 µm short.)
TEST(HelicalParameters, ATurnedToothIsAPitchDeviationOfItsArcOnTheReferenceCircle) {
  const double shift_um = 5.0;  // r_b a
  const Scenario s = helical_scenario(
      "deviations: {random: false, normal_um: \"(tooth == 3) * side * 5\"}\n"
      "evaluation: {parameters: [f_pt, F_p], profile_points: 25}\n");
  const RunResults r = run_one_gear(MonteCarloRun(s));
  const double arc = shift_um * (kReferenceDiameterMm / kBaseDiameterMm);
  EXPECT_NEAR(arc, shift_um / std::cos(kTransversePressureAngleDeg * kDeg), 1e-9);
  for (int side = 0; side < 2; ++side) {
    const auto& single = values(r, GearParameter::kfpt, side);
    ASSERT_EQ(single.size(), static_cast<size_t>(kTeeth));
    for (int k = 0; k < kTeeth; ++k) {  // item k: the pitch from tooth k + 1 to k + 2
      const double expected = k == 1 ? arc : k == 2 ? -arc : 0.0;
      EXPECT_NEAR(single[k].measured, expected, 2e-3) << "side " << side << " pitch " << k + 1;
      EXPECT_NEAR(single[k].true_dense, expected, 1e-6) << "side " << side << " pitch " << k + 1;
    }
    ASSERT_EQ(values(r, GearParameter::kFp, side).size(), 1u);
    EXPECT_NEAR(values(r, GearParameter::kFp, side)[0].measured, arc, 2e-3);
  }
}

// An eccentric helical gear: the gear's axis displaced by e along +X moves every flank point by
// e e_x, a transverse deviation e (e_x · n_t). In the section z the base point of roll length L
// lies at the polar angle phi_b = tooth angle +/- (theta_b - L / r_b) + z turn (theta_b = s_t / d
// + inv(alpha_t), turn = tan(beta_b) / r_b, right hand), and n_t = +/- (-sin phi_b, cos phi_b),
// so the deviation is -side e sin(phi_b). A ball in every tooth space then runs out by 2e
// (ISO 10064-2: the runout of an eccentric gear).
TEST(HelicalParameters, AnEccentricGearRunsOutByTwiceItsEccentricity) {
  const double rb = kBaseDiameterMm / 2;
  const double alpha_t = kTransversePressureAngleDeg * kDeg;
  const double theta_b =
      kTransverseThicknessMm / kReferenceDiameterMm + std::tan(alpha_t) - alpha_t;
  const double turn = std::tan(kBaseHelixAngleDeg * kDeg) / rb;
  const double e_um = 8.0;
  char expression[512];
  std::snprintf(expression, sizeof expression,
                "-side * %.17g * sin((tooth - 1) * %.17g + side * (%.17g - L / %.17g) + z * %.17g)",
                e_um, 2 * kPi / kTeeth, theta_b, rb, turn);
  const Scenario s =
      helical_scenario(std::string("deviations: {random: false, normal_um: \"") + expression +
                       "\"}\n"
                       "evaluation: {parameters: [F_r], profile_points: 25}\n");
  const RunResults r = run_one_gear(MonteCarloRun(s));
  ASSERT_EQ(values(r, GearParameter::kFr, 0).size(), 1u);
  const ParameterValue& runout = values(r, GearParameter::kFr, 0)[0];
  // First order in e/r (8 µm / 64 mm): the ball's second-order terms are below 1e-3 µm; 31
  // spaces sample the sine's extremes to 1 - cos(pi / 31) = 0.5 %.
  EXPECT_NEAR(runout.true_dense, 2 * e_um, 2 * e_um * (1 - std::cos(kPi / kTeeth)) + 1e-3);
  EXPECT_NEAR(runout.measured, runout.true_dense, 2e-3);
}

// One tooth space widened: the R flank of tooth 5 and the L flank of tooth 6 lose d of material
// (transverse). The ball in that space sinks along its radial line e_r (the space's centre line
// in the section z, turned by the helix) until it touches both again: n_t · Δ = -d on each flank
// with Δ = -h e_r, h = d / (n_t · e_r). On the R flank the transverse normal at roll length L
// is (-sin phi_b, cos phi_b) with phi_b = tooth angle + theta_b - L / r_b + z turn, the space's
// centre line lies at tooth angle + pi / z + z turn, so n_t · e_r = sin(pi / z - theta_b +
// L / r_b) (the L flank by symmetry). Every other ball stays: F_r = h.
TEST(HelicalParameters, AWidenedToothSpaceLetsItsBallSinkAlongTheTurnedCentreLine) {
  const double rb = kBaseDiameterMm / 2;
  const double alpha_t = kTransversePressureAngleDeg * kDeg;
  const double theta_b =
      kTransverseThicknessMm / kReferenceDiameterMm + std::tan(alpha_t) - alpha_t;
  const double d_um = 4.0;
  const Scenario s = helical_scenario(
      "deviations: {random: false, normal_um: \"-4 * ((tooth == 5) * (side > 0) + (tooth == 6) * "
      "(side < 0))\"}\n"
      "evaluation: {parameters: [F_r], profile_points: 25}\n");
  const MonteCarloRun mc(s);
  const ParameterEvaluator& e = *mc.parameter_evaluator();
  const double L_c = 0.5 * (e.profile_start_mm() + e.profile_end_mm());  // the ball's contacts
  const double h = d_um / std::sin(kPi / kTeeth - theta_b + L_c / rb);
  const RunResults r = run_one_gear(mc);
  ASSERT_EQ(values(r, GearParameter::kFr, 0).size(), 1u);
  const ParameterValue& runout = values(r, GearParameter::kFr, 0)[0];
  EXPECT_NEAR(runout.true_dense, h, 1e-6);
  EXPECT_NEAR(runout.measured, h, 2e-3);
  EXPECT_GT(h, 2 * d_um);  // the flanks are inclined: the ball sinks by more than d
}

// A z scale error s moves a recorded centre by s c_z e_z: the reading along the helicoid's
// normal by s c_z n_z with n_z = -/+ sin(beta_b) (- on R flanks of a right-hand gear), constant
// on a flank, so the transverse helix trace gains the slope s n_z / cos(beta_b) = -/+ s tan(beta_b)
// per mm of face: f_Hbeta changes by -/+ s tan(beta_b) L_beta, the profile by nothing. On a spur
// gear (n_z = 0) a z scale error is invisible; on a helical one it is not.
TEST(HelicalParameters, AZScaleErrorTiltsTheHelixByTheBaseHelixAngle) {
  const double ppm = 100.0;
  for (const char* hand : {"right", "left"}) {
    const std::string evaluation =
        "evaluation: {parameters: [f_Halpha, f_Hbeta], profile_points: 25, helix_points: 25}\n";
    const MonteCarloRun mc(helical_scenario(evaluation + "effects: {scale: {z_ppm: 100}}\n", hand));
    const MonteCarloRun plain(helical_scenario(evaluation, hand));
    const RunResults r = run_one_gear(mc), r0 = run_one_gear(plain);
    const double L_beta =
        mc.parameter_evaluator()->helix_end_mm() - mc.parameter_evaluator()->helix_start_mm();
    const double hand_sign = std::string(hand) == "right" ? 1.0 : -1.0;
    for (int side = 0; side < 2; ++side) {
      const double side_sign = side == 1 ? 1.0 : -1.0;
      const double predicted =
          -side_sign * hand_sign * ppm * 1e-6 * std::tan(kBaseHelixAngleDeg * kDeg) * L_beta * 1e3;
      const auto& helix = values(r, GearParameter::kfHbeta, side);
      const auto& helix0 = values(r0, GearParameter::kfHbeta, side);
      const auto& profile = values(r, GearParameter::kfHalpha, side);
      const auto& profile0 = values(r0, GearParameter::kfHalpha, side);
      ASSERT_EQ(helix.size(), static_cast<size_t>(kTeeth));
      for (std::size_t k = 0; k < helix.size(); ++k) {
        // s times the deviation itself (≤ ~30 µm): 3e-3 µm; δRcomp's part cancels in the
        // difference to second order.
        EXPECT_NEAR(helix[k].measured - helix0[k].measured, predicted, 4e-3)
            << hand << " side " << side << " tooth " << k + 1;
        EXPECT_NEAR(profile[k].measured - profile0[k].measured, 0.0, 4e-3);
        EXPECT_EQ(helix[k].true_dense, helix0[k].true_dense);  // the same gear
      }
      EXPECT_GT(std::abs(predicted), 0.8);  // 100 ppm × tan 14.08° × 36 mm = 0.90 µm
    }
  }
}

// Deviations are stated against the design flank (ISO 1328-1: the design profile and helix carry
// the modifications). A nominal gear with tip relief, helix crowning and a helix slope
// modification has true parameters of zero and measures near zero (only the second-order
// reading error of its tilted relief, R(1/cos(theta) - 1): theta < 0.025 rad here, < 0.35 µm at
// R 1 mm); the same random gear drawn with and without the modifications has the same true
// parameters (its deviations from the design are the same draws).
TEST(HelicalParameters, DeviationsAreStatedAgainstTheModifiedDesign) {
  const std::string modifications =
      "  modifications: {tip_relief: {amount_um: 10, length_mm: 3}, helix_crowning_um: 5, "
      "helix_slope_um: 6}\n";
  const auto with = [&](bool modified, const std::string& deviations) {
    std::string gear =
        "gear: {teeth: 31, module_mm: 4, pressure_angle_deg: 20, helix_angle_deg: 15, "
        "hand: right, profile_shift: 0.2, face_width_mm: 40}\n";
    if (modified) {
      gear =
          "gear:\n  teeth: 31\n  module_mm: 4\n  pressure_angle_deg: 20\n"
          "  helix_angle_deg: 15\n  hand: right\n  profile_shift: 0.2\n"
          "  face_width_mm: 40\n" +
          modifications;
    }
    return parse_scenario(
        "name: m\nseed: 5\n" + gear +
            "tolerances: {standard: iso_1328_1_2013, grade: 6}\n"
            "probing: {points_along_profile: 10, sections_across_face: 5, teeth: [1, 9, 17]}\n"
            "stylus: {radius_mm: 1.0}\n" +
            deviations + "evaluation: {parameters: all, profile_points: 25, helix_points: 25}\n",
        "modified.yaml");
  };
  const RunResults nominal =
      run_one_gear(MonteCarloRun(with(true, "deviations: {random: false}\n")));
  int items = 0;
  for (const GearParameter p :
       {GearParameter::kFalpha, GearParameter::kfHalpha, GearParameter::kffalpha,
        GearParameter::kFbeta, GearParameter::kfHbeta, GearParameter::kffbeta}) {
    for (int side = 0; side < 2; ++side) {
      for (const ParameterValue& v : values(nominal, p, side)) {
        EXPECT_NEAR(v.true_dense, 0.0, 1e-9) << parameter_symbol(p);
        EXPECT_NEAR(v.measured, 0.0, 0.35) << parameter_symbol(p);
        ++items;
      }
    }
  }
  EXPECT_EQ(items, 6 * 2 * 3);
  const RunResults plain = run_one_gear(MonteCarloRun(with(false, "")));
  const RunResults modified = run_one_gear(MonteCarloRun(with(true, "")));
  for (const GearParameter p : all_gear_parameters()) {
    for (int side = 0; side < 2; ++side) {
      const auto& a = values(plain, p, side);
      const auto& b = values(modified, p, side);
      ASSERT_EQ(a.size(), b.size());
      for (std::size_t k = 0; k < a.size(); ++k) {
        // Not exactly equal: the gear's eccentricity e moves the real (modified) flank sideways,
        // so the nominal normal line at L meets it at L + (e·t) r_b / L, where the design has
        // changed by its slope times that step (a real effect of an eccentric modified gear,
        // second order in e and the design's slope); over these traces it stays below
        // 4.1e-3 µm (seed 5), against 5.4 µm of design helix slope that the evaluation removes.
        EXPECT_NEAR(a[k].true_dense, b[k].true_dense, 0.01) << parameter_symbol(p);
      }
    }
  }
}

}  // namespace
}  // namespace gearmc
