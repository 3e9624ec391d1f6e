// `gearmc check`'s sequential run: gears are measured in the order of their index and the
// claims are looked at after fixed gear counts — 256, 512, 1024, … (doubling), and at the budget
// — until every claim is decided or the budget is reached. The looks depend on gear counts only,
// never on threads or timing, so the same scenario and seed give the same verdicts after the
// same number of gears for any thread count. A claim's verdict is frozen at the first look that
// decides it (its bounds are confidence sequences, valid at every look:
// confidence_sequences.h).
#pragma once

#include <atomic>
#include <cstdint>
#include <functional>
#include <optional>
#include <span>
#include <vector>

#include "engine/apps/check/claim_tracker.h"
#include "engine/run/monte_carlo.h"
#include "engine/scenario/claims.h"

namespace gearmc {

class MonteCarloRun;
class Ranks;
struct GearOutcome;

inline constexpr int kFirstLookGears = 256;
inline constexpr int kDefaultMaxGears = 20000;

// The gear counts after which the claims are looked at: 256, 512, 1024, … below max_gears, then
// max_gears itself.
std::vector<int> look_points(int max_gears);

// The sequential decision over any source of per-gear values (the method tests feed it
// synthetic gears; run_check feeds it the Monte-Carlo run).
class SequentialCheck {
 public:
  SequentialCheck(const std::vector<ClaimSpec>& claims, int max_gears);

  // Adds the next gear: values[i] are claim i's values of that gear. Returns true when this gear
  // completed a look.
  bool add_gear(const std::vector<std::span<const double>>& values);
  // Every claim decided, or the budget reached.
  bool done() const;
  int gears() const { return gears_; }
  int max_gears() const { return max_gears_; }
  const std::vector<ClaimResult>& results() const { return results_; }
  std::vector<ClaimResult>& results() { return results_; }
  const std::vector<ClaimTracker>& trackers() const { return trackers_; }
  bool decided(std::size_t claim) const { return frozen_[claim]; }

 private:
  std::vector<ClaimTracker> trackers_;
  std::vector<ClaimResult> results_;
  std::vector<bool> frozen_;
  std::vector<int> looks_;
  std::size_t next_look_ = 0;
  int gears_ = 0, max_gears_ = 0;
};

// The values of `claim`'s quantity and sides in one gear's outcome, appended to `out`.
void claim_values(const ClaimSpec& claim, const GearOutcome& gear, std::vector<double>& out);

struct CheckOptions {
  int max_gears = kDefaultMaxGears;
  int threads = 0;  // 0 = all cores
  const std::atomic<bool>* cancel = nullptr;
  // The processes of an MPI job (null: this process alone). The batches run over the ranks;
  // results and on_look exist on rank 0 only.
  const Ranks* ranks = nullptr;
  // After each look, with the gears done so far (calling thread).
  std::function<void(const SequentialCheck&)> on_look;
  // Keep the run's results of every gear the check measured (CheckRun::run_results, rank 0):
  // the batches merged as one run of those gears would give them (run_partials.h).
  bool keep_run = false;
};

struct CheckRun {
  std::vector<ClaimResult> results;
  std::vector<ClaimTracker> trackers;  // for the report's histograms
  int gears = 0;
  std::uint64_t contacts = 0, failed_contacts = 0, edge_contacts = 0, collisions = 0;
  double wall_s = 0.0;
  bool cancelled = false;
  // Every contact of the first gear gave no value (failed, edge or collision): the run stopped
  // after that gear, and the claims have no values to rest on (the command refuses the scenario).
  bool no_values = false;
  // With CheckOptions::keep_run: the results of gears 0 … gears−1, bit-identical to MonteCarloRun
  // ::run of that many gears (rank 0; wall_s the check's).
  std::optional<RunResults> run_results;
};

// Measures gears 0, 1, … of the run's scenario (its seed) in batches that end at the looks (over
// the ranks of options.ranks, in parallel blocks of 256 gears), feeding them in gear order to a
// SequentialCheck on rank 0, until done. Gear 0 runs alone first (and again in the first batch):
// when none of its contacts gives a value the run stops there with no_values set and gears 0 (a
// stylus too large for the tooth space would otherwise cost a whole first look of failing gears).
// Each claim's time_s is the wall time of the look that decided it (or of the last look).
CheckRun run_check(const MonteCarloRun& mc, const std::vector<ClaimSpec>& claims,
                   const CheckOptions& options);

}  // namespace gearmc
