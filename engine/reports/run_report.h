// What `gearmc run` tells its user, composed from a run's results: the data-chosen bins of each
// quantity (shared by the left and right flanks), the laws fitted to the per-flank maximum with
// an honest verdict, the warnings about contacts that gave no value, summary.json,
// histograms.csv, the SVG pictures and report.html (the terminal table: run_terminal.h). Values
// in µm.
#pragma once

#include <functional>
#include <nlohmann/json.hpp>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include "core/provenance.h"
#include "engine/run/monte_carlo.h"
#include "engine/statistics/distribution_fit.h"
#include "engine/statistics/histogram_bins.h"

namespace gearmc {

// The significance level at which a fitted law is rejected by its chi-square test.
inline constexpr double kLawRejectionLevel = 0.01;

// The laws fitted to one side's per-flank maxima and what may be said of them.
struct LawVerdict {
  std::vector<DistributionFit> fits;  // best AIC first (fit_distributions)
  // The best-AIC law among those its chi-square test does not reject at kLawRejectionLevel
  // (a test that cannot be made, dof < 1, does not reject); empty when every law is rejected.
  std::optional<DistributionFit> accepted;
  // The best-AIC applicable law (shown as "closest" when none is accepted); empty: no fit.
  std::optional<DistributionFit> closest;
  // E.g. "gamma (χ² p = 0.41)" or "no law of the five fits at the 1 % level; closest: gamma,
  // χ² p = 0.005".
  std::string sentence;
};

// The quantities of a run, in the order of RunPresentation::bins.
enum RunQuantity { kPointDelta, kFlankMax, kFlankMean, kTotalAbs, kRunQuantities };

struct RunPresentation {
  Provenance provenance;               // what made these outputs
  HistogramBins bins[kRunQuantities];  // shared by left and right
  LawVerdict laws[2];                  // per-flank maximum, [0] L, [1] R
  std::vector<std::string> warnings;   // also printed on the terminal
};

// The statistics of quantity q on side s of a run.
const ErrorStatistics& run_statistics(const RunResults& r, RunQuantity q, int s);

// Bins, law fits and warnings for the run (the fits cost ~0.1 s per side).
RunPresentation present_run(const RunResults& r, Provenance provenance);

// Warnings about contacts that gave no value and values that were not finite; empty when
// there is nothing to say. Throws nothing: the caller decides what is fatal.
std::vector<std::string> contact_warnings(const RunResults& r);

// P1's set-up (its gear, 10 × 5 grid, R 0.5 mm): only then are P1's Table 2 and its 4 µm claim
// shown next to the results.
bool is_p1_setup(const Scenario& s);

nlohmann::ordered_json run_summary_json(const Scenario& scenario, const MonteCarloRun& mc,
                                        const RunResults& r, const RunPresentation& view,
                                        std::optional<int> only_gear);
// Long format, one row per bin of each quantity and side on its shared bins:
// "quantity,side,bin_lo_um,bin_hi_um,count", plus rows with -inf / inf edges for values outside
// the bins when there are any.
std::string run_histograms_csv(const RunResults& r, const RunPresentation& view);

struct RunFigure {
  std::string file;  // e.g. "flank_max_left.svg"
  std::string svg, caption;
  int row = 0;         // figures with the same row are shown side by side
  bool sheet = false;  // an inspection sheet: the page's width, printed on a page of its own
};
std::vector<RunFigure> run_figures(const Scenario& scenario, const RunResults& r,
                                   const RunPresentation& view);
class HtmlReport;
// Adds `figures` to `report` in rows, consecutive figures with the same `row` side by side.
void add_figure_rows(HtmlReport& report, const std::vector<RunFigure>& figures);
// `first_section` (when set) adds its blocks right after the run's introduction (the gear
// parameters' table and charts, parameter_report.h). `opening` (when set) writes the box that
// opens the page, under the title (the parameters' capability verdict); without it the box
// states the δRcomp headline: each side's per-flank p99.73 and the largest value (and P1's
// 4 µm claim on P1's set-up).
std::string run_report_html(const Scenario& scenario, const RunResults& r,
                            const RunPresentation& view, const std::vector<RunFigure>& figures,
                            const std::function<void(HtmlReport&)>& first_section = {},
                            const std::function<void(HtmlReport&)>& opening = {});

}  // namespace gearmc
