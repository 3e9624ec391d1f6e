// The statistics of a run at every scale: RelativeHistogram quantiles against the exact order
// statistics of the same values at three scales (sub-µm, tens of µm, mm) and for signed values;
// exact, order-independent merges; the small-sample rule; Freedman–Diaconis bins shared by two
// histograms; the mode on them; and the two cases found from outside the project (an ISO class
// 11 gear with a 1.5 mm stylus, whose per-flank maximum exceeded the old 50 µm histogram, and
// pure noise of σ 20 µm). Random values come from std::mt19937_64 with the seeds written at each
// test; the bounds checked are deterministic (no significance level) except where stated.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <fstream>
#include <limits>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "engine/run/monte_carlo.h"
#include "engine/scenario/scenario.h"
#include "engine/statistics/histogram_bins.h"
#include "engine/statistics/relative_histogram.h"
#include "engine/statistics/stats_json.h"

namespace gearmc {
namespace {

constexpr double kProbabilities[] = {0.001, 0.01, 0.25, 0.5, 0.75, 0.9, 0.95, 0.99, 0.9973, 0.999};

// The exact sample quantile x_(k), k = quantile_rank(p, n), of the values (Hyndman & Fan def. 1).
double exact_quantile(std::vector<double> values, double p) {
  std::sort(values.begin(), values.end());
  return values[quantile_rank(p, values.size()) - 1];
}

// The documented bound: x_(k) <= q <= x_(k) + 2^-12 |x_(k)|.
void expect_quantiles_within_resolution(const std::vector<double>& values) {
  RelativeHistogram h;
  for (double v : values) h.add(v);
  ASSERT_EQ(h.total(), values.size());
  for (double p : kProbabilities) {
    const double exact = exact_quantile(values, p);
    const double q = h.quantile(p);
    EXPECT_GE(q, exact) << "p " << p;
    EXPECT_LE(q - exact, RelativeHistogram::kRelativeResolution * std::abs(exact)) << "p " << p;
  }
  EXPECT_EQ(h.quantile(0.0), *std::min_element(values.begin(), values.end()));
  EXPECT_EQ(h.quantile(1.0), *std::max_element(values.begin(), values.end()));
}

TEST(RelativeHistogram, QuantilesAtSubMicrometreScale) {
  std::mt19937_64 rng(11);
  std::lognormal_distribution<double> law(std::log(0.05), 0.6);  // median 0.05 µm
  std::vector<double> v(20000);
  for (double& x : v) x = law(rng);
  expect_quantiles_within_resolution(v);
}

TEST(RelativeHistogram, QuantilesAtTensOfMicrometres) {
  std::mt19937_64 rng(12);
  std::gamma_distribution<double> law(3.0, 10.0);  // mean 30 µm
  std::vector<double> v(20000);
  for (double& x : v) x = law(rng);
  expect_quantiles_within_resolution(v);
}

TEST(RelativeHistogram, QuantilesAtMillimetreScale) {
  std::mt19937_64 rng(13);
  std::uniform_real_distribution<double> law(500.0, 10000.0);  // 0.5 to 10 mm in µm
  std::vector<double> v(20000);
  for (double& x : v) x = law(rng);
  expect_quantiles_within_resolution(v);
}

TEST(RelativeHistogram, QuantilesOfSignedValuesAndZeros) {
  std::mt19937_64 rng(14);
  std::normal_distribution<double> law(0.0, 20.0);
  std::vector<double> v(20000);
  for (double& x : v) x = law(rng);
  for (int i = 0; i < 500; ++i) v.push_back(0.0);
  expect_quantiles_within_resolution(v);
}

TEST(RelativeHistogram, PureNoiseOfSigma20GivesP9973NearThreeSigma) {
  // |e| with e ~ N(0, 20 µm): the 0.9973 quantile of |e| is 20 Φ^-1(0.99865) = 59.9996 µm. The
  // old fixed 0–50 µm histogram returned the maximum (79.4 µm in the outside report). Standard
  // error of the sample quantile: sqrt(p (1 - p) / n) / f(q) with f(q) = 2 φ(3) / 20 = 4.43e-4
  // per µm: 0.37 µm at n = 1e5; tolerance 4 se = 1.5 µm (two-sided level about 6e-5). Seed 15.
  std::mt19937_64 rng(15);
  std::normal_distribution<double> law(0.0, 20.0);
  RelativeHistogram h;
  std::vector<double> v(100000);
  for (double& x : v) {
    x = std::abs(law(rng));
    h.add(x);
  }
  EXPECT_NEAR(h.quantile(0.9973), 59.9996, 1.5);
  EXPECT_LT(h.quantile(0.9973), h.max());
  expect_quantiles_within_resolution(v);
}

TEST(RelativeHistogram, MergesAreExactAndOrderIndependent) {
  std::mt19937_64 rng(16);
  std::gamma_distribution<double> law(2.0, 0.7);
  RelativeHistogram whole, forward, backward;
  std::vector<RelativeHistogram> parts(7);
  for (int i = 0; i < 30000; ++i) {
    const double x = i % 11 == 0 ? -law(rng) : law(rng);
    whole.add(x);
    parts[static_cast<std::size_t>(i) % parts.size()].add(x);
  }
  for (const RelativeHistogram& p : parts) forward.merge(p);
  for (auto it = parts.rbegin(); it != parts.rend(); ++it) backward.merge(*it);
  EXPECT_TRUE(forward == whole);
  EXPECT_TRUE(backward == whole);
  for (double p : kProbabilities) EXPECT_EQ(forward.quantile(p), whole.quantile(p));
  RelativeHistogram copy = whole;
  copy.add(1.0);
  EXPECT_FALSE(copy == whole);
}

TEST(RelativeHistogram, SpecialValuesAndExtremes) {
  RelativeHistogram h;
  EXPECT_TRUE(std::isnan(h.quantile(0.5)));
  EXPECT_TRUE(std::isnan(h.min()));
  const double inf = std::numeric_limits<double>::infinity();
  for (double x : {-inf, -2.0, 0.0, 1e-300, 3.0, inf}) h.add(x);
  h.add(std::numeric_limits<double>::quiet_NaN());
  EXPECT_EQ(h.total(), 6u);
  EXPECT_EQ(h.invalid(), 1u);
  EXPECT_EQ(h.min(), -inf);
  EXPECT_EQ(h.max(), inf);
  // k = ceil(p 6): p 1/6 -> k 1 = -inf; p 0.5 -> k 3 = 0 (exact); p 0.99 -> k 6 = +inf.
  EXPECT_EQ(h.quantile(1.0 / 6.0), -inf);
  EXPECT_EQ(h.quantile(0.5), 0.0);
  EXPECT_EQ(h.quantile(0.99), inf);
  // k 2: -2 is the upper edge of its bucket of values (-2 - 2^-11 ... , -2]: returned exactly.
  EXPECT_EQ(h.quantile(2.0 / 6.0), -2.0);
  EXPECT_THROW(h.quantile(1.5), std::invalid_argument);
}

// Every finite non-zero double (random bit patterns over the whole range, subnormals and the
// largest finite values included, and -0.0, both infinities and NaN) lands in one bucket [a, b)
// of its magnitude with a <= |x| < b and the right sign, the extremes are exact, and a copy and
// an encode/decode round trip hold the same buckets. Seed 7 (any would do).
TEST(RelativeHistogram, EveryDoubleLandsInItsOwnBucket) {
  std::mt19937_64 rng(7);
  RelativeHistogram all;
  std::uint64_t finite = 0;
  for (int i = 0; i < 20000; ++i) {
    double x = std::bit_cast<double>(rng());
    if (i < 4) {
      x = std::array{-0.0, std::numeric_limits<double>::denorm_min(),
                     -std::numeric_limits<double>::max(), std::numeric_limits<double>::max()}[i];
    }
    if (!std::isfinite(x) || x == 0.0) continue;
    ++finite;
    all.add(x);
    RelativeHistogram one;
    one.add(x);
    int buckets = 0;
    one.for_each_bucket([&](double a, double b, std::uint64_t count) {
      ++buckets;
      EXPECT_EQ(count, 1u);
      if (x > 0) {
        EXPECT_TRUE(a <= x && x < b) << x;
      } else {
        EXPECT_TRUE(a < x && x <= b) << x;  // magnitudes [|b|, |a|): values (a, b]
      }
    });
    EXPECT_EQ(buckets, 1) << x;
    EXPECT_EQ(one.min(), x);
    EXPECT_EQ(one.max(), x);
  }
  const double inf = std::numeric_limits<double>::infinity();
  for (double x : {-0.0, inf, -inf, std::numeric_limits<double>::quiet_NaN()}) all.add(x);
  EXPECT_EQ(all.total(), finite + 3);
  EXPECT_EQ(all.invalid(), 1u);
  const RelativeHistogram copy = all;
  EXPECT_TRUE(copy == all);
  std::string bytes;
  all.encode(bytes);
  ByteReader reader(bytes);
  EXPECT_TRUE(RelativeHistogram::decode(reader) == all);
  std::uint64_t counted = 0;
  all.for_each_bucket([&](double, double, std::uint64_t count) { counted += count; });
  EXPECT_EQ(counted, finite + 3);
}

TEST(RelativeHistogram, CountAtLeastIsExactOnBucketEdges) {
  RelativeHistogram h;
  for (double x : {3.9, 3.9999, 4.0, 4.0001, 7.0}) h.add(x);
  // 4 is a power of two, hence a bucket edge: exactly the three values >= 4.
  const RelativeHistogram::CountBounds at4 = h.count_at_least(4.0);
  EXPECT_EQ(at4.at_least, 3u);
  EXPECT_EQ(at4.at_most, 3u);
  // 3.99995 shares a bucket (width 2^-11 in [2, 4)) with 3.9999: bounds 3 and 4.
  const RelativeHistogram::CountBounds mid = h.count_at_least(3.99995);
  EXPECT_EQ(mid.at_least, 3u);
  EXPECT_EQ(mid.at_most, 4u);
}

TEST(RelativeHistogram, MinimumCountForAQuantile) {
  // n (1 - p) >= 1: 1 / 0.0027 = 370.37 -> 371; 1 / 0.05 = 20 (20 * 0.05 = 1 exactly in double
  // arithmetic? 0.05 is not exact: 1 - 0.95 = 0.050000000000000044, so 20 * that >= 1).
  EXPECT_EQ(RelativeHistogram::min_count_for_quantile(0.9973), 371u);
  EXPECT_EQ(RelativeHistogram::min_count_for_quantile(0.95), 20u);
  EXPECT_EQ(RelativeHistogram::min_count_for_quantile(0.5), 2u);
  EXPECT_EQ(RelativeHistogram::min_count_for_quantile(0.0), 1u);
}

TEST(RelativeHistogram, ToHistogramPutsEveryValueWithinOneBucketOfItsBin) {
  std::mt19937_64 rng(17);
  std::uniform_real_distribution<double> law(0.0, 10.0);
  RelativeHistogram h;
  Histogram exact(0.0, 0.5, 20);
  for (int i = 0; i < 5000; ++i) {
    const double x = law(rng);
    h.add(x);
    exact.add(x);
  }
  const Histogram rebinned = h.to_histogram(0.0, 0.5, 20);
  EXPECT_EQ(rebinned.total(), exact.total());
  EXPECT_EQ(rebinned.min(), exact.min());
  EXPECT_EQ(rebinned.max(), exact.max());
  // Only values within a bucket width (<= 10 * 2^-12 = 0.0025) of an edge can move; with 5000
  // values spread over 10 µm about 5000 * 2 * 0.0025 / 10 * 19 edges / 2 ... at most a few.
  std::uint64_t moved = 0;
  for (std::size_t i = 0; i < 20; ++i) {
    moved += static_cast<std::uint64_t>(std::abs(static_cast<long long>(rebinned.count(i)) -
                                                 static_cast<long long>(exact.count(i))));
  }
  EXPECT_LE(moved, 2u * 60u);  // generous: expected about 2 * 5000 * 19 * 0.0012 / 10 = 23
}

TEST(HistogramBins, NiceWidths) {
  EXPECT_DOUBLE_EQ(nice_width_at_least(0.13), 0.2);
  EXPECT_DOUBLE_EQ(nice_width_at_least(0.2), 0.2);
  EXPECT_DOUBLE_EQ(nice_width_at_least(3.0), 5.0);
  EXPECT_DOUBLE_EQ(nice_width_at_least(6.0), 10.0);
  EXPECT_DOUBLE_EQ(nice_width_at_least(1e-4), 1e-4);
  // Nearest in ratio: 0.13 is 1.3x above 0.1 and 1.54x below 0.2; 0.16 is 1.6x and 1.25x.
  EXPECT_DOUBLE_EQ(nice_width_nearest(0.13), 0.1);
  EXPECT_DOUBLE_EQ(nice_width_nearest(0.16), 0.2);
  EXPECT_DOUBLE_EQ(nice_width_nearest(3.0), 2.0);   // 1.5x above 2, 1.67x below 5
  EXPECT_DOUBLE_EQ(nice_width_nearest(3.3), 5.0);   // 1.65x above 2, 1.52x below 5
  EXPECT_DOUBLE_EQ(nice_width_nearest(8.0), 10.0);  // 1.6x above 5, 1.25x below 10
  EXPECT_DOUBLE_EQ(nice_width_nearest(0.002), 0.002);
}

TEST(HistogramBins, FreedmanDiaconisOnNormalDataSharedByTwoHistograms) {
  // N(5, 1) and N(5.5, 1), 5000 each: the union has sd sqrt(1 + 0.25^2) = 1.03 and IQR about
  // 1.349 x 1.03 = 1.39; FD = 2 IQR n^(-1/3) = 2.78 / 21.54 = 0.129 -> the nearest nice width
  // 0.1 (0.129 is 1.29x above 0.1, 1.55x below 0.2; sampling noise moves the IQR ~2 %).
  std::mt19937_64 rng(18);
  std::normal_distribution<double> law(5.0, 1.0);
  RelativeHistogram left, right;
  for (int i = 0; i < 5000; ++i) left.add(law(rng)), right.add(law(rng) + 0.5);
  const HistogramBins bins = freedman_diaconis_bins({&left, &right});
  EXPECT_DOUBLE_EQ(bins.width, 0.1);
  EXPECT_FALSE(bins.clipped);
  EXPECT_LE(bins.lo, std::min(left.min(), right.min()));
  EXPECT_GT(bins.lo + bins.width * static_cast<double>(bins.count),
            std::max(left.max(), right.max()));
  const Histogram l = bins.histogram_of(left), r = bins.histogram_of(right);
  EXPECT_EQ(l.underflow() + l.overflow() + r.underflow() + r.overflow(), 0u);
  // The mode of N(5, 1) on 0.2 bins lies near 5 (the density is flat there: within 0.5).
  EXPECT_NEAR(histogram_mode(left, bins), 5.0, 0.5);
}

TEST(HistogramBins, LongTailIsClippedAndCountedNotDrawnAsOneBar) {
  // 10 000 values near 1 µm and one at 10 mm: 200 bins over the whole range would put every
  // ordinary value in the first bar.
  std::mt19937_64 rng(19);
  std::normal_distribution<double> law(1.0, 0.1);
  RelativeHistogram h;
  for (int i = 0; i < 10000; ++i) h.add(law(rng));
  h.add(10000.0);
  const HistogramBins bins = freedman_diaconis_bins({&h}, 200);
  EXPECT_TRUE(bins.clipped);
  EXPECT_LE(bins.count, 201u);
  EXPECT_LT(bins.width, 0.05);
  const Histogram shown = bins.histogram_of(h);
  EXPECT_GE(shown.overflow(), 1u);
  EXPECT_NEAR(histogram_mode(h, bins), 1.0, 0.1);
}

TEST(HistogramBins, ConstantDataAndSubMicrometreData) {
  RelativeHistogram constant;
  for (int i = 0; i < 100; ++i) constant.add(2.5);
  const HistogramBins b = freedman_diaconis_bins({&constant});
  EXPECT_GT(b.width, 0.0);
  EXPECT_NEAR(histogram_mode(constant, b), 2.5, b.width);
  // Sub-µm data get sub-µm bins (the mode is not stuck at a 0.1 µm grid).
  std::mt19937_64 rng(20);
  std::normal_distribution<double> law(0.02, 0.002);
  RelativeHistogram small;
  for (int i = 0; i < 10000; ++i) small.add(law(rng));
  const HistogramBins s = freedman_diaconis_bins({&small});
  EXPECT_LE(s.width, 0.001);
  EXPECT_NEAR(histogram_mode(small, s), 0.02, 0.002);
  // No values: one bin [0, 1), and no mode.
  const HistogramBins none = freedman_diaconis_bins({});
  EXPECT_EQ(none.count, 1u);
  EXPECT_TRUE(std::isnan(histogram_mode(RelativeHistogram{}, none)));
}

TEST(RunStatistics, IsoClass11GearWithAStylusOf1p5mmMatchesExactOrderStatistics) {
  // The case found from outside: P1's gear at ISO 1328-1 class 11 with R 1.5 mm gave p95 = p99.73
  // = max = 137.115 µm for the per-flank maximum, because values above 50 µm fell out of the old
  // histogram. Here every per-flank maximum of the run is collected from the gear outcomes and
  // the run's quantiles are checked against their exact order statistics.
  std::ifstream file(std::string(GEARMC_SOURCE_DIR) + "/scenarios/p1_iso_class8.yaml");
  std::stringstream text;
  text << file.rdbuf();
  std::string yaml = text.str();
  for (const auto& [from, to] :
       {std::pair{"grade: 8", "grade: 11"}, std::pair{"radius_mm: 0.5", "radius_mm: 1.5"}}) {
    const std::size_t at = yaml.find(from);
    ASSERT_NE(at, std::string::npos) << from;
    yaml.replace(at, std::string(from).size(), to);
  }
  Scenario s = parse_scenario(yaml, "p1_iso_class8.yaml with grade 11 and R 1.5 mm");
  s.gears = 20;
  const MonteCarloRun mc(s);
  std::vector<double> flank_max[2];
  RunOptions options;
  options.on_gear = [&](const GearOutcome& g) {
    for (int side = 0; side < 2; ++side) {
      flank_max[side].insert(flank_max[side].end(), g.flank_max[side].begin(),
                             g.flank_max[side].end());
    }
  };
  const RunResults r = mc.run(options);
  for (int side = 0; side < 2; ++side) {
    const std::vector<double>& v = flank_max[side];
    ASSERT_EQ(r.flank_max[side].histogram.total(), v.size());
    ASSERT_GE(v.size(), 371u);  // 20 gears x 24 flanks = 480: p99.73 is supported
    EXPECT_GT(*std::max_element(v.begin(), v.end()), 50.0);  // beyond the old histogram
    for (double p : {0.5, 0.95, 0.9973}) {
      const double exact = exact_quantile(v, p);
      const double q = *supported_quantile(r.flank_max[side].histogram, p);
      EXPECT_GE(q, exact) << "side " << side << " p " << p;
      EXPECT_LE(q - exact, RelativeHistogram::kRelativeResolution * exact)
          << "side " << side << " p " << p;
    }
    EXPECT_LT(r.flank_max[side].histogram.quantile(0.95), r.flank_max[side].moments.max());
  }
}

}  // namespace
}  // namespace gearmc
