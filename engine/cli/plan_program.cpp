// A user's DMIS program as the probing plan (see plan_program.h).
#include "engine/cli/plan_program.h"

#include "core/input_error.h"
#include "engine/readings/dmis_results.h"
#include "engine/readings/point_matching.h"

namespace gearmc {

void apply_plan_program(const std::string& plan_path, Scenario& scenario) {
  if (scenario.evaluation &&
      (scenario.evaluation->profile_points > 0 || scenario.evaluation->helix_points > 0)) {
    throw InputError({scenario.source_path, 0, 0},
                     "--plan " + plan_path + ": the scenario " + scenario.source_path +
                         " asks for dedicated evaluation scans (evaluation.profile_points or "
                         "helix_points), which a user's program does not run; drop them to "
                         "evaluate the program's own profile and helix traces");
  }
  const InvoluteGear gear(scenario.gear);
  scenario.probing.points = plan_from_dmis(gear, read_dmis_plan(plan_path), plan_path);
}

}  // namespace gearmc
