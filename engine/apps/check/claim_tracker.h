// One accuracy claim decided from gears in the order they are drawn: the per-gear summaries a
// claim needs, and its verdict at a look. The unit of independence is the GEAR — the flanks of
// one gear share its eccentricity, runout and per-gear effect draws, so its values are
// correlated — and every bound is computed from one number (or pair) per gear, i.i.d. over
// gears (confidence_sequences.h):
// - quantile p, at_most L (q_p ≤ L ⇔ P(V > L) ≤ 1 − p): the gear's fraction of values beyond L,
//   X_g ∈ [0, 1], has mean P(V > L) for V a value of a random gear; holds when the betting
//   upper bound of that mean is below 1 − p, fails when the lower bound is above it. at_least L:
//   the fraction below L against p. The bound in µm is the same test inverted over the limit on
//   a grid of 256 bins per gear (resolution one bin width, stated in `resolution_um`).
// - mean: the gears' means (the population mean of V with gears weighted equally), asymptotic
//   confidence sequence. std: the standard deviation of V from the gears' means of v and v²,
//   the same sequence on the delta-method linearisation. Both need finite variances and are
//   large-sample (asymptotic) bounds. U = 2√E[v²] from the gears' means of v², U/T that over
//   the claim's tolerance width. Two-sided claims (a ≤ statistic ≤ b) take each bound at
//   (1 − c)/2.
// - max, at_most L: a claim no finite sample can prove. It fails as soon as one value beyond L
//   is seen (certain); it holds only at the budget with no value beyond L in any gear, and then
//   the probability that a gear shows one is below 1 − (1 − c)^(1/N) at confidence c (reported).
//   at_least L mirrors it (holds once a value ≥ L is seen).
#pragma once

#include <cstdint>
#include <limits>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "engine/scenario/claims.h"
#include "engine/statistics/histogram.h"

namespace gearmc {

enum class Verdict { kHolds, kFails, kUndecided };
const char* verdict_text(Verdict verdict);  // "holds", "fails", "undecided"

inline constexpr double kNoBound = std::numeric_limits<double>::quiet_NaN();

struct ClaimResult {
  Verdict verdict = Verdict::kUndecided;
  double estimate_um = kNoBound;  // the statistic's estimate
  // Confidence bounds on the statistic, each one-sided at the claim's confidence; NaN when the
  // data cannot bound it (e.g. beyond the histogram grid, or the upper bound of a max).
  double lower_um = kNoBound, upper_um = kNoBound;
  double resolution_um = 0.0;  // quantile claims: the grid's bin width (0: exact)
  // Quantile and max claims: the probability of a value beyond the limit (per gear for max)
  // with its one-sided bounds, and the largest probability the claim allows.
  std::optional<double> exceedance, exceedance_lower, exceedance_upper, exceedance_allowed;
  int gears = 0;        // gears the verdict rests on
  double time_s = 0.0;  // when it was reached (set by the caller)
  std::string method;   // the method's name
  std::string note;     // what the verdict means when it needs saying (max claims)
};

class ClaimTracker {
 public:
  static constexpr int kGridBins = 256;

  explicit ClaimTracker(ClaimSpec claim);

  // Adds the next gear's values of the claim's quantity and sides (any order within the gear).
  // A gear without values (every contact failed) counts as a gear with no information: it is
  // counted in gears_without_values() and left out of the bounds.
  void add_gear(std::span<const double> values);
  // The verdict on the gears added so far. `final_look`: the budget is reached (max claims can
  // only hold then). `with_um_bounds`: also the bounds (quantile claims: the exceedance
  // probability's bounds and the test inverted over the limit, which costs about 300 passes over
  // the gears); without, only the verdict and the estimate.
  ClaimResult look(bool final_look, bool with_um_bounds = true);

  const ClaimSpec& claim() const { return claim_; }
  int gears() const { return gears_; }
  int gears_without_values() const { return empty_gears_; }
  // All values added, on the per-gear grid (after the first look; empty before).
  const std::optional<Histogram>& pooled() const { return pooled_; }

 private:
  void fix_grid();
  void add_to_grid(std::span<const double> values);
  ClaimResult quantile_look(bool with_um_bounds) const;
  ClaimResult moment_look() const;
  ClaimResult max_look(bool final_look) const;

  ClaimSpec claim_;
  int gears_ = 0, empty_gears_ = 0;
  // Per gear with values, in order: count, count beyond the limit (v > L for at_most, v < L for
  // at_least; max: v ≥ L for at_least), Σ v, Σ v².
  std::vector<double> count_, beyond_, sum_, squares_;
  double min_ = std::numeric_limits<double>::infinity();
  double max_ = -std::numeric_limits<double>::infinity();
  // Quantile claims: per-gear counts on the grid (kGridBins + 2: underflow, bins, overflow),
  // fixed at the first look from the gears seen so far; until then their values are kept.
  std::vector<std::vector<double>> pending_;
  std::vector<std::uint32_t> grid_counts_;
  std::optional<Histogram> pooled_;
};

}  // namespace gearmc
