// Assembles the STATS object of summary.json from moments and histogram (see stats_json.h).
#include "engine/stats/stats_json.h"

#include <cmath>
#include <stdexcept>

namespace gearmc {
namespace {

nlohmann::ordered_json number_or_null(double x) {
  if (std::isfinite(x)) return x;
  return nullptr;
}

}  // namespace

nlohmann::ordered_json stats_json(const RunningStats& moments, const Histogram& histogram,
                                  double mode_display_width_um) {
  if (moments.count() != histogram.total()) {
    throw std::invalid_argument("stats_json: moments and histogram hold different counts");
  }
  nlohmann::ordered_json stats;
  stats["n"] = moments.count();
  stats["mean"] = number_or_null(moments.mean());
  stats["std"] = number_or_null(moments.stddev());
  stats["min"] = number_or_null(moments.min());
  stats["max"] = number_or_null(moments.max());
  stats["mode"] = number_or_null(histogram.mode(mode_display_width_um));
  stats["p95"] = number_or_null(histogram.quantile(0.95));  // NaN when empty
  stats["p99_73"] = number_or_null(histogram.quantile(0.9973));
  return stats;
}

}  // namespace gearmc
