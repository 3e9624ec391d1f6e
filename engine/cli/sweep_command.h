// `gearmc sweep SCENARIO --vary KEY=V1,V2,… [--vary …] [--statistic S] [--confidence C]
// [--at-most V] [--at-least V] [--out DIR] [--gears N] [--seed S] [--threads T] [--quiet]`
// (docs/sweep.md): the grid of scenario variants, each a Monte-Carlo run, and sweep.csv, sweep.json
// and report.html with the statistic against each key.
#pragma once

#include <cstdint>
#include <iosfwd>
#include <optional>
#include <string>
#include <vector>

#include "engine/scenario/scenario.h"

namespace gearmc {

struct SweepCommandOptions {
  std::string scenario_path;
  std::vector<std::string> vary;  // "KEY=V1,V2,…", at least one
  std::string statistic = "delta_rcomp.flank_max.p99_73";
  double confidence = 0.95;                 // of the bands
  std::optional<double> at_most, at_least;  // the limit (statistic's unit)
  std::string out_dir;                      // empty: results/<scenario name>_sweep
  ScenarioOverrides overrides;              // --seed, --gears
  int threads = 0;
  bool quiet = false;
  std::string command_line;
};

int sweep_command(const SweepCommandOptions& options, std::ostream& out, std::ostream& err);

}  // namespace gearmc
