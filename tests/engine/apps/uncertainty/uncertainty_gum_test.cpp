// The GUM side of `gearmc uncertainty` (JCGM 100:2008) against hand computations:
//  * sensitivities by central differences against the analytic derivatives of
//    x1 x2² + sin(x3) (relative 1e-8: the step rule's truncation error is ~1e-10 here);
//  * the law of propagation with a correlation (u² = u1² + u2² + 2 r u1 u2 for X1 + X2);
//  * Welch–Satterthwaite and k against a hand computation: contributions 0.3 (ν 4) and 0.4
//    (ν 10): ν_eff = 0.5⁴ / (0.3⁴/4 + 0.4⁴/10) = 13.6314…, k = t_0.975(13) = 2.1604 (GUM
//    Table G.2 prints 2.16 for ν = 13; 2.160369 from standard t tables);
//  * the 5.1.2 higher-order term for a product of independent normals, exact:
//    u² = x2² u1² + x1² u2² + u1² u2²;
//  * JCGM 101 §9.3 (mass calibration): GUF y = 1.2340 mg, u = 0.0539 mg; with the higher-order
//    terms u = 0.0750 mg (JCGM 101 Table 6), to half a unit of the last printed digit.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "engine/apps/uncertainty/gum.h"
#include "engine/apps/uncertainty/model.h"

namespace gearmc::uncertainty {
namespace {

UncertaintyModel model(const std::string& text) { return parse_uncertainty_model(text, "t.yaml"); }

TEST(UncertaintyGum, SensitivitiesMatchAnalyticDerivatives) {
  const UncertaintyModel m = model(R"M(
inputs:
  x1: {normal: [2, 0.1]}
  x2: {uniform: [2.8, 3.2]}
  x3: {triangular: [0.4, 0.6]}
outputs:
  y: "x1*x2^2 + sin(x3)"
)M");
  const GumResult r = evaluate_gum(m);
  const GumOutput& o = r.outputs[0];
  EXPECT_NEAR(o.estimate, 2 * 9 + std::sin(0.5), 1e-14);
  EXPECT_NEAR(o.sensitivities[0], 9.0, 9e-8);            // x2²
  EXPECT_NEAR(o.sensitivities[1], 12.0, 12e-8);          // 2 x1 x2
  EXPECT_NEAR(o.sensitivities[2], std::cos(0.5), 1e-8);  // cos x3
  const double u2 = 0.4 / std::sqrt(12.0), u3 = 0.2 / std::sqrt(24.0);
  EXPECT_NEAR(
      o.u, std::sqrt(std::pow(9 * 0.1, 2) + std::pow(12 * u2, 2) + std::pow(std::cos(0.5) * u3, 2)),
      1e-8);
  EXPECT_NEAR(o.contributions[1], 12 * u2, 1e-8);
}

TEST(UncertaintyGum, CorrelatedInputs) {
  const UncertaintyModel m = model(R"M(
inputs:
  a: {normal: [1, 1]}
  b: {normal: [2, 2]}
correlations: [[a, b, 0.5]]
outputs:
  s: "a + b"
  d: "a - b"
)M");
  const GumResult r = evaluate_gum(m);
  EXPECT_NEAR(r.outputs[0].u, std::sqrt(1 + 4 + 2 * 0.5 * 2), 1e-9);
  EXPECT_NEAR(r.outputs[1].u, std::sqrt(1 + 4 - 2 * 0.5 * 2), 1e-9);
}

TEST(UncertaintyGum, WelchSatterthwaiteByHand) {
  const UncertaintyModel m = model(R"M(
inputs:
  a: {student_t: [0, 0.3, 4]}
  b: {normal: [0, 0.2], dof: 10}
outputs:
  y: "a + 2*b"
)M");
  const GumResult r = evaluate_gum(m);
  const GumOutput& o = r.outputs[0];
  EXPECT_NEAR(o.u, 0.5, 1e-9);
  const double nu = std::pow(0.5, 4) / (std::pow(0.3, 4) / 4 + std::pow(0.4, 4) / 10);
  EXPECT_NEAR(o.nu_eff, nu, 1e-6);
  EXPECT_NEAR(nu, 13.6314, 1e-4);
  EXPECT_NEAR(o.k, 2.160369, 1e-6);
  EXPECT_NEAR(o.U, 2.160369 * 0.5, 1e-6);
  EXPECT_TRUE(std::isinf(welch_satterthwaite(1.0, {0.5, 0.5}, {INFINITY, INFINITY})));
}

TEST(UncertaintyGum, SecondOrderTermOfAProduct) {
  const UncertaintyModel m = model(R"M(
inputs:
  x1: {normal: [2, 0.5]}
  x2: {normal: [3, 0.4]}
outputs:
  y: "x1*x2"
settings: {second_order: true}
)M");
  // A copy: the result is a temporary (a reference into it dangles; found by scripts/test
  // --sanitize).
  const GumOutput o = evaluate_gum(m).outputs[0];
  EXPECT_NEAR(o.u_first_order, std::sqrt(9 * 0.25 + 4 * 0.16), 1e-8);
  EXPECT_NEAR(o.u, std::sqrt(9 * 0.25 + 4 * 0.16 + 0.25 * 0.16), 1e-8);
}

// Every first-order sensitivity zero (issue 29: "inf, 1.960" with no word): y = x² at x = 0 with
// x ~ N(0, 1) — the law of propagation would give u = 0; the 5.1.2 term gives u² = (1/2)(f'')² u⁴
// = 2, which is exact: x² is then χ² with 1 degree of freedom, variance 2. A second output with
// a first-order term keeps its first-order u (second order not requested), a constant output keeps
// u = 0 without a word, and the warning names the flat output.
TEST(UncertaintyGum, AFlatFirstOrderTakesTheHigherOrderTerms) {
  const UncertaintyModel m = model(R"M(
inputs:
  x: {normal: [0, 1]}
outputs:
  y: "x^2"
  z: "x^2 + 3*x"
  c: "5 + 0*x"
)M");
  const GumResult r = evaluate_gum(m);
  const GumOutput& y = r.outputs[0];
  EXPECT_TRUE(y.first_order_vanishes);
  EXPECT_EQ(y.u_first_order, 0.0);
  EXPECT_NEAR(y.u, std::sqrt(2.0), 1e-6);
  EXPECT_NEAR(y.k, 1.959964, 1e-6);
  const GumOutput& z = r.outputs[1];
  EXPECT_FALSE(z.first_order_vanishes);
  EXPECT_NEAR(z.u, 3.0, 1e-8);  // first order only: |dz/dx| u = 3
  // An output that does not depend on x at all: u = 0 is right, no word.
  EXPECT_FALSE(r.outputs[2].first_order_vanishes);
  EXPECT_EQ(r.outputs[2].u, 0.0);
  ASSERT_EQ(r.warnings.size(), 1u);
  EXPECT_NE(r.warnings[0].find("every first-order sensitivity of y is zero"), std::string::npos)
      << r.warnings[0];
  EXPECT_NE(r.warnings[0].find("ν_eff is not defined"), std::string::npos) << r.warnings[0];
}

TEST(UncertaintyGum, MassCalibrationJcgm101Section93) {
  UncertaintyModel m = load_uncertainty_model(std::string(GEARMC_SOURCE_DIR) +
                                              "/scenarios/uncertainty/mass_calibration.yaml");
  GumOutput o = evaluate_gum(m).outputs[0];
  EXPECT_NEAR(o.estimate, 1.2340, 0.00005);
  EXPECT_NEAR(o.u, 0.0539, 0.00005);
  EXPECT_NEAR(o.k, 1.959964, 1e-6);
  // Sensitivity to rho_a is (m_Rc + dm_Rc)(1/rho_W − 1/rho_R) = 0 at the estimates.
  EXPECT_NEAR(o.sensitivities[2], 0.0, 1e-6);
  m.settings.second_order = true;
  o = evaluate_gum(m).outputs[0];
  EXPECT_NEAR(o.u, 0.0750, 0.00005);
}

}  // namespace
}  // namespace gearmc::uncertainty
