// The measurement model built once from a scenario (see measurement_model.h).
#include "engine/measurement/measurement_model.h"

#include <tbb/enumerable_thread_specific.h>

#include <string>

#include "engine/contact/contact.h"
#include "engine/contact/mesh_probe.h"
#include "gears/normal_expression.h"

namespace gearmc {

// muParser is not thread-safe: each thread compiles its own copy of the expression.
struct MeasurementModel::ThreadExpressions {
  explicit ThreadExpressions(std::string text)
      : text_(std::move(text)), per_thread([this] { return NormalExpression(text_); }) {}
  std::string text_;
  tbb::enumerable_thread_specific<NormalExpression> per_thread;
};

MeasurementModel::MeasurementModel(const Scenario& scenario)
    : scenario_(scenario), gear_(std::make_unique<InvoluteGear>(scenario.gear)) {
  tolerances_ = resolve_scenario_tolerances(scenario_, *gear_);
  sampler_ =
      std::make_unique<GearSampler>(*gear_, tolerances_, scenario_.deviations, scenario_.seed);
  extent_ = std::make_unique<FlankExtent>(FlankExtent{gear_->active_roll_length_min_mm(),
                                                      gear_->active_roll_length_max_mm(), 0.0,
                                                      gear_->face_width_mm()});
  if (!scenario_.normal_expression_um.empty()) {
    expressions_ = std::make_unique<ThreadExpressions>(scenario_.normal_expression_um);
  }
  const auto flank_index = [](int tooth, FlankSide side) {
    return 2 * static_cast<std::size_t>(tooth - 1) + (side == FlankSide::kRight ? 1 : 0);
  };
  meshes_.resize(2 * static_cast<std::size_t>(gear_->teeth()));
  for (const FlankMeshSurface& surface : scenario_.surfaces) {
    meshes_[flank_index(surface.tooth, surface.side)] = std::make_unique<MeshFlankProbe>(
        *gear_, surface.tooth, surface.side, *surface.mesh, surface.contact);
  }

  const double R = scenario_.stylus_radius_mm;
  const auto plan_point = [&](PlanPoint& q, int tooth, FlankSide side, double L, double z) {
    q.roll_length_mm = L;
    q.z_mm = z;
    q.nominal = gear_->flank_point(tooth, side, L, z);
    q.clearance_mm =
        tooth_space_clearance(*gear_, tooth, side, q.nominal.point + R * q.nominal.normal,
                              q.nominal.normal, stylus_shape(), kProbeApproachMm)
            .smallest();
  };
  if (!scenario_.probing.points.empty()) {
    // A plan point by point (a user's program): the flanks in the order the program first
    // reaches them, each point where the program has it, the sequence the program's order.
    const std::vector<ExplicitPlanPoint>& points = scenario_.probing.points;
    std::vector<int> position(meshes_.size(), -1);  // flank index -> place in flanks_
    std::size_t flanks = 0;
    for (const ExplicitPlanPoint& e : points) {
      if (position[flank_index(e.tooth, e.side)] < 0) {
        position[flank_index(e.tooth, e.side)] = static_cast<int>(flanks++);
      }
    }
    flanks_.resize(flanks);
    std::vector<std::pair<std::size_t, std::size_t>> where;  // (flank, point) of each in order
    where.reserve(points.size());
    for (const ExplicitPlanPoint& e : points) {
      PlanFlank& flank = flanks_[static_cast<std::size_t>(position[flank_index(e.tooth, e.side)])];
      flank.tooth = e.tooth;
      flank.side = e.side;
      flank.mesh = meshes_[flank_index(e.tooth, e.side)].get();
      PlanPoint& q = flank.points.emplace_back();
      q.grid_position() = e.grid_position();
      plan_point(q, e.tooth, e.side, e.roll_length_mm, e.z_mm);
      where.emplace_back(&flank - flanks_.data(), flank.points.size() - 1);
    }
    for (const auto& [f, k] : where) {  // the points no longer move: their addresses are kept
      PlanPoint& q = flanks_[f].points[k];
      q.order = static_cast<int>(sequence_.size());
      sequence_.push_back(&q);
    }
    return;
  }

  std::vector<int> teeth = scenario_.probing.teeth;
  if (teeth.empty()) {
    for (int t = 1; t <= gear_->teeth(); ++t) teeth.push_back(t);
  }
  std::vector<FlankSide> sides;
  if (scenario_.probing.left) sides.push_back(FlankSide::kLeft);
  if (scenario_.probing.right) sides.push_back(FlankSide::kRight);
  const ProbingGridCoordinates grid = probing_grid_coordinates(*gear_, scenario_.probing.grid);
  std::vector<PlanFlank*> by_index(meshes_.size(), nullptr);
  flanks_.reserve(teeth.size() * sides.size());
  for (int tooth : teeth) {
    for (FlankSide side : sides) {
      PlanFlank& flank = flanks_.emplace_back();
      flank.tooth = tooth;
      flank.side = side;
      flank.mesh = meshes_[flank_index(tooth, side)].get();
      by_index[flank_index(tooth, side)] = &flank;
      for (int j = 0; j < static_cast<int>(grid.heights.size()); ++j) {
        for (int i = 0; i < static_cast<int>(grid.roll_lengths.size()); ++i) {
          PlanPoint& q = flank.points.emplace_back();
          q.grid_position() = GridPosition{tooth, side, i, j};
          plan_point(q, tooth, side, grid.roll_lengths[i], grid.heights[j]);
        }
      }
    }
  }
  // The probing order of the scenario (tooth by tooth or flank side by side).
  const int N = static_cast<int>(grid.roll_lengths.size());
  for (const PlannedPoint& planned : probing_sequence(*gear_, scenario_.probing)) {
    PlanFlank* flank = by_index[flank_index(planned.tooth, planned.side)];
    PlanPoint& q = flank->points[static_cast<std::size_t>(planned.j * N + planned.i)];
    q.order = static_cast<int>(sequence_.size());
    sequence_.push_back(&q);
  }
}

MeasurementModel::~MeasurementModel() = default;

int MeasurementModel::points_per_flank() const {
  if (!scenario_.probing.points.empty()) {  // a program's plan: its flanks' mean, rounded up
    return static_cast<int>((sequence_.size() + 2 * static_cast<std::size_t>(probed_teeth()) - 1) /
                            (2 * static_cast<std::size_t>(probed_teeth())));
  }
  return scenario_.probing.grid.points_along_profile * scenario_.probing.grid.sections_across_face;
}

int MeasurementModel::probed_teeth() const {
  if (!scenario_.probing.points.empty()) {
    std::vector<bool> seen(static_cast<std::size_t>(gear_->teeth()) + 1, false);
    int teeth = 0;
    for (const ExplicitPlanPoint& e : scenario_.probing.points) {
      if (!seen[static_cast<std::size_t>(e.tooth)])
        seen[static_cast<std::size_t>(e.tooth)] = true, ++teeth;
    }
    return teeth;
  }
  return scenario_.probing.teeth.empty() ? gear_->teeth()
                                         : static_cast<int>(scenario_.probing.teeth.size());
}

const NormalExpression* MeasurementModel::expression() const {
  return expressions_ ? &expressions_->per_thread.local() : nullptr;
}

}  // namespace gearmc
