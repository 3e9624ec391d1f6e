// Tests of the empirical term (engine/effects/empirical_effect.h,
// engine/apps/diagnose/empirical_term.h): the effect against hand-computed values of its basis, the
// BIC order choice against an independent least-squares computation with the Legendre polynomials
// written out, and the whole loop on readings whose structure is outside the library: the verdict
// leads with it, the term is fitted along its axis, written to fitted.yaml, and a second diagnosis
// against fitted.yaml finds the gap closed. Seeds are fixed (simulation seed 1, null-simulation
// seed 1, std::mt19937 seed 7), so every assertion is deterministic.
#include <gtest/gtest.h>

#include <Eigen/LU>
#include <Eigen/QR>
#include <cmath>
#include <numbers>
#include <random>

#include "core/input_error.h"
#include "engine/apps/diagnose/diagnosis.h"
#include "engine/apps/diagnose/empirical_term.h"
#include "engine/apps/diagnose/fitted_scenario.h"
#include "engine/effects/effect_config.h"
#include "engine/effects/empirical_effect.h"
#include "engine/run/simulate.h"

#include "tests/support/effect_chain.h"

namespace gearmc {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kNoiseUm = 0.3;

using testing_support::chain;
using testing_support::reading_change;

TEST(EmpiricalEffect, LegendreAndHarmonicTermsMatchHandValues) {
  PointContext p;
  p.p = Eigen::Vector3d(60.0, 10.0, 7.5);
  p.n = Eigen::Vector3d(std::cos(0.3), std::sin(0.3), 0.0);
  p.azimuth_rad = kPi / 6.0;
  // Legendre on z ∈ [0, 10]: t = 2·7.5/10 − 1 = 0.5; P1 = 0.5, P2 = (3·0.25 − 1)/2 = −0.125,
  // P3 = (5·0.125 − 3·0.5)/2 = −0.4375 (A&S 22.3.8): 0.2·0.5 − 0.3·(−0.125) + 0.1·(−0.4375).
  const EffectChain legendre = chain(
      "empirical: {axis: face_position, basis: legendre, from: 0, to: 10, terms: [{order: 1, "
      "a_um: 0.2}, {order: 2, a_um: -0.3}, {order: 3, a_um: 0.1}]}\n");
  EXPECT_NEAR(reading_change(legendre, p), 0.1 + 0.0375 - 0.04375, 1e-9);
  // Harmonic along the approach azimuth, order 2: 0.4 cos 60° + 0.1 sin 60°.
  const EffectChain harmonic = chain(
      "empirical: {axis: approach_azimuth, basis: harmonic, terms: [{order: 2, a_um: 0.4, b_um: "
      "0.1}]}\n");
  EXPECT_NEAR(reading_change(harmonic, p), 0.4 * 0.5 + 0.1 * std::sqrt(3.0) / 2.0, 1e-9);
  // Roll length: r_b = 50 mm, r² = 3700 → L = √1200 mm; range [0, 40] → t = √1200/20 − 1.
  p.base_radius_mm = 50.0;
  const double t = std::sqrt(1200.0) / 20.0 - 1.0;
  const EffectChain roll = chain(
      "empirical: {axis: roll_length, basis: legendre, from: 0, to: 40, terms: [{order: 1, a_um: "
      "1}]}\n");
  EXPECT_NEAR(reading_change(roll, p), t, 1e-9);
  // Flank: ±1 (left −1).
  p.side = FlankSide::kLeft;
  const EffectChain flank = chain(
      "empirical: {axis: flank, basis: legendre, from: -1, to: 1, terms: [{order: 1, a_um: "
      "0.25}]}\n");
  EXPECT_NEAR(reading_change(flank, p), -0.25, 1e-9);  // mm ↔ µm round trip
}

TEST(EmpiricalEffect, BadInputIsRefusedWithTheKey) {
  EXPECT_THROW(chain("empirical: {basis: legendre, from: 0, to: 1}\n"), InputError);
  EXPECT_THROW(chain("empirical: {axis: tooth, basis: legendre, from: 1, to: 1}\n"), InputError);
  EXPECT_THROW(chain("empirical: {axis: face_position, basis: legendre, from: 0, to: 1, terms: "
                     "[{order: 1, a_um: 1, b_um: 2}]}\n"),
               InputError);
  EXPECT_THROW(chain("empirical: {axis: tooth, basis: harmonic, terms: [{order: 1, a_um: 1}, "
                     "{order: 1, a_um: 2}]}\n"),
               InputError);
}

TEST(EmpiricalTerm, TheBicPicksTheTrueOrderAndTheFitMatchesAnIndependentSolve) {
  // 11 face positions z = 0 … 10 mm, 20 points each; residual = 0.5 P2(t) + N(0, 0.1²)
  // (std::mt19937 seed 7). The BIC of orders 1 and 2 recomputed with P1 = t, P2 = (3t² − 1)/2
  // written out and solved by Householder QR (not the recurrence nor the project's solver).
  std::vector<ResidualPoint> points;
  std::mt19937 gen(7);
  std::normal_distribution<double> noise(0.0, 0.1);
  for (int rep = 0; rep < 20; ++rep) {
    for (int k = 0; k <= 10; ++k) {
      ResidualPoint p;
      p.context.p = Eigen::Vector3d(60.0, 0.0, k);
      points.push_back(p);
    }
  }
  const int n = static_cast<int>(points.size());
  Eigen::VectorXd r(n);
  for (int i = 0; i < n; ++i) {
    const double t = 2.0 * points[i].context.p.z() / 10.0 - 1.0;
    r[i] = 0.5 * (3.0 * t * t - 1.0) / 2.0 + noise(gen);
  }
  const EmpiricalTerm e = fit_empirical_term(points, r, 0, 0.01, "face_position", 10.0);
  ASSERT_TRUE(e.fitted) << e.why_not;
  EXPECT_EQ(e.basis, "legendre");
  EXPECT_EQ(e.order, 2);
  EXPECT_EQ(e.max_order, 6);
  ASSERT_EQ(e.terms.size(), 2u);
  EXPECT_LE(std::abs(e.terms[0].value_um - 0.0), 3.0 * e.terms[0].std_error_um);
  EXPECT_LE(std::abs(e.terms[1].value_um - 0.5), 3.0 * e.terms[1].std_error_um);
  auto independent = [&](int order) {
    Eigen::MatrixXd b(n, order);
    for (int i = 0; i < n; ++i) {
      const double t = 2.0 * points[i].context.p.z() / 10.0 - 1.0;
      b(i, 0) = t;
      if (order == 2) b(i, 1) = (3.0 * t * t - 1.0) / 2.0;
    }
    const Eigen::VectorXd beta = b.householderQr().solve(r);
    return std::pair{(r - b * beta).squaredNorm(), beta};
  };
  const double rss0 = r.squaredNorm();
  for (int order : {1, 2}) {
    const double rss = independent(order).first;
    EXPECT_NEAR(e.bic[order], n * std::log(rss / rss0) + order * std::log(n), 1e-8) << order;
  }
  const auto [rss2, beta2] = independent(2);
  EXPECT_NEAR(e.terms[1].value_um, beta2[1], 1e-10);
  EXPECT_NEAR(e.rms_after_um, std::sqrt(rss2 / n), 1e-12);
  // Standard error: σ̂² (BᵀB)⁻¹ with σ̂² = RSS/(n − 2).
  Eigen::MatrixXd b(n, 2);
  for (int i = 0; i < n; ++i) {
    const double t = 2.0 * points[i].context.p.z() / 10.0 - 1.0;
    b(i, 0) = t;
    b(i, 1) = (3.0 * t * t - 1.0) / 2.0;
  }
  const Eigen::MatrixXd cov = (b.transpose() * b).inverse() * (rss2 / (n - 2));
  EXPECT_NEAR(e.terms[1].std_error_um, std::sqrt(cov(1, 1)), 1e-10);
  // Pure noise along the same axis: no order earns the BIC's 10, so no term.
  Eigen::VectorXd white(n);
  for (int i = 0; i < n; ++i) white[i] = noise(gen);
  const EmpiricalTerm none = fit_empirical_term(points, white, 0, 0.01, "face_position", 10.0);
  EXPECT_FALSE(none.fitted);
  EXPECT_FALSE(none.why_not.empty());
}

Scenario with_effects(const std::string& effects_yaml) {
  Scenario s = reference_scenario();
  s.effects = std::make_shared<const EffectChain>(chain(effects_yaml));
  return s;
}

TEST(EmpiricalTerm, StructureOutsideTheLibraryIsFittedWrittenAndClosesTheGapOnASecondDiagnosis) {
  // A waviness across the face, 0.8 sin(2π z / 20 mm) µm on every flank (outside the library),
  // noise 0.3 µm, P1's master and 10 × 5 grid; diagnosed against the reference with noise 0.3 µm.
  Scenario truth = with_effects("noise: {sigma_um: 0.3}\n");
  truth.normal_expression_um = "0.8*sin(2*_pi*z/20)";
  SimulateOptions o;
  o.master = true;
  truth.seed = 1;
  const Readings readings = simulate_readings(truth, o).readings;
  // The model from text (fitted.yaml starts from the model's text): the reference + noise 0.3 µm.
  const Scenario model = parse_scenario(
      reference_scenario().source_text + "\neffects:\n  noise: {sigma_um: 0.3}\n", "model.yaml");
  const Diagnosis d = diagnose(model, readings);
  EXPECT_EQ(d.named_effect_text(), "unexplained");
  EXPECT_EQ(d.unexplained_along.axis, "face_position");
  const EmpiricalTerm& e = d.empirical;
  ASSERT_TRUE(e.fitted) << e.why_not;
  EXPECT_EQ(e.axis, "face_position");
  EXPECT_EQ(e.basis, "legendre");
  // Five sections: at most order 4, which reproduces any five section means.
  EXPECT_LE(e.order, 4);
  EXPECT_LE(e.rms_after_um, 1.1 * kNoiseUm);
  EXPECT_GT(e.rms_before_um, 1.5 * kNoiseUm);
  EXPECT_FALSE(e.identify_by.empty());
  ASSERT_FALSE(d.notes.empty());
  EXPECT_NE(d.notes.front().find("empirical"), std::string::npos) << d.notes.front();
  // fitted.yaml holds the term and loads as a scenario; against it the gap is closed.
  const FittedScenario fitted = fitted_scenario(model, d, "model.yaml", "readings.csv");
  EXPECT_NE(fitted.yaml.find("empirical:"), std::string::npos) << fitted.yaml;
  const Scenario refitted = parse_scenario(fitted.yaml, "fitted.yaml");
  ASSERT_GE(refitted.effects->find("empirical"), 0);
  const Diagnosis again = diagnose(refitted, readings);
  EXPECT_LE(again.gap_before.rms_um, 1.1 * kNoiseUm);
  EXPECT_NEAR(again.gap_before.rms_um, e.rms_after_um, 0.02);
  EXPECT_EQ(again.named_effect_text(), "none");
}

}  // namespace
}  // namespace gearmc
