// The sequential decision of `gearmc check` and its Monte-Carlo driver (see sequential_check.h).
#include "engine/apps/check/sequential_check.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <optional>
#include <string>
#include <string_view>

#include "core/bytes.h"
#include "core/ranks.h"
#include "engine/evaluation/gear_parameters.h"
#include "engine/run/monte_carlo.h"
#include "engine/run/run_partials.h"

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
    if (claim.quantity == ClaimQuantity::kParameterError) {
      // measured − true (dense trace) of each item (flank, tooth or gear; F_r: one per gear).
      const std::optional<GearParameter> p = parameter_from_symbol(claim.parameter);
      if (!p || !gear.parameters) continue;
      for (const ParameterValue& v : gear.parameters->values[static_cast<int>(*p)][s]) {
        out.push_back(v.measured - v.true_dense);
      }
      continue;
    }
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
  const Ranks single;
  const Ranks& ranks = options.ranks ? *options.ranks : single;
  SequentialCheck check(claims, options.max_gears);
  CheckRun run;
  // Each gear travels as its contact counts and, per claim, its values (on the rank that ran it)
  // and reaches rank 0 in gear order, where it is fed to the sequential decision.
  std::vector<double> scratch;
  GearStream stream;
  stream.encode = [&](const GearOutcome& g, std::string& out) {
    ByteWriter w(out);
    w.put<std::uint64_t>(g.contacts);
    w.put<std::uint64_t>(g.failed);
    w.put<std::uint64_t>(g.edge);
    w.put<std::uint64_t>(g.collisions);
    for (const ClaimSpec& claim : claims) {
      scratch.clear();
      claim_values(claim, g, scratch);
      w.put<std::uint64_t>(scratch.size());
      for (double v : scratch) w.put<double>(v);
    }
  };
  std::vector<std::vector<double>> values(claims.size());
  std::vector<std::span<const double>> spans(claims.size());
  stream.consume = [&](std::string_view bytes) {
    ByteReader r(bytes);
    while (!r.done()) {
      run.contacts += r.get<std::uint64_t>();
      run.failed_contacts += r.get<std::uint64_t>();
      run.edge_contacts += r.get<std::uint64_t>();
      run.collisions += r.get<std::uint64_t>();
      for (std::size_t i = 0; i < claims.size(); ++i) {
        values[i].resize(static_cast<std::size_t>(r.get<std::uint64_t>()));
        for (double& v : values[i]) v = r.get<double>();
        spans[i] = values[i];
      }
      if (check.add_gear(spans)) {
        const double t = elapsed();
        for (std::size_t i = 0; i < claims.size(); ++i) {
          // A result made at this look has no time yet; a frozen one keeps its own.
          if (check.results()[i].time_s == 0.0) check.results()[i].time_s = t;
        }
        if (options.on_look) options.on_look(check);
      }
    }
  };
  // One batch per look: the gears up to the next look run over the ranks (each rank a contiguous
  // share of the batch's blocks), then rank 0 looks and tells every rank whether to go on. The
  // looks depend on gear counts only, so verdicts and gear counts do not depend on the number of
  // ranks or threads.
  // Gear 0 alone first, on every rank (the same gear everywhere, so every rank agrees): when none
  // of its contacts gives a value, stop before the first look.
  {
    RunOptions probe;
    probe.only_gear = 0;
    probe.threads = options.threads;
    const RunResults g = mc.run(probe);
    if (g.contacts > 0 && g.failed_contacts + g.edge_contacts + g.collisions == g.contacts) {
      run.no_values = true;
      run.contacts = g.contacts;
      run.failed_contacts = g.failed_contacts;
      run.edge_contacts = g.edge_contacts;
      run.collisions = g.collisions;
      run.wall_s = elapsed();
      return run;
    }
  }
  const std::vector<int> looks = look_points(options.max_gears);
  int first = 0;
  for (int end : looks) {
    RunOptions batch;
    batch.first_gear = first;
    batch.end_gear = end;
    batch.threads = options.threads;
    batch.cancel = options.cancel;
    batch.keep_block_moments = options.keep_run;
    RunResults r = run_on_ranks(mc, batch, ranks, stream);
    first = end;
    const bool cancelled = r.cancelled;
    if (options.keep_run && ranks.is_root() && !cancelled) {
      if (run.run_results) {
        append_partial(*run.run_results, r);
      } else {
        run.run_results = std::move(r);
      }
    }
    const std::vector<std::string> state = ranks.all_gather([&] {
      if (!ranks.is_root()) return std::string();
      return std::string(cancelled ? "c" : check.done() ? "d" : "g");
    });
    if (state[0] == "c") {
      run.cancelled = true;
      break;
    }
    if (state[0] == "d") break;
  }
  run.gears = check.gears();
  run.results = check.results();
  run.trackers = check.trackers();
  run.wall_s = elapsed();
  if (run.run_results) run.run_results->wall_s = run.wall_s;
  return run;
}

}  // namespace gearmc
