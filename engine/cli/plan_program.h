// `--plan PROGRAM.dmi` of `gearmc run` and `gearmc simulate`: a user's own DMIS program (its
// F(…)=FEAT/POINT nominals and vectors) as the probing plan, so users simulate the program they
// really run. Each planned point is matched to its flank of the scenario's gear
// (engine/readings/point_matching.h: plan_from_dmis) and the plan replaces the scenario's grid
// (probing.points: the program's points in its order; the grid keys, teeth, flanks and order
// are then not used). A scenario with `evaluation:` is refused with it (the ISO 1328-1 traces
// come from the grid).
#pragma once

#include <string>

#include "engine/scenario/scenario.h"

namespace gearmc {

// Reads the program at `plan_path` and puts its plan into `scenario`; InputError (exit 2) for a
// bad program or a point that is not on the scenario's gear, at its statement.
void apply_plan_program(const std::string& plan_path, Scenario& scenario);

}  // namespace gearmc
