// `gearmc check SCENARIO [--out DIR] [--max-gears N] [--seed S] [--threads T] [--junit FILE]
// [--quiet]` (docs/check.md): decides the scenario's `claims:` on gears run in batches until
// every claim is decided or the budget is reached; writes check.json and report.html (all or
// nothing) and, with --junit, the verdicts as JUnit XML; prints one line per claim. Exit 0 when
// every claim holds, 1 when one fails or is undecided at the budget, 2 on bad input.
#pragma once

#include <cstdint>
#include <iosfwd>
#include <optional>
#include <string>

#include "engine/scenario/scenario.h"

namespace gearmc {

struct CheckCommandOptions {
  std::string scenario_path;
  std::string out_dir;  // empty: results/<scenario name>/check
  int max_gears = 20000;
  ScenarioOverrides overrides;  // --seed, --gears
  int threads = 0;
  std::string junit_path;  // empty: none
  bool quiet = false;
  std::string command_line;
};

int check_command(const CheckCommandOptions& options, std::ostream& out, std::ostream& err);

}  // namespace gearmc
