// Deterministic normal deviations written as muParser expressions (docs/formats.md).
#include "gears/normal_expression.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>

namespace gearmc {
namespace {

TEST(NormalExpression, EvaluatesTheInterfaceExample) {
  // docs/formats.md's example: 2 sin(2 pi L / 5) + 0.1 (z - 39.445).
  const NormalExpression e("2*sin(2*_pi*L/5) + 0.1*(z-39.445)");
  const double L = 30.3, z = 12.0;
  EXPECT_NEAR(e.value_um(L, z, 1, 1.0),
              2 * std::sin(2 * std::numbers::pi * L / 5) + 0.1 * (z - 39.445),
              1e-9);  // muParser's bytecode reorders the arithmetic: agreement to ~1e-11
  EXPECT_NEAR(e.d_dL(L, z, 1, 1.0),
              2 * 2 * std::numbers::pi / 5 * std::cos(2 * std::numbers::pi * L / 5), 1e-6);
  EXPECT_NEAR(e.d_dz(L, z, 1, 1.0), 0.1, 1e-9);
}

// The slopes decide the contact point: a slope error e (µm/mm) moves C by about R e 1e-3 mm, so
// 1e-2 nm for R = 0.5 mm needs e <= 2e-5 µm/mm. Reference: the exact partials of a steep
// analytic field (35 µm waves of 0.8 x 0.9 mm, a 20 µm Gaussian bump of sigma 0.08 mm),
// differentiated by hand. The former central difference with h = 1e-3 mm was off by
// (h^2 / 6) |f'''| = 3e-3 µm/mm here (C off by ~1.4 nm).
TEST(NormalExpression, SlopesAreAccurateToTheCertificateTolerance) {
  const double pi = std::numbers::pi, kL = 2 * pi / 0.8, kz = 2 * pi / 0.9, s2 = 0.08 * 0.08;
  const NormalExpression e(
      "35*sin(2*_pi*L/0.8)*cos(2*_pi*z/0.9) + 20*exp(-((L-30)^2+(z-40)^2)/(2*0.08^2))");
  double worst_slope = 0, worst_second = 0;
  for (double L : {29.9, 30.0, 30.037, 30.13, 41.2}) {
    for (double z : {39.93, 40.0, 40.06, 12.5}) {
      const double g = 20 * std::exp(-((L - 30) * (L - 30) + (z - 40) * (z - 40)) / (2 * s2));
      const double gL = -(L - 30) / s2 * g, gz = -(z - 40) / s2 * g;
      const double dL = 35 * kL * std::cos(kL * L) * std::cos(kz * z) + gL;
      const double dz = -35 * kz * std::sin(kL * L) * std::sin(kz * z) + gz;
      const double dLL = -35 * kL * kL * std::sin(kL * L) * std::cos(kz * z) +
                         ((L - 30) * (L - 30) / (s2 * s2) - 1 / s2) * g;
      const double dzz = -35 * kz * kz * std::sin(kL * L) * std::cos(kz * z) +
                         ((z - 40) * (z - 40) / (s2 * s2) - 1 / s2) * g;
      const double dLz =
          -35 * kL * kz * std::cos(kL * L) * std::sin(kz * z) + (L - 30) * (z - 40) / (s2 * s2) * g;
      const NormalExpression::Derivatives d = e.derivatives(L, z, 1, 1.0);
      EXPECT_NEAR(e.d_dL(L, z, 1, 1.0), dL, 2e-5);
      EXPECT_NEAR(e.d_dz(L, z, 1, 1.0), dz, 2e-5);
      EXPECT_NEAR(d.dL, dL, 2e-5);
      EXPECT_NEAR(d.dz, dz, 2e-5);
      // Second partials only steer Newton and the certificate's curvature estimates: 1e-2
      // µm/mm² is 1e-5 of their scale (~1e3 µm/mm² here).
      EXPECT_NEAR(d.dLL, dLL, 1e-2);
      EXPECT_NEAR(d.dzz, dzz, 1e-2);
      EXPECT_NEAR(d.dLz, dLz, 2e-1);  // four-point cross difference: (h^2 / 6) f'''' ~ 0.1
      EXPECT_NEAR(d.value, e.value_um(L, z, 1, 1.0), 0.0);
      worst_slope = std::max({worst_slope, std::abs(d.dL - dL), std::abs(d.dz - dz)});
      worst_second = std::max({worst_second, std::abs(d.dLL - dLL), std::abs(d.dzz - dzz)});
    }
  }
  std::printf("worst slope error %.3g µm/mm, second partial %.3g µm/mm²\n", worst_slope,
              worst_second);
}

TEST(NormalExpression, ToothAndSideAreVariablesAndCopiesAreIndependent) {
  const NormalExpression e("tooth + 10*side");
  NormalExpression copy = e;
  EXPECT_DOUBLE_EQ(e.value_um(0, 0, 3, -1.0), -7.0);
  EXPECT_DOUBLE_EQ(copy.value_um(0, 0, 5, 1.0), 15.0);
  EXPECT_DOUBLE_EQ(e.value_um(0, 0, 3, 1.0), 13.0);
}

TEST(NormalExpression, BadExpressionsSayWhere) {
  EXPECT_THROW(NormalExpression("2*sin(L"), ExpressionError);
  try {
    NormalExpression bad("L + q");
    FAIL() << "unknown variable accepted";
  } catch (const ExpressionError& e) {
    EXPECT_EQ(e.position(), 4);
    EXPECT_NE(std::string(e.what()).find('q'), std::string::npos);
  }
}

}  // namespace
}  // namespace gearmc
