// Monte-Carlo batch over perturbed gears (see monte_carlo.h).
#include "engine/mc/monte_carlo.h"

#include <tbb/enumerable_thread_specific.h>
#include <tbb/global_control.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <chrono>
#include <cmath>

#include "engine/effects/measurement_effect.h"
#include "engine/probing/mesh_probe.h"
#include "engine/scenario/scenario.h"
#include "gears/normal_expression.h"
#include "surfaces/analytic_flank.h"

namespace gearmc {
namespace {

constexpr int kChunk = 256;  // gears per parallel chunk (bounds memory)

std::size_t flank_index(int tooth, FlankSide side) {
  return 2 * static_cast<std::size_t>(tooth - 1) + (side == FlankSide::kRight ? 1 : 0);
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

// muParser is not thread-safe: each thread compiles its own copy of the expression.
struct MonteCarloRun::ThreadExpressions {
  explicit ThreadExpressions(std::string text)
      : text_(std::move(text)), per_thread([this] { return NormalExpression(text_); }) {}
  std::string text_;
  tbb::enumerable_thread_specific<NormalExpression> per_thread;
};

MonteCarloRun::MonteCarloRun(const Scenario& scenario)
    : scenario_(scenario), gear_(std::make_unique<InvoluteGear>(scenario.gear)) {
  tolerances_ = resolve_scenario_tolerances(scenario_, *gear_);
  sampler_ =
      std::make_unique<GearSampler>(*gear_, tolerances_, scenario_.deviations, scenario_.seed);
  teeth_ = scenario_.probing.teeth;
  if (teeth_.empty()) {
    for (int t = 1; t <= gear_->teeth(); ++t) teeth_.push_back(t);
  }
  if (scenario_.probing.left) sides_.push_back(FlankSide::kLeft);
  if (scenario_.probing.right) sides_.push_back(FlankSide::kRight);
  extent_ = {gear_->form_roll_length_mm(), gear_->tip_roll_length_mm(), 0.0,
             gear_->face_width_mm()};
  if (!scenario_.normal_expression_um.empty()) {
    expressions_ = std::make_unique<ThreadExpressions>(scenario_.normal_expression_um);
  }
  order_.resize(2 * static_cast<std::size_t>(gear_->teeth()));
  const int N = scenario_.probing.grid.points_along_profile;
  for (const PlannedPoint& q : probing_sequence(*gear_, scenario_.probing)) {
    std::vector<int>& flank = order_[flank_index(q.tooth, q.side)];
    flank.resize(static_cast<std::size_t>(points_per_flank()), -1);
    flank[static_cast<std::size_t>(q.j * N + q.i)] = sequence_length_++;
  }
  nominal_.resize(2 * static_cast<std::size_t>(gear_->teeth()));
  nominal_clearance_.resize(nominal_.size());
  const ProbingGridCoordinates grid = probing_grid_coordinates(*gear_, scenario_.probing.grid);
  const double R = scenario_.stylus_radius_mm;
  for (int tooth : teeth_) {
    for (FlankSide side : sides_) {
      std::vector<FlankPoint>& points = nominal_[flank_index(tooth, side)];
      std::vector<double>& clearance = nominal_clearance_[flank_index(tooth, side)];
      for (double z : grid.heights) {
        for (double L : grid.roll_lengths) {
          points.push_back(gear_->flank_point(tooth, side, L, z));
          const FlankPoint& fp = points.back();
          clearance.push_back(tooth_space_clearance(*gear_, tooth, side, fp.point + R * fp.normal,
                                                    fp.normal, R, kProbeApproachMm)
                                  .smallest());
        }
      }
    }
  }
  mesh_probes_.resize(2 * static_cast<std::size_t>(gear_->teeth()));
  for (const FlankMeshSurface& surface : scenario_.surfaces) {
    mesh_probes_[flank_index(surface.tooth, surface.side)] = std::make_unique<MeshFlankProbe>(
        *gear_, surface.tooth, surface.side, *surface.mesh, surface.contact);
  }
}

MonteCarloRun::~MonteCarloRun() = default;

int MonteCarloRun::points_per_flank() const {
  return scenario_.probing.grid.points_along_profile * scenario_.probing.grid.sections_across_face;
}

GearOutcome MonteCarloRun::measure_gear(int k, bool record_points) const {
  GearOutcome out;
  out.gear = k;
  const PerturbedGear g = sampler_->draw(k);
  out.runout_redraws = g.runout_redraws;
  const NormalExpression* expression = expressions_ ? &expressions_->per_thread.local() : nullptr;
  const double R = scenario_.stylus_radius_mm;
  const ProbingGridCoordinates grid = probing_grid_coordinates(*gear_, scenario_.probing.grid);
  const EffectChain& effects = *scenario_.effects;
  const EffectValues effect_values = effects.draw(scenario_.seed, k);
  std::vector<double> contributions(effects.size());
  out.effects.contribution.resize(effects.size());
  out.effects.alone.resize(effects.size());
  const int N = static_cast<int>(grid.roll_lengths.size());  // planned index j * N + i
  for (int tooth : teeth_) {
    for (FlankSide side : sides_) {
      const int s = side == FlankSide::kRight ? 1 : 0;
      const AnalyticFlank flank(*gear_, tooth, side, g.flank(tooth, side), g.eccentricity_mm,
                                expression);
      const MeshFlankProbe* mesh = mesh_probes_[flank_index(tooth, side)].get();
      double max = 0.0, sum = 0.0;
      int valid = 0;
      for (int j = 0; j < static_cast<int>(grid.heights.size()); ++j) {
        for (int i = 0; i < static_cast<int>(grid.roll_lengths.size()); ++i) {
          const double L = grid.roll_lengths[i], z = grid.heights[j];
          const std::size_t planned = static_cast<std::size_t>(j * N + i);
          const FlankPoint& fp = nominal_[flank_index(tooth, side)][planned];
          ContactResult r = mesh ? mesh->probe(fp.point, fp.normal, R)
                                 : solve_contact(flank, extent_, fp.point, fp.normal, R, L, z);
          // The real stylus path is the nominal one moved along n by |t - R| (t = (O - p)·n);
          // the clearances are 1-Lipschitz in the path's position, so a path whose nominal
          // clearance exceeds that shift (plus 1 µm) cannot collide: the exact check is skipped.
          if (r.status == ContactResult::Status::kOk &&
              nominal_clearance_[flank_index(tooth, side)][planned] -
                      std::abs((r.centre - fp.point).dot(fp.normal) - R) <
                  1e-3) {
            check_tooth_space(*gear_, tooth, side, fp.normal, R, kProbeApproachMm, &r);
          }
          ++out.contacts;
          switch (r.status) {
            case ContactResult::Status::kOk:
              out.point_delta[s].push_back(r.delta_um);
              max = std::max(max, r.delta_um);
              sum += r.delta_um;
              ++valid;
              if (!effects.empty()) {
                PointContext context;
                context.p = fp.point;
                context.n = fp.normal;
                context.contact_normal = (r.centre - r.contact).normalized();
                context.azimuth_rad = std::atan2(-fp.normal.y(), -fp.normal.x());
                context.order =
                    order_[flank_index(tooth, side)][static_cast<std::size_t>(j * N + i)];
                context.sequence_length = sequence_length_;
                context.tooth = tooth;
                context.side = side;
                context.stylus_radius_mm = R;
                RandomStream rng = point_effect_stream(scenario_.seed, k, context.order);
                effects.apply(context, effect_values, r.centre, rng, contributions);
                double total = r.normal_error_um;
                for (std::size_t e = 0; e < contributions.size(); ++e) {
                  total += contributions[e];
                  out.effects.contribution[e].add(contributions[e]);
                  out.effects.alone[e].add(r.normal_error_um + contributions[e]);
                }
                out.effects.radius_compensation.add(r.normal_error_um);
                out.effects.total_signed[s].add(total);
                out.point_total_abs[s].push_back(std::abs(total));
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
          if (record_points) out.points.push_back({k, tooth, side, i, j, fp.point, fp.normal, r});
        }
      }
      if (valid > 0) {
        out.flank_max[s].push_back(max);
        out.flank_mean[s].push_back(sum / valid);
      }
    }
  }
  return out;
}

RunResults MonteCarloRun::run(const RunOptions& options) const {
  const auto start = std::chrono::steady_clock::now();
  // threads > 0: exactly that many threads, also above the machine's core count (the global
  // limit allows them, the arena asks for them), so a thread-independence check with 2 threads
  // really runs 2 threads on a 1-CPU machine. 0: oneTBB's default (all cores).
  std::optional<tbb::global_control> limit;
  std::optional<tbb::task_arena> arena;
  if (options.threads > 0) {
    limit.emplace(tbb::global_control::max_allowed_parallelism,
                  static_cast<std::size_t>(options.threads));
    arena.emplace(options.threads);
  }
  const auto parallel = [&](const std::function<void()>& work) {
    if (arena) {
      arena->execute(work);
    } else {
      work();
    }
  };
  std::vector<int> indices;
  if (options.only_gear) {
    indices.push_back(*options.only_gear);
  } else {
    for (int k = 0; k < options.gears; ++k) indices.push_back(k);
  }
  RunResults results;
  const int total = static_cast<int>(indices.size());
  for (int first = 0; first < total; first += kChunk) {
    const int count = std::min(kChunk, total - first);
    std::vector<GearOutcome> outcomes(count);
    const auto cancelled = [&] { return options.cancel && options.cancel->load(); };
    parallel([&] {
      tbb::parallel_for(0, count, [&](int c) {
        if (cancelled()) return;
        outcomes[c] = measure_gear(indices[first + c], options.record_points);
      });
    });
    if (cancelled()) {
      results.cancelled = true;
      break;
    }
    for (const GearOutcome& o : outcomes) {  // fixed order: deterministic statistics
      for (int s = 0; s < 2; ++s) {
        for (double v : o.point_delta[s]) results.point[s].add(v);
        for (double v : o.flank_max[s]) results.flank_max[s].add(v);
        for (double v : o.flank_mean[s]) results.flank_mean[s].add(v);
        for (double v : o.point_total_abs[s]) results.total_abs[s].add(v);
      }
      results.effects.merge(o.effects);
      results.contacts += o.contacts;
      results.failed_contacts += o.failed;
      results.edge_contacts += o.edge;
      results.collisions += o.collisions;
      results.runout_redrawn_gears += o.runout_redraws > 0 ? 1 : 0;
      results.runout_redraws += static_cast<std::uint64_t>(o.runout_redraws);
      ++results.gears;
      if (options.on_gear) options.on_gear(o);
    }
    if (options.progress) options.progress(first + count, total);
  }
  results.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return results;
}

}  // namespace gearmc
