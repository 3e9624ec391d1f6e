// Tests of the diagnosis's point-law stage (engine/apps/diagnose/point_law_stage.h): the residual
// law's moments and CDF by numerical integration, and the stage naming step quantization,
// probing noise and a stylus radius error from the spread of single readings. Readings are
// simulated from the built-in reference with fixed seeds.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <sstream>

#include "engine/apps/diagnose/diagnosis.h"
#include "engine/apps/diagnose/point_law_stage.h"
#include "tests/support/diagnose_readings.h"

namespace gearmc {
namespace {

using testing_support::baseline;
using testing_support::contains;
using testing_support::hidden;
using testing_support::master_readings;
using testing_support::value;
using testing_support::with_effects;

constexpr double kPi = std::numbers::pi;

// --- The point-law stage ----------------------------------------------------------------------

TEST(DiagnosePointLaw, ResidualLawIntegratesToItsMomentsAndCdf) {
  // r = o + e − u, e ~ N(0, 0.3²), u ~ U(0, 1), o = 0.2: mean o − w/2 = −0.3, variance
  // σ² + w²/12 (independent parts). Trapezoid integration of exp(log_density) on [−6, 6] (step
  // 1e-3; the tails beyond carry < 1e-15) gives 1, the mean and the variance; the closed-form
  // cdf equals the running integral of the density. Draws: sample mean and variance of 20 000
  // within 4 standard errors.
  const ResidualLaw law{0.3, 1.0, 0.2};
  const double h = 1e-3;
  double mass = 0.0, mean = 0.0, second = 0.0, running = 0.0;
  double previous = std::exp(law.log_density(-6.0));
  for (int k = 1; k <= 12000; ++k) {
    const double x = -6.0 + k * h;
    const double f = std::exp(law.log_density(x));
    const double slice = 0.5 * h * (f + previous);
    mass += slice;
    mean += 0.5 * h * (x * f + (x - h) * previous);
    second += 0.5 * h * (x * x * f + (x - h) * (x - h) * previous);
    running += slice;
    previous = f;
    if (k % 1500 == 0) {
      EXPECT_NEAR(law.cdf(x), running, 1e-6) << "x = " << x;
    }
  }
  EXPECT_NEAR(mass, 1.0, 1e-6);
  EXPECT_NEAR(mean, law.mean_um(), 1e-6);
  EXPECT_NEAR(mean, -0.3, 1e-6);
  EXPECT_NEAR(second - mean * mean, law.variance_um2(), 1e-6);
  EXPECT_NEAR(law.variance_um2(), 0.09 + 1.0 / 12.0, 1e-15);
  // In the upper tail the density is [Q(b) − Q(a)]/w, b = (x − o)/σ, a = (x − o + w)/σ (Q the
  // normal upper tail, by erfc); beyond double range it follows the Gaussian edge with Mills'
  // ratio Q(b) ≈ φ(b)/b (relative error ≈ 1/b² = 4e-4 at b = 49.3).
  auto upper = [](double z) { return 0.5 * std::erfc(z / std::sqrt(2.0)); };
  EXPECT_NEAR(law.log_density(3.0), std::log(upper(2.8 / 0.3) - upper(3.8 / 0.3)), 1e-9);
  const double b = 14.8 / 0.3;
  EXPECT_NEAR(law.log_density(15.0), -0.5 * b * b - 0.5 * std::log(2.0 * kPi) - std::log(b), 1e-3);
  EXPECT_TRUE(std::isfinite(law.log_density(40.0)));
  RandomStream rng(5, 0, StreamPurpose::kDiagnoseNull, 77);
  const int n = 20000;
  double s1 = 0.0, s2 = 0.0;
  for (int k = 0; k < n; ++k) {
    const double x = law.draw(rng);
    s1 += x;
    s2 += x * x;
  }
  const double m = s1 / n, v = s2 / n - m * m;
  EXPECT_NEAR(m, -0.3, 4.0 * std::sqrt(law.variance_um2() / n));
  EXPECT_NEAR(v, law.variance_um2(), 4.0 * law.variance_um2() * std::sqrt(2.0 / n));
  // The residual law of a model with a step: centred, the largest width kept.
  PointLaw model;
  model.gaussian_variance_um2 = 0.09;
  model.uniform_widths_um = {0.5, 1.0};
  const ResidualLaw centred = residual_law(model);
  EXPECT_DOUBLE_EQ(centred.width_um, 1.0);
  EXPECT_NEAR(centred.mean_um(), 0.0, 1e-15);
  EXPECT_NEAR(centred.variance_um2(), model.variance_um2(), 1e-15);
}

TEST(DiagnosePointLaw, StepQuantizationIsNamedByTheSpreadOfSingleReadings) {
  // Hidden: step_quantization q = 1 µm (the battery's size at 1×) on the master: every reading gets
  // −U(0, 1) µm, mean −0.5 µm, exactly a stylus radius error of +0.5 µm in the mean; the spread
  // √(0.3² + 1/12) = 0.416 µm (not 0.3) and its flat top name the step. The fitted model (q̂ in
  // the model) then has no gap.
  const Diagnosis d = diagnose(baseline(), hidden("step_quantization: {step_um: 1}\n"));
  EXPECT_TRUE(d.gap_detected);
  EXPECT_EQ(d.named_effect_text(), "step_quantization");
  EXPECT_FALSE(contains(d.ambiguous_with, "stylus_radius"));
  ASSERT_EQ(d.effects.size(), 1u);  // it replaced the constant shift stylus_radius had taken
  const FittedEffect& e = d.effects.front();
  EXPECT_TRUE(e.absolute);
  const FittedValue& q = value(e, "step_um");
  EXPECT_LE(std::abs(q.value - 1.0), 3.0 * q.std_error) << q.value << " ± " << q.std_error;
  EXPECT_LT(q.std_error, 0.05);
  EXPECT_TRUE(d.point_law.best().tied);
  EXPECT_LT(d.point_law.white_p, 0.01);
  EXPECT_NEAR(d.noise_floor_after_um, std::sqrt(0.09 + q.value * q.value / 12.0), 1e-12);
  EXPECT_LE(d.held_out_rms_um, 1.1 * d.noise_floor_after_um);
  EXPECT_FALSE(d.unexplained_structure);
  EXPECT_GE(d.explained_fraction, 0.9);
  EXPECT_GT(d.gap_after.energy_p, 0.01);  // the fitted law matches a simulation of itself

  std::ostringstream fitted;
  fitted << "step_quantization: {step_um: " << q.value << "}\nnoise: {sigma_um: 0.3}\n";
  const Diagnosis again =
      diagnose(with_effects(fitted.str()), hidden("step_quantization: {step_um: 1}\n"));
  EXPECT_EQ(again.named_effect_text(), "none");
  EXPECT_FALSE(again.gap_detected);
}

TEST(DiagnosePointLaw, ALargerProbingNoiseIsNamedNoise) {
  // Truth: noise σ 0.45 µm, model 0.3 µm; no systematic effect. The fitted σ is the truth's
  // within 3 standard errors, and a step (which would shift the mean) is not named.
  const Diagnosis d =
      diagnose(baseline(), master_readings(with_effects("noise: {sigma_um: 0.45}\n")));
  EXPECT_EQ(d.named_effect_text(), "noise");
  ASSERT_EQ(d.effects.size(), 1u);
  const FittedValue& s = value(d.effects.front(), "sigma_um");
  EXPECT_LE(std::abs(s.value - 0.45), 3.0 * s.std_error) << s.value << " ± " << s.std_error;
  EXPECT_FALSE(contains(d.ambiguous_with, "step_quantization"));
  EXPECT_FALSE(d.unexplained_structure);
}

TEST(DiagnosePointLaw, AStylusRadiusErrorIsNotAmbiguousWithStepQuantization) {
  // +0.5 µm radius error: the mean −0.5 µm a 1 µm step would also give, without its spread.
  const Diagnosis d = diagnose(baseline(), hidden("stylus_radius: {error_um: 0.5}\n"));
  EXPECT_LT(d.gap_before.energy_p, 0.01);  // a shift of 1.7 σ: the marginal laws differ
  EXPECT_EQ(d.named_effect_text(), "stylus_radius");
  EXPECT_FALSE(contains(d.ambiguous_with, "step_quantization"));
  EXPECT_EQ(d.point_law.chosen, 0);
  const PointLawHypothesis* step = d.point_law.find("step_quantization");
  ASSERT_NE(step, nullptr);
  EXPECT_GT(step->delta_bic, 6.0);
}

}  // namespace
}  // namespace gearmc
