// The STATS object of summary.json (interface.md, `run` outputs):
//   {"n", "mean", "std", "min", "max", "mode", "p95", "p99_73"}
// built from the streaming moments (n, mean, std, min, max: exact up to rounding) and the
// fine histogram of the same values (mode at a display width, quantiles at bin resolution, see
// histogram.h). Values in µm; a statistic that does not exist (empty data, std with n < 2) is
// written as JSON null.
#pragma once

#include <nlohmann/json.hpp>

#include "engine/stats/histogram.h"
#include "engine/stats/running_stats.h"

namespace gearmc {

// Throws std::invalid_argument if the two do not describe the same number of values.
// mode = histogram.mode(mode_display_width_um); p95 = histogram.quantile(0.95);
// p99_73 = histogram.quantile(0.9973) (P1's 99.73 % confidence level, sources.md).
nlohmann::ordered_json stats_json(const RunningStats& moments, const Histogram& histogram,
                                  double mode_display_width_um = 0.1);

}  // namespace gearmc
