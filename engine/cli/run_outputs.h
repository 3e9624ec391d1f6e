// The files of a Monte-Carlo run's results, shared by `gearmc run` and `gearmc check` (which
// writes the run report of the gears its claims rest on into run/): summary.json,
// histograms.csv, the figures (SVG) and report.html, into an all-or-nothing OutputFiles set
// (core/output_files.h). docs/formats.md `run`.
#pragma once

#include <optional>
#include <string>

#include "core/output_files.h"
#include "engine/reports/parameter_report.h"
#include "engine/reports/run_report.h"
#include "engine/run/monte_carlo.h"

namespace gearmc {

struct RunOutputs {
  RunPresentation view;
  std::optional<ParameterPresentation> parameters;  // scenario `evaluation:` only
};

// Writes the run files of `r` (results of `mc` on `scenario`, whose run.gears says how many gears
// the run asked for) into `files`; `command_line` for the provenance, `ranks` and `threads` for
// summary.json. Returns what the terminal summary prints.
RunOutputs write_run_files(OutputFiles& files, const Scenario& scenario, const MonteCarloRun& mc,
                           const RunResults& r, const std::string& command_line, int ranks,
                           int threads, std::optional<int> only_gear = std::nullopt);

}  // namespace gearmc
