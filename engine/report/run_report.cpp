// Composition of what `gearmc run` writes and prints (see run_report.h).
#include "engine/report/run_report.h"

#include <cmath>
#include <iomanip>
#include <limits>
#include <sstream>

#include "engine/effects/measurement_effect.h"
#include "engine/report/html_report.h"
#include "engine/report/svg_plot.h"
#include "engine/stats/stats_json.h"

namespace gearmc {
namespace {

constexpr double kP1ClaimUm = 4.0;  // P1: "the compensation error does not exceed 4 µm"
const char* const kSideName[2] = {"left", "right"};

std::string format_stat(double v) {
  if (!std::isfinite(v)) return "-";
  std::ostringstream s;
  s << std::fixed << std::setprecision(3) << v;
  std::string text = s.str();
  if (text == "-0.000") text = "0.000";
  return text;
}

// The number of characters (UTF-8 code points) of `text`, its width on a terminal.
std::size_t display_width(std::string_view text) {
  std::size_t n = 0;
  for (char c : text) n += (static_cast<unsigned char>(c) & 0xC0) != 0x80;
  return n;
}
// `text` padded with spaces to `width` characters, on the left (right-aligned) or the right.
std::string pad(std::string_view text, std::size_t width, bool right_align) {
  const std::size_t w = display_width(text);
  const std::string fill(w < width ? width - w : 0, ' ');
  return right_align ? fill + std::string(text) : std::string(text) + fill;
}
// One terminal table line: the first cell left-aligned in `first` characters, the others
// right-aligned in `rest` each (headers and numbers line up the same way).
std::string table_line(const std::vector<std::string>& cells, std::size_t first, std::size_t second,
                       std::size_t rest) {
  std::string line;
  for (std::size_t c = 0; c < cells.size(); ++c) {
    line += c == 0 ? pad(cells[c], first, false) : pad(cells[c], c == 1 ? second : rest, true);
  }
  while (!line.empty() && line.back() == ' ') line.pop_back();
  return line + "\n";
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

nlohmann::ordered_json side_pair(const RunResults& r, RunQuantity q, const HistogramBins& bins) {
  nlohmann::ordered_json j;
  for (int s = 0; s < 2; ++s) {
    const ErrorStatistics& e = run_statistics(r, q, s);
    j[kSideName[s]] = stats_json(e.moments, e.histogram, bins);
  }
  return j;
}

LawVerdict judge_laws(const ErrorStatistics& e, const HistogramBins& bins) {
  LawVerdict v;
  if (e.moments.count() < 2) {
    v.sentence = "too few values to fit a law";
    return v;
  }
  // Fits on bins four times finer than the plotted ones (still at least one RelativeHistogram
  // bucket wide, histogram_bins.h); chi-square cells of the plotted width.
  const Histogram fine = e.histogram.to_histogram(bins.lo, bins.width / 4.0, bins.count * 4);
  FitOptions options;
  options.chi_square_cell_width_um = bins.width;
  v.fits = fit_distributions(fine, options);
  for (const DistributionFit& f : v.fits) {
    if (!f.applicable) continue;
    if (!v.closest) v.closest = f;
    const bool rejected = f.chi_square_p_value < kLawRejectionLevel;  // NaN: not testable
    if (!rejected && !v.accepted) v.accepted = f;
  }
  if (!v.closest) {
    v.sentence = "no law could be fitted";
  } else if (v.accepted) {
    const DistributionFit& a = *v.accepted;
    v.sentence =
        std::string(law_name(a.distribution.law)) +
        (std::isnan(a.chi_square_p_value) ? " (best AIC; too few cells for a χ² test)"
                                          : " (χ² p = " + format_p(a.chi_square_p_value) + ")");
  } else {
    v.sentence = "no law of the five fits at the 1 % level; closest: " +
                 std::string(law_name(v.closest->distribution.law)) +
                 ", χ² p = " + format_p(v.closest->chi_square_p_value);
  }
  return v;
}

nlohmann::ordered_json fit_json(const DistributionFit& f) {
  nlohmann::ordered_json j;
  j["law"] = std::string(law_name(f.distribution.law));
  const auto names = f.distribution.parameter_names();
  j["parameters"] = {{std::string(names[0]), f.distribution.a},
                     {std::string(names[1]), f.distribution.b}};
  j["aic"] = f.aic;
  j["ks_distance"] = f.ks_distance;
  j["chi_square_p_value"] =
      std::isfinite(f.chi_square_p_value) ? nlohmann::ordered_json(f.chi_square_p_value) : nullptr;
  return j;
}

nlohmann::ordered_json law_json(const LawVerdict& v) {
  if (!v.closest) return nullptr;
  nlohmann::ordered_json j = fit_json(v.accepted ? *v.accepted : *v.closest);
  j["accepted"] = v.accepted.has_value();
  j["rejection_level"] = kLawRejectionLevel;
  j["verdict"] = v.sentence;
  return j;
}

// The error budget of a run with measurement effects: the radius-compensation normal error and
// each effect's change of the reading along n, with its share of the summed variances
// (covariances between sources are not split; they are small when the sources are independent).
struct BudgetLine {
  std::string source;
  const RunningStats* stats;
  double share;
  const RunningStats* alone = nullptr;  // the total with only this source on
};
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

struct TableRow {
  const char* label;
  RunQuantity q;
  int side;
};
constexpr TableRow kDeltaRows[] = {
    {"per point, left", kPointDelta, 0},     {"per point, right", kPointDelta, 1},
    {"per flank max, left", kFlankMax, 0},   {"per flank max, right", kFlankMax, 1},
    {"per flank mean, left", kFlankMean, 0}, {"per flank mean, right", kFlankMean, 1}};

}  // namespace

const ErrorStatistics& run_statistics(const RunResults& r, RunQuantity q, int s) {
  switch (q) {
    case kPointDelta:
      return r.point[s];
    case kFlankMax:
      return r.flank_max[s];
    case kFlankMean:
      return r.flank_mean[s];
    default:
      return r.total_abs[s];
  }
}

RunPresentation present_run(const RunResults& r, Provenance provenance) {
  RunPresentation view;
  view.provenance = std::move(provenance);
  for (int q = 0; q < kRunQuantities; ++q) {
    const auto quantity = static_cast<RunQuantity>(q);
    view.bins[q] = freedman_diaconis_bins(
        {&run_statistics(r, quantity, 0).histogram, &run_statistics(r, quantity, 1).histogram});
  }
  for (int s = 0; s < 2; ++s) view.laws[s] = judge_laws(r.flank_max[s], view.bins[kFlankMax]);
  view.warnings = contact_warnings(r);
  return view;
}

std::vector<std::string> contact_warnings(const RunResults& r) {
  std::vector<std::string> warnings;
  const std::uint64_t bad = r.failed_contacts + r.edge_contacts + r.collisions;
  if (r.contacts > 0 && bad > 0 && 100 * bad > r.contacts) {
    std::ostringstream w;
    const double percent = 100.0 * static_cast<double>(bad) / static_cast<double>(r.contacts);
    w << (2 * bad > r.contacts ? "most contacts gave no value: " : "contacts without a value: ")
      << bad << " of " << r.contacts << " (" << std::fixed << std::setprecision(1) << percent
      << " %: failed " << r.failed_contacts << ", edge " << r.edge_contacts << ", collisions "
      << r.collisions
      << "); the statistics describe only the other points — check the stylus radius against "
         "the tooth space and any normal_um expression";
    warnings.push_back(w.str());
  }
  if (r.runout_redrawn_gears > 0) {
    warnings.push_back(
        "F_r constrains the profile and helix shapes: " + std::to_string(r.runout_redrawn_gears) +
        " of " + std::to_string(r.gears) +
        " gears had shapes that alone broke F_r and were drawn again (" +
        std::to_string(r.runout_redraws) +
        " redraws in all), so the shapes follow the scenario's law conditioned on meeting F_r");
  }
  std::uint64_t non_finite = 0;
  for (int q = 0; q < kRunQuantities; ++q) {
    for (int s = 0; s < 2; ++s)
      non_finite += run_statistics(r, static_cast<RunQuantity>(q), s).non_finite;
  }
  if (non_finite > 0) {
    warnings.push_back(std::to_string(non_finite) +
                       " error values were not finite (left out of every statistic): an effect "
                       "parameter is probably far outside its physical range");
  }
  return warnings;
}

bool is_p1_setup(const Scenario& s) {
  // P1's set-up (Table 1 and Fig. 4 of P1): the gear, the grid and the stylus.
  const GearParameters& g = s.gear;
  return g.teeth == 24 && g.module_mm == 5.6 && g.pressure_angle_deg == 20.0 &&
         g.profile_shift == 0.90116 && g.face_width_mm == 78.89 && s.stylus_radius_mm == 0.5 &&
         s.probing.grid.points_along_profile == 10 && s.probing.grid.sections_across_face == 5;
}

nlohmann::ordered_json run_summary_json(const Scenario& scenario, const MonteCarloRun& mc,
                                        const RunResults& r, const RunPresentation& view,
                                        std::optional<int> only_gear) {
  nlohmann::ordered_json summary;
  summary["provenance"] = provenance_json(view.provenance);
  summary["scenario"] = scenario.name;
  summary["source"] = scenario.source_path;
  summary["gears"] = r.gears;
  summary["only_gear"] = only_gear ? nlohmann::ordered_json(*only_gear) : nlohmann::ordered_json();
  summary["teeth"] = mc.probed_teeth();
  summary["points_per_flank"] = mc.points_per_flank();
  summary["stylus_radius_mm"] = scenario.stylus_radius_mm;
  summary["seed"] = scenario.seed;
  summary["contacts"] = r.contacts;
  summary["failed_contacts"] = r.failed_contacts;
  summary["edge_contacts"] = r.edge_contacts;
  summary["collisions"] = r.collisions;
  summary["runout_redrawn_gears"] = r.runout_redrawn_gears;
  summary["wall_s"] = r.wall_s;
  summary["contacts_per_s"] = r.wall_s > 0 ? static_cast<double>(r.contacts) / r.wall_s : 0.0;
  summary["warnings"] = view.warnings;
  summary["input_warnings"] = scenario.warnings;
  // Flanks probed on a mesh instead of the analytic perturbed flank (`surfaces:`).
  nlohmann::ordered_json mesh_surfaces = nlohmann::ordered_json::array();
  for (const FlankMeshSurface& surface : scenario.surfaces) {
    mesh_surfaces.push_back(
        {{"tooth", surface.tooth},
         {"flank", std::string(1, side_letter(surface.side))},
         {"mesh", surface.mesh_path},
         {"contact", surface.contact == MeshContactPoint::kSmoothed ? "smoothed" : "facets"},
         {"triangles", triangle_count(*surface.mesh)}});
  }
  summary["mesh_surfaces"] = mesh_surfaces;
  summary["quantile_relative_resolution"] = RelativeHistogram::kRelativeResolution;
  summary["delta_rcomp_um"] = {{"point", side_pair(r, kPointDelta, view.bins[kPointDelta])},
                               {"flank_max", side_pair(r, kFlankMax, view.bins[kFlankMax])},
                               {"flank_mean", side_pair(r, kFlankMean, view.bins[kFlankMean])}};
  if (!scenario.effects->empty()) {
    nlohmann::ordered_json names = nlohmann::ordered_json::array();
    for (std::size_t e = 0; e < scenario.effects->size(); ++e) {
      names.push_back(std::string(scenario.effects->effect(e).name()));
    }
    summary["effects"] = names;
    auto signed_stats = [](const RunningStats& m) {
      nlohmann::ordered_json j;
      j["n"] = m.count();
      for (auto [key, v] : {std::pair{"mean", m.mean()}, std::pair{"std", m.stddev()},
                            std::pair{"min", m.min()}, std::pair{"max", m.max()}}) {
        j[key] = std::isfinite(v) ? nlohmann::ordered_json(v) : nlohmann::ordered_json();
      }
      return j;
    };
    summary["total_error_um"] = {{"signed",
                                  {{"left", signed_stats(r.effects.total_signed[0])},
                                   {"right", signed_stats(r.effects.total_signed[1])}}},
                                 {"abs", side_pair(r, kTotalAbs, view.bins[kTotalAbs])}};
    nlohmann::ordered_json budget = nlohmann::ordered_json::array();
    for (const BudgetLine& l : error_budget(scenario, r)) {
      nlohmann::ordered_json line = signed_stats(*l.stats);
      line["source"] = l.source;
      line["variance_share"] = l.share;
      if (l.alone) {
        const double alone = l.alone->stddev();
        line["total_std_alone"] = std::isfinite(alone) ? nlohmann::ordered_json(alone) : nullptr;
      }
      budget.push_back(line);
    }
    summary["error_budget_um"] = budget;
  }
  // Laws fitted to the per-flank maximum (P1 names a law for its per-flank values).
  summary["flank_max_best_law"] = {{"left", law_json(view.laws[0])},
                                   {"right", law_json(view.laws[1])}};
  return summary;
}

std::string run_histograms_csv(const RunResults& r, const RunPresentation& view) {
  static const char* const kName[kRunQuantities] = {"point", "flank_max", "flank_mean",
                                                    "total_abs"};
  std::ostringstream csv;
  csv << std::setprecision(17);
  csv << "# " << provenance_line(view.provenance) << "\n";
  csv << "quantity,side,bin_lo_um,bin_hi_um,count\n";
  for (int q = 0; q < kRunQuantities; ++q) {
    for (int s = 0; s < 2; ++s) {
      const ErrorStatistics& e = run_statistics(r, static_cast<RunQuantity>(q), s);
      if (e.moments.count() == 0) continue;
      const Histogram h = view.bins[q].histogram_of(e.histogram);
      const char* side = s == 0 ? "L" : "R";
      if (h.underflow() > 0) {
        csv << kName[q] << ',' << side << ",-inf," << h.lo() << ',' << h.underflow() << '\n';
      }
      for (std::size_t i = 0; i < h.bin_count(); ++i) {
        csv << kName[q] << ',' << side << ',' << h.edge(i) << ',' << h.edge(i + 1) << ','
            << h.count(i) << '\n';
      }
      if (h.overflow() > 0) {
        csv << kName[q] << ',' << side << ',' << h.hi() << ",inf," << h.overflow() << '\n';
      }
    }
  }
  return csv.str();
}

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

std::string run_report_html(const Scenario& scenario, const RunResults& r,
                            const RunPresentation& view, const std::vector<RunFigure>& figures,
                            const std::function<void(HtmlReport&)>& first_section) {
  HtmlReport report("gearmc run: " + scenario.name);
  for (const std::string& w : view.warnings) report.paragraph("Warning: " + w);
  std::ostringstream intro;
  intro << r.gears << " gears, " << r.contacts << " contacts (failed " << r.failed_contacts
        << ", edge " << r.edge_contacts << ", collisions " << r.collisions << "), stylus R "
        << scenario.stylus_radius_mm << " mm, seed " << scenario.seed << ". δRcomp = |C − E|: "
        << "distance between the true contact point and the point the CMM reports.";
  report.paragraph(intro.str());
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
  for (std::size_t i = 0; i < figures.size();) {
    std::vector<std::pair<std::string, std::string>> row;
    const int id = figures[i].row;
    for (; i < figures.size() && figures[i].row == id; ++i) {
      row.emplace_back(figures[i].svg, figures[i].caption);
    }
    report.figure_row(row);
  }
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

void print_run_tables(std::ostream& out, const Scenario& scenario, const RunResults& r,
                      const RunPresentation& view) {
  static const char* const kShortLabel[] = {"point L",     "point R",      "flank max L",
                                            "flank max R", "flank mean L", "flank mean R"};
  out << table_line({"δRcomp (µm)", "n", "mean", "std", "min", "mode", "p95", "p99.73", "max"}, 14,
                    8, 9);
  for (std::size_t k = 0; k < std::size(kDeltaRows); ++k) {
    const TableRow& row = kDeltaRows[k];
    out << table_line(
        stats_cells(kShortLabel[k], run_statistics(r, row.q, row.side), view.bins[row.q]), 14, 8,
        9);
  }
  if (scenario.effects->empty()) return;
  out << table_line({"total error (µm)", "n", "mean", "std", "min", "max", "|e| p95", "|e| p99.73"},
                    18, 8, 11);
  for (int s = 0; s < 2; ++s) {
    const RunningStats& m = r.effects.total_signed[s];
    out << table_line({s == 0 ? "point L, along n" : "point R, along n", std::to_string(m.count()),
                       format_stat(m.mean()), format_stat(m.stddev()), format_stat(m.min()),
                       format_stat(m.max()), quantile_cell(r.total_abs[s].histogram, 0.95),
                       quantile_cell(r.total_abs[s].histogram, 0.9973)},
                      18, 8, 11);
  }
  out << table_line({"error budget (µm)", "mean", "std", "share", "σ alone"}, 20, 9, 11);
  for (const BudgetLine& l : error_budget(scenario, r)) {
    out << table_line(
        {l.source, format_stat(l.stats->mean()), format_stat(l.stats->stddev()),
         format_stat(100.0 * l.share) + " %", l.alone ? format_stat(l.alone->stddev()) : ""},
        20, 9, 11);
  }
}

}  // namespace gearmc
