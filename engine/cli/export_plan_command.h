// `gearmc export-plan SCENARIO --format dmis --out FILE` (docs/formats.md): the scenario's probing
// plan as a DMIS program (engine/plan/dmis_plan.h), to run the plan gearmc simulates on a
// real CMM.
#pragma once

#include <iosfwd>
#include <string>

namespace gearmc {

struct ExportPlanOptions {
  std::string scenario_path;  // empty: the built-in reference scenario
  std::string format = "dmis";
  std::string out;
  std::string command_line;
};

// Throws InputError for bad input (unknown format, unwritable file).
int export_plan_command(const ExportPlanOptions& options, std::ostream& out, std::ostream& err);

}  // namespace gearmc
