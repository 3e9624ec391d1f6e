// Tests of the diagnosis's numerical tools (engine/apps/diagnose/linear_model.h): the Kolmogorov
// distance to a normal law and its tail as the diagnosis uses them, Holm's adjustment, canonical
// correlations, least squares with dependent columns and the harmonic spectrum, each against closed
// forms and textbook values.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

#include "core/special_functions.h"
#include "engine/apps/diagnose/diagnosis.h"
#include "engine/apps/diagnose/linear_model.h"
#include "tests/support/diagnose_readings.h"

namespace gearmc {
namespace {

constexpr double kPi = std::numbers::pi;

// --- Numerical tools --------------------------------------------------------------------------

TEST(DiagnoseTools, HolmAdjustmentOfATextbookExample) {
  // p = {0.01, 0.04, 0.03, 0.005}, m = 4: sorted 0.005·4 = 0.02, 0.01·3 = 0.03, 0.03·2 = 0.06,
  // 0.04·1 = 0.04 → monotone 0.06 (Holm 1979's step-down rule, by hand).
  const std::vector<double> adjusted = holm_adjust({0.01, 0.04, 0.03, 0.005});
  EXPECT_NEAR(adjusted[0], 0.03, 1e-15);
  EXPECT_NEAR(adjusted[1], 0.06, 1e-15);
  EXPECT_NEAR(adjusted[2], 0.06, 1e-15);
  EXPECT_NEAR(adjusted[3], 0.02, 1e-15);
}

TEST(DiagnoseTools, CanonicalCorrelationsAndConditionNumberOfKnownAngles) {
  // span{e1, e2} and span{e1, cos t e2 + sin t e3}: principal angles 0 and t.
  const double t = 0.3;
  Eigen::MatrixXd a(3, 2), b(3, 2);
  a << 1, 0, 0, 1, 0, 0;
  b << 1, 0, 0, std::cos(t), 0, std::sin(t);
  const std::vector<double> cc = canonical_correlations(a, b);
  ASSERT_EQ(cc.size(), 2u);
  EXPECT_NEAR(cc[0], 1.0, 1e-14);
  EXPECT_NEAR(cc[1], std::cos(t), 1e-14);
  // Two columns at cosine c (any lengths): singular values √(1 ± c) once scaled.
  Eigen::MatrixXd x(2, 2);
  x << 5.0, 0.2 * std::cos(t), 0.0, 0.2 * std::sin(t);
  const double c = std::cos(t);
  EXPECT_NEAR(scaled_condition_number(x), std::sqrt((1 + c) / (1 - c)), 1e-12);
}

TEST(DiagnoseTools, KolmogorovTailAtItsFivePercentPoint) {
  // Q_KS(1.358) = 0.05 (Kolmogorov's limiting law, the usual 5 % critical value 1.358).
  const int n = 2400;
  const double sn = std::sqrt(static_cast<double>(n));
  EXPECT_NEAR(ks_p_value(1.358 / (sn + 0.12 + 0.11 / sn), n), 0.05, 2e-4);
  // The distance of a sample equal to the normal quantiles (i − 1/2)/n is 1/(2n).
  // Φ⁻¹(0.1, 0.3, 0.5, 0.7, 0.9) (standard normal quantiles), scaled by σ = 0.3.
  std::vector<double> v;
  for (double q :
       {-1.2815515655446004, -0.5244005127080407, 0.0, 0.5244005127080407, 1.2815515655446004}) {
    v.push_back(0.3 * q);
  }
  EXPECT_NEAR(ks_distance_normal(v, 0.3), 0.1, 1e-12);
}

TEST(DiagnoseTools, LeastSquaresLeavesDependentColumnsOut) {
  Eigen::MatrixXd x(6, 3);
  Eigen::VectorXd y(6);
  for (int r = 0; r < 6; ++r) {
    x(r, 0) = 1.0;
    x(r, 1) = 2.0;  // = 2 × column 0
    x(r, 2) = r;
    y[r] = 0.5 + 0.25 * r;
  }
  const LeastSquaresFit fit = least_squares(x, y);
  EXPECT_EQ(fit.rank, 2);
  EXPECT_TRUE(fit.estimable[0]);
  EXPECT_FALSE(fit.estimable[1]);
  EXPECT_NEAR(fit.beta[0], 0.5, 1e-12);
  EXPECT_NEAR(fit.beta[2], 0.25, 1e-12);
  EXPECT_NEAR(fit.rss, 0.0, 1e-20);
  // (XᵀX)⁻¹ of [1, r], r = 0..5 by hand: det = 6·55 − 15² = 105 → [55, −15; −15, 6] / 105.
  EXPECT_NEAR(fit.cov_unscaled(0, 0), 55.0 / 105.0, 1e-12);
  EXPECT_NEAR(fit.cov_unscaled(2, 2), 6.0 / 105.0, 1e-12);
  EXPECT_NEAR(fit.cov_unscaled(0, 2), -15.0 / 105.0, 1e-12);
}

// gram_root: L Lᵀ reproduces a rank-deficient Gram matrix (checked by the product, not by the
// Cholesky recurrence), with one column per independent column: four columns of which the third
// is the sum of the first two and the fourth repeats the second, so rank 2. Its last row repeats
// the second's (the same column). A Gram matrix with a repeated eigenvalue (the identity plus a
// rounding-size change of 1e-15) gives a root within 1e-12 of the identity's, where an
// eigenvector root may turn by any angle inside the repeated eigenvalue.
TEST(DiagnoseTools, GramRootIsARootOfRankDeficientGramsAndMovesOnlyWithTheMatrix) {
  Eigen::MatrixXd x(5, 4);
  x << 1, 0, 1, 0,  //
      2, 1, 3, 1,   //
      0, 3, 3, 3,   //
      -1, 2, 1, 2,  //
      4, -1, 3, -1;
  const Eigen::MatrixXd g = x.transpose() * x;
  const Eigen::MatrixXd l = gram_root(g);
  ASSERT_EQ(l.rows(), 4);
  EXPECT_EQ(l.cols(), 2);
  EXPECT_LE((l * l.transpose() - g).cwiseAbs().maxCoeff(), 1e-12 * g.cwiseAbs().maxCoeff());
  EXPECT_LE((l.row(3) - l.row(1)).norm(), 1e-12 * l.norm());
  Eigen::MatrixXd i3 = Eigen::MatrixXd::Identity(3, 3);
  Eigen::MatrixXd nudged = i3;
  nudged(0, 1) = nudged(1, 0) = 1e-15;
  EXPECT_LE((gram_root(nudged) - gram_root(i3)).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_LE((gram_root(i3) - i3).cwiseAbs().maxCoeff(), 0.0);
}

TEST(DiagnoseTools, HarmonicSpectrumRecoversAmplitudesOnUnevenAzimuths) {
  std::vector<double> phi;
  Eigen::VectorXd r(300);
  for (int k = 0; k < 300; ++k) {
    const double a = 2.0 * kPi * std::pow((k + 0.5) / 300.0, 1.3);  // uneven sampling
    phi.push_back(a);
    r[k] = 0.2 + 0.5 * std::cos(3.0 * a - 1.0) + 0.3 * std::sin(7.0 * a);
  }
  const std::vector<double> amp = HarmonicSpectrum(phi, 12).amplitudes(r);
  ASSERT_EQ(amp.size(), 13u);
  for (int k = 0; k <= 12; ++k) {
    const double expected = k == 0 ? 0.2 : k == 3 ? 0.5 : k == 7 ? 0.3 : 0.0;
    EXPECT_NEAR(amp[k], expected, 1e-9) << "order " << k;
  }
}

}  // namespace
}  // namespace gearmc
