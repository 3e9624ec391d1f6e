// The gear parameters in report.html: the tables and the charts of parameter_report.h — profile
// and helix traces of one gear in the style of gear-measuring software (deviation against roll
// length or face position, the measured points, the mean line, the real surface and a tolerance
// band), pitch and runout bars, and each parameter's error histogram with its 95 % interval.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "engine/reports/html_report.h"
#include "engine/reports/parameter_report.h"
#include "engine/reports/svg_plot.h"
#include "engine/statistics/histogram_bins.h"

namespace gearmc {
namespace {

const char* flank_letter(FlankSide s) { return s == FlankSide::kRight ? "R" : "L"; }

// Up to four teeth spread over the gear among those with traces: 1, 1 + z/4, 1 + z/2, 1 + 3z/4.
std::vector<int> chart_teeth(const std::vector<FlankTrace>& traces, int z) {
  std::vector<int> probed;
  for (const FlankTrace& t : traces) {
    if (std::find(probed.begin(), probed.end(), t.tooth) == probed.end()) probed.push_back(t.tooth);
  }
  std::vector<int> chosen;
  for (int q = 0; q < 4 && !probed.empty(); ++q) {
    const int wanted = 1 + q * z / 4;
    const int best = *std::min_element(probed.begin(), probed.end(), [&](int a, int b) {
      return std::abs(a - wanted) < std::abs(b - wanted);
    });
    if (std::find(chosen.begin(), chosen.end(), best) == chosen.end()) chosen.push_back(best);
  }
  return chosen;
}

std::string trace_chart(const FlankTrace& t, bool profile, std::optional<double> tolerance,
                        const std::string& total_symbol) {
  std::vector<Series> series;
  Series measured{"measured", t.x_mm, t.measured_um, SeriesStyle::kLineAndPoints, ""};
  Series real{"real surface", t.dense_x_mm, t.dense_um, SeriesStyle::kLine, "#999999"};
  series.push_back(real);
  series.push_back(measured);
  XYPlotOptions o;
  if (t.measured_line.samples > 0) {
    Series line{"mean line",
                {t.range_start_mm, t.range_end_mm},
                {t.measured_line.intercept_um,
                 t.measured_line.intercept_um +
                     t.measured_line.slope_um_per_mm * (t.range_end_mm - t.range_start_mm)},
                SeriesStyle::kLine,
                ""};
    series.push_back(line);
    if (tolerance) {
      // The total tolerance as a corridor centred on the measured trace's extremes.
      double lo = INFINITY, hi = -INFINITY;
      for (double v : t.measured_um) {
        if (std::isfinite(v)) lo = std::min(lo, v), hi = std::max(hi, v);
      }
      const double mid = 0.5 * (lo + hi);
      o.bands.push_back({mid - *tolerance / 2, mid + *tolerance / 2,
                         total_symbol + "T = " + parameter_text(*tolerance, 1) + " µm", "#56B4E9"});
    }
  }
  o.title =
      std::string(profile ? "profile " : "helix ") + std::to_string(t.tooth) + flank_letter(t.side);
  o.x_label = profile ? "roll length L, mm" : "z, mm";
  o.y_label = "deviation, µm";
  o.markers = {{t.range_start_mm, "", "#bbbbbb", true}, {t.range_end_mm, "", "#bbbbbb", true}};
  o.width_px = 235;
  o.height_px = 250;
  return xy_plot_svg(series, o);
}

}  // namespace

std::vector<RunFigure> parameter_figures(const MonteCarloRun& mc, const RunResults& r,
                                         const ParameterPresentation& p) {
  std::vector<RunFigure> figures;
  if (!r.parameters || !r.parameters->chart_gear) return figures;
  const GearTraces& g = r.parameters->chart;
  const int gear_no = *r.parameters->chart_gear;
  const ToleranceSet& tol = mc.tolerances();
  const int z = mc.gear().teeth();
  int row = 1000;  // after the run's own figures
  const auto add_traces = [&](const std::vector<FlankTrace>& traces, bool profile) {
    const std::vector<int> teeth = chart_teeth(traces, z);
    const auto T = tol.get_um(profile ? ToleranceKind::kProfileTotal : ToleranceKind::kHelixTotal);
    for (const FlankSide side : {FlankSide::kLeft, FlankSide::kRight}) {
      ++row;
      for (int tooth : teeth) {
        for (const FlankTrace& t : traces) {
          if (t.tooth != tooth || t.side != side) continue;
          const std::string name = std::string(profile ? "profile_" : "helix_") +
                                   std::to_string(tooth) + flank_letter(side) + ".svg";
          figures.push_back({name, trace_chart(t, profile, T, profile ? "F_α" : "F_β"),
                             std::string(profile ? "Profile" : "Helix") + " of tooth " +
                                 std::to_string(tooth) + flank_letter(side) + ", gear " +
                                 std::to_string(gear_no),
                             row});
        }
      }
    }
  };
  add_traces(g.profile, true);
  add_traces(g.helix, false);
  // Pitch: f_pt,k per tooth, measured and true.
  ++row;
  for (int s = 0; s < 2; ++s) {
    if (g.pitch_measured[s].empty()) continue;
    std::vector<double> k;
    for (int i = 1; i <= static_cast<int>(g.pitch_measured[s].size()); ++i) k.push_back(i);
    XYPlotOptions o;
    o.title = std::string("single pitch f_pt, ") + (s ? "R" : "L") + " flanks, gear " +
              std::to_string(gear_no);
    o.x_label = "tooth k (pitch k → k+1)";
    o.y_label = "f_pt, µm";
    o.horizontal_lines = {0.0};
    if (const auto t = tol.get_um(ToleranceKind::kSinglePitch)) {
      o.bands.push_back({-*t, *t, "±f_pT", "#56B4E9"});
    }
    o.width_px = 500;
    o.height_px = 300;
    figures.push_back({std::string("pitch_") + (s ? "R" : "L") + ".svg",
                       xy_plot_svg({{"measured", k, g.pitch_measured[s], SeriesStyle::kStems, ""},
                                    {"true", k, g.pitch_true[s], SeriesStyle::kPoints, "#000000"}},
                                   o),
                       "Single pitch deviations, measured (stems) and true (dots)", row});
  }
  if (!g.ball_measured.empty()) {
    std::vector<double> k, m, t;
    const double m0 = *std::min_element(g.ball_measured.begin(), g.ball_measured.end());
    const double t0 = *std::min_element(g.ball_true.begin(), g.ball_true.end());
    for (std::size_t i = 0; i < g.ball_measured.size(); ++i) {
      k.push_back(static_cast<double>(i + 1));
      m.push_back(g.ball_measured[i] - m0);
      t.push_back(g.ball_true[i] - t0);
    }
    XYPlotOptions o;
    o.title = "runout: ball position per space, gear " + std::to_string(gear_no);
    o.x_label = "space k (between teeth k and k+1)";
    o.y_label = "radial position − min, µm";
    o.y_from_zero = true;
    if (const auto tr = tol.get_um(ToleranceKind::kRunout)) {
      o.bands.push_back({0.0, *tr, "F_rT", "#56B4E9"});
    }
    o.width_px = 500;
    o.height_px = 300;
    figures.push_back({"runout.svg",
                       xy_plot_svg({{"measured", k, m, SeriesStyle::kStems, ""},
                                    {"true", k, t, SeriesStyle::kPoints, "#000000"}},
                                   o),
                       "Radial runout: the ball's radial position in every space", row});
  }
  // Error histograms, both sides on shared bins, markers at each side's 95 % interval.
  int count = 0;
  for (const ParameterSummary& s : p.parameters) {
    if (count++ % 3 == 0) ++row;
    std::vector<const RelativeHistogram*> data;
    for (const ParameterSideSummary& side : s.sides) data.push_back(&side.error_values);
    if (data.empty() || data.front()->total() == 0) continue;
    const HistogramBins bins = freedman_diaconis_bins(data, 60);
    Histogram h = bins.histogram_of(*data.front());
    for (std::size_t i = 1; i < data.size(); ++i) h.merge(bins.histogram_of(*data[i]));
    HistogramPlotOptions o;
    o.title = parameter_symbol(s.parameter) + ": error = measured − true";
    o.x_label = "error, µm";
    o.bars_label = "all sides";
    for (const ParameterSideSummary& side : s.sides) {
      if (!side.interval95) continue;
      o.markers.push_back({side.interval95->lo, side.side + " 95 %", "", true});
      o.markers.push_back({side.interval95->hi, "", "", true});
    }
    o.width_px = 420;
    o.height_px = 300;
    figures.push_back({"error_" + parameter_symbol(s.parameter) + ".svg", histogram_svg(h, o),
                       "Error of " + parameter_symbol(s.parameter) +
                           " over the run, with the shortest 95 % interval of each side",
                       row});
  }
  return figures;
}

namespace {
// ", " and " ≤ " with no-break spaces (U+00A0), so that an interval or a limit stays on one line
// in a narrow table column.
constexpr const char* kNoBreak = ",\u00a0";
std::string acceptance_text(const ParameterConformity& k) {
  const std::string le = "\u00a0≤\u00a0";
  const std::string upper = parameter_text(*k.acceptance.upper, 2);
  if (!k.acceptance.lower) return "y" + le + upper;
  if (std::abs(*k.acceptance.lower + *k.acceptance.upper) < 0.005) return "|y|" + le + upper;
  return parameter_text(*k.acceptance.lower, 2) + le + "y" + le + upper;
}
}  // namespace

void add_parameter_section(HtmlReport& report, const MonteCarloRun& mc,
                           const ParameterPresentation& p, const std::vector<RunFigure>& figures) {
  const ParameterEvaluator& e = *mc.parameter_evaluator();
  report.heading("Gear parameters (ISO 1328-1:2013)");
  report.paragraph(
      "Each simulated measurement is evaluated like gear-measuring software: profile and helix "
      "traces, least-squares mean line over the evaluation range (profile L " +
      parameter_text(e.profile_start_mm(), 2) + " … " + parameter_text(e.profile_end_mm(), 2) +
      " mm, helix z " + parameter_text(e.helix_start_mm(), 2) + " … " +
      parameter_text(e.helix_end_mm(), 2) +
      " mm), pitch at the reference circle, runout with a ball in every space" +
      (mc.gear().helical()
           ? "; on this helical gear (β " + parameter_text(mc.scenario().gear.helix_angle_deg, 2) +
                 "°) every deviation in the transverse plane, the reading along the helicoid's "
                 "normal ÷ cos β_b"
           : std::string()) +
      ". error = measured − true, true = the same evaluation of the real surface on a dense "
      "trace; U = 2·√(u² + bias²). Measurement error: measured − true at the same points; "
      "sampling error: true at the points − dense true (standard deviations).");
  HtmlTable t;
  t.caption = "Parameters (µm)";
  t.header = {"parameter",     "side",           "n",       "true mean",
              "measured mean", "bias",           "u",       "U",
              "95 % interval", "95 % symmetric", "u meas.", "u sampl."};
  for (const ParameterSummary& s : p.parameters) {
    for (const ParameterSideSummary& side : s.sides) {
      const bool any = side.error_moments.count() > 0;
      t.rows.push_back(
          {{parameter_symbol(s.parameter), side.side, std::to_string(side.error_moments.count()),
            any ? parameter_text(side.true_moments.mean(), 2) : "–",
            any ? parameter_text(side.measured_moments.mean(), 2) : "–",
            any ? parameter_text(side.bias_um, 3) : "–", any ? parameter_text(side.u_um, 3) : "–",
            any ? parameter_text(side.U95_um, 2) : "–",
            side.interval95 ? "[" + parameter_text(side.interval95->lo, 2) + kNoBreak +
                                  parameter_text(side.interval95->hi, 2) + "]"
                            : "–",
            side.symmetric95 ? "[" + parameter_text(side.symmetric95->lo, 2) + kNoBreak +
                                   parameter_text(side.symmetric95->hi, 2) + "]"
                             : "–",
            side.measurement_error.count() > 1 ? parameter_text(side.measurement_error.stddev(), 3)
                                               : "–",
            side.sampling_error.count() > 1 ? parameter_text(side.sampling_error.stddev(), 3)
                                            : "–"}});
    }
  }
  report.table(t);
  HtmlTable c;
  c.caption =
      "Conformity, rule " + e.spec().decision_rule +
      " (ISO 14253-1): false accept = accepted although the true value is out of "
      "tolerance; false reject = rejected although it conforms; fractions of all items. "
      "U/T: the largest U over the tolerance interval's width (2T for ±T). The guard-banded "
      "acceptance narrows each limit by how far the error's probabilistically symmetric 95 % "
      "interval reaches past zero on that side (a skewed error law gets unequal bands). "
      "p_c: the run's worst measured value (its flank side) and the probability, from that "
      "side's error law, that its true value conforms.";
  c.header = {"parameter",
              "tolerance",
              "T",
              "U/T",
              "acceptance",
              "false accept",
              "false reject",
              "false reject (guard-banded)",
              "worst measured: p_c"};
  for (const ParameterSummary& s : p.parameters) {
    const ParameterConformity& k = s.conformity;
    if (!k.tolerance_um) {
      c.rows.push_back({{parameter_symbol(s.parameter), "–", "no tolerance in the set", "", "", "",
                         "", "", ""}});
      continue;
    }
    c.rows.push_back({{parameter_symbol(s.parameter), k.tolerance_symbol,
                       (k.two_sided ? "±" : "") + parameter_text(*k.tolerance_um, 1),
                       parameter_text(k.u_over_t, 2), acceptance_text(k),
                       parameter_text(100 * k.chosen().false_accept_rate(), 2) + " %",
                       parameter_text(100 * k.chosen().false_reject_rate(), 2) + " %",
                       parameter_text(100 * k.guard_banded.false_reject_rate(), 2) + " %",
                       parameter_text(k.worst_measured_um, 2) + " (" + k.worst_side +
                           "): " + parameter_text(k.conformance_probability_of_worst, 3)}});
  }
  report.table(c);
  for (const std::string& note : p.notes) report.paragraph("Note: " + note);
  add_figure_rows(report, figures);
}

}  // namespace gearmc
