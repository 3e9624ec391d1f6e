// `gearmc export-plan`: the probing plan as a DMIS program (see export_plan_command.h).
#include "engine/cli/export_plan_command.h"

#include <ostream>
#include <sstream>

#include "core/input_error.h"
#include "core/output_files.h"
#include "core/provenance.h"
#include "engine/contact/contact.h"
#include "engine/contact/tooth_space.h"
#include "engine/plan/dmis_plan.h"
#include "engine/scenario/scenario.h"

namespace gearmc {
namespace {

std::string short_number(double v) {
  std::ostringstream s;
  s << v;
  return s.str();
}

}  // namespace

int export_plan_command(const ExportPlanOptions& o, std::ostream& out, std::ostream& err) {
  const Scenario scenario =
      o.scenario_path.empty() ? reference_scenario() : load_scenario_file(o.scenario_path);
  for (const std::string& w : scenario.warnings) err << "gearmc: warning: " << w << "\n";
  if (o.format != "dmis") {
    throw InputError({}, "--format", o.format, "dmis (the only plan format so far)");
  }
  check_output_file(o.out, "--out");
  const InvoluteGear gear(scenario.gear);
  const std::vector<PlannedPoint> sequence = probing_sequence(gear, scenario.probing);
  const Provenance made =
      make_provenance(o.command_line, scenario.source_path, scenario.source_text);
  // A helical gear's plan lies on the involute helicoid: its normals tilt out of the transverse
  // plane by beta_b (docs/scenarios.md), which the comment states with the helix.
  const std::string helix =
      gear.helical() ? ", helix " + short_number(scenario.gear.helix_angle_deg) + " deg " +
                           (gear.hand() == Hand::kRight ? "right" : "left") + " hand (m normal)"
                     : "";
  const std::vector<std::string> comments = {
      "made by " + provenance_line(made),
      "gear: z " + std::to_string(gear.teeth()) + ", m " + short_number(gear.module_mm()) + " mm" +
          helix + "; stylus ball radius " + short_number(scenario.stylus_radius_mm) +
          " mm (qualify the probe with it); frame: gear axis +Z, tooth 1 on +X"};
  DmisProgramOptions program;
  program.title = "gearmc probing plan of " + scenario.name;
  program.comments = comments;
  program.approach_mm = kProbeApproachMm;
  program.stylus.ball_radius_mm = scenario.stylus_radius_mm;
  if (scenario.stylus_shaft_diameter_mm > 0.0) {
    program.stylus.shaft_radius_mm = 0.5 * scenario.stylus_shaft_diameter_mm;
    program.stylus.shaft = scenario.stylus_shaft_axis == ShaftAxis::kRadial ? PlanShaftAxis::kRadial
                                                                            : PlanShaftAxis::kAxial;
  }
  write_file_atomically(o.out, dmis_program(gear, sequence, program));
  out << "gearmc export-plan: " << scenario.name << ", " << sequence.size()
      << " points in probing order (DMIS) -> " << o.out << "\n";
  return 0;
}

}  // namespace gearmc
