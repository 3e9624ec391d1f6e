// The size deviations E_sn, E_Wk, E_MdK of a run (engine/evaluation): on gears whose real
// flanks carry a known deviation (`deviations: {random: false, normal_um: …}`, one value per
// flank), each item's true value against the hand formula — thickness from the two flanks of a
// tooth, span from the outer flanks of k teeth, ball pair from the four flanks the two balls
// touch, with the ball's pressure angle α_Kt from an independent recomputation (tests/gears/
// size_dimensions_reference.py's brute force agrees with it; KHK's over-pin table: m 1, z 20,
// D_M 1.7 → α_Kt 24.1350°) — and the measured value equal to it up to δRcomp's second-order
// error; and the scenario checks of the gauges (span or ball touching outside L_α, E_Wk on an
// internal gear, one flank probed) with their messages.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <numbers>
#include <string>

#include "core/input_error.h"
#include "engine/evaluation/parameter_evaluation.h"
#include "engine/reports/parameter_report.h"
#include "engine/run/monte_carlo.h"
#include "engine/scenario/scenario.h"

namespace gearmc {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

// The known real deviation along the flank normal, µm: a per side, c per tooth number.
double normal_deviation_um(int tooth, int side_sign) {
  return 0.8 + 0.3 * side_sign + 0.01 * tooth;
}

std::string scenario_text(const std::string& gear, const std::string& evaluation) {
  return "name: sizes\nseed: 3\ngear: " + gear +
         "\ntolerances: {standard: iso_1328_1_2013, grade: 5}\n"
         "probing: {points_along_profile: 8, sections_across_face: 3, margin_fraction: 0.05}\n"
         "deviations: {random: false, normal_um: \"0.8 + 0.3*side + 0.01*tooth\"}\n"
         "evaluation: " +
         evaluation + "\n";
}

RunResults run_one(const MonteCarloRun& mc) {
  RunOptions o;
  o.end_gear = 1;
  o.threads = 1;
  return mc.run(o);
}

const std::vector<ParameterValue>& items(const RunResults& r, GearParameter p) {
  return r.parameters->values[static_cast<int>(p)][0];
}

// Measured − true here is δRcomp's second-order error of flanks tilted by the known deviation's
// tooth-to-tooth steps only (none along a flank): far below 1e-3 µm.
constexpr double kMeasuredTolUm = 1e-3;

TEST(SizeParameters, SpurGearSizesFromKnownFlankDeviations) {
  for (const int z : {20, 21}) {
    SCOPED_TRACE("z " + std::to_string(z));
    const Scenario s = parse_scenario(
        scenario_text("{teeth: " + std::to_string(z) +
                          ", module_mm: 1, pressure_angle_deg: 20, face_width_mm: 10}",
                      "{parameters: [E_sn, E_Wk, E_MdK], profile_points: 30, span_teeth: 3, "
                      "ball_diameter_mm: 1.7}"),
        "sizes.yaml");
    const MonteCarloRun mc(s);
    const RunResults r = run_one(mc);
    ASSERT_TRUE(r.parameters);
    const double alpha = 20 * kDeg;
    const auto dL = [](int t) { return normal_deviation_um(t, -1); };
    const auto dR = [](int t) { return normal_deviation_um(t, +1); };
    const auto tooth = [&](int t) { return (t - 1 + z) % z + 1; };
    // E_sn = (d_L + d_R) / cos α on a spur gear.
    const auto& esn = items(r, GearParameter::kEsn);
    ASSERT_EQ(esn.size(), static_cast<std::size_t>(z));
    for (int t = 1; t <= z; ++t) {
      const double hand = (dL(t) + dR(t)) / std::cos(alpha);
      EXPECT_NEAR(esn[t - 1].true_dense, hand, 1e-9) << "tooth " << t;
      EXPECT_NEAR(esn[t - 1].measured, hand, kMeasuredTolUm) << "tooth " << t;
    }
    // E_Wk of the span over teeth t … t+2: L of t, R of t+2 (R faces counter-clockwise).
    const auto& ewk = items(r, GearParameter::kEWk);
    ASSERT_EQ(ewk.size(), static_cast<std::size_t>(z));
    for (int t = 1; t <= z; ++t) {
      const double hand = dL(t) + dR(tooth(t + 2));
      EXPECT_NEAR(ewk[t - 1].true_dense, hand, 1e-9) << "span from tooth " << t;
      EXPECT_NEAR(ewk[t - 1].measured, hand, kMeasuredTolUm);
    }
    // E_MdK: the ball in the space after tooth t (centre line at angle (t − ½) 2π/z) touches
    // R of t (normal: sin α_Kt outward, cos α_Kt counter-clockwise) and L of t+1 (sin α_Kt,
    // −cos α_Kt), so it rises by (d_R + d_L) / (2 sin α_Kt) and turns counter-clockwise by
    // (d_R − d_L) / (2 cos α_Kt); its partner sits z/2 spaces on (even z) or (z−1)/2 (odd z);
    // E_MdK is the change of the distance between the centres. α_Kt from the brute-force
    // recomputation (tests/gears/size_dimensions_reference.py).
    const double alpha_K = (z == 20 ? 24.134994 : 23.971816) * kDeg;
    const int across = z / 2;
    const auto shift = [&](int t) {
      const double angle = (t - 0.5) * 2 * std::numbers::pi / z;
      const double up = (dR(tooth(t)) + dL(tooth(t + 1))) / (2 * std::sin(alpha_K));
      const double turn = (dR(tooth(t)) - dL(tooth(t + 1))) / (2 * std::cos(alpha_K));
      return std::array<double, 4>{up * std::cos(angle) - turn * std::sin(angle),
                                   up * std::sin(angle) + turn * std::cos(angle), std::cos(angle),
                                   std::sin(angle)};
    };
    const auto change = [&](int ta, int tb) {
      const auto a = shift(ta), b = shift(tb);
      const double ux = a[2] - b[2], uy = a[3] - b[3], n = std::hypot(ux, uy);
      return (ux * (a[0] - b[0]) + uy * (a[1] - b[1])) / n;
    };
    const auto& emdk = items(r, GearParameter::kEMdK);
    ASSERT_EQ(emdk.size(), static_cast<std::size_t>(z % 2 ? z : z / 2));
    for (std::size_t k = 0; k < emdk.size(); ++k) {
      const int t = static_cast<int>(k) + 1;
      const double hand = change(t, t + across);
      // α_Kt to 1e-6° moves the value by ~1e-8 relative.
      EXPECT_NEAR(emdk[k].true_dense, hand, 1e-6) << "ball pair " << k;
      EXPECT_NEAR(emdk[k].measured, hand, kMeasuredTolUm);
    }
    EXPECT_EQ(*mc.parameter_evaluator()->span_teeth(), 3);
    EXPECT_DOUBLE_EQ(*mc.parameter_evaluator()->ball_diameter_mm(), 1.7);
  }
}

TEST(SizeParameters, HelicalGearSizesUseTransverseDeviationsAndTheBaseHelix) {
  // normal_um is a transverse deviation (docs/scenarios.md), as the traces are. E_sn is a
  // normal thickness (× cos β / cos α_t); E_Wk lies in the base plane, where a transverse
  // deviation is d cos β_b.
  const double beta = 15 * kDeg, an = 20 * kDeg;
  const Scenario s = parse_scenario(
      scenario_text(
          "{teeth: 20, module_mm: 1, pressure_angle_deg: 20, helix_angle_deg: 15, "
          "hand: right, profile_shift: 0.2, face_width_mm: 10}",
          "{parameters: [E_sn, E_Wk, E_MdK], profile_points: 30, ball_diameter_mm: 1.75}"),
      "sizes.yaml");
  const MonteCarloRun mc(s);
  const RunResults r = run_one(mc);
  const double at = std::atan(std::tan(an) / std::cos(beta));
  const double bb = std::asin(std::sin(beta) * std::cos(an));
  const auto dLn = [](int t) { return normal_deviation_um(t, -1); };
  const auto dRn = [](int t) { return normal_deviation_um(t, +1); };
  const auto& esn = items(r, GearParameter::kEsn);
  ASSERT_EQ(esn.size(), 20u);
  for (int t = 1; t <= 20; ++t) {
    const double hand = (dLn(t) + dRn(t)) / std::cos(at) * std::cos(beta);
    EXPECT_NEAR(esn[t - 1].true_dense, hand, 1e-9);
    EXPECT_NEAR(esn[t - 1].measured, hand, kMeasuredTolUm);
  }
  const int k = *mc.parameter_evaluator()->span_teeth();
  const auto& ewk = items(r, GearParameter::kEWk);
  ASSERT_EQ(ewk.size(), 20u);
  for (int t = 1; t <= 20; ++t) {
    const double hand = (dLn(t) + dRn((t + k - 2) % 20 + 1)) * std::cos(bb);
    EXPECT_NEAR(ewk[t - 1].true_dense, hand, 1e-9);
    EXPECT_NEAR(ewk[t - 1].measured, hand, kMeasuredTolUm);
  }
  // α_Kt of m_n 1, β 15°, z 20, x 0.2, D_M 1.75: 27.004850° (brute-force recomputation).
  const double aK = 27.004850 * kDeg;
  const auto rise = [&](int t) {
    return (dRn((t - 1) % 20 + 1) + dLn(t % 20 + 1)) / (2 * std::sin(aK));
  };
  const auto& emdk = items(r, GearParameter::kEMdK);
  ASSERT_EQ(emdk.size(), 10u);
  for (int t = 1; t <= 10; ++t) {
    EXPECT_NEAR(emdk[t - 1].true_dense, rise(t) + rise(t + 10), 1e-6);
    EXPECT_NEAR(emdk[t - 1].measured, rise(t) + rise(t + 10), kMeasuredTolUm);
  }
}

std::string error_of(const std::string& text) {
  try {
    parse_scenario(text, "sizes.yaml");
  } catch (const InputError& e) {
    return e.what();
  }
  return "no error";
}

TEST(SizeParameters, GaugesOutsideTheEvaluationRangeAndImpossibleSizesAreRefused) {
  const std::string spur = "{teeth: 20, module_mm: 1, pressure_angle_deg: 20, face_width_mm: 10}";
  // Span of 8 teeth on z 20: the jaws touch at W_8/2 = 11.2 mm, beyond L_α (0.50 … 5.46 mm);
  // by hand W_k/2 = cos 20° [(k − ½) π + 20 inv 20°] / 2 = 0.88, 2.35, 3.83, 5.31, 6.78 mm for
  // k = 1 … 5: k 1–4 touch within it.
  const std::string far = error_of(scenario_text(spur, "{parameters: [E_Wk], span_teeth: 8}"));
  EXPECT_NE(far.find("sizes.yaml:"), std::string::npos) << far;
  EXPECT_NE(far.find("evaluation.span_teeth"), std::string::npos) << far;
  EXPECT_NE(far.find("jaws touch within L_α"), std::string::npos) << far;
  EXPECT_NE(far.find("(k = 1, 2, 3, 4)"), std::string::npos) << far;
  // A 4 mm ball rides over the tip of a module-1 gear.
  const std::string ball =
      error_of(scenario_text(spur, "{parameters: [E_MdK], ball_diameter_mm: 4}"));
  EXPECT_NE(ball.find("evaluation.ball_diameter_mm"), std::string::npos) << ball;
  EXPECT_NE(ball.find("a ball touching within L_α"), std::string::npos) << ball;
  EXPECT_NE(ball.find("D_M = "), std::string::npos) << ball;
  // No calliper spans an internal gear's teeth.
  const std::string ring = error_of(scenario_text(
      "{teeth: 40, module_mm: 1, pressure_angle_deg: 20, face_width_mm: 10, internal: true}",
      "{parameters: [E_sn, E_Wk]}"));
  EXPECT_NE(ring.find("without E_Wk on an internal gear"), std::string::npos) << ring;
  // A size needs both flanks.
  std::string one_side = scenario_text(spur, "{parameters: [E_sn]}");
  one_side.replace(one_side.find("margin_fraction: 0.05}"), 22,
                   "margin_fraction: 0.05, flanks: L}");
  const std::string side = error_of(one_side);
  EXPECT_NE(side.find("both flanks probed"), std::string::npos) << side;
  // `all` stays the nine ISO 1328-1 parameters.
  const Scenario s = parse_scenario(scenario_text(spur, "{parameters: all}"), "sizes.yaml");
  EXPECT_EQ(s.evaluation->parameters.size(), 9u);
}

// The drawing's allowances of a size (evaluation.size_allowances_um): the limits [lower, upper],
// U/T over their width, the worst value the one farthest from the zone's centre, and the items
// whose true value lies outside them. Hand values: E_sn of tooth t is (d_L + d_R)/cos α =
// (1.6 + 0.02 t)/cos 20° (normal_deviation_um), 1.724 … 2.128 µm over t = 1 … 20; inside
// [1.8, 2.2] from t = 5 on ((1.6 + 0.02 t)/cos 20° ≥ 1.8 ⇔ t ≥ 4.57), so teeth 1–4 do not conform.
TEST(SizeParameters, AllowancesGiveTheSizesConformityDecisions) {
  const Scenario s = parse_scenario(
      scenario_text("{teeth: 20, module_mm: 1, pressure_angle_deg: 20, face_width_mm: 10}",
                    "{parameters: [E_sn, E_Wk], profile_points: 30, "
                    "size_allowances_um: {E_sn: {upper: 2.2, lower: 1.8}}}"),
      "sizes.yaml");
  const MonteCarloRun mc(s);
  const RunResults r = run_one(mc);
  const std::optional<ParameterPresentation> p = present_parameters(mc, r);
  ASSERT_TRUE(p);
  const ParameterSummary* esn = nullptr;
  const ParameterSummary* ewk = nullptr;
  for (const ParameterSummary& x : p->parameters) {
    if (x.parameter == GearParameter::kEsn) esn = &x;
    if (x.parameter == GearParameter::kEWk) ewk = &x;
  }
  ASSERT_TRUE(esn && ewk);
  const ParameterConformity& c = esn->conformity;
  ASSERT_TRUE(c.tolerance_um);
  EXPECT_TRUE(c.allowances);
  EXPECT_DOUBLE_EQ(*c.tolerance.lower, 1.8);
  EXPECT_DOUBLE_EQ(*c.tolerance.upper, 2.2);
  EXPECT_NEAR(*c.tolerance_um, 0.4, 1e-12);
  EXPECT_EQ(c.tolerance_text(), "[1.8, 2.2]");
  EXPECT_NEAR(c.u_over_t, esn->sides.front().U95_um / 0.4, 1e-12);
  EXPECT_EQ(c.simple.items, 20u);
  EXPECT_EQ(c.simple.nonconforming, 4u);
  EXPECT_EQ(c.simple.accepted, 16u);
  // Farthest from the centre 2.0: tooth 1 (1.724) rather than tooth 20 (2.128).
  EXPECT_NEAR(c.worst_measured_um, 1.62 / std::cos(20 * kDeg), kMeasuredTolUm);
  // A size without allowances has no decision.
  EXPECT_FALSE(ewk->conformity.tolerance_um);
  // Both ends are needed, the lower below the upper.
  const std::string spur = "{teeth: 20, module_mm: 1, pressure_angle_deg: 20, face_width_mm: 10}";
  const std::string one = error_of(
      scenario_text(spur, "{parameters: [E_sn], size_allowances_um: {E_sn: {upper: -20}}}"));
  EXPECT_NE(one.find("evaluation.size_allowances_um.E_sn"), std::string::npos) << one;
  EXPECT_NE(one.find("both allowances of E_sn"), std::string::npos) << one;
  const std::string order = error_of(scenario_text(
      spur, "{parameters: [E_sn], size_allowances_um: {E_sn: {upper: -60, lower: -20}}}"));
  EXPECT_NE(order.find("evaluation.size_allowances_um.E_sn.lower"), std::string::npos) << order;
  EXPECT_NE(order.find("below the upper allowance (-60 µm)"), std::string::npos) << order;
}

TEST(SizeParameters, InternalGearThicknessAndDimensionBetweenBalls) {
  // Between balls on a ring gear: material added on the flanks narrows the spaces and pushes the
  // balls towards the axis — the dimension shrinks, so the sign flips against an external gear.
  // α_Kt of m 1, z 40, x 0, D_M 1.7 (internal): 16.952062° (brute-force recomputation).
  const Scenario s = parse_scenario(
      scenario_text(
          "{teeth: 40, module_mm: 1, pressure_angle_deg: 20, face_width_mm: 10, internal: true}",
          "{parameters: [E_sn, E_MdK], profile_points: 30, ball_diameter_mm: 1.7}"),
      "sizes.yaml");
  const MonteCarloRun mc(s);
  const RunResults r = run_one(mc);
  const double aK = 16.952062 * kDeg;
  const auto dL = [](int t) { return normal_deviation_um(t, -1); };
  const auto dR = [](int t) { return normal_deviation_um(t, +1); };
  const auto& esn = items(r, GearParameter::kEsn);
  ASSERT_EQ(esn.size(), 40u);
  for (int t = 1; t <= 40; ++t) {
    EXPECT_NEAR(esn[t - 1].true_dense, (dL(t) + dR(t)) / std::cos(20 * kDeg), 1e-9);
  }
  const auto rise = [&](int t) {
    return -(dR((t - 1) % 40 + 1) + dL(t % 40 + 1)) / (2 * std::sin(aK));
  };
  const auto& emdk = items(r, GearParameter::kEMdK);
  ASSERT_EQ(emdk.size(), 20u);
  for (int t = 1; t <= 20; ++t) {
    EXPECT_NEAR(emdk[t - 1].true_dense, rise(t) + rise(t + 20), 1e-6);
    EXPECT_NEAR(emdk[t - 1].measured, rise(t) + rise(t + 20), kMeasuredTolUm);
  }
}

}  // namespace
}  // namespace gearmc
