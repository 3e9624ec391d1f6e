// Reading the `effects:` section of a scenario into an EffectChain (see effect_config.h).
#include "engine/effects/effect_config.h"

#include <optional>
#include <utility>

#include "engine/effects/artefact_form.h"
#include "engine/effects/effects.h"
#include "engine/effects/empirical_effect.h"
#include "engine/effects/probe_dynamics.h"
#include "engine/effects/probe_lobing.h"
#include "engine/effects/rotary_table.h"
#include "engine/effects/scale_resolution.h"
#include "engine/effects/stylus_bending.h"
#include "engine/effects/warmup_straightness.h"
#include "engine/schema/parameter_ranges.h"
#include "engine/schema/scenario_keys.h"

namespace gearmc {
namespace {

// The table key of `key` in the effect map `map` (its path is "effects.<effect>", or
// "effects.probe_lobing.harmonics[i]" for a harmonic): "effects.<effect>.<key>", without the
// list index.
std::string key_path(const YamlMap& map, const std::string& key) {
  std::string path = map.path();
  const std::size_t bracket = path.find('[');
  if (bracket != std::string::npos) path.erase(bracket, path.find(']', bracket) - bracket + 1);
  // The section may be read on its own (a document whose root is the effects map).
  if (path.rfind("effects.", 0) != 0) path = "effects." + path;
  return path + "." + key;
}

// The plausible range of parameter `key` of the effect whose map is `map`.
const ParameterRange& range_of(const YamlMap& map, const std::string& key) {
  return effect_ranges().at(key_path(map, key));
}

// The key table's default of number `key` in `map`.
double default_of(const YamlMap& map, const std::string& key) {
  return number_default(key_path(map, key));
}

// The key table's integer `key` in `map` within its bounds, or its default.
std::int64_t integer_of(const YamlMap& map, const std::string& key) {
  const ScenarioKey& k = scenario_key(key_path(map, key));
  return map.get_int(key, k.integer_min, k.integer_max)
      .value_or(static_cast<std::int64_t>(number_default(k.key)));
}

// A parameter: a number, or {uniform: [lo, hi]}, or {normal: [mean, sd]}; absent = the key
// table's default.
// Numbers, bounds and the mean lie within the parameter's valid range, a standard deviation
// within half its width (else an InputError); outside the usual range they give a warning.
EffectParameter read_parameter(const YamlMap& map, const std::string& key,
                               InputWarnings* warnings) {
  const ParameterRange& range = range_of(map, key);
  EffectParameter p;
  p.name = key;
  p.value = default_of(map, key);
  const auto value = map.find(key);
  if (!value) return p;
  if (!value->is_map()) {
    p.value = read_ranged(*value, range, warnings);
    return p;
  }
  const YamlMap law = value->as_map({"uniform", "normal"});
  if (law.entries().size() != 1) {
    throw value->error("a number, {uniform: [lo, hi]} or {normal: [mean, sd]}");
  }
  const YamlValue& spec = law.entries().front().value;
  const std::vector<YamlValue> pair = spec.as_sequence();
  if (pair.size() != 2) throw spec.error("two numbers [a, b]");
  if (law.entries().front().key == "uniform") {
    const double a = read_ranged(pair[0], range, warnings);
    const double b = read_ranged(pair[1], range, warnings);
    if (!(a <= b)) throw spec.error("[lo, hi] with lo <= hi");
    p.law = EffectParameter::Law::kUniform;
    p.lo = a;
    p.hi = b;
  } else {
    const double a = read_ranged(pair[0], range, warnings);
    const double half_width = 0.5 * (range.valid.max - range.valid.min);
    const double b = pair[1].as_number(
        NumberRange::closed(0.0, half_width),
        "a standard deviation in " + range.unit + ", at most half the width of the valid range");
    p.law = EffectParameter::Law::kNormal;
    p.value = a;
    p.spread = b;
  }
  return p;
}

// `from_probe_model:` — p0 and the harmonics of orders 3, 6, 9, … computed by the CVODE
// touch-trigger probe model (probe_dynamics.h) for the given stylus and approach speed.
void read_probe_model(const YamlMap& m, EffectParameter* pretravel, std::vector<int>* orders,
                      std::vector<EffectParameter>* harmonic_parameters, InputWarnings* warnings) {
  const auto number = [&](const std::string& key) {
    return get_ranged(m, key, range_of(m, key), warnings).value_or(default_of(m, key));
  };
  ProbeDynamicsParameters probe;
  probe.stylus_length_mm = number("stylus_length_mm");
  probe.stem_diameter_mm = number("stem_diameter_mm");
  probe.ball_diameter_mm = number("ball_diameter_mm");
  const std::string material_key = key_path(m, "stem_material");
  const std::string material = m.get_choice("stem_material", key_choices(material_key))
                                   .value_or(choice_default(material_key));
  probe.stem_material = material == "steel"      ? probe_materials::kSteel
                        : material == "zirconia" ? probe_materials::kZirconia
                                                 : probe_materials::kTungstenCarbide;
  probe.trigger_latency_s = number("trigger_latency_s");
  const double speed = number("speed_mm_s");
  const int directions = static_cast<int>(integer_of(m, "directions"));
  const int max_order = static_cast<int>(integer_of(m, "max_order"));
  if (2 * max_order >= directions) {
    throw m.require("max_order", "").error("an order below half the number of directions");
  }
  LobingHarmonics h;
  try {
    h = ProbeDynamics(probe).lobing_harmonics(directions, speed, max_order);
  } catch (const std::exception& e) {
    throw InputError(m.location(), m.path() + ": the probe model failed: " + e.what());
  }
  pretravel->value = h.p0_um;
  for (const LobingHarmonic& k : h.harmonics) {
    if (k.order % 3 != 0) continue;  // the three-leg seat: only orders 3, 6, 9, … (2π/3)
    orders->push_back(k.order);
    EffectParameter a, phase;
    a.name = "amplitude_" + std::to_string(k.order) + "_um";
    a.unit = "µm";
    a.value = k.amplitude_um;
    phase.name = "phase_" + std::to_string(k.order) + "_deg";
    phase.unit = "deg";
    phase.value = k.phase_deg;
    harmonic_parameters->push_back(a);
    harmonic_parameters->push_back(phase);
  }
}

std::unique_ptr<MeasurementEffect> read_probe_lobing(const YamlMap& m, InputWarnings* warnings) {
  EffectParameter pretravel = read_parameter(m, "pretravel_um", warnings);
  std::vector<int> orders;
  std::vector<EffectParameter> harmonic_parameters;
  if (const auto model =
          m.get_map("from_probe_model", child_keys(key_path(m, "from_probe_model")))) {
    for (const char* key : {"pretravel_um", "harmonics"}) {
      if (m.has(key)) {
        throw m.find(key)->error("nothing: from_probe_model gives p0 and the harmonics");
      }
    }
    read_probe_model(*model, &pretravel, &orders, &harmonic_parameters, warnings);
  }
  if (const auto list = m.find("harmonics")) {
    for (const YamlValue& item : list->as_sequence()) {
      const YamlMap h = item.as_map(child_keys(key_path(m, "harmonics")));
      const ScenarioKey& order_key = scenario_key(key_path(h, "order"));
      const int order =
          static_cast<int>(h.require_int("order", order_key.integer_min, order_key.integer_max));
      for (int existing : orders) {
        if (existing == order) throw h.require("order", "").error("an order not listed before");
      }
      orders.push_back(order);
      EffectParameter a = read_parameter(h, "amplitude_um", warnings);
      a.name = "amplitude_" + std::to_string(order) + "_um";
      a.unit = "µm";
      EffectParameter phase = read_parameter(h, "phase_deg", warnings);
      phase.name = "phase_" + std::to_string(order) + "_deg";
      phase.unit = "deg";
      harmonic_parameters.push_back(std::move(a));
      harmonic_parameters.push_back(std::move(phase));
    }
  }
  pretravel.unit = "µm";
  EffectParameter repeatability = read_parameter(m, "repeatability_um", warnings);
  repeatability.unit = "µm";
  ProbeQualificationSpec q;
  const auto choice = [&](const std::string& key) {
    const std::string path = key_path(m, key);
    return m.get_choice(key, key_choices(path)).value_or(choice_default(path));
  };
  const std::string s = choice("calibration");
  q.strategy = s == "none"             ? ProbeQualification::kNone
               : s == "mean6"          ? ProbeQualification::kMean6
               : s == "six_directions" ? ProbeQualification::kSixDirections
                                       : ProbeQualification::kPerDirection;
  q.use = choice("six_directions_use") == "nearest" ? SixDirectionUse::kNearest
                                                    : SixDirectionUse::kInterpolated;
  q.start_deg =
      get_ranged(m, "calibration_start_deg", range_of(m, "calibration_start_deg"), warnings)
          .value_or(default_of(m, "calibration_start_deg"));
  return std::make_unique<ProbeLobingEffect>(std::move(pretravel), std::move(orders),
                                             std::move(harmonic_parameters),
                                             std::move(repeatability), q);
}

// `empirical:` — axis, basis, the Legendre range [from, to] and the terms (each order once;
// b_um only for the harmonic basis).
std::unique_ptr<MeasurementEffect> read_empirical(const YamlMap& m, InputWarnings* warnings) {
  const auto choice = [&](const std::string& key) {
    const std::string path = key_path(m, key);
    const auto value = m.get_choice(key, key_choices(path));
    if (!value) {
      std::string expected;
      for (const std::string& c : key_choices(path)) expected += (expected.empty() ? "" : ", ") + c;
      throw m.missing(key, "one of " + expected);
    }
    return *value;
  };
  const EmpiricalAxis axis = parse_empirical_axis(choice("axis"));
  const EmpiricalBasis basis =
      choice("basis") == "legendre" ? EmpiricalBasis::kLegendre : EmpiricalBasis::kHarmonic;
  const double from =
      get_ranged(m, "from", range_of(m, "from"), warnings).value_or(default_of(m, "from"));
  const double to = get_ranged(m, "to", range_of(m, "to"), warnings).value_or(default_of(m, "to"));
  if (basis == EmpiricalBasis::kLegendre && !(to > from)) {
    const auto at = m.find("to") ? m.find("to") : m.find("from");
    if (!at) throw m.missing("to", "a range with from < to for the legendre basis");
    throw at->error("a range with from < to for the legendre basis");
  }
  std::vector<int> orders;
  std::vector<EffectParameter> parameters;
  if (const auto list = m.find("terms")) {
    for (const YamlValue& item : list->as_sequence()) {
      const YamlMap t = item.as_map(child_keys(key_path(m, "terms")));
      const ScenarioKey& order_key = scenario_key(key_path(t, "order"));
      const int order =
          static_cast<int>(t.require_int("order", order_key.integer_min, order_key.integer_max));
      for (int existing : orders) {
        if (existing == order) throw t.require("order", "").error("an order not listed before");
      }
      if (basis == EmpiricalBasis::kLegendre && t.has("b_um")) {
        throw t.find("b_um")->error(
            "nothing: the legendre basis has one coefficient a_um per order");
      }
      orders.push_back(order);
      EffectParameter a = read_parameter(t, "a_um", warnings);
      a.name = "a_" + std::to_string(order) + "_um";
      a.unit = "µm";
      parameters.push_back(std::move(a));
      if (basis == EmpiricalBasis::kHarmonic) {
        EffectParameter b = read_parameter(t, "b_um", warnings);
        b.name = "b_" + std::to_string(order) + "_um";
        b.unit = "µm";
        parameters.push_back(std::move(b));
      }
    }
  }
  return std::make_unique<EmpiricalEffect>(axis, basis, from, to, std::move(orders),
                                           std::move(parameters));
}

// `artefact_form:` — the eight form terms and the two evaluation ranges (required: the form's
// coordinates are normalised on them; each range from < to).
std::unique_ptr<MeasurementEffect> read_artefact_form(const YamlMap& m, InputWarnings* warnings) {
  std::vector<EffectParameter> parameters;
  for (const std::string& key : ArtefactFormEffect::parameter_names()) {
    parameters.push_back(read_parameter(m, key, warnings));
  }
  // Every range value is range-checked before a missing one is reported (the first error is the
  // value that is wrong, not its absent neighbour).
  const std::vector<std::pair<std::string, std::string>> keys = {
      {"profile_from_mm", "the roll length (mm) where the profile range starts"},
      {"profile_to_mm", "the roll length (mm) where the profile range ends"},
      {"face_from_mm", "the face position z (mm) where the helix range starts"},
      {"face_to_mm", "the face position z (mm) where the helix range ends"}};
  std::vector<std::optional<double>> values;
  for (const auto& [key, what] : keys) {
    values.push_back(get_ranged(m, key, range_of(m, key), warnings));
  }
  for (std::size_t k = 0; k < keys.size(); ++k) {
    if (!values[k]) throw m.missing(keys[k].first, keys[k].second);
  }
  FormRanges r{*values[0], *values[1], *values[2], *values[3]};
  if (!(r.profile_to_mm > r.profile_from_mm)) {
    throw m.find("profile_to_mm")->error("a roll length above profile_from_mm");
  }
  if (!(r.face_to_mm > r.face_from_mm)) {
    throw m.find("face_to_mm")->error("a face position above face_from_mm");
  }
  return std::make_unique<ArtefactFormEffect>(std::move(parameters), r);
}

}  // namespace

const std::vector<std::string>& effect_names() {
  static const std::vector<std::string> names = child_keys("effects");
  return names;
}

EffectChain parse_effects(const YamlValue& section, InputWarnings* warnings) {
  EffectChain chain;
  if (section.is_null()) return chain;
  const YamlMap effects = section.as_map(effect_names());
  for (const auto& entry : effects.entries()) {
    const std::string& name = entry.key;
    const YamlMap m = entry.value.as_map(child_keys("effects." + name));
    if (!m.get_bool("enabled").value_or(boolean_default("effects." + name + ".enabled"))) continue;
    std::unique_ptr<MeasurementEffect> effect;
    if (name == "probe_lobing") {
      effect = read_probe_lobing(m, warnings);
    } else if (name == "stylus_radius") {
      effect = std::make_unique<StylusRadiusEffect>(read_parameter(m, "error_um", warnings));
    } else if (name == "tip_form") {
      effect = std::make_unique<TipFormEffect>(static_cast<int>(integer_of(m, "order")),
                                               read_parameter(m, "amplitude_um", warnings),
                                               read_parameter(m, "phase_deg", warnings));
    } else if (name == "scale") {
      effect = std::make_unique<ScaleEffect>(read_parameter(m, "x_ppm", warnings),
                                             read_parameter(m, "y_ppm", warnings),
                                             read_parameter(m, "z_ppm", warnings));
    } else if (name == "squareness") {
      effect = std::make_unique<SquarenessEffect>(read_parameter(m, "xy_urad", warnings),
                                                  read_parameter(m, "xz_urad", warnings),
                                                  read_parameter(m, "yz_urad", warnings));
    } else if (name == "thermal_expansion") {
      effect = std::make_unique<ThermalExpansionEffect>(
          read_parameter(m, "workpiece_delta_t_k", warnings),
          read_parameter(m, "scale_delta_t_k", warnings),
          read_parameter(m, "workpiece_cte_ppm_per_k", warnings),
          read_parameter(m, "scale_cte_ppm_per_k", warnings));
    } else if (name == "drift") {
      effect = std::make_unique<DriftEffect>(read_parameter(m, "x_um", warnings),
                                             read_parameter(m, "y_um", warnings),
                                             read_parameter(m, "z_um", warnings));
    } else if (name == "step_quantization") {
      effect = std::make_unique<StepQuantizationEffect>(
          read_parameter(m, "step_um", warnings),
          get_ranged(m, "approach_mm", range_of(m, "approach_mm"), warnings)
              .value_or(default_of(m, "approach_mm")));
    } else if (name == "eccentricity") {
      effect = std::make_unique<EccentricityEffect>(read_parameter(m, "x_um", warnings),
                                                    read_parameter(m, "y_um", warnings));
    } else if (name == "clocking") {
      effect = std::make_unique<ClockingEffect>(read_parameter(m, "angle_urad", warnings));
    } else if (name == "probe_warmup") {
      effect = std::make_unique<ProbeWarmupEffect>(
          read_parameter(m, "change_um", warnings),
          get_ranged(m, "time_constant", range_of(m, "time_constant"), warnings)
              .value_or(default_of(m, "time_constant")));
    } else if (name == "straightness") {
      effect = std::make_unique<StraightnessEffect>(
          read_parameter(m, "xy_um", warnings), read_parameter(m, "xz_um", warnings),
          read_parameter(m, "yx_um", warnings), read_parameter(m, "yz_um", warnings),
          get_ranged(m, "length_mm", range_of(m, "length_mm"), warnings)
              .value_or(default_of(m, "length_mm")));
    } else if (name == "empirical") {
      effect = read_empirical(m, warnings);
    } else if (name == "rotary_table") {
      std::vector<EffectParameter> parameters;
      for (const std::string& key : RotaryTableEffect::parameter_names()) {
        parameters.push_back(read_parameter(m, key, warnings));
      }
      effect = std::make_unique<RotaryTableEffect>(std::move(parameters));
    } else if (name == "stylus_bending") {
      const std::string axis =
          m.get_choice("stylus_axis", key_choices(key_path(m, "stylus_axis"))).value_or("z");
      effect = std::make_unique<StylusBendingEffect>(
          read_parameter(m, "deflection_um", warnings),
          axis == "x" ? Eigen::Vector3d::UnitX()
                      : (axis == "y" ? Eigen::Vector3d::UnitY() : Eigen::Vector3d::UnitZ()));
    } else if (name == "artefact_form") {
      effect = read_artefact_form(m, warnings);
    } else if (name == "scale_resolution") {
      effect = std::make_unique<ScaleResolutionEffect>(read_parameter(m, "x_um", warnings),
                                                       read_parameter(m, "y_um", warnings),
                                                       read_parameter(m, "z_um", warnings));
    } else {
      effect = std::make_unique<NoiseEffect>(read_parameter(m, "sigma_um", warnings));
    }
    chain.add(std::move(effect));
  }
  return chain;
}

}  // namespace gearmc
