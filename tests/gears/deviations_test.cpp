// Deviation model: the B-spline form fields, the ISO trace evaluation on traces with known
// answers, the runout measurement on pure eccentricity and pure flank offsets, and the
// sampler's reproducibility (gear k depends only on (seed, k)).
#include "gears/deviations.h"
#include "tests/support/helical_fixtures.h"
#include "tests/support/p1_fixtures.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

namespace gearmc {
namespace {

using testing_support::p1_gear;
using testing_support::p1_gear_parameters;

TEST(CubicBSpline, ReproducesLinesThroughGrevilleAbscissae) {
  const CubicBSpline knots(2.0, 7.0, std::vector<double>(9, 0.0));
  std::vector<double> c(9);
  for (int i = 0; i < 9; ++i) c[i] = 1.5 - 0.7 * knots.greville(i);
  const CubicBSpline s(2.0, 7.0, c);
  for (double t = 2.0; t <= 7.0; t += 0.123) {
    EXPECT_NEAR(s.value(t), 1.5 - 0.7 * t, 1e-12);
    EXPECT_NEAR(s.derivative(t), -0.7, 1e-12);
    EXPECT_NEAR(s.second_derivative(t), 0.0, 1e-10);
  }
  // Linear continuation outside the range.
  EXPECT_NEAR(s.value(9.0), 1.5 - 0.7 * 9.0, 1e-12);
  EXPECT_NEAR(s.value(0.0), 1.5, 1e-12);
}

TEST(CubicBSpline, DerivativesMatchFiniteDifferencesAndEndsInterpolate) {
  const std::vector<double> c = {0.3, -1.2, 2.0, 0.5, -0.4, 1.1, 0.0, -2.2};
  const CubicBSpline s(-1.0, 4.0, c);
  EXPECT_NEAR(s.value(-1.0), c.front(), 1e-14);  // clamped: interpolates the end values
  EXPECT_NEAR(s.value(4.0), c.back(), 1e-12);
  const double h = 1e-5;
  for (double t = -0.95; t < 3.96; t += 0.173) {
    EXPECT_NEAR(s.derivative(t), (s.value(t + h) - s.value(t - h)) / (2 * h), 1e-7);
    EXPECT_NEAR(s.second_derivative(t), (s.derivative(t + h) - s.derivative(t - h)) / (2 * h),
                1e-6);
  }
  // Partition of unity: all coefficients 1 -> the constant 1.
  const CubicBSpline one(0.0, 1.0, std::vector<double>(6, 1.0));
  for (double t = 0.0; t <= 1.0; t += 0.01) EXPECT_NEAR(one.value(t), 1.0, 1e-14);
}

TEST(EvaluateTrace, LineGivesSlopeOnlyAndSineGivesForm) {
  std::vector<double> x, line, wave;
  for (int i = 0; i <= 1000; ++i) {
    x.push_back(10.0 + 20.0 * i / 1000.0);
    line.push_back(3.0 + 0.25 * (x.back() - 10.0));  // rises 5 µm over the range
    // Even about the range middle: 3 periods of 2 cos, +2 at the middle, -2 at both ends.
    wave.push_back(2.0 * std::cos(2 * std::numbers::pi * 3.0 * (x.back() - 20.0) / 20.0));
  }
  const TraceEvaluation l = evaluate_trace(x, line);
  EXPECT_NEAR(l.slope_um, 5.0, 1e-12);
  EXPECT_NEAR(l.form_um, 0.0, 1e-12);
  EXPECT_NEAR(l.total_um, 5.0, 1e-12);
  // An even trace on symmetric samples has a flat LS line (slope 0 exactly), so form = total =
  // peak to peak = 4 µm; adding the line above changes the slope only.
  const TraceEvaluation w = evaluate_trace(x, wave);
  EXPECT_NEAR(w.slope_um, 0.0, 1e-12);
  EXPECT_NEAR(w.form_um, 4.0, 1e-12);
  EXPECT_NEAR(w.total_um, 4.0, 1e-12);
  std::vector<double> both(x.size());
  for (size_t i = 0; i < x.size(); ++i) both[i] = wave[i] + line[i];
  const TraceEvaluation wl = evaluate_trace(x, both);
  EXPECT_NEAR(wl.slope_um, 5.0, 1e-12);
  EXPECT_NEAR(wl.form_um, 4.0, 1e-12);
}

// The runout's independent facts on `gear`: no deviation or a uniform offset (thinner teeth,
// every ball moves by the same amount): 0. Pure eccentricity e: every ball centre moves by the
// eccentricity vector, so the runout is max - min of |C_k + e| with C_k the nominal centres on
// the space bisectors: between 2 e cos(pi / z) and 2 e. Opening one space by 1 µm on each
// flank lowers that ball by 1 µm / sin(alpha_contact): between 1 / sin(alpha) at the profile
// range's ends.
void expect_runout_facts(const InvoluteGear& gear) {
  const int z = gear.teeth();
  PerturbedGear g;
  g.flanks.resize(2 * z);
  EXPECT_NEAR(radial_runout_um(gear, g), 0.0, 1e-6);
  for (auto& f : g.flanks) f.offset_um = -20.0;
  EXPECT_NEAR(radial_runout_um(gear, g), 0.0, 1e-6);
  for (auto& f : g.flanks) f.offset_um = 0.0;
  g.eccentricity_mm = {0.015, 0.008};
  const double runout = radial_runout_um(gear, g);
  const double e_um = 1e3 * g.eccentricity_mm.norm();
  EXPECT_LE(runout, 2 * e_um + 1e-6);
  EXPECT_GE(runout, 2 * e_um * std::cos(std::numbers::pi / z) - 1e-6);
  g.eccentricity_mm = {0, 0};
  g.flank(3, FlankSide::kRight).offset_um = -1.0;
  g.flank(4, FlankSide::kLeft).offset_um = -1.0;
  const double one = radial_runout_um(gear, g);
  const EvaluationRanges r = evaluation_ranges(gear);
  const double r_b = gear.base_diameter_mm() / 2;
  EXPECT_GT(one, 1.0 / std::sin(std::atan(r.profile_end_mm / r_b)));
  EXPECT_LT(one, 1.0 / std::sin(std::atan(r.profile_start_mm / r_b)));
}

TEST(RadialRunout, PureEccentricityAndUniformOffsets) {
  expect_runout_facts(InvoluteGear(p1_gear_parameters()));
}

TEST(GearSampler, GearKDependsOnlyOnSeedAndK) {
  const InvoluteGear gear(p1_gear_parameters());
  const ToleranceSet tol = testing_support::p1_tolerance_set();
  const GearSampler a(gear, tol, DeviationModel{}, 7);
  const GearSampler b(gear, tol, DeviationModel{}, 7);
  const GearSampler other_seed(gear, tol, DeviationModel{}, 8);
  const PerturbedGear g5 = a.draw(5);
  (void)a.draw(3);  // drawing others first changes nothing
  const PerturbedGear g5_again = b.draw(5);
  EXPECT_EQ(g5.eccentricity_mm, g5_again.eccentricity_mm);
  EXPECT_EQ(g5.rack_shift_um, g5_again.rack_shift_um);
  for (int i = 0; i < 48; ++i) {
    EXPECT_EQ(g5.flanks[i].offset_um, g5_again.flanks[i].offset_um);
    EXPECT_EQ(g5.flanks[i].profile_form.coefficients(),
              g5_again.flanks[i].profile_form.coefficients());
  }
  EXPECT_NE(g5.rack_shift_um, other_seed.draw(5).rack_shift_um);
  EXPECT_NE(g5.rack_shift_um, a.draw(6).rack_shift_um);
  // Thickness: rack shift in [-(E_Hs + T_H), -E_Hs] = [-210, -110] µm.
  EXPECT_LE(g5.rack_shift_um, -110.0);
  EXPECT_GE(g5.rack_shift_um, -210.0);
  // random: false gives the nominal gear.
  DeviationModel off;
  off.random = false;
  const PerturbedGear nominal = GearSampler(gear, tol, off, 7).draw(5);
  EXPECT_EQ(nominal.eccentricity_mm.norm(), 0.0);
  for (const auto& f : nominal.flanks) EXPECT_EQ(f.normal_um(30.0, 20.0), 0.0);
}

TEST(GearSampler, ShapesThatAloneBreakTheRunoutAreDrawnAgain) {
  // P1's tolerances with F_r = 8 µm: the profile (8 µm) and helix (10 µm) shapes alone often
  // give more runout than that. Such a gear's shapes are drawn again from further streams, so
  // every drawn gear meets F_r (radial_runout_um, the sampler's own measure, includes the
  // eccentricity drawn within what is left of F_r), and a gear that fits at once is the plain
  // draw (same shapes as with F_r 50, which never needs a redraw on these gears).
  const InvoluteGear gear(p1_gear_parameters());
  ToleranceSet tight = testing_support::p1_tolerance_set();
  tight.values[ToleranceKind::kRunout] = {8, "test", true};
  const GearSampler sampler(gear, tight, DeviationModel{}, 3);
  const GearSampler loose(gear, testing_support::p1_tolerance_set(), DeviationModel{}, 3);
  int redrawn = 0, plain = 0;
  for (int k = 0; k < 40; ++k) {
    const PerturbedGear g = sampler.draw(k);
    EXPECT_LE(radial_runout_um(gear, g), 8.0) << "gear " << k;
    const PerturbedGear l = loose.draw(k);
    ASSERT_EQ(l.runout_redraws, 0);
    if (g.runout_redraws > 0) {
      ++redrawn;
      EXPECT_NE(g.flanks[0].profile_form.coefficients(), l.flanks[0].profile_form.coefficients());
    } else {
      ++plain;
      for (int i = 0; i < 48; ++i) {
        EXPECT_EQ(g.flanks[i].profile_form.coefficients(), l.flanks[i].profile_form.coefficients());
      }
    }
  }
  EXPECT_GT(redrawn, 0);  // the case is exercised
  EXPECT_GT(plain, 0);
}

// Radial runout of a helical gear (the example, both hands), measured in the transverse
// section at mid face (turned by z tan(beta) / r): the same independent facts as for a spur gear
// (no deviation or a uniform offset: 0; pure eccentricity e: between 2 e cos(pi / z) and 2 e;
// one space opened by 1 µm on each flank: between 1 / sin(alpha) at the profile range's ends,
// alpha the transverse pressure angle at the contact), and the sampler keeps every drawn gear
// within a tight F_r.
TEST(RadialRunout, HelicalGearInItsTransverseSection) {
  for (Hand hand : {Hand::kRight, Hand::kLeft}) {
    const InvoluteGear gear = testing_support::helical_gear(hand);
    expect_runout_facts(gear);
    // The sampler: F_r 10 µm with P1's profile and helix tolerances, 20 gears.
    ToleranceSet tight = testing_support::p1_tolerance_set();
    tight.values[ToleranceKind::kRunout] = {10, "test", true};
    const GearSampler sampler(gear, tight, DeviationModel{}, 5);
    for (int k = 0; k < 20; ++k) {
      EXPECT_LE(radial_runout_um(gear, sampler.draw(k)), 10.0) << "gear " << k;
    }
  }
}

}  // namespace
}  // namespace gearmc
