// The sequential decision of `gearmc check` and its Monte-Carlo driver (see sequential_check.h).
#include "engine/check/sequential_check.h"

#include <tbb/global_control.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <optional>

#include "engine/mc/monte_carlo.h"

namespace gearmc {

std::vector<int> look_points(int max_gears) {
  std::vector<int> looks;
  for (long n = kFirstLookGears; n < max_gears; n *= 2) looks.push_back(static_cast<int>(n));
  looks.push_back(max_gears);
  return looks;
}

SequentialCheck::SequentialCheck(const std::vector<ClaimSpec>& claims, int max_gears)
    : results_(claims.size()),
      frozen_(claims.size(), false),
      looks_(look_points(max_gears)),
      max_gears_(max_gears) {
  for (const ClaimSpec& c : claims) trackers_.emplace_back(c);
}

bool SequentialCheck::add_gear(const std::vector<std::span<const double>>& values) {
  ++gears_;
  for (std::size_t i = 0; i < trackers_.size(); ++i) {
    if (!frozen_[i]) trackers_[i].add_gear(values[i]);
  }
  if (next_look_ >= looks_.size() || gears_ != looks_[next_look_]) return false;
  const bool final_look = next_look_ + 1 == looks_.size();
  ++next_look_;
  for (std::size_t i = 0; i < trackers_.size(); ++i) {
    if (frozen_[i]) continue;
    // The bounds in µm (a test per grid edge) only for a result that stays: decided, or last.
    results_[i] = trackers_[i].look(final_look, false);
    frozen_[i] = results_[i].verdict != Verdict::kUndecided;
    if (frozen_[i] || final_look) results_[i] = trackers_[i].look(final_look, true);
  }
  return true;
}

bool SequentialCheck::done() const {
  if (gears_ >= max_gears_) return true;
  return std::all_of(frozen_.begin(), frozen_.end(), [](bool f) { return f; });
}

void claim_values(const ClaimSpec& claim, const GearOutcome& gear, std::vector<double>& out) {
  for (int s = 0; s < 2; ++s) {
    if (claim.side == ClaimSide::kLeft && s == 1) continue;
    if (claim.side == ClaimSide::kRight && s == 0) continue;
    const std::vector<double>& v =
        claim.quantity == ClaimQuantity::kDeltaRcompPoint      ? gear.point_delta[s]
        : claim.quantity == ClaimQuantity::kDeltaRcompFlankMax ? gear.flank_max[s]
                                                               : gear.point_total_abs[s];
    out.insert(out.end(), v.begin(), v.end());
  }
}

CheckRun run_check(const MonteCarloRun& mc, const std::vector<ClaimSpec>& claims,
                   const CheckOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  const auto elapsed = [&] {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  };
  // threads > 0: exactly that many (as MonteCarloRun::run does).
  std::optional<tbb::global_control> limit;
  std::optional<tbb::task_arena> arena;
  if (options.threads > 0) {
    limit.emplace(tbb::global_control::max_allowed_parallelism,
                  static_cast<std::size_t>(options.threads));
    arena.emplace(options.threads);
  }
  const auto cancelled = [&] { return options.cancel && options.cancel->load(); };
  SequentialCheck check(claims, options.max_gears);
  CheckRun run;
  constexpr int kChunk = kFirstLookGears;  // every look is a multiple of it, or the budget
  std::vector<std::vector<double>> values(claims.size());
  std::vector<std::span<const double>> spans(claims.size());
  while (!check.done()) {
    const int first = check.gears();
    const int count = std::min(kChunk, options.max_gears - first);
    std::vector<GearOutcome> outcomes(count);
    const auto work = [&] {
      tbb::parallel_for(0, count, [&](int c) {
        if (cancelled()) return;
        outcomes[c] = mc.measure_gear(first + c, false);
      });
    };
    if (arena) {
      arena->execute(work);
    } else {
      work();
    }
    if (cancelled()) {
      run.cancelled = true;
      break;
    }
    for (const GearOutcome& o : outcomes) {  // gear order: the same looks for any thread count
      for (std::size_t i = 0; i < claims.size(); ++i) {
        values[i].clear();
        claim_values(claims[i], o, values[i]);
        spans[i] = values[i];
      }
      run.contacts += o.contacts;
      run.failed_contacts += o.failed;
      run.edge_contacts += o.edge;
      run.collisions += o.collisions;
      if (check.add_gear(spans)) {
        const double t = elapsed();
        for (std::size_t i = 0; i < claims.size(); ++i) {
          // A result made at this look has no time yet; a frozen one keeps its own.
          if (check.results()[i].time_s == 0.0) check.results()[i].time_s = t;
        }
        if (options.on_look) options.on_look(check);
        if (check.done()) break;
      }
    }
  }
  run.gears = check.gears();
  run.results = check.results();
  run.trackers = check.trackers();
  run.wall_s = elapsed();
  return run;
}

}  // namespace gearmc
