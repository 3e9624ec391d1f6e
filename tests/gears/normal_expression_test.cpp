// Deterministic normal deviations written as muParser expressions (interface.md).
#include "gears/normal_expression.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

namespace gearmc {
namespace {

TEST(NormalExpression, EvaluatesTheInterfaceExample) {
  // interface.md's example: 2 sin(2 pi L / 5) + 0.1 (z - 39.445).
  const NormalExpression e("2*sin(2*_pi*L/5) + 0.1*(z-39.445)");
  const double L = 30.3, z = 12.0;
  EXPECT_NEAR(e.value_um(L, z, 1, 1.0),
              2 * std::sin(2 * std::numbers::pi * L / 5) + 0.1 * (z - 39.445),
              1e-9);  // muParser's bytecode reorders the arithmetic: agreement to ~1e-11
  EXPECT_NEAR(e.d_dL(L, z, 1, 1.0),
              2 * 2 * std::numbers::pi / 5 * std::cos(2 * std::numbers::pi * L / 5), 1e-6);
  EXPECT_NEAR(e.d_dz(L, z, 1, 1.0), 0.1, 1e-9);
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
