// `gearmc geometry`: nominal gear geometry and resolved tolerances as JSON (docs/formats.md).
#include "engine/cli/geometry_command.h"

#include <nlohmann/json.hpp>

#include <cmath>
#include <numbers>
#include <ostream>

#include "core/input_error.h"

namespace gearmc {
namespace {

// Lengths printed to the nanometre (1e-6 mm), angles to 1e-9 degree: exact to what a gear
// metrologist reads, without binary-fraction noise like 134.39999999999998.
double mm(double value) { return std::round(value * 1e6) / 1e6; }
double deg(double value_rad) {
  return std::round(value_rad * 180.0 / std::numbers::pi * 1e9) / 1e9;
}

}  // namespace

void write_geometry_json(const Scenario& scenario, std::ostream& out) {
  using nlohmann::ordered_json;
  const InvoluteGear gear(scenario.gear);
  const ToleranceSet tolerances = resolve_scenario_tolerances(scenario, gear);
  const GearParameters& p = scenario.gear;
  const EvaluationRanges ranges = evaluation_ranges(gear);

  ordered_json doc;
  doc["scenario"] = scenario.name;
  doc["source"] = scenario.source_path;
  doc["conventions"] =
      "gear axis +Z, z = 0 on the lower face, tooth 1 centred on +X, teeth counter-clockwise; "
      "flank R: outward normal turns counter-clockwise; profile position = roll length L";
  doc["gear"] = {{"teeth", p.teeth},
                 {"module_mm", p.module_mm},
                 {"pressure_angle_deg", p.pressure_angle_deg},
                 {"profile_shift", p.profile_shift},
                 {"face_width_mm", p.face_width_mm},
                 {"basic_rack_in_modules",
                  {{"addendum", p.rack.addendum},
                   {"dedendum", p.rack.dedendum},
                   {"root_radius", p.rack.root_radius}}}};
  if (gear.internal()) {
    doc["gear"]["internal"] = true;  // the tip circle inside the reference circle, the root outside
  }
  if (gear.helical()) {  // ISO 21771 §4: the transverse section's values below are these
    doc["helix"] = {
        {"helix_angle_beta_deg", p.helix_angle_deg},
        {"hand", p.hand == Hand::kRight ? "right" : "left"},
        {"base_helix_angle_beta_b_deg", deg(gear.base_helix_angle_rad())},
        {"transverse_module_m_t_mm", mm(gear.transverse_module_mm())},
        {"transverse_pressure_angle_alpha_t_deg", deg(gear.transverse_pressure_angle_rad())},
        {"lead_p_z_mm", mm(gear.lead_mm())},
        {"normal_base_pitch_p_bn_mm",
         mm(gear.base_pitch_mm() * std::cos(gear.base_helix_angle_rad()))}};
  }
  doc["geometry_mm"] = {{"reference_diameter_d", mm(gear.reference_diameter_mm())},
                        {"tip_diameter_d_a", mm(gear.tip_diameter_mm())},
                        {"root_diameter_d_f", mm(gear.root_diameter_mm())},
                        {"base_diameter_d_b", mm(gear.base_diameter_mm())},
                        {"base_pitch_p_b", mm(gear.base_pitch_mm())},
                        {"tooth_thickness_s", mm(gear.tooth_thickness_mm())},
                        {"tip_thickness_s_a", mm(gear.tip_thickness_mm())},
                        {"form_diameter_d_Ff", mm(gear.form_diameter_mm())},
                        {"form_roll_length_L_Ff", mm(gear.form_roll_length_mm())},
                        {"tip_roll_length_L_a", mm(gear.tip_roll_length_mm())},
                        {"angular_pitch_deg", deg(gear.angular_pitch_rad())},
                        {"undercut", gear.undercut()}};
  if (gear.internal()) {  // the rack's form circle is an approximation for a pinion-type cutter
    doc["geometry_mm"]["form_diameter_from"] =
        p.form_diameter_mm ? "form_diameter_mm"
                           : "the rack (ISO 21771; a pinion-type cutter's differs)";
  }
  const FlankModifications& mods = p.modifications;
  if (mods.any()) {  // where each designed modification starts (gears/flank_modifications.h)
    ordered_json m = ordered_json::object();
    const auto profile_relief = [&](const FlankRelief& r, double start_L) {
      return ordered_json{{"amount_um", r.amount_um},
                          {"length_mm", r.length_mm},
                          {"shape", r.linear ? "linear" : "circular"},
                          {"starts_at_roll_length_mm", mm(start_L)},
                          {"starts_at_diameter_mm", mm(gear.diameter_at_roll_length(start_L))}};
    };
    if (mods.tip_relief.present()) {
      m["tip_relief"] =
          profile_relief(mods.tip_relief,
                         gear.tip_roll_length_mm() - gear.roll_sign() * mods.tip_relief.length_mm);
    }
    if (mods.root_relief.present()) {
      m["root_relief"] =
          profile_relief(mods.root_relief, gear.form_roll_length_mm() +
                                               gear.roll_sign() * mods.root_relief.length_mm);
    }
    if (mods.profile_crowning_um != 0.0) m["profile_crowning_um"] = mods.profile_crowning_um;
    if (mods.end_relief.present()) {
      m["end_relief"] = {
          {"amount_um", mods.end_relief.amount_um},
          {"length_mm", mods.end_relief.length_mm},
          {"shape", mods.end_relief.linear ? "linear" : "circular"},
          {"unrelieved_z_mm",
           {mm(mods.end_relief.length_mm), mm(p.face_width_mm - mods.end_relief.length_mm)}}};
    }
    if (mods.helix_crowning_um != 0.0) m["helix_crowning_um"] = mods.helix_crowning_um;
    if (mods.helix_slope_um != 0.0) m["helix_slope_um"] = mods.helix_slope_um;
    doc["modifications"] = m;
  }
  doc["evaluation_ranges_mm"] = {
      {"profile_roll_length", {mm(ranges.profile_start_mm), mm(ranges.profile_end_mm)}},
      {"helix_z", {mm(ranges.helix_start_mm), mm(ranges.helix_end_mm)}}};
  ordered_json values = ordered_json::object();
  for (ToleranceKind kind : all_tolerance_kinds()) {
    const auto it = tolerances.values.find(kind);
    if (it == tolerances.values.end()) continue;
    const auto symbol = tolerance_symbol(kind, tolerances.standard);
    values[symbol ? *symbol : std::to_string(static_cast<int>(kind))] = {
        {"value", it->second.value_um},
        {"source", it->second.source},
        {"confirmed", it->second.confirmed}};
  }
  doc["tolerances_um"] = {{"standard", standard_name(tolerances.standard)},
                          {"grade", tolerances.grade},
                          {"values", values}};
  out << doc.dump(2) << '\n';
}

}  // namespace gearmc
