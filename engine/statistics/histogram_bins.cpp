// Freedman–Diaconis bins shared by several RelativeHistograms, and the mode on them (see
// histogram_bins.h).
#include "engine/statistics/histogram_bins.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace gearmc {
namespace {

// The smallest and largest finite bucket edges of the values (their finite range).
std::pair<double, double> finite_range(const RelativeHistogram& h) {
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  h.for_each_bucket([&](double a, double b, std::uint64_t) {
    if (std::isfinite(a)) lo = std::min(lo, a), hi = std::max(hi, a);
    if (std::isfinite(b)) lo = std::min(lo, b), hi = std::max(hi, b);
  });
  if (std::isfinite(h.min())) lo = std::max(lo, h.min());
  if (std::isfinite(h.max())) hi = std::min(hi, h.max());
  return {lo, hi};
}

}  // namespace

double nice_width_at_least(double x) {
  const double decade = std::pow(10.0, std::floor(std::log10(x)));
  for (double step : {1.0, 2.0, 5.0, 10.0}) {
    if (step * decade >= x * (1.0 - 1e-12)) return step * decade;
  }
  return 10.0 * decade;
}

double nice_width_nearest(double x) {
  const double up = nice_width_at_least(x);
  // The next smaller nice width: 5 -> 2, 2 -> 1, 1 -> 0.5 of the decade.
  const double mantissa = up / std::pow(10.0, std::floor(std::log10(up) + 1e-12));
  const double down = up * (mantissa > 4.0 ? 0.4 : 0.5);
  return x / down < up / x ? down : up;
}

HistogramBins freedman_diaconis_bins(const std::vector<const RelativeHistogram*>& data,
                                     std::size_t max_bins) {
  RelativeHistogram all;
  for (const RelativeHistogram* h : data) {
    if (h != nullptr) all.merge(*h);
  }
  HistogramBins bins;
  if (all.total() == 0) return bins;
  auto [lo, hi] = finite_range(all);
  if (!(lo <= hi)) return bins;  // only infinite values
  const double n = static_cast<double>(all.total());
  double width = 2.0 * (all.quantile(0.75) - all.quantile(0.25)) / std::cbrt(n);
  if (!(width > 0.0) || !std::isfinite(width)) width = (hi - lo) / std::sqrt(n);
  // Never finer than four buckets of the RelativeHistogram at the largest magnitude shown.
  const auto floor_width = [](double a, double b) {
    return std::max(std::abs(a), std::abs(b)) / 1024.0;
  };
  if ((hi - lo) / std::max(width, floor_width(lo, hi)) > static_cast<double>(max_bins)) {
    // A long tail: show the central 99.8 %.
    bins.clipped = true;
    lo = std::max(lo, all.quantile(0.001));
    hi = std::min(hi, all.quantile(0.999));
  }
  if (!(width > 0.0) || !std::isfinite(width)) {
    const double magnitude = std::max(std::abs(lo), std::abs(hi));
    width = magnitude > 0.0 ? magnitude / 256.0 : 1e-3;
  }
  width = nice_width_nearest(width);
  // The floors are hard: never finer than four buckets, never more than max_bins bins.
  const double least = std::max(floor_width(lo, hi), (hi - lo) / static_cast<double>(max_bins));
  if (width < least) width = nice_width_at_least(least);
  bins.width = width;
  bins.lo = std::floor(lo / width) * width;
  // Cover hi itself (bins are half-open).
  bins.count = static_cast<std::size_t>(std::floor((hi - bins.lo) / width)) + 1;
  return bins;
}

double histogram_mode(const RelativeHistogram& values, const HistogramBins& bins) {
  const Histogram h = bins.histogram_of(values);
  const auto& counts = h.counts();
  const auto fullest = std::max_element(counts.begin(), counts.end());
  if (fullest == counts.end() || *fullest == 0) return std::numeric_limits<double>::quiet_NaN();
  return h.centre(static_cast<std::size_t>(fullest - counts.begin()));
}

}  // namespace gearmc
