// The input laws of `gearmc uncertainty`, against independent answers (their special functions
// are tested in tests/core/special_functions_test.cpp):
//  * each law's mean and variance (closed forms of JCGM 101 §6.4) against ∫_0^1 Q(p) dp and
//    ∫_0^1 Q(p)^2 dp computed numerically from the law's own quantile function (substituting p =
//    Φ(z), a fine rectangle rule in z), i.e. moments and CDF checked against each other;
//  * quantile(cdf(x)) round trips, and named CDF values (a triangle's mode, a trapezoid's
//    corner);
//  * sampling: 200 000 draws of each law (seed 11) have a mean within 4.5 standard errors of the
//    exact mean and a Kolmogorov–Smirnov distance to the law's CDF below the 0.1 % critical
//    value 1.949/√n (two-sided; Massey 1951), so each check fails by chance with probability
//    below 0.1 %, and with fixed seeds never flakes.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <vector>

#include "core/special_functions.h"
#include "engine/apps/uncertainty/laws.h"

namespace gearmc::uncertainty {
namespace {

struct LawCase {
  const char* what;
  Law law;
};

std::vector<LawCase> all_laws() {
  return {
      {"normal", make_law(LawKind::kNormal, {3.0, 0.5})},
      {"uniform", make_law(LawKind::kUniform, {-1.0, 3.0})},
      {"triangular symmetric", make_law(LawKind::kTriangular, {-2.0, 2.0})},
      {"triangular skew", make_law(LawKind::kTriangular, {0.0, 1.0, 4.0})},
      {"arcsine", make_law(LawKind::kArcsine, {1.0, 2.0})},
      {"trapezoidal", make_law(LawKind::kTrapezoidal, {0.0, 2.0, 0.4})},
      {"curvilinear trapezoid", make_law(LawKind::kCurvilinearTrapezoid, {-1.0, 1.0, 0.3})},
      {"student t", make_law(LawKind::kStudentT, {10.0, 0.2, 7.0})},
      {"data", make_from_data({9.8, 10.1, 10.0, 10.4, 9.9, 10.2})},
      {"exponential", make_law(LawKind::kExponential, {2.0})},
      {"gamma", make_law(LawKind::kGamma, {3.0, 1.5})},
      {"gamma shape < 1", make_law(LawKind::kGamma, {1.0, 1.5})},
  };
}

TEST(UncertaintyLaws, MomentsEqualIntegralsOfTheQuantileFunction) {
  // E X = ∫ Q(p) dp, E X² = ∫ Q(p)² dp; substitution p = Φ(z) puts the tails at finite z, the
  // integral in z by the rectangle rule on [-8, 8] (step 2e-3; beyond ±8 the normal weight
  // is below 1e-15).
  for (const LawCase& c : all_laws()) {
    double m1 = 0, m2 = 0;
    const double h = 2e-3;
    for (double z = -8.0; z <= 8.0; z += h) {
      const double dens = std::exp(-0.5 * z * z) / std::sqrt(2 * std::numbers::pi);
      const double q = c.law.quantile(normal_cdf(z));
      m1 += q * dens * h;
      m2 += q * q * dens * h;
    }
    EXPECT_NEAR(m1, c.law.mean(), 1e-5 * (1 + std::fabs(c.law.mean()))) << c.what;
    EXPECT_NEAR(m2 - m1 * m1, c.law.variance(), 2e-4 * c.law.variance()) << c.what;
  }
}

TEST(UncertaintyLaws, QuantileInvertsCdfAndNamedValues) {
  for (const LawCase& c : all_laws()) {
    for (double p : {0.001, 0.05, 0.3, 0.5, 0.81, 0.975, 0.9995}) {
      EXPECT_NEAR(c.law.cdf(c.law.quantile(p)), p, 1e-9) << c.what << " p " << p;
    }
  }
  // Triangle [0, 1, 4]: F(mode) = (c−a)/(b−a) = 1/4.
  EXPECT_DOUBLE_EQ(make_law(LawKind::kTriangular, {0.0, 1.0, 4.0}).cdf(1.0), 0.25);
  // Trapezoid [0, 2, 0.4]: ramps of width 0.6, top height 2/(2·1.4); F(0.6) = 0.6·h/2 = 3/14.
  EXPECT_NEAR(make_law(LawKind::kTrapezoidal, {0.0, 2.0, 0.4}).cdf(0.6), 3.0 / 14.0, 1e-15);
  // Arcsine: F at a quarter of the way = 1/2 + asin(-1/2)/π = 1/3.
  EXPECT_NEAR(make_law(LawKind::kArcsine, {0.0, 4.0}).cdf(1.0), 1.0 / 3.0, 1e-15);
  // Data: x̄ = 10.0667, s = 0.21602, scale s/√6, ν = 5 (JCGM 101 §6.4.9), by hand.
  const Law d = make_from_data({9.8, 10.1, 10.0, 10.4, 9.9, 10.2});
  EXPECT_NEAR(d.mean(), 60.4 / 6.0, 1e-12);
  EXPECT_NEAR(d.gum_u(), std::sqrt(0.23333333333333 / 5.0) / std::sqrt(6.0), 1e-9);
  EXPECT_EQ(d.gum_dof(), 5.0);
  EXPECT_EQ(make_law(LawKind::kUniform, {0, 1}).gum_dof(), INFINITY);
}

TEST(UncertaintyLaws, SamplesMatchMeanAndCdf) {
  const int n = 200000;
  for (const LawCase& c : all_laws()) {
    std::vector<double> x(n);
    for (int t = 0; t < n; ++t) {
      TrialStream s(11, static_cast<std::uint64_t>(t), 3);
      x[t] = c.law.sample(s);
    }
    double mean = 0;
    for (double v : x) mean += v;
    mean /= n;
    EXPECT_NEAR(mean, c.law.mean(), 4.5 * c.law.sd() / std::sqrt(double(n))) << c.what;
    std::sort(x.begin(), x.end());
    double ks = 0;
    for (int i = 0; i < n; ++i) {
      const double f = c.law.cdf(x[i]);
      ks = std::max({ks, std::fabs(f - double(i) / n), std::fabs(f - double(i + 1) / n)});
    }
    EXPECT_LT(ks, 1.949 / std::sqrt(double(n))) << c.what;
  }
}

TEST(UncertaintyLaws, BadParametersAreRefused) {
  EXPECT_THROW(make_law(LawKind::kNormal, {1.0}), std::invalid_argument);
  EXPECT_THROW(make_law(LawKind::kNormal, {1.0, 0.0}), std::invalid_argument);
  EXPECT_THROW(make_law(LawKind::kUniform, {2.0, 1.0}), std::invalid_argument);
  EXPECT_THROW(make_law(LawKind::kTriangular, {0.0, 5.0, 4.0}), std::invalid_argument);
  EXPECT_THROW(make_law(LawKind::kTrapezoidal, {0.0, 1.0, 1.5}), std::invalid_argument);
  EXPECT_THROW(make_law(LawKind::kCurvilinearTrapezoid, {0.0, 1.0, 0.5}), std::invalid_argument);
  EXPECT_THROW(make_law(LawKind::kGamma, {1.0, -1.0}), std::invalid_argument);
  EXPECT_THROW(make_from_data({1.0, 1.0, 1.0}), std::invalid_argument);
  EXPECT_THROW(make_from_data({1.0}), std::invalid_argument);
}

// The Gaussian copula (laws.h). Between two uniform inputs the correlation coefficient is
// (6/π) arcsin(ρ/2) (Pearson 1907; Kruskal, JASA 53, 1958: for uniform marginals Pearson's r is
// Spearman's ρ_S of the normal pair), so the copula's ρ for r is 2 sin(πr/6); two normal inputs
// need none (ρ = r); a law without a finite variance, and a correlation the two laws cannot have
// (an exponential and a uniform input cannot reach ±0.99), are refused.
TEST(UncertaintyLaws, GaussianCopulaGivesTheStatedCorrelation) {
  const Law u1 = make_law(LawKind::kUniform, {0.0, 1.0});
  const Law u2 = make_law(LawKind::kUniform, {-3.0, 5.0});
  for (double r : {0.5, -0.3, 0.9}) {
    EXPECT_NEAR(copula_correlation_for(u1, u2, r), 2.0 * std::sin(std::numbers::pi * r / 6.0), 1e-4)
        << r;
  }
  EXPECT_NEAR(copula_input_correlation(u1, u2, 0.7), 6.0 / std::numbers::pi * std::asin(0.35),
              1e-4);
  const Law n1 = make_law(LawKind::kNormal, {1.0, 2.0});
  const Law n2 = make_law(LawKind::kNormal, {0.0, 1.0});
  EXPECT_EQ(copula_correlation_for(n1, n2, 0.37), 0.37);
  // Normal–normal through the quadrature too: r = ρ (the rule is exact for these polynomials).
  EXPECT_NEAR(copula_input_correlation(n1, n2, 0.37), 0.37, 1e-12);
  // A skewed pair: the stated r is met (the copula's ρ differs from it).
  const Law e = make_law(LawKind::kExponential, {2.0});
  const double rho = copula_correlation_for(e, u1, 0.6);
  EXPECT_NEAR(copula_input_correlation(e, u1, rho), 0.6, 1e-9);
  EXPECT_GT(std::abs(rho - 0.6), 0.01);
  EXPECT_THROW(copula_correlation_for(e, u1, 0.99), std::invalid_argument);
  const Law t2 = make_law(LawKind::kStudentT, {0.0, 1.0, 2.0});  // ν = 2: no finite variance
  EXPECT_THROW(copula_correlation_for(t2, u1, 0.5), std::invalid_argument);
}

}  // namespace
}  // namespace gearmc::uncertainty
