// The sections of a scenario that define the gear to be drawn: `gear:` (the spur gear's
// parameters), `tolerances:` (standard, grade, overrides) and `deviations:` (the laws of the random
// deviations and the deterministic `normal_um`), each read into its typed, validated value; and
// the check that the resolved tolerances let the gear sampler draw gears (F_r against the profile
// and helix shapes). Every mistake is one InputError at file:line:column. Units as the keys say
// (mm, degrees, µm).
#pragma once

#include <optional>
#include <string>

#include "core/input_error.h"
#include "core/yaml_reader.h"
#include "engine/scenario/scenario.h"
#include "gears/deviations.h"
#include "gears/involute_gear.h"
#include "gears/tolerances.h"

namespace gearmc {

// gear: the spur gear (schema at the definition); throws InputError at the `gear` key when the
// parameters together do not make a gear.
GearParameters read_gear(const YamlMap& gear, InputWarnings* warnings);

// tolerances: standard, grade and overrides_um (schema at the definition).
ToleranceSpec read_tolerances(const YamlMap& tolerances, InputWarnings* warnings);

// deviations: the laws of the random deviation groups and `normal_um`, which is compiled here so
// that its errors point into the file and stored in `normal_expression_um` (schema at the
// definition).
DeviationModel read_deviations(const YamlMap& deviations, std::string* normal_expression_um,
                               InputWarnings* warnings);

// Resolves the scenario's tolerances for its gear and checks that F_r can hold what the profile
// and helix tolerances alone produce (see the definition); errors are placed at the override,
// the grade, the tolerances section or the gear, warnings are added to scenario.warnings.
void check_tolerances(Scenario& scenario, const YamlMap& gear_map,
                      const std::optional<YamlMap>& tolerances);

}  // namespace gearmc
