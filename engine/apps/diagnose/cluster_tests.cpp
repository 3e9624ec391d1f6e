// Cluster-aware two-sample and bootstrap statistics of the diagnosis: the energy distance by
// sorting, the paired cluster-swap permutation test and the percentile cluster bootstrap of the
// RMS (see cluster_tests.h for the formulas and their sources). Units: µm.
#include "engine/apps/diagnose/cluster_tests.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <stdexcept>
#include <string>
#include <unordered_map>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/parallel_reduce.h>

#include "core/random_stream.h"
#include "engine/apps/diagnose/selection.h"

namespace gearmc {
namespace {

// Relative tolerance for ties of the permutation statistic (see cluster_tests.h).
constexpr double kTieTolerance = 1e-10;

void require_finite(std::span<const double> v, const char* what, const char* name) {
  for (const double value : v) {
    if (!std::isfinite(value)) {
      throw std::invalid_argument(std::string(what) + ": " + name + " has a non-finite value");
    }
  }
}

// Σ_{i<k} |z_i − z_k| of the merged sorted samples a and b (either may be empty), as
// Σ_k (z_(k) − c)(2k − N − 1) with k 1-based. The coefficients sum to 0, so subtracting the
// centre c changes nothing in exact arithmetic and keeps large offsets from cancelling.
double merged_pair_sum(const std::vector<double>& a, const std::vector<double>& b, double c) {
  const std::size_t n = a.size() + b.size();
  double sum = 0.0;
  std::size_t i = 0, j = 0;
  for (std::size_t k = 0; k < n; ++k) {
    double z;
    if (j == b.size() || (i < a.size() && a[i] <= b[j])) {
      z = a[i++];
    } else {
      z = b[j++];
    }
    sum += (z - c) * (2.0 * static_cast<double>(k) - static_cast<double>(n) + 1.0);
  }
  return sum;
}

// Energy distance of two non-empty samples; sorts them in place.
double energy_distance_in_place(std::vector<double>& x, std::vector<double>& y) {
  std::sort(x.begin(), x.end());
  std::sort(y.begin(), y.end());
  const double c = 0.5 * (std::min(x.front(), y.front()) + std::max(x.back(), y.back()));
  const std::vector<double> none;
  const double sxx = merged_pair_sum(x, none, c);  // Σ_{i<k} |x_i − x_k|
  const double syy = merged_pair_sum(y, none, c);
  const double sxy = merged_pair_sum(x, y, c) - sxx - syy;  // Σ_{i,j} |x_i − y_j|
  const double n = static_cast<double>(x.size()), m = static_cast<double>(y.size());
  // Ordered pairs: the within-sample sums count every unordered pair twice.
  return 2.0 * sxy / (n * m) - 2.0 * sxx / (n * n) - 2.0 * syy / (m * m);
}

// Cluster ids mapped to 0..C−1 in order of first appearance.
struct DenseClusters {
  std::vector<int> index;  // per point
  int count = 0;
};

DenseClusters dense_clusters(std::span<const int> cluster) {
  DenseClusters out;
  out.index.reserve(cluster.size());
  std::unordered_map<int, int> seen;
  for (const int id : cluster) {
    const auto [it, inserted] = seen.try_emplace(id, out.count);
    if (inserted) ++out.count;
    out.index.push_back(it->second);
  }
  return out;
}

// Value at 1-based position h of sorted v, linearly interpolated and clamped to 1..size.
double order_statistic(const std::vector<double>& v, double h) {
  const double last = static_cast<double>(v.size());
  h = std::clamp(h, 1.0, last);
  const double below = std::floor(h);
  const auto k = static_cast<std::size_t>(below) - 1;
  if (k + 1 >= v.size()) return v.back();
  return v[k] + (h - below) * (v[k + 1] - v[k]);
}

}  // namespace

double energy_distance(std::span<const double> x, std::span<const double> y) {
  constexpr const char* kWhat = "energy_distance";
  if (x.empty() || y.empty()) {
    throw std::invalid_argument("energy_distance: both samples must be non-empty (got " +
                                std::to_string(x.size()) + " and " + std::to_string(y.size()) +
                                " values)");
  }
  require_finite(x, kWhat, "x");
  require_finite(y, kWhat, "y");
  std::vector<double> xs(x.begin(), x.end()), ys(y.begin(), y.end());
  return energy_distance_in_place(xs, ys);
}

PermutationTest cluster_swap_energy_test(std::span<const double> x, std::span<const double> y,
                                         std::span<const int> cluster, int replicates,
                                         std::uint64_t seed, std::uint32_t sub_index) {
  constexpr const char* kWhat = "cluster_swap_energy_test";
  if (x.size() != y.size() || x.size() != cluster.size()) {
    throw std::invalid_argument(std::string(kWhat) +
                                ": x, y and cluster must have the same length (got " +
                                std::to_string(x.size()) + ", " + std::to_string(y.size()) +
                                " and " + std::to_string(cluster.size()) + ")");
  }
  if (x.empty()) throw std::invalid_argument(std::string(kWhat) + ": no points");
  if (replicates < 1) {
    throw std::invalid_argument(std::string(kWhat) + ": replicates must be >= 1 (got " +
                                std::to_string(replicates) + ")");
  }
  require_finite(x, kWhat, "x");
  require_finite(y, kWhat, "y");

  const DenseClusters dc = dense_clusters(cluster);
  PermutationTest out;
  out.replicates = replicates;
  out.clusters = dc.count;

  std::vector<double> xs(x.begin(), x.end()), ys(y.begin(), y.end());
  out.statistic = energy_distance_in_place(xs, ys);
  double scale = 0.0;
  for (std::size_t k = 0; k < x.size(); ++k) {
    scale = std::max({scale, std::abs(x[k]), std::abs(y[k])});
  }
  xs = {};
  ys = {};

  // A swap moves values between x and y but never changes the pooled sample, so it is sorted
  // once; each replicate walks it in order, giving every value its rank within its (swapped)
  // sample: Σ_{i<k} |x_i − x_k| = Σ_k (x_(k) − c)(2k − n − 1) as in merged_pair_sum, and
  // E = 2 S_xy / n² − 2 S_xx / n² − 2 S_yy / n² with S_xy = T − S_xx − S_yy, T the pooled sum:
  // O(N) per replicate instead of a sort.
  const std::size_t n = x.size();
  struct Pooled {
    double value;
    std::uint32_t point;  // index k of the pair
    bool from_y;
  };
  std::vector<Pooled> pooled;
  pooled.reserve(2 * n);
  for (std::size_t k = 0; k < n; ++k) {
    pooled.push_back({x[k], static_cast<std::uint32_t>(k), false});
    pooled.push_back({y[k], static_cast<std::uint32_t>(k), true});
  }
  std::sort(pooled.begin(), pooled.end(), [](const Pooled& a, const Pooled& b) {
    return a.value < b.value ||
           (a.value == b.value &&
            (a.point < b.point || (a.point == b.point && a.from_y < b.from_y)));
  });
  const double c = 0.5 * (pooled.front().value + pooled.back().value);
  const double dn = static_cast<double>(n);
  double total = 0.0;  // T = Σ_{i<k} |z_i − z_k| over the pooled 2n values
  for (std::size_t k = 0; k < pooled.size(); ++k) {
    total += (pooled[k].value - c) * (2.0 * static_cast<double>(k) - 2.0 * dn + 1.0);
  }
  // In pooled order: the value less c, its cluster, and whether it came from y — three arrays
  // read in sequence by every replicate (the cluster looked up once, not per replicate).
  std::vector<double> centred(pooled.size());
  std::vector<std::int32_t> pooled_cluster(pooled.size());
  std::vector<char> pooled_from_y(pooled.size());
  for (std::size_t k = 0; k < pooled.size(); ++k) {
    centred[k] = pooled[k].value - c;
    pooled_cluster[k] = dc.index[pooled[k].point];
    pooled_from_y[k] = pooled[k].from_y ? 1 : 0;
  }
  pooled = {};
  auto energy_with_swaps = [&](const std::vector<char>& swap) {
    double sxx = 0.0, syy = 0.0, kx = 0.0, ky = 0.0;
    for (std::size_t k = 0; k < centred.size(); ++k) {
      // Branch-free (a swap is a coin toss, so a branch would be mispredicted half the time):
      // the other sample's sum gains an exact 0.
      const double in_x =
          (pooled_from_y[k] != 0) == (swap[static_cast<std::size_t>(pooled_cluster[k])] != 0) ? 1.0
                                                                                              : 0.0;
      sxx += in_x * (centred[k] * (2.0 * kx - dn + 1.0));
      syy += (1.0 - in_x) * (centred[k] * (2.0 * ky - dn + 1.0));
      kx += in_x;
      ky += 1.0 - in_x;
    }
    const double sxy = total - sxx - syy;
    return 2.0 * (sxy - sxx - syy) / (dn * dn);
  };
  // The observed value on the same path, so the all-swapped replicate ties it exactly.
  const double observed = energy_with_swaps(std::vector<char>(static_cast<std::size_t>(dc.count)));
  const double threshold = observed - kTieTolerance * scale;

  // The replicates in parallel, each from its own stream; the count is an integer sum, the same
  // for any number of threads.
  const int at_least = tbb::parallel_reduce(
      tbb::blocked_range<int>(0, replicates), 0,
      [&](const tbb::blocked_range<int>& range, int count) {
        std::vector<char> swap(static_cast<std::size_t>(dc.count));
        for (int r = range.begin(); r < range.end(); ++r) {
          RandomStream rng(seed, static_cast<std::uint32_t>(r), kDiagnoseNullStream, sub_index);
          for (char& s : swap) s = rng.uniform() < 0.5 ? 1 : 0;
          if (energy_with_swaps(swap) >= threshold) ++count;
        }
        return count;
      },
      std::plus<int>());
  out.p_value = (1.0 + at_least) / (replicates + 1.0);
  return out;
}

BootstrapInterval cluster_bootstrap_rms(std::span<const double> r, std::span<const int> cluster,
                                        int replicates, std::uint64_t seed, std::uint32_t sub_index,
                                        double level) {
  constexpr const char* kWhat = "cluster_bootstrap_rms";
  if (r.size() != cluster.size()) {
    throw std::invalid_argument(std::string(kWhat) + ": r and cluster must have the same length " +
                                "(got " + std::to_string(r.size()) + " and " +
                                std::to_string(cluster.size()) + ")");
  }
  if (r.empty()) throw std::invalid_argument(std::string(kWhat) + ": no points");
  if (replicates < 1) {
    throw std::invalid_argument(std::string(kWhat) + ": replicates must be >= 1 (got " +
                                std::to_string(replicates) + ")");
  }
  if (!(level > 0.0 && level < 1.0)) {
    throw std::invalid_argument(std::string(kWhat) + ": level must be in (0, 1) (got " +
                                std::to_string(level) + ")");
  }
  require_finite(r, kWhat, "r");

  const DenseClusters dc = dense_clusters(cluster);
  const auto c_count = static_cast<std::size_t>(dc.count);
  // Per cluster: Σ r² and the number of points.
  std::vector<double> sum_sq(c_count, 0.0), points(c_count, 0.0);
  double total_sq = 0.0;
  for (std::size_t k = 0; k < r.size(); ++k) {
    const auto c = static_cast<std::size_t>(dc.index[k]);
    sum_sq[c] += r[k] * r[k];
    points[c] += 1.0;
    total_sq += r[k] * r[k];
  }

  BootstrapInterval out;
  out.estimate = std::sqrt(total_sq / static_cast<double>(r.size()));
  out.level = level;
  out.replicates = replicates;
  out.clusters = dc.count;

  std::vector<double> rms(static_cast<std::size_t>(replicates));
  for (int b = 0; b < replicates; ++b) {
    RandomStream rng(seed, static_cast<std::uint32_t>(b), kDiagnoseNullStream, sub_index);
    double sq = 0.0, n = 0.0;
    for (int draw = 0; draw < dc.count; ++draw) {
      // uniform() is in (0, 1]; the clamp keeps u = 1 on the last cluster.
      const auto c = std::min(static_cast<std::size_t>(rng.uniform() * dc.count), c_count - 1);
      sq += sum_sq[c];
      n += points[c];
    }
    rms[static_cast<std::size_t>(b)] = std::sqrt(sq / n);
  }
  std::sort(rms.begin(), rms.end());
  const double alpha = 0.5 * (1.0 - level);
  out.lo = order_statistic(rms, (replicates + 1.0) * alpha);
  out.hi = order_statistic(rms, (replicates + 1.0) * (1.0 - alpha));
  return out;
}

}  // namespace gearmc
