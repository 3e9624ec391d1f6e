// The gear parameters of a Monte-Carlo run (engine/evaluation/parameter_evaluation.h through
// engine/run): with every effect off the only error is δRcomp's, of the size a first-order
// estimate gives; an XY scale error gives the predicted profile slope error; the values are the
// same for any thread count; the `evaluation:` section is read and checked.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "core/input_error.h"
#include "engine/reports/parameter_report.h"
#include "engine/run/monte_carlo.h"
#include "engine/scenario/scenario.h"

namespace gearmc {
namespace {

const char* kGear =
    "gear: {teeth: 24, module_mm: 5.6, pressure_angle_deg: 20, profile_shift: 0.90116, "
    "face_width_mm: 78.89}\n"
    "tolerances: {standard: iso_1328_1_2013, grade: 5}\n"
    "probing: {points_along_profile: 10, sections_across_face: 5, margin_fraction: 0.05}\n";

Scenario scenario_with(const std::string& extra) {
  return parse_scenario(std::string("name: t\nseed: 7\n") + kGear + extra, "test.yaml");
}

const std::vector<ParameterValue>& values(const RunResults& r, GearParameter p, int side) {
  return r.parameters->values[static_cast<int>(p)][side];
}

TEST(ParameterRun, EffectsOffLeaveOnlyTheSecondOrderRadiusCompensationError) {
  // Without effects the reported deviation at a nominal point is the stylus centre's offset
  // along n minus R: for a sphere touching a surface inclined by θ to the nominal one it exceeds
  // the surface's deviation by R(1/cos θ − 1) ≈ Rθ²/2 — first order in the deviation, the error
  // is second order. θ is bounded by the real surface's slopes along the dense traces (the
  // chart gear's, below); a trace parameter's error is at most ~4 × the pointwise error
  // (form, total: 2×; a least-squares end value: < 4×), pitch and runout less (2/cos α and
  // about 2/sin α of it over two flanks, with a pointwise error that is smaller near the
  // reference circle), so 4 × Rθ²/2 bounds every parameter's error for the gears run here
  // (the chart gear's θ stands for both: the sampler draws both gears within the same tolerances).
  const Scenario s =
      scenario_with("evaluation: {parameters: all, profile_points: 25, helix_points: 25}\n");
  const MonteCarloRun mc(s);
  RunOptions o;
  o.end_gear = 2;
  o.threads = 1;
  const RunResults r = mc.run(o);
  ASSERT_TRUE(r.parameters);
  // The slope of the real surface along the chart gear's traces bounds θ, per unit of arc
  // length: along the profile ds = (L / r_b) dL (involute arc length s = L² / 2r_b), across the
  // face ds = dz.
  const double rb = mc.gear().base_diameter_mm() / 2;
  double theta_profile = 0.0, theta_helix = 0.0;
  for (const FlankTrace& t : r.parameters->chart.profile) {
    for (std::size_t i = 1; i < t.dense_um.size(); ++i) {
      const double L = 0.5 * (t.dense_x_mm[i] + t.dense_x_mm[i - 1]);
      theta_profile =
          std::max(theta_profile, std::abs(t.dense_um[i] - t.dense_um[i - 1]) /
                                      (t.dense_x_mm[i] - t.dense_x_mm[i - 1]) * (rb / L) * 1e-3);
    }
  }
  for (const FlankTrace& t : r.parameters->chart.helix) {
    for (std::size_t i = 1; i < t.dense_um.size(); ++i) {
      theta_helix = std::max(theta_helix, std::abs(t.dense_um[i] - t.dense_um[i - 1]) /
                                              (t.dense_x_mm[i] - t.dense_x_mm[i - 1]) * 1e-3);
    }
  }
  EXPECT_LT(theta_profile, 0.05);  // a class-5 flank tilts by milliradians, not more
  EXPECT_LT(theta_helix, 0.05);
  const double point_bound_um =
      1e3 * 0.5 * s.stylus_radius_mm * (theta_profile * theta_profile + theta_helix * theta_helix);
  double worst = 0.0;
  int items = 0;
  for (GearParameter p : all_gear_parameters()) {
    for (int side = 0; side < 2; ++side) {
      for (const ParameterValue& v : values(r, p, side)) {
        ASSERT_TRUE(std::isfinite(v.measured));
        worst = std::max(worst, std::abs(v.measured - v.true_points));
        ++items;
      }
    }
  }
  EXPECT_GT(items, 2 * (6 * 48 + 2 * 24 + 2 + 1) - 1);
  EXPECT_LT(worst, 4 * point_bound_um + 1e-4);  // + the contact solver's 0.1 nm
  EXPECT_GT(worst, 0.0);                        // δRcomp is there, not nothing
}

TEST(ParameterRun, XyScaleErrorGivesThePredictedProfileSlopeError) {
  // A scale error s in x and y moves a recorded centre c by s·c, the reading along n by
  // s (c·n) with c = p + R n; along an involute p·n changes linearly with the roll length, so
  // the measured profile slope deviation changes by s·1e3·[(p·n)(L_end) − (p·n)(L_start)] µm
  // (L in mm), computed from the nominal flank; the helix slope (n ⟂ z) does not change.
  const double ppm = 20.0;
  const Scenario s = scenario_with(
      "evaluation: {parameters: [f_Halpha, f_Hbeta], profile_points: 25, helix_points: 25}\n"
      "effects: {scale: {x_ppm: 20, y_ppm: 20}}\n");
  const MonteCarloRun mc(s);
  // The same gear without the effect: its measured − true is δRcomp's part, subtracted below.
  const MonteCarloRun plain(scenario_with(
      "evaluation: {parameters: [f_Halpha, f_Hbeta], profile_points: 25, helix_points: 25}\n"));
  RunOptions o;
  o.end_gear = 1;
  const RunResults r = mc.run(o), r0 = plain.run(o);
  const ParameterEvaluator& e = *mc.parameter_evaluator();
  const InvoluteGear& gear = mc.gear();
  for (int side = 0; side < 2; ++side) {
    const FlankSide fs = side ? FlankSide::kRight : FlankSide::kLeft;
    const auto& slopes = values(r, GearParameter::kfHalpha, side);
    const auto& slopes0 = values(r0, GearParameter::kfHalpha, side);
    ASSERT_EQ(slopes.size(), 24u);
    ASSERT_EQ(slopes0.size(), 24u);
    for (std::size_t k = 0; k < slopes.size(); ++k) {
      const int tooth = static_cast<int>(k) + 1;
      const double z = 0.5 * (e.helix_start_mm() + e.helix_end_mm());
      const FlankPoint a = gear.flank_point(tooth, fs, e.profile_start_mm(), z);
      const FlankPoint b = gear.flank_point(tooth, fs, e.profile_end_mm(), z);
      const double predicted = ppm * 1e-6 * 1e3 * (b.point.dot(b.normal) - a.point.dot(a.normal));
      // Tolerance: the reading moves by s (c·n) with c·n = p·n + R + d, so the deviation d itself
      // adds s × (its change over the range, ≤ ~20 µm) = 2e-5 × 20 = 4e-4 µm; δRcomp's part
      // changes by second order in s.
      EXPECT_NEAR(slopes[k].measured - slopes0[k].measured, predicted, 5e-4)
          << "tooth " << tooth << " side " << side;
      EXPECT_EQ(slopes[k].true_points, slopes0[k].true_points);  // the same gear
      EXPECT_GT(std::abs(predicted), 0.3);  // the effect is visible: 20 ppm × ~25 mm of range
    }
    const auto& helix = values(r, GearParameter::kfHbeta, side);
    const auto& helix0 = values(r0, GearParameter::kfHbeta, side);
    ASSERT_EQ(helix.size(), helix0.size());
    for (std::size_t k = 0; k < helix.size(); ++k) {
      EXPECT_NEAR(helix[k].measured - helix0[k].measured, 0.0, 5e-4);  // s × d, as above
    }
  }
}

TEST(ParameterRun, SameValuesForOneAndTwoThreads) {
  const Scenario s = scenario_with(
      "evaluation: {parameters: all, profile_points: 12}\n"
      "effects: {noise: {sigma_um: 0.3}, drift: {x_um: {uniform: [-0.5, 0.5]}}}\n");
  const MonteCarloRun mc(s);
  RunOptions one, two;
  one.end_gear = two.end_gear = 4;
  one.threads = 1;
  two.threads = 2;
  const RunResults a = mc.run(one), b = mc.run(two);
  for (GearParameter p : all_gear_parameters()) {
    for (int side = 0; side < 2; ++side) {
      const auto& x = values(a, p, side);
      const auto& y = values(b, p, side);
      ASSERT_EQ(x.size(), y.size());
      for (std::size_t i = 0; i < x.size(); ++i) {
        EXPECT_EQ(x[i].measured, y[i].measured);
        EXPECT_EQ(x[i].true_dense, y[i].true_dense);
        EXPECT_EQ(x[i].budget, y[i].budget);
      }
    }
  }
}

// The conformance probability of the run's worst measured item takes the error law of the flank
// side that item is on, as docs/parameters.md says (it once pooled both sides: F_α 0.0266 printed
// where the right flank's values give 0.0301): the fraction of that side's errors e with
// T_L ≤ y − e ≤ T_U. The guard bands are each limit's reach of the sides' probabilistically
// symmetric 95 % intervals. An x scale error of 60 ppm makes the two sides' slope errors differ;
// the references are computed here from the per-item values by hand: the worst |y| (or largest
// y), a count over that side's errors, and the order statistics y_(r), y_(r+q) of JCGM 101
// §7.7.1 (q = floor(0.95 M + 1/2), r = floor((M − q + 1)/2)).
TEST(ParameterRun, ConformanceOfTheWorstItemAndTheGuardBandsUseEachSidesErrorLaw) {
  const Scenario s = scenario_with(
      "evaluation: {parameters: all, profile_points: 12}\n"
      "effects: {noise: {sigma_um: 0.3}, scale: {x_ppm: 60}}\n");
  const MonteCarloRun mc(s);
  RunOptions o;
  o.end_gear = 6;
  const RunResults r = mc.run(o);
  const std::optional<ParameterPresentation> view = present_parameters(mc, r);
  ASSERT_TRUE(view.has_value());
  int checked = 0, sides_differ = 0;
  for (const ParameterSummary& summary : view->parameters) {
    const ParameterConformity& c = summary.conformity;
    if (!c.tolerance_um || summary.sides.size() < 2) continue;
    double worst = 0.0;
    int worst_side = -1;
    double mean[2] = {0, 0}, sd[2] = {0, 0};
    std::vector<double> side_errors[2];
    double band_upper = 0.0, band_lower = 0.0;
    for (int side = 0; side < 2; ++side) {
      std::vector<double>& errors = side_errors[side];
      for (const ParameterValue& v : values(r, summary.parameter, side)) {
        if (!std::isfinite(v.measured) || !std::isfinite(v.true_dense) ||
            !std::isfinite(v.true_points)) {
          continue;
        }
        errors.push_back(v.measured - v.true_dense);
        if (worst_side < 0 ||
            (c.two_sided ? std::abs(v.measured) > std::abs(worst) : v.measured > worst)) {
          worst = v.measured;
          worst_side = side;
        }
      }
      const double n = static_cast<double>(errors.size());
      for (double e : errors) mean[side] += e / n;
      for (double e : errors) sd[side] += (e - mean[side]) * (e - mean[side]);
      sd[side] = std::sqrt(sd[side] / (n - 1.0));
      std::vector<double> sorted = errors;
      std::sort(sorted.begin(), sorted.end());
      const std::size_t m = sorted.size();
      const std::size_t q =
          static_cast<std::size_t>(std::floor(0.95 * static_cast<double>(m) + 0.5));
      if (q >= m) {  // too few for an interval (F_p, F_r: a value per gear): U = 2 √(u² + b²)
        band_upper = std::max(band_upper, 2.0 * std::hypot(sd[side], mean[side]));
        band_lower = std::max(band_lower, 2.0 * std::hypot(sd[side], mean[side]));
        continue;
      }
      const std::size_t low = std::max<std::size_t>(1, (m - q + 1) / 2);
      band_upper = std::max(band_upper, std::max(0.0, -sorted[low - 1]));
      band_lower = std::max(band_lower, std::max(0.0, sorted[low + q - 1]));
    }
    ASSERT_GE(worst_side, 0);
    const double T = *c.tolerance_um;
    double inside = 0.0;
    for (double e : side_errors[worst_side]) {
      const double true_value = worst - e;
      inside += true_value <= T && (!c.two_sided || true_value >= -T) ? 1.0 : 0.0;
    }
    const double expected = inside / static_cast<double>(side_errors[worst_side].size());
    EXPECT_NEAR(c.guard_band_upper_um, band_upper, 1e-12) << parameter_symbol(summary.parameter);
    if (c.two_sided) {
      EXPECT_NEAR(c.guard_band_lower_um, band_lower, 1e-12) << parameter_symbol(summary.parameter);
    }
    EXPECT_EQ(c.worst_measured_um, worst) << parameter_symbol(summary.parameter);
    EXPECT_EQ(c.worst_side, worst_side == 0 ? "left" : "right");
    EXPECT_NEAR(c.conformance_probability_of_worst, expected, 1e-12)
        << parameter_symbol(summary.parameter);
    // U/T and the capability ratio Q_MP = 2U/(T_U − T_L) (ISO 22514-7): U = 2 √(u² + b²) of the
    // side with the larger one, over 2T for ±T and T (natural lower limit 0) for ≤ T.
    const double U = std::max(2.0 * std::hypot(sd[0], mean[0]), 2.0 * std::hypot(sd[1], mean[1]));
    const double width = c.two_sided ? 2.0 * T : T;
    EXPECT_NEAR(c.u_over_t, U / width, 1e-9) << parameter_symbol(summary.parameter);
    EXPECT_NEAR(c.capability_ratio, 2.0 * U / width, 1e-9) << parameter_symbol(summary.parameter);
    EXPECT_EQ(c.capable(), 2.0 * U / width <= 0.30) << parameter_symbol(summary.parameter);
    ++checked;
    sides_differ += std::abs(mean[0] - mean[1]) > 0.1 * (sd[0] + sd[1]);
  }
  EXPECT_GE(checked, 6);
  EXPECT_GE(sides_differ, 1);  // the case where pooling was wrong is present
  // The report's verdict counts the toleranced parameters and names each one that is not capable.
  const ParameterVerdict verdict = parameter_verdict(*view);
  int assessed = 0, capable = 0;
  for (const ParameterSummary& summary : view->parameters) {
    if (!summary.conformity.tolerance_um) continue;
    ++assessed;
    capable += summary.conformity.capability_ratio <= 0.30;
    if (summary.conformity.capability_ratio > 0.30) {
      EXPECT_NE(verdict.headline.find(parameter_symbol(summary.parameter) + " ("),
                std::string::npos)
          << verdict.headline;
    }
  }
  EXPECT_EQ(verdict.assessed, assessed);
  EXPECT_EQ(verdict.capable, capable);
  EXPECT_EQ(verdict.lines.size(), static_cast<std::size_t>(assessed));
  EXPECT_EQ(verdict.headline.rfind(capable == assessed ? "Capable" : "NOT capable", 0), 0u);
}

// The helix evaluation range L_β leaves out min(5 % b, m_n) at each end (ISO 1328-1:2013 §3.3;
// docs/parameters.md): for P1's gear 0.05 · 78.89 = 3.9445 mm < m 5.6 mm, so [3.9445, 74.9455].
// A 20 µm step confined to z < 2 mm (a nominal gear with deviations.normal_um) lies outside it:
// F_β of that gear, true and measured, is below 1 µm; taken over the whole face it would be
// about 20 µm.
TEST(ParameterRun, TheHelixRangeLeavesOutTheEnds) {
  const Scenario s = scenario_with(
      "deviations: {random: false, normal_um: \"z < 2 ? 20 : 0\"}\n"
      "evaluation: {parameters: [F_beta], helix_points: 200}\n");
  const MonteCarloRun mc(s);
  ASSERT_NE(mc.parameter_evaluator(), nullptr);
  EXPECT_NEAR(mc.parameter_evaluator()->helix_start_mm(), 3.9445, 1e-12);
  EXPECT_NEAR(mc.parameter_evaluator()->helix_end_mm(), 78.89 - 3.9445, 1e-12);
  RunOptions o;
  o.end_gear = 1;
  const RunResults r = mc.run(o);
  int checked = 0;
  for (int side = 0; side < 2; ++side) {
    for (const ParameterValue& v : values(r, GearParameter::kFbeta, side)) {
      EXPECT_LT(std::abs(v.true_dense), 1.0);
      EXPECT_LT(std::abs(v.measured), 1.0);
      ++checked;
    }
  }
  EXPECT_GT(checked, 0);
}

TEST(ParameterRun, EvaluationSectionIsReadAndChecked) {
  const Scenario s = scenario_with(
      "evaluation: {parameters: [F_p, F_alpha], decision_rule: guard_banded, "
      "helix_end_exclusion_mm: 2}\n");
  ASSERT_TRUE(s.evaluation);
  EXPECT_EQ(s.evaluation->parameters, (std::vector<std::string>{"F_alpha", "F_p"}));
  EXPECT_EQ(s.evaluation->decision_rule, "guard_banded");
  EXPECT_FALSE(scenario_with("").evaluation);
  const auto message = [](const std::string& extra) {
    try {
      scenario_with(extra);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(message("evaluation: {parameters: [F_alfa]}\n").find("F_alpha"), std::string::npos);
  EXPECT_NE(message("evaluation: {parameters: [F_p, F_p]}\n").find("twice"), std::string::npos);
  EXPECT_NE(message("evaluation: {parameters: all, helix_end_exclusion_mm: 50}\n")
                .find("half the face width"),
            std::string::npos);
  EXPECT_NE(message("evaluation: {parameters: all, profile_points: 2}\n").find("at least 3"),
            std::string::npos);
  // Pitch listed with a tooth subset: an error at the section; with `all` a note instead.
  const std::string subset =
      "name: t\ngear: {teeth: 24, module_mm: 5.6, face_width_mm: 78.89}\n"
      "tolerances: {standard: iso_1328_1_2013, grade: 5}\n"
      "probing: {teeth: [1, 2]}\n";
  const auto subset_message = [&](const std::string& list) {
    try {
      parse_scenario(subset + "evaluation: {parameters: " + list + "}\n", "subset.yaml");
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(subset_message("[F_alpha, f_pt]").find("every tooth"), std::string::npos);
  EXPECT_EQ(subset_message("all"), "no error");
  const MonteCarloRun mc(parse_scenario(subset + "evaluation: {parameters: all}\n", "s.yaml"));
  EXPECT_FALSE(mc.parameter_evaluator()->evaluates(GearParameter::kFp));
  EXPECT_TRUE(mc.parameter_evaluator()->evaluates(GearParameter::kFalpha));
  EXPECT_EQ(mc.parameter_evaluator()->notes().size(), 3u);  // f_pt, F_p, F_r
}

}  // namespace
}  // namespace gearmc
