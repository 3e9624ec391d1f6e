// The verdict, the terminal summary and the page of `gearmc diagnose` (see diagnosis_report.h);
// the page's data and sections are in diagnosis_report_data.cpp and diagnosis_report_sections.cpp.
#include "engine/apps/diagnose/diagnosis_report.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <numbers>
#include <sstream>

#include "engine/apps/diagnose/diagnosis_report_data.h"
#include "engine/apps/diagnose/diagnosis_report_sections.h"
#include "engine/reports/html_report.h"

namespace gearmc {

using namespace diagnose_report;

namespace {

// Parameters worth stating: |value| > 3 standard errors (a phase goes with its amplitude).
std::vector<const FittedValue*> significant_parameters(const FittedEffect& e) {
  std::vector<const FittedValue*> out;
  for (const FittedValue& v : e.parameters) {
    if (!v.estimable || !std::isfinite(v.value)) continue;
    if (v.name.rfind("phase_", 0) == 0) {
      const std::string order = v.name.substr(6, v.name.size() - 6 - 4);  // phase_<k>_deg
      const bool amplitude_shown = std::any_of(out.begin(), out.end(), [&](const FittedValue* a) {
        return a->name == "amplitude_" + order + "_um";
      });
      if (amplitude_shown) out.push_back(&v);
      continue;
    }
    if (std::abs(v.value) > 3.0 * v.std_error) out.push_back(&v);
  }
  if (out.empty()) {
    for (const FittedValue& v : e.parameters) {
      if (v.estimable && std::isfinite(v.value)) out.push_back(&v);
    }
  }
  return out;
}

std::string parameter_list(const FittedEffect& e, const char* separator) {
  std::string s;
  for (const FittedValue* v : significant_parameters(e)) {
    if (!s.empty()) s += separator;
    s += v->name + " = " + with_error(v->value, v->std_error) + " " + v->unit;
  }
  return s;
}

// The harmonic orders ≥ 1 of the "before" spectrum above their 95 % null band, strongest first.
std::vector<int> orders_above_null(const Diagnosis& d) {
  std::vector<int> orders;
  for (std::size_t k = 1; k < d.spectrum_before_um.size(); ++k) {  // order 0 is the mean
    if (k < d.spectrum_null95_before_um.size() &&
        d.spectrum_before_um[k] > d.spectrum_null95_before_um[k] &&
        std::isfinite(d.spectrum_null95_before_um[k])) {
      orders.push_back(static_cast<int>(k));
    }
  }
  std::stable_sort(orders.begin(), orders.end(), [&](int a, int b) {
    return d.spectrum_before_um[a] / d.spectrum_null95_before_um[a] >
           d.spectrum_before_um[b] / d.spectrum_null95_before_um[b];
  });
  return orders;
}

std::string spectrum_phrase(const Diagnosis& d, int order) {
  std::string s = "order " + std::to_string(order) + " of the azimuth spectrum is " +
                  fixed(d.spectrum_before_um[order]) + " µm";
  if (static_cast<std::size_t>(order) < d.spectrum_null95_before_um.size()) {
    s += ", its 95 % null band " + fixed(d.spectrum_null95_before_um[order]) + " µm";
  }
  return s;
}

// Where the named effect shows, in its own terms.
std::string effect_where(const FittedEffect& e, const Diagnosis& d, const ReportData& r) {
  const std::string& name = e.name;
  if (name == "probe_lobing") {
    int best = -1;
    double largest = 0.0;
    for (const FittedValue& v : e.parameters) {
      int k = 0;
      if (v.estimable && std::sscanf(v.name.c_str(), "amplitude_%d_um", &k) == 1 &&
          v.value > largest) {
        largest = v.value;
        best = k;
      }
    }
    if (best > 0 && static_cast<std::size_t>(best) < d.spectrum_before_um.size()) {
      return "against the approach azimuth, a " + std::to_string(best) + "-fold pattern (" +
             spectrum_phrase(d, best) + ")";
    }
    return "against the approach azimuth";
  }
  if ((name == "step_quantization" || name == "noise") && e.absolute) {
    const PointLawStage& st = d.point_law;
    std::string s =
        "in the spread of single readings: the second differences along the scans "
        "give " +
        fixed(std::sqrt(st.white_variance_um2)) +
        " µm per reading where the model "
        "says " +
        fixed(std::sqrt(st.model_variance_um2)) + " µm";
    if (name == "step_quantization") {
      s += ", with a flat-topped shape and a constant shift (mean residual " +
           fixed(r.mean_before) + " µm) tied to it";
      const PointLawHypothesis* noise = st.find("noise");
      if (noise && st.chosen > 0 && st.best().tied) {
        s += " (a stylus radius error plus a larger noise gives the same shift and spread with "
             "one parameter more, ΔBIC " +
             fixed(noise->bic - st.best().bic, 0) + " worse)";
      }
    }
    return s;
  }
  if (name == "stylus_radius" || name == "step_quantization") {
    return "a constant shift of every reading (mean residual " + fixed(r.mean_before) + " µm)";
  }
  if (name == "scale" || name == "thermal_expansion") {
    return "a size error: the residual follows the distance from the gear centre along the "
           "normal (mean residual " +
           fixed(r.mean_before) + " µm, varying around the gear and between the flank sides)";
  }
  if (name == "drift") {
    return "along the measurement order: the mean residual goes from " + fixed(r.first_tenth) +
           " µm in the first tenth of the sequence to " + fixed(r.last_tenth) + " µm in the last";
  }
  if (name == "eccentricity") {
    return "once around the gear: the per-tooth mean follows one sine over the teeth, with "
           "opposite signs on left and right flanks";
  }
  if (name == "clocking") {
    return "between the flank sides: left and right flanks moved by the same amount in opposite "
           "directions on every tooth (a turn of the gear about its axis)";
  }
  if (name == "squareness") {
    return "with the position along the machine's axes (a shear of the axes)";
  }
  return "in the effect's signature";
}

// The axes along which the bin means vary beyond noise (at most `most`), strongest first.
std::string axes_phrase(const ReportData& r, int most) {
  std::string s;
  int shown = 0;
  for (const AxisStructure& a : r.axes) {
    if (a.ratio < 4.0 || shown == most) break;
    s += shown == 0 ? "most visible against " : "; then against ";
    s += a.axis + " (bin means " + fixed(a.rms_um) + " µm RMS, noise alone " +
         fixed(a.noise_rms_um) + " µm)";
    ++shown;
  }
  return s;
}

// Where, without naming an effect: axes, the strongest harmonic, a constant shift.
std::string generic_where(const ReportData& r, const Diagnosis& d) {
  std::string s = axes_phrase(r, 2);
  const std::vector<int> orders = orders_above_null(d);
  if (!orders.empty() &&
      d.spectrum_before_um[orders.front()] > 2.0 * d.spectrum_null95_before_um[orders.front()]) {
    s += (s.empty() ? "" : "; ") + std::string("strongest harmonic: ") +
         spectrum_phrase(d, orders.front());
  }
  if (std::abs(r.mean_before) > 4.0 * r.sigma / std::sqrt(std::max(1, r.n))) {
    s += (s.empty() ? "" : "; ") + std::string("mean residual ") + fixed(r.mean_before) + " µm";
  }
  return s;
}

std::string gap_phrase(const GapStatistics& g, double sigma, int replicates) {
  return "residual RMS " + fixed(g.rms_um) + " µm against a noise floor of " + fixed(sigma) +
         " µm (χ²/dof " + fixed(g.chi2_dof, 2) + ", " + p_text(g.chi2_p, replicates) +
         "; KS distance " + fixed(g.ks, 3) + ", " + p_text(g.ks_p, replicates) +
         "; the two as one test, " + p_text(g.combined_p, replicates) + ")";
}

// ", X µm with the fitted <effect>" when a point-law effect widened the noise floor.
std::string floor_after_phrase(const Diagnosis& d) {
  for (const FittedEffect& e : d.effects) {
    if (e.absolute) {
      return ", " + fixed(d.noise_floor_after_um) + " µm with the fitted " + e.name + "'s spread";
    }
  }
  return "";
}

std::string points_phrase(const DiagnosisReportInput& in) {
  std::ostringstream s;
  s << in.diagnosis.points << " readings of " << in.readings_path << " against the model "
    << in.model.name << " (" << in.model_path << ")";
  return s.str();
}

// The verdict and what a residual is.
void verdict_section(HtmlReport& report, const ReportContext& ctx) {
  report.heading("Verdict");
  report.paragraph(diagnosis_verdict(ctx.in));
  report.paragraph(
      std::string("Residual = measured − predicted deviation along the nominal flank normal (µm, + "
                  "= material side outward). ") +
      (ctx.d.part.fitted
           ? "\"Before\" is against the model with the gear's own flank deviations fitted; "
             "\"after\" with the selected effects fitted as well. The plots show bin means "
             "(lines) so a pattern stands out of the noise; the held-out RMS fits on one half of "
             "every flank's points and evaluates on the other, and the other way round."
           : "\"Before\" is against the model as given; \"after\" with the selected effects "
             "fitted. The plots show bin means (lines) so a pattern stands out of the noise; the "
             "held-out RMS fits on odd teeth and evaluates on even ones, and the other way "
             "round."));
}

// The verdict when the first effect is the artefact's form (a property of the master gear, told
// as such) or the scales' resolution (read off the coordinates' grid), up to "fitted.yaml".
std::string artefact_or_grid_verdict(const DiagnosisReportInput& in, const ReportData& r) {
  const Diagnosis& d = in.diagnosis;
  const FittedEffect& e = d.effects.front();
  const int k = d.null_replicates;
  std::ostringstream s;
  if (e.name == "artefact_form") {
    s << "Gap found: the artefact's form, not a CMM error. What disagreed: " << points_phrase(in)
      << ", " << gap_phrase(d.gap_before, r.sigma, k) << ". Where: on every tooth alike, along the "
      << "flank's own coordinates (roll length and face position), as a workpiece's form does; a "
      << "machine error follows the machine's axes and changes from tooth to tooth. How big: "
      << parameter_list(e, ", ") << " (Legendre terms, µm at the ends of the range";
    for (const auto& [key, value] : e.settings) s << "; " << key << " " << fixed(value, 3);
    s << "; ΔBIC " << fixed(e.evidence.delta_bic, 0) << ", " << p_text(e.evidence.p_null, k)
      << "). These are the master gear's own profile and helix form: keep them with this artefact "
         "(compare them with its calibration certificate); do not correct the CMM with them. ";
  } else {
    s << "Gap found: the scales' resolution: " << d.coordinate_grid.note
      << "; the model has no such grid. Along the flank normal the latching adds a zero-mean "
         "spread the model lacks (the noise floor now includes it: "
      << fixed(d.noise.sigma_um) << " µm). ";
  }
  for (std::size_t x = 1; x < d.effects.size(); ++x) {
    s << "Together with " << d.effects[x].name << " with " << parameter_list(d.effects[x], ", ")
      << ". ";
  }
  if (!e.ambiguous.empty()) {
    s << "On this probing plan it cannot be told apart from";
    for (const Ambiguity& a : e.ambiguous) s << " " << a.with;
    s << "; to separate them, " << e.ambiguous.front().separate_by << ". ";
  }
  s << "Gap: RMS " << fixed(d.gap_before.rms_um) << " µm → " << fixed(d.gap_after.rms_um)
    << " µm with it, " << fixed(d.held_out_rms_um) << " µm held out ("
    << held_out_split_text(d.held_out_split) << "). ";
  if (d.unexplained_structure) s << "Unexplained structure remains after it. ";
  return s.str();
}

}  // namespace

std::string diagnosis_verdict(const DiagnosisReportInput& in) {
  const Diagnosis& d = in.diagnosis;
  const ReportData r = report_data(in);
  const int k = d.null_replicates;
  std::ostringstream s;
  if (d.status != DiagnosisStatus::kTested) {
    s << "No verdict: " << d.status_reason << ". Nothing was tested; fitted.yaml is the model "
      << "unchanged. Give the model its noise (e.g. effects: noise: {sigma_um: …}) or more "
      << "readings.";
    return s.str();
  }
  if (d.part.fitted) {
    s << "A production gear: its own flank deviations (" << d.part.flanks.size()
      << " flanks: position, profile and helix slope and crowning, RMS "
      << fixed(d.part.fitted_rms_um) << " µm) are fitted in every model; \"before\" is the model "
      << "with them, so what follows is the machine's part. ";
  }
  if (d.setups.fitted) {
    s << "The readings hold " << d.setups.runs.size() + 1
      << " runs whose set-ups differ (a shift and a turn of the gear per run, F test "
      << p_text(d.setups.p_value, 0) << ", RMS " << fixed(d.setups.rms_um)
      << " µm): the differences from the first run's set-up are fitted in every model, so what "
         "follows is common to the runs or varies within them. ";
  }
  if (!d.gap_detected) {
    s << (d.part.fitted ? "No machine gap: the gear's own deviations and the noise floor explain "
                          "the readings. "
          : d.law_shape.differs
              ? "No gap in the readings' mean: nothing is missing from the model's prediction. "
              : "No gap: the readings agree with the model within the noise floor. ")
      << points_phrase(in) << ": " << gap_phrase(d.gap_before, r.sigma, k) << ". ";
    if (d.law_shape.differs) {
      s << "Their law differs from the model's in its shape (spread "
        << fixed(d.law_shape.spread_ratio) << " × the model's; " << d.law_shape.shape
        << ": excess kurtosis " << fixed(d.law_shape.excess_kurtosis) << " ± "
        << fixed(d.law_shape.kurtosis_std_error) << " against the model's "
        << fixed(d.law_shape.model_excess_kurtosis) << ", " << p_text(d.law_shape.ks_p, k)
        << " for the shape) and they vary along no axis: a statement about the readings' noise "
           "law, not a missing effect. ";
    }
    const CandidateTest* best = nullptr;
    if (!d.selection.steps.empty()) {
      for (const CandidateTest& t : d.selection.steps.front().tests) {
        if (std::isfinite(t.delta_bic) && (!best || t.delta_bic < best->delta_bic)) best = &t;
      }
    }
    s << "No effect of the library passes the selection";
    if (best) {
      s << " (closest: " << best->name << ", ΔBIC " << fixed(best->delta_bic, 1) << ", "
        << p_text(best->p_null, k) << ", it would remove " << fixed(best->effect_rms_um)
        << " µm RMS)";
    }
    s << ". fitted.yaml is the model unchanged.";
    return s.str();
  }
  const std::string where = generic_where(r, d);
  if (d.finding != DiagnosisFinding::kEffect) {
    s << "Gap found, not explained by the effect library: unexplained structure remains. What "
         "disagreed: "
      << points_phrase(in) << ", " << gap_phrase(d.gap_before, r.sigma, k) << ". ";
    if (!where.empty()) s << "Where: " << where << ". ";
    if (d.effects.empty()) {
      s << "No library effect passes the selection";
    } else {
      s << "The selected library effects (";
      for (std::size_t e = 0; e < d.effects.size(); ++e) s << (e ? ", " : "") << d.effects[e].name;
      s << ") explain " << (d.explained_fraction < 0.5 ? "only " : "")
        << fixed(100.0 * d.explained_fraction, 0) << " % of the excess variance (RMS "
        << fixed(d.gap_before.rms_um) << " → " << fixed(d.gap_after.rms_um) << " µm)";
      if (d.unexplained_structure) s << ", and structure remains after them";
    }
    if (!d.unexplained_along.axis.empty()) {
      if (std::isfinite(d.unexplained_along.period_mm)) {
        s << ". The remaining structure varies most along " << d.unexplained_along.axis
          << ", periodically: period " << fixed(d.unexplained_along.period_mm, 2)
          << " mm, amplitude " << fixed(d.unexplained_along.amplitude_um) << " µm along the axis ("
          << fixed(100.0 * d.unexplained_along.variance_share, 0)
          << " % of the remaining variance) — a periodic error of that axis's scale or its "
             "encoder; to map it, "
          << d.empirical.identify_by;
      } else {
        s << ". The remaining structure varies most along " << d.unexplained_along.axis
          << " (its group means carry " << fixed(100.0 * d.unexplained_along.variance_share, 0)
          << " % of the remaining variance)";
      }
    }
    const EmpiricalTerm& em = d.empirical;
    if (em.fitted) {
      s << ". An empirical term describes it: " << em.basis << " of order " << em.order << " along "
        << em.axis << " (chosen by BIC, ΔBIC " << fixed(em.delta_bic, 0) << "), RMS "
        << fixed(em.fitted_rms_um) << " µm; with it the residual RMS goes from "
        << fixed(em.rms_before_um) << " to " << fixed(em.rms_after_um)
        << " µm (excess over the noise floor " << fixed(em.excess_rms_before_um) << " → "
        << fixed(em.excess_rms_after_um)
        << " µm). fitted.yaml holds this term as the effect empirical";
      if (!d.effects_with_empirical.empty()) {
        s << ", together with ";
        for (std::size_t x = 0; x < d.effects_with_empirical.size(); ++x) {
          s << (x ? ", " : "") << d.effects_with_empirical[x].name;
        }
        s << " fitted again beside it";
      }
      s << ". The term reproduces the readings; it does not say what causes them. To identify it: "
        << em.identify_by << ".";
    } else {
      if (!em.why_not.empty()) s << "; no empirical term was fitted (" << em.why_not << ")";
      s << (!d.effects.empty() && !d.fit_refused
                ? ". fitted.yaml holds the library's effects fitted, which explain part of it"
                : ". fitted.yaml is the model unchanged")
        << "; the plots below show the structure to look for outside the library (the artefact "
           "itself, a form or fixture effect).";
    }
    return s.str();
  }
  const FittedEffect& e = d.effects.front();
  if (e.name == "artefact_form" || e.name == "scale_resolution") {
    s << artefact_or_grid_verdict(in, r) << "fitted.yaml is the model with it added"
      << (e.name == "artefact_form" ? " as the separate entry artefact_form, marked as the "
                                      "artefact's own form."
                                    : ".");
    return s.str();
  }
  s << "Gap found, explained by " << e.name << ". What disagreed: " << points_phrase(in) << ", "
    << gap_phrase(d.gap_before, r.sigma, k) << ". Where: " << effect_where(e, d, r);
  const std::string axes = axes_phrase(r, 1);
  if (!axes.empty()) s << "; " << axes;
  s << ". Which effect, how big: " << e.name << " with " << parameter_list(e, ", ") << " (ΔBIC "
    << fixed(e.evidence.delta_bic, 0) << ", " << p_text(e.evidence.p_null, k) << ")";
  for (std::size_t x = 1; x < d.effects.size(); ++x) {
    s << ", together with " << d.effects[x].name << " with " << parameter_list(d.effects[x], ", ");
  }
  s << ". ";
  if (!d.ambiguous_with.empty()) {
    s << "On this probing plan it cannot be told apart from ";
    for (std::size_t a = 0; a < d.ambiguous_with.size(); ++a) {
      s << (a ? ", " : "") << d.ambiguous_with[a];
    }
    // The distinct measurements that would separate them (at most two; all in the table below).
    std::vector<std::string> separate;
    for (const Ambiguity& a : e.ambiguous) {
      if (separate.size() < 2 &&
          std::find(separate.begin(), separate.end(), a.separate_by) == separate.end()) {
        separate.push_back(a.separate_by);
      }
    }
    for (std::size_t a = 0; a < separate.size(); ++a) {
      s << (a == 0 ? "; to separate them, " : "; and ") << separate[a];
    }
    s << ". ";
  }
  s << "Gap: RMS " << fixed(d.gap_before.rms_um) << " µm → " << fixed(d.gap_after.rms_um)
    << " µm with it, " << fixed(d.held_out_rms_um) << " µm held out ("
    << held_out_split_text(d.held_out_split) << "), noise floor " << fixed(r.sigma) << " µm"
    << floor_after_phrase(d) << " (it explains " << fixed(100.0 * d.explained_fraction, 0)
    << " % of the excess variance). ";
  if (d.unexplained_structure) {
    s << "Unexplained structure remains after it (χ²/dof " << fixed(d.gap_after.chi2_dof, 2) << ", "
      << p_text(d.gap_after.chi2_p, k) << "; KS " << p_text(d.gap_after.ks_p, k)
      << "; the two as one test, " << p_text(d.gap_after.combined_p, k) << "). ";
  }
  s << "fitted.yaml is the model with it added.";
  return s.str();
}

std::vector<std::string> diagnosis_summary_lines(const DiagnosisReportInput& in) {
  const Diagnosis& d = in.diagnosis;
  std::vector<std::string> lines;
  lines.push_back("gearmc diagnose: " + std::to_string(d.points) + " readings of " +
                  in.readings_path + " against " + in.model.name + ", noise floor " +
                  fixed(d.noise.sigma_um) + " µm (" + std::string(spelling(d.noise.source)) + ")");
  std::string verdict;
  if (d.status != DiagnosisStatus::kTested) {
    verdict = "no verdict: " + d.status_reason;
  } else if (!d.gap_detected) {
    verdict = d.part.fitted ? "no machine gap: the gear's own flank deviations and the noise "
                              "floor explain the readings"
                            : "no gap: the readings agree with the model within the noise floor";
    if (d.law_shape.differs) {
      verdict = (d.part.fitted ? "no machine gap" : "no gap in the readings' mean") +
                std::string("; their law differs from the model's in its shape (") +
                d.law_shape.shape + ", spread " + fixed(d.law_shape.spread_ratio) +
                " × the model's): a statement about the noise law, not a missing effect";
    }
  } else if (d.finding != DiagnosisFinding::kEffect) {
    verdict = "gap, unexplained structure remains";
    if (!d.unexplained_along.axis.empty()) verdict += " along " + d.unexplained_along.axis;
    verdict += d.partially_explained_by.empty()
                   ? ": no library effect explains it"
                   : " (" + d.partially_explained_by + " explains part of it)";
  } else {
    const FittedEffect& e = d.effects.front();
    verdict = "gap: " + e.name + " (" + parameter_list(e, ", ") + ")";
    if (e.name == "artefact_form") {
      verdict = "gap: the artefact's form, not a CMM error: artefact_form (" +
                parameter_list(e, ", ") + ")";
    }
    if (!d.ambiguous_with.empty()) {
      verdict += ", ambiguous with";
      for (const std::string& a : d.ambiguous_with) verdict += " " + a;
    }
    if (d.unexplained_structure) verdict += "; unexplained structure remains";
  }
  lines.push_back(verdict);
  // Every accepted effect after the first (named above) with its values; an effect fitted per
  // gear with the range of its values over the gears.
  for (std::size_t k = 0; k < d.effects.size(); ++k) {
    const FittedEffect& e = d.effects[k];
    if (k == 0 && d.finding == DiagnosisFinding::kEffect) continue;
    std::string line =
        (k == 0 ? "effect: " : "also: ") + e.name + " (" + parameter_list(e, ", ") + ")";
    if (e.varies_per_gear && !e.per_gear.empty()) {
      line += "; varies per gear (p " + fixed(e.per_gear_p, 4) + "):";
      const std::size_t columns = e.per_gear.front().coefficients.size();
      for (std::size_t c = 0; c < columns; ++c) {
        double lo = INFINITY, hi = -INFINITY;
        for (const FittedEffect::GearValues& g : e.per_gear) {
          if (c >= g.coefficients.size() || !g.coefficients[c].estimable) continue;
          lo = std::min(lo, g.coefficients[c].value);
          hi = std::max(hi, g.coefficients[c].value);
        }
        if (!(lo <= hi)) continue;
        const FittedValue& v = e.per_gear.front().coefficients[c];
        line += " " + v.name + " " + fixed(lo) + " … " + fixed(hi) + " " + v.unit + " over " +
                std::to_string(e.per_gear.size()) + " gears;";
      }
      line.pop_back();
    }
    lines.push_back(line);
  }
  if (d.setups.fitted) {
    std::string line = "the runs' set-ups differ (F test p " + fixed(d.setups.p_value, 4) +
                       "; fitted in every model, relative to the first run's):";
    for (const SetupRun& r : d.setups.runs) {
      line += " gear " + std::to_string(r.gear) + " shift x " + fixed(r.shift_x_um) + " ± " +
              fixed(r.shift_x_se_um) + ", y " + fixed(r.shift_y_um) + " ± " +
              fixed(r.shift_y_se_um) + " µm, turn " + fixed(r.turn_urad) + " ± " +
              fixed(r.turn_se_urad) + " µrad;";
    }
    line.pop_back();
    lines.push_back(line);
  }
  if (d.part.fitted) {
    const auto side_text = [](const PartSideSummary& s) {
      return std::string(s.side == FlankSide::kRight ? "right" : "left") + " f_Hαm " +
             fixed(s.f_h_alpha_mean_um) + " (" + fixed(s.f_h_alpha_min_um) + " … " +
             fixed(s.f_h_alpha_max_um) + "), C_α " + fixed(s.c_alpha_mean_um) + ", f_Hβm " +
             fixed(s.f_h_beta_mean_um) + " (" + fixed(s.f_h_beta_min_um) + " … " +
             fixed(s.f_h_beta_max_um) + "), C_β " + fixed(s.c_beta_mean_um) + ", position range " +
             fixed(s.position_range_um) + " µm";
    };
    std::string line =
        "the gear's own deviations on " + std::to_string(d.part.flanks.size()) + " flanks";
    if (!d.part.turned_by_teeth.empty()) {
      line +=
          " measured in " + std::to_string(d.part.turned_by_teeth.size()) + " set-ups (turned by";
      for (std::size_t g = 0; g < d.part.turned_by_teeth.size(); ++g) {
        line += (g ? ", " : " ") + std::to_string(d.part.turned_by_teeth[g]);
      }
      line += " teeth)";
    }
    line += " (µm, in every model):";
    for (const PartSideSummary& s : d.part.sides) line += " " + side_text(s) + ";";
    line.pop_back();
    lines.push_back(line);
    std::string confounded;
    for (const PartConfounding& c : d.part.confounded) {
      confounded += (confounded.empty() ? "" : ", ") + c.effect;
      if (!c.indistinguishable) confounded += " (ρ " + fixed(c.correlation, 3) + ")";
    }
    if (!confounded.empty()) {
      lines.push_back(
          std::string("not separable from the gear's own deviations ") +
          (d.part.turned_by_teeth.size() > 1 ? "in these set-ups: " : "on this set-up: ") +
          confounded +
          " (diagnosis.json part.confounded_with_machine says what "
          "separates them)");
    }
  }
  lines.push_back("residual RMS " + fixed(d.gap_before.rms_um) + " µm before, " +
                  fixed(d.gap_after.rms_um) + " µm after (held-out " + fixed(d.held_out_rms_um) +
                  " µm, noise floor " + fixed(d.noise.sigma_um) + " µm" + floor_after_phrase(d) +
                  ")");
  if (d.empirical.fitted) {
    const EmpiricalTerm& em = d.empirical;
    lines.push_back("empirical term (in fitted.yaml): " + em.basis + " of order " +
                    std::to_string(em.order) + " along " + em.axis + ", residual RMS " +
                    fixed(em.rms_before_um) + " → " + fixed(em.rms_after_um) + " µm");
  }
  if (!d.outliers.excluded.empty()) {
    std::string which;
    for (std::size_t e = 0; e < d.outliers.excluded.size() && e < 5; ++e) {
      which += (e ? ", " : "") + std::to_string(d.outliers.excluded[e].line);
    }
    if (d.outliers.excluded.size() > 5) which += ", …";
    lines.push_back("excluded " + std::to_string(d.outliers.excluded.size()) +
                    " gross outlier reading" + (d.outliers.excluded.size() == 1 ? "" : "s") +
                    " (CSV line " + which + "; see the report)");
  }
  return lines;
}

std::string diagnosis_report_html(const DiagnosisReportInput& in) {
  const ReportData r = report_data(in);
  const ReportContext ctx{in, in.diagnosis, r, in.diagnosis.null_replicates,
                          !in.diagnosis.effects.empty()};
  HtmlReport report("gearmc diagnose: " + in.model.name + " vs " + in.readings_path);
  report.contents();
  verdict_section(report, ctx);
  part_section(report, ctx);
  azimuth_section(report, ctx);
  spectrum_section(report, ctx);
  position_section(report, ctx);
  gap_section(report, ctx);
  point_law_section(report, ctx);
  fitted_effects_section(report, ctx);
  selection_section(report, ctx);
  ambiguity_section(report, ctx);
  histograms_section(report, ctx);
  notes_and_inputs_section(report, ctx);
  return report.html();
}

}  // namespace gearmc
