// The two tolerance standards behind resolve_tolerances (tolerances.h), each in its own file:
// GOST 1643-81's table (gost_1643_81.cpp) and ISO 1328-1:2013's formulas (iso_1328_1.cpp), and
// the symbol and grade helpers they share with tolerances.cpp. Internal to gears/. Values in µm,
// the gear's sizes in mm.
#pragma once

#include <optional>
#include <string>
#include <string_view>

#include "gears/involute_gear.h"
#include "gears/tolerances.h"

namespace gearmc::tolerance_detail {

// A name for messages: the symbol in `standard`, else in the other standard.
std::string kind_label(ToleranceKind kind, ToleranceStandard standard);

// Adds to `set` the GOST 1643-81 table's norm of every tabulated kind that `spec` does not
// override, for the gear's d, m and b and the grade of the kind's group (kinematic, smoothness,
// contact). Throws ToleranceError naming every norm the table lacks.
void resolve_gost(const ToleranceSpec& spec, const InvoluteGear& gear, ToleranceSet& set);

// Adds to `set` the ISO 1328-1:2013 class value of every kind the standard's formulas give that
// `spec` does not override. Throws ToleranceError for a class outside 1 ... 11 or a gear outside
// the standard's scope.
void resolve_iso(const ToleranceSpec& spec, const InvoluteGear& gear, ToleranceSet& set);

}  // namespace gearmc::tolerance_detail
