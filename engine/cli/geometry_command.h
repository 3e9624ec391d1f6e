// `gearmc geometry [SCENARIO]`: the nominal geometry of the scenario's gear and its resolved
// tolerances as JSON (lengths mm, angles degrees, tolerances µm with their sources).
#pragma once

#include <iosfwd>

#include "engine/scenario/scenario.h"

namespace gearmc {

// Writes the JSON document (2-space indented, newline-terminated). Throws InputError when the
// tolerance standard cannot resolve a value the scenario needs.
void write_geometry_json(const Scenario& scenario, std::ostream& out);

}  // namespace gearmc
