// N x M probing grid on a flank with edge margins (see probing_grid.h).
#include "engine/plan/probing_grid.h"

#include <cmath>

namespace gearmc {
namespace {

std::vector<double> spaced(double lo, double hi, double margin_fraction, int count) {
  const double a = lo + margin_fraction * (hi - lo);
  const double b = hi - margin_fraction * (hi - lo);
  std::vector<double> v(count);
  for (int k = 0; k < count; ++k) v[k] = count == 1 ? 0.5 * (a + b) : a + (b - a) * k / (count - 1);
  return v;
}

}  // namespace

ProbingGridCoordinates probing_grid_coordinates(const InvoluteGear& gear,
                                                const ProbingGridSpec& spec) {
  const double L0 = gear.form_roll_length_mm(), L1 = gear.tip_roll_length_mm();
  const double r_b = 0.5 * gear.base_diameter_mm();
  std::vector<double> roll_lengths;
  switch (spec.spacing) {
    case ProfileSpacing::kRollLength:
      roll_lengths = spaced(L0, L1, spec.margin_fraction, spec.points_along_profile);
      break;
    case ProfileSpacing::kArcLength:  // arc length from the base circle: s = L^2 / (2 r_b)
      roll_lengths = spaced(L0 * L0 / (2 * r_b), L1 * L1 / (2 * r_b), spec.margin_fraction,
                            spec.points_along_profile);
      for (double& s : roll_lengths) s = std::sqrt(2 * r_b * s);
      break;
    case ProfileSpacing::kRadius:
      roll_lengths = spaced(std::hypot(r_b, L0), std::hypot(r_b, L1), spec.margin_fraction,
                            spec.points_along_profile);
      for (double& r : roll_lengths) r = std::sqrt(r * r - r_b * r_b);
      break;
  }
  return {roll_lengths,
          spaced(0.0, gear.face_width_mm(), spec.margin_fraction, spec.sections_across_face)};
}

std::vector<PlannedPoint> plan_flank(const InvoluteGear& gear, const ProbingGridSpec& spec,
                                     int tooth, FlankSide side) {
  const ProbingGridCoordinates grid = probing_grid_coordinates(gear, spec);
  std::vector<PlannedPoint> points;
  points.reserve(grid.roll_lengths.size() * grid.heights.size());
  for (int j = 0; j < static_cast<int>(grid.heights.size()); ++j) {
    for (int i = 0; i < static_cast<int>(grid.roll_lengths.size()); ++i) {
      const FlankPoint fp = gear.flank_point(tooth, side, grid.roll_lengths[i], grid.heights[j]);
      PlannedPoint& q = points.emplace_back();
      q.grid_position() = GridPosition{tooth, side, i, j};
      q.roll_length_mm = grid.roll_lengths[i];
      q.z_mm = grid.heights[j];
      q.point = fp.point;
      q.normal = fp.normal;
    }
  }
  return points;
}

std::vector<PlannedPoint> probing_sequence(const InvoluteGear& gear, const ProbingPlanSpec& plan) {
  std::vector<int> teeth = plan.teeth;
  if (teeth.empty()) {
    for (int t = 1; t <= gear.teeth(); ++t) teeth.push_back(t);
  }
  std::vector<FlankSide> sides;
  if (plan.left) sides.push_back(FlankSide::kLeft);
  if (plan.right) sides.push_back(FlankSide::kRight);
  std::vector<PlannedPoint> sequence;
  auto append = [&](int tooth, FlankSide side) {
    for (const PlannedPoint& q : plan_flank(gear, plan.grid, tooth, side)) sequence.push_back(q);
  };
  if (plan.order == ProbingOrder::kToothByTooth) {
    for (int tooth : teeth) {
      for (FlankSide side : sides) append(tooth, side);
    }
  } else {
    for (FlankSide side : sides) {
      for (int tooth : teeth) append(tooth, side);
    }
  }
  return sequence;
}

}  // namespace gearmc
