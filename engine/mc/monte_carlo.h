// The Monte-Carlo batch (docs/formats.md `run`, docs/architecture.md "What flows through the
// engine"): gear k is drawn from its own random streams, every planned point of every probed flank
// is probed with the exact contact solver, and the errors are reduced into streaming statistics. A
// flank the scenario replaces by a mesh (`surfaces:`) is probed on that mesh, with the same plan
// and result semantics, in every gear. Gears run in parallel (oneTBB) in chunks; each chunk's
// per-gear outcomes are merged in gear order, so the results are bit-identical for any thread count
// and memory does not grow with the number of gears. Errors in µm, lengths in mm.
#pragma once

#include <Eigen/Core>
#include <atomic>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <vector>

#include "engine/probing/contact.h"
#include "engine/probing/probing_grid.h"
#include "engine/scenario/scenario.h"
#include "engine/stats/relative_histogram.h"
#include "engine/stats/running_stats.h"

namespace gearmc {

class MeshFlankProbe;  // engine/probing/mesh_probe.h (keeps OpenMesh out of this header)

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
struct ProbedPoint {
  int gear, tooth;
  FlankSide side;
  int i, j;
  Eigen::Vector3d p, n;  // nominal point and outward normal
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
  int runout_redraws = 0;           // PerturbedGear::runout_redraws
  std::vector<ProbedPoint> points;  // only when asked for
};

struct RunOptions {
  int gears = 50;
  std::uint64_t seed = 1;
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
};

class MonteCarloRun {
 public:
  explicit MonteCarloRun(const Scenario& scenario);
  ~MonteCarloRun();

  // Probes gear `k` (0-based). Thread-safe.
  GearOutcome measure_gear(int k, bool record_points) const;
  RunResults run(const RunOptions& options) const;

  const InvoluteGear& gear() const { return *gear_; }
  const ToleranceSet& tolerances() const { return tolerances_; }
  const Scenario& scenario() const { return scenario_; }
  int points_per_flank() const;
  int probed_teeth() const { return static_cast<int>(teeth_.size()); }

 private:
  Scenario scenario_;
  std::unique_ptr<InvoluteGear> gear_;
  ToleranceSet tolerances_;
  std::unique_ptr<GearSampler> sampler_;
  std::vector<int> teeth_;
  std::vector<FlankSide> sides_;
  FlankExtent extent_;
  // The scenario's mesh flanks (`surfaces:`), index 2 (tooth - 1) + (R ? 1 : 0); null = the
  // analytic perturbed flank. Built once per run (AABB trees), read-only across threads.
  std::vector<std::unique_ptr<const MeshFlankProbe>> mesh_probes_;
  // Probing order of each planned point, [flank index][j * N + i], and the sequence's length
  // (the measurement effects' `order` within one gear's measurement).
  std::vector<std::vector<int>> order_;
  int sequence_length_ = 0;
  // Per planned point, [flank index][j * N + i]: the nominal point and normal, and the nominal
  // stylus path's tooth-space clearance (mm), computed once per run (they do not depend on the
  // gear drawn).
  std::vector<std::vector<FlankPoint>> nominal_;
  std::vector<std::vector<double>> nominal_clearance_;
  struct ThreadExpressions;
  std::unique_ptr<ThreadExpressions> expressions_;
};

}  // namespace gearmc
