// `gearmc run [SCENARIO] [--out DIR] [--gears N] [--seed S] [--threads T] [--points]
// [--only-gear K] [--quiet]` (docs/formats.md): the Monte-Carlo batch and its outputs —
// summary.json, histogram counts (CSV), histogram pictures (SVG), report.html and, with
// --points, points.csv — written under temporary names and renamed when complete.
#pragma once

#include <cstdint>
#include <iosfwd>
#include <optional>
#include <string>

#include "engine/scenario/scenario.h"

namespace gearmc {

struct RunCommandOptions {
  std::string scenario_path;    // empty: the built-in reference scenario
  std::string out_dir;          // empty: results/<scenario name>
  ScenarioOverrides overrides;  // --seed, --gears
  int threads = 0;
  bool points = false;
  std::optional<int> only_gear;
  bool quiet = false;
  bool force = false;        // write points.csv even above the size limit
  std::string plan_path;     // --plan PROGRAM.dmi: a user's DMIS program as the probing plan
  std::string command_line;  // as typed, for the outputs' provenance
};

// Runs the command; throws InputError for bad input. `out` gets the terminal summary, `err`
// the progress bar (only when it is a terminal and not quiet).
int run_command(const RunCommandOptions& options, std::ostream& out, std::ostream& err);

}  // namespace gearmc
