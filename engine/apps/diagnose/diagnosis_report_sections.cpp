// The sections of report.html after the verdict (see diagnosis_report_sections.h): plots from
// svg_plot.h, tables and paragraphs through HtmlReport.
#include "engine/apps/diagnose/diagnosis_report_sections.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <sstream>

#include "engine/apps/diagnose/report_plot_data.h"
#include "engine/reports/svg_plot.h"
#include "engine/statistics/histogram.h"

namespace gearmc::diagnose_report {

void azimuth_section(HtmlReport& report, const ReportContext& ctx) {
  const Diagnosis& d = ctx.d;
  const ReportData& r = ctx.r;
  const bool fitted_any = ctx.fitted_any;
  report.heading("Where: residuals against the approach azimuth");
  {
    std::vector<Series> series;
    // A bounded number of marks: bin means use every point, the grey marks a sample of them.
    const std::vector<std::size_t> shown = plotted_sample(r.before, kMaxScatterMarks, d.seed);
    Series each{"each point, before", {}, {}, SeriesStyle::kPoints, kRawColour};
    for (std::size_t q : shown) {
      each.x.push_back(r.azimuth_deg[q]);
      each.y.push_back(r.before[q]);
    }
    if (shown.size() < r.before.size()) {
      each.label = "sample of " + std::to_string(shown.size()) + " points, before";
    }
    series.push_back(std::move(each));
    series.push_back(
        {"mean per 5°, before", r.azimuth.x, r.azimuth.before, SeriesStyle::kLine, kBefore});
    if (fitted_any) {
      series.push_back(
          {"mean per 5°, after", r.azimuth.x, r.azimuth.after, SeriesStyle::kLine, kAfter});
      std::vector<double> fitted(r.azimuth.x.size());
      for (std::size_t b = 0; b < fitted.size(); ++b) {
        fitted[b] = r.azimuth.before[b] - r.azimuth.after[b];
      }
      series.push_back({"fitted effect", r.azimuth.x, fitted, SeriesStyle::kLine, kFitted});
    }
    XYPlotOptions o;
    o.title = "Residual vs approach azimuth φ";
    o.x_label = "approach azimuth φ = atan2(−n_y, −n_x), deg";
    o.y_label = "residual, µm";
    o.x_min = 0.0;
    o.x_max = 360.0;
    o.horizontal_lines = {0.0};
    report.figure(
        xy_plot_svg(series, o),
        (shown.size() < r.before.size()
             ? "A sample of " + std::to_string(shown.size()) + " of the " + std::to_string(r.n) +
                   " readings (grey: the smallest and largest residual and a random "
                   "sample of the others)"
             : std::string("Every reading (grey)")) +
            " and the mean per 5° of azimuth of every reading before and after the "
            "fit.");
  }
  {
    std::vector<double> angle, before, after;
    std::map<long, std::pair<double, double>> sum;
    std::map<long, int> count;
    for (int q = 0; q < r.n; ++q) {
      const long key = static_cast<long>(r.azimuth_deg[q] / 10.0);
      sum[key].first += r.before[q];
      sum[key].second += r.after[q];
      ++count[key];
    }
    for (const auto& [key, s] : sum) {
      angle.push_back((static_cast<double>(key) + 0.5) * 10.0 * kPi / 180.0);
      before.push_back(s.first / count[key]);
      after.push_back(s.second / count[key]);
    }
    if (!angle.empty()) {  // close the loop
      angle.push_back(angle.front() + 2.0 * kPi);
      before.push_back(before.front());
      after.push_back(after.front());
    }
    std::vector<PolarSeries> polar;
    polar.push_back({"mean per 10°, before", angle, before, SeriesStyle::kLineAndPoints, kBefore});
    if (fitted_any) {
      polar.push_back({"mean per 10°, after", angle, after, SeriesStyle::kLineAndPoints, kAfter});
    }
    PolarPlotOptions o;
    o.title = "Residual around the approach directions";
    o.radius_label = "mean residual, µm (the centre is the smallest value, not 0)";
    report.figure(polar_plot_svg(polar, o),
                  "Polar view: angle = approach azimuth, radius = mean residual per 10°. A probe "
                  "lobing shows as lobes, a constant shift as a circle off the zero ring.");
  }
}

void spectrum_section(HtmlReport& report, const ReportContext& ctx) {
  const Diagnosis& d = ctx.d;
  const int k = ctx.k;
  const bool fitted_any = ctx.fitted_any;
  report.heading("Harmonic spectrum against approach azimuth", 3);
  if (!d.spectrum_before_um.empty()) {
    std::vector<double> orders;
    for (std::size_t o = 0; o < d.spectrum_before_um.size(); ++o) {
      orders.push_back(static_cast<double>(o));
    }
    // One stem per order; with a fit, "before" stands just left of its order and "after" just
    // right, so the two never hide each other.
    const double shift = fitted_any ? 0.15 : 0.0;
    std::vector<double> left = orders, right = orders;
    for (std::size_t o = 0; o < orders.size(); ++o) left[o] -= shift, right[o] += shift;
    std::vector<Series> series;
    series.push_back({"before", left, d.spectrum_before_um, SeriesStyle::kStems, kBefore});
    if (!d.spectrum_null95_before_um.empty()) {
      series.push_back({"95 % null band, before", orders, d.spectrum_null95_before_um,
                        SeriesStyle::kLine, kNullBefore});
    }
    if (fitted_any) {
      series.push_back({"after", right, d.spectrum_after_um, SeriesStyle::kStems, kAfter});
      if (!d.spectrum_null95_after_um.empty()) {
        series.push_back({"95 % null band, after", orders, d.spectrum_null95_after_um,
                          SeriesStyle::kLine, kNullAfter});
      }
    }
    XYPlotOptions o;
    o.title = "Amplitude of each harmonic order of the residual vs φ";
    o.x_label = "order k (cycles per turn of the approach direction)";
    o.y_label = "amplitude, µm";
    o.y_from_zero = true;
    o.x_min = -0.5;
    o.x_max = orders.back() + 0.5;
    const std::string stems =
        fitted_any ? "Stems: the amplitude of each order, before (left) and after the fit (right). "
                   : "Stems: the amplitude of each order. ";
    std::string caption =
        stems +
        "Least-squares amplitude of cos kφ, sin kφ (order 0 = mean). The null band is the 95 % "
        "quantile of each order's amplitude in " +
        std::to_string(k) +
        " simulations of pure noise at the noise floor; an order well above it is structure.";
    if (k == 0) caption = stems + "Least-squares amplitude of cos kφ, sin kφ (order 0 = mean).";
    report.figure(xy_plot_svg(series, o), caption);
  }
}

void position_section(HtmlReport& report, const ReportContext& ctx) {
  const DiagnosisReportInput& in = ctx.in;
  const ReportData& r = ctx.r;
  const bool fitted_any = ctx.fitted_any;
  report.heading("Residuals against measurement order, tooth and position", 3);
  // noise_band: shade ±2σ/√n around zero, where a bin mean of n readings of pure noise at the
  // noise floor σ stays 95 % of the time (n the fewest readings of any bin: the widest band).
  auto line_plot = [&](const Bins& b, const std::string& title, const std::string& x_label,
                       std::string caption, const std::string& what, bool noise_band) {
    std::vector<Series> series;
    series.push_back(
        {"mean " + what + ", before", b.x, b.before, SeriesStyle::kLineAndPoints, kBefore});
    if (fitted_any) {
      series.push_back(
          {"mean " + what + ", after", b.x, b.after, SeriesStyle::kLineAndPoints, kAfter});
    }
    XYPlotOptions o;
    o.title = title;
    o.x_label = x_label;
    o.y_label = "mean residual, µm";
    o.horizontal_lines = {0.0};
    const int fewest = b.count.empty() ? 0 : *std::min_element(b.count.begin(), b.count.end());
    if (noise_band && fewest > 0 && r.sigma > 0.0) {
      const double half = 2.0 * r.sigma / std::sqrt(static_cast<double>(fewest));
      o.bands.push_back({-half, half, "noise band ±2σ/√n", "#777777"});
      caption += " Grey band: ±2σ/√n = ±" + fixed(half) +
                 " µm, where a bin mean of n = " + std::to_string(fewest) +
                 " readings (the fewest of any bin) stays 95 % of the " +
                 "time if the residuals are noise at the noise floor σ = " + fixed(r.sigma) +
                 " µm; bin means inside it are not structure (residuals correlated along a "
                 "scan spread wider).";
    }
    report.figure(xy_plot_svg(series, o), caption);
  };
  line_plot(r.by_order, "Residual vs measurement order", "order (file's order column)",
            "Mean residual of consecutive groups of readings (up to 60 groups of equal size). "
            "Drift shows as a trend.",
            "per group", false);
  {
    std::vector<Series> series;
    const char* side_name[2] = {"L", "R"};
    for (int s = 0; s < 2; ++s) {
      if (r.tooth[s].x.empty()) continue;
      series.push_back({std::string("flank ") + side_name[s] + ", before", r.tooth[s].x,
                        r.tooth[s].before, SeriesStyle::kLineAndPoints,
                        s == 0 ? kBefore : kNullBefore});
    }
    if (fitted_any) {
      for (int s = 0; s < 2; ++s) {
        if (r.tooth[s].x.empty()) continue;
        series.push_back({std::string("flank ") + side_name[s] + ", after", r.tooth[s].x,
                          r.tooth[s].after, SeriesStyle::kLineAndPoints,
                          s == 0 ? kAfter : kNullAfter});
      }
    }
    XYPlotOptions o;
    o.title = "Residual vs tooth";
    o.x_min = 0.0;
    o.x_max = in.model.gear.teeth + 1.0;
    o.x_label = "tooth (1 on +X, counter-clockwise)";
    o.y_label = "mean residual, µm";
    o.horizontal_lines = {0.0};
    report.figure(xy_plot_svg(series, o),
                  "Mean residual per tooth and flank side. Eccentricity shows as one sine over "
                  "the teeth, opposite on left and right flanks.");
  }
  line_plot(r.roll, "Residual vs roll length", "roll length L, mm",
            "Mean residual per profile position (grid index i).", "per position", true);
  line_plot(r.face, "Residual vs face position", "z, mm",
            "Mean residual per face section (grid index j).", "per section", true);
  {
    HtmlTable t;
    t.caption =
        "Structure along each axis (before the fit): RMS of the bin means about their mean, and "
        "what noise alone gives; ratio = χ² of the bin means per degree of freedom (≈ 1 for "
        "noise).";
    t.header = {"axis", "bin means RMS, µm", "noise alone, µm", "ratio"};
    for (const AxisStructure& a : r.axes) {
      t.rows.push_back(
          {{a.axis, fixed(a.rms_um), fixed(a.noise_rms_um), fixed(a.ratio, 1)}, a.ratio >= 4.0});
    }
    report.table(t);
  }
}

void gap_section(HtmlReport& report, const ReportContext& ctx) {
  const Diagnosis& d = ctx.d;
  const int k = ctx.k;
  report.heading("Gap before and after");
  {
    HtmlTable t;
    t.caption = "Gap statistics (p-values from " + std::to_string(k) +
                " simulations of the null: noise at the noise floor at the same points).";
    t.header = {"", "before", "after"};
    t.rows.push_back({{"residual RMS, µm", fixed(d.gap_before.rms_um), fixed(d.gap_after.rms_um)}});
    t.rows.push_back({{"held-out RMS (" + held_out_split_text(d.held_out_split) + "), µm", "",
                       fixed(d.held_out_rms_um)}});
    t.rows.push_back(
        {{"noise floor σ, µm", fixed(d.noise.sigma_um), fixed(d.noise_floor_after_um)}});
    t.rows.push_back({{"excess RMS √(RMS² − σ²), µm", fixed(d.gap_before.excess_rms_um),
                       fixed(d.gap_after.excess_rms_um)}});
    t.rows.push_back(
        {{"χ²/dof (dof)",
          fixed(d.gap_before.chi2_dof, 3) + " (" + std::to_string(d.gap_before.dof) + ")",
          fixed(d.gap_after.chi2_dof, 3) + " (" + std::to_string(d.gap_after.dof) + ")"}});
    t.rows.push_back(
        {{"χ² p-value", p_text(d.gap_before.chi2_p, k), p_text(d.gap_after.chi2_p, k)}});
    t.rows.push_back(
        {{"KS distance to the point law", fixed(d.gap_before.ks, 4), fixed(d.gap_after.ks, 4)}});
    t.rows.push_back({{"KS p-value", p_text(d.gap_before.ks_p, k), p_text(d.gap_after.ks_p, k)}});
    t.rows.push_back({{"gap test p-value (χ² and KS as one test of level α, min-P)",
                       p_text(d.gap_before.combined_p, k), p_text(d.gap_after.combined_p, k)}});
    auto interval = [](const GapStatistics& g) {
      return std::isfinite(g.rms_lo_um) ? fixed(g.rms_lo_um) + " – " + fixed(g.rms_hi_um) : "–";
    };
    t.rows.push_back({{"RMS 95 % interval (bootstrap over teeth), µm", interval(d.gap_before),
                       interval(d.gap_after)}});
    t.rows.push_back({{"energy distance to a model simulation, µm",
                       fixed(d.gap_before.energy_um, 4), fixed(d.gap_after.energy_um, 4)}});
    t.rows.push_back({{"energy p-value (whole flanks swapped)", p_text(d.gap_before.energy_p, k),
                       p_text(d.gap_after.energy_p, k)}});
    report.table(t);
    std::ostringstream floor;
    floor << "Noise floor " << fixed(d.noise.sigma_um) << " µm from " << spelling(d.noise.source)
          << " (model's own noise " << fixed(d.noise.model_um)
          << " µm; robust estimate from the residuals' second differences along the scans "
          << fixed(d.noise.robust_um) << " µm from " << d.noise.differences << " differences).";
    report.paragraph(floor.str());
  }
}

void point_law_section(HtmlReport& report, const ReportContext& ctx) {
  const Diagnosis& d = ctx.d;
  const int k = ctx.k;
  report.heading("Spread of single readings");
  {
    const PointLawStage& st = d.point_law;
    if (!st.ran) {
      report.paragraph("Not tested: " + st.skipped_because + ".");
    } else {
      std::ostringstream text;
      text << "Effects that change the law of each reading rather than its mean: a probing noise "
              "larger than the model's, or the servo step quantisation (a latch delay uniform on "
              "[0, q), whose mean −q/2 is the constant shift of a stylus radius error and whose "
              "spread q²/12 is what tells them apart). The second differences along the scans "
              "(structure linear along a scan cancels) give "
           << fixed(std::sqrt(st.white_variance_um2)) << " µm per reading against the model's "
           << fixed(std::sqrt(st.model_variance_um2)) << " µm (" << p_text(st.white_p, k)
           << ", from " << st.differences << " differences).";
      report.paragraph(text.str());
      HtmlTable t;
      t.caption =
          "Laws of a single reading compared by BIC (with the selected effects' columns; a tied "
          "step drops their constant shift and explains it by its mean −q/2). Accepted: white "
          "excess variance, mostly white, ΔBIC ≤ −10.";
      t.header = {"law", "fitted, µm", "σ of a reading, µm", "parameters", "ΔBIC", "accepted"};
      for (std::size_t h = 0; h < st.hypotheses.size(); ++h) {
        const PointLawHypothesis& x = st.hypotheses[h];
        std::string label = x.name == "model"   ? "the model's"
                            : x.name == "noise" ? "noise σ fitted"
                            : x.tied            ? "step q fitted, tied to the shift"
                                                : "step q fitted, with a free shift";
        std::string fitted = "–";
        if (h > 0)
          fitted = (x.name == "noise" ? "σ = " : "q = ") + with_error(x.estimate, x.std_error);
        t.rows.push_back({{label, fitted, fixed(std::sqrt(x.law.variance_um2())),
                           std::to_string(x.parameters), h > 0 ? fixed(x.delta_bic, 1) : "0",
                           h == 0 ? "" : (x.accepted ? "yes" : "no: " + x.note)},
                          static_cast<int>(h) == st.chosen && st.chosen > 0});
      }
      report.table(t);
    }
  }
}

void fitted_effects_section(HtmlReport& report, const ReportContext& ctx) {
  const Diagnosis& d = ctx.d;
  report.heading("Fitted effects");
  if (d.effects.empty()) {
    report.paragraph("No effect was selected.");
  } else {
    HtmlTable t;
    t.caption =
        "Fitted physical parameters (increments on the model's own values of the effect), with "
        "standard errors from the joint least-squares fit (σ̂² = RSS/(n − p)).";
    t.header = {"effect", "parameter", "value ± standard error", "unit", "note"};
    for (const FittedEffect& e : d.effects) {
      for (const FittedValue& v : e.parameters) {
        t.rows.push_back(
            {{e.name, v.name, v.estimable ? with_error(v.value, v.std_error) : "–", v.unit,
              !v.estimable ? "not observable on this plan"
              : e.absolute ? "the effect's own value (point-law stage, standard "
                             "error from the profile likelihood)"
                           : ""},
             d.finding == DiagnosisFinding::kEffect && e.name == d.named_effect});
      }
    }
    report.table(t);
  }
  // Effects whose value differs from gear to gear: one row per gear.
  for (const FittedEffect& e : d.effects) {
    if (!e.varies_per_gear || e.per_gear.empty()) continue;
    HtmlTable t;
    std::ostringstream caption;
    caption << e.name << " differs from gear to gear (F test of one value per gear against one "
            << "for all, p " << (e.per_gear_p < 1e-16 ? "< 1e-16" : "= " + general(e.per_gear_p))
            << "): its coefficients fitted per gear, the other effects shared.";
    t.caption = caption.str();
    t.header = {"gear"};
    for (const FittedValue& v : e.per_gear.front().coefficients) {
      t.header.push_back(v.name + ", " + v.unit);
    }
    for (const FittedEffect::GearValues& g : e.per_gear) {
      std::vector<std::string> row = {std::to_string(g.gear)};
      for (const FittedValue& v : g.coefficients) {
        row.push_back(v.estimable ? with_error(v.value, v.std_error) : "–");
      }
      t.rows.push_back({row});
    }
    report.table(t);
  }
}

void selection_section(HtmlReport& report, const ReportContext& ctx) {
  const Diagnosis& d = ctx.d;
  const int k = ctx.k;
  report.heading("Selection");
  report.paragraph(
      "Forward selection over the effect library: at each step every candidate not yet selected "
      "is tested as an addition. It is accepted only when it is significant (Holm-adjusted F "
      "test and the null-calibrated p below α = " +
      general(d.alpha) +
      "), strongly supported (ΔBIC ≤ −10) and practically relevant (it removes at least a "
      "quarter of the noise floor in RMS); the best such candidate by ΔBIC is taken.");
  for (std::size_t s = 0; s < d.selection.steps.size(); ++s) {
    const SelectionStep& step = d.selection.steps[s];
    HtmlTable t;
    std::string before;
    for (int c : step.selected_before) {
      before += (before.empty() ? "" : ", ") + d.candidate_names.at(c);
    }
    t.caption = "Step " + std::to_string(s + 1) +
                (before.empty() ? "" : " (given " + before + ")") + ": " +
                (step.accepted >= 0 ? step.tests[step.accepted].name + " accepted"
                                    : std::string("nothing accepted, selection stops"));
    t.header = {"candidate", "columns",         "F",           "p (F, Holm)", "p (null)",
                "ΔBIC",      "removes RMS, µm", "significant", "ΔBIC ≤ −10",  "practical"};
    for (std::size_t c = 0; c < step.tests.size(); ++c) {
      const CandidateTest& test = step.tests[c];
      auto yes = [](bool b) { return std::string(b ? "yes" : "no"); };
      std::string name = test.name;
      if (!test.note.empty()) name += " (" + test.note + ")";
      t.rows.push_back(
          {{name, std::to_string(test.added_rank), general(test.f), general(test.p_holm),
            p_text(test.p_null, k), fixed(test.delta_bic, 1), fixed(test.effect_rms_um),
            yes(test.significant), yes(test.bic_support), yes(test.practical)},
           static_cast<int>(c) == step.accepted});
    }
    report.table(t);
  }
  if (d.selection.retest.empty() && d.selection.dropped.empty()) return;
  // The re-test: each selected effect as the last one in, given all the others (selection.h).
  HtmlTable r;
  r.caption = "Re-test of the selected effects, each given all the others" +
              std::string(d.selection.dropped.empty()
                              ? ": every one kept"
                              : ": " + std::to_string(d.selection.dropped.size()) + " dropped") +
              " (kept ones ordered by the RMS each removes; the first is the headline)";
  r.header = {"effect", "columns", "F", "p (F, Holm)", "ΔBIC", "removes RMS, µm", "kept"};
  const auto row = [&](const CandidateTest& test, bool kept) {
    std::string name = test.name;
    if (!test.note.empty()) name += " (" + test.note + ")";
    r.rows.push_back({{name, std::to_string(test.added_rank), general(test.f), general(test.p_holm),
                       fixed(test.delta_bic, 1), fixed(test.effect_rms_um), kept ? "yes" : "no"},
                      kept});
  };
  for (const CandidateTest& test : d.selection.retest) row(test, true);
  for (const CandidateTest& test : d.selection.dropped) row(test, false);
  report.table(r);
}

void ambiguity_section(HtmlReport& report, const ReportContext& ctx) {
  const Diagnosis& d = ctx.d;
  report.heading("Ambiguity");
  bool any_ambiguity = false;
  for (const FittedEffect& e : d.effects) {
    if (e.ambiguous.empty()) {
      report.paragraph(e.name +
                       " is identified on this probing plan: no other candidate reproduces its "
                       "fitted contribution (signal correlation ≤ 0.9) and none came within "
                       "ΔBIC 6 of it.");
      continue;
    }
    any_ambiguity = true;
    HtmlTable t;
    t.caption = e.name + " cannot be told apart from:";
    t.header = {"other effect",
                "reason",
                "signal correlation",
                "canonical correlation",
                "condition number",
                "ΔBIC gap",
                "measurement that would separate them"};
    for (const Ambiguity& a : e.ambiguous) {
      t.rows.push_back(
          {{a.with, a.reason, fixed(a.signal_correlation), fixed(a.canonical_correlation),
            general(a.condition_number), fixed(a.delta_bic_gap, 1), a.separate_by}});
    }
    report.table(t);
  }
  if (d.effects.empty())
    report.paragraph("No effect was selected, so there is nothing to separate.");
  (void)any_ambiguity;
}

void histograms_section(HtmlReport& report, const ReportContext& ctx) {
  const Diagnosis& d = ctx.d;
  const ReportData& r = ctx.r;
  const bool fitted_any = ctx.fitted_any;
  report.heading("Distribution of the residuals before and after");
  if (r.n > 0) {
    // Bins from the central quantiles of both residual sets, never from their full range.
    std::vector<double> both = r.before;
    if (fitted_any) both.insert(both.end(), r.after.begin(), r.after.end());
    const DisplayBins bins_of = display_bins(both, r.sigma);
    both = {};
    const double start = bins_of.lo_um, width = bins_of.width_um;
    const std::size_t bins = bins_of.bins;
    const double sigma = r.sigma;
    for (int which = 0; which < (fitted_any ? 2 : 1); ++which) {
      Histogram h(start, width, bins);
      for (double v : which == 0 ? r.before : r.after) h.add(v);
      HistogramPlotOptions o;
      o.title = std::string("Residuals ") + (which == 0 ? "before" : "after") +
                " the fit (n = " + std::to_string(r.n) + ")";
      o.x_label = "residual, µm";
      o.bars_label = which == 0 ? "before" : "after";
      // The law a residual follows if the model (before) or the fitted model (after) is right:
      // the model's per-point law (Gaussian, or with a step's flat top), centred.
      ResidualLaw law;
      law.sigma_um = sigma;
      if (d.noise.law.variance_um2() > 0.0) law = residual_law(d.noise.law);
      if (which == 1 && d.point_law.chosen > 0) {
        law = d.point_law.best().law;
        law.offset_um -= law.mean_um();
      }
      if (law.variance_um2() > 0.0) {
        o.overlay_pdf = [law](double x) { return std::exp(law.log_density(x)); };
        o.overlay_label = law.width_um > 0.0
                              ? "the law of a reading: N(0, " + fixed(law.sigma_um) +
                                    "²) with a step of " + fixed(law.width_um) + " µm, centred"
                              : "N(0, σ²), σ = " + fixed(law.sigma_um) + " µm";
      }
      o.x_min = start;
      o.x_max = start + width * static_cast<double>(bins);
      std::string caption = which == 0 ? "Residuals against the model as given."
                                       : "Residuals with the selected effects fitted.";
      if (h.underflow() + h.overflow() > 0) {
        caption += " Outside the plotted range: " + std::to_string(h.underflow()) +
                   " below (smallest " + general(h.underflow_min()) + " µm) and " +
                   std::to_string(h.overflow()) + " above (largest " + general(h.overflow_max()) +
                   " µm); the range is the central 99 % of the residuals widened by half its width "
                   "on each side.";
      }
      report.figure(histogram_svg(h, o), caption);
    }
  }
}

void notes_and_inputs_section(HtmlReport& report, const ReportContext& ctx) {
  const DiagnosisReportInput& in = ctx.in;
  const Diagnosis& d = ctx.d;
  const int k = ctx.k;
  std::vector<std::string> notes = d.notes;
  for (const std::string& n : in.fitted.notes) notes.push_back("fitted.yaml: " + n);
  if (!notes.empty()) {
    report.heading("Notes");
    for (const std::string& n : notes) report.paragraph(n + ".");
  }
  if (!d.outliers.excluded.empty()) {
    constexpr std::size_t kShown = 50;
    HtmlTable t;
    t.caption = "Readings excluded as gross outliers (|z| > " + fixed(d.outliers.threshold_z, 2) +
                " against the prediction from their profile scan's neighbours, σ " +
                fixed(d.outliers.sigma_um) + " µm; a 1 % chance per clean file)" +
                (d.outliers.excluded.size() > kShown
                     ? "; the first " + std::to_string(kShown) + " of " +
                           std::to_string(d.outliers.excluded.size()) + ", all in diagnosis.json"
                     : std::string()) +
                ".";
    t.header = {"CSV line", "gear", "tooth", "flank", "i", "j", "residual, µm", "z"};
    for (std::size_t e = 0; e < d.outliers.excluded.size() && e < kShown; ++e) {
      const ExcludedReading& x = d.outliers.excluded[e];
      t.rows.push_back({{std::to_string(x.line), std::to_string(x.gear), std::to_string(x.tooth),
                         x.side == FlankSide::kRight ? "R" : "L", std::to_string(x.i),
                         std::to_string(x.j), fixed(x.residual_um), fixed(x.z_score, 1)}});
    }
    report.heading("Excluded readings");
    report.table(t);
  }
  report.heading("Inputs");
  {
    std::ostringstream s;
    s << "Model: " << in.model_path << " (scenario " << in.model.name << "), predicted on "
      << (in.residuals.artefact == ArtefactModel::kModelGears ? "the model's perturbed gears"
                                                              : "the model's nominal master gear")
      << ". Readings: " << in.readings_path << ", " << d.points << " points, stylus radius "
      << in.model.stylus_radius_mm << " mm";
    if (d.nominal_fallback > 0) s << " (" << d.nominal_fallback << " predicted with p + R n)";
    if (in.matching) {
      s << "; without labels: " << in.matching->points - in.matching->refused << " of "
        << in.matching->points << " points matched to their flanks (from them "
        << general(in.matching->rms_distance_um) << " µm RMS, "
        << general(in.matching->max_distance_um) << " µm at most)";
      if (in.matching->refused > 0) {
        s << ", " << in.matching->refused << " refused (listed in the warnings)";
      }
    }
    s << ". Null simulation: " << k << " replicates, seed " << d.seed
      << ", α = " << general(d.alpha) << ".";
    report.paragraph(s.str());
  }
  report.preformatted(in.fitted.yaml, "fitted.yaml");
}

}  // namespace gearmc::diagnose_report
