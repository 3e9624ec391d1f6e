// Tests of the cluster-aware statistics of the diagnosis (engine/apps/diagnose/cluster_tests.h):
// the energy distance against an independent brute-force O(n²) double loop over all ordered
// pairs and against its definition on point masses; the cluster-swap permutation test's
// calibration on simulated clustered data under the null (p-values ≈ uniform) and its power on a
// 1 σ shift; the cluster bootstrap's estimate against the plain RMS, its collapse when there is
// no between-cluster variation, and its coverage of the true RMS on simulated data. Data are
// drawn from RandomStream with purpose kEffectNoise (a stream the statistics never use), with
// fixed seeds, so every assertion is deterministic; the statistical thresholds are set about 3
// binomial standard deviations away from the nominal values so that they test the method and not
// the luck of the seeds.
#include "engine/apps/diagnose/cluster_tests.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <stdexcept>
#include <vector>

#include "core/random_stream.h"

namespace gearmc {
namespace {

// Test data stream: (data seed, gear = 0, kEffectNoise, sub-index = which sample).
RandomStream data_stream(std::uint64_t seed, std::uint32_t which) {
  return RandomStream(seed, 0, StreamPurpose::kEffectNoise, which);
}

std::vector<double> normal_sample(std::uint64_t seed, std::uint32_t which, int n, double mean,
                                  double sigma) {
  RandomStream rng = data_stream(seed, which);
  std::vector<double> v(static_cast<std::size_t>(n));
  for (double& value : v) value = mean + sigma * rng.normal();
  return v;
}

// Independent reference: the definition's means over all ordered pairs, as a double loop.
double brute_force_energy(const std::vector<double>& x, const std::vector<double>& y) {
  double xy = 0.0, xx = 0.0, yy = 0.0;
  for (double a : x) {
    for (double b : y) xy += std::abs(a - b);
  }
  for (double a : x) {
    for (double b : x) xx += std::abs(a - b);
  }
  for (double a : y) {
    for (double b : y) yy += std::abs(a - b);
  }
  const double n = static_cast<double>(x.size()), m = static_cast<double>(y.size());
  return 2.0 * xy / (n * m) - xx / (n * n) - yy / (m * m);
}

// Clustered paired data: `clusters` clusters of `per_cluster` points each; x's points of a cluster
// share one offset N(0, offset_sigma²), y's points another, independent one, plus N(0, 1) noise
// per point; y is shifted by `shift`. Under shift = 0 the x and y halves of each cluster are
// exchangeable, the null of the cluster-swap test, while points of a cluster are correlated.
struct Clustered {
  std::vector<double> x, y;
  std::vector<int> cluster;
};
Clustered clustered(std::uint64_t seed, int clusters, int per_cluster, double offset_sigma,
                    double shift) {
  RandomStream rng = data_stream(seed, 100);
  Clustered d;
  for (int c = 0; c < clusters; ++c) {
    const double ox = offset_sigma * rng.normal();
    const double oy = offset_sigma * rng.normal();
    for (int k = 0; k < per_cluster; ++k) {
      d.x.push_back(ox + rng.normal());
      d.y.push_back(shift + oy + rng.normal());
      d.cluster.push_back(7 * c - 20);  // arbitrary, non-contiguous ids
    }
  }
  return d;
}

double plain_rms(const std::vector<double>& r) {
  double s = 0.0;
  for (double v : r) s += v * v;
  return std::sqrt(s / static_cast<double>(r.size()));
}

// --- energy distance -------------------------------------------------------------------------

TEST(ClusterTestsEnergy, MatchesBruteForceDoubleLoop) {
  for (std::uint64_t seed = 1; seed <= 5; ++seed) {
    // Different sizes, locations and scales; a large common offset checks the centring.
    const std::vector<double> x = normal_sample(seed, 1, 37, 1000.0, 1.0);
    const std::vector<double> y = normal_sample(seed, 2, 53, 1000.5, 2.0);
    const double reference = brute_force_energy(x, y);
    EXPECT_NEAR(energy_distance(x, y), reference, 1e-9 * reference) << "seed " << seed;
    EXPECT_NEAR(energy_distance(y, x), reference, 1e-9 * reference) << "seed " << seed;
  }
  // Sizes 1 and 2 with ties (x contains y's value).
  const std::vector<double> x{0.5, 0.5, -1.25}, y{0.5};
  EXPECT_NEAR(energy_distance(x, y), brute_force_energy(x, y), 1e-15);
}

TEST(ClusterTestsEnergy, ZeroForIdenticalSamples) {
  const std::vector<double> x = normal_sample(3, 1, 64, 0.0, 1.0);
  std::vector<double> shuffled(x.rbegin(), x.rend());  // same empirical law, other order
  EXPECT_NEAR(energy_distance(x, x), 0.0, 1e-12);
  EXPECT_NEAR(energy_distance(x, shuffled), 0.0, 1e-12);
}

TEST(ClusterTestsEnergy, PointMassesGiveTwiceTheDistance) {
  // Definition: for x ≡ a, y ≡ b the within-sample means are 0 and the cross mean is |a − b|.
  EXPECT_DOUBLE_EQ(energy_distance(std::vector<double>{1.5}, std::vector<double>{-2.0}), 7.0);
  EXPECT_DOUBLE_EQ(energy_distance(std::vector<double>(4, 3.0), std::vector<double>(9, 3.25)), 0.5);
}

TEST(ClusterTestsEnergy, RejectsInvalidInput) {
  const std::vector<double> x{1.0, 2.0}, empty;
  EXPECT_THROW(energy_distance(x, empty), std::invalid_argument);
  EXPECT_THROW(energy_distance(empty, x), std::invalid_argument);
  EXPECT_THROW(energy_distance(x, std::vector<double>{std::numeric_limits<double>::quiet_NaN()}),
               std::invalid_argument);
}

// --- cluster-swap permutation test ------------------------------------------------------------

TEST(ClusterTestsPermutation, NullPValuesAreRoughlyUniform) {
  // 100 data sets under the null with a strong cluster effect (offset σ 1 = noise σ), 16 clusters
  // of 10 points; 99 replicates each. Under the null p is uniform on {1, …, 100}/100 (Davison &
  // Hinkley ch. 4): P(p < 0.05) = 0.04 (binomial sd over 100 sets 0.02; accepted ≤ 0.12) and the
  // mean of p is 0.505 (sd 0.029; accepted 0.40–0.60).
  constexpr int kSets = 100;
  int below_005 = 0;
  double mean_p = 0.0;
  for (int s = 0; s < kSets; ++s) {
    const Clustered d = clustered(1000 + s, 16, 10, 1.0, 0.0);
    const PermutationTest t =
        cluster_swap_energy_test(d.x, d.y, d.cluster, 99, 1 + static_cast<std::uint64_t>(s), 7);
    EXPECT_EQ(t.clusters, 16);
    EXPECT_EQ(t.replicates, 99);
    EXPECT_GT(t.p_value, 0.0);
    EXPECT_LE(t.p_value, 1.0);
    if (t.p_value < 0.05) ++below_005;
    mean_p += t.p_value / kSets;
  }
  std::printf("[ null ] fraction p < 0.05: %.2f, mean p: %.3f (%d sets)\n",
              static_cast<double>(below_005) / kSets, mean_p, kSets);
  EXPECT_LE(below_005, 12);
  EXPECT_GT(mean_p, 0.40);
  EXPECT_LT(mean_p, 0.60);
}

TEST(ClusterTestsPermutation, DetectsOneSigmaShift) {
  // y shifted by 1 noise σ (offset σ 0.5); 32 clusters of 10 points, 999 replicates: the smallest
  // possible p is 1/1000.
  const Clustered d = clustered(42, 32, 10, 0.5, 1.0);
  const PermutationTest t = cluster_swap_energy_test(d.x, d.y, d.cluster, 999, 1, 7);
  std::printf("[ shift ] E = %.4f um, p = %.4f\n", t.statistic, t.p_value);
  EXPECT_NEAR(t.statistic, energy_distance(d.x, d.y), 1e-15);
  EXPECT_LT(t.p_value, 0.01);
}

TEST(ClusterTestsPermutation, DeterministicAndIndependentOfIdLabels) {
  const Clustered d = clustered(5, 12, 6, 1.0, 0.3);
  const PermutationTest a = cluster_swap_energy_test(d.x, d.y, d.cluster, 199, 11, 3);
  const PermutationTest b = cluster_swap_energy_test(d.x, d.y, d.cluster, 199, 11, 3);
  EXPECT_EQ(a.p_value, b.p_value);
  EXPECT_EQ(a.statistic, b.statistic);
  // Relabelling the clusters 0..C−1 in order of first appearance gives the same draws.
  std::vector<int> dense;
  for (std::size_t k = 0; k < d.cluster.size(); ++k) dense.push_back(static_cast<int>(k / 6));
  const PermutationTest c = cluster_swap_energy_test(d.x, d.y, dense, 199, 11, 3);
  EXPECT_EQ(a.p_value, c.p_value);
  EXPECT_EQ(c.clusters, 12);
}

TEST(ClusterTestsPermutation, PValueEqualsTheDefinitionReplicateByReplicate) {
  // The test walks the pooled sample sorted once instead of re-sorting each replicate; the
  // reference here is the definition: each replicate draws the same swaps (RandomStream(seed, r,
  // kDiagnoseNullStream, sub_index), one uniform per cluster in order of first appearance,
  // swapped when < 1/2), swaps x and y on those clusters and computes energy_distance of the
  // swapped samples. p = (1 + #{E* ≥ E − 1e-10 max|x, y|}) / (R + 1) must be the same.
  for (std::uint64_t seed : {3u, 8u, 21u}) {
    const Clustered d = clustered(seed, 9, 7, 1.0, 0.2 * static_cast<double>(seed % 3));
    constexpr int kReplicates = 99;
    const PermutationTest t = cluster_swap_energy_test(d.x, d.y, d.cluster, kReplicates, seed, 5);
    double scale = 0.0;
    for (std::size_t k = 0; k < d.x.size(); ++k) {
      scale = std::max({scale, std::abs(d.x[k]), std::abs(d.y[k])});
    }
    const double observed = energy_distance(d.x, d.y);
    std::vector<int> dense;  // ids in order of first appearance
    std::vector<int> seen;
    for (int id : d.cluster) {
      auto at = std::find(seen.begin(), seen.end(), id);
      if (at == seen.end()) seen.push_back(id), at = seen.end() - 1;
      dense.push_back(static_cast<int>(at - seen.begin()));
    }
    int at_least = 0;
    for (int r = 0; r < kReplicates; ++r) {
      RandomStream rng(seed, static_cast<std::uint32_t>(r), StreamPurpose::kDiagnoseNull, 5);
      std::vector<bool> swap;
      for (std::size_t c = 0; c < seen.size(); ++c) swap.push_back(rng.uniform() < 0.5);
      std::vector<double> xs, ys;
      for (std::size_t k = 0; k < d.x.size(); ++k) {
        const bool s = swap[static_cast<std::size_t>(dense[k])];
        xs.push_back(s ? d.y[k] : d.x[k]);
        ys.push_back(s ? d.x[k] : d.y[k]);
      }
      if (energy_distance(xs, ys) >= observed - 1e-10 * scale) ++at_least;
    }
    EXPECT_DOUBLE_EQ(t.p_value, (1.0 + at_least) / (kReplicates + 1.0)) << "seed " << seed;
  }
}

TEST(ClusterTestsPermutation, SingleClusterCannotReject) {
  // Swapping the only cluster gives E again, so every replicate ties with the observed E.
  const Clustered d = clustered(9, 1, 20, 0.0, 3.0);
  const PermutationTest t = cluster_swap_energy_test(d.x, d.y, d.cluster, 50, 1, 0);
  EXPECT_EQ(t.clusters, 1);
  EXPECT_DOUBLE_EQ(t.p_value, 1.0);
}

TEST(ClusterTestsPermutation, RejectsInvalidInput) {
  const std::vector<double> x{1.0, 2.0}, y{1.0, 3.0}, short_y{1.0};
  const std::vector<int> c{0, 1}, short_c{0};
  EXPECT_THROW(cluster_swap_energy_test(x, short_y, c, 10, 1, 0), std::invalid_argument);
  EXPECT_THROW(cluster_swap_energy_test(x, y, short_c, 10, 1, 0), std::invalid_argument);
  EXPECT_THROW(cluster_swap_energy_test({}, {}, {}, 10, 1, 0), std::invalid_argument);
  EXPECT_THROW(cluster_swap_energy_test(x, y, c, 0, 1, 0), std::invalid_argument);
}

// --- cluster bootstrap of the RMS -------------------------------------------------------------

TEST(ClusterTestsBootstrap, EstimateIsPlainRmsAndInsideInterval) {
  const Clustered d = clustered(3, 20, 15, 0.5, 0.0);
  const BootstrapInterval b = cluster_bootstrap_rms(d.x, d.cluster, 999, 1, 5);
  EXPECT_NEAR(b.estimate, plain_rms(d.x), 1e-14);
  EXPECT_LT(b.lo, b.estimate);
  EXPECT_GT(b.hi, b.estimate);
  EXPECT_EQ(b.clusters, 20);
  EXPECT_EQ(b.replicates, 999);
  EXPECT_DOUBLE_EQ(b.level, 0.95);
  // Deterministic; a wider level gives a wider interval from the same draws.
  const BootstrapInterval again = cluster_bootstrap_rms(d.x, d.cluster, 999, 1, 5);
  EXPECT_EQ(b.lo, again.lo);
  EXPECT_EQ(b.hi, again.hi);
  const BootstrapInterval wide = cluster_bootstrap_rms(d.x, d.cluster, 999, 1, 5, 0.99);
  EXPECT_LE(wide.lo, b.lo);
  EXPECT_GE(wide.hi, b.hi);
}

TEST(ClusterTestsBootstrap, CollapsesWithoutBetweenClusterVariation) {
  // One cluster: every replicate redraws the whole data set.
  const std::vector<double> r = normal_sample(4, 1, 30, 0.0, 1.0);
  const std::vector<int> one(r.size(), 5);
  const BootstrapInterval b = cluster_bootstrap_rms(r, one, 200, 1, 0);
  EXPECT_EQ(b.clusters, 1);
  EXPECT_DOUBLE_EQ(b.lo, b.estimate);
  EXPECT_DOUBLE_EQ(b.hi, b.estimate);
  // The same cluster repeated 6 times: every draw of 6 clusters has the same RMS.
  std::vector<double> repeated;
  std::vector<int> ids;
  for (int c = 0; c < 6; ++c) {
    repeated.insert(repeated.end(), r.begin(), r.end());
    ids.insert(ids.end(), r.size(), c);
  }
  const BootstrapInterval rep = cluster_bootstrap_rms(repeated, ids, 200, 1, 0);
  EXPECT_NEAR(rep.estimate, plain_rms(r), 1e-14);
  EXPECT_NEAR(rep.lo, rep.estimate, 1e-14);
  EXPECT_NEAR(rep.hi, rep.estimate, 1e-14);
}

TEST(ClusterTestsBootstrap, CoversTrueRms) {
  // N(0, 1) data, true RMS 1; 48 clusters of 50 points, 499 replicates, 200 data sets. Nominal
  // coverage 0.95 (binomial sd over 200 sets 0.015); accepted 0.90–0.99.
  constexpr int kSets = 200;
  int covered = 0;
  std::vector<int> ids;
  for (int c = 0; c < 48; ++c) ids.insert(ids.end(), 50, c);
  for (int s = 0; s < kSets; ++s) {
    const std::vector<double> r =
        normal_sample(2000 + static_cast<std::uint64_t>(s), 1, 48 * 50, 0.0, 1.0);
    const BootstrapInterval b =
        cluster_bootstrap_rms(r, ids, 499, 1 + static_cast<std::uint64_t>(s), 9);
    if (b.lo <= 1.0 && 1.0 <= b.hi) ++covered;
  }
  const double coverage = static_cast<double>(covered) / kSets;
  std::printf("[ bootstrap ] coverage of the true RMS: %.3f (%d sets)\n", coverage, kSets);
  EXPECT_GE(coverage, 0.90);
  EXPECT_LE(coverage, 0.99);
}

TEST(ClusterTestsBootstrap, RejectsInvalidInput) {
  const std::vector<double> r{1.0, 2.0};
  const std::vector<int> c{0, 1}, short_c{0};
  EXPECT_THROW(cluster_bootstrap_rms(r, short_c, 10, 1, 0), std::invalid_argument);
  EXPECT_THROW(cluster_bootstrap_rms({}, {}, 10, 1, 0), std::invalid_argument);
  EXPECT_THROW(cluster_bootstrap_rms(r, c, 0, 1, 0), std::invalid_argument);
  EXPECT_THROW(cluster_bootstrap_rms(r, c, 10, 1, 0, 1.0), std::invalid_argument);
  EXPECT_THROW(cluster_bootstrap_rms(r, c, 10, 1, 0, 0.0), std::invalid_argument);
}

}  // namespace
}  // namespace gearmc
