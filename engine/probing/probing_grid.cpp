// N x M probing grid on a flank with edge margins (see probing_grid.h).
#include "engine/probing/probing_grid.h"

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
  return {spaced(gear.form_roll_length_mm(), gear.tip_roll_length_mm(), spec.margin_fraction,
                 spec.points_along_profile),
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
      points.push_back(
          {tooth, side, i, j, grid.roll_lengths[i], grid.heights[j], fp.point, fp.normal});
    }
  }
  return points;
}

}  // namespace gearmc
