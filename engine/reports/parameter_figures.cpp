// The gear parameters in report.html: the tables and the charts of parameter_report.h — profile
// and helix traces of one gear in the style of gear-measuring software (deviation against roll
// length or face position, the measured points, the mean line, the real surface and a tolerance
// band), pitch and runout bars, and each parameter's error histogram with its 95 % interval.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <string>

#include "engine/reports/html_report.h"
#include "engine/reports/inspection_charts.h"
#include "engine/reports/parameter_report.h"
#include "engine/reports/svg_plot.h"
#include "engine/statistics/histogram_bins.h"
#include "gears/tolerances.h"

namespace gearmc {
namespace {

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

const ParameterSummary* summary_of(const ParameterPresentation& p, GearParameter q) {
  for (const ParameterSummary& s : p.parameters) {
    if (s.parameter == q) return &s;
  }
  return nullptr;
}

// The run's U of a parameter on a side ("left", "right"); none when not evaluated.
std::optional<double> expanded_uncertainty(const ParameterPresentation& p, GearParameter q,
                                           const std::string& side) {
  const ParameterSummary* s = summary_of(p, q);
  if (s == nullptr) return std::nullopt;
  for (const ParameterSideSummary& x : s->sides) {
    if (x.side == side && x.error_moments.count() > 0) return x.U95_um;
  }
  return std::nullopt;
}

// The ISO 1328-1 class a value meets, when the scenario's tolerances are ISO 1328-1's and the gear
// is in the standard's scope (none otherwise: the row then prints no class).
struct ClassOf {
  const MonteCarloRun& mc;
  bool applies() const {
    if (mc.tolerances().standard != ToleranceStandard::kIso1328_1_2013) return false;
    try {
      const InvoluteGear& g = mc.gear();
      iso1328_tolerances(5, g.reference_diameter_mm(), g.module_mm(), g.face_width_mm(), g.teeth());
      return true;
    } catch (const ToleranceError&) {
      return false;
    }
  }
  std::optional<int> operator()(GearParameter q, double value_um) const {
    const InvoluteGear& g = mc.gear();
    const std::optional<ToleranceKind> kind = parameter_tolerance_kind(q);
    if (!kind) return std::nullopt;
    return iso1328_class_met(*kind, value_um, g.reference_diameter_mm(), g.module_mm(),
                             g.face_width_mm(), g.teeth());
  }
};

// The profile or helix sheet of the chart gear: the chosen teeth of each side, their values
// with the run's U and tolerances.
InspectionSheet trace_sheet(const MonteCarloRun& mc, const ParameterPresentation& p,
                            const std::vector<FlankTrace>& traces, bool profile, int gear_no) {
  const ToleranceSet& tol = mc.tolerances();
  const std::array<GearParameter, 3> params =
      profile ? std::array{GearParameter::kFalpha, GearParameter::kfHalpha, GearParameter::kffalpha}
              : std::array{GearParameter::kFbeta, GearParameter::kfHbeta, GearParameter::kffbeta};
  const std::array<const char*, 3> symbols =
      profile ? std::array{"Fα", "fHα", "ffα"} : std::array{"Fβ", "fHβ", "ffβ"};
  const ClassOf class_of{mc};
  const bool classes = class_of.applies();
  InspectionSheet sheet;
  sheet.title = std::string(profile ? "Profile" : "Helix") + " — gear " + std::to_string(gear_no);
  sheet.position_label = profile ? "roll length L, mm" : "face position z, mm";
  sheet.top_word = profile ? "tip" : "z = b";
  sheet.positions_downwards = profile && mc.gear().internal();
  sheet.total_tolerance_um = parameter_tolerance_um(tol, params[0]);
  sheet.slope_tolerance_um = parameter_tolerance_um(tol, params[1]);
  const std::vector<int> teeth = chart_teeth(traces, mc.gear().teeth());
  for (int s = 0; s < 2; ++s) {
    const FlankSide side = s == 0 ? FlankSide::kLeft : FlankSide::kRight;
    const std::string side_name = s == 0 ? "left" : "right";
    InspectionSide& out = sheet.sides[s];
    out.name = s == 0 ? "left flanks" : "right flanks";
    for (std::size_t i = 0; i < params.size(); ++i) {
      InspectionValueRow row;
      row.symbol = symbols[i];
      row.tolerance_um = parameter_tolerance_um(tol, params[i]);
      row.two_sided = parameter_signed(params[i]);
      row.expanded_uncertainty_um = expanded_uncertainty(p, params[i], side_name);
      out.rows.push_back(row);
    }
    for (int tooth : teeth) {
      for (const FlankTrace& t : traces) {
        if (t.tooth != tooth || t.side != side) continue;
        InspectionTrace chart;
        chart.tooth = tooth;
        chart.x_mm = t.x_mm;
        chart.measured_um = t.measured_um;
        chart.dense_x_mm = t.dense_x_mm;
        chart.dense_um = t.dense_um;
        chart.range_start_mm = t.range_start_mm;
        chart.range_end_mm = t.range_end_mm;
        const bool line = t.measured_line.samples > 0;
        if (line) {
          chart.mean_intercept_um = t.measured_line.intercept_um;
          chart.mean_slope_um_per_mm = t.measured_line.slope_um_per_mm;
        }
        const double values[3] = {t.measured_line.total_um, t.measured_line.slope_um,
                                  t.measured_line.form_um};
        for (std::size_t i = 0; i < params.size(); ++i) {
          const double v = line ? values[i] : std::nan("");
          out.rows[i].values_um.push_back(v);
          if (classes) out.rows[i].classes.push_back(class_of(params[i], v));
        }
        out.traces.push_back(std::move(chart));
      }
    }
  }
  return sheet;
}

}  // namespace

std::vector<RunFigure> parameter_figures(const MonteCarloRun& mc, const RunResults& r,
                                         const ParameterPresentation& p) {
  std::vector<RunFigure> figures;
  if (!r.parameters || !r.parameters->chart_gear) return figures;
  const GearTraces& g = r.parameters->chart;
  const int gear_no = *r.parameters->chart_gear;
  const ToleranceSet& tol = mc.tolerances();
  int row = 1000;  // after the run's own figures
  for (const bool profile : {true, false}) {
    const std::vector<FlankTrace>& traces = profile ? g.profile : g.helix;
    if (traces.empty()) continue;
    ++row;
    figures.push_back(
        {profile ? "profile.svg" : "helix.svg",
         inspection_sheet_svg(trace_sheet(mc, p, traces, profile, gear_no)),
         std::string(profile ? "Profile" : "Helix") + " traces of gear " + std::to_string(gear_no) +
             ", as gear-measuring software draws them (values of the measured traces; U from "
             "the run, T from the scenario's tolerances" +
             (ClassOf{mc}.applies() ? ", Q the ISO 1328-1 class the value meets)" : ")"),
         row, true});
  }
  // Pitch: f_pt,k per tooth and the cumulative F_pk, measured and true, each side with its values.
  const ClassOf class_of{mc};
  const bool classes = class_of.applies();
  const auto values_text = [&](GearParameter q, double measured, double truth,
                               const std::string& side) {
    std::string text = parameter_symbol(q) + " " + parameter_text(measured, 1) + " µm";
    if (const auto t = parameter_tolerance_um(tol, q)) {
      text += std::string(" (T ") + (q == GearParameter::kfpt ? "±" : "") + parameter_text(*t, 1);
      if (const auto U = expanded_uncertainty(p, q, side)) text += ", U " + parameter_text(*U, 1);
      if (classes) {
        const auto c = class_of(q, measured);
        text += c ? ", Q" + std::to_string(*c) : std::string(", Q>11");
      }
      text += ")";
    }
    return text + ", true " + parameter_text(truth, 1) + " µm";
  };
  for (const bool cumulative : {false, true}) {
    ++row;
    for (int s = 0; s < 2; ++s) {
      if (g.pitch_measured[s].empty()) continue;
      const std::string side = s ? "right" : "left", letter = s ? "R" : "L";
      std::vector<double> k;
      for (int i = 1; i <= static_cast<int>(g.pitch_measured[s].size()); ++i) k.push_back(i);
      XYPlotOptions o;
      o.horizontal_lines = {0.0};
      o.width_px = 500;
      o.height_px = 300;
      if (!cumulative) {
        o.title = "single pitch f_pt, " + letter + " flanks, gear " + std::to_string(gear_no);
        o.x_label = "tooth k (pitch k → k+1)";
        o.y_label = "f_pt,k, µm";
        if (const auto t = tol.get_um(ToleranceKind::kSinglePitch)) {
          o.bands.push_back({-*t, *t, "±f_pT", "#56B4E9"});
        }
        const auto largest = [](const std::vector<double>& v) {
          double m = 0.0;
          for (double x : v) m = std::max(m, std::abs(x));
          return m;
        };
        figures.push_back(
            {"pitch_" + letter + ".svg",
             xy_plot_svg({{"measured", k, g.pitch_measured[s], SeriesStyle::kStems, ""},
                          {"true", k, g.pitch_true[s], SeriesStyle::kPoints, "#000000"}},
                         o),
             "Single pitch deviations of the " + letter +
                 " flanks, measured (stems) and true "
                 "(dots): " +
                 values_text(GearParameter::kfpt, largest(g.pitch_measured[s]),
                             largest(g.pitch_true[s]), side) +
                 " (largest |f_pt,k|)",
             row});
        continue;
      }
      const std::vector<double> m = cumulative_pitch_um(g.pitch_measured[s]);
      const std::vector<double> t = cumulative_pitch_um(g.pitch_true[s]);
      const auto finite = [](const std::vector<double>& v) {
        return std::all_of(v.begin(), v.end(), [](double x) { return std::isfinite(x); });
      };
      if (!finite(m) || !finite(t)) continue;  // a tooth without a value: no F_p either
      const auto spread = [](const std::vector<double>& v) {
        const auto [lo, hi] = std::minmax_element(v.begin(), v.end());
        return std::pair{*lo, *hi - *lo};
      };
      const auto [m_lo, m_Fp] = spread(m);
      o.title = "cumulative pitch F_pk, " + letter + " flanks, gear " + std::to_string(gear_no);
      o.x_label = "tooth k";
      o.y_label = "F_pk = u_k − u_1, µm";
      if (const auto T = tol.get_um(ToleranceKind::kCumulativePitch)) {
        // The tolerance as a band of height F_pT from the lowest measured F_pk: the curve stays
        // inside it exactly when F_p ≤ F_pT.
        o.bands.push_back({m_lo, m_lo + *T, "F_pT from the lowest F_pk", "#56B4E9"});
      }
      figures.push_back({"cumulative_pitch_" + letter + ".svg",
                         xy_plot_svg({{"measured", k, m, SeriesStyle::kLineAndPoints, ""},
                                      {"true", k, t, SeriesStyle::kPoints, "#000000"}},
                                     o),
                         "Cumulative pitch deviations of the " + letter +
                             " flanks, measured (line) and true "
                             "(dots): " +
                             values_text(GearParameter::kFp, m_Fp, spread(t).second, side) +
                             " (F_p = max − min of F_pk)",
                         row});
    }
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
  if (const std::string sizes = size_gauges_text(mc); !sizes.empty()) report.paragraph(sizes);
  if (const auto& spec = e.spec(); spec.profile_cutoff_mm || spec.helix_cutoff_mm) {
    const auto cut = [](const std::optional<double>& c) {
      return c ? "λc " + parameter_text(*c, 3) + " mm" : std::string("unfiltered");
    };
    report.paragraph(
        "Filter (ISO 16610-21 Gaussian, first-order regression at the trace ends): "
        "profile " +
        cut(spec.profile_cutoff_mm) + ", helix " + cut(spec.helix_cutoff_mm) +
        "; F, f_H, f_f of the filtered measured and true traces, the charts show "
        "the unfiltered points.");
  }
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
      "U/T: the largest U over the tolerance interval's width (2T for ±T); Q_MP = 2U/(T_U − T_L) = "
      "2·U/T, the capability ratio of ISO 22514-7 and VDA 5 (≤ 30 %: capable). The guard-banded "
      "acceptance narrows each limit by how far the error's probabilistically symmetric 95 % "
      "interval reaches past zero on that side (a skewed error law gets unequal bands). "
      "p_c: the run's worst measured value (its flank side) and the probability, from that "
      "side's error law, that its true value conforms.";
  c.header = {"parameter",
              "tolerance",
              "T",
              "U/T",
              "Q_MP",
              "acceptance",
              "false accept",
              "false reject",
              "false reject (guard-banded)",
              "worst measured: p_c"};
  for (const ParameterSummary& s : p.parameters) {
    const ParameterConformity& k = s.conformity;
    if (!k.tolerance_um) {
      c.rows.push_back(
          {{parameter_symbol(s.parameter), "–",
            parameter_is_size(s.parameter) ? "a size without allowances (size_allowances_um)"
                                           : "no tolerance in the set",
            "", "", "", "", "", "", ""}});
      continue;
    }
    c.rows.push_back(
        {{parameter_symbol(s.parameter), k.tolerance_symbol, k.tolerance_text(),
          parameter_text(k.u_over_t, 2),
          parameter_text(100 * k.capability_ratio, 0) + " %" + (k.capable() ? "" : " > 30 %"),
          acceptance_text(k), parameter_text(100 * k.chosen().false_accept_rate(), 2) + " %",
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
