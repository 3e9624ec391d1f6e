// `gearmc simulate SCENARIO --out READINGS.csv` (docs/formats.md): what a CMM would record
// measuring the scenario's gears with its effects on, as the readings CSV.
#pragma once

#include <cstdint>
#include <optional>
#include <ostream>
#include <string>

#include "engine/scenario/scenario.h"

namespace gearmc {

struct SimulateCommandOptions {
  std::string scenario_path;  // empty: the built-in reference
  std::string out;            // the readings CSV
  int gears = 1;
  ScenarioOverrides overrides;  // --seed, --gears
  bool master = false;
  bool reference_deviations = false;
  std::string plan_path;     // --plan PROGRAM.dmi: a user's DMIS program as the probing plan
  std::string command_line;  // as typed, for the outputs' provenance
};

// Returns the exit code; throws InputError for bad input.
int simulate_command(const SimulateCommandOptions& options, std::ostream& out, std::ostream& err);

}  // namespace gearmc
