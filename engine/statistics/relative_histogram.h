// A streaming histogram with a stated RELATIVE resolution over the whole range of doubles, for
// the error statistics of a run: a scenario can produce errors from 0.01 µm (P1's δRcomp on a
// good gear) to millimetres (a coarse gear with a large stylus), and every quantile, mode and
// law fit must be right at any of these scales (docs/architecture.md principle 3: streaming, exact
// merges).
//
// Buckets are read off the bits of the IEEE 754 double: a positive x with biased exponent e and
// mantissa bits m falls in bucket (e, top kMantissaBits bits of m), so each power-of-two interval
// [2^k, 2^(k+1)) is cut into 2^kMantissaBits = 4096 equal buckets of width 2^(k-12). A bucket
// [a, b) therefore has b - a <= 2^-12 a (about 2.4e-4 relative), its edges are exact doubles and
// membership is exact (no rounding: the bucket of x is a bit shift of x). Negative values use the
// same buckets for |x|; zero, +inf and -inf have a count each; NaN is counted as invalid only.
// Counts are integers and merging adds them, so the result does not depend on the order of the
// merges (bit-identical for any thread count). Memory: 32 KiB per occupied power of two and sign
// (a run whose values span 0.001–100 µm uses 17 of them, 0.5 MiB).
//
// Nothing here depends on the unit; the engine uses µm.
// Public API (docs/api.md): a stable part of the C++ interface, installed with its includes.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "core/bytes.h"
#include "engine/statistics/histogram.h"

namespace gearmc {

class RelativeHistogram {
 public:
  static constexpr int kMantissaBits = 12;
  // The largest (b - a) / a of a bucket [a, b) of positive values: 2^-12.
  static constexpr double kRelativeResolution = 1.0 / 4096.0;

  RelativeHistogram();
  RelativeHistogram(const RelativeHistogram& other);
  RelativeHistogram& operator=(const RelativeHistogram& other);
  RelativeHistogram(RelativeHistogram&&) noexcept;
  RelativeHistogram& operator=(RelativeHistogram&&) noexcept;
  ~RelativeHistogram();

  // Adds one value. NaN goes to invalid() only; +-inf are counted in total() and the extremes.
  void add(double x);
  // Adds the counts of `other` (exact; independent of the order of merges).
  void merge(const RelativeHistogram& other);

  std::uint64_t total() const { return total_; }  // every non-NaN value added
  std::uint64_t invalid() const { return invalid_; }
  // Exact extremes of the values added; NaN when empty.
  double min() const;
  double max() const;

  // The p-quantile (0 <= p <= 1): with k = quantile_rank(p, total()) (Hyndman & Fan 1996,
  // definition 1, see histogram.h), the upper edge of the bucket that holds the order statistic
  // x_(k), clamped to [min(), max()]. So
  //   x_(k) <= quantile(p) <= x_(k) + 2^-12 |x_(k)|   (exact when x_(k) is 0 or infinite):
  // a conservative (upper) bound with a relative error of at most 2.4e-4, at any scale.
  // p = 0 gives min(), p = 1 max(), both exact. NaN when empty. Throws std::invalid_argument
  // unless 0 <= p <= 1.
  double quantile(double p) const;

  // Whether quantile(p) is an estimate the data can support: at least one value lies above the
  // rank k (n (1 - p) >= 1, i.e. n >= min_count_for_quantile(p)); otherwise quantile(p) is just
  // the maximum. 0.9973 needs 371 values, 0.95 needs 20.
  static std::uint64_t min_count_for_quantile(double p);

  // Bounds of the number of values >= t: {values in buckets entirely at or above t, that plus the
  // values of the bucket that straddles t}. Equal when t is a bucket edge (e.g. any power of two
  // or 0) or no value shares t's bucket.
  struct CountBounds {
    std::uint64_t at_least, at_most;
  };
  CountBounds count_at_least(double t) const;

  // The values re-binned into the fixed-width Histogram(lo, width, bins) (e.g. for plots, the
  // mode and law fits). Each bucket's count goes to the bin that holds the bucket's centre, so a
  // value is placed at most one bucket width (2^-12 of its size) from its true bin; extremes and
  // the under/overflow counts carry over (the under/overflow extremes are bucket-accurate).
  Histogram to_histogram(double lo, double width, std::size_t bins) const;

  // Visits the occupied buckets in increasing order of value: f(lower edge, upper edge, count).
  // Zero is a bucket [0, 0]; -inf and +inf are buckets [-inf, -inf] and [inf, inf].
  void for_each_bucket(const std::function<void(double, double, std::uint64_t)>& f) const;

  // The counts, extremes and totals as bytes (core/bytes.h: occupied buckets only), and
  // back exactly: partial results of other processes.
  void encode(std::string& out) const;
  static RelativeHistogram decode(ByteReader& in);

  // The same multiset of bucket counts (not the storage layout).
  bool operator==(const RelativeHistogram& other) const;

 private:
  // x into the extremes and the total (every value that is not NaN).
  void count_value(double x) {
    if (total_ == 0) {
      min_ = max_ = x;
    } else {
      min_ = std::min(min_, x);
      max_ = std::max(max_, x);
    }
    ++total_;
  }
  struct Side;  // the buckets of one sign: blocks of 4096 counters per biased exponent
  std::unique_ptr<Side> positive_, negative_;
  std::uint64_t zero_ = 0, plus_inf_ = 0, minus_inf_ = 0;
  std::uint64_t total_ = 0, invalid_ = 0;
  double min_ = 0, max_ = 0;
};

}  // namespace gearmc
