// The Monte Carlo side of `gearmc uncertainty` (JCGM 101:2008):
//  * the numerical tolerance of §7.9.2 (u = 0.00035 at 2 digits: δ = 5e-6, the clause's own
//    example form; u = 2.0 at 2 digits: δ = 0.05 as in §9.2), the block size of §7.9.4 b)
//    (p = 0.9973: ceil(100/0.0027) = 37038) and the interval rules of §7.7.2 on small arrays;
//  * JCGM 101 §9.2 (Y = X1 + X2 + X3 + X4): normal inputs, exact Y ~ N(0, 4) and 95 % interval
//    ±1.959964·2; rectangular R(−√3, √3) inputs, exact Irwin–Hall 95 % limits ±3.879407
//    (computed by tests/bench/uncertainty_reference.py from the piecewise-cubic CDF; the GUF
//    gives ±3.92);
//  * JCGM 101 §9.3 (mass calibration) against an independent NumPy run with 10^7 trials
//    (tests/bench/uncertainty_reference.py, PCG64 seed 20261122: u = 0.075497 mg, symmetric
//    95 % [1.084461, 1.383605] mg, shortest [1.084440, 1.383582] mg, endpoint standard errors
//    0.00007 mg), not the printed [1.0834, 1.3825] of JCGM 101 Table 6, which lies ~15
//    standard errors of that run away;
//  * correlated normal inputs: u(a + b) = √7 for u 1 and 2, r = 0.5;
//  * the adaptive stop: recomputed from the block values, the rule holds at the last block
//    and failed at the one before;
//  * a builtin model from the registry.
// Tolerances: 4 Monte-Carlo standard errors (estimate σ/√M; u σ√((κ−1)/(4M)) with κ the
// sample kurtosis; a quantile √(p(1−p)/M)/f(q) with the exact density f) plus the reference's
// own uncertainty (half a unit of its last digit, or 4 of its standard errors). With seeds 1
// (§9.2 normal), 2 (§9.2 rectangular), 3 (§9.3), 4 (correlated), a false failure by chance has
// probability below 1e-4 per check; the runs are deterministic, so a pass stays a pass.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>

#include "core/random_stream.h"
#include "core/special_functions.h"
#include "engine/apps/uncertainty/mcm.h"
#include "engine/apps/uncertainty/model.h"

namespace gearmc::uncertainty {
namespace {

UncertaintyModel load(const std::string& name) {
  return load_uncertainty_model(std::string(GEARMC_SOURCE_DIR) + "/scenarios/uncertainty/" + name);
}

McmResult fixed_run(const UncertaintyModel& m, std::uint64_t M, std::uint64_t seed) {
  McmOptions o;
  o.trials = M;
  o.seed = seed;
  o.coverage_probability = 0.95;
  return run_mcm(m, o);
}

double kurtosis(const std::vector<double>& v) {
  double mean = 0;
  for (double x : v) mean += x;
  mean /= double(v.size());
  double m2 = 0, m4 = 0;
  for (double x : v) {
    const double d = (x - mean) * (x - mean);
    m2 += d;
    m4 += d * d;
  }
  m2 /= double(v.size());
  m4 /= double(v.size());
  return m4 / (m2 * m2);
}

// 4 standard errors of the estimate, of u and of a p-quantile at density f.
double se_mean(const McmOutput& o) { return o.u / std::sqrt(double(o.sorted.size())); }
double se_u(const McmOutput& o) {
  return o.u * std::sqrt((kurtosis(o.sorted) - 1) / (4.0 * double(o.sorted.size())));
}
double se_quantile(double p, double f, std::size_t M) {
  return std::sqrt(p * (1 - p) / static_cast<double>(M)) / f;
}

TEST(UncertaintyMcm, NumericalToleranceBlockSizeAndIntervals) {
  EXPECT_DOUBLE_EQ(numerical_tolerance(0.00035, 2), 5e-6);
  EXPECT_DOUBLE_EQ(numerical_tolerance(2.0, 2), 0.05);
  EXPECT_DOUBLE_EQ(numerical_tolerance(2.0, 1), 0.5);
  EXPECT_DOUBLE_EQ(numerical_tolerance(0.0539, 2), 0.0005);
  EXPECT_DOUBLE_EQ(numerical_tolerance(0.0996, 2), 0.005);  // rounds to 0.10: c = 10, l = −2
  EXPECT_EQ(adaptive_block_size(0.95), 10000u);
  EXPECT_EQ(adaptive_block_size(0.9973), 37038u);
  EXPECT_EQ(adaptive_block_size(0.999), 100000u);
  // M = 20, p = 0.9: q = 18, r = 1: [y_(1), y_(19)]. The shortest of the two windows
  // [y_(r), y_(r+18)], r = 1, 2: widths 24 and 18.5.
  std::vector<double> y;
  for (int i = 1; i <= 20; ++i) y.push_back(i);
  y[19] = 20.5;
  y[0] = -5;
  EXPECT_EQ(coverage_count(20, 0.9), 18u);
  EXPECT_DOUBLE_EQ(symmetric_interval(y, 0.9).lo, -5);
  EXPECT_DOUBLE_EQ(symmetric_interval(y, 0.9).hi, 19);
  EXPECT_DOUBLE_EQ(shortest_interval(y, 0.9).lo, 2);
  EXPECT_DOUBLE_EQ(shortest_interval(y, 0.9).hi, 20.5);
  // M = 21, p = 0.9: pM = 18.9 → q = 19; (M − q)/2 = 1: [y_(1), y_(20)].
  y.push_back(30);
  EXPECT_EQ(coverage_count(21, 0.9), 19u);
  EXPECT_DOUBLE_EQ(symmetric_interval(y, 0.9).hi, 20.5);
  // M = 5, p = 0.95: q = round(4.75) = 5 = M, no interval: an internal error (exit 4), not a
  // read past the end (AddressSanitizer found the R-Test's axes passing 5 values left of 2000
  // trials; they now check first, r_test_evaluation.cpp).
  const std::vector<double> five = {1, 2, 3, 4, 5};
  EXPECT_EQ(coverage_count(5, 0.95), 5u);
  EXPECT_EXIT(symmetric_interval(five, 0.95), testing::ExitedWithCode(4),
              "fewer values than the coverage needs");
}

// The smallest M with a coverage interval, against a brute-force scan of the definition
// (JCGM 101 §7.7: q = pM rounded, the interval needs 1 ≤ q ≤ M − 1), and the message that names
// it: it once said "at least 21" for p = 0.95 (accepting 11) and "at least 3" when refusing
// 2000 trials at p = 0.0001 (which needs 5000).
TEST(UncertaintyMcm, SmallestTrialsAndTheRefusalSayTheSameNumber) {
  for (const double p : {0.0001, 0.01, 0.3, 0.5, 0.9, 0.95, 0.9973, 0.99999}) {
    std::uint64_t brute = 1;
    while (!(std::llround(p * static_cast<double>(brute)) >= 1 &&
             static_cast<std::uint64_t>(std::llround(p * static_cast<double>(brute))) < brute)) {
      ++brute;
    }
    EXPECT_EQ(smallest_trials(p), brute) << p;
    EXPECT_NO_THROW(check_trials(brute, 1, p, {}, "--trials")) << p;
    try {
      check_trials(brute - 1, 1, p, {}, "--trials");
      ADD_FAILURE() << "accepted " << brute - 1 << " at p " << p;
    } catch (const InputError& e) {
      EXPECT_NE(
          std::string(e.what()).find("expected at least " + std::to_string(brute) + " trials"),
          std::string::npos)
          << e.what();
    }
  }
  EXPECT_EQ(smallest_trials(0.95), 11u);
  EXPECT_EQ(smallest_trials(0.0001), 5000u);
}

TEST(UncertaintyMcm, RadixSortEqualsStdSort) {
  // Mixed signs, zeros, subnormals, huge and tiny magnitudes, repeats; compared value by value
  // with std::sort (which orders −0 and +0 as equal, so zeros are compared by value).
  std::vector<double> v = {3.5, -0.0, 0.0, -1e-310, 1e-310, -1e300, 1e300, 2.0, -2.0, 2.0, -7.25};
  for (int i = 0; i < 100000; ++i) {
    TrialStream s(9, std::uint64_t(i), 0);
    v.push_back(s.normal() * std::pow(10.0, 20 * s.uniform() - 10));
  }
  std::vector<double> expected = v;
  std::sort(expected.begin(), expected.end());
  sort_values(v);
  ASSERT_EQ(v.size(), expected.size());
  for (std::size_t i = 0; i < v.size(); ++i) ASSERT_EQ(v[i], expected[i]) << i;
}

TEST(UncertaintyMcm, AdditiveNormalJcgm101Section922) {
  const McmResult r = fixed_run(load("additive_normal.yaml"), 200000, 1);
  const McmOutput& o = r.outputs[0];
  EXPECT_NEAR(o.estimate, 0.0, 4 * se_mean(o));
  EXPECT_NEAR(o.u, 2.0, 4 * se_u(o));
  const double q = 1.959963984540054 * 2;
  const double f = std::exp(-0.5 * 1.959963984540054 * 1.959963984540054) /
                   (std::sqrt(2 * std::numbers::pi) * 2);
  const double tol = 4 * se_quantile(0.025, f, o.sorted.size());
  EXPECT_NEAR(o.symmetric.lo, -q, tol);
  EXPECT_NEAR(o.symmetric.hi, q, tol);
  EXPECT_NEAR(o.shortest.lo, -q, tol);
  EXPECT_NEAR(o.shortest.hi, q, tol);
}

// Irwin–Hall density of the sum S of four U(0,1) at s (for Y = 2√3 (S − 2): f_Y = f_S/(2√3)).
double irwin_hall_pdf(double s) {
  double f = 0;
  for (int k = 0; k <= 4; ++k) {
    const double c[] = {1, 4, 6, 4, 1};
    if (s > k) f += (k % 2 ? -1 : 1) * c[k] * std::pow(s - k, 3);
  }
  return f / 6.0;
}

TEST(UncertaintyMcm, AdditiveRectangularJcgm101Section923) {
  const McmResult r = fixed_run(load("additive_rectangular.yaml"), 200000, 2);
  const McmOutput& o = r.outputs[0];
  EXPECT_NEAR(o.estimate, 0.0, 4 * se_mean(o));
  EXPECT_NEAR(o.u, 2.0, 4 * se_u(o));
  const double q = 3.879407;  // tests/bench/uncertainty_reference.py, to 1e-6
  const double s = q / (2 * std::sqrt(3.0)) + 2;
  const double f = irwin_hall_pdf(s) / (2 * std::sqrt(3.0));
  const double tol = 4 * se_quantile(0.025, f, o.sorted.size()) + 5e-7;
  EXPECT_NEAR(o.symmetric.lo, -q, tol);
  EXPECT_NEAR(o.symmetric.hi, q, tol);
  EXPECT_NEAR(o.shortest.lo, -q, tol);
  EXPECT_NEAR(o.shortest.hi, q, tol);
  // The GUF's ±3.92 lies outside: the difference is real, not noise.
  EXPECT_GT(3.919928 - o.symmetric.hi, tol / 2);
}

TEST(UncertaintyMcm, MassCalibrationJcgm101Section93) {
  const McmResult r = fixed_run(load("mass_calibration.yaml"), 200000, 3);
  const McmOutput& o = r.outputs[0];
  // NumPy reference (10^7 trials): y 1.234012, u 0.075497, density at the endpoints 0.7416/mg.
  const double ref_se_q = 0.00007;
  EXPECT_NEAR(o.estimate, 1.234012, 4 * se_mean(o) + 4 * 0.0755 / std::sqrt(1e7));
  EXPECT_NEAR(o.u, 0.075497, 4 * se_u(o) + 4 * 0.0755 / std::sqrt(2e7));
  const double tol = 4 * se_quantile(0.025, 0.7416, o.sorted.size()) + 4 * ref_se_q;
  EXPECT_NEAR(o.symmetric.lo, 1.084461, tol);
  EXPECT_NEAR(o.symmetric.hi, 1.383605, tol);
  EXPECT_NEAR(o.shortest.lo, 1.084440, tol);
  EXPECT_NEAR(o.shortest.hi, 1.383582, tol);
  const Validation v =
      validate_gum(1.2340, 1.959964 * 0.053852, 0.053852, o.symmetric, 2, o.sorted);
  EXPECT_DOUBLE_EQ(v.delta, 0.0005);
  EXPECT_FALSE(v.validated);  // JCGM 101 §9.3: the GUF interval is not validated
  EXPECT_FALSE(v.undecided);  // d ≈ 0.044 is ~100 of its standard errors beyond δ = 0.0005
}

// The endpoints' Monte-Carlo standard error (mcm.h, from the order statistics) against the
// asymptotic formula √(a(1 − a)/M)/f(x_a) of a sample quantile with the exact density: standard
// normal values (M = 10⁵, seed 11), a = 0.025 and 0.975 (f = φ(1.959964) = 0.058445) and 0.5
// (f = 0.398942); within 15 % (the estimator's own spread is about 1/√(2k), k ≈ 49 … 158 ranks:
// 10 % and less).
TEST(UncertaintyMcm, QuantileStandardErrorMatchesTheAsymptoticFormula) {
  RandomStream rng(11, 0, StreamPurpose::kDiagnoseNull, 77);  // any fixed stream
  constexpr std::size_t kM = 100000;
  std::vector<double> v(kM);
  for (double& x : v) x = rng.normal();
  std::sort(v.begin(), v.end());
  const struct {
    double a, x, f;
  } cases[] = {{0.025, -1.959964, 0.058445}, {0.975, 1.959964, 0.058445}, {0.5, 0.0, 0.398942}};
  for (const auto& c : cases) {
    const double exact = std::sqrt(c.a * (1 - c.a) / kM) / c.f;
    const double value = v[static_cast<std::size_t>(c.a * kM)];
    EXPECT_NEAR(quantile_standard_error(v, value), exact, 0.15 * exact) << c.a;
  }
}

// JCGM 101 §9.2.3 (four rectangular inputs, adaptive at ndig 2): the GUM interval ±3.9199 is
// within δ = 0.05 of the exact Irwin–Hall ±3.8794 (d = 0.0405), but the MCM's endpoints carry a
// standard error of about 0.015 at its ~10⁵ trials (Irwin–Hall density 0.033 at the endpoint), so
// a verdict on d alone flipped with the seed (NOT validated for 22 of 60 seeds). With the MCM's
// own error (mcm.h: d ± 3s against δ) a false rejection needs d − 3s > δ, about 3.6 standard
// errors beyond the exact d: for seeds 1 … 60 at most 1 of the 120 ends is allowed (expected
// 0.02 if s were exact; at 2s instead of 3s this test fails with 3), and an undecided verdict
// names an M larger than the run's own.
TEST(UncertaintyMcm, ValidationOfTheRectangularCaseIsNeverAWrongVerdict) {
  const UncertaintyModel m = load("additive_rectangular.yaml");
  const double U = 1.959964 * 2.0;  // GUM: u = 2, k for ν = ∞
  int rejected = 0, undecided = 0;
  for (std::uint64_t seed = 1; seed <= 60; ++seed) {
    McmOptions o;
    o.seed = seed;
    o.coverage_probability = 0.95;
    o.significant_digits = 2;
    const McmResult r = run_mcm(m, o);
    const McmOutput& out = r.outputs[0];
    const Validation v = validate_gum(0.0, U, 2.0, out.symmetric, 2, out.sorted);
    EXPECT_DOUBLE_EQ(v.delta, 0.05);
    rejected += !v.validated && !v.undecided ? 1 : 0;
    if (v.undecided) {
      ++undecided;
      EXPECT_GT(v.trials_to_decide, static_cast<double>(r.trials)) << seed;
    }
  }
  EXPECT_LE(rejected, 1);
  EXPECT_GT(undecided, 0);  // the case is close to δ: the verdict says so
}

TEST(UncertaintyMcm, CorrelatedNormalInputs) {
  const UncertaintyModel m = parse_uncertainty_model(R"M(
inputs:
  a: {normal: [1, 1]}
  b: {normal: [2, 2]}
  c: {uniform: [0, 1]}
correlations: [[a, b, 0.5]]
outputs:
  s: "a + b"
  c2: "c"
)M",
                                                     "t.yaml");
  const McmResult r = fixed_run(m, 100000, 4);
  EXPECT_NEAR(r.outputs[0].u, std::sqrt(7.0), 4 * se_u(r.outputs[0]));
  EXPECT_NEAR(r.outputs[0].estimate, 3.0, 4 * se_mean(r.outputs[0]));
  EXPECT_NEAR(r.outputs[1].u, 1 / std::sqrt(12.0), 4 * se_u(r.outputs[1]));
}

// Correlated inputs of other laws (the Gaussian copula, laws.h): a uniform and a triangular
// input with r = 0.6. The MCM's u(a + b) must be the one the stated r gives,
// √(u_a² + u_b² + 2 r u_a u_b) (u_a = 1/√3 of R(−1, 1), u_b = 2/√6 of T(−2, 0, 2)), within 4
// standard errors of u (seed 8, 10⁵ trials), and the marginal of a stays uniform: the KS distance
// of its values to R(−1, 1) below 1.63/√M (Kolmogorov, α = 0.01).
TEST(UncertaintyMcm, CorrelatedInputsOfOtherLawsHaveTheStatedCorrelation) {
  const UncertaintyModel m = parse_uncertainty_model(R"M(
inputs:
  a: {uniform: [-1, 1]}
  b: {triangular: [-2, 2]}
correlations: [[a, b, 0.6]]
outputs:
  s: "a + b"
  a_alone: "a"
)M",
                                                     "t.yaml");
  const McmResult r = fixed_run(m, 100000, 8);
  const double ua = 1.0 / std::sqrt(3.0), ub = 2.0 / std::sqrt(6.0);
  EXPECT_NEAR(r.outputs[0].u, std::sqrt(ua * ua + ub * ub + 2 * 0.6 * ua * ub),
              4 * se_u(r.outputs[0]));
  // The uncorrelated value is 4 standard errors away at least: the test can fail.
  EXPECT_GT(
      std::abs(std::sqrt(ua * ua + ub * ub + 2 * 0.6 * ua * ub) - std::sqrt(ua * ua + ub * ub)),
      8 * se_u(r.outputs[0]));
  const std::vector<double>& v = r.outputs[1].sorted;
  double ks = 0.0;
  for (std::size_t i = 0; i < v.size(); ++i) {
    const double f = std::clamp((v[i] + 1.0) / 2.0, 0.0, 1.0);
    const double n = static_cast<double>(v.size());
    ks = std::max({ks, std::abs(f - static_cast<double>(i) / n),
                   std::abs(f - static_cast<double>(i + 1) / n)});
  }
  EXPECT_LT(ks, 1.63 / std::sqrt(static_cast<double>(v.size())));
}

// The adaptive stop's quantities after the first h blocks of `r` (JCGM 101 §7.9.4): δ from the
// pooled standard deviation of the h B values (h), and 2 s of the average of each block value
// (g), computed here from the blocks' own values.
struct StopRule {
  double delta = 0.0;
  double two_s[6] = {};  // estimate, u, symmetric lo, hi, shortest lo, hi
  bool holds() const {
    for (double t : two_s) {
      if (!(t <= delta)) return false;
    }
    return true;
  }
};

StopRule stop_rule(const McmResult& r, int h, int significant_digits) {
  StopRule rule;
  const double B = double(r.block_size);
  double mean = 0;
  for (int b = 0; b < h; ++b) mean += r.block_values[b].estimate[0] / h;
  double ss = 0;
  for (int b = 0; b < h; ++b) {
    const auto& v = r.block_values[b];
    ss += (B - 1) * v.u[0] * v.u[0] + B * (v.estimate[0] - mean) * (v.estimate[0] - mean);
  }
  rule.delta = numerical_tolerance(std::sqrt(ss / (h * B - 1)), significant_digits);
  const auto two_s = [&](auto get) {
    double m1 = 0;
    for (int b = 0; b < h; ++b) m1 += get(r.block_values[b]) / h;
    double s2 = 0;
    for (int b = 0; b < h; ++b) s2 += std::pow(get(r.block_values[b]) - m1, 2);
    return 2 * std::sqrt(s2 / (h * (h - 1.0)));
  };
  rule.two_s[0] = two_s([](const BlockValues& v) { return v.estimate[0]; });
  rule.two_s[1] = two_s([](const BlockValues& v) { return v.u[0]; });
  rule.two_s[2] = two_s([](const BlockValues& v) { return v.lo[0]; });
  rule.two_s[3] = two_s([](const BlockValues& v) { return v.hi[0]; });
  rule.two_s[4] = two_s([](const BlockValues& v) { return v.short_lo[0]; });
  rule.two_s[5] = two_s([](const BlockValues& v) { return v.short_hi[0]; });
  return rule;
}

TEST(UncertaintyMcm, AdaptiveStopsByItsRule) {
  const UncertaintyModel m = load("additive_normal.yaml");
  McmOptions o;
  o.seed = 5;
  o.coverage_probability = 0.95;
  o.significant_digits = 2;
  const McmResult r = run_mcm(m, o);
  ASSERT_TRUE(r.adaptive);
  ASSERT_TRUE(r.converged);
  ASSERT_GE(r.blocks, 2);
  EXPECT_EQ(r.block_size, 10000u);
  EXPECT_EQ(r.trials, r.block_size * std::uint64_t(r.blocks));
  EXPECT_EQ(r.outputs[0].sorted.size(), r.trials);  // final results from all trials
  // 2 s of the average of block values (JCGM 101 §7.9.4 g) for the first h blocks, and δ from
  // the pooled standard deviation of those h blocks (§7.9.4 h): the rule holds at the stop and
  // not a block earlier.
  EXPECT_TRUE(stop_rule(r, r.blocks, 2).holds());
  if (r.blocks > 2) {
    EXPECT_FALSE(stop_rule(r, r.blocks - 1, 2).holds());
  }
  EXPECT_EQ(r.outputs[0].delta, 0.05);
  // The reported criteria are these values, with their factor 2 (the rule is decided on them;
  // in additive_normal.yaml the interval endpoints, not the estimate, decide the stop for every
  // seed 1 … 40 tried, so the estimate's factor is checked here, on the value itself).
  EXPECT_NEAR(r.outputs[0].two_s_estimate, stop_rule(r, r.blocks, 2).two_s[0], 1e-15);
  EXPECT_NEAR(r.outputs[0].two_s_u, stop_rule(r, r.blocks, 2).two_s[1], 1e-15);
}

TEST(UncertaintyMcm, BuiltinModelFromTheRegistry) {
  const UncertaintyModel m = parse_uncertainty_model(R"M(
inputs:
  a: {uniform: [0, 1]}
  b: {constant: 2}
builtin: {model: sum}
)M",
                                                     "t.yaml");
  ASSERT_EQ(m.outputs.size(), 1u);
  EXPECT_EQ(m.outputs[0].name, "Y");
  const McmResult r = fixed_run(m, 20000, 6);
  EXPECT_NEAR(r.outputs[0].estimate, 2.5, 4 * se_mean(r.outputs[0]));
  EXPECT_GE(r.outputs[0].sorted.front(), 2.0);
  EXPECT_LE(r.outputs[0].sorted.back(), 3.0);
}

}  // namespace
}  // namespace gearmc::uncertainty
