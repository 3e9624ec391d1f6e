// Assembles the STATS object of summary.json from moments and histogram (see stats_json.h).
#include "engine/statistics/stats_json.h"

#include <cmath>
#include <sstream>
#include <stdexcept>

namespace gearmc {
namespace {

nlohmann::ordered_json number_or_null(double x) {
  if (std::isfinite(x)) return x;
  return nullptr;
}

std::string percent_label(double p) {
  std::ostringstream s;
  s << 100.0 * p;
  return s.str();
}

}  // namespace

std::optional<double> supported_quantile(const RelativeHistogram& values, double p) {
  if (values.total() < RelativeHistogram::min_count_for_quantile(p)) return std::nullopt;
  return values.quantile(p);
}

std::string not_enough_values_note(std::uint64_t n, double p) {
  return "not enough values: n = " + std::to_string(n) + ", p" + percent_label(p) +
         " needs at least " + std::to_string(RelativeHistogram::min_count_for_quantile(p));
}

nlohmann::ordered_json stats_json(const RunningStats& moments, const RelativeHistogram& values,
                                  const HistogramBins& mode_bins) {
  if (moments.count() != values.total()) {
    throw std::invalid_argument("stats_json: moments and histogram hold different counts");
  }
  nlohmann::ordered_json stats;
  stats["n"] = moments.count();
  stats["mean"] = number_or_null(moments.mean());
  stats["std"] = number_or_null(moments.stddev());
  stats["min"] = number_or_null(moments.min());
  stats["max"] = number_or_null(moments.max());
  stats["mode"] = number_or_null(histogram_mode(values, mode_bins));
  stats["mode_bin_um"] = mode_bins.width;
  for (const auto& [key, p] : {std::pair{"p95", 0.95}, std::pair{"p99_73", 0.9973}}) {
    const std::optional<double> q = supported_quantile(values, p);
    stats[key] = q ? number_or_null(*q) : nlohmann::ordered_json();
    if (!q && values.total() > 0) {
      stats[std::string(key) + "_note"] = not_enough_values_note(values.total(), p);
    }
  }
  return stats;
}

}  // namespace gearmc
