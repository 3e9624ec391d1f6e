// The outputs of `gearmc sweep` (docs/sweep.md): sweep.csv (one row per grid point), sweep.json
// (the grid, the statistic per point for the left, right and both flanks, counts, provenance) and
// report.html with one figure per varied key: the statistic (both flanks) against that key's
// values, one line per level of the other keys. Values in µm.
#pragma once

#include <array>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "core/provenance.h"
#include "engine/apps/sweep/sweep.h"
#include "engine/apps/sweep/sweep_bands.h"

namespace gearmc {

struct SweepValue {
  std::optional<double> value;
  std::string note;
};

struct SweepOutcome {
  std::string scenario_name, source_path;
  std::vector<SweepAxis> axes;
  SweepStatistic statistic;
  std::vector<SweepPoint> points;
  std::vector<RunResults> results;                // one per point, in point order
  std::vector<std::array<SweepValue, 3>> values;  // optional: sweep_values' result, kept
  // One per point (empty: no bands): the statistic's confidence bands (sweep_bands.h).
  std::vector<std::array<SweepBand, 3>> bands;
  double confidence = 0.95;
  int resamples = kSweepResamples;
  SweepLimit limit;  // --at-most / --at-least (none: no verdicts)
  int ranks = 1, threads = 1;
  double wall_s = 0.0;
  Provenance provenance;
};

// A gear parameter's statistic at one point (sweep.h) from the run's parameter presentation, as
// the run report states it: [0] L, [1] R, [2] both (the larger side, or the parameter as a whole).
std::array<SweepValue, 3> sweep_parameter_values(const SweepStatistic& stat,
                                                 const MonteCarloRun& mc, const RunResults& r);

// Statistic values per point: [point][side 0 L, 1 R, 2 both]; nullopt with a note when missing.
// `values` of the outcome when set (the command computes them once: a parameter statistic
// evaluates each point's parameters), else computed from the results.
std::vector<std::array<SweepValue, 3>> sweep_values(const SweepOutcome& s);

// The bands of every point at the outcome's confidence: δRcomp statistics from each point's
// per-gear values (run_sweep's gear_values), parameter statistics from the point's run.
std::vector<std::array<SweepBand, 3>> sweep_point_bands(const SweepOutcome& s,
                                                        const std::vector<GearValues>& gears);
// The verdict of each point's "both" value against the limit (sweep_verdict); empty without one.
std::vector<SweepVerdict> sweep_verdicts(const SweepOutcome& s);

std::string sweep_csv(const SweepOutcome& s);
nlohmann::ordered_json sweep_json(const SweepOutcome& s);
// The figures: one SVG per axis (statistic of both flanks against the axis' values).
std::vector<std::string> sweep_figures(const SweepOutcome& s);
std::string sweep_report_html(const SweepOutcome& s, const std::vector<std::string>& figures);

}  // namespace gearmc
