// The STATS object of summary.json (the `run` outputs):
//   {"n", "mean", "std", "min", "max", "mode", "mode_bin_um", "p95", "p99_73", ...}
// built from the streaming moments (n, mean, std, min, max: exact up to rounding) and the
// RelativeHistogram of the same values (quantiles as conservative upper bounds within 2^-12 of
// the exact order statistic, see relative_histogram.h; the mode as the centre of the fullest bin
// of the data-chosen bins, see histogram_bins.h). Values in µm. A statistic that does not exist
// is written as JSON null, never silently: a quantile p needs at least
// RelativeHistogram::min_count_for_quantile(p) values (371 for p99.73, 20 for p95) — with fewer
// it would only repeat the maximum — and then "<key>_note" says so, e.g.
//   "p99_73": null, "p99_73_note": "not enough values: n = 200, p99.73 needs at least 371".
#pragma once

#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#include "engine/statistics/histogram_bins.h"
#include "engine/statistics/relative_histogram.h"
#include "engine/statistics/running_stats.h"

namespace gearmc {

// The p-quantile of `values` when there are enough values for it (see above); nullopt otherwise.
std::optional<double> supported_quantile(const RelativeHistogram& values, double p);
// "not enough values: n = N, pLABEL needs at least M" (label e.g. "99.73").
std::string not_enough_values_note(std::uint64_t n, double p);

// Throws std::invalid_argument if the two do not describe the same number of values.
nlohmann::ordered_json stats_json(const RunningStats& moments, const RelativeHistogram& values,
                                  const HistogramBins& mode_bins);

}  // namespace gearmc
