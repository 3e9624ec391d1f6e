// Reading the `effects:` section of a scenario into an EffectChain (see effect_config.h).
#include "engine/effects/effect_config.h"

#include <numbers>

#include "engine/effects/effects.h"
#include "engine/effects/probe_dynamics.h"
#include "engine/effects/probe_lobing.h"
#include "engine/io/parameter_ranges.h"

namespace gearmc {
namespace {

// The plausible range of parameter `key` of the effect whose map is `map` (its path is
// "effects.<effect>", or "effects.probe_lobing.harmonics[i]" for a harmonic).
const ParameterRange& range_of(const YamlMap& map, const std::string& key) {
  std::string path = map.path();
  const std::size_t bracket = path.find('[');
  if (bracket != std::string::npos) path.erase(bracket, path.find(']', bracket) - bracket + 1);
  // The section may be read on its own (a document whose root is the effects map).
  if (path.rfind("effects.", 0) != 0) path = "effects." + path;
  return effect_ranges().at(path + "." + key);
}

// A parameter: a number, or {uniform: [lo, hi]}, or {normal: [mean, sd]}; absent = `fallback`.
// Numbers, bounds and the mean lie within the parameter's valid range, a standard deviation
// within half its width (else an InputError); outside the usual range they give a warning.
EffectParameter read_parameter(const YamlMap& map, const std::string& key, double fallback,
                               InputWarnings* warnings) {
  const ParameterRange& range = range_of(map, key);
  EffectParameter p;
  p.name = key;
  p.value = fallback;
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

std::vector<std::string> with_enabled(std::vector<std::string> keys) {
  keys.insert(keys.begin(), "enabled");
  return keys;
}

// `from_probe_model:` — p0 and the harmonics of orders 3, 6, 9, … computed by the CVODE
// touch-trigger probe model (probe_dynamics.h) for the given stylus and approach speed.
void read_probe_model(const YamlMap& m, EffectParameter* pretravel, std::vector<int>* orders,
                      std::vector<EffectParameter>* harmonic_parameters, InputWarnings* warnings) {
  const auto number = [&](const std::string& key) {
    return get_ranged(m, key, range_of(m, key), warnings);
  };
  ProbeDynamicsParameters probe;
  probe.stylus_length_mm = number("stylus_length_mm").value_or(probe.stylus_length_mm);
  probe.stem_diameter_mm = number("stem_diameter_mm").value_or(probe.stem_diameter_mm);
  probe.ball_diameter_mm = number("ball_diameter_mm").value_or(probe.ball_diameter_mm);
  if (const auto material =
          m.get_choice("stem_material", {"tungsten_carbide", "steel", "zirconia"})) {
    probe.stem_material = *material == "steel"      ? probe_materials::kSteel
                          : *material == "zirconia" ? probe_materials::kZirconia
                                                    : probe_materials::kTungstenCarbide;
  }
  probe.trigger_latency_s = number("trigger_latency_s").value_or(probe.trigger_latency_s);
  const double speed = number("speed_mm_s").value_or(2.0);
  const int directions = static_cast<int>(m.get_int("directions", 12, 720).value_or(72));
  const int max_order = static_cast<int>(m.get_int("max_order", 3, 12).value_or(9));
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
  for (const PretravelHarmonic& k : h.harmonics) {
    if (k.order % 3 != 0) continue;  // the three-leg seat: only orders 3, 6, 9, … (2π/3)
    orders->push_back(k.order);
    EffectParameter a, phase;
    a.name = "amplitude_" + std::to_string(k.order) + "_um";
    a.unit = "µm";
    a.value = k.amplitude_um;
    phase.name = "phase_" + std::to_string(k.order) + "_deg";
    phase.unit = "deg";
    phase.value = k.phase_rad * 180.0 / std::numbers::pi;
    harmonic_parameters->push_back(a);
    harmonic_parameters->push_back(phase);
  }
}

std::unique_ptr<MeasurementEffect> read_probe_lobing(const YamlMap& m, InputWarnings* warnings) {
  EffectParameter pretravel = read_parameter(m, "pretravel_um", 0.0, warnings);
  std::vector<int> orders;
  std::vector<EffectParameter> harmonic_parameters;
  if (const auto model =
          m.get_map("from_probe_model",
                    {"stylus_length_mm", "stem_diameter_mm", "ball_diameter_mm", "stem_material",
                     "trigger_latency_s", "speed_mm_s", "directions", "max_order"})) {
    for (const char* key : {"pretravel_um", "harmonics"}) {
      if (m.has(key)) {
        throw m.find(key)->error("nothing: from_probe_model gives p0 and the harmonics");
      }
    }
    read_probe_model(*model, &pretravel, &orders, &harmonic_parameters, warnings);
  }
  if (const auto list = m.find("harmonics")) {
    for (const YamlValue& item : list->as_sequence()) {
      const YamlMap h = item.as_map({"order", "amplitude_um", "phase_deg"});
      const int order = static_cast<int>(h.require_int("order", 1, 36));
      for (int existing : orders) {
        if (existing == order) throw h.require("order", "").error("an order not listed before");
      }
      orders.push_back(order);
      EffectParameter a = read_parameter(h, "amplitude_um", 0.0, warnings);
      a.name = "amplitude_" + std::to_string(order) + "_um";
      a.unit = "µm";
      EffectParameter phase = read_parameter(h, "phase_deg", 0.0, warnings);
      phase.name = "phase_" + std::to_string(order) + "_deg";
      phase.unit = "deg";
      harmonic_parameters.push_back(std::move(a));
      harmonic_parameters.push_back(std::move(phase));
    }
  }
  pretravel.unit = "µm";
  EffectParameter repeatability = read_parameter(m, "repeatability_um", 0.0, warnings);
  repeatability.unit = "µm";
  ProbeQualificationSpec q;
  if (const auto s =
          m.get_choice("calibration", {"none", "mean6", "six_directions", "per_direction"})) {
    q.strategy = *s == "none"             ? ProbeQualification::kNone
                 : *s == "mean6"          ? ProbeQualification::kMean6
                 : *s == "six_directions" ? ProbeQualification::kSixDirections
                                          : ProbeQualification::kPerDirection;
  }
  if (const auto u = m.get_choice("six_directions_use", {"nearest", "interpolated"})) {
    q.use = *u == "nearest" ? SixDirectionUse::kNearest : SixDirectionUse::kInterpolated;
  }
  q.start_deg =
      get_ranged(m, "calibration_start_deg", range_of(m, "calibration_start_deg"), warnings)
          .value_or(90.0);
  return std::make_unique<ProbeLobingEffect>(std::move(pretravel), std::move(orders),
                                             std::move(harmonic_parameters),
                                             std::move(repeatability), q);
}

}  // namespace

const std::vector<std::string>& effect_names() {
  static const std::vector<std::string> names = {
      "probe_lobing",      "stylus_radius", "tip_form",          "scale",        "squareness",
      "thermal_expansion", "drift",         "step_quantization", "eccentricity", "noise"};
  return names;
}

EffectChain parse_effects(const YamlValue& section, InputWarnings* warnings) {
  EffectChain chain;
  if (section.is_null()) return chain;
  const YamlMap effects = section.as_map(effect_names());
  for (const auto& entry : effects.entries()) {
    const std::string& name = entry.key;
    std::vector<std::string> keys;
    if (name == "probe_lobing") {
      keys = {"pretravel_um", "harmonics",          "from_probe_model",     "repeatability_um",
              "calibration",  "six_directions_use", "calibration_start_deg"};
    } else if (name == "stylus_radius") {
      keys = {"error_um"};
    } else if (name == "tip_form") {
      keys = {"order", "amplitude_um", "phase_deg"};
    } else if (name == "scale") {
      keys = {"x_ppm", "y_ppm", "z_ppm"};
    } else if (name == "squareness") {
      keys = {"xy_urad", "xz_urad", "yz_urad"};
    } else if (name == "thermal_expansion") {
      keys = {"workpiece_delta_t_k", "scale_delta_t_k", "workpiece_cte_ppm_per_k",
              "scale_cte_ppm_per_k"};
    } else if (name == "drift") {
      keys = {"x_um", "y_um", "z_um"};
    } else if (name == "step_quantization") {
      keys = {"step_um", "approach_mm"};
    } else if (name == "eccentricity") {
      keys = {"x_um", "y_um"};
    } else {  // noise
      keys = {"sigma_um"};
    }
    const YamlMap m = entry.value.as_map(with_enabled(keys));
    if (!m.get_bool("enabled").value_or(true)) continue;
    std::unique_ptr<MeasurementEffect> effect;
    if (name == "probe_lobing") {
      effect = read_probe_lobing(m, warnings);
    } else if (name == "stylus_radius") {
      effect = std::make_unique<StylusRadiusEffect>(read_parameter(m, "error_um", 0.0, warnings));
    } else if (name == "tip_form") {
      effect =
          std::make_unique<TipFormEffect>(static_cast<int>(m.get_int("order", 1, 36).value_or(2)),
                                          read_parameter(m, "amplitude_um", 0.0, warnings),
                                          read_parameter(m, "phase_deg", 0.0, warnings));
    } else if (name == "scale") {
      effect = std::make_unique<ScaleEffect>(read_parameter(m, "x_ppm", 0.0, warnings),
                                             read_parameter(m, "y_ppm", 0.0, warnings),
                                             read_parameter(m, "z_ppm", 0.0, warnings));
    } else if (name == "squareness") {
      effect = std::make_unique<SquarenessEffect>(read_parameter(m, "xy_urad", 0.0, warnings),
                                                  read_parameter(m, "xz_urad", 0.0, warnings),
                                                  read_parameter(m, "yz_urad", 0.0, warnings));
    } else if (name == "thermal_expansion") {
      effect = std::make_unique<ThermalExpansionEffect>(
          read_parameter(m, "workpiece_delta_t_k", 0.0, warnings),
          read_parameter(m, "scale_delta_t_k", 0.0, warnings),
          read_parameter(m, "workpiece_cte_ppm_per_k", 11.5, warnings),
          read_parameter(m, "scale_cte_ppm_per_k", 0.0, warnings));
    } else if (name == "drift") {
      effect = std::make_unique<DriftEffect>(read_parameter(m, "x_um", 0.0, warnings),
                                             read_parameter(m, "y_um", 0.0, warnings),
                                             read_parameter(m, "z_um", 0.0, warnings));
    } else if (name == "step_quantization") {
      effect = std::make_unique<StepQuantizationEffect>(
          read_parameter(m, "step_um", 0.0, warnings),
          get_ranged(m, "approach_mm", range_of(m, "approach_mm"), warnings).value_or(2.0));
    } else if (name == "eccentricity") {
      effect = std::make_unique<EccentricityEffect>(read_parameter(m, "x_um", 0.0, warnings),
                                                    read_parameter(m, "y_um", 0.0, warnings));
    } else {
      effect = std::make_unique<NoiseEffect>(read_parameter(m, "sigma_um", 0.0, warnings));
    }
    chain.add(std::move(effect));
  }
  return chain;
}

}  // namespace gearmc
