// Monte-Carlo batch over perturbed gears (see monte_carlo.h).
#include "engine/mc/monte_carlo.h"

#include <tbb/enumerable_thread_specific.h>
#include <tbb/global_control.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <chrono>

#include "engine/cli/geometry_command.h"
#include "gears/normal_expression.h"
#include "surfaces/analytic_flank.h"

namespace gearmc {
namespace {

constexpr double kApproachMm = 1.0;  // stylus pre-position distance outside the planned point
constexpr int kChunk = 256;          // gears per parallel chunk (bounds memory)

}  // namespace

ErrorStatistics::ErrorStatistics() : histogram(0.0, 0.001, 50000) {}
void ErrorStatistics::add(double value_um) {
  moments.add(value_um);
  histogram.add(value_um);
}
void ErrorStatistics::merge(const ErrorStatistics& other) {
  moments.merge(other.moments);
  histogram.merge(other.histogram);
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
}

MonteCarloRun::~MonteCarloRun() = default;

int MonteCarloRun::points_per_flank() const {
  return scenario_.probing.grid.points_along_profile * scenario_.probing.grid.sections_across_face;
}

GearOutcome MonteCarloRun::measure_gear(int k, bool record_points) const {
  GearOutcome out;
  out.gear = k;
  const PerturbedGear g = sampler_->draw(k);
  const NormalExpression* expression = expressions_ ? &expressions_->per_thread.local() : nullptr;
  const double R = scenario_.stylus_radius_mm;
  const ProbingGridCoordinates grid = probing_grid_coordinates(*gear_, scenario_.probing.grid);
  for (int tooth : teeth_) {
    for (FlankSide side : sides_) {
      const int s = side == FlankSide::kRight ? 1 : 0;
      const AnalyticFlank flank(*gear_, tooth, side, g.flank(tooth, side), g.eccentricity_mm,
                                expression);
      double max = 0.0, sum = 0.0;
      int valid = 0;
      for (int j = 0; j < static_cast<int>(grid.heights.size()); ++j) {
        for (int i = 0; i < static_cast<int>(grid.roll_lengths.size()); ++i) {
          const double L = grid.roll_lengths[i], z = grid.heights[j];
          const FlankPoint fp = gear_->flank_point(tooth, side, L, z);
          ContactResult r = solve_contact(flank, extent_, fp.point, fp.normal, R, L, z);
          check_tooth_space(*gear_, tooth, side, fp.normal, R, kApproachMm, &r);
          ++out.contacts;
          switch (r.status) {
            case ContactResult::Status::kOk:
              out.point_delta[s].push_back(r.delta_um);
              max = std::max(max, r.delta_um);
              sum += r.delta_um;
              ++valid;
              break;
            case ContactResult::Status::kEdge:
              ++out.edge;
              break;
            case ContactResult::Status::kCollision:
              ++out.collisions;
              break;
            case ContactResult::Status::kNotConverged:
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
  std::optional<tbb::global_control> limit;
  if (options.threads > 0) {
    limit.emplace(tbb::global_control::max_allowed_parallelism,
                  static_cast<std::size_t>(options.threads));
  }
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
    tbb::parallel_for(0, count, [&](int c) {
      outcomes[c] = measure_gear(indices[first + c], options.record_points);
    });
    for (const GearOutcome& o : outcomes) {  // fixed order: deterministic statistics
      for (int s = 0; s < 2; ++s) {
        for (double v : o.point_delta[s]) results.point[s].add(v);
        for (double v : o.flank_max[s]) results.flank_max[s].add(v);
        for (double v : o.flank_mean[s]) results.flank_mean[s].add(v);
      }
      results.contacts += o.contacts;
      results.failed_contacts += o.failed;
      results.edge_contacts += o.edge;
      results.collisions += o.collisions;
      ++results.gears;
      if (options.on_gear) options.on_gear(o);
    }
    if (options.progress) options.progress(first + count, total);
  }
  results.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return results;
}

}  // namespace gearmc
