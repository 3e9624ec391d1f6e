// The `evaluation:` section reader (see evaluation_spec.h).
#include "engine/scenario/evaluation_spec.h"

#include <algorithm>

#include "core/input_error.h"
#include "core/yaml_reader.h"
#include "engine/schema/parameter_ranges.h"
#include "engine/schema/scenario_keys.h"

namespace gearmc {

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
    spec.all = true;  // the default: every parameter
    spec.parameters = symbols;
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
  if (const auto rule = map.get_choice("decision_rule", key_choices("evaluation.decision_rule"))) {
    spec.decision_rule = *rule;
  } else {
    spec.decision_rule = choice_default("evaluation.decision_rule");
  }
  return spec;
}

void check_evaluation(const YamlValue& value, const EvaluationSpec& spec,
                      const ProbingPlanSpec& plan, int gear_teeth, bool has_mesh_surfaces) {
  if (has_mesh_surfaces) {
    throw value.error(
        "no `surfaces:` in the same scenario: a mesh flank's true deviation at a point is not "
        "known, so its parameters would have no true value to compare with");
  }
  if (spec.all) return;  // evaluate what the plan allows, with a note for the rest
  const auto listed = [&](const char* symbol) {
    return std::find(spec.parameters.begin(), spec.parameters.end(), symbol) !=
           spec.parameters.end();
  };
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
