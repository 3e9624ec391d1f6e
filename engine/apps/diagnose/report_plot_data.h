// What the diagnosis report plots when the readings are many or wild: the memory and the size
// of report.html must not grow with the spread of the residuals, and only boundedly with their
// number.
//  * display_bins: the bins of a residual histogram. At most `max_bins` bins of a 1-2-5 width
//    (…, 0.1, 0.2, 0.5, 1, 2, 5, … µm) covering the central part of the values — the
//    `tail_fraction` and 1 − `tail_fraction` sample quantiles (Hyndman & Fan 1996, definition 1),
//    widened by half their distance on each side (not beyond the data: a Gaussian sample's
//    ±2.6σ become ±5.2σ, so only gross outliers fall outside) and to ±3σ of the noise floor so
//    the expected law shows — never a bin count taken from
//    the full range: one reading 10⁸ mm off no longer asks for 10¹¹ bins. Values outside the
//    bins are the histogram's underflow / overflow, which the plot states with their extremes.
//  * plotted_sample: which points a scatter plot draws. All of them up to `max_marks`; beyond,
//    the smallest and the largest value (so an outlier is never hidden) plus a uniform random
//    sample without replacement of the others (Knuth, TAOCP vol. 2, 3.4.2, Algorithm S), drawn
//    from a counter-based stream so the same seed gives the same marks. Bin means, computed
//    from every point, carry the pattern; the sample shows the scatter around them.
// Units: µm (values, σ, bins). Non-finite values are ignored (they are not plotted).
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

namespace gearmc {

struct DisplayBins {
  double lo_um = 0.0;     // left edge of the first bin
  double width_um = 1.0;  // a 1-2-5 value
  std::size_t bins = 1;   // ≤ max_bins + 2
};
DisplayBins display_bins(std::span<const double> values, double sigma_um, int max_bins = 60,
                         double tail_fraction = 0.005);

// Indices (ascending) of the points to draw: every index when values.size() ≤ max_marks, else
// exactly max_marks of them (max_marks ≥ 2): the arg-min, the arg-max and a random sample.
std::vector<std::size_t> plotted_sample(std::span<const double> values, std::size_t max_marks,
                                        std::uint64_t seed);

}  // namespace gearmc
