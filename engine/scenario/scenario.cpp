// Scenario files: the YAML text is read section by section into the typed, validated Scenario
// struct (docs/architecture.md, principle 5), so that constructors downstream only ever see good
// values. Unknown keys, wrong types, out-of-range values, missing required keys, YAML syntax
// errors and unreadable files all become one InputError naming file:line:column, the dotted key,
// the value and what was expected (principle 4). This file reads the top level and the small
// sections (name, seed, stylus, run) and hands each larger section to its reader: the gear's
// sections (gear_sections.h), the plan's (probing_sections.h), effects (effect_config.h),
// claims (claims.h) and evaluation (evaluation_spec.h); each documents its schema.
#include "engine/scenario/scenario.h"

#include <algorithm>
#include <filesystem>
#include <memory>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "core/input_error.h"
#include "core/input_file.h"
#include "core/yaml_reader.h"
#include "engine/effects/cmm_effects.h"
#include "engine/effects/effect_config.h"
#include "engine/effects/measurement_effect.h"
#include "engine/scenario/claims.h"
#include "engine/scenario/gear_sections.h"
#include "engine/scenario/probing_sections.h"
#include "engine/schema/parameter_ranges.h"
#include "engine/schema/scenario_keys.h"

namespace gearmc {
namespace {

// The scenario's name: results go to results/<name>/, so it must be one plain path component.
std::string read_name(const YamlValue& value) {
  const std::string expected = "a non-empty name without '/' or '\\' (it names the results folder)";
  const std::string name = value.as_string();
  if (name.empty() || name == "." || name == ".." ||
      name.find_first_of("/\\") != std::string::npos) {
    throw value.error(expected);
  }
  return name;
}

}  // namespace

Scenario::Scenario() : effects(std::make_shared<const EffectChain>()) {}

Scenario parse_scenario(const std::string& yaml_text, const std::string& source_name) {
  // Every user string may end up in JSON outputs and reports: the whole text must be UTF-8.
  require_utf8(yaml_text, source_name, "scenario file");
  const YamlValue root = parse_yaml_document(yaml_text, source_name);
  const std::string expected_top =
      "a map of scenario keys (name, seed, gear, tolerances, deviations, probing, stylus, run, "
      "surfaces, effects, claims, evaluation)";
  if (root.is_null()) {
    throw InputError(root.location(), "", "", expected_top + ", but the scenario is empty");
  }
  if (!root.is_map()) throw root.error(expected_top);
  const YamlMap top = root.as_map(child_keys(""));

  Scenario scenario;
  scenario.source_path = source_name;
  scenario.source_text = yaml_text;
  if (const auto name = top.find("name")) {
    scenario.name = read_name(*name);
  } else {
    scenario.name = std::filesystem::path(source_name).stem().string();
    if (scenario.name.empty()) scenario.name = "scenario";
  }
  scenario.seed =
      top.get_uint64("seed").value_or(static_cast<std::uint64_t>(number_default("seed")));
  InputWarnings* warnings = &scenario.warnings;
  const YamlMap gear_map = top.require_map("gear", child_keys("gear"));
  scenario.gear = read_gear(gear_map, warnings);
  const std::optional<YamlMap> tolerances = top.get_map("tolerances", child_keys("tolerances"));
  if (tolerances) scenario.tolerances = read_tolerances(*tolerances, warnings);
  if (const auto deviations = top.get_map("deviations", child_keys("deviations"))) {
    scenario.deviations = read_deviations(*deviations, &scenario.normal_expression_um, warnings);
  }
  // The tolerances are resolved here, so that every command (geometry, run, simulate, …)
  // accepts or rejects the same scenario, with the place of the cause.
  check_tolerances(scenario, gear_map, tolerances);
  const std::optional<YamlMap> probing = top.get_map("probing", child_keys("probing"));
  scenario.probing =
      probing ? read_probing(*probing, scenario.gear.teeth, warnings) : probing_defaults();
  {
    const ProbingPlanSpec& plan = scenario.probing;
    const double teeth =
        plan.teeth.empty() ? scenario.gear.teeth : static_cast<double>(plan.teeth.size());
    const double points = static_cast<double>(plan.grid.points_along_profile) *
                          plan.grid.sections_across_face * teeth *
                          ((plan.left ? 1 : 0) + (plan.right ? 1 : 0));
    const InputLocation where = probing ? probing->location() : top.location();
    check_ranged(points, probing_ranges().at("probing.points_per_gear"), where,
                 std::to_string(static_cast<long long>(points)), warnings);
  }
  scenario.stylus_radius_mm = number_default("stylus.radius_mm");
  scenario.gears = static_cast<int>(number_default("run.gears"));
  if (const auto stylus = top.get_map("stylus", child_keys("stylus"))) {
    scenario.stylus_radius_mm =
        get_ranged(*stylus, "radius_mm", probing_ranges().at("stylus.radius_mm"), warnings)
            .value_or(scenario.stylus_radius_mm);
    if (const auto shaft = get_ranged(*stylus, "shaft_diameter_mm",
                                      probing_ranges().at("stylus.shaft_diameter_mm"), warnings)) {
      if (*shaft >= 2.0 * scenario.stylus_radius_mm) {
        std::ostringstream expected;
        expected << "a shaft thinner than the ball (diameter " << 2.0 * scenario.stylus_radius_mm
                 << " mm)";
        throw stylus->find("shaft_diameter_mm")->error(expected.str());
      }
      scenario.stylus_shaft_diameter_mm = *shaft;
    }
    if (const auto axis = stylus->get_choice("shaft_axis", key_choices("stylus.shaft_axis"))) {
      scenario.stylus_shaft_axis = *axis == "radial" ? ShaftAxis::kRadial : ShaftAxis::kZ;
    }
  }
  if (const auto run = top.get_map("run", child_keys("run"))) {
    scenario.gears =
        static_cast<int>(get_ranged_int(*run, "gears", probing_ranges().at("run.gears"), warnings)
                             .value_or(scenario.gears));
  }
  if (const auto surfaces = top.find("surfaces")) {
    scenario.surfaces = read_surfaces(*surfaces, scenario.gear, scenario.probing, source_name);
  }
  {
    EffectChain chain;
    if (const auto effects = top.find("effects")) chain = parse_effects(*effects, warnings);
    if (const auto cmm = top.find("cmm")) {
      const InvoluteGear nominal(scenario.gear);
      const double radius = 0.5 * std::max(nominal.tip_diameter_mm(), nominal.root_diameter_mm()) +
                            scenario.stylus_radius_mm;
      const bool radial = scenario.stylus_shaft_axis == ShaftAxis::kRadial;
      scenario.cmm = read_cmm(*cmm, scenario.seed, radius, scenario.gear.face_width_mm, radial,
                              scenario.gear.internal, warnings);
      add_cmm_effects(scenario.cmm, radial, scenario.gear.internal, chain);
    }
    scenario.effects = std::make_shared<const EffectChain>(std::move(chain));
  }
  if (const auto claims = top.find("claims")) {
    scenario.claims = read_claims(*claims, !scenario.effects->empty(), warnings);
  }
  if (const auto evaluation = top.find("evaluation")) {
    scenario.evaluation = read_evaluation(*evaluation, scenario.gear.face_width_mm, warnings);
    check_evaluation(*evaluation, *scenario.evaluation, scenario.probing,
                     InvoluteGear(scenario.gear), !scenario.surfaces.empty());
  }
  // A claim on a gear parameter needs that parameter in `evaluation:`.
  const auto joined = [](const std::vector<std::string>& v) {
    std::string out;
    for (const std::string& x : v) out += (out.empty() ? "" : ", ") + x;
    return out;
  };
  for (const ClaimSpec& c : scenario.claims) {
    if (c.quantity != ClaimQuantity::kParameterError) continue;
    const std::vector<std::string>* evaluated =
        scenario.evaluation ? &scenario.evaluation->parameters : nullptr;
    if (!evaluated ||
        std::find(evaluated->begin(), evaluated->end(), c.parameter) == evaluated->end()) {
      throw InputError(c.quantity_where, "claims.quantity", c.quantity_text,
                       "a gear parameter the scenario's `evaluation:` evaluates (" +
                           (evaluated ? "it evaluates: " + joined(*evaluated)
                                      : std::string("add evaluation: {parameters: all}")) +
                           ")");
    }
  }
  return scenario;
}

Scenario load_scenario_file(const std::string& path) {
  return parse_scenario(read_input_file(path, "scenario file", kMaxScenarioBytes), path);
}

ToleranceSet resolve_scenario_tolerances(const Scenario& scenario, const InvoluteGear& gear) {
  try {
    return resolve_tolerances(scenario.tolerances, gear);
  } catch (const ToleranceError& e) {
    throw InputError({scenario.source_path, 0, 0},
                     scenario.source_path + ": tolerances: " + e.what());
  }
}

void apply_overrides(const ScenarioOverrides& overrides, Scenario& scenario) {
  if (overrides.seed) scenario.seed = *overrides.seed;
  if (overrides.gears) scenario.gears = *overrides.gears;
}

}  // namespace gearmc
