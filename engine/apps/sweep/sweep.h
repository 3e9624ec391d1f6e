// `gearmc sweep`: a grid of scenario variants (e.g. stylus radius × points along the profile),
// each a whole Monte-Carlo run, and one statistic of each (e.g. the 99.73 % quantile of the
// per-flank maximum δRcomp). A variant is the scenario file with some keys set to other values
// (`--vary stylus.radius_mm=0.3,0.5,1`), checked by the scenario reader like any scenario, so a
// bad key or value gets the scenario checker's message. The grid's points are split over the ranks
// of an MPI job in contiguous shares; each point's run is MonteCarloRun::run in one process, so
// its results do not depend on the rank or thread count, and rank 0 receives them all in point
// order. Statistics in µm.
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "core/ranks.h"
#include "engine/run/monte_carlo.h"
#include "engine/scenario/scenario.h"

namespace gearmc {

// One varied key and its values (as written, YAML scalars).
struct SweepAxis {
  std::string key;                  // dotted scenario key, e.g. "stylus.radius_mm"
  std::vector<std::string> values;  // at least one, no duplicates
};
// "KEY=V1,V2,…" → axis; InputError naming --vary otherwise.
SweepAxis parse_vary(const std::string& text);

// The statistic of a point: "delta_rcomp.<point|flank_max|flank_mean>.<n|mean|std|min|max|p95|
// p99_73>", over the left flanks, the right flanks and both together; or a gear parameter's
// (`evaluation:`, docs/parameters.md) "parameters.<symbol>.<bias|u|U|U_over_T|Q_MP|
// false_accept|false_reject>": bias, u, U per side (both: the larger of the two sides, as U/T
// takes; a parameter of both flanks, F_r or a size, has only both), the others of the parameter
// as a whole (both only).
struct SweepStatistic {
  std::string text, quantity, statistic;
  std::string parameter;  // the gear parameter's symbol; empty for δRcomp
  // A ratio or rate without unit (U_over_T, Q_MP, false_accept, false_reject).
  bool ratio() const;
  // The statistic's unit: "" for the count n and the ratios, "µm" for the others.
  const char* unit() const { return statistic == "n" || ratio() ? "" : "µm"; }
};
SweepStatistic parse_sweep_statistic(const std::string& text);

// The statistic of `values`; nullopt when it does not exist (no values, a quantile with too few
// values: stats_json.h) with the reason in *note.
std::optional<double> sweep_statistic_value(const SweepStatistic& s, const ErrorStatistics& values,
                                            std::string* note);
// The quantity's statistics in `r` for side 0 (L), 1 (R) and 2 (both flanks merged).
ErrorStatistics sweep_quantity(const SweepStatistic& s, const RunResults& r, int side);

struct SweepPoint {
  std::vector<std::string> values;  // one per axis
  Scenario scenario;
};
// A parameter statistic needs every point to evaluate that parameter: InputError naming
// --statistic and the first point that does not.
void check_sweep_statistic(const SweepStatistic& s, const std::vector<SweepPoint>& points);

// "50 gears each (seed 1, the same perturbed gears at every point)" when every point runs the
// same gears; otherwise what varies ("50–200 gears", "seeds 1–3: other perturbed gears for each
// seed"). `brief`: the gear count alone ("50 gears", "50–200 gears").
std::string sweep_runs_text(const std::vector<SweepPoint>& points, bool brief = false);

// Every combination of the axes' values, the last axis fastest, each a variant of the scenario
// text `base_text` read from `base_path` (the variant's messages and relative paths use it),
// with `overrides` (--gears, --seed) applied. Throws the scenario reader's InputError, prefixed
// with the --vary values of the variant.
std::vector<SweepPoint> sweep_grid(const std::string& base_text, const std::string& base_path,
                                   const std::vector<SweepAxis>& axes,
                                   const ScenarioOverrides& overrides);

struct GearValues;

// Runs every point (each with `threads` threads) split over `ranks`; on rank 0 the results in
// point order (other ranks: empty). With `gear_values` and a δRcomp statistic `s`, also each
// point's per-gear values of s's quantity (for the bands, sweep_bands.h) into *gear_values on
// rank 0. `progress(done, total)` on rank 0 after each of its points, with the estimate
// done × ranks. Collective; an error on any rank is thrown on all.
std::vector<RunResults> run_sweep(const std::vector<SweepPoint>& points, int threads,
                                  const Ranks& ranks,
                                  const std::function<void(int, int)>& progress = {},
                                  const SweepStatistic* s = nullptr,
                                  std::vector<GearValues>* gear_values = nullptr);

}  // namespace gearmc
