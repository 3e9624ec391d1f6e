// Tests of the diagnosis's false-positive budget (docs/diagnosis.md, "Error budget"): the min-P
// combination of the χ² and KS gap tests (linear_model.h min_p_combined_p_value) against closed
// forms, its level on exchangeable samples, and the verdict of whole diagnoses on null residuals
// (independent N(0, σ²) at the points of P1's master plan, diagnose_residuals) — how often it
// reports a gap, against the binomial bound of its level. Seeds are fixed (std::mt19937_64 seeds
// 11 and 23, readings simulation seed 1, null-simulation seed = the dataset's number), so every
// assertion is deterministic.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include "engine/apps/diagnose/diagnosis.h"
#include "engine/apps/diagnose/linear_model.h"
#include "engine/effects/effect_config.h"
#include "engine/run/simulate.h"

namespace gearmc {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// P(X ≤ k) for X ~ Binomial(n, p), summed from the pmf C(n, j) p^j (1 − p)^(n − j) (log-gamma).
double binomial_cdf(int k, int n, double p) {
  double sum = 0.0;
  for (int j = 0; j <= k; ++j) {
    sum += std::exp(std::lgamma(n + 1.0) - std::lgamma(j + 1.0) - std::lgamma(n - j + 1.0) +
                    j * std::log(p) + (n - j) * std::log1p(-p));
  }
  return sum;
}
// The smallest k with P(X ≤ k) ≥ q, and the largest k with P(X < k) ≤ 1 − q (for q near 1:
// the upper and lower ends of a central interval).
int binomial_upper(int n, double p, double q) {
  int k = 0;
  while (binomial_cdf(k, n, p) < q) ++k;
  return k;
}
int binomial_lower(int n, double p, double q) {
  int k = 0;
  while (binomial_cdf(k, n, p) <= 1.0 - q) ++k;
  return k;
}

// Samples 0 … K (0 is the data) with statistic values `values`, as one ResampledTest.
ResampledTest test_of(const std::vector<double>& values, double gate = -kInf) {
  return {values.front(), std::vector<double>(values.begin() + 1, values.end()), gate};
}

// --- The combination against closed forms ------------------------------------------------------

TEST(DiagnoseMinP, TwoIdenticalTestsCostNothingTwoOpposedOnesCostBonferroni) {
  // K = 99 replicates: 100 samples with distinct values v(i); the data is the one ranked c-th
  // from the top of test A. Closed forms (exact, from the counting definition):
  //  - B = A: each sample's two p-values are equal, m(i) = p_A(i), so the combined p is the
  //    marginal one, c / 100;
  //  - B = −A: m(i) = min(rank from the top, rank from the bottom) / 100, so #{m ≤ c/100} = 2c
  //    (c ≤ 50): the combined p is 2c / 100, exactly Bonferroni's factor 2.
  const int samples = 100;
  for (int c : {1, 2, 5, 50}) {
    std::vector<double> a(samples);
    // The data first with value 100 − c + 1 (the c-th largest of 1 … 100), the rest in any order.
    a[0] = samples - c + 1;
    for (int v = 1, at = 1; v <= samples; ++v) {
      if (v != samples - c + 1) a[at++] = v;
    }
    std::vector<double> minus_a(a);
    for (double& v : minus_a) v = -v;
    EXPECT_DOUBLE_EQ(empirical_p_value(a[0], {a.begin() + 1, a.end()}), c / 100.0);
    EXPECT_DOUBLE_EQ(min_p_combined_p_value({test_of(a), test_of(a)}), c / 100.0) << c;
    EXPECT_DOUBLE_EQ(min_p_combined_p_value({test_of(a), test_of(minus_a)}), 2.0 * c / 100.0) << c;
    // One test alone: the combination is its own empirical p-value.
    EXPECT_DOUBLE_EQ(min_p_combined_p_value({test_of(a)}), c / 100.0) << c;
  }
}

TEST(DiagnoseMinP, AGateAppliesToTheDataAndToEveryReplicateAlike) {
  // Values 1 … 100, the data 100 (the top of A) and B = −A. The gate 100.5 on A: nobody passes,
  // so A cannot reject anywhere and the combination is B's own p-value for the data, 100/100 = 1.
  // The gate 99.5: only the data passes A, m(data) = 1/100; of the replicates only B's top (A's
  // value 1) has m = 1/100, so the combined p is 2/100. Without a gate: also 2/100 (c = 1 above),
  // and with the gate 50.5 (replicates 51 … 99 pass A too, but with larger p-values): 2/100.
  std::vector<double> a(100);
  a[0] = 100;
  for (int v = 1; v < 100; ++v) a[v] = v;
  std::vector<double> minus_a(a);
  for (double& v : minus_a) v = -v;
  EXPECT_DOUBLE_EQ(min_p_combined_p_value({test_of(a, 100.5), test_of(minus_a)}), 1.0);
  EXPECT_DOUBLE_EQ(min_p_combined_p_value({test_of(a, 99.5), test_of(minus_a)}), 0.02);
  EXPECT_DOUBLE_EQ(min_p_combined_p_value({test_of(a, 50.5), test_of(minus_a)}), 0.02);
  // The data A's 3rd (value 98; replicates 1 … 97, 99, 100), B = −A: ungated, 6 samples have
  // m ≤ 3/100 (A's top 3, B's top 3): 6/100. With B gated at −0.5 (every B value is ≤ −1, so B
  // can reject nowhere, the data included) the family is A alone: 3/100.
  std::vector<double> third(100);
  third[0] = 98;
  for (int v = 1, at = 1; v <= 100; ++v) {
    if (v != 98) third[at++] = v;
  }
  std::vector<double> minus_third(third);
  for (double& v : minus_third) v = -v;
  EXPECT_DOUBLE_EQ(min_p_combined_p_value({test_of(third), test_of(minus_third)}), 0.06);
  EXPECT_DOUBLE_EQ(min_p_combined_p_value({test_of(third), test_of(minus_third, -0.5)}), 0.03);
}

TEST(DiagnoseMinP, NoReplicatesOrNoStatisticIsNotAPValue) {
  EXPECT_TRUE(std::isnan(min_p_combined_p_value({})));
  EXPECT_TRUE(std::isnan(min_p_combined_p_value({{1.0, {}}})));
  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_TRUE(std::isnan(min_p_combined_p_value({{nan, {1.0, 2.0}}, {nan, {1.0, 2.0}}})));
  // Replicates of different lengths are not one family.
  EXPECT_TRUE(std::isnan(min_p_combined_p_value({{3.0, {1.0, 2.0}}, {3.0, {1.0}}})));
  // A NaN replicate cannot reject (p 1); the data's p counts only the finite values ≥ it.
  EXPECT_DOUBLE_EQ(min_p_combined_p_value({{3.0, {nan, 1.0, 2.0}}}), 0.25);
}

TEST(DiagnoseMinP, ItsLevelIsAlphaUpToTheMonteCarloResolution) {
  // 20 000 families of K + 1 = 201 exchangeable samples, two independent N(0, 1) statistics each
  // (std::mt19937_64 seed 11). At α = 0.01 the test rejects when the combined p < α, i.e. when
  // at most 2 samples have m ≤ m(data): exactly 2/201 = 0.995 % by exchangeability. Each test
  // alone at α, either rejecting, would be 1 − (1 − 2/201)² = 1.98 %. The count is checked against
  // the central 99.9 % interval of Binomial(20 000, 2/201) (0.05 % on each side).
  std::mt19937_64 rng(11);
  std::normal_distribution<double> normal;
  const int families = 20000, samples = 201;
  int combined = 0, either = 0;
  std::vector<double> a(samples), b(samples);
  for (int f = 0; f < families; ++f) {
    for (int i = 0; i < samples; ++i) {
      a[i] = normal(rng);
      b[i] = normal(rng);
    }
    const ResampledTest ta = test_of(a), tb = test_of(b);
    combined += min_p_combined_p_value({ta, tb}) < 0.01 ? 1 : 0;
    either += (empirical_p_value(ta.observed, ta.null_values) < 0.01 ||
               empirical_p_value(tb.observed, tb.null_values) < 0.01)
                  ? 1
                  : 0;
  }
  const double level = 2.0 / 201.0;
  EXPECT_GE(combined, binomial_lower(families, level, 0.9995)) << combined;
  EXPECT_LE(combined, binomial_upper(families, level, 0.9995)) << combined;
  // The union of the two marginal tests is outside that interval: this test tells them apart.
  EXPECT_GT(either, binomial_upper(families, level, 0.9995)) << either;
  RecordProperty("combined", combined);
  RecordProperty("either", either);
}

// --- Whole diagnoses on null residuals ---------------------------------------------------------

// P1's master plan on tooth 1 (2 flanks × 10 × 5 = 100 points) with the contexts the
// candidates' columns are made from, the model's noise floor σ 0.3 µm with its law.
struct NullDesign {
  Residuals residuals;
  NoiseFloor noise;
};
NullDesign null_design() {
  Scenario model = reference_scenario();
  model.effects = std::make_shared<const EffectChain>(
      parse_effects(parse_yaml_document("noise: {sigma_um: 0.3}\n", "effects.yaml")));
  SimulateOptions o;
  o.master = true;
  model.seed = 1;
  const Residuals all = compute_residuals(model, simulate_readings(model, o).readings);
  NullDesign d;
  d.residuals = all;
  d.residuals.points.clear();
  for (const ResidualPoint& p : all.points) {
    if (p.tooth == 1) d.residuals.points.push_back(p);
  }
  d.noise = estimate_noise_floor(model, d.residuals);
  return d;
}

TEST(DiagnoseErrorBudget, WithoutNullSimulationsTheTablePValuesAreCombinedByBonferroni) {
  // K = 0 (--null-replicates 0): the χ² law's and Kolmogorov's table p-values, combined as
  // min(1, 2 min(p_χ², p_KS)), p_χ² counting only at an excess RMS ≥ 0.25 σ; at the numerical
  // floor the family is χ² alone (factor 1). Residuals N(0, σ²) scaled by 1.5 (a clear excess:
  // χ² rejects) and by 1 (null), std::mt19937_64 seed 5.
  const NullDesign design = null_design();
  std::mt19937_64 rng(5);
  std::normal_distribution<double> normal(0.0, design.noise.sigma_um);
  Residuals r = design.residuals;
  std::vector<double> draws;
  for (std::size_t k = 0; k < r.points.size(); ++k) draws.push_back(normal(rng));
  DiagnoseOptions options;
  options.selection.null_replicates = 0;
  options.fit_empirical = false;
  for (double scale : {1.0, 1.5}) {
    for (std::size_t k = 0; k < r.points.size(); ++k) r.points[k].residual_um = scale * draws[k];
    for (bool floor : {false, true}) {
      NoiseFloor noise = design.noise;
      noise.at_numerical_floor = floor;
      const Diagnosis d = diagnose_residuals(r, noise, options);
      ASSERT_EQ(d.null_replicates, 0);
      const GapStatistics& g = d.gap_before;
      ASSERT_TRUE(std::isfinite(g.chi2_p) && std::isfinite(g.ks_p));
      const double p_chi2 = g.excess_rms_um >= 0.25 * noise.sigma_um ? g.chi2_p : 1.0;
      const double expected = floor ? p_chi2 : std::min(1.0, 2.0 * std::min(p_chi2, g.ks_p));
      EXPECT_NEAR(g.combined_p, expected, 1e-15 * (1.0 + expected)) << scale << " " << floor;
      if (scale > 1.0) {
        EXPECT_LT(g.combined_p, 0.01) << floor;
      }
    }
  }
}

TEST(DiagnoseErrorBudget, TheVerdictOnNullResidualsKeepsItsLevel) {
  // 1 000 null datasets: the 100 points' residuals replaced by independent N(0, 0.3²) µm draws
  // (std::mt19937_64 seed 23), each diagnosed (diagnose_residuals) at α = 0.05 with K = 100 null
  // replicates, null seed = the dataset's number. α = 0.05 and K = 100 rather than the defaults
  // 0.01 and 200 so that 1 000 datasets (a few seconds) resolve the level; the code path is the
  // same. The gap test alone rejects when at most 5 of the 101 samples have m ≤ m(data):
  // 5/101 = 4.95 % exactly (exchangeability). The whole verdict adds the selection and the
  // point-law stage, whose null rates the ΔBIC ≤ −10 gate holds far below α (docs/diagnosis.md:
  // at most 1.5·10⁻³ for the selection here), so:
  //  - the gap test's rejections lie in the central 99.9 % interval of Binomial(1000, 5/101);
  //  - datasets with a gap (any stage) ≤ the 99.95 % quantile of Binomial(1000, α);
  //  - the rule before (χ² or KS, each at α) rejects more often than that bound on the same
  //    datasets, so this test would have failed on it.
  const NullDesign design = null_design();
  ASSERT_EQ(design.residuals.points.size(), 100u);
  ASSERT_EQ(spelling(design.noise.source), "model");
  const double sigma = design.noise.sigma_um;
  ASSERT_NEAR(sigma, 0.3, 1e-12);
  std::mt19937_64 rng(23);
  std::normal_distribution<double> normal(0.0, sigma);
  DiagnoseOptions options;
  options.selection.alpha = 0.05;
  options.selection.null_replicates = 100;
  options.fit_empirical = false;
  const int datasets = 1000;
  int gap_test = 0, verdict = 0, before_rule = 0;
  Residuals r = design.residuals;
  for (int k = 0; k < datasets; ++k) {
    for (ResidualPoint& p : r.points) p.residual_um = normal(rng);
    options.selection.seed = static_cast<std::uint64_t>(k + 1);
    const Diagnosis d = diagnose_residuals(r, design.noise, options);
    ASSERT_EQ(d.null_replicates, 100);
    const GapStatistics& g = d.gap_before;
    gap_test += g.combined_p < 0.05 ? 1 : 0;
    verdict += d.gap_detected ? 1 : 0;
    EXPECT_EQ(d.gap_detected, d.named_effect_text() != "none");
    before_rule += ((g.chi2_p < 0.05 && g.excess_rms_um >= 0.25 * sigma) || g.ks_p < 0.05) ? 1 : 0;
  }
  const double level = 5.0 / 101.0;
  EXPECT_GE(gap_test, binomial_lower(datasets, level, 0.9995)) << gap_test;
  EXPECT_LE(gap_test, binomial_upper(datasets, level, 0.9995)) << gap_test;
  const int bound = binomial_upper(datasets, 0.05, 0.9995);
  EXPECT_LE(verdict, bound) << verdict << " of " << datasets;
  EXPECT_GT(before_rule, bound) << before_rule << " of " << datasets;
  RecordProperty("gap_test", gap_test);
  RecordProperty("verdict", verdict);
  RecordProperty("before_rule", before_rule);
}

}  // namespace
}  // namespace gearmc
