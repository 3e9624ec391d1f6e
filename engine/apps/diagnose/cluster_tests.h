// Cluster-aware statistics for the discrepancy diagnosis: a two-sample test and a bootstrap
// interval whose resampling moves whole clusters of points. The residuals of one CMM scan (one
// gear flank) are correlated — form errors, probe lobing and the fit itself act on the whole
// scan — so resampling single points would treat n correlated points as n independent ones and
// make tests too liberal and intervals too narrow. Here the unit of resampling is the cluster
// (flank or tooth) named by an arbitrary int per point; ids are mapped to 0..C−1 internally in
// order of first appearance, so the points of a cluster need not be contiguous.
//   * energy_distance: the 1-D energy distance of Székely & Rizzo ("Energy statistics: A class
//     of statistics based on distances", J. Stat. Plann. Inference 143, 2013),
//     E = 2 mean|x_i − y_j| − mean|x_i − x_k| − mean|y_j − y_l|, in the V-statistic form (means
//     over all ordered pairs, i = k included). E ≥ 0, and E = 0 only for equal samples (as
//     empirical laws). The pair sums come from sorted samples: for z_(1) ≤ … ≤ z_(N),
//     Σ_{i<k} (z_(k) − z_(i)) = Σ_k z_(k) (2k − N − 1), so the cost is O(N log N).
//   * cluster_swap_energy_test: a paired permutation test (Fisher's randomization test for
//     matched pairs; Good, "Permutation, Parametric, and Bootstrap Tests of Hypotheses", 3rd ed.,
//     Springer 2005) of "x and y come from the same law", where x[k] and y[k] are two observations
//     at the same point k (a measured residual and a model-simulated one). Under the null the
//     pair (x-cluster, y-cluster) is exchangeable, so each replicate swaps x and y on all points
//     of a cluster together, every cluster independently with probability 1/2, and recomputes
//     E (a swap never changes the pooled sample, so it is sorted once and each replicate only
//     re-labels it: O(N) per replicate); p = (1 + #{E* ≥ E}) / (replicates + 1), the Monte-Carlo
//     p-value of Davison & Hinkley
//     ("Bootstrap Methods and their Application", 1997, ch. 4), valid for any number of
//     replicates. Ties in exact arithmetic (e.g. the all-swapped replicate) are counted as
//     E* ≥ E despite rounding: E* ≥ E − 1e-10 · max|x, y|. E is symmetric in x and y, so swapping
//     every cluster gives E again: with C clusters there are at most 2^(C−1) distinct values of E*,
//     and p cannot drop below about 2^(1−C) however many replicates are drawn.
//   * cluster_bootstrap_rms: the percentile bootstrap interval of the RMS √(mean r²), resampling
//     clusters (Davison & Hinkley 1997, §3.8: draw C clusters with replacement out of the C,
//     keep all points of each drawn cluster). The interval limits are the order statistics of
//     the R replicate RMS values at positions (R + 1)(1 − level)/2 and (R + 1)(1 + level)/2
//     (the basic percentile method and the (R + 1)α order-statistic convention of Davison &
//     Hinkley, ch. 5), linearly interpolated between neighbours when the position is not an
//     integer and clamped to 1..R; choose R with (R + 1)(1 − level)/2 an integer (e.g. R = 999
//     for level 0.95). With a single cluster the interval collapses to the estimate (no
//     between-cluster information), and few clusters give too-narrow intervals (the bootstrap
//     variance of a mean of C cluster totals is (C − 1)/C times the unbiased one, and the RMS
//     behaves about the same).
// Units: µm (x, y, r, E, the RMS and its interval).
// Random numbers: counter-based streams RandomStream(seed, replicate, kDiagnoseNullStream,
// sub_index) as in the rest of the diagnosis (selection.h), so the same seed and sub-index give
// the same result on any machine; the caller picks a sub-index not used by other draws under the
// same seed (the selection steps use 0, 1, 2, …; the gap's null simulation uses 1000).
// Invalid input (different lengths, empty samples, replicates < 1, a level outside (0, 1),
// non-finite values) throws std::invalid_argument.
#pragma once

#include <cstdint>
#include <span>

namespace gearmc {

// 1-D energy distance of two samples (V-statistic form, see above); µm.
double energy_distance(std::span<const double> x, std::span<const double> y);

struct PermutationTest {
  double statistic = 0;  // energy distance of the observed x, y (µm)
  double p_value = 1;    // (1 + #{E* ≥ E}) / (replicates + 1)
  int replicates = 0;
  int clusters = 0;  // distinct cluster ids
};
// Paired cluster-swap permutation test of "x and y come from the same law" (see above); x, y and
// cluster have one entry per point.
PermutationTest cluster_swap_energy_test(std::span<const double> x, std::span<const double> y,
                                         std::span<const int> cluster, int replicates,
                                         std::uint64_t seed, std::uint32_t sub_index);

struct BootstrapInterval {
  double estimate = 0, lo = 0, hi = 0;  // RMS of the data and its percentile interval (µm)
  double level = 0.95;
  int replicates = 0;
  int clusters = 0;  // distinct cluster ids
};
// Percentile cluster-bootstrap interval of the RMS √(mean r²) (see above); r and cluster have
// one entry per point.
BootstrapInterval cluster_bootstrap_rms(std::span<const double> r, std::span<const int> cluster,
                                        int replicates, std::uint64_t seed, std::uint32_t sub_index,
                                        double level = 0.95);

}  // namespace gearmc
