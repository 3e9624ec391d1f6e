// The nearest point of a nominal flank to a point in space by a nested grid search over the
// flank's parameters (41 x 41 nodes, the box shrinking 4 times per level, 16 levels; no Newton,
// no closed form), for the tests of balls in tooth spaces (dimension over and between balls).
#pragma once

#include <Eigen/Core>

#include "gears/involute_gear.h"

namespace gearmc::testing_support {

struct NearestFlankPoint {
  double distance_mm, roll_length_mm, z_mm;
};

// Starts at (L, z) with a half-width of 3 mm.
inline NearestFlankPoint nearest_flank_point(const InvoluteGear& g, int tooth, FlankSide side,
                                             const Eigen::Vector3d& x, double L, double z) {
  double half = 3.0, best = 1e9;
  for (int level = 0; level < 16; ++level) {
    double bL = L, bz = z;
    for (int a = -20; a <= 20; ++a) {
      for (int b = -20; b <= 20; ++b) {
        const double Lc = L + half * a / 20, zc = z + half * b / 20;
        const double d = (g.flank_point(tooth, side, Lc, zc).point - x).norm();
        if (d < best) best = d, bL = Lc, bz = zc;
      }
    }
    L = bL, z = bz, half *= 0.25;
  }
  return {best, L, z};
}

}  // namespace gearmc::testing_support
