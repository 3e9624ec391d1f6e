// Tests of core/special_functions.h, the one toolbox of special functions, each against an
// independent answer: closed forms (Student t with ν = 1, 2; incomplete beta with a or b = 1 and
// a = b = 1/2; incomplete gamma with a = 1, 1/2 and integer a; F tails with d1 = 2 and
// d1 = d2 = 1), printed tables (JCGM 100:2008 Table G.2; Abramowitz & Stegun table 26.9;
// Smirnov's 1948 table of Kolmogorov's limiting law), and a brute-force supremum for the
// Kolmogorov–Smirnov distance.
#include "core/special_functions.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

namespace gearmc {
namespace {

TEST(SpecialFunctions, StudentTQuantileClosedForms) {
  for (double p : {0.6, 0.9, 0.975, 0.99865, 0.999}) {
    EXPECT_NEAR(student_t_quantile(p, 1.0), std::tan(std::numbers::pi * (p - 0.5)),
                1e-10 * std::tan(std::numbers::pi * (p - 0.5)));
    const double t2 = (2 * p - 1) / std::sqrt(2 * p * (1 - p));
    EXPECT_NEAR(student_t_quantile(p, 2.0), t2, 1e-10 * t2);
    EXPECT_NEAR(student_t_quantile(1 - p, 2.0), -t2, 1e-10 * t2);
  }
}

TEST(SpecialFunctions, StudentTQuantileGumTableG2) {
  // JCGM 100:2008 Table G.2, t_p(ν) for p = 95 % and 99.73 % (printed to 2 decimals). The
  // table's 99.73 % is the coverage of k = 3 for the normal law, 2Φ(3) − 1 = 0.9973002 (with
  // 0.9973 exactly, ν = 1 gives 235.78, not the printed 235.80).
  const double p3 = 2 * normal_cdf(3.0) - 1;
  struct Row {
    double nu, t95, t9973;
  };
  const Row rows[] = {{1, 12.71, 235.80}, {2, 4.30, 19.21}, {3, 3.18, 9.22}, {5, 2.57, 5.51},
                      {10, 2.23, 3.96},   {20, 2.09, 3.42}, {50, 2.01, 3.16}};
  for (const Row& r : rows) {
    EXPECT_NEAR(student_t_quantile(0.975, r.nu), r.t95, 0.005) << r.nu;
    EXPECT_NEAR(student_t_quantile(0.5 + p3 / 2, r.nu), r.t9973, 0.005) << r.nu;
  }
  // ν = ∞ row: 1.96 and 3.00; the normal quantile to full precision.
  EXPECT_NEAR(student_t_quantile(0.975, INFINITY), 1.959963984540054, 1e-13);
  // Huge ν: t → normal; I_x(ν/2, 1/2) near x = 1 loses digits (lgamma of 5e8), 1e-6 is kept.
  EXPECT_NEAR(student_t_quantile(0.975, 1e9), 1.959963984540054, 1e-6);
  // ν = 1e4: Cornish–Fisher, z + (z³ + z)/(4ν) + (5z⁵ + 16z³ + 3z)/(96ν²) (A&S 26.7.5).
  const double z = 1.959963984540054, nu = 1e4;
  EXPECT_NEAR(student_t_quantile(0.975, nu),
              z + (z * z * z + z) / (4 * nu) +
                  (5 * std::pow(z, 5) + 16 * z * z * z + 3 * z) / (96 * nu * nu),
              1e-10);
  for (double p : {1e-10, 0.001, 0.02425, 0.3, 0.5, 0.9, 0.99999}) {
    EXPECT_NEAR(normal_cdf(normal_quantile(p)), p, 1e-14 * std::max(p, 1e-3));
  }
}

TEST(SpecialFunctions, IncompleteBetaClosedForms) {
  // I_x(a, 1) = x^a; I_x(1, b) = 1 − (1−x)^b; I_x(1/2, 1/2) = (2/π) asin(√x).
  for (double x : {0.01, 0.3, 0.5, 0.77, 0.999}) {
    EXPECT_NEAR(incomplete_beta(2.5, 1.0, x), std::pow(x, 2.5), 1e-14);
    EXPECT_NEAR(incomplete_beta(1.0, 3.5, x), 1 - std::pow(1 - x, 3.5), 1e-14);
    EXPECT_NEAR(incomplete_beta(0.5, 0.5, x), 2 / std::numbers::pi * std::asin(std::sqrt(x)),
                1e-13);
  }
}

TEST(SpecialFunctions, FDistributionTailMatchesClosedFormsAndTables) {
  // d1 = 2: P(F > f) = (1 + 2f/d2)^(−d2/2); d1 = d2 = 1: 1 − (2/π) atan √f (both follow from
  // the F density, Johnson, Kotz & Balakrishnan vol. 2, ch. 27).
  for (double f : {0.1, 1.0, 3.0, 10.0}) {
    for (double d2 : {5.0, 40.0, 2400.0}) {
      EXPECT_NEAR(f_distribution_upper_tail(f, 2, d2), std::pow(1.0 + 2.0 * f / d2, -d2 / 2),
                  1e-12);
    }
    EXPECT_NEAR(f_distribution_upper_tail(f, 1, 1),
                1.0 - 2.0 / std::numbers::pi * std::atan(std::sqrt(f)), 1e-12);
  }
  // Table values (Abramowitz & Stegun table 26.9): F_0.05(1, 10) = 4.96, F_0.05(5, 10) = 3.33,
  // F_0.01(3, 120) = 3.95; more digits from the quantile function: 4.964603, 3.325835, 3.949163.
  EXPECT_NEAR(f_distribution_upper_tail(4.964603, 1, 10), 0.05, 1e-6);
  EXPECT_NEAR(f_distribution_upper_tail(3.325835, 5, 10), 0.05, 1e-6);
  EXPECT_NEAR(f_distribution_upper_tail(3.949163, 3, 120), 0.01, 1e-6);
}

TEST(SpecialFunctions, IncompleteGammaClosedForms) {
  for (double x : {0.01, 0.5, 1.0, 3.0, 10.0, 40.0}) {
    // P(1, x) = 1 - e^-x; P(1/2, x) = erf(sqrt x) (Abramowitz & Stegun 6.5.17 with 7.1.1).
    EXPECT_NEAR(regularized_gamma_p(1.0, x), -std::expm1(-x), 1e-15);
    EXPECT_NEAR(regularized_gamma_q(1.0, x) / std::exp(-x), 1.0, 1e-13);
    EXPECT_NEAR(regularized_gamma_p(0.5, x), std::erf(std::sqrt(x)), 1e-14);
    EXPECT_NEAR(regularized_gamma_q(0.5, x) / std::erfc(std::sqrt(x)), 1.0, 1e-12);
  }
  // Integer a: Q(k, x) = e^-x sum_{j<k} x^j / j! (the Erlang / Poisson identity, A&S 6.5.13).
  for (int k : {2, 5, 12, 50}) {
    for (double x : {0.3, 2.0, 5.0, 11.0, 30.0, 70.0}) {
      double term = 1.0, sum = 1.0;
      for (int j = 1; j < k; ++j) {
        term *= x / j;
        sum += term;
      }
      const double q = std::exp(-x) * sum;
      EXPECT_NEAR(regularized_gamma_q(k, x) / q, 1.0, 1e-12) << "k " << k << " x " << x;
      EXPECT_NEAR(regularized_gamma_p(k, x) + regularized_gamma_q(k, x), 1.0, 1e-14);
    }
  }
}

// Kolmogorov's limiting law (Smirnov 1948, the table of K(λ)): Q_KS(1.3581) = 0.05 and
// Q_KS(1.6276) = 0.01. For large n the corrected λ is √n D, so D = K/√n gives those tails.
TEST(SpecialFunctions, KolmogorovTailAtItsTabulatedPoints) {
  const int n = 1000000;
  const double sn = std::sqrt(static_cast<double>(n));
  EXPECT_NEAR(ks_p_value(1.3581 / (sn + 0.12 + 0.11 / sn), n), 0.05, 1e-4);
  EXPECT_NEAR(ks_p_value(1.6276 / (sn + 0.12 + 0.11 / sn), n), 0.01, 1e-4);
  EXPECT_EQ(ks_p_value(0.0, n), 1.0);
  EXPECT_TRUE(std::isnan(ks_p_value(0.1, 0)));
}

// The KS distance is the exact supremum over the sample's jumps: compared with a brute-force
// supremum of |F_n(x) − F(x)| on a fine grid plus both one-sided limits at every sample point,
// for the uniform CDF on [0, 1] (F(x) = x) and an unsorted sample with a tie.
TEST(SpecialFunctions, KsDistanceIsTheSupremumOverTheJumps) {
  const std::vector<double> v = {0.62, 0.05, 0.31, 0.31, 0.97, 0.44, 0.12};
  const auto cdf = [](double x) { return std::clamp(x, 0.0, 1.0); };
  const double n = static_cast<double>(v.size());
  auto empirical = [&](double x, bool inclusive) {
    return static_cast<double>(std::count_if(
               v.begin(), v.end(), [&](double y) { return inclusive ? y <= x : y < x; })) /
           n;
  };
  double brute = 0.0;
  for (int k = 0; k <= 100000; ++k) {
    const double x = k / 100000.0;
    brute = std::max(brute, std::abs(empirical(x, true) - cdf(x)));
  }
  for (double y : v) {  // the limits from the left and at the jump
    brute = std::max(
        {brute, std::abs(empirical(y, false) - cdf(y)), std::abs(empirical(y, true) - cdf(y))});
  }
  EXPECT_NEAR(ks_distance(v, cdf), brute, 1e-12);
  EXPECT_TRUE(std::isnan(ks_distance(std::vector<double>{}, cdf)));
}

}  // namespace
}  // namespace gearmc
