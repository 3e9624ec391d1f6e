// The sweep's confidence bands and verdicts (engine/apps/sweep/sweep_bands.h), against values that
// do not come from the bootstrap code:
// - the percentile rule against Hyndman & Fan's type 7 written out by hand (R's default quantile);
// - the resampled gear indices: uniform over the gears (χ² test, significance 0.001, seed 7) and
//   a pure function of (seed, resample);
// - coverage on synthetic gears with a known statistic: 8 values per gear, each side's 4 sharing
//   an effect (correlation 0.5, as a gear's flanks share its eccentricity): the 95 % band of the
//   mean and of the 95 % quantile covers the true value in 95 % of 200 data sets (seeds 1–200;
//   accepted within [0.90, 0.99], a two-sided binomial test at about 0.005). A bootstrap of
//   single values instead of whole gears covers about 78 % (4 values per flank side share an
//   effect: design effect 1 + 3 · 0.5 = 2.5, 2Φ(1.96/√2.5) − 1) and must stay below 0.85;
// - the band of a mean against the cluster-robust normal interval mean ± 1.96 se computed here
//   from per-gear sums (the ratio estimator's variance; Cochran, "Sampling Techniques", 1977,
//   §6.13), within 10 % of its width;
// - a gear parameter's band (bias of F_α from a P1 run) against the same cluster-robust interval
//   of the run's own errors, computed here from the parameter samples;
// - the verdict rules, one case per branch.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numeric>
#include <random>
#include <string>
#include <vector>

#include "engine/apps/sweep/sweep_bands.h"
#include "engine/apps/sweep/sweep_report.h"
#include "engine/scenario/scenario.h"

namespace gearmc {
namespace {

TEST(SweepBands, PercentileBandIsHyndmanFanType7) {
  // x = 1..5 sorted from a shuffled input; type 7: h = (n − 1) p, x[⌊h⌋] + (h − ⌊h⌋)(x[⌊h⌋+1] −
  // x[⌊h⌋]). c = 0.5: p = 0.25 → h = 1 → 2; p = 0.75 → h = 3 → 4. c = 0.9: p = 0.05 → h = 0.2
  // → 1.2; p = 0.95 → h = 3.8 → 4.8.
  const std::vector<double> x = {4, 2, 5, 1, 3};
  const auto half = percentile_band(x, 0.5);
  ASSERT_TRUE(half);
  EXPECT_DOUBLE_EQ((*half)[0], 2.0);
  EXPECT_DOUBLE_EQ((*half)[1], 4.0);
  const auto ninety = percentile_band(x, 0.9);
  ASSERT_TRUE(ninety);
  EXPECT_NEAR((*ninety)[0], 1.2, 1e-12);
  EXPECT_NEAR((*ninety)[1], 4.8, 1e-12);
  EXPECT_FALSE(percentile_band({1.0}, 0.95));
  EXPECT_FALSE(percentile_band(x, 1.0));
}

TEST(SweepBands, ResampledGearsAreUniformAndReproducible) {
  constexpr int kGears = 10, kResamples = 2000;
  std::vector<double> counts(kGears, 0.0);
  for (int b = 0; b < kResamples; ++b) {
    for (int g : bootstrap_gears(7, b, kGears)) {
      ASSERT_GE(g, 0);
      ASSERT_LT(g, kGears);
      counts[static_cast<std::size_t>(g)] += 1.0;
    }
  }
  const double expected = static_cast<double>(kResamples);  // kResamples × kGears draws / kGears
  double chi2 = 0.0;
  for (double c : counts) chi2 += (c - expected) * (c - expected) / expected;
  // χ²(9) upper 0.001 point: 27.88 (NIST/SEMATECH e-Handbook, table 1.3.6.7.4).
  EXPECT_LT(chi2, 27.88);
  EXPECT_EQ(bootstrap_gears(7, 5, kGears), bootstrap_gears(7, 5, kGears));
  EXPECT_NE(bootstrap_gears(7, 5, kGears), bootstrap_gears(7, 6, kGears));
  EXPECT_NE(bootstrap_gears(7, 5, kGears), bootstrap_gears(8, 5, kGears));
}

// G gears of m/2 left values a_g + e_gi and m/2 right values b_g + e_gi, a_g, b_g, e_gi independent
// N(0, 1): values of one side of a gear correlate with ρ = 0.5; every value is N(0, 2).
GearValues synthetic_gears(unsigned seed, int gears, int per_gear) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> normal;
  GearValues g;
  for (int k = 0; k < gears; ++k) {
    const double a = normal(rng), b = normal(rng);
    std::vector<double> left, right;
    for (int i = 0; i < per_gear / 2; ++i) left.push_back(a + normal(rng));
    for (int i = 0; i < per_gear / 2; ++i) right.push_back(b + normal(rng));
    g.add_gear(left, right);
  }
  return g;
}

TEST(SweepBands, BandsOfWholeGearsCoverTheTrueMeanAndQuantile) {
  constexpr int kSets = 200, kGears = 100, kPerGear = 8;
  SweepStatistic mean{"delta_rcomp.point.mean", "point", "mean", ""};
  SweepStatistic p95{"delta_rcomp.point.p95", "point", "p95", ""};
  // True values: mean 0; the 95 % quantile of N(0, 2) is 1.644854 · √2.
  const double q95 = 1.6448536269514722 * std::sqrt(2.0);
  int covered_mean = 0, covered_q = 0;
  for (int set = 1; set <= kSets; ++set) {
    const GearValues g = synthetic_gears(static_cast<unsigned>(set), kGears, kPerGear);
    const auto bm = delta_rcomp_bands(mean, g, 0.95, 1000 + set, 400);
    const auto bq = delta_rcomp_bands(p95, g, 0.95, 1000 + set, 400);
    ASSERT_TRUE(bm[2].lower && bq[2].lower) << bm[2].note << bq[2].note;
    covered_mean += *bm[2].lower <= 0.0 && 0.0 <= *bm[2].upper;
    covered_q += *bq[2].lower <= q95 && q95 <= *bq[2].upper;
  }
  // The test's power: the same values with every value taken as a gear of its own (a bootstrap
  // blind to the gears) cover the mean far less often.
  int covered_naive = 0;
  for (int set = 1; set <= kSets; ++set) {
    const GearValues g = synthetic_gears(static_cast<unsigned>(set), kGears, kPerGear);
    GearValues single;
    for (int side = 0; side < 2; ++side) {
      for (double v : g.values[side]) {
        single.add_gear(side == 0 ? std::vector<double>{v} : std::vector<double>{},
                        side == 1 ? std::vector<double>{v} : std::vector<double>{});
      }
    }
    const auto b = delta_rcomp_bands(mean, single, 0.95, 1000 + set, 200);
    covered_naive += *b[2].lower <= 0.0 && 0.0 <= *b[2].upper;
  }
  std::printf("coverage of 200 sets: mean %d, p95 %d, values as gears %d\n", covered_mean,
              covered_q, covered_naive);
  EXPECT_LT(covered_naive, 170);
  EXPECT_GE(covered_mean, 180);  // 0.90 of 200
  EXPECT_LE(covered_mean, 198);  // 0.99 of 200
  EXPECT_GE(covered_q, 180);
  EXPECT_LE(covered_q, 198);
}

TEST(SweepBands, BandOfAMeanMatchesTheClusterRobustInterval) {
  const GearValues g = synthetic_gears(42, 200, 8);
  SweepStatistic mean{"delta_rcomp.point.mean", "point", "mean", ""};
  const auto band = delta_rcomp_bands(mean, g, 0.95, 3);
  ASSERT_TRUE(band[0].lower);
  // Left flanks: per gear n_g values with sum s_g; m = Σs/Σn; var(m) = G/(G−1) Σ(s_g − m
  // n_g)²/(Σn)².
  std::vector<double> s, n;
  std::uint64_t begin = 0;
  for (std::uint64_t end : g.end[0]) {
    s.push_back(std::accumulate(g.values[0].begin() + static_cast<std::ptrdiff_t>(begin),
                                g.values[0].begin() + static_cast<std::ptrdiff_t>(end), 0.0));
    n.push_back(static_cast<double>(end - begin));
    begin = end;
  }
  const double S = std::accumulate(s.begin(), s.end(), 0.0);
  const double N = std::accumulate(n.begin(), n.end(), 0.0);
  const double m = S / N;
  double ss = 0.0;
  for (std::size_t k = 0; k < s.size(); ++k) ss += (s[k] - m * n[k]) * (s[k] - m * n[k]);
  const double G = static_cast<double>(s.size());
  const double se = std::sqrt(G / (G - 1.0) * ss) / N;
  const double width = 2.0 * 1.959963984540054 * se;
  EXPECT_NEAR(*band[0].upper - *band[0].lower, width, 0.1 * width);
  EXPECT_NEAR(0.5 * (*band[0].upper + *band[0].lower), m, 0.1 * width);
}

TEST(SweepBands, CountsAndExtremesHaveNoBandButSayWhy) {
  const GearValues g = synthetic_gears(1, 20, 8);
  for (const std::string st : {"n", "min", "max"}) {
    const auto b = delta_rcomp_bands({"delta_rcomp.point." + st, "point", st, ""}, g, 0.95, 1);
    EXPECT_FALSE(b[2].lower) << st;
    EXPECT_FALSE(b[2].note.empty()) << st;
  }
  // A quantile that a resample cannot give (p99.73 of 160 values needs 371): no band, a note.
  const auto q = delta_rcomp_bands({"delta_rcomp.point.p99_73", "point", "p99_73", ""}, g, 0.95, 1);
  EXPECT_FALSE(q[2].lower);
  EXPECT_NE(q[2].note.find("resamples have no value"), std::string::npos) << q[2].note;
}

TEST(SweepBands, GearValuesTravelBitForBit) {
  const GearValues g = synthetic_gears(5, 7, 6);
  std::string bytes;
  g.encode(bytes);
  const GearValues back = GearValues::decode(bytes);
  for (int s = 0; s < 2; ++s) {
    EXPECT_EQ(back.values[s], g.values[s]);
    EXPECT_EQ(back.end[s], g.end[s]);
  }
}

TEST(SweepBands, VerdictFollowsTheBandAndTheLimit) {
  const SweepStatistic q{"delta_rcomp.point.p95", "point", "p95", ""};
  const SweepLimit at_most{4.0, std::nullopt}, at_least{std::nullopt, 1.0}, two{4.0, 1.0};
  const auto band = [](double lo, double hi) { return SweepBand{lo, hi, ""}; };
  EXPECT_EQ(sweep_verdict(at_most, q, 3.5, band(3.0, 3.9)), SweepVerdict::kMeets);
  EXPECT_EQ(sweep_verdict(at_most, q, 3.9, band(3.5, 4.1)), SweepVerdict::kUndecided);
  EXPECT_EQ(sweep_verdict(at_most, q, 4.5, band(4.1, 4.9)), SweepVerdict::kMisses);
  EXPECT_EQ(sweep_verdict(at_least, q, 1.5, band(1.1, 1.9)), SweepVerdict::kMeets);
  EXPECT_EQ(sweep_verdict(at_least, q, 0.9, band(0.5, 0.95)), SweepVerdict::kMisses);
  EXPECT_EQ(sweep_verdict(two, q, 2.0, band(1.5, 2.5)), SweepVerdict::kMeets);
  EXPECT_EQ(sweep_verdict(two, q, 1.0, band(0.8, 1.2)), SweepVerdict::kUndecided);
  EXPECT_EQ(sweep_verdict(two, q, 5.0, band(4.5, 5.5)), SweepVerdict::kMisses);
  // No band: undecided, except what more gears cannot change.
  EXPECT_EQ(sweep_verdict(at_most, q, 3.0, SweepBand{}), SweepVerdict::kUndecided);
  EXPECT_EQ(sweep_verdict(at_most, q, std::nullopt, SweepBand{}), SweepVerdict::kUndecided);
  const SweepStatistic max{"delta_rcomp.point.max", "point", "max", ""};
  const SweepStatistic min{"delta_rcomp.point.min", "point", "min", ""};
  const SweepStatistic n{"delta_rcomp.point.n", "point", "n", ""};
  EXPECT_EQ(sweep_verdict(at_most, max, 4.2, SweepBand{}), SweepVerdict::kMisses);
  EXPECT_EQ(sweep_verdict(at_most, max, 3.2, SweepBand{}), SweepVerdict::kUndecided);
  EXPECT_EQ(sweep_verdict(at_least, max, 1.2, SweepBand{}), SweepVerdict::kMeets);
  EXPECT_EQ(sweep_verdict(at_least, min, 0.5, SweepBand{}), SweepVerdict::kMisses);
  EXPECT_EQ(sweep_verdict(at_most, min, 0.5, SweepBand{}), SweepVerdict::kMeets);
  EXPECT_EQ(sweep_verdict(at_least, min, 1.5, SweepBand{}), SweepVerdict::kUndecided);
  EXPECT_EQ(sweep_verdict(at_most, n, 4.0, SweepBand{}), SweepVerdict::kMeets);
  EXPECT_EQ(sweep_verdict(at_most, n, 5.0, SweepBand{}), SweepVerdict::kMisses);
  EXPECT_EQ(two.text("µm"), "in [1, 4] µm");
  EXPECT_EQ(at_most.text(""), "≤ 4");
}

TEST(SweepBands, AParameterBandMatchesTheClusterRobustIntervalOfItsErrors) {
  // P1's parameter scenario, 60 gears: the band of the bias of F_α (left flanks) against
  // mean ± 1.96 se of the errors measured − true_dense grouped by gear, computed here.
  Scenario scenario = load_scenario_file(std::string(GEARMC_SOURCE_DIR) +
                                         "/scenarios/p1_reference_parameters.yaml");
  scenario.gears = 60;
  const MonteCarloRun mc(scenario);
  RunOptions options;
  options.threads = 2;
  const RunResults r = mc.run(options);
  ASSERT_TRUE(r.parameters);
  const SweepStatistic bias{"parameters.F_alpha.bias", "parameters", "bias", "F_alpha"};
  const auto band = parameter_bands(bias, mc, r, 0.95, scenario.seed);
  ASSERT_TRUE(band[0].lower) << band[0].note;
  const auto& items = r.parameters->values[static_cast<int>(GearParameter::kFalpha)][0];
  const std::size_t per_gear = items.size() / 60;
  ASSERT_EQ(per_gear * 60, items.size());
  std::vector<double> s;
  for (std::size_t g = 0; g < 60; ++g) {
    double sum = 0.0;
    for (std::size_t i = 0; i < per_gear; ++i) {
      const ParameterValue& v = items[g * per_gear + i];
      sum += v.measured - v.true_dense;
    }
    s.push_back(sum);
  }
  const double N = static_cast<double>(items.size());
  const double m = std::accumulate(s.begin(), s.end(), 0.0) / N;
  double ss = 0.0;
  const double n_g = static_cast<double>(per_gear);
  for (double x : s) ss += (x - m * n_g) * (x - m * n_g);
  const double se = std::sqrt(60.0 / 59.0 * ss) / N;
  const double width = 2.0 * 1.959963984540054 * se;
  EXPECT_NEAR(*band[0].upper - *band[0].lower, width, 0.15 * width);
  EXPECT_NEAR(0.5 * (*band[0].upper + *band[0].lower), m, 0.15 * width);
  // The estimate itself is the run report's bias.
  const auto value = sweep_parameter_values(bias, mc, r);
  ASSERT_TRUE(value[0].value);
  EXPECT_NEAR(*value[0].value, m, 1e-9);
}

}  // namespace
}  // namespace gearmc
