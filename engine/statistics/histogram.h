// A fixed-width histogram for streaming quantiles (docs/architecture.md, principle 3): bins of
// width w from lo, integer counts, underflow/overflow counters with the exact min and max of the
// values that fell outside, and the exact overall min and max. Merging adds integer counts, so it
// is exact and independent of the merge order. Quantiles are returned at bin resolution with a
// stated, one-sided error (see quantile()); the "most probable value" of P1 (docs/sources.md, Table
// 2) is the centre of the fullest bin of a coarser display histogram (see mode()). Units: µm for
// δRcomp, but nothing here depends on the unit.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace gearmc {

// The 1-based rank k = ceil(p n), clamped to [1, n], of the order statistic x_(k) that is the
// p-quantile of n sorted values: the inverse of the empirical CDF (Hyndman & Fan 1996,
// "Sample quantiles in statistical packages", definition 1). Requires n >= 1 and 0 <= p <= 1.
std::uint64_t quantile_rank(double p, std::uint64_t n);

class Histogram {
 public:
  // `bins` bins of width `width_um` starting at `lo_um`: bin i holds the values x with
  // edge(i) <= x < edge(i + 1), edge(i) = lo + i w (computed exactly as written, in double).
  // Values below lo are underflow, values >= edge(bins) are overflow. Throws
  // std::invalid_argument unless width > 0, bins >= 1 and lo finite.
  // Example: Histogram(0.0, 0.001, 20000) covers 0 to 20 µm at 1 nm resolution (160 kB).
  Histogram(double lo_um, double width_um, std::size_t bins);

  // Adds one value (µm). +inf goes to overflow, -inf to underflow; a NaN is counted only in
  // invalid() and nowhere else.
  void add(double x) { add(x, 1); }
  // Adds `count` copies of x (e.g. when re-binning a RelativeHistogram).
  void add(double x, std::uint64_t count);
  // Sets the overall extremes (e.g. the exact ones of the values a re-binned histogram came
  // from); the under/overflow extremes stay as added.
  void set_extremes(double min, double max);

  // Adds the counts of `other`, which must have the same lo, width and bin count (bitwise);
  // throws std::invalid_argument otherwise. Exact: the result does not depend on merge order.
  void merge(const Histogram& other);

  double lo() const { return lo_; }
  double width() const { return width_; }
  std::size_t bin_count() const { return counts_.size(); }
  // edge(i) = lo + i w, i = 0 .. bin_count() (µm). hi() = edge(bin_count()).
  double edge(std::size_t i) const { return lo_ + static_cast<double>(i) * width_; }
  double hi() const { return edge(counts_.size()); }
  double centre(std::size_t i) const { return lo_ + (static_cast<double>(i) + 0.5) * width_; }
  std::uint64_t count(std::size_t i) const { return counts_[i]; }
  const std::vector<std::uint64_t>& counts() const { return counts_; }

  std::uint64_t underflow() const { return underflow_; }
  std::uint64_t overflow() const { return overflow_; }
  std::uint64_t invalid() const { return invalid_; }
  // All finite-or-infinite values added: underflow + overflow + sum of bin counts (not NaNs).
  std::uint64_t total() const { return total_; }

  // Exact extremes (µm) of all values, of the underflow values and of the overflow values;
  // NaN when the respective set is empty.
  double min() const;
  double max() const;
  double underflow_min() const;
  double underflow_max() const;
  double overflow_min() const;
  double overflow_max() const;

  // The p-quantile (0 <= p <= 1) at bin resolution (µm). With k = quantile_rank(p, total()),
  // returns min(upper edge of the bin in which the cumulative count, underflow included, first
  // reaches k, max()). The exact sample quantile x_(k) (Hyndman & Fan definition 1) lies in
  // that bin, so  x_(k) <= quantile(p) <= x_(k) + w : a conservative (upper) bound with error at
  // most one bin width. Outside the binned range: if x_(k) is an underflow value, returns
  // underflow_max() (>= x_(k)); if an overflow value, returns max() (>= x_(k), not within w).
  // p = 0 returns min(), p = 1 returns max(), both exact. NaN when empty.
  double quantile(double p) const;

  // The histogram with bins `factor` times wider (a display histogram): same lo, bin_count /
  // factor bins, counts summed, under/overflow and extremes carried over. Throws
  // std::invalid_argument unless factor >= 1 divides bin_count().
  Histogram rebin(std::size_t factor) const;
  // The factor that turns this width into `display_width_um`; throws std::invalid_argument
  // unless the ratio is an integer (to 1e-9 relative) that divides bin_count().
  std::size_t rebin_factor(double display_width_um) const;

  // P1's "E (most probable)" (docs/sources.md, Table 2): the centre (µm) of the fullest bin of the
  // display histogram rebin(rebin_factor(display_width_um)); ties go to the lower bin. It is a
  // property of the display width, not of the data alone: a narrower width gives a noisier,
  // a wider one a coarser answer (P1's Fig. 5 uses bins of about 0.2 µm; default 0.1 µm).
  // Under/overflow are not candidates. NaN when no value lies in the binned range.
  double mode(double display_width_um = 0.1) const;

  // The bins as CSV: header "bin_lo_um,bin_hi_um,count", one row per bin, then rows
  // "underflow,,N" and "overflow,,N". Edges printed with 17 significant digits at most.
  std::string to_csv() const;

  bool operator==(const Histogram&) const = default;

 private:
  double lo_, width_;
  std::vector<std::uint64_t> counts_;
  std::uint64_t underflow_ = 0, overflow_ = 0, invalid_ = 0, total_ = 0;
  double min_ = 0, max_ = 0;
  double underflow_min_ = 0, underflow_max_ = 0;
  double overflow_min_ = 0, overflow_max_ = 0;
};

}  // namespace gearmc
