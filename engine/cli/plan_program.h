// `--plan PROGRAM.dmi` of `gearmc run` and `gearmc simulate`: a user's own DMIS program (its
// F(…)=FEAT/POINT nominals and vectors) as the probing plan, so users simulate the program they
// really run. Each planned point is matched to its flank of the scenario's gear
// (engine/readings/point_matching.h: plan_from_dmis) and the plan replaces the scenario's grid
// (probing.points: the program's points in its order; the grid keys, teeth, flanks and order
// are then not used). With `evaluation:` the ISO 1328-1 parameters come from the program's own
// profile and helix traces (engine/evaluation/parameter_evaluation.h); dedicated evaluation
// scans (`profile_points`, `helix_points`) are refused with it: the program does not run them.
#pragma once

#include <string>

#include "engine/scenario/scenario.h"

namespace gearmc {

// Reads the program at `plan_path` and puts its plan into `scenario`; InputError (exit 2) for a
// bad program or a point that is not on the scenario's gear, at its statement.
void apply_plan_program(const std::string& plan_path, Scenario& scenario);

}  // namespace gearmc
