// diagnosis.json from a Diagnosis (see diagnosis_json.h).
#include "engine/apps/diagnose/diagnosis_json.h"

#include <cmath>
#include <nlohmann/json.hpp>

#include "core/output_files.h"

namespace gearmc {
namespace {

using Json = nlohmann::ordered_json;

Json number(double x) { return std::isfinite(x) ? Json(x) : Json(nullptr); }

Json numbers(const std::vector<double>& values) {
  Json a = Json::array();
  for (double v : values) a.push_back(number(v));
  return a;
}

Json part_value(const PartValue& v) {
  if (!v.estimable) return nullptr;
  return Json{{"value_um", number(v.value_um)}, {"U_um", number(v.u_um)}};
}

// A production gear's own deviations (part_model.h): per flank and per side, with U (k = 2).
Json part_json(const PartDeviations& p) {
  Json flanks = Json::array();
  for (const PartFlankDeviations& d : p.flanks) {
    const PartFlank& f = d.flank;
    flanks.push_back({{"gear", f.gear},
                      {"tooth", f.tooth},
                      {"flank", f.side == FlankSide::kRight ? "R" : "L"},
                      {"points", f.points},
                      {"profile_range_mm", {number(f.profile_from_mm), number(f.profile_to_mm)}},
                      {"face_range_mm", {number(f.face_from_mm), number(f.face_to_mm)}},
                      {"position", part_value(d.position)},
                      {"f_Halpha", part_value(d.f_h_alpha)},
                      {"C_alpha", part_value(d.c_alpha)},
                      {"f_Hbeta", part_value(d.f_h_beta)},
                      {"C_beta", part_value(d.c_beta)}});
  }
  Json sides = Json::array();
  for (const PartSideSummary& s : p.sides) {
    sides.push_back(
        {{"flank", s.side == FlankSide::kRight ? "R" : "L"},
         {"flanks", s.flanks},
         {"f_Halpha_mean_um", number(s.f_h_alpha_mean_um)},
         {"f_Halpha_range_um", {number(s.f_h_alpha_min_um), number(s.f_h_alpha_max_um)}},
         {"C_alpha_mean_um", number(s.c_alpha_mean_um)},
         {"f_Hbeta_mean_um", number(s.f_h_beta_mean_um)},
         {"f_Hbeta_range_um", {number(s.f_h_beta_min_um), number(s.f_h_beta_max_um)}},
         {"C_beta_mean_um", number(s.c_beta_mean_um)},
         {"position_mean_um", number(s.position_mean_um)},
         {"position_range_um", number(s.position_range_um)}});
  }
  Json confounded = Json::array();
  for (const PartConfounding& c : p.confounded) {
    confounded.push_back({{"effect", c.effect},
                          {"correlation", number(c.correlation)},
                          {"indistinguishable", c.indistinguishable},
                          {"separate_by", c.separate_by}});
  }
  Json setups = Json::array();
  for (std::size_t g = 0; g < p.turned_by_teeth.size(); ++g) {
    setups.push_back({{"gear", g}, {"turned_by_teeth", p.turned_by_teeth[g]}});
  }
  return Json{{"columns", p.columns}, {"rank", p.rank},
              {"setups", setups},     {"fitted_rms_um", number(p.fitted_rms_um)},
              {"sides", sides},       {"confounded_with_machine", confounded},
              {"flanks", flanks}};
}

Json gap_json(const GapStatistics& g) {
  Json j;
  j["rms_um"] = number(g.rms_um);
  j["ks"] = number(g.ks);
  j["ks_p"] = number(g.ks_p);
  j["chi2_dof"] = number(g.chi2_dof);
  j["chi2_p"] = number(g.chi2_p);
  j["combined_p"] = number(g.combined_p);
  j["dof"] = g.dof;
  j["excess_rms_um"] = number(g.excess_rms_um);
  j["energy_um"] = number(g.energy_um);
  j["energy_p"] = number(g.energy_p);
  j["rms_ci95_um"] = {number(g.rms_lo_um), number(g.rms_hi_um)};
  return j;
}

Json test_json(const CandidateTest& t) {
  Json j;
  j["name"] = t.name;
  j["added_columns"] = t.added_rank;
  j["dof_residual"] = t.dof_residual;
  j["f"] = number(t.f);
  j["p_f"] = number(t.p_f);
  j["p_holm"] = number(t.p_holm);
  j["p_null"] = number(t.p_null);
  j["delta_bic"] = number(t.delta_bic);
  j["effect_rms_um"] = number(t.effect_rms_um);
  j["joint_rms_um"] = number(t.joint_rms_um);
  j["significant"] = t.significant;
  j["bic_support"] = t.bic_support;
  j["practical"] = t.practical;
  j["accepted"] = t.accepted;
  if (!t.note.empty()) j["note"] = t.note;
  return j;
}

Json values_json(const std::vector<FittedValue>& values, bool errors) {
  Json j = Json::object();
  for (const FittedValue& v : values) j[v.name] = number(errors ? v.std_error : v.value);
  return j;
}

// Removes every null (a number that could not be computed) from `j`: a null member of an object,
// or a member array with a null element, is taken out and its key listed in that object's
// "not_computed" array; arrays of objects are walked element by element.
void move_nulls_to_status(Json& j) {
  if (j.is_array()) {
    for (Json& e : j) move_nulls_to_status(e);
    return;
  }
  if (!j.is_object()) return;
  Json missing = Json::array();
  Json kept = Json::object();
  for (auto& [key, value] : j.items()) {
    bool null = value.is_null();
    if (value.is_array()) {
      for (const Json& e : value) null = null || e.is_null();
    }
    if (null) {
      missing.push_back(key);
      continue;
    }
    move_nulls_to_status(value);
    kept[key] = std::move(value);
  }
  if (!missing.empty()) kept["not_computed"] = missing;
  j = std::move(kept);
}

}  // namespace

std::string diagnosis_json(const Diagnosis& d) {
  Json j;
  j["status"] = std::string(spelling(d.status));
  if (!d.status_reason.empty()) j["status_reason"] = d.status_reason;
  j["gap_detected"] = d.gap_detected;
  j["named_effect"] = d.named_effect_text();
  j["ambiguous_with"] = d.ambiguous_with;
  Json effects = Json::array();
  for (const FittedEffect& e : d.effects) {
    Json je;
    je["name"] = e.name;
    je["parameters"] = values_json(e.parameters, false);
    // Point-law effects give their own values, the linear ones increments to the model's.
    je["parameters_are"] = e.absolute ? "values" : "increments";
    je["std_errors"] = values_json(e.parameters, true);
    if (!e.settings.empty()) {
      Json settings = Json::object();
      for (const auto& [key, value] : e.settings) settings[key] = number(value);
      je["settings"] = settings;
    }
    if (e.name == "artefact_form") je["kind"] = "artefact";  // the workpiece's, not the CMM's
    Json units = Json::object();
    for (const FittedValue& v : e.parameters) units[v.name] = v.unit;
    je["units"] = units;
    Json not_observable = Json::array();
    for (const FittedValue& v : e.parameters) {
      if (!v.estimable) not_observable.push_back(v.name);
    }
    Json evidence = test_json(e.evidence);
    evidence["step"] = e.step;
    evidence["fitted_rms_um"] = number(e.fitted_rms_um);
    evidence["not_observable"] = not_observable;
    Json coefficients = Json::object();
    for (const FittedValue& v : e.coefficients) {
      coefficients[v.name] = {
          {"value", number(v.value)}, {"std_error", number(v.std_error)}, {"unit", v.unit}};
    }
    evidence["coefficients"] = coefficients;
    Json ambiguous = Json::array();
    for (const Ambiguity& a : e.ambiguous) {
      ambiguous.push_back({{"with", a.with},
                           {"reason", a.reason},
                           {"signal_correlation", number(a.signal_correlation)},
                           {"canonical_correlation", number(a.canonical_correlation)},
                           {"condition_number", number(a.condition_number)},
                           {"delta_bic_gap", number(a.delta_bic_gap)},
                           {"separate_by", a.separate_by}});
    }
    evidence["ambiguous"] = ambiguous;
    je["evidence"] = evidence;
    if (std::isfinite(e.per_gear_p)) {
      Json gears = Json::array();
      for (const FittedEffect::GearValues& g : e.per_gear) {
        gears.push_back({{"gear", g.gear},
                         {"coefficients", values_json(g.coefficients, false)},
                         {"std_errors", values_json(g.coefficients, true)}});
      }
      je["per_gear"] = {
          {"varies", e.varies_per_gear}, {"p_value", number(e.per_gear_p)}, {"gears", gears}};
    }
    effects.push_back(je);
  }
  j["effects"] = effects;
  j["workpiece"] = d.workpiece == Workpiece::kProduction ? "production" : "master";
  if (d.reading_grid.found()) {
    j["reading_resolution"] = {{"step_um", number(d.reading_grid.step_um)},
                               {"resultant", number(d.reading_grid.resultant)},
                               {"dithered", true}};
  }
  if (d.part.fitted) j["part"] = part_json(d.part);
  if (d.setups.tested) {
    Json runs = Json::array();
    for (const SetupRun& r : d.setups.runs) {
      runs.push_back({{"gear", r.gear},
                      {"shift_x_um", number(r.shift_x_um)},
                      {"shift_x_std_error_um", number(r.shift_x_se_um)},
                      {"shift_y_um", number(r.shift_y_um)},
                      {"shift_y_std_error_um", number(r.shift_y_se_um)},
                      {"turn_urad", number(r.turn_urad)},
                      {"turn_std_error_urad", number(r.turn_se_urad)}});
    }
    j["setups"] = {{"fitted", d.setups.fitted},           {"f", number(d.setups.f)},
                   {"p_value", number(d.setups.p_value)}, {"columns", d.setups.columns},
                   {"rms_um", number(d.setups.rms_um)},   {"runs", runs}};
  }
  j["gap_before"] = gap_json(d.gap_before);
  Json after = gap_json(d.gap_after);
  after["held_out_rms_um"] = number(d.held_out_rms_um);
  after["held_out_without_effects_rms_um"] = number(d.held_out_without_rms_um);
  after["held_out_split"] = d.held_out_split;
  j["gap_after"] = after;
  j["noise_floor_um"] = number(d.noise.sigma_um);
  j["noise_floor_after_um"] = number(d.noise_floor_after_um);
  j["noise_floor"] = {{"source", std::string(spelling(d.noise.source))},
                      {"numerical_floor_um", number(d.noise.numerical_um)},
                      {"raised_to_numerical_floor", d.noise.at_numerical_floor},
                      {"model_um", number(d.noise.model_um)},
                      {"robust_um", number(d.noise.robust_um)},
                      {"second_differences", d.noise.differences}};
  {
    const PointLawStage& st = d.point_law;
    Json hypotheses = Json::array();
    for (const PointLawHypothesis& h : st.hypotheses) {
      hypotheses.push_back({{"name", h.name},
                            {"tied", h.tied},
                            {"parameters", h.parameters},
                            {"log_likelihood", number(h.log_likelihood)},
                            {"delta_bic", number(h.delta_bic)},
                            {"estimate_um", number(h.estimate)},
                            {"std_error_um", number(h.std_error)},
                            {"sd_um", number(std::sqrt(h.law.variance_um2()))},
                            {"accepted", h.accepted},
                            {"note", h.note}});
    }
    j["point_law"] = {{"ran", st.ran},
                      {"skipped_because", st.skipped_because},
                      {"model_sd_um", number(std::sqrt(st.model_variance_um2))},
                      {"white_sd_um", number(std::sqrt(st.white_variance_um2))},
                      {"white_p", number(st.white_p)},
                      {"second_differences", st.differences},
                      {"chosen", st.chosen > 0 ? Json(st.best().name) : Json("none")},
                      {"hypotheses", hypotheses}};
  }
  {
    const CoordinateGrid& g = d.coordinate_grid;
    Json axes = Json::object();
    const char* names[3] = {"x", "y", "z"};
    for (int a = 0; a < 3; ++a) {
      const CoordinateGridAxis& axis = g.axes[static_cast<std::size_t>(a)];
      axes[names[a]] = {{"step_um", number(axis.step_um)},
                        {"resultant", number(axis.resultant)},
                        {"observable", axis.observable}};
    }
    j["coordinate_grid"] = {{"ran", g.ran},
                            {"skipped_because", g.skipped_because},
                            {"points", g.points},
                            {"axes", axes},
                            {"rms_um", number(g.rms_um)},
                            {"false_alarm", number(g.false_alarm)},
                            {"in_model", g.in_model},
                            {"named", g.named},
                            {"note", g.note}};
    if (g.check.ran) {
      j["coordinate_grid"]["latched_model_check"] = {{"replicates", g.check.replicates},
                                                     {"ks", number(g.check.ks)},
                                                     {"rms_um", number(g.check.rms_um)},
                                                     {"p", number(g.check.p)}};
    }
  }
  j["unexplained_structure"] = d.unexplained_structure;
  if (d.law_shape.differs) {
    j["law_shape"] = {{"differs", true},
                      {"shape", d.law_shape.shape},
                      {"ks_p", number(d.law_shape.ks_p)},
                      {"excess_kurtosis", number(d.law_shape.excess_kurtosis)},
                      {"kurtosis_std_error", number(d.law_shape.kurtosis_std_error)},
                      {"model_excess_kurtosis", number(d.law_shape.model_excess_kurtosis)},
                      {"spread_ratio", number(d.law_shape.spread_ratio)}};
  }
  if (d.unexplained_structure) {
    j["partially_explained_by"] = d.partially_explained_by;
    j["unexplained_along"] = {{"axis", d.unexplained_along.axis},
                              {"p_value", number(d.unexplained_along.p_value)},
                              {"variance_share", number(d.unexplained_along.variance_share)},
                              {"axes_tested", d.unexplained_along.axes_tested}};
    if (std::isfinite(d.unexplained_along.period_mm)) {
      j["unexplained_along"]["period_mm"] = number(d.unexplained_along.period_mm);
      j["unexplained_along"]["amplitude_um"] = number(d.unexplained_along.amplitude_um);
    }
    const EmpiricalTerm& e = d.empirical;
    Json empirical = {{"fitted", e.fitted},
                      {"axis", e.axis},
                      {"basis", e.basis},
                      {"identify_by", e.identify_by},
                      {"rms_before_um", number(e.rms_before_um)},
                      {"rms_after_um", number(e.rms_after_um)},
                      {"excess_rms_before_um", number(e.excess_rms_before_um)},
                      {"excess_rms_after_um", number(e.excess_rms_after_um)}};
    if (e.fitted) {
      Json terms = Json::object(), errors = Json::object(), bic = Json::array();
      for (const EmpiricalTermValue& v : e.terms) {
        terms[v.name] = number(v.value_um);
        errors[v.name] = number(v.std_error_um);
      }
      for (double b : e.bic) bic.push_back(number(b));
      empirical["order"] = e.order;
      empirical["max_order"] = e.max_order;
      if (e.basis == "legendre") empirical["range"] = {number(e.from), number(e.to)};
      empirical["terms_um"] = terms;
      empirical["std_errors_um"] = errors;
      empirical["delta_bic"] = number(e.delta_bic);
      empirical["bic_by_order"] = bic;
      empirical["fitted_rms_um"] = number(e.fitted_rms_um);
      Json beside = Json::array();
      for (const FittedEffect& f : d.effects_with_empirical) beside.push_back(f.name);
      empirical["library_effects_beside"] = beside;
    } else {
      empirical["why_not"] = e.why_not;
    }
    j["empirical"] = empirical;
  }
  j["explained_fraction"] = number(d.explained_fraction);
  {
    const OutlierScreen& o = d.outliers;
    Json excluded = Json::array();
    for (const ExcludedReading& e : o.excluded) {
      excluded.push_back({{"line", e.line},
                          {"gear", e.gear},
                          {"tooth", e.tooth},
                          {"flank", e.side == FlankSide::kRight ? "R" : "L"},
                          {"i", e.i},
                          {"j", e.j},
                          {"residual_um", number(e.residual_um)},
                          {"z", number(e.z_score)}});
    }
    j["outliers"] = {{"rule",
                      "prediction from the profile scan's neighbours, |z| > z* = "
                      "Phi^-1(1 - alpha/(2n)), excluded one at a time"},
                     {"family_false_alarm", number(o.family_false_alarm)},
                     {"threshold_z", number(o.threshold_z)},
                     {"sigma_um", number(o.sigma_um)},
                     {"screened", o.screened},
                     {"excluded", excluded},
                     {"not_applied", o.not_applied}};
  }
  j["notes"] = d.notes;
  j["points"] = d.points;
  j["nominal_fallback_points"] = d.nominal_fallback;
  j["null_replicates"] = d.null_replicates;
  j["null_rows"] = d.null_rows;
  j["seed"] = d.seed;
  j["alpha"] = d.alpha;
  Json steps = Json::array();
  for (const SelectionStep& s : d.selection.steps) {
    Json js;
    Json before = Json::array();
    for (int c : s.selected_before) before.push_back(d.candidate_names.at(c));
    js["selected_before"] = before;
    js["rss_before_um2"] = number(s.rss_before);
    js["null_max_f_95"] = number(s.null_max_f_95);
    Json tests = Json::array();
    for (const CandidateTest& t : s.tests) tests.push_back(test_json(t));
    js["candidates"] = tests;
    js["accepted"] = s.accepted >= 0 ? Json(s.tests[s.accepted].name) : Json("none");
    steps.push_back(js);
  }
  j["selection"] = steps;
  {  // Every selected effect re-tested given the others (selection.h): kept and dropped.
    Json kept = Json::array(), dropped = Json::array();
    for (const CandidateTest& t : d.selection.retest) kept.push_back(test_json(t));
    for (const CandidateTest& t : d.selection.dropped) dropped.push_back(test_json(t));
    j["selection_retest"] = {{"kept", kept}, {"dropped", dropped}};
  }
  Json orders = Json::array();
  for (std::size_t k = 0; k < d.spectrum_before_um.size(); ++k) orders.push_back(k);
  j["spectrum"] = {{"orders", orders},
                   {"before_um", numbers(d.spectrum_before_um)},
                   {"after_um", numbers(d.spectrum_after_um)},
                   {"null95_before_um", numbers(d.spectrum_null95_before_um)},
                   {"null95_after_um", numbers(d.spectrum_null95_after_um)}};
  move_nulls_to_status(j);
  return j.dump(2) + "\n";
}

void write_diagnosis_json(const std::string& path, const Diagnosis& diagnosis) {
  write_file_atomically(path, diagnosis_json(diagnosis));
}

}  // namespace gearmc
