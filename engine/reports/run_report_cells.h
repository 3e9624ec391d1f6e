// Pieces shared by the outputs of `gearmc run` (summary.json, the figures, report.html and the
// terminal tables, run_report.h and run_terminal.h): how a statistic is written in a table cell,
// the rows of the δRcomp table, and the error budget of a run with measurement effects. Values
// in µm. Internal to engine/reports.
#pragma once

#include <string>
#include <vector>

#include "engine/reports/run_report.h"
#include "engine/run/monte_carlo.h"
#include "engine/statistics/histogram_bins.h"
#include "engine/statistics/relative_histogram.h"

namespace gearmc::run_output {

inline constexpr double kP1ClaimUm = 4.0;  // P1: "the compensation error does not exceed 4 µm"
inline constexpr const char* kSideName[2] = {"left", "right"};

// A statistic with three decimals ("-" when not finite; "-0.000" is written "0.000").
std::string format_stat(double v);
// A p-value with two significant digits.
std::string format_p(double p);

// The p-quantile as a table cell: the value, or "n<M" when there are too few values.
std::string quantile_cell(const RelativeHistogram& h, double p);

// The error budget of a run with measurement effects: the radius-compensation normal error and
// each effect's change of the reading along n, with its share of the summed variances
// (covariances between sources are not split; they are small when the sources are independent).
struct BudgetLine {
  std::string source;
  const RunningStats* stats;
  double share;
  const RunningStats* alone = nullptr;  // the total with only this source on
};
std::vector<BudgetLine> error_budget(const Scenario& scenario, const RunResults& r);

// One row of the δRcomp table: label, n, mean, std, min, mode, p95, p99.73, max.
std::vector<std::string> stats_cells(const std::string& label, const ErrorStatistics& e,
                                     const HistogramBins& bins);

// The rows of the δRcomp table (report.html and the terminal), in their order.
struct TableRow {
  const char* label;
  RunQuantity q;
  int side;
};
inline constexpr TableRow kDeltaRows[] = {
    {"per point, left", kPointDelta, 0},     {"per point, right", kPointDelta, 1},
    {"per flank max, left", kFlankMax, 0},   {"per flank max, right", kFlankMax, 1},
    {"per flank mean, left", kFlankMean, 0}, {"per flank mean, right", kFlankMean, 1}};

}  // namespace gearmc::run_output
