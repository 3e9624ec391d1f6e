// Table cells and the error budget shared by the outputs of `gearmc run` (see run_report_cells.h).
#include "engine/reports/run_report_cells.h"

#include <cmath>
#include <iomanip>
#include <optional>
#include <sstream>

#include "engine/effects/measurement_effect.h"
#include "engine/statistics/stats_json.h"

namespace gearmc::run_output {

std::string format_stat(double v) {
  if (!std::isfinite(v)) return "-";
  std::ostringstream s;
  s << std::fixed << std::setprecision(3) << v;
  std::string text = s.str();
  if (text == "-0.000") text = "0.000";
  return text;
}

std::string format_p(double p) {
  std::ostringstream s;
  s << std::setprecision(2) << p;
  return s.str();
}

// The p-quantile as a table cell: the value, or "n<M" when there are too few values.
std::string quantile_cell(const RelativeHistogram& h, double p) {
  if (h.total() == 0) return "-";
  const std::optional<double> q = supported_quantile(h, p);
  if (!q) return "n<" + std::to_string(RelativeHistogram::min_count_for_quantile(p));
  return format_stat(*q);
}

std::vector<BudgetLine> error_budget(const Scenario& scenario, const RunResults& r) {
  std::vector<BudgetLine> lines;
  lines.push_back({"radius_compensation", &r.effects.radius_compensation, 0.0});
  for (std::size_t e = 0; e < r.effects.contribution.size(); ++e) {
    lines.push_back({std::string(scenario.effects->effect(e).name()), &r.effects.contribution[e],
                     0.0, &r.effects.alone[e]});
  }
  double sum = 0.0;
  for (const BudgetLine& l : lines) sum += l.stats->count() > 1 ? l.stats->variance() : 0.0;
  for (BudgetLine& l : lines) {
    l.share = sum > 0.0 && l.stats->count() > 1 ? l.stats->variance() / sum : 0.0;
  }
  return lines;
}

std::vector<std::string> stats_cells(const std::string& label, const ErrorStatistics& e,
                                     const HistogramBins& bins) {
  const auto& m = e.moments;
  return {label,
          std::to_string(m.count()),
          format_stat(m.mean()),
          format_stat(m.stddev()),
          format_stat(m.min()),
          format_stat(histogram_mode(e.histogram, bins)),
          quantile_cell(e.histogram, 0.95),
          quantile_cell(e.histogram, 0.9973),
          format_stat(m.max())};
}

}  // namespace gearmc::run_output
