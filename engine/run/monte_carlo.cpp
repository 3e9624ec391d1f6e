// Monte-Carlo batch over perturbed gears (see monte_carlo.h).
#include "engine/run/monte_carlo.h"

#include <tbb/parallel_for.h>
#include <tbb/task_group.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>

#include "core/thread_arena.h"
#include "engine/measurement/gear_measurement.h"

namespace gearmc {
namespace {

constexpr int kChunk = kGearsPerBlock;  // gears per parallel chunk (bounds memory)

// A value into the run's exact part (histogram, non-finite count) and the block's moments.
void add_value(ErrorStatistics& run, RunningStats& block, double value_um) {
  if (!std::isfinite(value_um)) {
    ++run.non_finite;
    return;
  }
  block.add(value_um);
  run.histogram.add(value_um);
}

}  // namespace

void ErrorStatistics::add(double value_um) {
  if (!std::isfinite(value_um)) {
    ++non_finite;
    return;
  }
  moments.add(value_um);
  histogram.add(value_um);
}
void ErrorStatistics::merge(const ErrorStatistics& other) {
  moments.merge(other.moments);
  histogram.merge(other.histogram);
  non_finite += other.non_finite;
}

void EffectTotals::merge(const EffectTotals& other) {
  for (int s = 0; s < 2; ++s) total_signed[s].merge(other.total_signed[s]);
  radius_compensation.merge(other.radius_compensation);
  if (contribution.size() < other.contribution.size()) {
    contribution.resize(other.contribution.size());
    alone.resize(other.contribution.size());
  }
  for (std::size_t e = 0; e < other.contribution.size(); ++e) {
    contribution[e].merge(other.contribution[e]);
    alone[e].merge(other.alone[e]);
  }
}

void RunResults::fold(const BlockMoments& b) {
  for (int s = 0; s < 2; ++s) {
    point[s].moments.merge(b.point[s]);
    flank_max[s].moments.merge(b.flank_max[s]);
    flank_mean[s].moments.merge(b.flank_mean[s]);
    total_abs[s].moments.merge(b.total_abs[s]);
  }
  effects.merge(b.effects);
}

MonteCarloRun::MonteCarloRun(const Scenario& scenario) : model_(scenario) {
  if (model_.scenario().evaluation) {
    evaluator_ = std::make_unique<const ParameterEvaluator>(model_, *model_.scenario().evaluation);
  }
}

MonteCarloRun::~MonteCarloRun() = default;

GearOutcome MonteCarloRun::measure_gear(int k, bool record_points, bool chart_traces) const {
  GearOutcome out;
  out.gear = k;
  const GearMeasurement measurement(model_, k, EffectMode::kDrawn);
  out.runout_redraws = measurement.perturbed().runout_redraws;
  const bool with_effects = !model_.effects().empty();
  out.effects.contribution.resize(model_.effects().size());
  out.effects.alone.resize(model_.effects().size());
  std::optional<ParameterEvaluator::Gear> parameters;
  if (evaluator_) parameters.emplace(*evaluator_, measurement);
  std::size_t points_per_side[2] = {0, 0};  // one allocation per side, not ~11 doublings
  for (const PlanFlank& flank : model_.flanks()) {
    points_per_side[flank.side == FlankSide::kRight ? 1 : 0] += flank.points.size();
  }
  for (int s : {0, 1}) out.point_delta[s].reserve(points_per_side[s]);
  int flank_index = 0;
  for (const PlanFlank& flank : model_.flanks()) {
    const int s = flank.side == FlankSide::kRight ? 1 : 0;
    double max = 0.0, sum = 0.0;
    int valid = 0;
    measurement.measure_flank(flank, [&](const PointMeasurement& m) {
      const ContactResult& r = m.contact;
      if (parameters) parameters->record(flank_index, m);
      ++out.contacts;
      switch (r.status) {
        case ContactResult::Status::kOk:
          out.point_delta[s].push_back(r.delta_um);
          max = std::max(max, r.delta_um);
          sum += r.delta_um;
          ++valid;
          if (with_effects) {
            for (std::size_t e = 0; e < m.contributions.size(); ++e) {
              out.effects.contribution[e].add(m.contributions[e]);
              out.effects.alone[e].add(r.normal_error_um + m.contributions[e]);
            }
            out.effects.radius_compensation.add(r.normal_error_um);
            out.effects.total_signed[s].add(m.total_error_um);
            out.point_total_abs[s].push_back(std::abs(m.total_error_um));
          }
          break;
        case ContactResult::Status::kEdge:
          ++out.edge;
          break;
        case ContactResult::Status::kCollision:
          ++out.collisions;
          break;
        case ContactResult::Status::kNotConverged:
        case ContactResult::Status::kUncertified:  // reason in r.failure
          ++out.failed;
          break;
      }
      if (record_points) {
        const PlanPoint& q = *m.plan;
        ProbedPoint& probed = out.points.emplace_back();
        probed.key() = point_key(k, q);
        probed.p = q.nominal.point;
        probed.n = q.nominal.normal;
        probed.contact = r;
      }
    });
    if (valid > 0) {
      out.flank_max[s].push_back(max);
      out.flank_mean[s].push_back(sum / valid);
    }
    ++flank_index;
  }
  if (parameters) out.parameters = parameters->finish(chart_traces);
  return out;
}

RunResults MonteCarloRun::run(const RunOptions& options) const {
  const auto start = std::chrono::steady_clock::now();
  ThreadArena arena(options.threads);  // --threads (thread_arena.h)
  const auto parallel = [&](const std::function<void()>& work) { arena.run(work); };
  std::vector<int> indices;
  if (options.only_gear) {
    indices.push_back(*options.only_gear);
  } else {
    const int end = end_gear(options);
    if (options.first_gear % kGearsPerBlock != 0) {
      throw std::invalid_argument("MonteCarloRun::run: first_gear is not at a block boundary");
    }
    for (int k = options.first_gear; k < end; ++k) indices.push_back(k);
  }
  RunResults results;
  results.first_block = options.only_gear ? 0 : options.first_gear / kGearsPerBlock;
  if (evaluator_) results.parameters.emplace();
  const int total = static_cast<int>(indices.size());
  const auto cancelled = [&] { return options.cancel && options.cancel->load(); };
  // Merges one measured chunk into the results, in gear order (deterministic statistics).
  const auto merge = [&](std::vector<GearOutcome>& outcomes, int first) {
    BlockMoments block;
    for (GearOutcome& o : outcomes) {
      if (o.parameters) results.parameters->append(o.gear, std::move(*o.parameters));
      for (int s = 0; s < 2; ++s) {
        for (double v : o.point_delta[s]) add_value(results.point[s], block.point[s], v);
        for (double v : o.flank_max[s]) add_value(results.flank_max[s], block.flank_max[s], v);
        for (double v : o.flank_mean[s]) add_value(results.flank_mean[s], block.flank_mean[s], v);
        for (double v : o.point_total_abs[s]) {
          add_value(results.total_abs[s], block.total_abs[s], v);
        }
      }
      block.effects.merge(o.effects);
      results.contacts += o.contacts;
      results.failed_contacts += o.failed;
      results.edge_contacts += o.edge;
      results.collisions += o.collisions;
      results.runout_redrawn_gears += o.runout_redraws > 0 ? 1 : 0;
      results.runout_redraws += static_cast<std::uint64_t>(o.runout_redraws);
      ++results.gears;
      if (options.on_gear) options.on_gear(o);
    }
    results.fold(block);
    if (options.keep_block_moments) results.block_moments.push_back(std::move(block));
    if (options.progress) options.progress(first + static_cast<int>(outcomes.size()), total);
  };
  // A pipeline of two stages: while the arena's threads measure chunk i + 1, this thread merges
  // chunk i (the merge is serial, so without the overlap the other cores would idle through
  // it), then helps measuring. At most two chunks of outcomes are alive; chunks are merged in
  // order, so the results stay bit-identical for any thread count. With one thread the chunk's
  // measuring task runs when this thread waits for it, after the merge.
  parallel([&] {
    std::vector<GearOutcome> measured;  // the chunk waiting for its merge (never empty when set)
    int measured_first = 0;
    for (int first = 0; first < total; first += kChunk) {
      const int count = std::min(kChunk, total - first);
      std::vector<GearOutcome> outcomes(count);
      tbb::task_group measuring;
      measuring.run([&] {
        tbb::parallel_for(0, count, [&](int c) {
          if (cancelled()) return;
          // The first gear of the run is the one whose traces the report charts.
          outcomes[c] = measure_gear(indices[first + c], options.record_points, first + c == 0);
        });
      });
      try {
        if (!measured.empty()) merge(measured, measured_first);
      } catch (...) {
        measuring.cancel();  // outcomes and indices must outlive the measuring task
        try {
          measuring.wait();
        } catch (...) {  // the merge's exception is the one reported
        }
        throw;
      }
      measured.clear();
      measured.shrink_to_fit();
      measuring.wait();
      if (cancelled()) {
        results.cancelled = true;
        return;
      }
      measured = std::move(outcomes);
      measured_first = first;
    }
    if (!measured.empty()) merge(measured, measured_first);
  });
  results.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return results;
}

}  // namespace gearmc
