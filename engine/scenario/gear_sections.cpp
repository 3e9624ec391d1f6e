// The gear, tolerances and deviations sections of a scenario and the runout check (see
// gear_sections.h). The schema of each section is documented with its reader below.
#include "engine/scenario/gear_sections.h"

#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "engine/schema/parameter_ranges.h"
#include "engine/schema/scenario_keys.h"
#include "gears/normal_expression.h"

namespace gearmc {
namespace {

// The grade in the form the standard uses: GOST 1643-81 "K-S-C" (kinematic, smoothness and
// contact grades, each 1..12) or one grade 1..12 for all three; ISO 1328-1:2013 the flank
// tolerance class 1..11. Written as text or as an integer.
std::string read_grade(const YamlValue& value, ToleranceStandard standard) {
  const bool gost = standard == ToleranceStandard::kGost1643_81;
  const std::string expected =
      gost ? "a GOST 1643-81 accuracy grade: 'K-S-C' (kinematic-smoothness-contact grades, each "
             "from 1 to 12, e.g. \"6-5-5\") or one grade from 1 to 12"
           : "an ISO 1328-1:2013 flank tolerance class, an integer from 1 to 11";
  if (!value.is_scalar()) throw value.error(expected);
  const std::string text = value.node().Scalar();
  if (!gost) {
    if (!parse_grade_number(text, 1, 11)) throw value.error(expected);
    return text;
  }
  std::vector<std::string> parts;
  std::size_t start = 0;
  while (true) {
    const std::size_t dash = text.find('-', start);
    parts.push_back(text.substr(start, dash - start));
    if (dash == std::string::npos) break;
    start = dash + 1;
  }
  if (parts.size() != 1 && parts.size() != 3) throw value.error(expected);
  for (const std::string& part : parts) {
    if (!parse_grade_number(part, 1, 12)) throw value.error(expected);
  }
  return text;
}

std::vector<std::string> tolerance_symbols(ToleranceStandard standard) {
  std::vector<std::string> symbols;
  for (const ToleranceKind kind : all_tolerance_kinds()) {
    if (const auto symbol = tolerance_symbol(kind, standard)) symbols.push_back(*symbol);
  }
  return symbols;
}

// overrides_um: {symbol: µm}. The symbols are the chosen standard's (tolerance_symbol); E_Hs is
// the magnitude of the least rack shift (>= 0), every other value a tolerance (> 0).
std::map<ToleranceKind, double> read_overrides(const YamlMap& overrides, ToleranceStandard standard,
                                               InputWarnings* warnings) {
  const ToleranceStandard other = standard == ToleranceStandard::kGost1643_81
                                      ? ToleranceStandard::kIso1328_1_2013
                                      : ToleranceStandard::kGost1643_81;
  std::map<ToleranceKind, double> values;
  for (const YamlMap::Entry& entry : overrides.entries()) {
    const std::optional<ToleranceKind> kind = tolerance_kind_from_symbol(entry.key, standard);
    if (!kind) {
      const std::vector<std::string> symbols = tolerance_symbols(standard);
      std::string expected = "a tolerance symbol of " + standard_name(standard) + " (";
      for (std::size_t i = 0; i < symbols.size(); ++i) expected += (i ? ", " : "") + symbols[i];
      expected += ")";
      if (tolerance_kind_from_symbol(entry.key, other)) {
        expected += "; '" + entry.key + "' is a symbol of " + standard_name(other);
      }
      throw InputError(entry.value.key_location(), entry.value.path(), entry.key, expected,
                       did_you_mean(entry.key, symbols));
    }
    const bool shift = *kind == ToleranceKind::kThicknessUpper;
    const ParameterRange& range = tolerance_ranges().at(
        shift ? "tolerances.overrides_um.E_Hs" : "tolerances.overrides_um.tolerance");
    values[*kind] = read_ranged(entry.value, range, warnings);
  }
  return values;
}

// {distribution: uniform | normal | at_tolerance, k: > 0}, each key falling back to `base`.
DeviationDistribution read_law(const YamlMap& map, DeviationDistribution base,
                               InputWarnings* warnings) {
  if (const auto law = map.get_choice("distribution", key_choices("deviations.distribution"))) {
    base.law = *law == "normal"         ? DeviationDistribution::Law::kNormal
               : *law == "at_tolerance" ? DeviationDistribution::Law::kAtTolerance
                                        : DeviationDistribution::Law::kUniform;
  }
  base.k = get_ranged(map, "k", deviation_ranges().at("deviations.k"), warnings).value_or(base.k);
  return base;
}

// Where a tolerance problem is best shown: the override of `kind` when the scenario gives one,
// else the grade, else the tolerances section, else the gear (a default GOST grade).
InputLocation tolerance_place(const YamlMap& gear, const std::optional<YamlMap>& tolerances,
                              std::optional<ToleranceKind> kind, std::string* key) {
  if (tolerances) {
    if (kind) {
      if (const auto overrides = tolerances->find("overrides_um")) {
        const YamlMap map = overrides->as_open_map();
        for (const YamlMap::Entry& entry : map.entries()) {
          if (tolerance_kind_from_symbol(entry.key, ToleranceStandard::kGost1643_81) == kind ||
              tolerance_kind_from_symbol(entry.key, ToleranceStandard::kIso1328_1_2013) == kind) {
            *key = entry.value.path();
            return entry.value.location();
          }
        }
      }
    }
    if (const auto grade = tolerances->find("grade")) {
      *key = grade->path();
      return grade->location();
    }
    *key = tolerances->path();
    return tolerances->location();
  }
  *key = gear.path();
  return gear.location();
}

// Gears drawn by the runout check (see check_tolerances).
constexpr int kRunoutCheckGears = 8;

}  // namespace

namespace {

// gear: modifications: the design flank (gears/flank_modifications.h). Each relief needs its
// amount and length; `shape: linear` (a kink in the flank: along the face for the tip and root
// reliefs, across it for the end relief) or circular (the default).
FlankModifications read_modifications(const YamlMap& m, InputWarnings* warnings) {
  const RangeTable& r = gear_ranges();
  FlankModifications out;
  const auto relief = [&](const std::string& name, FlankRelief* into) {
    const std::string path = "gear.modifications." + name;
    const auto map = m.get_map(name, child_keys(path));
    if (!map) return;
    // Both values are range-checked before a missing one is reported.
    const auto amount = get_ranged(*map, "amount_um", r.at(path + ".amount_um"), warnings);
    const auto length = get_ranged(*map, "length_mm", r.at(path + ".length_mm"), warnings);
    for (const std::string key : {"amount_um", "length_mm"}) {
      if (!map->find(key)) (void)map->require(key, describe_range(r.at(path + "." + key)));
    }
    into->amount_um = *amount;
    into->length_mm = *length;
    const std::optional<std::string> shape = map->get_choice("shape", key_choices(path + ".shape"));
    into->linear = shape && *shape == "linear";
  };
  relief("tip_relief", &out.tip_relief);
  relief("root_relief", &out.root_relief);
  relief("end_relief", &out.end_relief);
  const auto number = [&](const std::string& name) {
    const std::string path = "gear.modifications." + name;
    return get_ranged(m, name, r.at(path), warnings).value_or(number_default(path));
  };
  out.profile_crowning_um = number("profile_crowning_um");
  out.helix_crowning_um = number("helix_crowning_um");
  out.helix_slope_um = number("helix_slope_um");
  return out;
}

}  // namespace

// gear: the gear (ISO 21771 quantities; lengths in mm, angle in degrees, rack in modules).
//   teeth (required, 5..1000; -1000..-5 an internal gear), module_mm (required, > 0),
//   pressure_angle_deg (0 < α < 45, default 20), helix_angle_deg and hand, internal (bool),
//   profile_shift ([-1.5, 3], default 0), face_width_mm (required, > 0),
//   tip_diameter_mm, root_diameter_mm, form_diameter_mm (> 0, optional overrides),
//   basic_rack: {addendum > 0, dedendum > 0, root_radius >= 0} (defaults: ISO 53 profile A).
// The parameters together must make a gear (validate_gear_parameters); if not, the error is
// placed at the `gear` key.
GearParameters read_gear(const YamlMap& gear, InputWarnings* warnings) {
  const RangeTable& r = gear_ranges();
  GearParameters p;
  const auto required = [&](const std::string& key) {
    const ParameterRange& range = r.at("gear." + key);
    return gear.require(key, describe_range(range));
  };
  // A negative tooth count is an internal gear (ISO 21771's sign convention): |z| in the range.
  const YamlValue teeth = required("teeth");
  bool negative_teeth = false;
  try {
    negative_teeth = teeth.as_int() < 0;
  } catch (const InputError&) {
  }  // read_ranged_int says what is wrong
  if (negative_teeth) {
    const std::int64_t z = -teeth.as_int();
    if (!r.at("gear.teeth").valid.contains(static_cast<double>(z))) {
      throw teeth.error(describe_range(r.at("gear.teeth")) +
                        " (a negative count -z is an internal gear of z teeth)");
    }
    p.teeth = static_cast<int>(z);
  } else {
    p.teeth = static_cast<int>(read_ranged_int(teeth, r.at("gear.teeth"), warnings));
  }
  p.module_mm = read_ranged(required("module_mm"), r.at("gear.module_mm"), warnings);
  p.pressure_angle_deg =
      get_ranged(gear, "pressure_angle_deg", r.at("gear.pressure_angle_deg"), warnings)
          .value_or(number_default("gear.pressure_angle_deg"));
  p.helix_angle_deg = get_ranged(gear, "helix_angle_deg", r.at("gear.helix_angle_deg"), warnings)
                          .value_or(number_default("gear.helix_angle_deg"));
  // The hand: required with a helix angle (a helical gear is right or left), refused without one
  // (a spur gear has none: a hand there is a forgotten helix angle).
  const std::optional<std::string> hand = gear.get_choice("hand", key_choices("gear.hand"));
  if (p.helix_angle_deg > 0.0 && !hand) {
    const YamlValue beta = *gear.find("helix_angle_deg");
    throw InputError(
        beta.key_location(), "gear.hand", "",
        "'right' or 'left' with helix_angle_deg " + beta.shown() + " (a helical gear has a hand)");
  }
  if (p.helix_angle_deg == 0.0 && hand) {
    throw InputError(gear.find("hand")->location(), "gear.hand", *hand,
                     "no hand on a spur gear (helix_angle_deg 0): give the helix angle too");
  }
  p.hand = hand && *hand == "left" ? Hand::kLeft : Hand::kRight;
  // An internal (ring) gear: `internal: true` or a negative tooth count (not both contradicting).
  const std::optional<bool> internal = gear.get_bool("internal");
  if (negative_teeth && internal && !*internal) {
    throw gear.find("internal")
        ->error("true or no `internal` key with teeth " + teeth.shown() +
                " (a negative tooth count is an internal gear, ISO 21771)");
  }
  p.internal = negative_teeth || internal.value_or(false);
  if (const auto m = gear.get_map("modifications", child_keys("gear.modifications"))) {
    p.modifications = read_modifications(*m, warnings);
  }
  p.profile_shift = get_ranged(gear, "profile_shift", r.at("gear.profile_shift"), warnings)
                        .value_or(number_default("gear.profile_shift"));
  p.face_width_mm = read_ranged(required("face_width_mm"), r.at("gear.face_width_mm"), warnings);
  p.tip_diameter_mm = get_ranged(gear, "tip_diameter_mm", r.at("gear.tip_diameter_mm"), warnings);
  p.root_diameter_mm =
      get_ranged(gear, "root_diameter_mm", r.at("gear.root_diameter_mm"), warnings);
  p.form_diameter_mm =
      get_ranged(gear, "form_diameter_mm", r.at("gear.form_diameter_mm"), warnings);
  p.rack.addendum = number_default("gear.basic_rack.addendum");
  p.rack.dedendum = number_default("gear.basic_rack.dedendum");
  p.rack.root_radius = number_default("gear.basic_rack.root_radius");
  if (const auto rack = gear.get_map("basic_rack", child_keys("gear.basic_rack"))) {
    p.rack.addendum = get_ranged(*rack, "addendum", r.at("gear.basic_rack.addendum"), warnings)
                          .value_or(p.rack.addendum);
    p.rack.dedendum = get_ranged(*rack, "dedendum", r.at("gear.basic_rack.dedendum"), warnings)
                          .value_or(p.rack.dedendum);
    p.rack.root_radius =
        get_ranged(*rack, "root_radius", r.at("gear.basic_rack.root_radius"), warnings)
            .value_or(p.rack.root_radius);
  }
  const std::string why = validate_gear_parameters(p);
  if (!why.empty()) {
    throw InputError(gear.location(), gear.path(), "", "parameters that make a gear, but " + why);
  }
  return p;
}

// tolerances: standard (gost_1643_81 | iso_1328_1_2013, default gost_1643_81), grade (see
// read_grade; default "6-5-5" for GOST, required for ISO), overrides_um (see read_overrides).
ToleranceSpec read_tolerances(const YamlMap& tolerances, InputWarnings* warnings) {
  ToleranceSpec spec;
  const std::string standard = tolerances.get_choice("standard", key_choices("tolerances.standard"))
                                   .value_or(choice_default("tolerances.standard"));
  spec.standard = standard == standard_name(ToleranceStandard::kGost1643_81)
                      ? ToleranceStandard::kGost1643_81
                      : ToleranceStandard::kIso1328_1_2013;
  if (const auto grade = tolerances.find("grade")) {
    spec.grade = read_grade(*grade, spec.standard);
  } else if (spec.standard == ToleranceStandard::kIso1328_1_2013) {
    throw tolerances.missing("grade",
                             "an ISO 1328-1:2013 flank tolerance class, an integer from 1 to 11");
  }
  if (const auto overrides = tolerances.find("overrides_um")) {
    spec.overrides_um = read_overrides(overrides->as_open_map(), spec.standard, warnings);
  }
  return spec;
}

// deviations: random (bool, default true); distribution and k: the default law of every group;
// eccentricity, pitch, thickness: {distribution, k}; profile, helix: {distribution, k,
// control_points 4..64} (the law applies to both slope and form of the group); normal_um: a
// muParser expression in L, z, tooth, side (µm), checked where it is compiled.
DeviationModel read_deviations(const YamlMap& deviations, std::string* normal_expression_um,
                               InputWarnings* warnings) {
  DeviationModel model;
  model.random = deviations.get_bool("random").value_or(boolean_default("deviations.random"));
  DeviationDistribution defaults;  // the table's law and k, unless the section gives them
  const std::string default_law = choice_default("deviations.distribution");
  defaults.law = default_law == "normal"         ? DeviationDistribution::Law::kNormal
                 : default_law == "at_tolerance" ? DeviationDistribution::Law::kAtTolerance
                                                 : DeviationDistribution::Law::kUniform;
  defaults.k = number_default("deviations.k");
  const DeviationDistribution base = read_law(deviations, defaults, warnings);
  model.eccentricity = model.pitch = model.thickness = model.profile_slope = model.profile_form =
      model.helix_slope = model.helix_form = base;

  const std::vector<std::pair<std::string, DeviationDistribution*>> simple_groups = {
      {"eccentricity", &model.eccentricity},
      {"pitch", &model.pitch},
      {"thickness", &model.thickness}};
  for (const auto& [key, law] : simple_groups) {
    if (const auto group = deviations.get_map(key, child_keys("deviations." + key))) {
      *law = read_law(*group, base, warnings);
    }
  }

  const ParameterRange& points = deviation_ranges().at("deviations.control_points");
  model.profile_form_control_points =
      static_cast<int>(number_default("deviations.profile.control_points"));
  model.helix_form_control_points =
      static_cast<int>(number_default("deviations.helix.control_points"));
  if (const auto profile = deviations.get_map("profile", child_keys("deviations.profile"))) {
    model.profile_slope = model.profile_form = read_law(*profile, base, warnings);
    model.profile_form_control_points =
        static_cast<int>(get_ranged_int(*profile, "control_points", points, warnings)
                             .value_or(model.profile_form_control_points));
  }
  if (const auto helix = deviations.get_map("helix", child_keys("deviations.helix"))) {
    model.helix_slope = model.helix_form = read_law(*helix, base, warnings);
    model.helix_form_control_points =
        static_cast<int>(get_ranged_int(*helix, "control_points", points, warnings)
                             .value_or(model.helix_form_control_points));
  }

  if (const auto expression = deviations.find("normal_um")) {
    const std::string expected =
        "a muParser expression of L, z, tooth, side giving µm, e.g. \"2*sin(2*_pi*L/5)\"";
    if (!expression->is_scalar()) throw expression->error(expected);
    const std::string text = expression->node().Scalar();
    if (text.find_first_not_of(" \t\r\n") == std::string::npos) throw expression->error(expected);
    try {
      const NormalExpression compiled(text);  // compile now: errors point into the file
    } catch (const ExpressionError& e) {
      throw expression->error(expected + " (muParser: " + shown_input(e.what(), 2 * kShownChars) +
                              " at character " + std::to_string(e.position() + 1) + ")");
    }
    *normal_expression_um = text;
  }
  return model;
}

// Resolves the scenario's tolerances for its gear (as every command does later) and checks
// that the runout tolerance F_r can hold what the profile and helix tolerances alone produce:
// the gear sampler shrinks pitch deviations to fit F_r but not profile and helix shapes, so a
// gear whose shapes alone break F_r stops a run. The check draws the run's first
// kRunoutCheckGears gears (the scenario's seed and laws) and rejects F_r when one of them does
// not fit; when gears with every profile and helix deviation at its tolerance (the largest any
// law draws) do not fit, it warns that a longer run may meet such a gear.
void check_tolerances(Scenario& scenario, const YamlMap& gear_map,
                      const std::optional<YamlMap>& tolerances) {
  const InvoluteGear gear(scenario.gear);
  ToleranceSet set;
  std::string key;
  try {
    set = resolve_tolerances(scenario.tolerances, gear);
  } catch (const ToleranceError& e) {
    const InputLocation where = tolerance_place(gear_map, tolerances, std::nullopt, &key);
    throw InputError(where, key + ": " + e.what());
  }
  if (!set.get_um(ToleranceKind::kRunout) || !scenario.deviations.random) return;
  const GearSampler sampler(gear, set, scenario.deviations, scenario.seed);
  for (int k = 0; k < kRunoutCheckGears; ++k) {
    try {
      sampler.draw(k);
    } catch (const ToleranceError& e) {
      const InputLocation where =
          tolerance_place(gear_map, tolerances, ToleranceKind::kRunout, &key);
      throw InputError(where, key + ": " + e.what() + " (gear " + std::to_string(k) +
                                  " of the run; every command rejects this scenario)");
    }
  }
  DeviationModel worst = scenario.deviations;
  for (DeviationDistribution* law :
       {&worst.profile_slope, &worst.profile_form, &worst.helix_slope, &worst.helix_form}) {
    law->law = DeviationDistribution::Law::kAtTolerance;
  }
  const GearSampler worst_sampler(gear, set, worst, scenario.seed);
  for (int k = 0; k < kRunoutCheckGears; ++k) {
    try {
      worst_sampler.draw(k);
    } catch (const ToleranceError& e) {
      const InputLocation where =
          tolerance_place(gear_map, tolerances, ToleranceKind::kRunout, &key);
      scenario.warnings.push_back(
          InputError(where, key +
                                ": F_r leaves little room: with profile and helix deviations "
                                "at their tolerances, " +
                                e.what() + "; a run may stop at such a gear")
              .what());
      break;
    }
  }
}

}  // namespace gearmc
