// The ISO 10360-2 length test of a kinematic machine (length_test.h).
#include "engine/machine/length_test.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace gearmc {

std::vector<LengthTestPosition> length_test_positions(const Eigen::Vector3d& travel_mm) {
  std::vector<LengthTestPosition> out;
  // The line through the centre along u leaves the box |q_a| ≤ T_a/2 at t = min_a (T_a/2)/|u_a|.
  auto line = [&](const Eigen::Vector3d& u) {
    double half = std::numeric_limits<double>::infinity();
    for (int a = 0; a < 3; ++a) {
      if (std::abs(u[a]) > 1e-12) half = std::min(half, 0.5 * travel_mm[a] / std::abs(u[a]));
    }
    return 2.0 * half;
  };
  const char* signs[4] = {"ppp", "npp", "pnp", "ppn"};
  const double s[4][3] = {{1, 1, 1}, {-1, 1, 1}, {1, -1, 1}, {1, 1, -1}};
  for (int d = 0; d < 4; ++d) {
    // Along the box's own diagonal (corner to corner), not at 45°.
    const Eigen::Vector3d u =
        Eigen::Vector3d(s[d][0] * travel_mm.x(), s[d][1] * travel_mm.y(), s[d][2] * travel_mm.z())
            .normalized();
    out.push_back({std::string("diagonal_") + signs[d], u, line(u)});
  }
  for (int a = 0; a < 3; ++a) {
    const Eigen::Vector3d u = Eigen::Vector3d::Unit(a);
    out.push_back({std::string(1, "xyz"[a]), u, line(u)});
  }
  return out;
}

double kinematic_length_error_um(const KinematicMachine& machine, const Eigen::Vector3d& u,
                                 double length_mm, const LengthTestOptions& options) {
  // The gauge centred where the ram stands at the reference point (the middle of the travel):
  // the tip there is the stylus offset, in gear coordinates less the placement.
  const Eigen::Vector3d centre = options.stylus_mm - machine.placement_mm;
  const Eigen::Vector3d a = centre - (0.5 * length_mm + options.ball_radius_mm) * u;
  const Eigen::Vector3d b = centre + (0.5 * length_mm + options.ball_radius_mm) * u;
  return (machine.tip_error_um(b, options.stylus_mm) - machine.tip_error_um(a, options.stylus_mm))
      .dot(u);
}

std::vector<LengthError> length_test(const KinematicMachine& machine,
                                     const LengthTestOptions& options) {
  std::vector<LengthError> out;
  const std::vector<LengthTestPosition> positions = length_test_positions(machine.travel_mm);
  for (std::size_t p = 0; p < positions.size(); ++p) {
    for (double f : options.fractions) {
      const double length = f * positions[p].line_mm;
      out.push_back({static_cast<int>(p), length,
                     kinematic_length_error_um(machine, positions[p].direction, length, options)});
    }
  }
  return out;
}

}  // namespace gearmc
