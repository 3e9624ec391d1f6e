// report.html of `gearmc uncertainty` (evaluation.h), built with the project's SVG plots and
// HTML page builder.
#include <algorithm>
#include <cmath>
#include <numbers>
#include <sstream>

#include "core/special_functions.h"
#include "engine/apps/uncertainty/evaluation.h"
#include "engine/reports/html_report.h"
#include "engine/reports/svg_plot.h"
#include "engine/statistics/histogram.h"

namespace gearmc::uncertainty {
namespace {

std::string fmt(double v, int decimals) {
  std::ostringstream s;
  s.setf(std::ios::fixed);
  s.precision(decimals);
  s << v;
  return s.str();
}

// The GUM's distribution for Y (JCGM 101 §5.6.2): y + u t_ν, or N(y, u²) for ν = inf.
double gum_pdf(const GumOutput& g, double x) {
  const double t = (x - g.estimate) / g.u;
  if (!std::isfinite(g.nu_eff) || g.nu_eff > 1e7) {
    return std::exp(-0.5 * t * t) / (std::sqrt(2 * std::numbers::pi) * g.u);
  }
  const double nu = std::max(1.0, std::floor(g.nu_eff));
  const double c = std::exp(std::lgamma(0.5 * (nu + 1)) - std::lgamma(0.5 * nu)) /
                   std::sqrt(nu * std::numbers::pi);
  return c * std::pow(1 + t * t / nu, -0.5 * (nu + 1)) / g.u;
}
double gum_cdf(const GumOutput& g, double x) {
  const double t = (x - g.estimate) / g.u;
  const double nu =
      std::isfinite(g.nu_eff) && g.nu_eff <= 1e7 ? std::max(1.0, std::floor(g.nu_eff)) : INFINITY;
  return student_t_cdf(t, nu);
}

// 2 s of the block averages after each block and δ, as in run_mcm's stop rule.
std::string adaptive_svg(const McmResult& r, std::size_t k, int ndig) {
  const double B = static_cast<double>(r.block_size);
  std::vector<double> hs;
  std::vector<std::vector<double>> two_s(4);
  std::vector<double> delta;
  for (int h = 2; h <= r.blocks; ++h) {
    auto sd_avg = [&](auto get) {
      double m = 0;
      for (int b = 0; b < h; ++b) m += get(r.block_values[b]) / h;
      double ss = 0;
      for (int b = 0; b < h; ++b) ss += (get(r.block_values[b]) - m) * (get(r.block_values[b]) - m);
      return 2 * std::sqrt(ss / (h * (h - 1.0)));
    };
    hs.push_back(h);
    two_s[0].push_back(sd_avg([k](const BlockValues& v) { return v.estimate[k]; }));
    two_s[1].push_back(sd_avg([k](const BlockValues& v) { return v.u[k]; }));
    two_s[2].push_back(std::max(sd_avg([k](const BlockValues& v) { return v.lo[k]; }),
                                sd_avg([k](const BlockValues& v) { return v.short_lo[k]; })));
    two_s[3].push_back(std::max(sd_avg([k](const BlockValues& v) { return v.hi[k]; }),
                                sd_avg([k](const BlockValues& v) { return v.short_hi[k]; })));
    double mean = 0;
    for (int b = 0; b < h; ++b) mean += r.block_values[b].estimate[k] / h;
    double ss = 0;
    for (int b = 0; b < h; ++b) {
      const BlockValues& v = r.block_values[b];
      ss += (B - 1) * v.u[k] * v.u[k] + B * (v.estimate[k] - mean) * (v.estimate[k] - mean);
    }
    delta.push_back(numerical_tolerance(std::sqrt(ss / (h * B - 1)), ndig));
  }
  const char* names[] = {"2 s(y)", "2 s(u)", "2 s(y_low)", "2 s(y_high)"};
  std::vector<Series> series;
  for (int i = 0; i < 4; ++i) series.push_back({names[i], hs, two_s[i], SeriesStyle::kLine, ""});
  series.push_back({"δ", hs, delta, SeriesStyle::kLine, "#000000"});
  XYPlotOptions xo;
  xo.title = r.outputs[k].name + ": adaptive stop";
  xo.x_label = "blocks h (of " + std::to_string(r.block_size) + " trials)";
  xo.y_label = "units of " + r.outputs[k].name;
  xo.y_from_zero = true;
  xo.width_px = 900;
  xo.height_px = 320;
  return xy_plot_svg(series, xo);
}

}  // namespace

std::string evaluation_report_html(const UncertaintyModel& model, const McmOptions& o,
                                   const Evaluation& e, const Provenance& provenance) {
  HtmlReport page("gearmc uncertainty: " + model.name);
  {  // The verdict box: per output the Monte Carlo result and whether it validates the GUM's.
    int not_validated = 0, undecided = 0;
    std::vector<std::string> lines;
    for (std::size_t k = 0; k < model.outputs.size(); ++k) {
      const GumOutput& g = e.gum.outputs[k];
      const McmOutput& m = e.mcm.outputs[k];
      const Validation& v = e.validation[k];
      const int d = display_decimals(std::min(g.u, m.u), o.significant_digits);
      not_validated += !v.validated && !v.undecided;
      undecided += v.undecided;
      lines.push_back(g.name + " = " + fmt(m.estimate, d) + ", u " + fmt(m.u, d) + ", " +
                      fmt(100.0 * o.coverage_probability, 0) + " % interval [" +
                      fmt(m.symmetric.lo, d) + ", " + fmt(m.symmetric.hi, d) +
                      "] (Monte Carlo, probabilistically symmetric); the GUM's interval [" +
                      fmt(g.lo, d) + ", " + fmt(g.hi, d) + "]: " + v.verdict() + " (JCGM 101 §8)");
    }
    const std::size_t n = model.outputs.size();
    const std::string headline =
        not_validated == 0 && undecided == 0
            ? "The GUM's results are validated by the Monte Carlo method for " +
                  std::string(n == 1 ? "the output" : "every output (" + std::to_string(n) + ")") +
                  "."
        : not_validated > 0
            ? "The GUM's results are NOT validated for " + std::to_string(not_validated) + " of " +
                  std::to_string(n) + " output(s): use the Monte Carlo intervals (JCGM 101 §8)."
            : "Validation undecided for " + std::to_string(undecided) + " of " + std::to_string(n) +
                  " output(s): more trials would decide (JCGM 101 §8).";
    page.verdict(headline, lines,
                 not_validated > 0 ? HtmlReport::Tone::kBad
                 : undecided > 0   ? HtmlReport::Tone::kNeutral
                                   : HtmlReport::Tone::kGood);
  }
  std::ostringstream intro;
  intro << "GUM (JCGM 100) and Monte Carlo (JCGM 101) side by side for " << model.inputs.size()
        << " input(s) and " << model.outputs.size() << " output(s); coverage probability "
        << o.coverage_probability << ", seed " << o.seed << ", " << e.mcm.trials << " trials";
  if (e.mcm.adaptive) {
    intro << " chosen by the adaptive procedure of JCGM 101 §7.9 (" << e.mcm.blocks << " blocks of "
          << e.mcm.block_size << "; "
          << (e.mcm.converged ? "every result stable" : "NOT stable: max_trials reached") << " to "
          << o.significant_digits << " significant digits)";
  }
  intro << ". Sensitivities: " << kSensitivityMethod << ".";
  page.paragraph(intro.str());
  for (const std::string& w : e.warnings) page.paragraph("Warning: " + w);

  HtmlTable summary;
  summary.caption = "Results (units of each output)";
  summary.header = {"output", "method", "y", "u(y)", "ν_eff", "k", "interval", "§8 validation"};
  for (std::size_t k = 0; k < model.outputs.size(); ++k) {
    const GumOutput& g = e.gum.outputs[k];
    const McmOutput& m = e.mcm.outputs[k];
    const Validation& v = e.validation[k];
    const int d = display_decimals(std::min(g.u, m.u), o.significant_digits);
    summary.rows.push_back({{g.name, "GUM", fmt(g.estimate, d), fmt(g.u, d),
                             g.first_order_vanishes ? std::string("undefined (no first-order term)")
                             : std::isfinite(g.nu_eff) ? fmt(g.nu_eff, 1)
                                                       : "∞",
                             fmt(g.k, 3), "[" + fmt(g.lo, d) + ", " + fmt(g.hi, d) + "]",
                             std::string(v.verdict()) + " (δ " + fmt(v.delta, d + 1) + ", d_low " +
                                 fmt(v.d_low, d + 1) + ", d_high " + fmt(v.d_high, d + 1) + ")"},
                            false});
    summary.rows.push_back(
        {{g.name, "MCM symmetric", fmt(m.estimate, d), fmt(m.u, d), "", "",
          "[" + fmt(m.symmetric.lo, d) + ", " + fmt(m.symmetric.hi, d) + "]", ""},
         true});
    summary.rows.push_back({{g.name, "MCM shortest", "", "", "", "",
                             "[" + fmt(m.shortest.lo, d) + ", " + fmt(m.shortest.hi, d) + "]", ""},
                            false});
  }
  page.table(summary);

  for (std::size_t k = 0; k < model.outputs.size(); ++k) {
    const GumOutput& g = e.gum.outputs[k];
    const McmOutput& m = e.mcm.outputs[k];
    const Validation& v = e.validation[k];
    const ModelOutput& limits = model.outputs[k];  // its tolerance limits (JCGM 106)
    const int d = display_decimals(std::min(g.u, m.u), o.significant_digits);
    page.heading("Output " + g.name + unit_label(model, g.name));
    // Shown range: the MCM 0.05 % to 99.95 % quantiles and both intervals, 100 bars.
    const std::vector<double>& s = m.sorted;
    const std::size_t M = s.size();
    double lo = std::min({s[static_cast<std::size_t>(0.0005 * double(M))], g.lo, m.shortest.lo});
    double hi = std::max(
        {s[std::min(M - 1, static_cast<std::size_t>(0.9995 * double(M)))], g.hi, m.shortest.hi});
    if (!(hi > lo)) {  // every value the same (an output without uncertainty)
      const double w = 1e-6 * std::max(1.0, std::fabs(lo));
      lo -= w;
      hi += w;
    }
    const double pad = 0.05 * (hi - lo);
    lo -= pad;
    hi += pad;
    const std::size_t bins = 100;
    const bool drawable =
        std::isfinite(lo) && std::isfinite(hi) && std::isfinite((hi - lo) / double(bins));
    if (!drawable) {  // tails so heavy (1/X for X near 0) that the range overflows a double
      page.paragraph("No histogram of " + g.name + ": its MCM values from the 0.05 % to the " +
                     "99.95 % quantile span more than a double can hold (" + fmt(lo, d) + " … " +
                     fmt(hi, d) + "); the tables above give its estimate and intervals.");
    } else {
      Histogram hist(lo, (hi - lo) / double(bins), bins);
      for (double x : s) hist.add(x);
      HistogramPlotOptions ho;
      ho.title = g.name + ": " + std::to_string(M) + " MCM values and the GUM density";
      ho.x_label = g.name + unit_label(model, g.name);
      ho.bars_label = "MCM";
      if (g.u > 0) ho.overlay_pdf = [&g](double x) { return gum_pdf(g, x); };
      ho.overlay_label = std::isfinite(g.nu_eff) ? "GUM: y + u t_ν" : "GUM: N(y, u²)";
      ho.markers = {{g.lo, "GUM " + fmt(g.lo, d), "#D55E00", true},
                    {g.hi, "GUM " + fmt(g.hi, d), "#D55E00", true},
                    {m.symmetric.lo, "MCM " + fmt(m.symmetric.lo, d), "#0072B2", false},
                    {m.symmetric.hi, "MCM " + fmt(m.symmetric.hi, d), "#0072B2", false},
                    {m.shortest.lo, "", "#009E73", true},
                    {m.shortest.hi, "", "#009E73", true}};
      // Tolerance limits (JCGM 106), inside the plotted range.
      bool limits_shown = false;
      for (const std::optional<double>& t : {limits.lower, limits.upper}) {
        if (t && *t >= lo && *t <= hi) {
          ho.markers.push_back({*t, "T " + fmt(*t, d), "#000000", false});
          limits_shown = true;
        }
      }
      ho.x_min = lo;
      ho.x_max = hi;
      ho.width_px = 900;
      ho.height_px = 420;
      page.figure(
          histogram_svg(hist, ho),
          std::string("Histogram of the MCM values with the GUM density (expected count per "
                      "bar); dashed: the GUM interval y ± U (orange), solid blue: the MCM "
                      "probabilistically symmetric interval, dashed green: the MCM shortest "
                      "interval") +
              (limits_shown ? "; solid black: the tolerance limits." : "."));

      Series mc{"MCM (empirical CDF)", {}, {}, SeriesStyle::kLine, "#0072B2"};
      const std::size_t points = std::min<std::size_t>(M, 500);
      for (std::size_t i = 0; i < points; ++i) {
        const std::size_t idx = (2 * i + 1) * M / (2 * points);
        mc.x.push_back(s[idx]);
        mc.y.push_back((double(idx) + 0.5) / double(M));
      }
      Series gu{"GUM", {}, {}, SeriesStyle::kLine, "#D55E00"};
      for (int i = 0; i <= 200; ++i) {
        const double x = lo + (hi - lo) * i / 200.0;
        gu.x.push_back(x);
        gu.y.push_back(gum_cdf(g, x));
      }
      XYPlotOptions co;
      co.title = g.name + ": distribution functions";
      co.x_label = g.name + unit_label(model, g.name);
      co.y_label = "probability";
      co.x_min = lo;
      co.x_max = hi;
      co.y_min = 0;
      co.y_max = 1;
      co.width_px = 900;
      co.height_px = 360;
      page.figure(xy_plot_svg({mc, gu}, co),
                  "MCM and GUM distribution functions of " + g.name + ".");
    }

    std::vector<std::string> labels;
    for (const ModelInput& in : model.inputs) labels.push_back(in.name);
    BarChartOptions bo;
    bo.title = g.name + ": uncertainty budget |c_i| u(x_i)";
    bo.x_label = "|c_i| u(x_i), units of " + g.name;
    double top = 0;
    for (double c : g.contributions) top = std::max(top, c);
    bo.decimals = top > 0 ? std::max(0, -static_cast<int>(std::floor(std::log10(top))) + 2) : 2;
    bo.width_px = 900;
    page.figure(bar_chart_svg(labels, g.contributions, bo),
                "First-order contributions of the inputs (GUM); u_c = " + fmt(g.u, d) +
                    (model.correlated ? " includes the correlation terms." : "."));

    HtmlTable budget;
    budget.caption = "Budget of " + g.name;
    budget.header = {"input", "law", "x_i", "u(x_i)", "ν_i", "c_i", "|c_i| u(x_i)"};
    for (std::size_t i = 0; i < model.inputs.size(); ++i) {
      std::ostringstream xs, us, cs, ds;
      xs.precision(10);
      us.precision(4);
      cs.precision(4);
      ds.precision(4);
      xs << e.gum.x[i];
      us << e.gum.u[i];
      cs << g.sensitivities[i];
      ds << g.contributions[i];
      budget.rows.push_back(
          {{model.inputs[i].name, model.inputs[i].law_text, xs.str(), us.str(),
            std::isfinite(model.inputs[i].dof) ? fmt(model.inputs[i].dof, 1) : "∞", cs.str(),
            ds.str()},
           false});
    }
    page.table(budget);
    if (e.mcm.adaptive && e.mcm.blocks >= 2) {
      page.figure(adaptive_svg(e.mcm, k, o.significant_digits),
                  "The adaptive stop (JCGM 101 §7.9.4): after each block h, twice the standard "
                  "deviation of the average of the block values of y, u(y) and the interval "
                  "endpoints (the larger of the symmetric and shortest ones), against δ; the run "
                  "stops at the first h where all four are below it.");
    }
    page.paragraph("JCGM 101 §8 validation: δ = " + fmt(v.delta, d + 1) + " (u(y) of the GUM at " +
                   std::to_string(o.significant_digits) +
                   " significant digits), d_low = |y − U − y_low| = " + fmt(v.d_low, d + 1) +
                   ", d_high = |y + U − y_high| = " + fmt(v.d_high, d + 1) +
                   " against the MCM probabilistically symmetric interval, whose endpoints' own "
                   "Monte-Carlo standard errors are s = " +
                   fmt(v.s_low, d + 1) + " and " + fmt(v.s_high, d + 1) + ": the GUM is " +
                   v.verdict() + " for this model (decided at d ± 3s against δ)." +
                   (v.undecided ? " Run more trials (" +
                                      (std::isfinite(v.trials_to_decide)
                                           ? "about " + fmt(v.trials_to_decide, 0)
                                           : std::string("many more")) +
                                      ") to decide; until then use the MCM results."
                    : v.validated ? ""
                                  : " Use the MCM results."));
    if (e.conformity[k].set) {
      page.paragraph(
          "Conformity (JCGM 106:2012 §7.6): the probability that " + limits.name +
          " lies within [" + (limits.lower ? fmt(*limits.lower, d) : std::string("−∞")) + ", " +
          (limits.upper ? fmt(*limits.upper, d) : std::string("∞")) + "] is " +
          fmt(e.conformity[k].gum_probability, 4) + " by the GUM (a Gaussian N(y, u²)) and " +
          fmt(e.conformity[k].mcm_probability, 4) + " by Monte Carlo (the share of the " +
          std::to_string(e.mcm.trials) + " values within the limits).");
    }
  }
  page.preformatted(model.source_text, "Model file " + model.source_path);
  page.paragraph(provenance_line(provenance));
  return page.html();
}

}  // namespace gearmc::uncertainty
