// report.html of a run (run_report_html, run_report.h): the introduction, the δRcomp table next
// to P1's Table 2, the total error and its budget with effects, P1's 4 µm claim, the figures,
// the fitted laws and the scenario's text; and add_figure_rows, shared with the parameters'
// figures.
#include <algorithm>
#include <cmath>
#include <iomanip>
#include <sstream>

#include "engine/reports/cmm_summary.h"
#include "engine/reports/html_report.h"
#include "engine/reports/run_report.h"
#include "engine/reports/run_report_cells.h"

namespace gearmc {
using namespace run_output;

void add_figure_rows(HtmlReport& report, const std::vector<RunFigure>& figures) {
  for (std::size_t i = 0; i < figures.size();) {
    if (figures[i].sheet) {
      report.sheet(figures[i].svg, figures[i].caption);
      ++i;
      continue;
    }
    std::vector<std::pair<std::string, std::string>> row;
    const int id = figures[i].row;
    for (; i < figures.size() && figures[i].row == id && !figures[i].sheet; ++i) {
      row.emplace_back(figures[i].svg, figures[i].caption);
    }
    report.figure_row(row);
  }
}

std::string run_report_html(const Scenario& scenario, const RunResults& r,
                            const RunPresentation& view, const std::vector<RunFigure>& figures,
                            const std::function<void(HtmlReport&)>& first_section,
                            const std::function<void(HtmlReport&)>& opening) {
  HtmlReport report("gearmc run: " + scenario.name);
  if (opening) {
    opening(report);
  } else {
    const double worst = std::max(r.flank_max[0].moments.max(), r.flank_max[1].moments.max());
    std::vector<std::string> lines;
    if (is_p1_setup(scenario)) {
      std::uint64_t above = 0;
      for (int s = 0; s < 2; ++s) {
        above += r.flank_max[s].histogram.count_at_least(kP1ClaimUm).at_least;
      }
      lines.push_back("P1's claim \"δRcomp does not exceed 4 µm\": " +
                      std::string(above == 0 ? "holds on every flank of the run"
                                             : "exceeded on " + std::to_string(above) + " flanks"));
    }
    lines.push_back("A claim with a confidence bound: gearmc check (docs/check.md).");
    report.verdict("δRcomp per flank (µm): p99.73 " +
                       quantile_cell(r.flank_max[0].histogram, 0.9973) + " left, " +
                       quantile_cell(r.flank_max[1].histogram, 0.9973) + " right; largest " +
                       format_stat(worst) + " over " + std::to_string(r.gears) + " gears.",
                   lines);
  }
  for (const std::string& w : view.warnings) report.paragraph("Warning: " + w);
  std::ostringstream intro;
  intro << r.gears << " gears, " << r.contacts << " contacts (failed " << r.failed_contacts
        << ", edge " << r.edge_contacts << ", collisions " << r.collisions << "), stylus R "
        << scenario.stylus_radius_mm << " mm, seed " << scenario.seed << ". δRcomp = |C − E|: "
        << "distance between the true contact point and the point the CMM reports.";
  report.paragraph(intro.str());
  // The machine the gears were measured on comes before what they gave (docs/cmm.md).
  if (scenario.cmm) report.paragraph(cmm_summary_sentence(*scenario.cmm));
  for (const FlankMeshSurface& surface : scenario.surfaces) {
    std::ostringstream mesh;
    mesh << "Flank " << surface.tooth << side_letter(surface.side) << " is the mesh "
         << surface.mesh_path << " (" << triangle_count(*surface.mesh) << " triangles, "
         << (surface.contact == MeshContactPoint::kSmoothed ? "smoothed" : "facet")
         << " contact point) in every gear; its random deviations are not used.";
    report.paragraph(mesh.str());
  }
  if (first_section) first_section(report);
  HtmlTable table;
  table.caption =
      "δRcomp statistics (µm). Quantiles are upper bounds within 0.025 % of the exact order "
      "statistic; p95 needs at least 20 values, p99.73 at least 371 (\"n<371\": too few). "
      "Mode = centre of the fullest bin of the plotted histogram.";
  table.header = {"quantity", "n", "mean", "std", "min", "mode", "p95", "p99.73", "max"};
  for (const TableRow& row : kDeltaRows) {
    table.rows.push_back(
        {stats_cells(row.label, run_statistics(r, row.q, row.side), view.bins[row.q])});
  }
  if (is_p1_setup(scenario)) {
    // P1 Table 2: per-flank value, 50 gears; E = most probable value.
    table.rows.push_back(
        {{"P1 Table 2, left", "1200", "1.6", "0.6", "0.7", "", "", "", "3.4"}, true});
    table.rows.push_back(
        {{"P1 Table 2, right", "1200", "1.6", "0.6", "0.7", "", "", "", "3.2"}, true});
  }
  report.table(table);
  if (!scenario.effects->empty()) {
    HtmlTable total;
    total.caption =
        "Total point error with the measurement effects on (µm): (E' − C)·n, E' the point "
        "reported from the recorded stylus centre, C the true contact point; quantiles of |e|.";
    total.header = {"flank", "n", "mean", "std", "min", "max", "|e| p95", "|e| p99.73"};
    for (int s = 0; s < 2; ++s) {
      const RunningStats& m = r.effects.total_signed[s];
      total.rows.push_back({{kSideName[s], std::to_string(m.count()), format_stat(m.mean()),
                             format_stat(m.stddev()), format_stat(m.min()), format_stat(m.max()),
                             quantile_cell(r.total_abs[s].histogram, 0.95),
                             quantile_cell(r.total_abs[s].histogram, 0.9973)}});
    }
    report.table(total);
    HtmlTable budget;
    budget.caption =
        "Error budget: each source's change of the reading along n (µm), its share of the "
        "summed variances, and the total error's σ with that effect alone on (besides δRcomp).";
    budget.header = {"source", "mean", "std", "share of variance", "total σ, alone"};
    for (const BudgetLine& l : error_budget(scenario, r)) {
      budget.rows.push_back(
          {{l.source, format_stat(l.stats->mean()), format_stat(l.stats->stddev()),
            format_stat(100.0 * l.share) + " %", l.alone ? format_stat(l.alone->stddev()) : ""}});
    }
    report.table(budget);
  }
  if (is_p1_setup(scenario)) {
    const double worst = std::max(r.flank_max[0].moments.max(), r.flank_max[1].moments.max());
    std::uint64_t above = 0, total = 0;
    for (int s = 0; s < 2; ++s) {
      // 4 is a power of two, hence a bucket edge: the count is exact.
      above += r.flank_max[s].histogram.count_at_least(kP1ClaimUm).at_least;
      total += r.flank_max[s].histogram.total();
    }
    std::ostringstream claim;
    claim << "P1's claim \"δRcomp does not exceed 4 µm\": the largest per-flank value here is "
          << format_stat(worst) << " µm; " << above << " of " << total
          << " flanks reach 4 µm or more.";
    report.paragraph(claim.str());
  }
  add_figure_rows(report, figures);
  HtmlTable fit_table;
  fit_table.caption =
      "Laws fitted to the per-flank maximum (binned maximum likelihood), best first by AIC; a "
      "law is rejected when its χ² p-value is below 0.01. Left: " +
      view.laws[0].sentence + ". Right: " + view.laws[1].sentence + ".";
  fit_table.header = {"flank", "law", "parameters", "AIC", "KS distance", "χ² p-value"};
  for (int s = 0; s < 2; ++s) {
    for (const DistributionFit& f : view.laws[s].fits) {
      if (!f.applicable) continue;
      const auto names = f.distribution.parameter_names();
      std::ostringstream params;
      params << names[0] << " " << format_stat(f.distribution.a) << ", " << names[1] << " "
             << format_stat(f.distribution.b);
      std::ostringstream aic, ks;
      aic << std::fixed << std::setprecision(1) << f.aic;
      ks << std::fixed << std::setprecision(4) << f.ks_distance;
      const bool chosen =
          view.laws[s].accepted && view.laws[s].accepted->distribution.law == f.distribution.law;
      fit_table.rows.push_back(
          {{kSideName[s], std::string(law_name(f.distribution.law)), params.str(), aic.str(),
            ks.str(), std::isnan(f.chi_square_p_value) ? "-" : format_p(f.chi_square_p_value)},
           chosen});
    }
  }
  report.table(fit_table);
  report.preformatted(scenario.source_text, "Scenario (" + scenario.source_path + ")");
  report.paragraph("Made by " + provenance_line(view.provenance) + ".");
  return report.html();
}

}  // namespace gearmc
