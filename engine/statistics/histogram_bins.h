// Bins chosen from the data, for the pictures, the CSV counts, the mode and the law fits of a
// run: the Freedman–Diaconis width 2·IQR·n^(-1/3) (Freedman & Diaconis, "On the histogram as a
// density estimator: L2 theory", Z. Wahrscheinlichkeitstheorie verw. Gebiete 57, 1981), rounded
// to the nearest (in ratio) of 1, 2 or 5 × 10^k, over the range of the data, shared by every
// histogram passed in (so the left and right flanks are drawn on the same bins). A width is never
// finer than 2^-10 of the largest magnitude, so every bin spans at least four buckets of a
// RelativeHistogram (whose buckets are 2^-12 of their value wide) and re-binning by bucket centres
// is faithful. When the range would need more than `max_bins` bins (a long tail), the bins cover
// the 0.1 % to 99.9 % quantiles and the rest is counted as under/overflow, which the plots state.
#pragma once

#include <cstddef>
#include <vector>

#include "engine/statistics/histogram.h"
#include "engine/statistics/relative_histogram.h"

namespace gearmc {

struct HistogramBins {
  double lo = 0.0, width = 1.0;  // same unit as the values (µm in the engine)
  std::size_t count = 1;
  bool clipped = false;  // the range was cut to the 0.1 %–99.9 % quantiles
  Histogram histogram_of(const RelativeHistogram& values) const {
    return values.to_histogram(lo, width, count);
  }
};

// The smallest of 1, 2, 5 × 10^k that is >= x (x > 0, finite).
double nice_width_at_least(double x);
// The one of 1, 2, 5 × 10^k nearest to x in ratio (x > 0, finite); ties go up.
double nice_width_nearest(double x);

// Freedman–Diaconis bins for the union of `data` (null entries and empty histograms are
// ignored; with no value at all: one bin [0, 1)). A zero IQR (most values equal) falls back to
// range / sqrt(n), and a zero range to 2^-8 of the value (or 1e-3 for zero).
HistogramBins freedman_diaconis_bins(const std::vector<const RelativeHistogram*>& data,
                                     std::size_t max_bins = 200);

// The mode on given bins: the centre of the fullest bin of bins.histogram_of(values) (ties to
// the lower bin); NaN when no value lies inside the bins. A property of the bin width as much as
// of the data (a histogram mode), which is why the width is reported with it.
double histogram_mode(const RelativeHistogram& values, const HistogramBins& bins);

}  // namespace gearmc
