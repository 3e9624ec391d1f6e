// The SVG pictures of a run (run_figures, run_report.h): the histograms of the per-flank maximum,
// the per-point value and the total error, left and right on shared bins, the cumulative
// distributions and the error budget.
#include <algorithm>
#include <limits>
#include <sstream>

#include "engine/reports/run_report.h"
#include "engine/reports/run_report_cells.h"
#include "engine/reports/svg_plot.h"
#include "engine/statistics/stats_json.h"

namespace gearmc {
using namespace run_output;

std::vector<RunFigure> run_figures(const Scenario& scenario, const RunResults& r,
                                   const RunPresentation& view) {
  // Per-flank-max, per-point (with a log10 count view of the same bins under it, where the
  // tail's few counts show) and (with effects) total-error histograms, left and right side by
  // side on the same bins and the same count axis (P1 Fig. 5); then the cumulative
  // distributions and, with effects, the error budget.
  std::vector<RunFigure> figures;
  struct Kind {
    RunQuantity q;
    const char* file;
    const char* what;
    const char* x_label;
    bool log_count = false;
  };
  const Kind kinds[] = {
      {kFlankMax, "flank_max_", "δRcomp per-flank maximum", "δRcomp, µm"},
      {kPointDelta, "point_", "δRcomp per point", "δRcomp, µm"},
      {kPointDelta, "point_log_", "δRcomp per point, log count", "δRcomp, µm", true},
      {kTotalAbs, "total_abs_", "|total point error| with effects", "|e|, µm"}};
  int row = 0;
  for (const Kind& kind : kinds) {
    const HistogramBins& bins = view.bins[kind.q];
    Histogram shown[2] = {bins.histogram_of(run_statistics(r, kind.q, 0).histogram),
                          bins.histogram_of(run_statistics(r, kind.q, 1).histogram)};
    double tallest = 0.0;
    for (const Histogram& h : shown) {
      for (std::uint64_t c : h.counts()) tallest = std::max(tallest, static_cast<double>(c));
    }
    for (int s = 0; s < 2; ++s) {
      const ErrorStatistics& e = run_statistics(r, kind.q, s);
      if (e.moments.count() == 0) continue;
      HistogramPlotOptions plot;
      plot.title = std::string(kind.what) + ", " + kSideName[s] +
                   " (n = " + std::to_string(e.moments.count()) + ")";
      plot.x_label = kind.x_label;
      plot.log_count = kind.log_count;
      if (kind.log_count) plot.y_label = "count (log scale)";
      plot.x_min = bins.lo;
      plot.x_max = bins.lo + bins.width * static_cast<double>(bins.count);
      plot.y_max = tallest;
      if (const std::optional<double> q9973 = supported_quantile(e.histogram, 0.9973)) {
        plot.markers.push_back({*q9973, "p99.73 = " + format_stat(*q9973) + " µm", "", true});
      }
      if (kind.q == kFlankMax) {
        if (is_p1_setup(scenario)) {
          plot.markers.push_back({kP1ClaimUm, "P1's claim 4 µm", "", true});
        }
        const LawVerdict& law = view.laws[s];
        if (law.closest) {
          const Distribution d = (law.accepted ? *law.accepted : *law.closest).distribution;
          plot.overlay_pdf = [d](double x) { return d.pdf(x); };
          plot.overlay_label =
              law.accepted ? "best fit: " + std::string(law_name(d.law))
                           : "closest law (rejected at 1 %): " + std::string(law_name(d.law));
        }
      }
      for (const MarkerLine& m : plot.markers) {
        *plot.x_max = std::max(*plot.x_max, m.x);
        *plot.x_min = std::min(*plot.x_min, m.x);
      }
      std::ostringstream bin_note;
      bin_note << "; bins " << bins.width << " µm (Freedman–Diaconis, shared by both flanks)";
      if (kind.log_count) bin_note << "; log10 count axis, so the tail's single counts show";
      const std::string file = std::string(kind.file) + kSideName[s] + ".svg";
      figures.push_back(
          {file, histogram_svg(shown[s], plot), plot.title + bin_note.str() + " — " + file, row});
    }
    ++row;
  }
  // Cumulative distributions: the fraction of values at or below x, read off the histogram's
  // buckets (a coverage interval [0, x] at probability P is where the curve crosses P).
  for (RunQuantity q : {kFlankMax, kPointDelta}) {
    std::vector<Series> series;
    XYPlotOptions plot;
    plot.title = std::string("Cumulative distribution, δRcomp ") +
                 (q == kFlankMax ? "per-flank maximum" : "per point");
    plot.x_label = "δRcomp, µm";
    plot.y_label = "fraction ≤ x";
    plot.y_min = 0.0;
    plot.y_max = 1.0;
    plot.horizontal_lines = {0.95, 0.9973};
    for (int s = 0; s < 2; ++s) {
      const RelativeHistogram& h = run_statistics(r, q, s).histogram;
      if (h.total() == 0) continue;
      Series line;
      line.label = kSideName[s];
      double cumulative = 0.0;
      const double n = static_cast<double>(h.total());
      // At most ~2 000 points: merge buckets that are closer than 1/2000 of the range.
      const double step = (h.max() - h.min()) / 2000.0;
      double last_x = -std::numeric_limits<double>::infinity();
      h.for_each_bucket([&](double, double hi, std::uint64_t c) {
        cumulative += static_cast<double>(c);
        const double x = std::min(hi, h.max());
        if (x - last_x >= step || cumulative == n) {
          line.x.push_back(x);
          line.y.push_back(cumulative / n);
          last_x = x;
        }
      });
      series.push_back(std::move(line));
    }
    if (series.empty()) continue;
    const std::string file = std::string(q == kFlankMax ? "cdf_flank_max" : "cdf_point") + ".svg";
    figures.push_back({file, xy_plot_svg(series, plot),
                       plot.title + " (thin lines at 0.95 and 0.9973) — " + file, row});
  }
  ++row;
  if (!scenario.effects->empty()) {
    std::vector<std::string> labels;
    std::vector<double> shares;
    for (const BudgetLine& l : error_budget(scenario, r)) {
      labels.push_back(l.source);
      shares.push_back(100.0 * l.share);
    }
    BarChartOptions chart;
    chart.title = "Error budget: share of the summed variances";
    chart.x_label = "share, %";
    figures.push_back({"error_budget.svg", bar_chart_svg(labels, shares, chart),
                       "Each source's share of the summed variances of the total point error — "
                       "error_budget.svg",
                       row});
  }
  return figures;
}

}  // namespace gearmc
