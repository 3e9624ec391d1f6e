// A user's DMIS program as the probing plan (see plan_program.h).
#include "engine/cli/plan_program.h"

#include "core/input_error.h"
#include "engine/readings/dmis_results.h"
#include "engine/readings/point_matching.h"

namespace gearmc {

void apply_plan_program(const std::string& plan_path, Scenario& scenario) {
  if (scenario.evaluation) {
    throw InputError({scenario.source_path, 0, 0},
                     "--plan " + plan_path + ": the scenario " + scenario.source_path +
                         " has `evaluation:`, whose ISO 1328-1 traces come from the probing grid; "
                         "drop `evaluation:` to run a program's plan");
  }
  const InvoluteGear gear(scenario.gear);
  scenario.probing.points = plan_from_dmis(gear, read_dmis_plan(plan_path), plan_path);
}

}  // namespace gearmc
