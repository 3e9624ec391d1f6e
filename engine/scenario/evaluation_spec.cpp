// The `evaluation:` section reader (see evaluation_spec.h).
#include "engine/scenario/evaluation_spec.h"

#include <algorithm>
#include <cmath>

#include "core/input_error.h"
#include "core/number_text.h"
#include "core/yaml_reader.h"
#include "engine/schema/parameter_ranges.h"
#include "engine/schema/scenario_keys.h"
#include "gears/size_dimensions.h"

namespace gearmc {
namespace {

// The size deviations: listed by name only (`all` is ISO 1328-1's nine flank parameters).
bool size_symbol(const std::string& s) { return s == "E_sn" || s == "E_Wk" || s == "E_MdK"; }

}  // namespace

std::pair<double, double> profile_evaluation_roll_lengths(const InvoluteGear& gear,
                                                          const EvaluationSpec& spec) {
  const double L0 = gear.form_roll_length_mm(), L1 = gear.tip_roll_length_mm();
  const double end = L0 + spec.profile_end_fraction * (L1 - L0);
  return {std::min(L0, end), std::max(L0, end)};
}

std::optional<int> evaluation_span_teeth(const InvoluteGear& gear, const EvaluationSpec& spec) {
  if (gear.internal()) return std::nullopt;
  const auto [lo, hi] = profile_evaluation_roll_lengths(gear, spec);
  const auto inside = [&](int k) {
    const double L = span_contact_roll_length_mm(gear, k);
    return L >= lo && L <= hi;
  };
  if (spec.span_teeth) {
    if (*spec.span_teeth < gear.teeth() && inside(*spec.span_teeth)) return spec.span_teeth;
    return std::nullopt;
  }
  std::optional<int> best;
  const double mid = 0.5 * (lo + hi);
  for (int k = 1; k < gear.teeth(); ++k) {
    if (!inside(k)) continue;
    const double miss = std::abs(span_contact_roll_length_mm(gear, k) - mid);
    if (!best || miss < std::abs(span_contact_roll_length_mm(gear, *best) - mid)) best = k;
  }
  return best;
}

std::optional<double> evaluation_ball_diameter_mm(const InvoluteGear& gear,
                                                  const EvaluationSpec& spec) {
  const auto [lo, hi] = profile_evaluation_roll_lengths(gear, spec);
  if (spec.ball_diameter_mm) {
    const double L = ball_position(gear, *spec.ball_diameter_mm).contact_roll_length_mm;
    if (L >= lo && L <= hi) return spec.ball_diameter_mm;
    return std::nullopt;
  }
  return ball_diameter_touching_at(gear, 0.5 * (lo + hi));
}

EvaluationSpec read_evaluation(const YamlValue& value, double face_width_mm,
                               InputWarnings* warnings) {
  EvaluationSpec spec;
  if (value.is_null()) {
    throw value.error("a map of evaluation keys, e.g. {parameters: all}");
  }
  const YamlMap map = value.as_map(child_keys("evaluation"));
  const std::vector<std::string>& symbols = scenario_key("evaluation.parameters").allowed;
  const std::string expected = "`all` or a list of parameter symbols (" + [&] {
    std::string s;
    for (const std::string& x : symbols) s += (s.empty() ? "" : ", ") + x;
    return s;
  }() + "), each once";
  const std::optional<YamlValue> given = map.find("parameters");
  if (!given || (given->is_scalar() && !given->is_quoted() && given->as_string() == "all")) {
    spec.all = true;  // the default: every ISO 1328-1 parameter
    for (const std::string& s : symbols) {
      if (!size_symbol(s)) spec.parameters.push_back(s);
    }
  } else if (given->is_sequence()) {
    const std::vector<YamlValue> items = given->as_sequence();
    if (items.empty()) throw given->error(expected);
    std::vector<bool> seen(symbols.size(), false);
    for (const YamlValue& item : items) {
      const std::string name = item.as_choice(symbols);
      const auto at = static_cast<std::size_t>(std::find(symbols.begin(), symbols.end(), name) -
                                               symbols.begin());
      if (seen[at]) throw item.error(expected, "'" + name + "' is listed twice");
      seen[at] = true;
    }
    for (std::size_t i = 0; i < symbols.size(); ++i) {
      if (seen[i]) spec.parameters.push_back(symbols[i]);
    }
  } else {
    throw given->error(expected);
  }
  const RangeTable& r = probing_ranges();
  const auto integer = [&](const char* key, int fallback) {
    return static_cast<int>(
        get_ranged_int(map, key, r.at(std::string("evaluation.") + key), warnings)
            .value_or(fallback));
  };
  spec.profile_points =
      integer("profile_points", static_cast<int>(number_default("evaluation.profile_points")));
  spec.helix_points =
      integer("helix_points", static_cast<int>(number_default("evaluation.helix_points")));
  spec.truth_points =
      integer("truth_points", static_cast<int>(number_default("evaluation.truth_points")));
  spec.profile_sections =
      integer("profile_sections", static_cast<int>(number_default("evaluation.profile_sections")));
  spec.helix_sections =
      integer("helix_sections", static_cast<int>(number_default("evaluation.helix_sections")));
  for (const char* key : {"profile_sections", "helix_sections"}) {
    if (const auto v = map.find(key); v && v->as_int() > 1 && !spec.sections_at) {
      spec.sections_at = v->location();
      spec.sections_key = std::string("evaluation.") + key;
      spec.sections_value = std::to_string(v->as_int());
    }
  }
  for (const char* key : {"profile_points", "helix_points"}) {
    if (const auto v = map.find(key); v && v->as_int() > 0 && v->as_int() < 3) {
      throw v->error("0 (the probing grid) or at least 3 points (a mean line and a form need 3)");
    }
    if (const auto v = map.find(key); v && v->as_int() > 0 && !spec.scans_at) {
      spec.scans_at = v->location();
      spec.scans_key = std::string("evaluation.") + key;
      spec.scans_value = std::to_string(v->as_int());
    }
  }
  spec.profile_end_fraction =
      get_ranged(map, "profile_end_fraction", r.at("evaluation.profile_end_fraction"), warnings)
          .value_or(number_default("evaluation.profile_end_fraction"));
  spec.helix_end_exclusion_mm = get_ranged(map, "helix_end_exclusion_mm",
                                           r.at("evaluation.helix_end_exclusion_mm"), warnings);
  if (spec.helix_end_exclusion_mm && *spec.helix_end_exclusion_mm >= 0.5 * face_width_mm) {
    throw map.find("helix_end_exclusion_mm")
        ->error("less than half the face width (" + std::to_string(0.5 * face_width_mm) +
                " mm), so that a helix evaluation range remains");
  }
  if (map.find("span_teeth")) spec.span_teeth = integer("span_teeth", 0);
  spec.ball_diameter_mm =
      get_ranged(map, "ball_diameter_mm", r.at("evaluation.ball_diameter_mm"), warnings);
  if (const auto allowances = map.find("size_allowances_um")) {
    const YamlMap sizes = allowances->as_map(child_keys("evaluation.size_allowances_um"));
    for (const char* symbol : {"E_sn", "E_Wk", "E_MdK"}) {
      const auto size = sizes.find(symbol);
      if (!size) continue;
      const std::string base = std::string("evaluation.size_allowances_um.") + symbol;
      const YamlMap ends = size->as_map(child_keys(base));
      const auto upper = get_ranged(ends, "upper", r.at(base + ".upper"), warnings);
      const auto lower = get_ranged(ends, "lower", r.at(base + ".lower"), warnings);
      if (!upper || !lower) {
        throw size->error("both allowances of " + std::string(symbol) +
                          ": {upper: µm, lower: µm} (e.g. {upper: -20, lower: -60})");
      }
      if (!(*lower < *upper)) {
        throw ends.find("lower")->error("below the upper allowance (" + short_text(*upper) +
                                        " µm)");
      }
      spec.size_allowances_um[symbol] = {*lower, *upper};
    }
  }
  spec.profile_cutoff_mm =
      get_ranged(map, "profile_cutoff_mm", r.at("evaluation.profile_cutoff_mm"), warnings);
  spec.helix_cutoff_mm =
      get_ranged(map, "helix_cutoff_mm", r.at("evaluation.helix_cutoff_mm"), warnings);
  if (const auto rule = map.get_choice("decision_rule", key_choices("evaluation.decision_rule"))) {
    spec.decision_rule = *rule;
  } else {
    spec.decision_rule = choice_default("evaluation.decision_rule");
  }
  return spec;
}

void check_evaluation(const YamlValue& value, const EvaluationSpec& spec,
                      const ProbingPlanSpec& plan, const InvoluteGear& gear,
                      bool has_mesh_surfaces) {
  const int gear_teeth = gear.teeth();
  if (has_mesh_surfaces) {
    throw value.error(
        "no `surfaces:` in the same scenario: a mesh flank's true deviation at a point is not "
        "known, so its parameters would have no true value to compare with");
  }
  const auto listed = [&](const char* symbol) {
    return std::find(spec.parameters.begin(), spec.parameters.end(), symbol) !=
           spec.parameters.end();
  };
  // The gauges must touch where the profile is evaluated: their size deviations are read off the
  // profile traces there.
  const YamlMap map = value.as_map(child_keys("evaluation"));
  const auto [lo, hi] = profile_evaluation_roll_lengths(gear, spec);
  const std::string range = "L_α = " + short_text(lo) + " … " + short_text(hi) + " mm";
  if (spec.span_teeth && !evaluation_span_teeth(gear, spec)) {
    std::string fits;
    for (int k = 1; k < gear_teeth && !gear.internal(); ++k) {
      const double L = span_contact_roll_length_mm(gear, k);
      if (L >= lo && L <= hi) fits += (fits.empty() ? "" : ", ") + std::to_string(k);
    }
    throw map.find("span_teeth")
        ->error(gear.internal() ? "no span_teeth: an internal gear has no base tangent length"
                : *spec.span_teeth >= gear_teeth
                    ? "fewer teeth than the gear's " + std::to_string(gear_teeth)
                    : "a span whose jaws touch within " + range +
                          " (k = " + (fits.empty() ? std::string("none") : fits) +
                          "); this one touches at L = " +
                          short_text(span_contact_roll_length_mm(gear, *spec.span_teeth)) + " mm");
  }
  if (spec.ball_diameter_mm && !evaluation_ball_diameter_mm(gear, spec)) {
    const auto d_lo = ball_diameter_touching_at(gear, gear.internal() ? hi : lo);
    const auto d_hi = ball_diameter_touching_at(gear, gear.internal() ? lo : hi);
    throw map.find("ball_diameter_mm")
        ->error("a ball touching within " + range +
                (d_lo && d_hi ? " (D_M = " + short_text(*d_lo) + " … " + short_text(*d_hi) + " mm)"
                              : std::string("")) +
                "; this one touches at L = " +
                short_text(ball_position(gear, *spec.ball_diameter_mm).contact_roll_length_mm) +
                " mm");
  }
  if (listed("E_Wk") && gear.internal()) {
    throw value.error(
        "parameters without E_Wk on an internal gear (no calliper spans its teeth; "
        "E_MdK is the dimension between balls)");
  }
  if (listed("E_Wk") && !evaluation_span_teeth(gear, spec)) {
    throw value.error("parameters without E_Wk: no span of this gear touches within " + range);
  }
  if (listed("E_MdK") && !evaluation_ball_diameter_mm(gear, spec)) {
    throw value.error("parameters without E_MdK: no ball touches within " + range);
  }
  // On the grid, several traces take distinct sections (columns) of it.
  if (spec.profile_points == 0 && spec.profile_sections > plan.grid.sections_across_face) {
    throw map.find("profile_sections")
        ->error("at most the grid's " + std::to_string(plan.grid.sections_across_face) +
                " sections (probing.sections_across_face), or profile_points for scans");
  }
  if (spec.helix_points == 0 && spec.helix_sections > plan.grid.points_along_profile) {
    throw map.find("helix_sections")
        ->error("at most the grid's " + std::to_string(plan.grid.points_along_profile) +
                " columns (probing.points_along_profile), or helix_points for scans");
  }
  for (const char* symbol : {"E_sn", "E_Wk", "E_MdK"}) {
    if (listed(symbol) && !(plan.left && plan.right)) {
      throw value.error(std::string("parameters without ") + symbol +
                        ", or both flanks probed (probing.flanks: both): a size is measured "
                        "between two flanks");
    }
  }
  if (spec.all) return;  // evaluate what the plan allows, with a note for the rest
  const bool every_tooth = plan.teeth.empty() || static_cast<int>(plan.teeth.size()) == gear_teeth;
  for (const char* symbol : {"f_pt", "F_p", "F_r"}) {
    if (listed(symbol) && !every_tooth) {
      throw value.error(std::string("parameters without ") + symbol +
                        ", or every tooth probed (probing.teeth: all): pitch and runout need "
                        "every tooth");
    }
  }
  if (listed("F_r") && !(plan.left && plan.right)) {
    throw value.error(
        "parameters without F_r, or both flanks probed (probing.flanks: both): the runout ball "
        "touches both flanks of every space");
  }
}

}  // namespace gearmc
