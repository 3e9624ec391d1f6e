// report.html of an R-Test evaluation (r_test_output.h), built with the project's SVG plots and
// HTML page builder: the instrument seen from above, the calibration residuals, P3's GUM of the
// base points with its budget, the budget of the ball centre per input class, and the routes'
// expanded uncertainties against the verification errors (P3's Fig. 5 comparison).
#include <algorithm>
#include <cmath>
#include <iomanip>
#include <numbers>
#include <sstream>

#include "core/constants.h"
#include "engine/apps/r_test/r_test_output.h"
#include "engine/reports/html_report.h"
#include "engine/reports/svg_plot.h"

namespace gearmc::rtest {
namespace {

std::string fx(double v, int d) {
  std::ostringstream s;
  s.setf(std::ios::fixed);
  s.precision(d);
  s << v;
  return s.str();
}

Series circle(const std::string& label, const Vector3d& c, double radius, const std::string& col) {
  Series s;
  s.label = label;
  s.colour = col;
  for (int k = 0; k <= 120; ++k) {
    const double t = 2 * std::numbers::pi * k / 120;
    s.x.push_back(c.x() + radius * std::cos(t));
    s.y.push_back(c.y() + radius * std::sin(t));
  }
  return s;
}

std::string sketch_svg(const RTestModel& m) {
  const Geometry& g = m.geometry;
  std::vector<Series> series;
  series.push_back(circle("ball", g.centre, g.ball_radius, "#0072B2"));
  Series axes, tips, bases;
  axes.label = "axes";
  axes.colour = "#999999";
  tips.label = "C_i0";
  tips.style = SeriesStyle::kPoints;
  tips.colour = "#D55E00";
  bases.label = "C_i1";
  bases.style = SeriesStyle::kPoints;
  bases.colour = "#009E73";
  const double l0 = g.reading_at_centre();
  for (int i = 0; i < kSensors; ++i) {
    const Vector3d tip = g.base[i] + l0 * g.axis[i];
    axes.x.insert(axes.x.end(), {g.base[i].x(), g.centre.x(), NAN});
    axes.y.insert(axes.y.end(), {g.base[i].y(), g.centre.y(), NAN});
    tips.x.push_back(tip.x());
    tips.y.push_back(tip.y());
    bases.x.push_back(g.base[i].x());
    bases.y.push_back(g.base[i].y());
    series.push_back(circle(i == 0 ? "tips" : "", tip, g.tip_radius, "#D55E00"));
  }
  series.push_back(axes);
  series.push_back(tips);
  series.push_back(bases);
  XYPlotOptions o;
  o.title = "Instrument seen from above (plane M, z up)";
  o.x_label = "x, mm";
  o.y_label = "y, mm";
  const double e = 1.25 * g.base_radius;
  o.x_min = -e;
  o.x_max = e;
  o.y_min = -e;
  o.y_max = e;
  o.width_px = 560;
  o.height_px = 560;
  return xy_plot_svg(series, o);
}

std::string residuals_svg(const RTestResult& r) {
  std::vector<Series> series;
  static const char* colours[] = {"#0072B2", "#D55E00", "#009E73"};
  for (int i = 0; i < kSensors; ++i) {
    Series s;
    s.label = "sensor " + std::to_string(i + 1);
    s.style = SeriesStyle::kStems;
    s.colour = colours[i];
    for (int j = 0; j < kCalibrationPoints; ++j) {
      s.x.push_back(i * kCalibrationPoints + j + 1);
      s.y.push_back(r.observed.fit[i].residuals[j] * kUmPerMm);
    }
    series.push_back(s);
  }
  XYPlotOptions o;
  o.title = "Calibration residuals g_ij = |P_j − C_i0j| − (R + r)";
  o.x_label = "reading (sensor 1: 1–6, sensor 2: 7–12, sensor 3: 13–18)";
  o.y_label = "residual, µm";
  o.horizontal_lines = {0.0};
  o.x_min = 0;
  o.x_max = 19;
  return xy_plot_svg(series, o);
}

std::string fig5_svg(const RTestResult& r, int k, bool zoom) {
  const Verification& v = r.verification;
  const double n = static_cast<double>(v.positions.size());
  std::vector<Series> series;
  Series actual;
  actual.label = "actual";
  actual.style = SeriesStyle::kPoints;
  actual.colour = "#000000";
  Series chain, p3;
  chain.label = "chain GUM";
  chain.colour = "#009E73";
  p3.label = "P3 GUM";
  p3.colour = "#E69F00";
  for (std::size_t q = 0; q < v.positions.size(); ++q) {
    const double x = static_cast<double>(q) + 1.0;
    actual.x.push_back(x);
    actual.y.push_back(v.actual95[q][k] * kUmPerMm);
    chain.x.push_back(x);
    chain.y.push_back(v.gum_chain_U[q][k] * kUmPerMm);
    p3.x.push_back(x);
    p3.y.push_back(v.gum_p3_U[q][k] * kUmPerMm);
  }
  series.push_back(actual);
  series.push_back(chain);
  series.push_back(p3);
  for (const Prediction& p : r.predictions) {
    if (p.id != "gum_mcm_p3" && p.id != "full_mcm") continue;
    Series s;
    s.label = p.id == "full_mcm" ? "full MCM at P_m" : "P3 GUM+MCM at P_m";
    s.colour = p.id == "full_mcm" ? "#0072B2" : "#D55E00";
    s.x = {1.0, n};
    s.y = {p.axis[k].U * kUmPerMm, p.axis[k].U * kUmPerMm};
    series.push_back(s);
  }
  XYPlotOptions o;
  o.title = std::string(zoom ? "Near the actual errors, " : "Predicted U and actual 95 % error, ") +
            "xyz"[k] + " axis";
  o.x_label = "verification position";
  o.y_label = "µm";
  o.y_from_zero = true;
  if (zoom) {
    o.y_min = 0.0;
    o.y_max = 2.0 * v.pooled95[k] * kUmPerMm;
  }
  o.width_px = 600;
  o.height_px = 420;
  return xy_plot_svg(series, o);
}

}  // namespace

std::string r_test_report_html(const uncertainty::UncertaintyModel& model, const RTestModel& m,
                               const RTestResult& r, const Provenance& provenance) {
  const Geometry& g = m.geometry;
  HtmlReport page("gearmc uncertainty: " + model.name + " (R-Test)");
  std::ostringstream intro;
  intro << "P3's contact R-Test: a ball of radius " << g.ball_radius << " mm touched by three "
        << "sensors (tip radius " << g.tip_radius << " mm) on mutually perpendicular axes at "
        << fx(g.alpha * 180 / std::numbers::pi, 2) << "° to plane M, base points " << g.base_radius
        << " mm from O'. Calibration at " << kCalibrationPoints << " points O ± "
        << m.settings.calibration_step << " mm along x, y, z; seed " << m.seed
        << ", coverage probability " << m.coverage_probability << ". Form errors are "
        << (m.settings.form_per_sensor ? "fixed per sensor (the same contact patch)"
                                       : "drawn per reading")
        << ". Method and assumptions: docs/r-test.md.";
  {  // The verdict box: does each route's U at P_m cover the verification's actual 95 % error?
    const Verification& v = r.verification;
    std::vector<std::string> lines;
    int covering = 0;
    for (const Prediction& p : r.predictions) {
      std::string short_axes;
      double lo = INFINITY, hi = 0.0;  // U ÷ actual over the axes
      for (int k = 0; k < 3; ++k) {
        lo = std::min(lo, p.axis[k].U / v.pooled95[k]);
        hi = std::max(hi, p.axis[k].U / v.pooled95[k]);
        if (p.axis[k].U < v.pooled95[k]) {
          short_axes += std::string(short_axes.empty() ? "" : ", ") + "xyz"[k] + " (" +
                        fx(100.0 * (p.axis[k].U / v.pooled95[k] - 1.0), 1) + " %)";
        }
      }
      covering += short_axes.empty();
      lines.push_back(p.label + ": U = " + fx(p.axis[0].U * kUmPerMm, 3) + ", " +
                      fx(p.axis[1].U * kUmPerMm, 3) + ", " + fx(p.axis[2].U * kUmPerMm, 3) +
                      " µm (x, y, z) — " +
                      (short_axes.empty() ? "covers the actual 95 % error on every axis (U ÷ "
                                            "actual " +
                                                fx(lo, 2) + " … " + fx(hi, 2) + ")"
                                          : "below the actual 95 % error on " + short_axes));
    }
    page.verdict(
        std::to_string(covering) + " of " + std::to_string(r.predictions.size()) +
            " routes give a U at P_m that covers the verification's actual 95 % |error| (" +
            fx(v.pooled95[0] * kUmPerMm, 3) + ", " + fx(v.pooled95[1] * kUmPerMm, 3) + ", " +
            fx(v.pooled95[2] * kUmPerMm, 3) + " µm on x, y, z).",
        lines);
  }
  page.paragraph(intro.str());
  for (const std::string& w : r.warnings) page.paragraph("Warning: " + w);
  page.contents();

  page.heading("Instrument");
  page.figure(sketch_svg(m),
              "Top view: ball, tips and base points (nominal), axes projected on "
              "plane M.");
  HtmlTable inputs;
  inputs.caption = "Type-B inputs (model file)";
  inputs.header = {"input", "law (mm)", "u, µm", "ν"};
  for (int c = 0; c < kClasses; ++c) {
    inputs.rows.push_back({{input_class_names()[c], m.laws[c].text, fx(m.laws[c].u * kUmPerMm, 4),
                            std::isfinite(m.laws[c].dof) ? fx(m.laws[c].dof, 0) : "∞"},
                           false});
  }
  page.table(inputs);

  page.heading("Calibration");
  page.figure(residuals_svg(r), "Residuals of the least-squares fit of the simulated calibration.");
  HtmlTable base;
  base.caption = "P3's GUM of the base points (µm; budget by exact sensitivities)";
  base.header = {"C_i1", "fitted − true", "u exact", "u varied", "ν_eff", "k", "U"};
  for (const std::string& c : input_class_names()) base.header.push_back(c);
  for (int i = 0; i < kSensors; ++i) {
    for (int k = 0; k < 3; ++k) {
      const BaseCoordinate& b = r.base[i][k];
      HtmlTable::Row row;
      row.cells = {"C" + std::to_string(i + 1) + "1 " + "xyz"[k],
                   fx((b.estimate - b.true_value) * kUmPerMm, 3),
                   fx(b.u_exact * kUmPerMm, 3),
                   fx(b.u_varied * kUmPerMm, 3),
                   fx(b.nu_eff, 0),
                   fx(b.k, 3),
                   fx(b.U * kUmPerMm, 3)};
      for (double c : b.budget) row.cells.push_back(fx(c * kUmPerMm, 3));
      base.rows.push_back(row);
    }
  }
  page.table(base);
  {
    std::ostringstream s;
    s << "Varied-parameter method: δ = " << m.settings.varied_delta
      << " mm, e = " << m.settings.varied_step
      << " mm; its sensitivities differ from the exact ones by at most " << std::scientific
      << std::setprecision(2) << r.sensitivity_max_rel_diff << " (relative, worst input).";
    page.paragraph(s.str());
  }

  page.heading("Budget of the ball centre");
  for (const Prediction& p : r.predictions) {
    if (p.budget.empty()) continue;
    HtmlTable t;
    t.caption = p.label + ": |c| u per input, µm";
    t.header = {"input", "x", "y", "z"};
    for (const BudgetItem& b : p.budget) {
      t.rows.push_back({{b.name, fx(b.contribution[0] * kUmPerMm, 3),
                         fx(b.contribution[1] * kUmPerMm, 3), fx(b.contribution[2] * kUmPerMm, 3)},
                        false});
    }
    page.table(t);
    if (p.id == "gum_chain") {
      std::vector<std::pair<std::string, std::string>> figs;
      for (int k = 0; k < 3; ++k) {
        std::vector<std::string> labels;
        std::vector<double> values;
        for (const BudgetItem& b : p.budget) {
          labels.push_back(b.name);
          values.push_back(b.contribution[k] * kUmPerMm);
        }
        BarChartOptions bo;
        bo.title = std::string("whole chain, ") + "xyz"[k];
        bo.x_label = "|c| u, µm";
        bo.decimals = 3;
        bo.width_px = 440;
        figs.push_back(
            {bar_chart_svg(labels, values, bo),
             std::string("Budget of the ball centre's ") + "xyz"[k] + " by input class."});
      }
      page.figure_row(figs);
    }
  }

  page.heading("Predictions against the verification");
  const Verification& v = r.verification;
  HtmlTable t;
  t.caption = "Expanded uncertainty (p = " + fx(m.coverage_probability, 2) +
              ") at P_m and the actual 95 % error of the verification, µm";
  t.header = {"route", "U_x", "U_y", "U_z", "vs actual x", "y", "z"};
  for (const Prediction& p : r.predictions) {
    HtmlTable::Row row;
    row.cells = {p.label};
    for (int k = 0; k < 3; ++k) row.cells.push_back(fx(p.axis[k].U * kUmPerMm, 3));
    for (int k = 0; k < 3; ++k) {
      row.cells.push_back(fx(100.0 * (p.axis[k].U / v.pooled95[k] - 1.0), 1) + " %");
    }
    t.rows.push_back(row);
  }
  HtmlTable::Row actual;
  actual.highlight = true;
  actual.cells = {"verification: actual 95 % |error| (" + std::to_string(v.positions.size()) +
                  " positions × " + std::to_string(m.settings.repetitions) + ")"};
  for (int k = 0; k < 3; ++k) actual.cells.push_back(fx(v.pooled95[k] * kUmPerMm, 3));
  actual.cells.insert(actual.cells.end(), {"", "", ""});
  t.rows.push_back(actual);
  HtmlTable::Row at_m;
  at_m.highlight = true;
  at_m.cells = {"verification: actual 95 % |error| at P_m (" +
                std::to_string(m.settings.repetitions) + " repetitions)"};
  for (int k = 0; k < 3; ++k) at_m.cells.push_back(fx(v.at_measured95[k] * kUmPerMm, 3));
  at_m.cells.insert(at_m.cells.end(), {"", "", ""});
  t.rows.push_back(at_m);
  page.table(t);
  for (int k = 0; k < 3; ++k) {
    page.figure_row(
        {{fig5_svg(r, k, false),
          std::string("As P3's Fig. 5, ") + "xyz"[k] +
              " axis. Points: the actual 95 % |error| at each position over the repetitions; "
              "lines: the whole-chain GUM and P3's GUM (with the measuring readings) at each "
              "position, P3's GUM+MCM and the full MCM at P_m."},
         {fig5_svg(r, k, true), "The same, y axis from 0 to twice the actual 95 % error."}});
  }
  page.preformatted(model.source_text, "Model file " + model.source_path);
  page.paragraph(provenance_line(provenance));
  return page.html();
}

}  // namespace gearmc::rtest
