// A claim's per-gear summaries and its verdict at a look (see claim_tracker.h for the method).
#include "engine/apps/check/claim_tracker.h"

#include <algorithm>
#include <cmath>

#include "engine/apps/check/confidence_sequences.h"

namespace gearmc {
namespace {

constexpr const char* kQuantileMethod =
    "betting confidence sequence on per-gear exceedance fractions (Waudby-Smith & Ramdas 2024)";
constexpr const char* kMomentMethod =
    "asymptotic confidence sequence on per-gear moments (Waudby-Smith et al. 2024)";
constexpr const char* kMaxMethod = "no value beyond the limit in any gear (exact)";

// Gears before the first look whose values are kept to place the grid.
double ratio(double a, double b) { return b > 0.0 ? a / b : 0.0; }

}  // namespace

const char* verdict_text(Verdict verdict) {
  switch (verdict) {
    case Verdict::kHolds:
      return "holds";
    case Verdict::kFails:
      return "fails";
    case Verdict::kUndecided:
      return "undecided";
  }
  return "undecided";
}

ClaimTracker::ClaimTracker(ClaimSpec claim) : claim_(std::move(claim)) {}

void ClaimTracker::add_gear(std::span<const double> values) {
  ++gears_;
  std::size_t finite = 0;
  double sum = 0.0, squares = 0.0, beyond = 0.0;
  const double L = claim_.limit_um;
  const bool max_claim = claim_.statistic == ClaimStatistic::kMax;
  for (double v : values) {
    if (!std::isfinite(v)) continue;  // counted by the run as non-finite, never a value here
    ++finite;
    sum += v;
    squares += v * v;
    min_ = std::min(min_, v);
    max_ = std::max(max_, v);
    const bool past = claim_.at_most ? v > L : (max_claim ? v >= L : v < L);
    beyond += past ? 1.0 : 0.0;
  }
  if (finite == 0) {
    ++empty_gears_;
    return;
  }
  count_.push_back(static_cast<double>(finite));
  beyond_.push_back(beyond);
  sum_.push_back(sum);
  squares_.push_back(squares);
  if (!pooled_) {
    pending_.emplace_back(values.begin(), values.end());
  } else {
    add_to_grid(values);
  }
}

void ClaimTracker::fix_grid() {
  const double L = claim_.limit_um;
  double lo = std::isfinite(min_) ? std::min(min_, L) : L;
  double hi = std::isfinite(max_) ? std::max(max_, L) : L;
  double span = hi - lo;
  if (!(span > 0.0)) span = std::max(std::abs(L), 1.0);
  lo -= 0.25 * span;
  hi += 0.25 * span;
  pooled_.emplace(lo, (hi - lo) / kGridBins, kGridBins);
  for (const std::vector<double>& gear : pending_) add_to_grid(gear);
  pending_.clear();
  pending_.shrink_to_fit();
}

void ClaimTracker::add_to_grid(std::span<const double> values) {
  const bool per_gear = claim_.statistic == ClaimStatistic::kQuantile;
  const std::size_t first = grid_counts_.size();
  if (per_gear) grid_counts_.resize(first + kGridBins + 2, 0);
  bool any = false;
  for (double v : values) {
    if (!std::isfinite(v)) continue;
    any = true;
    pooled_->add(v);
    if (!per_gear) continue;
    const double position = (v - pooled_->lo()) / pooled_->width();
    const std::size_t index = position < 0.0          ? 0
                              : position >= kGridBins ? kGridBins + 1
                                                      : static_cast<std::size_t>(position) + 1;
    ++grid_counts_[first + index];
  }
  if (per_gear && !any) grid_counts_.resize(first);  // a gear without values has no row
}

ClaimResult ClaimTracker::look(bool final_look, bool with_um_bounds) {
  if (!pooled_) fix_grid();
  ClaimResult r;
  switch (claim_.statistic) {
    case ClaimStatistic::kQuantile:
      r = quantile_look(with_um_bounds);
      break;
    case ClaimStatistic::kMean:
    case ClaimStatistic::kStd:
    case ClaimStatistic::kExpandedUncertainty:
    case ClaimStatistic::kUOverT:
      r = moment_look();
      break;
    case ClaimStatistic::kMax:
      r = max_look(final_look);
      break;
  }
  r.gears = gears_;
  return r;
}

ClaimResult ClaimTracker::quantile_look(bool with_um_bounds) const {
  ClaimResult r;
  r.method = kQuantileMethod;
  const double alpha = 1.0 - claim_.confidence;
  const double allowed = claim_.at_most ? 1.0 - claim_.quantile : claim_.quantile;
  r.exceedance_allowed = allowed;
  const std::size_t t = count_.size();
  if (t == 0) return r;
  std::vector<double> x(t);
  for (std::size_t g = 0; g < t; ++g) x[g] = beyond_[g] / count_[g];
  const bool holds = betting_rejects_mean_at_least(x, allowed, alpha);
  const bool fails = betting_rejects_mean_at_most(x, allowed, alpha);
  r.verdict = holds == fails ? Verdict::kUndecided : holds ? Verdict::kHolds : Verdict::kFails;
  r.estimate_um = pooled_->quantile(claim_.quantile);
  r.resolution_um = pooled_->width();
  if (!with_um_bounds) return r;
  const MeanBounds b = betting_mean_bounds(x, alpha);
  r.exceedance = b.estimate;
  r.exceedance_lower = b.lower;
  r.exceedance_upper = b.upper;

  // The bound in µm: the test "q_p ≤ T" at grid edges T = e_j, with the gear's fraction of
  // values ≥ e_j (at bin resolution) in place of its fraction beyond L. upper = the lowest edge
  // from which on "q_p ≤ T" holds; lower = the highest edge up to which it fails. Both tests
  // reject more as T moves away from the quantile (every gear's fraction falls as T grows), so
  // each edge is found by bisection over the grid.
  const double excess = 1.0 - claim_.quantile;
  const std::size_t row = kGridBins + 2;
  std::vector<std::uint32_t> suffix(t * (row + 1), 0);  // per gear: count in storage ≥ i
  for (std::size_t g = 0; g < t; ++g) {
    for (std::size_t i = row; i-- > 0;) {
      suffix[g * (row + 1) + i] = suffix[g * (row + 1) + i + 1] + grid_counts_[g * row + i];
    }
  }
  // Edge j (0 … kGridBins) starts storage index j + 1.
  std::vector<double> a(t);
  const auto fractions = [&](int j) -> std::span<const double> {
    for (std::size_t g = 0; g < t; ++g) a[g] = ratio(suffix[g * (row + 1) + j + 1], count_[g]);
    return a;
  };
  const auto holds_at = [&](int j) {
    return betting_rejects_mean_at_least(fractions(j), excess, alpha);
  };
  const auto fails_at = [&](int j) {
    return betting_rejects_mean_at_most(fractions(j), excess, alpha);
  };
  int upper_edge = -1;
  if (holds_at(kGridBins)) {
    int lo = -1, hi = kGridBins;  // holds at hi; lo = not known to hold
    if (holds_at(0))
      hi = 0;
    else
      lo = 0;
    while (hi - lo > 1) {
      const int mid = (lo + hi) / 2;
      (holds_at(mid) ? hi : lo) = mid;
    }
    upper_edge = hi;
  }
  int lower_edge = -1;
  if (fails_at(0)) {
    int lo = 0, hi = kGridBins + 1;  // fails at lo; hi = not known to fail
    if (fails_at(kGridBins))
      lo = kGridBins;
    else
      hi = kGridBins;
    while (hi - lo > 1) {
      const int mid = (lo + hi) / 2;
      (fails_at(mid) ? lo : hi) = mid;
    }
    lower_edge = lo;
  }
  if (upper_edge >= 0) r.upper_um = pooled_->edge(upper_edge);
  if (lower_edge >= 0) r.lower_um = pooled_->edge(lower_edge);
  // The verdict is the same test at the limit itself, exactly (each gear's fraction beyond L, not
  // at bin resolution): a decided claim puts the limit on its side of the bound, so the bound
  // never contradicts the verdict ("holds" with an upper bound a bin above L).
  const double limit = claim_.limit_um;
  const bool below = claim_.at_most ? r.verdict == Verdict::kHolds : r.verdict == Verdict::kFails;
  const bool above = claim_.at_most ? r.verdict == Verdict::kFails : r.verdict == Verdict::kHolds;
  if (below && !(r.upper_um <= limit)) r.upper_um = limit;  // q_p ≤ L shown
  if (above && !(r.lower_um >= limit)) r.lower_um = limit;  // q_p ≥ L shown
  const bool no_upper = !std::isfinite(r.upper_um), no_lower = !std::isfinite(r.lower_um);
  if (no_upper || no_lower) {
    r.note = std::string("no ") + (no_upper ? "upper" : "lower") +
             " bound in µm: at no value of the grid (" + std::to_string(t) +
             " gears) is the quantile shown to be " + (no_upper ? "below" : "above") +
             " it; more gears would give one";
  }
  return r;
}

ClaimResult ClaimTracker::moment_look() const {
  ClaimResult r;
  r.method = kMomentMethod;
  const std::size_t t = count_.size();
  if (t < 2) return r;
  const double alpha = bound_alpha(claim_);
  std::vector<double> means(t);
  for (std::size_t g = 0; g < t; ++g) means[g] = sum_[g] / count_[g];
  if (claim_.statistic == ClaimStatistic::kMean) {
    const MeanBounds b = asymptotic_mean_bounds(means, alpha);
    r.estimate_um = b.estimate;
    r.lower_um = b.lower;
    r.upper_um = b.upper;
  } else if (claim_.statistic == ClaimStatistic::kExpandedUncertainty ||
             claim_.statistic == ClaimStatistic::kUOverT) {
    // U = 2 √m2, m2 = E[v²] the mean over gears of each gear's mean of v²: the same sequence on
    // those per-gear means, and U's bounds its monotone image (a lower bound of m2 below 0 is 0).
    std::vector<double> second(t);
    for (std::size_t g = 0; g < t; ++g) second[g] = squares_[g] / count_[g];
    const MeanBounds b = asymptotic_mean_bounds(second, alpha);
    r.estimate_um = 2.0 * std::sqrt(std::max(0.0, b.estimate));
    r.lower_um = 2.0 * std::sqrt(std::max(0.0, b.lower));
    r.upper_um = 2.0 * std::sqrt(std::max(0.0, b.upper));
    if (claim_.statistic == ClaimStatistic::kUOverT) {
      // U/T: the same bounds over the (fixed) tolerance width, a monotone image again.
      const double w = claim_.tolerance_width_um;
      r.estimate_um /= w;
      r.lower_um /= w;
      r.upper_um /= w;
    }
  } else {
    // σ² = E[s2] − μ², s1, s2 the gear's means of v and v² (gears weighted equally). The
    // delta method linearises the estimator to the per-gear values z = s2 − 2 μ s1, whose
    // standard deviation enters the sequence's width.
    double mu = 0.0, m2 = 0.0;
    for (std::size_t g = 0; g < t; ++g) {
      mu += means[g];
      m2 += squares_[g] / count_[g];
    }
    mu /= static_cast<double>(t);
    m2 /= static_cast<double>(t);
    const double variance = std::max(0.0, m2 - mu * mu);
    std::vector<double> z(t);
    double z_mean = 0.0;
    for (std::size_t g = 0; g < t; ++g) {
      z[g] = squares_[g] / count_[g] - 2.0 * mu * means[g];
      z_mean += z[g];
    }
    z_mean /= static_cast<double>(t);
    double z_squares = 0.0;
    for (double v : z) z_squares += (v - z_mean) * (v - z_mean);
    const double w = asymptotic_half_width(std::sqrt(z_squares / static_cast<double>(t - 1)),
                                           static_cast<double>(t), alpha);
    r.estimate_um = std::sqrt(variance);
    r.lower_um = std::sqrt(std::max(0.0, variance - w));
    r.upper_um = std::sqrt(variance + w);
  }
  const double L = claim_.limit_um;
  const bool above = r.lower_um > L, below = r.upper_um < L;
  if (claim_.two_sided) {
    // a ≤ statistic ≤ b: holds when both bounds are inside, fails when one is past a limit
    // on the far side (the whole confidence interval outside).
    const double a = claim_.lower_limit_um;
    const bool inside = r.lower_um > a && below;
    const bool outside = r.upper_um < a || above;
    r.verdict = inside ? Verdict::kHolds : outside ? Verdict::kFails : Verdict::kUndecided;
  } else if (claim_.at_most) {
    r.verdict = below ? Verdict::kHolds : above ? Verdict::kFails : Verdict::kUndecided;
  } else {
    r.verdict = above ? Verdict::kHolds : below ? Verdict::kFails : Verdict::kUndecided;
  }
  return r;
}

ClaimResult ClaimTracker::max_look(bool final_look) const {
  ClaimResult r;
  r.method = kMaxMethod;
  const std::size_t t = count_.size();
  if (t == 0) return r;
  double gears_beyond = 0.0;
  for (double b : beyond_) gears_beyond += b > 0.0 ? 1.0 : 0.0;
  r.estimate_um = max_;
  r.lower_um = max_;  // the largest value seen: the population's maximum is at least this
  r.exceedance = gears_beyond / static_cast<double>(t);
  r.exceedance_allowed = 0.0;
  const bool seen = gears_beyond > 0.0;
  if (seen) {
    r.verdict = claim_.at_most ? Verdict::kFails : Verdict::kHolds;
    r.note = claim_.at_most ? "a value beyond the limit was seen: the maximum exceeds it"
                            : "a value at or beyond the limit was seen";
    return r;
  }
  // None in t gears: with confidence c the probability that a gear shows one is below
  // 1 − (1 − c)^(1/t) (the exact binomial bound for zero events, Clopper & Pearson 1934).
  r.exceedance_upper = 1.0 - std::pow(1.0 - claim_.confidence, 1.0 / static_cast<double>(t));
  r.exceedance_lower = 0.0;
  if (final_look) {
    r.verdict = claim_.at_most ? Verdict::kHolds : Verdict::kFails;
    r.note = "no value beyond the limit in " + std::to_string(t) +
             " gears; a maximum is never proven by a sample: with this confidence, fewer than " +
             "the bound's fraction of gears would show one";
  }
  return r;
}

}  // namespace gearmc
