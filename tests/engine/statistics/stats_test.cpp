// Streaming statistics against independent answers:
//  * RunningStats: textbook data sets with known mean / sample std, a cancellation-prone shift,
//    a two-pass long-double reference, bitwise determinism for one split and merge order, and
//    1e-12 relative agreement between different splits;
//  * Histogram: bin membership exactly at the edges, exact merges, quantiles against the exact
//    sorted-sample quantile (Hyndman & Fan definition 1): x_(k) <= q <= x_(k) + w, the mode at
//    a display width, rebinning, CSV, and the STATS JSON object;
//  * distribution fits: the incomplete gamma function against closed forms, pdf/cdf/quantile
//    consistency, and recovery of known parameters from 20 000 draws of each law within five
//    asymptotic standard errors (from the Fisher information, sources cited per law), with the
//    true law ranked first by AIC.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include "engine/statistics/distribution_fit.h"
#include "engine/statistics/histogram.h"
#include "engine/statistics/histogram_bins.h"
#include "engine/statistics/relative_histogram.h"
#include "engine/statistics/running_stats.h"
#include "engine/statistics/stats_json.h"

namespace gearmc {
namespace {

double relative_difference(double a, double b) {
  return std::abs(a - b) / std::max(std::abs(a), std::abs(b));
}

std::vector<double> gamma_sample(std::size_t n, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::gamma_distribution<double> law(4.0, 0.4);
  std::vector<double> v(n);
  for (double& x : v) x = law(rng);
  return v;
}

// ---------------------------------------------------------------------------------------------
// RunningStats

TEST(RunningStats, TextbookDataSet) {
  // {2, 4, 4, 4, 5, 5, 7, 9}: mean 5, sum of squared deviations 32 (the standard-deviation
  // example of most statistics texts), so the sample variance is 32 / 7.
  RunningStats s;
  for (double x : {2.0, 4.0, 4.0, 4.0, 5.0, 5.0, 7.0, 9.0}) s.add(x);
  EXPECT_EQ(s.count(), 8u);
  EXPECT_DOUBLE_EQ(s.mean(), 5.0);
  EXPECT_DOUBLE_EQ(s.variance(), 32.0 / 7.0);
  EXPECT_DOUBLE_EQ(s.stddev(), std::sqrt(32.0 / 7.0));
  EXPECT_EQ(s.min(), 2.0);
  EXPECT_EQ(s.max(), 9.0);
}

TEST(RunningStats, LargeOffsetDoesNotCancel) {
  // 1e9 + {4, 7, 13, 16}: deviations -6, -3, 3, 6, so M2 = 90 and the sample variance is 30
  // exactly; the naive sum-of-squares formula loses all digits here (Chan, Golub & LeVeque 1983,
  // "Algorithms for computing the sample variance: analysis and recommendations").
  RunningStats a, b, whole;
  for (double x : {4.0, 7.0}) a.add(1e9 + x);
  for (double x : {13.0, 16.0}) b.add(1e9 + x);
  for (double x : {4.0, 7.0, 13.0, 16.0}) whole.add(1e9 + x);
  a.merge(b);
  EXPECT_NEAR(whole.variance(), 30.0, 30.0 * 1e-9);
  EXPECT_NEAR(a.variance(), 30.0, 30.0 * 1e-9);
  EXPECT_DOUBLE_EQ(a.mean(), 1e9 + 10.0);
}

TEST(RunningStats, EmptyAndSingleValue) {
  RunningStats s;
  EXPECT_EQ(s.count(), 0u);
  EXPECT_TRUE(std::isnan(s.mean()));
  EXPECT_TRUE(std::isnan(s.min()));
  EXPECT_TRUE(std::isnan(s.stddev()));
  s.add(3.5);
  EXPECT_EQ(s.mean(), 3.5);
  EXPECT_EQ(s.min(), 3.5);
  EXPECT_EQ(s.max(), 3.5);
  EXPECT_TRUE(std::isnan(s.stddev()));  // sample std needs two values
  RunningStats empty;
  s.merge(empty);  // merging an empty part changes nothing
  EXPECT_EQ(s.count(), 1u);
  EXPECT_EQ(s.mean(), 3.5);
  empty.merge(s);  // merging into an empty part copies
  EXPECT_EQ(empty, s);
}

// Splits `values` into consecutive parts of the given sizes (cycled), reduces each part with
// add() and merges the parts in order: what the runner does per gear.
RunningStats split_and_merge(const std::vector<double>& values, std::vector<std::size_t> sizes) {
  RunningStats total;
  std::size_t i = 0, part = 0;
  while (i < values.size()) {
    RunningStats piece;
    const std::size_t end = std::min(values.size(), i + sizes[part++ % sizes.size()]);
    for (; i < end; ++i) piece.add(values[i]);
    total.merge(piece);
  }
  return total;
}

TEST(RunningStats, MergeIsDeterministicAndSplitIndependentToRounding) {
  const std::vector<double> values = gamma_sample(100000, 7);
  // Reference: two-pass mean and variance in long double.
  long double sum = 0;
  for (double x : values) sum += x;
  const long double mean = sum / values.size();
  long double m2 = 0;
  for (double x : values) m2 += (x - mean) * (x - mean);
  const double ref_mean = static_cast<double>(mean);
  const double ref_std = static_cast<double>(std::sqrt(m2 / (values.size() - 1)));

  const RunningStats a1 = split_and_merge(values, {2400});
  const RunningStats a2 = split_and_merge(values, {2400});
  EXPECT_EQ(a1, a2);  // same split, same order: bitwise identical state

  RunningStats sequential;
  for (double x : values) sequential.add(x);
  const RunningStats uneven = split_and_merge(values, {1, 7, 1200, 33, 50000});
  const RunningStats pairs = split_and_merge(values, {2});
  for (const RunningStats* s :
       std::vector<const RunningStats*>{&a1, &sequential, &uneven, &pairs}) {
    EXPECT_EQ(s->count(), values.size());
    EXPECT_LE(relative_difference(s->mean(), ref_mean), 1e-12);
    EXPECT_LE(relative_difference(s->stddev(), ref_std), 1e-12);
    EXPECT_EQ(s->min(), *std::min_element(values.begin(), values.end()));
    EXPECT_EQ(s->max(), *std::max_element(values.begin(), values.end()));
  }
}

// ---------------------------------------------------------------------------------------------
// Histogram

// The index of the single occupied bin of a histogram holding one value.
std::size_t bin_of(const Histogram& layout, double x) {
  Histogram h(layout.lo(), layout.width(), layout.bin_count());
  h.add(x);
  for (std::size_t i = 0; i < h.bin_count(); ++i) {
    if (h.count(i) == 1) return i;
  }
  return static_cast<std::size_t>(-1);
}

TEST(Histogram, MembershipAgreesExactlyWithTheEdges) {
  // Bin i holds edge(i) <= x < edge(i + 1), with edge(i) = lo + i w as computed in double. The
  // plain (x - lo) / w misplaces some edge values by one bin (0.001 is not a binary fraction);
  // check every edge of the range, the value just below it, and a negative lo.
  for (double lo : {0.0, -0.3}) {
    const Histogram layout(lo, 0.001, 3000);
    for (std::size_t i = 0; i < layout.bin_count(); ++i) {
      const double e = layout.edge(i);
      ASSERT_EQ(bin_of(layout, e), i) << "edge " << i;
      if (i > 0) {
        ASSERT_EQ(bin_of(layout, std::nextafter(e, -1e9)), i - 1) << "below edge " << i;
      }
    }
  }
}

TEST(Histogram, OutsideValuesAndExtremes) {
  Histogram h(0.0, 0.5, 4);  // [0, 2)
  for (double x : {-0.7, -0.2, 0.0, 1.99, 2.0, 3.5, std::numeric_limits<double>::infinity()}) {
    h.add(x);
  }
  h.add(std::numeric_limits<double>::quiet_NaN());
  EXPECT_EQ(h.underflow(), 2u);
  EXPECT_EQ(h.overflow(), 3u);  // 2.0 = hi is outside, as is +inf
  EXPECT_EQ(h.invalid(), 1u);
  EXPECT_EQ(h.total(), 7u);
  EXPECT_EQ(h.count(0), 1u);
  EXPECT_EQ(h.count(3), 1u);
  EXPECT_EQ(h.underflow_min(), -0.7);
  EXPECT_EQ(h.underflow_max(), -0.2);
  EXPECT_EQ(h.overflow_min(), 2.0);
  EXPECT_EQ(h.min(), -0.7);
  EXPECT_TRUE(std::isinf(h.max()));
  EXPECT_THROW(Histogram(0.0, 0.0, 10), std::invalid_argument);
  EXPECT_THROW(Histogram(0.0, 0.1, 0), std::invalid_argument);
}

TEST(Histogram, MergeIsExactAndOrderIndependent) {
  const std::vector<double> values = gamma_sample(30000, 11);
  Histogram whole(0.0, 0.001, 3000);  // [0, 3): the gamma tail beyond 3 µm overflows
  for (double x : values) whole.add(x);
  Histogram forward(0.0, 0.001, 3000), backward(0.0, 0.001, 3000);
  std::vector<Histogram> parts(7, Histogram(0.0, 0.001, 3000));
  for (std::size_t i = 0; i < values.size(); ++i) parts[i % 7].add(values[i]);
  for (const Histogram& p : parts) forward.merge(p);
  for (auto it = parts.rbegin(); it != parts.rend(); ++it) backward.merge(*it);
  EXPECT_GT(whole.overflow(), 0u);
  EXPECT_EQ(forward, whole);
  EXPECT_EQ(backward, whole);
  EXPECT_THROW(whole.merge(Histogram(0.0, 0.002, 3000)), std::invalid_argument);
  EXPECT_THROW(whole.merge(Histogram(0.0, 0.001, 2999)), std::invalid_argument);
}

TEST(Histogram, QuantileRank) {
  // k = ceil(p n) (Hyndman & Fan 1996, definition 1), clamped to [1, n].
  EXPECT_EQ(quantile_rank(0.95, 20), 19u);
  EXPECT_EQ(quantile_rank(0.9973, 1200), 1197u);  // 1196.76 rounded up
  EXPECT_EQ(quantile_rank(0.5, 1), 1u);
  EXPECT_EQ(quantile_rank(0.0, 10), 1u);
  EXPECT_EQ(quantile_rank(1.0, 10), 10u);
  EXPECT_THROW(quantile_rank(1.5, 10), std::invalid_argument);
}

TEST(Histogram, QuantilesWithinOneBinAboveTheExactSampleQuantile) {
  const double w = 0.001;
  for (std::size_t n : {1u, 2u, 37u, 1200u, 50000u}) {
    std::vector<double> values = gamma_sample(n, 100 + n);
    Histogram h(0.0, w, 20000);  // 0-20 µm
    for (double x : values) h.add(x);
    std::sort(values.begin(), values.end());
    for (double p : {0.001, 0.25, 0.5, 0.95, 0.9973, 0.999, 1.0}) {
      const double exact = values[quantile_rank(p, n) - 1];
      const double q = h.quantile(p);
      EXPECT_GE(q, exact) << "n " << n << " p " << p;
      EXPECT_LE(q - exact, w) << "n " << n << " p " << p;
    }
    EXPECT_EQ(h.quantile(0.0), values.front());
    EXPECT_EQ(h.quantile(1.0), values.back());
  }
  EXPECT_TRUE(std::isnan(Histogram(0.0, w, 10).quantile(0.5)));
}

TEST(Histogram, QuantilesOutsideTheBinnedRange) {
  Histogram h(1.0, 0.1, 10);  // [1, 2)
  for (double x : {0.2, 0.4, 1.05, 1.55, 2.5, 7.0}) h.add(x);
  EXPECT_EQ(h.quantile(1.0 / 6.0), 0.4);     // k = 1 lies in the underflow: its max, >= x_(1)
  EXPECT_EQ(h.quantile(2.0 / 6.0), 0.4);     // k = 2: the underflow max is exact
  EXPECT_NEAR(h.quantile(0.5), 1.1, 1e-12);  // k = 3: upper edge of [1.0, 1.1)
  EXPECT_EQ(h.quantile(5.0 / 6.0), 7.0);     // k = 5 is an overflow value: max() bounds it
}

TEST(Histogram, RebinAndModeAtADisplayWidth) {
  Histogram h(0.0, 0.01, 400);  // [0, 4)
  // Display bins of 0.1: [1.6, 1.7) gets 5 values, [1.2, 1.3) 4, [2.0, 2.1) 5 (tie, higher).
  // Every value is in a different 0.01 bin and none sits on an edge.
  for (double x : {1.612, 1.625, 1.655, 1.681, 1.699}) h.add(x);
  for (double x : {1.213, 1.226, 1.237, 1.248}) h.add(x);
  for (double x : {2.013, 2.024, 2.035, 2.046, 2.057}) h.add(x);
  EXPECT_EQ(h.rebin_factor(0.1), 10u);
  const Histogram display = h.rebin(10);
  EXPECT_EQ(display.bin_count(), 40u);
  EXPECT_DOUBLE_EQ(display.width(), 0.1);
  EXPECT_EQ(display.count(16), 5u);
  EXPECT_EQ(display.count(12), 4u);
  EXPECT_EQ(display.total(), h.total());
  EXPECT_NEAR(h.mode(0.1), 1.65, 1e-12);  // tie between 1.65 and 2.05: the lower bin
  // At a 0.4 display width [1.2, 1.6) holds 4, [1.6, 2.0) 5, [2.0, 2.4) 5: the tie-break again.
  EXPECT_NEAR(h.mode(0.4), 1.8, 1e-12);
  // At 0.01 every occupied bin holds one value: the tie-break picks the lowest, [1.21, 1.22).
  EXPECT_NEAR(h.mode(0.01), 1.215, 1e-12);
  EXPECT_THROW(h.rebin(3), std::invalid_argument);             // 3 does not divide 400
  EXPECT_THROW(h.rebin_factor(0.015), std::invalid_argument);  // not a whole multiple
  EXPECT_TRUE(std::isnan(Histogram(0.0, 0.01, 10).mode(0.1)));
}

TEST(Histogram, Csv) {
  Histogram h(0.0, 0.5, 2);
  for (double x : {0.1, 0.6, 0.7, -1.0}) h.add(x);
  EXPECT_EQ(h.to_csv(), "bin_lo_um,bin_hi_um,count\n0,0.5,1\n0.5,1,2\nunderflow,,1\noverflow,,0\n");
}

TEST(StatsJson, KeysValuesAndOrder) {
  // Hand-computable data: 1.0, 1.5, 2.0, 2.5, 3.0: mean 2, sample std sqrt(0.625).
  RunningStats moments;
  RelativeHistogram h;
  for (double x : {1.0, 1.5, 2.0, 2.5, 3.0}) {
    moments.add(x);
    h.add(x);
  }
  const HistogramBins bins{0.0, 0.1, 40};  // [0, 4) in 0.1 µm bins
  const nlohmann::ordered_json j = stats_json(moments, h, bins);
  std::vector<std::string> keys;
  for (const auto& item : j.items()) keys.push_back(item.key());
  EXPECT_EQ(keys, (std::vector<std::string>{"n", "mean", "std", "min", "max", "mode", "mode_bin_um",
                                            "p95", "p95_note", "p99_73", "p99_73_note"}));
  EXPECT_EQ(j["n"].get<std::uint64_t>(), 5u);
  EXPECT_DOUBLE_EQ(j["mean"].get<double>(), 2.0);
  EXPECT_DOUBLE_EQ(j["std"].get<double>(), std::sqrt(0.625));
  EXPECT_EQ(j["min"].get<double>(), 1.0);
  EXPECT_EQ(j["max"].get<double>(), 3.0);
  EXPECT_NEAR(j["mode"].get<double>(), 1.05, 1e-12);  // five singletons: the lowest, [1.0, 1.1)
  EXPECT_EQ(j["mode_bin_um"].get<double>(), 0.1);
  // 5 values cannot support p95 (needs n (1 - p) >= 1: 20 values) nor p99.73 (371): null with
  // a note, not the maximum in disguise.
  EXPECT_TRUE(j["p95"].is_null());
  EXPECT_EQ(j["p95_note"].get<std::string>(), "not enough values: n = 5, p95 needs at least 20");
  EXPECT_TRUE(j["p99_73"].is_null());
  EXPECT_EQ(j["p99_73_note"].get<std::string>(),
            "not enough values: n = 5, p99.73 needs at least 371");

  const nlohmann::ordered_json empty = stats_json(RunningStats{}, RelativeHistogram{}, bins);
  EXPECT_EQ(empty.dump(), R"({"n":0,"mean":null,"std":null,"min":null,"max":null,"mode":null,)"
                          R"("mode_bin_um":0.1,"p95":null,"p99_73":null})");
  RunningStats one;
  one.add(1.0);
  EXPECT_THROW(stats_json(one, RelativeHistogram{}, bins), std::invalid_argument);
}

TEST(StatsJson, QuantilesOnceThereAreEnoughValues) {
  // 371 values 1, 2, ..., 371: p99.73 is x_(k), k = ceil(0.9973 * 371) = ceil(369.998) = 370
  // (Hyndman & Fan definition 1) — supported since 371 (1 - 0.9973) = 1.0017 >= 1; p95:
  // k = ceil(352.45) = 353. An integer below 512 is a bucket edge (bucket width 2^(8 - 12) = 1/16
  // in [256, 512)), so the returned upper edge of x's bucket is x + 1/16: 353.0625 and 370.0625.
  RunningStats moments;
  RelativeHistogram h;
  for (int i = 1; i <= 371; ++i) {
    moments.add(i);
    h.add(i);
  }
  const nlohmann::ordered_json j = stats_json(moments, h, HistogramBins{0.0, 10.0, 38});
  EXPECT_DOUBLE_EQ(j["p95"].get<double>(), 353.0625);
  EXPECT_DOUBLE_EQ(j["p99_73"].get<double>(), 370.0625);
  EXPECT_FALSE(j.contains("p95_note"));
  EXPECT_FALSE(j.contains("p99_73_note"));
}

// ---------------------------------------------------------------------------------------------
// Distribution fits

std::vector<Distribution> reference_laws() {
  // Parameters in the range of P1's per-flank δRcomp (mean 1-2 µm, sigma 0.4-0.8 µm).
  return {{DistributionLaw::kNormal, 2.0, 0.4},
          {DistributionLaw::kLognormal, 0.3, 0.5},
          {DistributionLaw::kGamma, 4.0, 0.4},
          {DistributionLaw::kWeibull, 2.0, 1.8},
          {DistributionLaw::kGumbelMax, 1.35, 0.45}};
}

TEST(Distribution, PdfIsTheDerivativeOfCdfAndQuantileInvertsIt) {
  for (const Distribution& d : reference_laws()) {
    for (double p : {1e-6, 0.01, 0.3, 0.5, 0.9, 0.9973, 1 - 1e-9}) {
      const double x = d.quantile(p);
      const double back = p <= 0.5 ? d.cdf(x) : 1.0 - d.survival(x);
      EXPECT_NEAR(back, p, 1e-12 * std::max(p, 1e-3)) << law_name(d.law) << " p " << p;
      const double h = 1e-5 * d.stddev();
      const double derivative = (d.cdf(x + h) - d.cdf(x - h)) / (2 * h);
      EXPECT_NEAR(derivative, d.pdf(x), 1e-6 * d.pdf(x) + 1e-9) << law_name(d.law) << " p " << p;
      EXPECT_NEAR(d.cdf(x) + d.survival(x), 1.0, 1e-14);
    }
  }
  // Closed forms: a normal quantile (z_0.975 = 1.959963984540054, A&S table 26.5); the Weibull
  // and Gumbel quantiles by inverting their CDFs.
  const Distribution normal{DistributionLaw::kNormal, 1.0, 2.0};
  const Distribution weibull{DistributionLaw::kWeibull, 2.0, 1.8};
  const Distribution gumbel{DistributionLaw::kGumbelMax, 1.35, 0.45};
  EXPECT_NEAR(normal.quantile(0.975), 1.0 + 2.0 * 1.959963984540054, 1e-12);
  EXPECT_NEAR(weibull.quantile(0.9), 1.8 * std::pow(-std::log(0.1), 0.5), 1e-12);
  EXPECT_NEAR(gumbel.quantile(0.99), 1.35 - 0.45 * std::log(-std::log(0.99)), 1e-12);
}

std::vector<double> draw(const Distribution& d, std::size_t n, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::vector<double> v(n);
  switch (d.law) {
    case DistributionLaw::kNormal: {
      std::normal_distribution<double> law(d.a, d.b);
      for (double& x : v) x = law(rng);
      break;
    }
    case DistributionLaw::kLognormal: {
      std::lognormal_distribution<double> law(d.a, d.b);
      for (double& x : v) x = law(rng);
      break;
    }
    case DistributionLaw::kGamma: {
      std::gamma_distribution<double> law(d.a, d.b);  // (shape, scale)
      for (double& x : v) x = law(rng);
      break;
    }
    case DistributionLaw::kWeibull: {
      std::weibull_distribution<double> law(d.a, d.b);  // (shape, scale)
      for (double& x : v) x = law(rng);
      break;
    }
    case DistributionLaw::kGumbelMax: {
      // The C++ extreme_value_distribution(a, b) is the Gumbel law of maxima,
      // F = exp(-exp(-(x - a) / b)) ([rand.dist.pois.extreme]).
      std::extreme_value_distribution<double> law(d.a, d.b);
      for (double& x : v) x = law(rng);
      break;
    }
  }
  return v;
}

// Asymptotic standard errors of the maximum-likelihood estimates of (a, b) for n values, from
// the inverse Fisher information:
//  normal:     se(mu) = sigma / sqrt n, se(sigma) = sigma / sqrt(2n) (any statistics text);
//  lognormal:  the same for the log-parameters;
//  gamma:      var(k) = k / (n (k psi'(k) - 1)), var(theta) = theta^2 psi'(k) / (n (k psi'(k) - 1))
//              (Johnson, Kotz & Balakrishnan vol. 1, ch. 17, from I = [[psi'(k), 1/theta],
//              [1/theta, k/theta^2]]);
//  weibull:    var(k) = 6 k^2 / (pi^2 n), var(lambda) = lambda^2 (1 + 6 (1 - gamma)^2 / pi^2) /
//              (k^2 n) (Cohen 1965, "Maximum likelihood estimation in the Weibull distribution");
//  gumbel_max: var(mu) = beta^2 (1 + 6 (1 - gamma)^2 / pi^2) / n, var(beta) = 6 beta^2 / (pi^2 n)
//              (Johnson, Kotz & Balakrishnan vol. 2, ch. 22).
// Binning at 0.001 µm (< sigma / 400) loses a negligible part of the information.
std::array<double, 2> standard_errors(const Distribution& d, double n) {
  constexpr double pi2 = std::numbers::pi * std::numbers::pi;
  const double c = 1.0 + 6.0 * (1.0 - std::numbers::egamma) * (1.0 - std::numbers::egamma) / pi2;
  switch (d.law) {
    case DistributionLaw::kNormal:
    case DistributionLaw::kLognormal:
      return {d.b / std::sqrt(n), d.b / std::sqrt(2 * n)};
    case DistributionLaw::kGamma: {
      // trigamma(k) for k = 4: pi^2 / 6 - (1 + 1/4 + 1/9) (A&S 6.4.3 and 6.4.6).
      EXPECT_EQ(d.a, 4.0);
      const double trigamma = pi2 / 6.0 - (1.0 + 0.25 + 1.0 / 9.0);
      const double det = d.a * trigamma - 1.0;
      return {std::sqrt(d.a / (n * det)), std::sqrt(d.b * d.b * trigamma / (n * det))};
    }
    case DistributionLaw::kWeibull:
      return {std::sqrt(6.0 * d.a * d.a / (pi2 * n)), std::sqrt(d.b * d.b * c / (d.a * d.a * n))};
    case DistributionLaw::kGumbelMax:
      return {std::sqrt(d.b * d.b * c / n), std::sqrt(6.0 * d.b * d.b / (pi2 * n))};
  }
  return {0, 0};
}

TEST(DistributionFit, RecoversEachLawFrom20000Draws) {
  const std::size_t n = 20000;
  std::uint64_t seed = 2024;
  for (const Distribution& truth : reference_laws()) {
    SCOPED_TRACE(std::string(law_name(truth.law)));
    Histogram h(0.0, 0.001, 20000);  // 0-20 µm at 1 nm, as the runner's fine histogram
    for (double x : draw(truth, n, seed++)) h.add(x);
    ASSERT_EQ(h.total(), n);

    const std::vector<DistributionFit> fits = fit_distributions(h);
    ASSERT_EQ(fits.size(), 5u);
    // The true law ranks first (strictly; no ΔAIC < 2 tie rule is needed). The closest pair is
    // Gumbel data vs a lognormal fit (a lognormal with sigma_log ~ 0.35 has the Gumbel's
    // skewness 1.14): over 40 other seeds the gap was ΔAIC = 22 ± 8 (all 40 ranked Gumbel first),
    // so with a different sample, e.g. another standard library's <random>, this check would
    // fail with a probability of about 0.3 %. The gaps are printed for the record.
    EXPECT_EQ(fits[0].distribution.law, truth.law)
        << "first " << law_name(fits[0].distribution.law);
    std::printf("  %-10s  ΔAIC to the runner-up %.1f (%s)\n",
                std::string(law_name(truth.law)).c_str(), fits[1].aic - fits[0].aic,
                std::string(law_name(fits[1].distribution.law)).c_str());
    for (std::size_t i = 1; i < fits.size(); ++i) EXPECT_LE(fits[i - 1].aic, fits[i].aic);

    const DistributionFit fit = fit_distribution(h, truth.law);
    ASSERT_TRUE(fit.applicable) << fit.note;
    const auto se = standard_errors(truth, static_cast<double>(n));
    // Five standard errors: a false alarm has probability < 1e-6 per parameter.
    EXPECT_NEAR(fit.distribution.a, truth.a, 5 * se[0]);
    EXPECT_NEAR(fit.distribution.b, truth.b, 5 * se[1]);
    // The optimiser found a maximum at least as high as the true parameters' likelihood.
    EXPECT_GE(fit.log_likelihood, binned_log_likelihood(h, truth) - 1e-6);
    EXPECT_DOUBLE_EQ(fit.aic, 4.0 - 2.0 * fit.log_likelihood);
    // Goodness of fit of the true law: KS below the 1 % critical value of a fully specified law,
    // 1.63 / sqrt n (Smirnov 1948; fitted parameters make D smaller still), and the chi-square
    // test not rejected at 0.1 %.
    EXPECT_LT(fit.ks_distance, 1.63 / std::sqrt(static_cast<double>(n)));
    EXPECT_GT(fit.chi_square_p_value, 0.001)
        << "chi2 " << fit.chi_square << " dof " << fit.chi_square_dof;
    EXPECT_GT(fit.chi_square_dof, 10);
  }
}

TEST(DistributionFit, NormalFitMatchesTheClosedFormMle) {
  // The normal MLE of raw data is (mean, sqrt(M2 / n)); binning at w = 0.001 µm moves the binned
  // MLE by O(w^2 / sigma) plus rounding noise of order w / sqrt(n): within w / 10 here.
  const Distribution truth{DistributionLaw::kNormal, 2.0, 0.4};
  const std::vector<double> values = draw(truth, 20000, 99);
  RunningStats raw;
  Histogram h(0.0, 0.001, 20000);
  for (double x : values) {
    raw.add(x);
    h.add(x);
  }
  const DistributionFit fit = fit_distribution(h, DistributionLaw::kNormal);
  const double mle_sigma =
      std::sqrt(raw.sum_squared_deviations() / static_cast<double>(values.size()));
  EXPECT_NEAR(fit.distribution.a, raw.mean(), 1e-4);
  EXPECT_NEAR(fit.distribution.b, mle_sigma, 1e-4);
}

TEST(DistributionFit, UsesUnderflowAndOverflowAsCensoredCells) {
  // Normal(2, 0.4) seen through a window [1.8, 2.2) = mu ± sigma / 2: 62 % of the values fall
  // outside and enter only as counts. The doubly censored normal's Fisher information (Cohen
  // 1991, "Truncated and censored samples"), evaluated numerically for this window, gives
  // var(mu) = 1.199 sigma^2 / n and var(sigma) = 1.899 sigma^2 / n.
  const Distribution truth{DistributionLaw::kNormal, 2.0, 0.4};
  const double n = 20000;
  Histogram h(1.8, 0.001, 400);
  for (double x : draw(truth, 20000, 5)) h.add(x);
  EXPECT_GT(h.underflow(), 5000u);
  EXPECT_GT(h.overflow(), 5000u);
  const DistributionFit fit = fit_distribution(h, DistributionLaw::kNormal);
  ASSERT_TRUE(fit.applicable);
  EXPECT_NEAR(fit.distribution.a, truth.a, 5 * std::sqrt(1.199 / n) * truth.b);
  EXPECT_NEAR(fit.distribution.b, truth.b, 5 * std::sqrt(1.899 / n) * truth.b);
}

TEST(DistributionFit, WrongLawIsRejected) {
  // Skewed gamma(4, 0.4) data (skewness 2 / sqrt 4 = 1): a normal fit must fail both GOF tests.
  const Distribution truth{DistributionLaw::kGamma, 4.0, 0.4};
  Histogram h(0.0, 0.001, 20000);
  for (double x : draw(truth, 20000, 3)) h.add(x);
  const DistributionFit normal = fit_distribution(h, DistributionLaw::kNormal);
  EXPECT_LT(normal.chi_square_p_value, 1e-6);
  EXPECT_GT(normal.ks_distance, 1.63 / std::sqrt(20000.0));
}

TEST(DistributionFit, NotApplicableCases) {
  Histogram negative(-1.0, 0.001, 4000);
  for (double x : draw({DistributionLaw::kNormal, 0.5, 0.4}, 2000, 1)) negative.add(x);
  const std::vector<DistributionFit> fits = fit_distributions(negative);
  ASSERT_EQ(fits.size(), 5u);
  // Normal and Gumbel can describe negative values; the three positive laws cannot and go last.
  EXPECT_TRUE(fits[0].applicable);
  EXPECT_TRUE(fits[1].applicable);
  for (std::size_t i = 2; i < 5; ++i) {
    EXPECT_FALSE(fits[i].applicable);
    EXPECT_FALSE(fits[i].note.empty());
    EXPECT_TRUE(std::isinf(fits[i].aic));
  }
  Histogram single(0.0, 0.001, 100);
  for (int i = 0; i < 10; ++i) single.add(0.0505);
  EXPECT_FALSE(fit_distribution(single, DistributionLaw::kNormal).applicable);
  EXPECT_FALSE(fit_distribution(Histogram(0.0, 0.001, 100), DistributionLaw::kGamma).applicable);
}

}  // namespace
}  // namespace gearmc
