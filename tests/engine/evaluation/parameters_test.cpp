// The ISO 1328-1 parameter evaluation (engine/evaluation/gear_parameters.h) against analytic
// traces, pitch and runout patterns with known answers, and the conformity algebra
// (engine/statistics/conformity.h) against JCGM 106's example and a closed-form Gaussian case.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>
#include <vector>

#include "engine/evaluation/gear_parameters.h"
#include "engine/statistics/conformity.h"
#include "tests/support/p1_fixtures.h"

namespace gearmc {
namespace {

constexpr double kPi = std::numbers::pi;

std::vector<double> linspace(double a, double b, int n) {
  std::vector<double> x(n);
  for (int i = 0; i < n; ++i) x[i] = a + (b - a) * i / (n - 1);
  return x;
}

TEST(TraceEvaluation, PureSlopeGivesSlopeTimesRangeAndNoForm) {
  // d = s (x − a): the mean line is the trace itself, f_H = s · (b − a), f_f = 0, F = |f_H|.
  const double a = 12.0, b = 31.0, s = 0.3;  // mm, mm, µm/mm
  const auto x = linspace(a, b, 40);
  std::vector<double> d;
  for (double v : x) d.push_back(5.0 + s * (v - a));
  const auto r = evaluate_trace_over(x, d, a, b);
  ASSERT_TRUE(r);
  EXPECT_NEAR(r->slope_um, s * (b - a), 1e-12);
  EXPECT_NEAR(r->form_um, 0.0, 1e-12);
  EXPECT_NEAR(r->total_um, s * (b - a), 1e-12);
  EXPECT_NEAR(r->intercept_um, 5.0, 1e-12);
  EXPECT_EQ(r->samples, 40);
}

TEST(TraceEvaluation, OnePeriodSineHasTheKnownSlopeAndForm) {
  // d = A sin(2π t), t = (x − a)/(b − a). The continuous least-squares slope is
  // ∫(t − ½) A sin 2πt dt / ∫(t − ½)² dt = A(−1/2π)/(1/12) = −6A/π per range, so f_H = −6A/π
  // (checked independently by a 200001-point trapezoid least-squares fit in Python:
  // −1.9098593 for A = 1). The residual A sin 2πt + (6A/π)(t − ½) has its extremes at the ends,
  // ∓3A/π (its interior stationary values, cos 2πt = −3/π², are ±0.569A), so f_f = 6A/π; the
  // total band is max − min = 2A.
  const double A = 2.5, a = 20.0, b = 45.0;
  const auto x = linspace(a, b, 2001);
  std::vector<double> d;
  for (double v : x) d.push_back(A * std::sin(2 * kPi * (v - a) / (b - a)));
  const auto r = evaluate_trace_over(x, d, a, b);
  ASSERT_TRUE(r);
  // Trapezoid weights approximate the continuous line to O(h²): h = 1/2000 of the range.
  EXPECT_NEAR(r->slope_um, -6 * A / kPi, 1e-5);
  EXPECT_NEAR(r->form_um, 6 * A / kPi, 1e-5);
  EXPECT_NEAR(r->total_um, 2 * A, 1e-5);
}

TEST(TraceEvaluation, OnlyTheRangeCountsAndTheSlopeSpansTheWholeRange) {
  // Samples outside [a, b] carry a large step that must not enter; inside, a pure slope sampled
  // on [a + 1, b − 1] only: the slope deviation is still s · (b − a) (the mean line's values at
  // the range ends).
  const double a = 0.0, b = 10.0, s = -0.4;
  std::vector<double> x = {-2.0, -1.0}, d = {100.0, 100.0};
  for (double v : linspace(a + 1, b - 1, 9)) {
    x.push_back(v);
    d.push_back(s * v);
  }
  x.push_back(11.0);
  d.push_back(-50.0);
  const auto r = evaluate_trace_over(x, d, a, b);
  ASSERT_TRUE(r);
  EXPECT_EQ(r->samples, 9);
  EXPECT_NEAR(r->slope_um, s * (b - a), 1e-12);
  EXPECT_NEAR(r->form_um, 0.0, 1e-12);
  EXPECT_FALSE(evaluate_trace_over(x, d, 20.0, 30.0));  // no sample in the range: no value
}

TEST(Pitch, SinusoidalIndexErrorOf24Teeth) {
  // u_k = 10 sin(2πk/24) µm: F_p = max − min = 20 µm (k = 6, 18);
  // f_pt,k = 20 sin(π/24) cos(π(2k + 1)/24), largest at 2k + 1 = ±1: 20 sin(π/24) cos(π/24)
  // = 10 sin(π/12) = 2.58819 µm (also a direct Python evaluation of the differences).
  std::vector<double> u;
  for (int k = 0; k < 24; ++k) u.push_back(10.0 * std::sin(2 * kPi * k / 24));
  const PitchResult p = evaluate_pitch(u);
  EXPECT_NEAR(p.cumulative_um, 20.0, 1e-12);
  EXPECT_NEAR(p.single_max_abs_um, 2.588190451, 1e-9);
  ASSERT_EQ(p.single_um.size(), 24u);
  double sum = 0;
  for (double f : p.single_um) sum += f;
  EXPECT_NEAR(sum, 0.0, 1e-12);  // the pitches close the circle
}

TEST(Pitch, ArcPositionOfARotatedFlank) {
  // Rotating the nominal R flank of tooth 1 counter-clockwise by φ moves its point on the
  // reference circle along the old normal by (rotated − original)·n; the arc position must give
  // back r φ (the arc on the reference circle), for R with + and for L with −.
  const InvoluteGear gear = testing_support::p1_gear();
  const double r = gear.reference_diameter_mm() / 2, rb = gear.base_diameter_mm() / 2;
  const double L = std::sqrt(r * r - rb * rb), alpha = gear.pressure_angle_rad();
  const double phi = 1e-6;  // rad: 67 nm of arc, first order is exact to 1e-12 relative
  for (FlankSide side : {FlankSide::kRight, FlankSide::kLeft}) {
    const FlankPoint p = gear.flank_point(1, side, L, 10.0);
    const Eigen::Vector3d q(std::cos(phi) * p.point.x() - std::sin(phi) * p.point.y(),
                            std::sin(phi) * p.point.x() + std::cos(phi) * p.point.y(), p.point.z());
    // The rotated flank's normal deviation at p, to first order: its displacement along n.
    const double d_um = 1e3 * (q - p.point).dot(p.normal);
    EXPECT_NEAR(flank_arc_position_um(side, d_um, alpha), 1e3 * r * phi, 1e-6);
  }
}

TEST(Runout, EccentricityGivesTwiceItAndRotationOrThicknessNothing) {
  // A gear moved by e: every flank's normal deviation at a point is e·n, the ball of each
  // space moves by e, radial displacement e·e_k; with e along the bisector of space 0 and
  // z = 24 even, space 12 is opposite: F_r = 2|e| (ISO 10064-4: runout ≈ 2 × eccentricity).
  const InvoluteGear gear = testing_support::p1_gear();
  const EvaluationRanges ranges = evaluation_ranges(gear);
  const double Lc = 0.5 * (ranges.profile_start_mm + ranges.profile_end_mm);
  const double z = gear.face_width_mm() / 2;
  const auto contacts = ball_contacts(gear, Lc, z);
  ASSERT_EQ(static_cast<int>(contacts.size()), gear.teeth());
  const Eigen::Vector2d e = 7.0 * contacts[0].radial;  // µm
  std::vector<double> dr, dl;
  for (int k = 1; k <= gear.teeth(); ++k) {
    dr.push_back(e.dot(gear.flank_point(k, FlankSide::kRight, Lc, z).normal.head<2>()));
    dl.push_back(e.dot(gear.flank_point(k, FlankSide::kLeft, Lc, z).normal.head<2>()));
  }
  EXPECT_NEAR(runout_um(contacts, dr, dl), 14.0, 1e-9);
  // A rotation: R flanks +d, L flanks −d (the same arc): the balls turn, no radial change.
  std::vector<double> plus(gear.teeth(), 3.0), minus(gear.teeth(), -3.0);
  EXPECT_NEAR(runout_um(contacts, plus, minus), 0.0, 1e-9);
  // Thicker teeth (both flanks +d): every ball moves out alike, no runout.
  EXPECT_NEAR(runout_um(contacts, plus, plus), 0.0, 1e-9);
  // One space narrowed by d on both flanks: its ball rises by d / (n·e) with n·e the radial
  // component of the flank normals; every other ball stays, F_r = that rise.
  std::vector<double> zero(gear.teeth(), 0.0), dr1 = zero, dl1 = zero;
  dr1[0] = 2.0;
  dl1[1] = 2.0;
  const double ne = contacts[0].normal_right.dot(contacts[0].radial);
  EXPECT_NEAR(runout_um(contacts, dr1, dl1), 2.0 / ne, 1e-9);
}

TEST(Conformity, Jcgm106Section7Example) {
  // y = 13.6, u = 1.8, limits 12.5 and 16.3: Φ(1.5) − Φ(−0.6111) = 0.93319 − 0.27056 = 0.6626
  // (independent: the Gaussian CDF values from tables / Python's math.erf).
  EXPECT_NEAR(conformance_probability(13.6, 1.8, 12.5, 16.3), 0.6626, 5e-5);
  EXPECT_NEAR(conformance_probability(5.0, 0.0, std::nullopt, 6.0), 1.0, 0.0);
}

// n true values X ~ N(centre, σ²) and their measurements Y = X + E, E ~ N(0, u²) (std::mt19937_64
// seed 15).
void draw_measured(double centre, double sigma, double u, int n, std::vector<double>* x,
                   std::vector<double>* y) {
  std::mt19937_64 rng(15);
  std::normal_distribution<double> g(0.0, 1.0);
  x->resize(n);
  y->resize(n);
  for (int i = 0; i < n; ++i) {
    (*x)[i] = centre + sigma * g(rng);
    (*y)[i] = (*x)[i] + u * g(rng);
  }
}

// ∫_0^∞ φ_σ(a) Φ(−(a + g)/u) da: the false-accept rate at one limit with a guard band g, by the
// midpoint rule (20000 steps to 8σ; the tail beyond is < 1e-15).
double guarded_false_accept(double sigma, double u, double g) {
  double integral = 0.0;
  const double h = 8 * sigma / 20000;
  for (int i = 0; i < 20000; ++i) {
    const double a = (i + 0.5) * h;
    const double phi = std::exp(-0.5 * a * a / (sigma * sigma)) / (sigma * std::sqrt(2 * kPi));
    integral += h * phi * 0.5 * std::erfc((a + g) / (u * std::numbers::sqrt2));
  }
  return integral;
}

TEST(Conformity, SimpleRuleRatesMatchTheClosedFormGaussianCase) {
  // Population X ~ N(T, σ²) centred on the upper limit T, measured Y = X + E, E ~ N(0, u²),
  // accept Y <= T. With A = X − T and B = −(Y − T) jointly normal with correlation
  // ρ = −σ/√(σ² + u²), P(false accept) = P(A > 0, B >= 0) = 1/4 + arcsin(ρ)/(2π) (Sheppard's
  // orthant formula); σ = u gives 1/4 − 1/8 = 0.125, and false reject the same by symmetry.
  // 200000 draws, seed 15 (std::mt19937_64): standard error √(p(1 − p)/n) = 7.4e-4; bound 4
  // standard errors (two-sided significance 6e-5).
  const double T = 10.0, sigma = 2.0, u = 2.0;
  const int n = 200000;
  std::vector<double> x, y;
  draw_measured(T, sigma, u, n, &x, &y);
  const ToleranceLimits tol{std::nullopt, T};
  const DecisionRates r =
      decision_rates(x, y, tol, acceptance_limits(tol, DecisionRule::kSimple, 0));
  const double expected = 0.25 - std::asin(sigma / std::hypot(sigma, u)) / (2 * kPi);
  const double bound = 4 * std::sqrt(expected * (1 - expected) / n);
  EXPECT_NEAR(r.false_accept_rate(), expected, bound);
  EXPECT_NEAR(r.false_reject_rate(), expected, bound);
  // A guard band of U = 2u: accept Y <= T − 2u. Then a false accept needs E <= −(A + 2u) with
  // A > 0; P = ∫_0^∞ φ_σ(a) Φ(−(a + 2u)/u) da, a one-dimensional integral evaluated below by
  // the midpoint rule (20000 steps to 8σ; the tail beyond is < 1e-15).
  const DecisionRates gb =
      decision_rates(x, y, tol, acceptance_limits(tol, DecisionRule::kGuardBanded, 2 * u));
  const double integral = guarded_false_accept(sigma, u, 2 * u);
  EXPECT_NEAR(gb.false_accept_rate(), integral, 4 * std::sqrt(integral / n) + 1e-6);
  EXPECT_LT(gb.false_accept_rate(), r.false_accept_rate());
  EXPECT_GT(gb.false_reject_rate(), r.false_reject_rate());
}

// The guard band narrows the acceptance zone at both limits (ISO 14253-1 §5): a lower limit
// moves up by g, an upper limit down by g. Limits written by hand; then the mirror of the test
// above on a lower limit T_L (X ~ N(T_L, σ²), accept Y ≥ T_L + 2u): the same integral by
// symmetry, from the same draws reflected (x → 2 T_L − x keeps the law).
TEST(Conformity, GuardBandNarrowsALowerLimitUpwards) {
  const ToleranceLimits both{-3.0, 5.0};
  const ToleranceLimits a = acceptance_limits(both, DecisionRule::kGuardBanded, 0.5);
  EXPECT_EQ(*a.lower, -2.5);
  EXPECT_EQ(*a.upper, 4.5);
  const ToleranceLimits lower_only{2.0, std::nullopt};
  const ToleranceLimits b = acceptance_limits(lower_only, DecisionRule::kGuardBanded, 0.5);
  EXPECT_EQ(*b.lower, 2.5);
  EXPECT_FALSE(b.upper.has_value());

  const double TL = -10.0, sigma = 2.0, u = 2.0;
  const int n = 200000;
  std::vector<double> x, y;
  draw_measured(TL, sigma, u, n, &x, &y);
  const ToleranceLimits tol{TL, std::nullopt};
  const DecisionRates gb =
      decision_rates(x, y, tol, acceptance_limits(tol, DecisionRule::kGuardBanded, 2 * u));
  // P(X < T_L, Y >= T_L + 2u): the same integral as at an upper limit, by symmetry.
  const double integral = guarded_false_accept(sigma, u, 2 * u);
  EXPECT_NEAR(gb.false_accept_rate(), integral, 4 * std::sqrt(integral / n) + 1e-6);
}

TEST(Conformity, ShortestIntervalOfASample) {
  // JCGM 101 §7.7.2: M = 100 values 0 … 99 equally spaced, p = 0.95, q = 95: every window has
  // width 95, the first is taken: [0, 95]. A skewed sample (squares) puts it at the low end.
  std::vector<double> v, sq;
  for (int i = 0; i < 100; ++i) {
    v.push_back(i);
    sq.push_back(i * i);
  }
  const auto a = shortest_coverage_interval(v, 0.95);
  ASSERT_TRUE(a);
  EXPECT_EQ(a->lo, 0.0);
  EXPECT_EQ(a->hi, 95.0);
  const auto b = shortest_coverage_interval(sq, 0.95);
  ASSERT_TRUE(b);
  EXPECT_EQ(b->hi, 95.0 * 95.0);
  EXPECT_FALSE(shortest_coverage_interval(std::vector<double>(10, 1.0), 0.95));  // q = M
}

TEST(Conformity, SymmetricIntervalAndEmpiricalConformanceOfASample) {
  // JCGM 101 §7.7.1: M = 100 values 0 … 99, p = 0.95: q = 95, (M − q)/2 = 2.5 is not an
  // integer, r = floor((M − q + 1)/2) = 3: [y_(3), y_(98)] = [2, 97] (1-based order statistics)
  // — 2 values below, 2 above. M = 1000 values 0 … 999: r = 25, [y_(25), y_(975)] = [24, 974].
  std::vector<double> v, w;
  for (int i = 0; i < 100; ++i) v.push_back(i);
  for (int i = 0; i < 1000; ++i) w.push_back(i);
  const auto a = symmetric_coverage_interval(v, 0.95);
  ASSERT_TRUE(a);
  EXPECT_EQ(a->lo, 2.0);
  EXPECT_EQ(a->hi, 97.0);
  const auto b = symmetric_coverage_interval(w, 0.95);
  ASSERT_TRUE(b);
  EXPECT_EQ(b->lo, 24.0);
  EXPECT_EQ(b->hi, 974.0);
  EXPECT_FALSE(symmetric_coverage_interval(std::vector<double>(10, 1.0), 0.95));
  // Errors 0 … 99 (µm) and a reading y = 150 against T_U = 100: the true value y − e conforms for
  // e ≥ 50, 50 of the 100 errors; with T_L = 60 also e ≤ 90: 41 of them (50 … 90). Counted by
  // hand.
  EXPECT_DOUBLE_EQ(empirical_conformance_probability(v, 150.0, std::nullopt, 100.0), 0.50);
  EXPECT_DOUBLE_EQ(empirical_conformance_probability(v, 150.0, 60.0, 100.0), 0.41);
  EXPECT_DOUBLE_EQ(empirical_conformance_probability(v, 0.0, std::nullopt, 100.0), 1.0);
  EXPECT_TRUE(std::isnan(empirical_conformance_probability({}, 0.0, std::nullopt, 1.0)));
  // Unequal guard bands: the lower limit moves up by its band, the upper down by its own.
  const ToleranceLimits a2 = acceptance_limits({-3.0, 5.0}, DecisionRule::kGuardBanded, 0.25, 1.5);
  EXPECT_EQ(*a2.lower, -2.75);
  EXPECT_EQ(*a2.upper, 3.5);
  EXPECT_EQ(*acceptance_limits({-3.0, 5.0}, DecisionRule::kSimple, 0.25, 1.5).upper, 5.0);
}

// The guard band from a skewed error law keeps the specific risk at the acceptance limit at
// 2.5 % (JCGM 106 §8.3), where a band of U = 2·√(u² + b²) does not. Errors E = 3 − X, X
// exponential of mean 3 (E: mean 0, u = 3, the long lower tail of a reading that misses high
// values), 400 000 draws (std::mt19937_64, seed 21). The band at the upper limit is
// −e_lo of the symmetric 95 % interval; an item measured at T_U − g has a true value
// T_U − g − E beyond T_U when E < −g: by construction 2.5 % of the errors (±2 binomial standard
// errors). With the band U = 6 the same risk is P(E < −6) = P(X > 9) = e⁻³ = 5.0 %.
TEST(Conformity, AGuardBandFromTheSymmetricIntervalHoldsTheSpecificRiskOfASkewedLaw) {
  std::mt19937_64 rng(21);
  std::exponential_distribution<double> x(1.0 / 3.0);
  const int n = 400000;
  std::vector<double> e(n);
  for (double& v : e) v = 3.0 - x(rng);
  std::sort(e.begin(), e.end());
  const auto interval = symmetric_coverage_interval(e, 0.95);
  ASSERT_TRUE(interval);
  const double g = -interval->lo;
  // Exponential quantile: E_lo = 3 − 3 ln(1/0.025) = 3 − 11.07 = −8.07 (independent, closed form).
  EXPECT_NEAR(g, 3.0 * std::log(40.0) - 3.0, 0.15);
  const double beyond = 1.0 - empirical_conformance_probability(e, 10.0 - g, std::nullopt, 10.0);
  EXPECT_NEAR(beyond, 0.025, 2 * std::sqrt(0.025 * 0.975 / n) + 1.0 / n);
  const double beyond_u =
      1.0 - empirical_conformance_probability(e, 10.0 - 6.0, std::nullopt, 10.0);
  EXPECT_NEAR(beyond_u, std::exp(-3.0), 4 * std::sqrt(0.05 * 0.95 / n));
}

}  // namespace
}  // namespace gearmc
