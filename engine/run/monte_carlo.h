// The Monte-Carlo batch (docs/formats.md `run`, docs/architecture.md "What flows through the
// engine"): gear k is measured by the measurement pipeline (engine/measurement: drawn from its own
// random streams, every planned point of every probed flank probed with the exact contact solver
// or on the scenario's mesh flank, the effects applied) and its errors are reduced into streaming
// statistics. Gears run in parallel (oneTBB) in fixed blocks of kGearsPerBlock gears (gear k is in
// block k / kGearsPerBlock, whatever the number of threads or processes): each block's per-gear
// outcomes are reduced in gear order into the block's own moments, and the run's moments are the
// blocks' moments merged in block order (histograms and counts are exact integer merges). So the
// results are bit-identical for any thread count and for any split of the blocks over processes
// (engine/run/run_partials.h), and memory does not grow with the number of gears. Errors in µm,
// lengths in mm.
// Public API (docs/api.md): a stable part of the C++ interface, installed with its includes.
#pragma once

#include <Eigen/Core>
#include <atomic>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <vector>

#include "engine/contact/contact.h"
#include "engine/evaluation/parameter_evaluation.h"
#include "engine/measurement/measurement_model.h"
#include "engine/scenario/scenario.h"
#include "engine/statistics/relative_histogram.h"
#include "engine/statistics/running_stats.h"
#include "gears/point_key.h"

namespace gearmc {

// Moments and a histogram of relative resolution 2^-12 (any scale, relative_histogram.h) of one
// error quantity. A value that is not finite is counted in `non_finite` and nowhere else (it
// would poison the moments); the run reports such counts as a warning.
struct ErrorStatistics {
  void add(double value_um);
  void merge(const ErrorStatistics& other);
  RunningStats moments;
  RelativeHistogram histogram;
  std::uint64_t non_finite = 0;
};

// One probed point (docs/formats.md points.csv): the plan, the contact and its errors.
struct ProbedPoint : PointKey {
  Eigen::Vector3d p, n;  // nominal point (mm) and outward unit normal
  ContactResult contact;
};

// The measurement effects' part of a gear's or a run's results (scenario `effects:`): the total
// point error along n, (E' − C)·n with E' = c − R n the point reported from the recorded centre
// c, and its budget: the δRcomp normal error (E − C)·n and each effect's change of the reading.
struct EffectTotals {
  RunningStats total_signed[2];            // [0] L, [1] R, µm
  RunningStats radius_compensation;        // (E − C)·n, µm
  std::vector<RunningStats> contribution;  // per effect of the chain, µm
  // Per effect: the total error with that effect alone on, (E − C)·n + its contribution, µm
  // (first order: at micrometre size an effect's change does not depend on the others).
  std::vector<RunningStats> alone;
  void merge(const EffectTotals& other);
};

// What one gear gave.
struct GearOutcome {
  int gear = 0;
  std::vector<double> point_delta[2];  // [0] L flanks, [1] R flanks, every valid point
  std::vector<double> flank_max[2], flank_mean[2];
  std::vector<double> point_total_abs[2];  // |total point error| with effects (when any), µm
  EffectTotals effects;
  std::uint64_t contacts = 0, failed = 0, edge = 0, collisions = 0;
  int runout_redraws = 0;                         // PerturbedGear::runout_redraws
  std::vector<ProbedPoint> points;                // only when asked for
  std::optional<GearParameterValues> parameters;  // scenario `evaluation:` only
};

// Gears per block of the reduction (see the top of this file); also the parallel chunk.
inline constexpr int kGearsPerBlock = 256;

// The order-dependent part of one block's results: the moments of its values, reduced in gear
// order (Welford within a gear's values and across its gears, Chan's merge for effect totals).
struct BlockMoments {
  RunningStats point[2], flank_max[2], flank_mean[2], total_abs[2];
  EffectTotals effects;
};

// How to run, not what: the gears, the seed and everything else the run measures are the
// scenario's (Scenario::gears, Scenario::seed, …), overridden on the scenario itself.
struct RunOptions {
  // Only the gears [first_gear, end_gear) (end_gear < 0: to the scenario's run.gears);
  // first_gear must be a multiple of kGearsPerBlock (a process's share of whole blocks).
  int first_gear = 0, end_gear = -1;
  // Keep each block's moments in RunResults::block_moments (to merge partial runs exactly).
  bool keep_block_moments = false;
  int threads = 0;               // 0 = all cores
  std::optional<int> only_gear;  // re-run one gear alone (0-based index)
  bool record_points = false;
  // Called after each chunk with (gears done, gears total), from the calling thread.
  std::function<void(int, int)> progress;
  // Called with each gear's outcome in gear order (e.g. to write points.csv), calling thread.
  std::function<void(const GearOutcome&)> on_gear;
  // When set and it becomes true (e.g. from a signal handler), the run stops within about one
  // gear's time: gears not yet started are skipped and run() returns with `cancelled` set and
  // statistics of an unspecified part of the gears (to be discarded).
  const std::atomic<bool>* cancel = nullptr;
};

struct RunResults {
  ErrorStatistics point[2], flank_max[2], flank_mean[2];  // [0] L, [1] R
  ErrorStatistics total_abs[2];  // |total point error| with the effects on (when there are any)
  EffectTotals effects;
  std::uint64_t contacts = 0, failed_contacts = 0, edge_contacts = 0, collisions = 0;
  // Gears whose profile and helix shapes were drawn again to meet F_r, and the redraws in all.
  std::uint64_t runout_redrawn_gears = 0, runout_redraws = 0;
  int gears = 0;
  double wall_s = 0.0;
  bool cancelled = false;
  // With RunOptions::keep_block_moments: the blocks' moments in block order, starting at block
  // first_block; the moments above are these merged in this order.
  int first_block = 0;
  std::vector<BlockMoments> block_moments;
  // run_on_ranks over several ranks, on rank 0: bytes of partial results it received (from
  // ceil(log2 ranks) ranks of the reduction tree); the time after its own share spent waiting for
  // and receiving them, s; and the time spent decoding and merging them, s. Not written to the
  // output files.
  std::uint64_t reduction_bytes = 0;
  double gather_s = 0.0, merge_s = 0.0;
  // Merges the moments of a block that follows every block merged so far.
  void fold(const BlockMoments& block);
  std::optional<ParameterSamples> parameters;  // scenario `evaluation:` only, in gear order
};

class MonteCarloRun {
 public:
  explicit MonteCarloRun(const Scenario& scenario);
  ~MonteCarloRun();

  // Measures gear `k` (0-based) with the model's effects drawn (gear_measurement.h) and reduces
  // its points into the gear's outcome (with `evaluation:`, its parameters, and the traces for
  // the charts when `chart_traces`). Thread-safe.
  GearOutcome measure_gear(int k, bool record_points, bool chart_traces = false) const;
  RunResults run(const RunOptions& options) const;
  // The end of the gears `options` asks for: its end_gear, or the scenario's run.gears.
  int end_gear(const RunOptions& options) const {
    return options.end_gear < 0 ? scenario().gears : options.end_gear;
  }

  const MeasurementModel& model() const { return model_; }
  const InvoluteGear& gear() const { return model_.gear(); }
  const ToleranceSet& tolerances() const { return model_.tolerances(); }
  const Scenario& scenario() const { return model_.scenario(); }
  int points_per_flank() const { return model_.points_per_flank(); }
  int probed_teeth() const { return model_.probed_teeth(); }
  // The gear-parameter evaluation of the scenario's `evaluation:` (null without it).
  const ParameterEvaluator* parameter_evaluator() const { return evaluator_.get(); }

 private:
  MeasurementModel model_;
  std::unique_ptr<const ParameterEvaluator> evaluator_;
};

}  // namespace gearmc
