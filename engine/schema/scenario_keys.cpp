// The table of scenario keys and the reference page made from it (see scenario_keys.h). The
// defaults are the readers' own: scenario.cpp and effect_config.cpp read them from here.
#include "engine/schema/scenario_keys.h"

#include <algorithm>
#include <charconv>
#include <stdexcept>
#include <tuple>

#include "engine/schema/parameter_ranges.h"
#include "gears/tolerances.h"

namespace gearmc {
namespace {

ScenarioKey make_key(std::string key, KeyType type, std::optional<double> value,
                     std::string default_text, std::vector<std::string> allowed,
                     std::string description) {
  ScenarioKey k;
  k.key = std::move(key);
  k.type = type;
  k.default_number = value;
  k.default_text = std::move(default_text);
  k.allowed = std::move(allowed);
  k.description = std::move(description);
  return k;
}
ScenarioKey map_key(std::string key, std::string default_text, std::string description) {
  return make_key(std::move(key), KeyType::kMap, std::nullopt, std::move(default_text), {},
                  std::move(description));
}
ScenarioKey list_key(std::string key, std::string default_text, std::string description) {
  return make_key(std::move(key), KeyType::kList, std::nullopt, std::move(default_text), {},
                  std::move(description));
}
ScenarioKey text_key(std::string key, std::string default_text, std::string description) {
  return make_key(std::move(key), KeyType::kString, std::nullopt, std::move(default_text), {},
                  std::move(description));
}
ScenarioKey boolean_key(std::string key, bool value, std::string description) {
  return make_key(std::move(key), KeyType::kBoolean, std::nullopt, value ? "true" : "false", {},
                  std::move(description));
}
ScenarioKey choice_key(std::string key, std::vector<std::string> allowed, std::string value,
                       std::string description) {
  return make_key(std::move(key), KeyType::kChoice, std::nullopt, std::move(value),
                  std::move(allowed), std::move(description));
}
// A number or integer with a default the reader uses (nullopt: `default_text` says what).
ScenarioKey number_key(std::string key, KeyType type, std::optional<double> value,
                       std::string default_text, std::string description,
                       std::string range_key = "") {
  ScenarioKey k =
      make_key(std::move(key), type, value, std::move(default_text), {}, std::move(description));
  k.range_key = std::move(range_key);
  return k;
}
ScenarioKey parameter_key(std::string key, double value, std::string description) {
  return number_key(std::move(key), KeyType::kParameter, value, "", std::move(description));
}
ScenarioKey bounded_integer(std::string key, std::optional<double> value, std::string default_text,
                            long min, long max, std::string description) {
  ScenarioKey k = number_key(std::move(key), KeyType::kInteger, value, std::move(default_text),
                             std::move(description));
  k.integer_min = min;
  k.integer_max = max;
  return k;
}

std::vector<std::string> symbols_of(ToleranceStandard standard) {
  std::vector<std::string> symbols;
  for (const ToleranceKind kind : all_tolerance_kinds()) {
    if (const auto symbol = tolerance_symbol(kind, standard)) symbols.push_back(*symbol);
  }
  return symbols;
}

std::vector<ScenarioKey> make_table() {
  constexpr KeyType kNum = KeyType::kNumber, kInt = KeyType::kInteger;
  const std::vector<std::string> laws = {"uniform", "normal", "at_tolerance"};
  std::vector<ScenarioKey> t = {
      text_key("name", "the file name without .yaml",
               "names the results folder results/<name>/ (no '/' or '\\')"),
      number_key("seed", kInt, 1, "", "seed of every random draw (0 … 2⁶⁴ − 1)"),
      map_key("gear", "required", "the spur or helical gear (ISO 21771 quantities)"),
      map_key("tolerances", "GOST 1643-81 grade 6-5-5", "the tolerance system and grade"),
      map_key("deviations", "every law uniform", "how real gears are drawn within tolerance"),
      map_key("probing", "P1's 10 × 5 grid on every flank", "the probing plan"),
      map_key("stylus", "R 0.5 mm", "the stylus"),
      map_key("run", "50 gears", "the Monte-Carlo run"),
      list_key("surfaces", "none (analytic flanks)", "flanks whose real surface is a mesh file"),
      map_key("effects", "none", "measurement effects, in chain order"),
      map_key("cmm", "none (the effects' own machine errors)",
              "a CMM from its data sheet: machines drawn and kept by their acceptance tests, "
              "each gear measured on one (docs/cmm.md)"),
      list_key("claims", "none", "accuracy claims that `gearmc check` decides"),
      map_key("evaluation", "none (no gear parameters)",
              "ISO 1328-1 gear parameters of every simulated measurement"),

      number_key("gear.teeth", kInt, std::nullopt, "required", "number of teeth z"),
      number_key("gear.module_mm", kNum, std::nullopt, "required", "normal module m_n"),
      number_key("gear.pressure_angle_deg", kNum, 20, "", "normal pressure angle α_n"),
      number_key("gear.helix_angle_deg", kNum, 0, "",
                 "helix angle β at the reference diameter (0: spur)"),
      choice_key("gear.hand", {"right", "left"}, "required when helix_angle_deg > 0",
                 "hand of the helix (right: the section turns counter-clockwise going up +Z)"),
      boolean_key("gear.internal", false, "an internal (ring) gear (also: a negative tooth count)"),
      map_key("gear.modifications", "none",
              "designed profile and helix modifications: the design flank deviations are "
              "measured against"),
      number_key("gear.modifications.profile_crowning_um", kNum, 0, "",
                 "profile crowning over the active profile, µm at both ends"),
      number_key("gear.modifications.helix_crowning_um", kNum, 0, "",
                 "helix crowning over the face width, µm at both ends"),
      number_key("gear.modifications.helix_slope_um", kNum, 0, "",
                 "helix slope modification over the face width, µm (+ = more material at z = b)"),
      number_key("gear.profile_shift", kNum, 0, "", "profile shift coefficient x"),
      number_key("gear.face_width_mm", kNum, std::nullopt, "required", "face width b"),
      number_key("gear.tip_diameter_mm", kNum, std::nullopt, "from the rack and the shift",
                 "tip diameter override"),
      number_key("gear.root_diameter_mm", kNum, std::nullopt, "from the rack and the shift",
                 "root diameter override"),
      number_key("gear.form_diameter_mm", kNum, std::nullopt, "from the rack and the shift",
                 "form diameter override: where the involute starts on the root side (a ring "
                 "gear's from its pinion-type cutter)"),
      map_key("gear.basic_rack", "ISO 53 profile A", "the basic rack, in modules"),
      number_key("gear.basic_rack.addendum", kNum, 1.0, "", "rack addendum h_aP/m"),
      number_key("gear.basic_rack.dedendum", kNum, 1.25, "", "rack dedendum h_fP/m"),
      number_key("gear.basic_rack.root_radius", kNum, 0.38, "", "rack tip radius ρ_fP/m"),

      choice_key("tolerances.standard",
                 {standard_name(ToleranceStandard::kGost1643_81),
                  standard_name(ToleranceStandard::kIso1328_1_2013)},
                 standard_name(ToleranceStandard::kGost1643_81), "the tolerance system"),
      text_key("tolerances.grade", "\"6-5-5\" for GOST; required for ISO",
               "GOST: \"K-S-C\" (kinematic, smoothness, contact, each 1 … 12) or one grade "
               "1 … 12; ISO 1328-1:2013: the flank tolerance class 1 … 11"),
      make_key("tolerances.overrides_um", KeyType::kSymbolMap, std::nullopt, "none", {},
               "explicit tolerances, µm, by the chosen standard's symbols (E_Hs: least rack "
               "shift)"),

      boolean_key("deviations.random", true, "false: the nominal gear (plus normal_um)"),
      choice_key("deviations.distribution", laws, "uniform", "the law of every group"),
      number_key("deviations.k", kNum, 3, "", "tolerance = k σ for the normal law"),
  };
  // The tolerance symbols of both standards (the reader accepts the chosen standard's).
  for (ScenarioKey& k : t) {
    if (k.key != "tolerances.overrides_um") continue;
    for (const ToleranceStandard s :
         {ToleranceStandard::kGost1643_81, ToleranceStandard::kIso1328_1_2013}) {
      std::string names;
      for (const std::string& symbol : symbols_of(s)) names += (names.empty() ? "" : ", ") + symbol;
      k.allowed.push_back(standard_name(s) + ": " + names);
    }
  }
  for (const char* group : {"eccentricity", "pitch", "thickness", "profile", "helix"}) {
    const std::string g = std::string("deviations.") + group;
    const bool shape = g == "deviations.profile" || g == "deviations.helix";
    t.push_back(map_key(g, "the section's law",
                        shape ? std::string("the law of the ") + group +
                                    " slope and form, and the form's smoothness"
                              : std::string("the law of the ") + group + " deviations"));
    t.push_back(choice_key(g + ".distribution", laws, "deviations.distribution", "the law"));
    t.push_back(number_key(g + ".k", kNum, std::nullopt, "deviations.k",
                           "tolerance = k σ for the normal law", "deviations.k"));
    if (shape) {
      t.push_back(number_key(g + ".control_points", kInt, g == "deviations.profile" ? 8 : 6, "",
                             "B-spline control values of the form (more = wavier)",
                             "deviations.control_points"));
    }
  }
  const std::vector<ScenarioKey> rest = {
      text_key("deviations.normal_um", "none",
               "a muParser expression of L, z, tooth, side giving a deterministic deviation, µm"),

      number_key("probing.points_along_profile", kInt, 10, "", "N points along the profile"),
      number_key("probing.sections_across_face", kInt, 5, "", "M sections across the face"),
      number_key("probing.margin_fraction", kNum, 0.05, "", "margin at each end, of the extent"),
      choice_key("probing.profile_spacing", {"roll_length", "arc_length", "radius"}, "roll_length",
                 "what the profile points are equally spaced in"),
      make_key("probing.teeth", KeyType::kTeeth, std::nullopt, "all", {}, "the teeth probed"),
      choice_key("probing.flanks", {"both", "L", "R"}, "both", "the flank sides probed"),
      choice_key("probing.order", {"tooth_by_tooth", "side_by_side"}, "tooth_by_tooth",
                 "the order of the flanks in time (drift)"),
      number_key("stylus.radius_mm", kNum, 0.5, "", "stylus tip radius R"),
      number_key("stylus.shaft_diameter_mm", kNum, std::nullopt, "the shaft is not checked",
                 "the stylus shaft's (stem's) diameter, less than the ball's: the shaft (along "
                 "`shaft_axis`) is checked for collisions with the tooth space"),
      choice_key("cmm.layout", {"bridge", "gantry", "horizontal_arm"}, "bridge",
                 "the axes' stacking: bridge and gantry Y carries X carries Z, horizontal arm X "
                 "carries Z carries Y"),
      text_key("cmm.mpe_e_um", "required, unless a verification table stands instead",
               "ISO 10360-2's MPE_E as \"A + L/K\" (µm, L in mm), e.g. \"1.8 + L/300\""),
      number_key("cmm.mpe_p_um", kNum, std::nullopt, "no probing part",
                 "ISO 10360-5's MPE_P (P_FTU), µm: the kept machines' probes pass it"),
      make_key("cmm.travel_mm", KeyType::kVector3, std::nullopt, "[700, 1000, 600]", {},
               "the travel of x, y, z"),
      make_key("cmm.placement_mm", KeyType::kVector3, std::nullopt, "[0, 0, 0]", {},
               "where the gear's centre (on its lower face) stands, from the middle of the "
               "travel"),
      number_key("cmm.stylus_length_mm", kNum, 50, "",
                 "the stylus's length from the ram's reference point (the Abbe arm)"),
      text_key("cmm.verification", "none",
               "the machine's own ISO 10360-2 results: a CSV position,length_mm,error_um[,u_um] "
               "(relative to the scenario's folder); the machines drawn agree with them"),
      number_key("cmm.verification_u_um", kNum, std::nullopt, "a u_um column is required",
                 "the measured errors' standard uncertainty when the table has no u_um column"),
      map_key("cmm.rotary_table", "none (the gear stands still)",
              "the gear turned on the machine's rotary table, each tooth probed in the same "
              "region; the table's data sheet (ISO 230-7 error motion values)"),
      number_key("cmm.rotary_table.radial_um", kNum, 0, "",
                 "radial error motion value (range over a turn), µm; 0: perfect"),
      number_key("cmm.rotary_table.axial_um", kNum, 0, "",
                 "axial error motion value (range over a turn), µm; 0: perfect"),
      number_key("cmm.rotary_table.angular_arcsec", kNum, 0, "",
                 "angular positioning error value (range over a turn), arcsec; 0: perfect"),
      bounded_integer(
          "cmm.machines", 1000, "", 10, 20000,
          "kept machines to draw (at least the run's gears: each gear another machine)"),
      bounded_integer("cmm.order", 3, "", 1, 8,
                      "highest Legendre order of the error functions over the travel"),
      choice_key("stylus.shaft_axis", {"z", "radial"}, "z",
                 "where the shaft points from the ball: z, parallel to the gear axis up past the "
                 "top face (probing from above); radial, horizontal along the radius out of the "
                 "tooth space (into a ring gear's from the axis)"),
      number_key("run.gears", kInt, 50, "", "gears simulated by `run`"),

      bounded_integer("surfaces.tooth", std::nullopt, "required", 1, 0,
                      "tooth number 1 … z of the flank"),
      choice_key("surfaces.flank", {"L", "R"}, "required", "flank side"),
      text_key("surfaces.mesh", "required",
               "triangle mesh file (.stl, .ply, .obj, .off; datum frame, mm; relative to the "
               "scenario's folder)"),
      choice_key("surfaces.contact", {"smoothed", "facets"}, "smoothed",
                 "contact on the smoothed surface or on the facets"),

      make_key(
          "evaluation.parameters", KeyType::kSymbols, std::nullopt, "required",
          {"F_alpha", "f_Halpha", "f_falpha", "F_beta", "f_Hbeta", "f_fbeta", "f_pt", "F_p", "F_r",
           "E_sn", "E_Wk", "E_MdK"},
          "the parameters evaluated: ISO 1328-1's (f_pt, F_p, F_r need every tooth probed, F_r "
          "both flanks; `all` lists these nine) and the size deviations E_sn, E_Wk, E_MdK (both "
          "flanks; listed by name)"),
      number_key("evaluation.profile_points", kInt, 0, "",
                 "points of a dedicated profile scan at mid face (0: the grid's mid section)"),
      number_key("evaluation.helix_points", kInt, 0, "",
                 "points of a dedicated helix scan at mid profile (0: the grid's mid column)"),
      number_key("evaluation.profile_sections", kInt, 1, "",
                 "profile traces per flank, at the centres of equal parts of the helix range "
                 "(1: mid face; on the grid, its sections spread alike)"),
      number_key("evaluation.helix_sections", kInt, 1, "",
                 "helix traces per flank, at the centres of equal parts of the profile range "
                 "(1: mid profile; on the grid, its columns spread alike)"),
      number_key("evaluation.truth_points", kInt, 100, "",
                 "points of the dense trace on the real surface (true values)"),
      number_key("evaluation.profile_end_fraction", kNum, 0.95, "",
                 "profile evaluation range L_α: this fraction of the active roll length"),
      number_key("evaluation.helix_end_exclusion_mm", kNum, std::nullopt, "min(5 % b, m_n)",
                 "helix evaluation range L_β: b minus this at each end"),
      number_key("evaluation.span_teeth", kInt, std::nullopt, "jaws nearest mid profile",
                 "k of the base tangent length W_k (E_Wk): the jaws must touch within L_α"),
      number_key("evaluation.ball_diameter_mm", kNum, std::nullopt, "ball touching mid profile",
                 "D_M of the dimension over balls M_dK (E_MdK): it must touch within L_α"),
      map_key("evaluation.size_allowances_um", "none",
              "the drawing's size allowances (DIN 3967): E_sn, E_Wk, E_MdK, each {upper, lower}"),
      map_key("evaluation.size_allowances_um.E_sn", "none",
              "the drawing's allowances of the normal tooth thickness: its conformity decisions, "
              "U/T and Q_MP"),
      number_key("evaluation.size_allowances_um.E_sn.upper", kNum, std::nullopt, "required",
                 "upper allowance (upper limit of E_sn), µm"),
      number_key("evaluation.size_allowances_um.E_sn.lower", kNum, std::nullopt, "required",
                 "lower allowance (lower limit of E_sn), µm; below upper"),
      map_key("evaluation.size_allowances_um.E_Wk", "none",
              "the drawing's allowances of the base tangent length W_k: its conformity decisions, "
              "U/T and Q_MP"),
      number_key("evaluation.size_allowances_um.E_Wk.upper", kNum, std::nullopt, "required",
                 "upper allowance (upper limit of E_Wk), µm"),
      number_key("evaluation.size_allowances_um.E_Wk.lower", kNum, std::nullopt, "required",
                 "lower allowance (lower limit of E_Wk), µm; below upper"),
      map_key("evaluation.size_allowances_um.E_MdK", "none",
              "the drawing's allowances of the dimension over (between) balls M_dK: its conformity "
              "decisions, U/T and Q_MP"),
      number_key("evaluation.size_allowances_um.E_MdK.upper", kNum, std::nullopt, "required",
                 "upper allowance (upper limit of E_MdK), µm"),
      number_key("evaluation.size_allowances_um.E_MdK.lower", kNum, std::nullopt, "required",
                 "lower allowance (lower limit of E_MdK), µm; below upper"),
      number_key("evaluation.profile_cutoff_mm", kNum, std::nullopt, "unfiltered",
                 "cut-off λc of the Gaussian profile filter (ISO 16610-21), along L"),
      number_key("evaluation.helix_cutoff_mm", kNum, std::nullopt, "unfiltered",
                 "cut-off λc of the Gaussian helix filter (ISO 16610-21), along z"),
      choice_key("evaluation.decision_rule", {"simple", "guard_banded"}, "simple",
                 "ISO 14253-1 acceptance: within T, or within T narrowed at each limit by the "
                 "error's 95 % reach past zero (docs/parameters.md)"),
  };
  t.insert(t.end(), rest.begin(), rest.end());
  // The three reliefs of gear.modifications, after its map key: amount, length, shape each.
  std::vector<ScenarioKey> reliefs;
  for (const auto& [name, what, along] :
       {std::tuple<std::string, std::string, std::string>{
            "tip_relief", "tip relief, ending at the tip circle", "along the roll length"},
        {"root_relief", "root relief, ending at the form circle", "along the roll length"},
        {"end_relief", "end relief at both faces", "along the face, at each end"}}) {
    const std::string path = "gear.modifications." + name;
    reliefs.push_back(map_key(path, "none", what));
    reliefs.push_back(number_key(path + ".amount_um", kNum, std::nullopt, "required",
                                 "material removed at the end, µm"));
    reliefs.push_back(number_key(path + ".length_mm", kNum, std::nullopt, "required",
                                 "its length " + along + ", mm"));
    reliefs.push_back(choice_key(
        path + ".shape", {"circular", "linear"}, "circular",
        name == "end_relief"
            ? "circular: an arc tangent to the flank; linear: a straight line from a kink across "
              "the face"
            : "circular: an arc tangent to the flank; linear: a straight line from a kink along "
              "the face"));
  }
  const auto after = std::find_if(
      t.begin(), t.end(), [](const ScenarioKey& k) { return k.key == "gear.modifications"; });
  t.insert(after + 1, reliefs.begin(), reliefs.end());

  // effects: each effect's map (absent = off) with `enabled` and its parameters.
  struct Effect {
    const char* name;
    const char* description;
    std::vector<ScenarioKey> keys;  // after `enabled`
  };
  const std::string lobing = "effects.probe_lobing.";
  const std::string model = lobing + "from_probe_model.";
  const std::vector<Effect> effects = {
      {"probe_lobing",
       "pre-travel p(φ) = p0 + Σ a_k cos(k(φ − φ_k)) with P2's qualification",
       {parameter_key(lobing + "pretravel_um", 0, "p0"),
        list_key(lobing + "harmonics", "none", "the harmonics a_k, φ_k"),
        map_key(lobing + "from_probe_model", "none",
                "p0 and the orders 3, 6, 9, … from the CVODE probe model (replaces pretravel_um "
                "and harmonics)"),
        parameter_key(lobing + "repeatability_um", 0, "σ of one trigger"),
        choice_key(lobing + "calibration", {"none", "mean6", "six_directions", "per_direction"},
                   "none", "P2's qualification strategy"),
        choice_key(lobing + "six_directions_use", {"nearest", "interpolated"}, "nearest",
                   "how six_directions applies its six values"),
        number_key(lobing + "calibration_start_deg", kNum, 90, "",
                   "first qualification direction")}},
      {"stylus_radius",
       "an error of the stylus radius",
       {parameter_key("effects.stylus_radius.error_um", 0, "radius error")}},
      {"tip_form",
       "form deviation of the tip ball",
       {bounded_integer("effects.tip_form.order", 2, "", 1, 36, "lobes of the tip's form"),
        parameter_key("effects.tip_form.amplitude_um", 0, "amplitude"),
        parameter_key("effects.tip_form.phase_deg", 0, "azimuth of a maximum")}},
      {"scale",
       "scale errors of the machine's axes",
       {parameter_key("effects.scale.x_ppm", 0, "x scale error"),
        parameter_key("effects.scale.y_ppm", 0, "y scale error"),
        parameter_key("effects.scale.z_ppm", 0, "z scale error")}},
      {"squareness",
       "out-of-squareness of the axes",
       {parameter_key("effects.squareness.xy_urad", 0, "x–y"),
        parameter_key("effects.squareness.xz_urad", 0, "x–z"),
        parameter_key("effects.squareness.yz_urad", 0, "y–z")}},
      {"thermal_expansion",
       "workpiece and scale temperatures off 20 °C",
       {parameter_key("effects.thermal_expansion.workpiece_delta_t_k", 0, "workpiece ΔT"),
        parameter_key("effects.thermal_expansion.scale_delta_t_k", 0, "scale ΔT"),
        parameter_key("effects.thermal_expansion.workpiece_cte_ppm_per_k", 11.5,
                      "workpiece expansion coefficient (steel)"),
        parameter_key("effects.thermal_expansion.scale_cte_ppm_per_k", 0,
                      "scale expansion coefficient")}},
      {"drift",
       "a drift over the measurement, linear in the probing order",
       {parameter_key("effects.drift.x_um", 0, "x drift over the measurement"),
        parameter_key("effects.drift.y_um", 0, "y drift"),
        parameter_key("effects.drift.z_um", 0, "z drift")}},
      {"step_quantization",
       "servo step q: a latch delay uniform on [0, q)",
       {parameter_key("effects.step_quantization.step_um", 0, "step q"),
        number_key("effects.step_quantization.approach_mm", kNum, 2.0, "", "approach distance")}},
      {"eccentricity",
       "the gear's axis off the rotary table's",
       {parameter_key("effects.eccentricity.x_um", 0, "x offset"),
        parameter_key("effects.eccentricity.y_um", 0, "y offset")}},
      {"clocking",
       "the gear turned about its axis from the plan's angular datum",
       {parameter_key("effects.clocking.angle_urad", 0, "angle, counter-clockwise from +z")}},
      {"noise", "probing noise N(0, σ²)", {parameter_key("effects.noise.sigma_um", 0, "σ")}},
      {"probe_warmup",
       "pre-travel drifting as the probe warms up, an exponential approach over the sequence",
       {parameter_key("effects.probe_warmup.change_um", 0, "pre-travel change reached at the end"),
        number_key("effects.probe_warmup.time_constant", kNum, 0.3, "",
                   "thermal time constant, as a fraction of one gear's sequence")}},
      {"straightness",
       "straightness of the X and Y axes: a quadratic bow along the other axes' travel",
       {parameter_key("effects.straightness.xy_um", 0, "X deviation at a Y travel of L"),
        parameter_key("effects.straightness.xz_um", 0, "X deviation at a Z travel of L"),
        parameter_key("effects.straightness.yx_um", 0, "Y deviation at an X travel of L"),
        parameter_key("effects.straightness.yz_um", 0, "Y deviation at a Z travel of L"),
        number_key("effects.straightness.length_mm", kNum, 100.0, "", "the travel L")}},
      {"artefact_form",
       "the master gear's own profile and helix form: Legendre orders 2, 3 per flank side (a "
       "property of the artefact, not of the CMM)",
       {parameter_key("effects.artefact_form.left_profile_2_um", 0,
                      "left flanks: P₂ in roll length, µm at the range's ends"),
        parameter_key("effects.artefact_form.left_profile_3_um", 0,
                      "left flanks: P₃ in roll length, µm at profile_to_mm"),
        parameter_key("effects.artefact_form.left_helix_2_um", 0,
                      "left flanks: P₂ in face position, µm at the range's ends"),
        parameter_key("effects.artefact_form.left_helix_3_um", 0,
                      "left flanks: P₃ in face position, µm at face_to_mm"),
        parameter_key("effects.artefact_form.right_profile_2_um", 0,
                      "right flanks: P₂ in roll length"),
        parameter_key("effects.artefact_form.right_profile_3_um", 0,
                      "right flanks: P₃ in roll length"),
        parameter_key("effects.artefact_form.right_helix_2_um", 0,
                      "right flanks: P₂ in face position"),
        parameter_key("effects.artefact_form.right_helix_3_um", 0,
                      "right flanks: P₃ in face position"),
        number_key("effects.artefact_form.profile_from_mm", kNum, std::nullopt, "required",
                   "roll length √(r² − r_b²) where the profile range starts"),
        number_key("effects.artefact_form.profile_to_mm", kNum, std::nullopt, "required",
                   "roll length where the profile range ends"),
        number_key("effects.artefact_form.face_from_mm", kNum, std::nullopt, "required",
                   "face position z where the helix range starts"),
        number_key("effects.artefact_form.face_to_mm", kNum, std::nullopt, "required",
                   "face position z where the helix range ends")}},
      {"scale_resolution",
       "the scales' resolution: each recorded coordinate latched on its axis's grid, c ← "
       "s·round(c/s)",
       {parameter_key("effects.scale_resolution.x_um", 0, "step of the X scale (0: not latched)"),
        parameter_key("effects.scale_resolution.y_um", 0, "step of the Y scale"),
        parameter_key("effects.scale_resolution.z_um", 0, "step of the Z scale")}},
      {"empirical",
       "a low-order term along one axis for structure outside the library (written by diagnose)",
       {choice_key(
            "effects.empirical.axis",
            {"roll_length", "face_position", "tooth", "flank", "approach_azimuth", "probing_order"},
            "required", "the axis the term varies along"),
        choice_key("effects.empirical.basis", {"legendre", "harmonic"}, "required",
                   "Legendre polynomials P_k or harmonics cos/sin kx"),
        number_key("effects.empirical.from", kNum, 0.0, "",
                   "start of the Legendre range along the axis (mm, or 0–1 for probing_order)"),
        number_key("effects.empirical.to", kNum, 1.0, "", "end of the Legendre range"),
        list_key("effects.empirical.terms", "none", "the terms of orders k ≥ 1")}},
      {"rotary_table",
       "rotary table errors against the table angle θ_k = 2π(k − 1)/z of tooth k (ISO 230-7)",
       {parameter_key("effects.rotary_table.radial_cos_um", 0, "radial runout, cos θ part"),
        parameter_key("effects.rotary_table.radial_sin_um", 0, "radial runout, sin θ part"),
        parameter_key("effects.rotary_table.axial_cos_um", 0, "axial runout, cos θ part"),
        parameter_key("effects.rotary_table.axial_sin_um", 0, "axial runout, sin θ part"),
        parameter_key("effects.rotary_table.angular_cos_1_arcsec", 0,
                      "angular positioning error, cos θ part"),
        parameter_key("effects.rotary_table.angular_sin_1_arcsec", 0,
                      "angular positioning error, sin θ part"),
        parameter_key("effects.rotary_table.angular_cos_2_arcsec", 0,
                      "angular positioning error, cos 2θ part"),
        parameter_key("effects.rotary_table.angular_sin_2_arcsec", 0,
                      "angular positioning error, sin 2θ part")}},
      {"stylus_bending",
       "the stylus bends under the probing force: −δ₉₀ sin²γ, γ between approach and stylus",
       {parameter_key("effects.stylus_bending.deflection_um", 0,
                      "deflection δ₉₀ at an approach across the stylus (uncompensated part)"),
        choice_key("effects.stylus_bending.stylus_axis", {"z", "x", "y"}, "z",
                   "the stylus axis's direction")}},
  };
  for (const Effect& e : effects) {
    const std::string path = std::string("effects.") + e.name;
    t.push_back(map_key(path, "off", e.description));
    t.push_back(boolean_key(path + ".enabled", true, "false: the effect is off"));
    for (const ScenarioKey& k : e.keys) {
      t.push_back(k);
      if (k.key == lobing + "harmonics") {
        t.push_back(bounded_integer(lobing + "harmonics.order", std::nullopt, "required", 1, 36,
                                    "k, lobes per turn (each order once)"));
        t.push_back(parameter_key(lobing + "harmonics.amplitude_um", 0, "a_k"));
        t.push_back(parameter_key(lobing + "harmonics.phase_deg", 0, "φ_k, azimuth of a maximum"));
      }
      if (k.key == "effects.empirical.terms") {
        t.push_back(bounded_integer("effects.empirical.terms.order", std::nullopt, "required", 1,
                                    36, "k (each order once)"));
        t.push_back(parameter_key("effects.empirical.terms.a_um", 0, "a_k: P_k or cos kx"));
        t.push_back(parameter_key("effects.empirical.terms.b_um", 0, "b_k: sin kx (harmonic)"));
      }
      if (k.key == lobing + "from_probe_model") {
        t.push_back(number_key(model + "stylus_length_mm", kNum, 20.0, "", "stylus length ℓ"));
        t.push_back(number_key(model + "stem_diameter_mm", kNum, 0.7, "", "stem diameter"));
        t.push_back(number_key(model + "ball_diameter_mm", kNum, 1.0, "", "ball diameter"));
        t.push_back(choice_key(model + "stem_material", {"tungsten_carbide", "steel", "zirconia"},
                               "tungsten_carbide", "stem material"));
        t.push_back(
            number_key(model + "trigger_latency_s", kNum, 0.0, "", "trigger-to-latch delay"));
        t.push_back(number_key(model + "speed_mm_s", kNum, 2.0, "", "approach speed"));
        t.push_back(bounded_integer(model + "directions", 72, "", 12, 720,
                                    "approach directions the model is solved at"));
        t.push_back(bounded_integer(model + "max_order", 9, "", 3, 12,
                                    "highest harmonic order kept (below directions / 2)"));
      }
    }
  }

  // claims: what `gearmc check` decides (engine/scenario/claims.cpp).
  t.push_back(text_key("claims.name", "required", "the claim's name, unique in the file"));
  t.push_back(text_key("claims.quantity", "required",
                       "delta_rcomp.point, delta_rcomp.flank_max or total_error.point (needs "
                       "effects)"));
  t.push_back(choice_key("claims.side", {"left", "right", "both"}, "both",
                         "the flank sides whose values count"));
  t.push_back(choice_key("claims.statistic", {"mean", "std", "max", "U", "U_over_T"}, "required",
                         "the statistic: mean, std, max, U (2·√(u² + bias²) of a parameter "
                         "error), or a map {quantile: p}"));
  t.push_back(number_key("claims.statistic.quantile", kNum, std::nullopt, "required in the map",
                         "the quantile's probability p"));
  t.push_back(number_key("claims.at_most_um", kNum, std::nullopt, "one or both limits",
                         "the statistic is at most this (with at_least_um: a two-sided claim, "
                         "for mean, std and U)"));
  t.push_back(number_key("claims.at_least_um", kNum, std::nullopt, "one or both limits",
                         "the statistic is at least this"));
  t.push_back(number_key("claims.at_most", kNum, std::nullopt, "U_over_T: one or both limits",
                         "U/T is at most this (a ratio without unit)"));
  t.push_back(number_key("claims.at_least", kNum, std::nullopt, "U_over_T: one or both limits",
                         "U/T is at least this"));
  t.push_back(
      number_key("claims.confidence", kNum, 0.95, "", "the probability that a verdict is right"));
  return t;
}

std::string number_text(double value) {
  char buffer[64];
  const auto r = std::to_chars(buffer, buffer + sizeof buffer, value);
  return std::string(buffer, r.ptr);
}

const ParameterRange* range_of(const ScenarioKey& k) {
  const std::string& key = k.range_key.empty() ? k.key : k.range_key;
  for (const RangeTable* table : all_range_tables()) {
    for (const ParameterRange& r : table->entries) {
      if (r.key == key) return &r;
    }
  }
  return nullptr;
}

}  // namespace

const std::vector<ScenarioKey>& scenario_keys() {
  static const std::vector<ScenarioKey> table = make_table();
  return table;
}

const ScenarioKey& scenario_key(const std::string& key) {
  for (const ScenarioKey& k : scenario_keys()) {
    if (k.key == key) return k;
  }
  throw std::logic_error("no scenario key '" + key + "' in the key table");
}

std::vector<std::string> child_keys(const std::string& parent) {
  std::vector<std::string> children;
  const std::string prefix = parent.empty() ? "" : parent + ".";
  for (const ScenarioKey& k : scenario_keys()) {
    if (k.key.rfind(prefix, 0) != 0) continue;
    const std::string rest = k.key.substr(prefix.size());
    if (rest.find('.') == std::string::npos) children.push_back(rest);
  }
  if (children.empty()) throw std::logic_error("no keys under '" + parent + "' in the key table");
  return children;
}

const std::vector<std::string>& key_choices(const std::string& key) {
  const ScenarioKey& k = scenario_key(key);
  if (k.type != KeyType::kChoice) throw std::logic_error("'" + key + "' is not a choice");
  return k.allowed;
}

const std::string& choice_default(const std::string& key) {
  const ScenarioKey& k = scenario_key(key);
  if (k.type != KeyType::kChoice) throw std::logic_error("'" + key + "' is not a choice");
  return k.default_text;
}

bool boolean_default(const std::string& key) {
  const ScenarioKey& k = scenario_key(key);
  if (k.type != KeyType::kBoolean) throw std::logic_error("'" + key + "' is not a boolean");
  return k.default_text == "true";
}

double number_default(const std::string& key) {
  const ScenarioKey& k = scenario_key(key);
  if (!k.default_number) throw std::logic_error("'" + key + "' has no default number");
  return *k.default_number;
}

std::string scenario_keys_markdown() {
  auto cell = [](const std::string& text) {
    std::string out;
    for (char c : text) out += c == '|' ? std::string("\\|") : std::string(1, c);
    return out;
  };
  std::string md =
      "# Scenario keys: types, defaults, units and ranges\n\n"
      "Generated from `engine/schema/scenario_keys.cpp` (the key table the scenario readers "
      "take their key lists, choices and defaults from) and "
      "`engine/schema/parameter_ranges.cpp` (the ranges they check numbers against) by "
      "`scripts/update-docs`; a test fails when this page and the tables differ. List items "
      "are written without an index (`surfaces.tooth` is the `tooth` of each `surfaces:` "
      "item). A key not in this table is an error (exit 2, with a \"did you mean\").\n\n"
      "## Every key\n\n"
      "| key | type | unit | default | allowed values | what |\n"
      "|---|---|---|---|---|---|\n";
  for (const ScenarioKey& k : scenario_keys()) {
    const ParameterRange* range = range_of(k);
    std::string type, allowed;
    switch (k.type) {
      case KeyType::kMap:
        type = "map";
        allowed = "the keys below it";
        break;
      case KeyType::kList:
        type = "list of maps";
        allowed = "each item: the keys below it";
        break;
      case KeyType::kString:
        type = "text";
        break;
      case KeyType::kBoolean:
        type = "boolean";
        allowed = "true, false";
        break;
      case KeyType::kChoice:
        type = "choice";
        for (std::size_t i = 0; i < k.allowed.size(); ++i) {
          allowed += (i ? ", " : "") + std::string("`") + k.allowed[i] + "`";
        }
        break;
      case KeyType::kInteger:
        type = "integer";
        break;
      case KeyType::kNumber:
        type = "number";
        break;
      case KeyType::kParameter:
        type = "number or law";
        allowed = "`{uniform: [lo, hi]}`, `{normal: [mean, sd]}` within the valid range";
        break;
      case KeyType::kSymbolMap:
        type = "map symbol → number";
        for (std::size_t i = 0; i < k.allowed.size(); ++i) {
          allowed += (i ? "; " : "") + k.allowed[i];
        }
        break;
      case KeyType::kTeeth:
        type = "`all` or list of integers";
        allowed = "`all`, or tooth numbers 1 … z, each once";
        break;
      case KeyType::kVector3:
        type = "three numbers [x, y, z]";
        break;
      case KeyType::kSymbols:
        type = "`all` or list of names";
        allowed = "`all`, or a list of: ";
        for (std::size_t i = 0; i < k.allowed.size(); ++i) {
          allowed += (i ? ", " : "") + std::string("`") + k.allowed[i] + "`";
        }
        break;
    }
    if (range != nullptr) {
      const std::string valid =
          range->integer ? number_text(range->valid.min) + " … " + number_text(range->valid.max)
                         : range->valid.describe();
      allowed = valid + (allowed.empty() ? "" : "; " + allowed);
    } else if (k.type == KeyType::kInteger && k.integer_max > 0) {
      allowed = std::to_string(k.integer_min) + " … " + std::to_string(k.integer_max);
    } else if (k.type == KeyType::kInteger && k.integer_min > 0) {
      allowed = std::to_string(k.integer_min) + " … z";
    }
    const std::string value = k.default_number ? number_text(*k.default_number) : k.default_text;
    md += "| `" + k.key + "` | " + type + " | " + cell(range ? range->unit : "") + " | " +
          cell(value) + " | " + cell(allowed) + " | " + cell(k.description) + " |\n";
  }
  // The range tables follow, one level down.
  std::string ranges = range_reference_markdown();
  ranges = ranges.substr(ranges.find('\n') + 1);  // without its title
  std::string shifted;
  std::size_t start = 0;
  while (start < ranges.size()) {
    std::size_t end = ranges.find('\n', start);
    if (end == std::string::npos) end = ranges.size();
    std::string line = ranges.substr(start, end - start);
    if (line.rfind("## ", 0) == 0) line = "### " + line.substr(3);
    shifted += line + "\n";
    start = end + 1;
  }
  md += "\n## Numbers: units and ranges\n" + shifted;
  return md;
}

}  // namespace gearmc
