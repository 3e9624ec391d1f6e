// Fixed-width histogram: exact integer counts, bin-resolution quantiles with a one-sided error of
// at most one bin width, display rebinning and the display-width mode (see histogram.h).
#include "engine/statistics/histogram.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "core/constants.h"
#include "core/number_text.h"

namespace gearmc {
namespace {}  // namespace

std::uint64_t quantile_rank(double p, std::uint64_t n) {
  if (n == 0 || !(p >= 0.0 && p <= 1.0)) {
    throw std::invalid_argument("quantile_rank: need n >= 1 and 0 <= p <= 1");
  }
  const double k = std::ceil(p * static_cast<double>(n));
  if (k <= 1.0) return 1;
  if (k >= static_cast<double>(n)) return n;
  return static_cast<std::uint64_t>(k);
}

Histogram::Histogram(double lo_um, double width_um, std::size_t bins)
    : lo_(lo_um), width_(width_um), counts_(bins, 0) {
  if (!(width_um > 0.0) || !std::isfinite(width_um) || bins == 0 || !std::isfinite(lo_um) ||
      !std::isfinite(edge(bins))) {
    throw std::invalid_argument("Histogram: need a finite lo, width > 0 and at least one bin");
  }
}

void Histogram::set_extremes(double min, double max) {
  min_ = min;
  max_ = max;
}

void Histogram::add(double x, std::uint64_t count) {
  if (count == 0) return;
  if (std::isnan(x)) {
    invalid_ += count;
    return;
  }
  if (total_ == 0) {
    min_ = max_ = x;
  } else {
    min_ = std::min(min_, x);
    max_ = std::max(max_, x);
  }
  total_ += count;
  if (x < lo_) {
    underflow_min_ = underflow_ == 0 ? x : std::min(underflow_min_, x);
    underflow_max_ = underflow_ == 0 ? x : std::max(underflow_max_, x);
    underflow_ += count;
    return;
  }
  const std::size_t bins = counts_.size();
  if (x >= edge(bins)) {
    overflow_min_ = overflow_ == 0 ? x : std::min(overflow_min_, x);
    overflow_max_ = overflow_ == 0 ? x : std::max(overflow_max_, x);
    overflow_ += count;
    return;
  }
  // The division is within a few ulp of the true ratio, so the index is off by at most one;
  // the correction makes membership agree exactly with edge(i) <= x < edge(i + 1).
  std::size_t i = std::min(static_cast<std::size_t>((x - lo_) / width_), bins - 1);
  if (x < edge(i)) {
    --i;  // i > 0 here, since x >= lo = edge(0)
  } else if (i + 1 < bins && x >= edge(i + 1)) {
    ++i;
  }
  counts_[i] += count;
}

void Histogram::merge(const Histogram& other) {
  if (other.lo_ != lo_ || other.width_ != width_ || other.counts_.size() != counts_.size()) {
    throw std::invalid_argument("Histogram::merge: the two histograms have different bins");
  }
  if (other.total_ > 0) {
    min_ = total_ == 0 ? other.min_ : std::min(min_, other.min_);
    max_ = total_ == 0 ? other.max_ : std::max(max_, other.max_);
  }
  if (other.underflow_ > 0) {
    underflow_min_ =
        underflow_ == 0 ? other.underflow_min_ : std::min(underflow_min_, other.underflow_min_);
    underflow_max_ =
        underflow_ == 0 ? other.underflow_max_ : std::max(underflow_max_, other.underflow_max_);
  }
  if (other.overflow_ > 0) {
    overflow_min_ =
        overflow_ == 0 ? other.overflow_min_ : std::min(overflow_min_, other.overflow_min_);
    overflow_max_ =
        overflow_ == 0 ? other.overflow_max_ : std::max(overflow_max_, other.overflow_max_);
  }
  for (std::size_t i = 0; i < counts_.size(); ++i) counts_[i] += other.counts_[i];
  underflow_ += other.underflow_;
  overflow_ += other.overflow_;
  invalid_ += other.invalid_;
  total_ += other.total_;
}

double Histogram::min() const { return total_ == 0 ? kNaN : min_; }
double Histogram::max() const { return total_ == 0 ? kNaN : max_; }
double Histogram::underflow_min() const { return underflow_ == 0 ? kNaN : underflow_min_; }
double Histogram::underflow_max() const { return underflow_ == 0 ? kNaN : underflow_max_; }
double Histogram::overflow_min() const { return overflow_ == 0 ? kNaN : overflow_min_; }
double Histogram::overflow_max() const { return overflow_ == 0 ? kNaN : overflow_max_; }

double Histogram::quantile(double p) const {
  if (!(p >= 0.0 && p <= 1.0)) throw std::invalid_argument("Histogram::quantile: need 0<=p<=1");
  if (total_ == 0) return kNaN;
  if (p == 0.0) return min_;
  if (p == 1.0) return max_;
  const std::uint64_t k = quantile_rank(p, total_);
  if (k <= underflow_) return underflow_max_;
  std::uint64_t cumulative = underflow_;
  for (std::size_t i = 0; i < counts_.size(); ++i) {
    cumulative += counts_[i];
    if (cumulative >= k) return std::min(edge(i + 1), max_);
  }
  return max_;  // x_(k) is an overflow value
}

std::size_t Histogram::rebin_factor(double display_width_um) const {
  const double ratio = display_width_um / width_;
  const double rounded = std::round(ratio);
  if (!(rounded >= 1.0) || std::abs(ratio - rounded) > 1e-9 * rounded ||
      rounded > static_cast<double>(counts_.size()) ||
      counts_.size() % static_cast<std::size_t>(rounded) != 0) {
    throw std::invalid_argument("Histogram: display width " + shortest_text(display_width_um) +
                                " is not a whole multiple of the bin width " +
                                shortest_text(width_) + " that divides the " +
                                std::to_string(counts_.size()) + " bins");
  }
  return static_cast<std::size_t>(rounded);
}

Histogram Histogram::rebin(std::size_t factor) const {
  if (factor == 0 || counts_.size() % factor != 0) {
    throw std::invalid_argument("Histogram::rebin: the factor must divide the bin count");
  }
  Histogram coarse(lo_, width_ * static_cast<double>(factor), counts_.size() / factor);
  for (std::size_t i = 0; i < counts_.size(); ++i) coarse.counts_[i / factor] += counts_[i];
  coarse.underflow_ = underflow_;
  coarse.overflow_ = overflow_;
  coarse.invalid_ = invalid_;
  coarse.total_ = total_;
  coarse.min_ = min_;
  coarse.max_ = max_;
  coarse.underflow_min_ = underflow_min_;
  coarse.underflow_max_ = underflow_max_;
  coarse.overflow_min_ = overflow_min_;
  coarse.overflow_max_ = overflow_max_;
  return coarse;
}

double Histogram::mode(double display_width_um) const {
  const Histogram display = rebin(rebin_factor(display_width_um));
  const auto fullest = std::max_element(display.counts_.begin(), display.counts_.end());
  if (*fullest == 0) return kNaN;
  // max_element returns the first of equal maxima: ties go to the lower bin.
  return display.centre(static_cast<std::size_t>(fullest - display.counts_.begin()));
}

std::string Histogram::to_csv() const {
  std::string csv = "bin_lo_um,bin_hi_um,count\n";
  for (std::size_t i = 0; i < counts_.size(); ++i) {
    csv += shortest_text(edge(i)) + ',' + shortest_text(edge(i + 1)) + ',' +
           std::to_string(counts_[i]) + '\n';
  }
  csv += "underflow,," + std::to_string(underflow_) + '\n';
  csv += "overflow,," + std::to_string(overflow_) + '\n';
  return csv;
}

}  // namespace gearmc
