// The sections of a scenario that say how the gear is measured: `probing:` (the grid, the teeth
// and flanks, the order) and `surfaces:` (flanks whose real surface is a triangle mesh file,
// read and checked against the nominal flank they replace). Every mistake is one InputError at
// file:line:column. Lengths in mm.
#pragma once

#include <string>
#include <vector>

#include "core/input_error.h"
#include "core/yaml_reader.h"
#include "engine/plan/probing_grid.h"
#include "engine/scenario/scenario.h"
#include "gears/involute_gear.h"

namespace gearmc {

// The plan of a scenario without `probing:` (and the start of one with it): the key table's
// defaults, every tooth.
ProbingPlanSpec probing_defaults();

// probing: the plan (schema at the definition); tooth numbers are checked against the gear's
// `gear_teeth`.
ProbingPlanSpec read_probing(const YamlMap& probing, int gear_teeth, InputWarnings* warnings);

// surfaces: the flank meshes (schema at the definition), each read and checked against the
// nominal flank of `gear`; only flanks `plan` probes; relative mesh paths are taken from the
// folder of `source_name` (the scenario file).
std::vector<FlankMeshSurface> read_surfaces(const YamlValue& value, const GearParameters& gear,
                                            const ProbingPlanSpec& plan,
                                            const std::string& source_name);

}  // namespace gearmc
