// The plausible-range tables of scenario and readings numbers and the checks that use them
// (see parameter_ranges.h). Typical values quoted in the reasons are the README's "Measurement
// effects" table, ISO 1328-1:2013's scope (z 5–1000, d 5–15 000 mm, m_n 0.5–70 mm,
// b 4–1 200 mm) and ISO 53 (basic rack). Valid ranges are wide (a value beyond them is not a
// gear or not a CMM); usual ranges are what such gears and machines have.
#include "engine/schema/parameter_ranges.h"

#include <charconv>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <utility>

#include "core/constants.h"
#include "core/number_text.h"

namespace gearmc {
namespace {

NumberRange closed(double lo, double hi) { return NumberRange::closed(lo, hi); }
NumberRange above(double lo, double hi) { return {lo, hi, false, true}; }  // (lo, hi]

std::string with_unit(double value, const std::string& unit) {
  if (unit.empty()) return shortest_text(value);
  return shortest_text(value) + (unit == "%" ? "" : " ") + unit;
}

}  // namespace

const ParameterRange& RangeTable::at(const std::string& key) const {
  for (const ParameterRange& entry : entries) {
    if (entry.key == key) return entry;
  }
  throw std::logic_error("no plausible range for '" + key + "' in the " + section + " table");
}

const RangeTable& gear_ranges() {
  static const RangeTable table = [] {
    RangeTable t{
        "gear",
        {{"gear.teeth", "", closed(5, 1000), 6, 500, "ISO 1328-1:2013 scope z 5–1000", "", true},
         {"gear.module_mm", "mm", closed(0.01, 200), 0.2, 70,
          "ISO 1328-1:2013 scope m_n 0.5–70 mm; fine-pitch gears down to 0.2 mm",
          "a module in inches or in µm?"},
         {"gear.pressure_angle_deg", "deg", NumberRange{5, 45, true, false}, 14.5, 30,
          "ISO 53: 20°; 14.5°, 25° and 30° are also made",
          "a value below 1 is an angle in radians (0.349 rad = 20°): give degrees"},
         {"gear.helix_angle_deg", "deg", NumberRange{0, 45, true, false}, 0, 35,
          "ISO 21771: beta at the reference diameter; helical gears are made with 8°–35°, "
          "double-helical up to 45°",
          "a value below 1 is an angle in radians (0.262 rad = 15°): give degrees"},
         {"gear.profile_shift", "", closed(-1.5, 3), -1, 1.5,
          "profile shift coefficients in practice -1…+1.5 (P1: 0.90116)", ""},
         {"gear.face_width_mm", "mm", closed(0.01, 5000), 1, 1200,
          "ISO 1328-1:2013 scope b 4–1200 mm", "a width in m or in µm?"},
         {"gear.tip_diameter_mm", "mm", above(0, 100000), 1, 16000,
          "ISO 1328-1:2013 scope d 5–15000 mm", ""},
         {"gear.root_diameter_mm", "mm", above(0, 100000), 1, 16000,
          "ISO 1328-1:2013 scope d 5–15000 mm", ""},
         {"gear.form_diameter_mm", "mm", above(0, 100000), 1, 16000,
          "ISO 1328-1:2013 scope d 5–15000 mm", ""},
         {"gear.basic_rack.addendum", "modules", above(0, 3), 0.8, 1.25,
          "ISO 53 addendum 1.0 m; stub teeth 0.8 m", ""},
         {"gear.basic_rack.dedendum", "modules", above(0, 3), 1.0, 1.4,
          "ISO 53 dedendum 1.25 m (profiles A–D 1.25–1.4 m)", ""},
         {"gear.basic_rack.root_radius", "modules", closed(0, 1), 0, 0.5,
          "ISO 53 root radius 0.25–0.39 m", ""},
         {"gear.modifications.profile_crowning_um", "µm", closed(0, 1000), 0, 30,
          "profile crownings of a few µm (design practice, recalled)",
          "a value in mm? (0.005 mm = 5 µm)", false, SlipSide::kBelow},
         {"gear.modifications.helix_crowning_um", "µm", closed(0, 1000), 0, 50,
          "helix crownings of a few to tens of µm (design practice, recalled)",
          "a value in mm? (0.01 mm = 10 µm)", false, SlipSide::kBelow},
         {"gear.modifications.helix_slope_um", "µm", closed(-1000, 1000), -50, 50,
          "helix slope modifications of tens of µm over the face (design practice, recalled)",
          "a value in mm? (0.01 mm = 10 µm)", false, SlipSide::kBelow}}};
    // The three reliefs: an amount and a length each.
    for (const auto& [name, length_why] :
         {std::pair<std::string, std::string>{"tip_relief", "a fraction of the active profile"},
          {"root_relief", "a fraction of the active profile"},
          {"end_relief", "a fraction of the face width"}}) {
      const std::string path = "gear.modifications." + name;
      const std::string what = name.substr(0, name.find('_')) + " relief";
      t.entries.push_back({path + ".amount_um", "µm", closed(0, 1000), 1, 100,
                           what + "s of a few to tens of µm are usual (design practice, recalled)",
                           "a value in mm? (0.01 mm = 10 µm)", false, SlipSide::kBelow});
      t.entries.push_back({path + ".length_mm", "mm", above(0, 1000), 0.1, 50, length_why,
                           "a length in µm?", false, SlipSide::kAbove});
    }
    return t;
  }();
  return table;
}

const RangeTable& tolerance_ranges() {
  static const RangeTable table{
      "tolerances",
      {{"tolerances.overrides_um.tolerance", "µm", closed(0.5, 10000), 1, 2000,
        "ISO 1328-1:2013 class 1 (finest) gives >= 1.3 µm, class 11 at d 15000 mm about 1300 µm",
        "a value in mm? (0.02 mm = 20 µm)", false, SlipSide::kBelow},
       {"tolerances.overrides_um.E_Hs", "µm", closed(0, 10000), 1, 2000,
        "GOST 1643-81 least rack shifts are tens to hundreds of µm (P1: 110 µm)",
        "a value in mm? (0.11 mm = 110 µm)", false, SlipSide::kBelow}}};
  return table;
}

const RangeTable& deviation_ranges() {
  static const RangeTable table{
      "deviations",
      {{"deviations.k", "", closed(0.5, 100), 1, 6,
        "tolerance = k sigma; k 2–4 is usual (3: 99.73 % of a normal law inside); below 0.5 "
        "the law is nearly uniform and drawing within tolerance would reject almost every draw",
        ""},
       {"deviations.control_points", "", closed(4, 64), 4, 32,
        "B-spline control points of a form deviation; >= 4 for a cubic", "", true}}};
  return table;
}

const RangeTable& probing_ranges() {
  static const RangeTable table{
      "probing",
      {{"probing.points_along_profile", "", closed(1, 1000), 3, 200,
        "P1: 10; ISO 1328-1 evaluation needs a few points per mm", "", true},
       {"probing.sections_across_face", "", closed(1, 1000), 1, 100, "P1: 5", "", true},
       {"probing.points_per_gear", "", closed(1, 10000000), 1, 1000000,
        "points x sections x teeth x flanks; 10 million points is several GB of results", "", true},
       {"probing.margin_fraction", "", NumberRange{0, 0.5, true, false}, 0, 0.2,
        "P1: 0.05 away from every edge", "a percentage? (5 % is 0.05)", false, SlipSide::kAbove},
       {"stylus.radius_mm", "mm", closed(0.01, 50), 0.05, 5,
        "stylus balls are 0.1–10 mm in diameter (P1: R 0.5 mm)", "a diameter, or µm?", false,
        SlipSide::kAbove},
       {"stylus.shaft_diameter_mm", "mm", above(0, 100), 0.2, 6,
        "stylus stems are 0.2–6 mm in diameter, thinner than their ball", "a radius, or µm?"},
       {"run.gears", "", closed(1, 100000000), 1, 1000000, "P1: 50 gears", "", true},
       {"evaluation.profile_points", "", closed(0, 5000), 0, 1000,
        "gear CMMs scan 100–1000 points per trace; 0 = the probing grid's section", "", true},
       {"evaluation.helix_points", "", closed(0, 5000), 0, 1000,
        "gear CMMs scan 100–1000 points per trace; 0 = the probing grid's column", "", true},
       {"evaluation.profile_sections", "", closed(1, 50), 1, 5,
        "gear CMMs measure the profile at 1–3 heights, rarely more", "", true},
       {"evaluation.helix_sections", "", closed(1, 50), 1, 5,
        "gear CMMs measure the helix at 1–3 diameters, rarely more", "", true},
       {"evaluation.truth_points", "", closed(10, 100000), 50, 5000,
        "the true trace must resolve the form deviations (B-spline spans of a few mm)", "", true},
       {"evaluation.profile_end_fraction", "", closed(0.5, 1.0), 0.9, 1.0,
        "ISO 1328-1:2013: L_α is about 92–95 % of the active profile", "a percentage?", false,
        SlipSide::kAbove},
       {"evaluation.helix_end_exclusion_mm", "mm", closed(0, 1000), 0, 20,
        "ISO 1328-1:2013: the smaller of 5 % b and m_n at each end", "µm instead of mm?", false,
        SlipSide::kAbove},
       {"evaluation.span_teeth", "", closed(1, 1000), 2, 20,
        "spans of 2–10 teeth are usual (k ≈ z/9 + 0.5 at 20°)", "", true},
       {"evaluation.ball_diameter_mm", "mm", above(0, 1000), 0.5, 60,
        "balls of about 1.7 m_n touch near the reference circle", "µm instead of mm?", false,
        SlipSide::kAbove},
       {"evaluation.size_allowances_um.E_sn.upper", "µm", closed(-10000, 10000), -1000, 200,
        "size allowances are tens to hundreds of µm, mostly negative (backlash)",
        "mm instead of µm?", false},
       {"evaluation.size_allowances_um.E_sn.lower", "µm", closed(-10000, 10000), -1000, 200,
        "size allowances are tens to hundreds of µm, mostly negative (backlash)",
        "mm instead of µm?", false},
       {"evaluation.size_allowances_um.E_Wk.upper", "µm", closed(-10000, 10000), -1000, 200,
        "size allowances are tens to hundreds of µm, mostly negative (backlash)",
        "mm instead of µm?", false},
       {"evaluation.size_allowances_um.E_Wk.lower", "µm", closed(-10000, 10000), -1000, 200,
        "size allowances are tens to hundreds of µm, mostly negative (backlash)",
        "mm instead of µm?", false},
       {"evaluation.size_allowances_um.E_MdK.upper", "µm", closed(-10000, 10000), -1000, 200,
        "size allowances are tens to hundreds of µm, mostly negative (backlash)",
        "mm instead of µm?", false},
       {"evaluation.size_allowances_um.E_MdK.lower", "µm", closed(-10000, 10000), -1000, 200,
        "size allowances are tens to hundreds of µm, mostly negative (backlash)",
        "mm instead of µm?", false},
       {"evaluation.profile_cutoff_mm", "mm", above(0, 1000), 0.05, 10,
        "a profile filter keeps form waves of a few mm and removes roughness (cut-offs of "
        "0.08–2.5 mm are the surface-texture series)",
        "µm instead of mm?", false, SlipSide::kAbove},
       {"evaluation.helix_cutoff_mm", "mm", above(0, 1000), 0.05, 25,
        "a helix filter keeps the lead's form over the face width (cut-offs of 0.25–8 mm are "
        "the surface-texture series)",
        "µm instead of mm?", false, SlipSide::kAbove}}};
  return table;
}

const RangeTable& claim_ranges() {
  static const RangeTable table{
      "claims",
      {{"claims.statistic.quantile", "", NumberRange::probability(), 0.00001, 0.99999,
        "a quantile's probability p; P1's claim is at 0.9973 (3σ of a normal law), a lower-tail "
        "claim (with at_least_um) at e.g. 0.025; beyond 0.00001 … 0.99999 the check needs "
        "millions of gears",
        "a percentage? (99.73 % is 0.9973)", false, SlipSide::kAbove},
       {"claims.at_most_um", "µm", closed(-10000, 10000), -100, 100,
        "a limit on a measurement error; CMM errors on gears are a few µm (P1: 4 µm), "
        "10 mm is far beyond any",
        "mm? (4 µm is 4, not 0.004)", false, SlipSide::kBelow},
       {"claims.at_least_um", "µm", closed(-10000, 10000), -100, 100,
        "a limit on a measurement error; CMM errors on gears are a few µm", "mm?", false,
        SlipSide::kBelow},
       {"claims.at_most", "", closed(0, 1000), 0.01, 1,
        "a limit on U/T, the expanded uncertainty over the tolerance interval's width; 0.1 … 0.2 "
        "is usual (the capability limit Q_MP = 2U/T ≤ 30 % is U/T ≤ 0.15)",
        "a percentage? (15 % is 0.15)", false, SlipSide::kAbove},
       {"claims.at_least", "", closed(0, 1000), 0.01, 1, "a limit on U/T", "a percentage?", false,
        SlipSide::kAbove},
       {"claims.confidence", "", NumberRange::probability(), 0.8, 0.9999,
        "the probability that a verdict is right; 0.95 is usual, above 0.9999 needs many gears",
        "a percentage? (95 % is 0.95)", false, SlipSide::kAbove}}};
  return table;
}

const RangeTable& effect_ranges() {
  const std::string lobing =
      "touch-trigger pre-travel: P2 ±0.75 µm lobing, kinematic probes a few µm, TP20 ±0.6–1 µm";
  const std::string angle = "an angle in degrees; beyond ±3600° it is surely not meant";
  static const RangeTable table{
      "effects",
      {{"effects.probe_lobing.pretravel_um", "µm", closed(-1000, 1000), -100, 100, lobing,
        "a value in nm? (1000 nm = 1 µm)", false, SlipSide::kAbove},
       {"effects.probe_lobing.harmonics.amplitude_um", "µm", closed(-1000, 1000), -20, 20, lobing,
        "a value in nm?", false, SlipSide::kAbove},
       {"effects.probe_lobing.harmonics.phase_deg", "deg", closed(-3600, 3600), -360, 360, angle,
        ""},
       {"effects.probe_lobing.repeatability_um", "µm", closed(0, 100), 0, 5,
        "unidirectional repeatability of a probe 0.05–1 µm (P2: 0.07 µm)", "a value in nm?", false,
        SlipSide::kAbove},
       {"effects.probe_lobing.calibration_start_deg", "deg", closed(-3600, 3600), -360, 360, angle,
        ""},
       {"effects.probe_lobing.from_probe_model.stylus_length_mm", "mm", closed(1, 200), 10, 100,
        "styli are 10–100 mm long", ""},
       {"effects.probe_lobing.from_probe_model.stem_diameter_mm", "mm", closed(0.1, 10), 0.3, 5,
        "stylus stems 0.3–5 mm", ""},
       {"effects.probe_lobing.from_probe_model.ball_diameter_mm", "mm", closed(0.1, 20), 0.3, 10,
        "stylus balls 0.3–10 mm", ""},
       {"effects.probe_lobing.from_probe_model.trigger_latency_s", "s", closed(0, 0.1), 0, 0.01,
        "trigger latencies are µs to ms", "a value in ms? (1 ms = 0.001 s)", false,
        SlipSide::kAbove},
       {"effects.probe_lobing.from_probe_model.speed_mm_s", "mm/s", closed(0.01, 100), 0.5, 20,
        "probing speeds 1–10 mm/s", ""},
       {"effects.stylus_radius.error_um", "µm", closed(-100, 100), -5, 5,
        "radius qualification errors 0.1–0.5 µm", "a value in nm?", false, SlipSide::kAbove},
       {"effects.tip_form.amplitude_um", "µm", closed(-100, 100), -5, 5,
        "ruby ball grade 5 sphericity <= 0.13 µm (ISO 3290)", "a value in nm?", false,
        SlipSide::kAbove},
       {"effects.tip_form.phase_deg", "deg", closed(-3600, 3600), -360, 360, angle, ""},
       {"effects.scale.x_ppm", "ppm", closed(-10000, 10000), -100, 100,
        "scale errors 1–5 ppm; 10000 ppm is 1 %", ""},
       {"effects.scale.y_ppm", "ppm", closed(-10000, 10000), -100, 100,
        "scale errors 1–5 ppm; 10000 ppm is 1 %", ""},
       {"effects.scale.z_ppm", "ppm", closed(-10000, 10000), -100, 100,
        "scale errors 1–5 ppm; 10000 ppm is 1 %", ""},
       {"effects.squareness.xy_urad", "µrad", closed(-10000, 10000), -200, 200,
        "squareness errors 5–20 µrad; 10000 µrad is 0.57°", "a value in arc seconds?"},
       {"effects.squareness.xz_urad", "µrad", closed(-10000, 10000), -200, 200,
        "squareness errors 5–20 µrad; 10000 µrad is 0.57°", "a value in arc seconds?"},
       {"effects.squareness.yz_urad", "µrad", closed(-10000, 10000), -200, 200,
        "squareness errors 5–20 µrad; 10000 µrad is 0.57°", "a value in arc seconds?"},
       {"effects.thermal_expansion.workpiece_delta_t_k", "K", closed(-100, 100), -10, 10,
        "ΔT 0.5–2 K off 20 °C (ISO 1)", "a temperature in °C instead of its difference to 20 °C?",
        false, SlipSide::kAbove},
       {"effects.thermal_expansion.scale_delta_t_k", "K", closed(-100, 100), -10, 10,
        "ΔT 0.5–2 K off 20 °C (ISO 1)", "a temperature in °C instead of its difference to 20 °C?",
        false, SlipSide::kAbove},
       {"effects.thermal_expansion.workpiece_cte_ppm_per_k", "ppm/K", closed(0, 300), 0, 30,
        "steel 11.5, aluminium 23, plastics up to about 200 ppm/K", ""},
       {"effects.thermal_expansion.scale_cte_ppm_per_k", "ppm/K", closed(0, 300), 0, 30,
        "glass-ceramic 0, steel 11.5 ppm/K", ""},
       {"effects.drift.x_um", "µm", closed(-1000, 1000), -20, 20, "drift about 1 µm per hour",
        "a value in nm?", false, SlipSide::kAbove},
       {"effects.drift.y_um", "µm", closed(-1000, 1000), -20, 20, "drift about 1 µm per hour",
        "a value in nm?", false, SlipSide::kAbove},
       {"effects.drift.z_um", "µm", closed(-1000, 1000), -20, 20, "drift about 1 µm per hour",
        "a value in nm?", false, SlipSide::kAbove},
       {"effects.step_quantization.step_um", "µm", closed(0, 100), 0, 5,
        "servo interpolation steps 0.05–1 µm", "a value in nm?", false, SlipSide::kAbove},
       {"effects.step_quantization.approach_mm", "mm", above(0, 100), 0.1, 20,
        "approach distances 1–5 mm (default 2 mm)", ""},
       {"effects.eccentricity.x_um", "µm", closed(-1000, 1000), -100, 100,
        "set-up eccentricity a few µm", "a value in nm, or in mm given as µm?"},
       {"effects.eccentricity.y_um", "µm", closed(-1000, 1000), -100, 100,
        "set-up eccentricity a few µm", "a value in nm, or in mm given as µm?"},
       {"effects.clocking.angle_urad", "µrad", closed(-100000, 100000), -200, 200,
        "a datum tooth found off by 1 µm turns P1's gear (r_b 63 mm) by 16 µrad",
        "an angle in arcseconds (1″ = 4.85 µrad) or degrees?"},
       {"effects.noise.sigma_um", "µm", closed(0, 100), 0, 5, "probing noise σ 0.1–0.5 µm",
        "a value in nm? (300 nm = 0.3 µm)", false, SlipSide::kAbove},
       {"effects.probe_warmup.change_um", "µm", closed(-100, 100), -5, 5,
        "probe warm-up changes pre-travel by tenths of a µm to about 1 µm (recalled, unchecked)",
        "a value in nm?", false, SlipSide::kAbove},
       {"effects.probe_warmup.time_constant", "", above(0, 100), 0.02, 10,
        "a fraction of one gear's measurement (0.3: settled after about a third)", ""},
       {"effects.straightness.xy_um", "µm", closed(-1000, 1000), -20, 20,
        "CMM axis straightness 1–5 µm over the travel (recalled, unchecked)", "a value in nm?",
        false, SlipSide::kAbove},
       {"effects.straightness.xz_um", "µm", closed(-1000, 1000), -20, 20,
        "CMM axis straightness 1–5 µm over the travel (recalled, unchecked)", "a value in nm?",
        false, SlipSide::kAbove},
       {"effects.straightness.yx_um", "µm", closed(-1000, 1000), -20, 20,
        "CMM axis straightness 1–5 µm over the travel (recalled, unchecked)", "a value in nm?",
        false, SlipSide::kAbove},
       {"effects.straightness.yz_um", "µm", closed(-1000, 1000), -20, 20,
        "CMM axis straightness 1–5 µm over the travel (recalled, unchecked)", "a value in nm?",
        false, SlipSide::kAbove},
       {"effects.straightness.length_mm", "mm", above(0, 10000), 10, 2000,
        "the travel the bow is given at, e.g. the gear's diameter or the axis's length", ""},
       {"effects.artefact_form.left_profile_2_um", "µm", closed(-1000, 1000), -10, 10,
        "a master gear's form terms 0.2–2 µm (recalled, unchecked)", "a value in nm?", false,
        SlipSide::kAbove},
       {"effects.artefact_form.left_profile_3_um", "µm", closed(-1000, 1000), -10, 10,
        "a master gear's form terms 0.2–2 µm (recalled, unchecked)", "a value in nm?", false,
        SlipSide::kAbove},
       {"effects.artefact_form.left_helix_2_um", "µm", closed(-1000, 1000), -10, 10,
        "a master gear's form terms 0.2–2 µm (recalled, unchecked)", "a value in nm?", false,
        SlipSide::kAbove},
       {"effects.artefact_form.left_helix_3_um", "µm", closed(-1000, 1000), -10, 10,
        "a master gear's form terms 0.2–2 µm (recalled, unchecked)", "a value in nm?", false,
        SlipSide::kAbove},
       {"effects.artefact_form.right_profile_2_um", "µm", closed(-1000, 1000), -10, 10,
        "a master gear's form terms 0.2–2 µm (recalled, unchecked)", "a value in nm?", false,
        SlipSide::kAbove},
       {"effects.artefact_form.right_profile_3_um", "µm", closed(-1000, 1000), -10, 10,
        "a master gear's form terms 0.2–2 µm (recalled, unchecked)", "a value in nm?", false,
        SlipSide::kAbove},
       {"effects.artefact_form.right_helix_2_um", "µm", closed(-1000, 1000), -10, 10,
        "a master gear's form terms 0.2–2 µm (recalled, unchecked)", "a value in nm?", false,
        SlipSide::kAbove},
       {"effects.artefact_form.right_helix_3_um", "µm", closed(-1000, 1000), -10, 10,
        "a master gear's form terms 0.2–2 µm (recalled, unchecked)", "a value in nm?", false,
        SlipSide::kAbove},
       {"effects.artefact_form.profile_from_mm", "mm", closed(0, 10000), 0, 1000,
        "roll lengths of the profile evaluation range", ""},
       {"effects.artefact_form.profile_to_mm", "mm", closed(0, 10000), 0, 1000,
        "roll lengths of the profile evaluation range", ""},
       {"effects.artefact_form.face_from_mm", "mm", closed(-10000, 10000), -1000, 1000,
        "face positions z of the helix evaluation range", ""},
       {"effects.artefact_form.face_to_mm", "mm", closed(-10000, 10000), -1000, 1000,
        "face positions z of the helix evaluation range", ""},
       {"effects.scale_resolution.x_um", "µm", closed(0, 100), 0, 5,
        "scale resolution 0.05–1 µm (recalled, unchecked)", "a value in nm? (100 nm = 0.1 µm)",
        false, SlipSide::kAbove},
       {"effects.scale_resolution.y_um", "µm", closed(0, 100), 0, 5,
        "scale resolution 0.05–1 µm (recalled, unchecked)", "a value in nm? (100 nm = 0.1 µm)",
        false, SlipSide::kAbove},
       {"effects.scale_resolution.z_um", "µm", closed(0, 100), 0, 5,
        "scale resolution 0.05–1 µm (recalled, unchecked)", "a value in nm? (100 nm = 0.1 µm)",
        false, SlipSide::kAbove},
       {"effects.empirical.from", "axis unit", closed(-100000, 100000), -1000, 1000,
        "roll length or face position in mm, probing order 0–1", ""},
       {"effects.empirical.to", "axis unit", closed(-100000, 100000), -1000, 1000,
        "roll length or face position in mm, probing order 0–1", ""},
       {"effects.empirical.terms.a_um", "µm", closed(-1000, 1000), -20, 20,
        "structure left after the library's fit, usually below a few µm", "a value in nm?", false,
        SlipSide::kAbove},
       {"effects.empirical.terms.b_um", "µm", closed(-1000, 1000), -20, 20,
        "structure left after the library's fit, usually below a few µm", "a value in nm?", false,
        SlipSide::kAbove},
       {"effects.rotary_table.radial_cos_um", "µm", closed(-1000, 1000), -10, 10,
        "rotary-table radial runout 0.1–3 µm", "a value in nm?", false, SlipSide::kAbove},
       {"effects.rotary_table.radial_sin_um", "µm", closed(-1000, 1000), -10, 10,
        "rotary-table radial runout 0.1–3 µm", "a value in nm?", false, SlipSide::kAbove},
       {"effects.rotary_table.axial_cos_um", "µm", closed(-1000, 1000), -10, 10,
        "rotary-table axial runout 0.1–3 µm", "a value in nm?", false, SlipSide::kAbove},
       {"effects.rotary_table.axial_sin_um", "µm", closed(-1000, 1000), -10, 10,
        "rotary-table axial runout 0.1–3 µm", "a value in nm?", false, SlipSide::kAbove},
       {"effects.rotary_table.angular_cos_1_arcsec", "arcsec", closed(-3600, 3600), -30, 30,
        "rotary-table positioning error 0.5–5 arcsec", "a value in µrad? (1 arcsec = 4.85 µrad)",
        false, SlipSide::kAbove},
       {"effects.rotary_table.angular_sin_1_arcsec", "arcsec", closed(-3600, 3600), -30, 30,
        "rotary-table positioning error 0.5–5 arcsec", "a value in µrad? (1 arcsec = 4.85 µrad)",
        false, SlipSide::kAbove},
       {"effects.rotary_table.angular_cos_2_arcsec", "arcsec", closed(-3600, 3600), -30, 30,
        "rotary-table positioning error 0.5–5 arcsec", "a value in µrad? (1 arcsec = 4.85 µrad)",
        false, SlipSide::kAbove},
       {"effects.rotary_table.angular_sin_2_arcsec", "arcsec", closed(-3600, 3600), -30, 30,
        "rotary-table positioning error 0.5–5 arcsec", "a value in µrad? (1 arcsec = 4.85 µrad)",
        false, SlipSide::kAbove},
       {"effects.stylus_bending.deflection_um", "µm", closed(-1000, 1000), -10, 10,
        "uncompensated stylus bending 0.1–2 µm", "a value in nm?", false, SlipSide::kAbove}}};
  return table;
}

const RangeTable& readings_ranges() {
  static const RangeTable table{
      "readings",
      {{"stylus_radius_mm", "mm", closed(0.01, 50), 0.05, 5,
        "stylus balls are 0.1–10 mm in diameter", "a diameter, or µm?", false, SlipSide::kAbove},
       {"coordinate_mm", "mm", closed(-100000, 100000), -10000, 10000,
        "a CMM's measuring volume is at most a few metres", "µm instead of mm?", false,
        SlipSide::kAbove},
       {"ref_dev_um", "µm", closed(-10000, 10000), -1000, 1000,
        "an artefact's calibrated deviation is a few µm", "mm instead of µm?", false,
        SlipSide::kBelow},
       {"reading_um", "µm", closed(-100000, 100000), -10000, 10000,
        "(c − p)·n − R: a measured flank is within a few tens of µm of the nominal one",
        "a stylus radius or a point in other units?"}}};
  return table;
}

const RangeTable& machine_ranges() {
  static const RangeTable table{
      "cmm",
      {{"cmm.mpe_e_um.A", "µm", closed(0, 1000), 0.3, 20,
        "A of MPE_E = A + L/K: 0.3 µm (best CMMs) … 20 µm (shop-floor arms)", "nm?"},
       {"cmm.mpe_e_um.K", "mm/µm", closed(1, 100000), 50, 2000,
        "K of MPE_E = A + L/K: L/1000 (best CMMs) … L/50 (shop-floor arms)", "", false},
       {"cmm.mpe_p_um", "µm", above(0, 1000), 0.3, 20,
        "ISO 10360-5 MPE_P (P_FTU) of 0.3 µm … 20 µm", "nm?"},
       {"cmm.travel_mm", "mm", above(0, 100000), 100, 10000,
        "CMM travels of 100 mm … 10 m per axis", "m?"},
       {"cmm.placement_mm", "mm", closed(-50000, 50000), -5000, 5000,
        "within the travel (checked against it)", "µm?"},
       {"cmm.stylus_length_mm", "mm", closed(0, 1000), 10, 300, "styli of 10 … 300 mm from the ram",
        "µm?"},
       {"cmm.rotary_table.radial_um", "µm", closed(0, 100), 0.05, 5,
        "radial error motion of gear-measuring tables: 0.1 … 2 µm", "nm?"},
       {"cmm.rotary_table.axial_um", "µm", closed(0, 100), 0.05, 5,
        "axial error motion of gear-measuring tables: 0.1 … 2 µm", "nm?"},
       {"cmm.rotary_table.angular_arcsec", "arcsec", closed(0, 360), 0.1, 10,
        "angular positioning of gear-measuring tables: 0.5 … 3 arcsec", "degrees or µrad?"},
       {"cmm.verification_u_um", "µm", above(0, 100), 0.05, 2,
        "the standard uncertainty of a measured length error: 0.05 µm (interferometer) … 2 µm",
        "nm?"},
       {"cmm.machines", "", closed(10, 20000), 200, 5000,
        "a U from 200 machines was 8 % short of one from 1 000 (F_p, docs/cmm.md)", "", true},
       {"cmm.order", "", closed(1, 8), 1, 5,
        "smooth error functions over the travel; a high order is not what a data sheet says", "",
        true}}};
  return table;
}

std::vector<const RangeTable*> all_range_tables() {
  return {&gear_ranges(),   &tolerance_ranges(), &deviation_ranges(), &probing_ranges(),
          &effect_ranges(), &machine_ranges(),   &claim_ranges(),     &readings_ranges()};
}

std::string describe_range(const ParameterRange& range) {
  std::string text = range.valid.describe();
  if (range.integer) {
    text = "an integer from " + shortest_text(range.valid.min) + " to " +
           shortest_text(range.valid.max);
  }
  if (!range.unit.empty()) text += " " + range.unit;
  return text + " (" + range.why + ")";
}

namespace {

std::string warning_text(double value, const ParameterRange& range) {
  std::string text = with_unit(value, range.unit) + " is outside the usual range " +
                     shortest_text(range.usual_min) + " … " +
                     with_unit(range.usual_max, range.unit) + " (" + range.why + ")";
  if (const std::string slip = range.slip_for(value); !slip.empty()) text += "; " + slip;
  return text;
}

}  // namespace

std::string range_reference_markdown() {
  std::string md =
      "# Scenario and readings numbers: units and ranges\n\n"
      "Generated from `engine/schema/parameter_ranges.cpp` (the tables the readers check "
      "against) by `scripts/update-docs`; a test fails when this page and the tables differ. "
      "A value outside the **valid** range is an error (exit 2, with file:line:column, the key, "
      "the value and the range); a value outside the **usual** range is accepted with a "
      "warning (`gearmc: warning: …`, also in summary.json `input_warnings`). Keys in "
      "`effects.<effect>.<parameter>` may also be given as a per-gear law "
      "(`{uniform: [lo, hi]}` or `{normal: [mean, sd]}`), whose bounds are checked the same "
      "way. The structure of a scenario file, with every key and its default, is in "
      "[scenarios.md](scenarios.md).\n";
  auto cell = [](std::string text) {
    std::string out;
    for (char c : text) out += c == '|' ? std::string("\\|") : std::string(1, c);
    return out;
  };
  for (const RangeTable* table : all_range_tables()) {
    md += "\n## " + table->section + "\n\n";
    md += "| key | unit | valid | usual | why | a value outside the usual range may be |\n";
    md += "|---|---|---|---|---|---|\n";
    for (const ParameterRange& r : table->entries) {
      const std::string valid =
          r.integer ? "integer " + shortest_text(r.valid.min) + " … " + shortest_text(r.valid.max)
                    : r.valid.describe();
      md += "| `" + r.key + "` | " + cell(r.unit) + " | " + cell(valid) + " | " +
            shortest_text(r.usual_min) + " … " + shortest_text(r.usual_max) + " | " + cell(r.why) +
            " | " + cell(r.slip) + " |\n";
    }
  }
  return md;
}

double read_ranged(const YamlValue& value, const ParameterRange& range, InputWarnings* warnings) {
  std::string expected = describe_range(range);
  double x = 0.0;
  try {
    x = value.as_number();
  } catch (const InputError&) {
    throw value.error(expected + (value.is_quoted() ? ", written without quotes" : ""));
  }
  if (!range.valid.contains(x)) {
    if (const std::string slip = range.slip_for(x); !slip.empty()) expected += "; " + slip;
    throw value.error(expected);
  }
  if (warnings != nullptr && (x < range.usual_min || x > range.usual_max)) {
    warnings->push_back(
        InputError(value.location(), value.path() + ": " + warning_text(x, range)).what());
  }
  return x;
}

std::int64_t read_ranged_int(const YamlValue& value, const ParameterRange& range,
                             InputWarnings* warnings) {
  const std::string expected = describe_range(range);
  std::int64_t x = 0;
  try {
    x = value.as_int();
  } catch (const InputError&) {
    throw value.error(expected + (value.is_quoted() ? ", written without quotes" : ""));
  }
  const double real = static_cast<double>(x);
  if (!range.valid.contains(real)) throw value.error(expected);
  if (warnings != nullptr && (real < range.usual_min || real > range.usual_max)) {
    warnings->push_back(
        InputError(value.location(), value.path() + ": " + warning_text(real, range)).what());
  }
  return x;
}

std::optional<std::int64_t> get_ranged_int(const YamlMap& map, const std::string& key,
                                           const ParameterRange& range, InputWarnings* warnings) {
  const std::optional<YamlValue> value = map.find(key);
  if (!value) return std::nullopt;
  return read_ranged_int(*value, range, warnings);
}

std::optional<double> get_ranged(const YamlMap& map, const std::string& key,
                                 const ParameterRange& range, InputWarnings* warnings) {
  const std::optional<YamlValue> value = map.find(key);
  if (!value) return std::nullopt;
  return read_ranged(*value, range, warnings);
}

void check_ranged(double value, const ParameterRange& range, const InputLocation& where,
                  const std::string& shown, InputWarnings* warnings) {
  if (!range.valid.contains(value)) {
    std::string expected = describe_range(range);
    if (const std::string slip = range.slip_for(value); !slip.empty()) expected += "; " + slip;
    throw InputError(where, range.key, shown, expected);
  }
  if (warnings != nullptr && (value < range.usual_min || value > range.usual_max)) {
    warnings->push_back(InputError(where, range.key + ": " + warning_text(value, range)).what());
  }
}

}  // namespace gearmc
