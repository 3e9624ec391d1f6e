// A user's DMIS program as the probing plan (see plan_program.h).
#include "engine/cli/plan_program.h"

#include "core/input_error.h"
#include "engine/readings/dmis_results.h"
#include "engine/readings/point_matching.h"

namespace gearmc {

void apply_plan_program(const std::string& plan_path, Scenario& scenario) {
  if (scenario.evaluation && scenario.evaluation->scans_at) {
    const EvaluationSpec& e = *scenario.evaluation;
    throw InputError(*e.scans_at, e.scans_key, e.scans_value,
                     "0 with --plan " + plan_path +
                         ": a dedicated evaluation scan is not part of a user's program; drop it "
                         "to evaluate the program's own profile and helix traces");
  }
  if (scenario.evaluation && scenario.evaluation->sections_at) {
    const EvaluationSpec& e = *scenario.evaluation;
    throw InputError(*e.sections_at, e.sections_key, e.sections_value,
                     "1 with --plan " + plan_path +
                         ": a user's program gives one profile and one helix trace per flank "
                         "(its own, docs/parameters.md)");
  }
  const InvoluteGear gear(scenario.gear);
  scenario.probing.points = plan_from_dmis(gear, read_dmis_plan(plan_path), plan_path);
}

}  // namespace gearmc
