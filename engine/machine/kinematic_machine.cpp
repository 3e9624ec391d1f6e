// The kinematic machine's tip error (kinematic_machine.h).
#include "engine/machine/kinematic_machine.h"

#include <Eigen/Geometry>
#include <stdexcept>

namespace gearmc {

MachineLayout parse_machine_layout(const std::string& name) {
  if (name == "bridge") return MachineLayout::kBridge;
  if (name == "gantry") return MachineLayout::kGantry;
  if (name == "horizontal_arm") return MachineLayout::kHorizontalArm;
  throw std::invalid_argument("expected bridge, gantry or horizontal_arm, got '" + name + "'");
}

std::string machine_layout_name(MachineLayout layout) {
  switch (layout) {
    case MachineLayout::kBridge:
      return "bridge";
    case MachineLayout::kGantry:
      return "gantry";
    case MachineLayout::kHorizontalArm:
      return "horizontal_arm";
  }
  return "?";
}

double legendre_series(const std::vector<double>& c, double u) {
  double sum = 0.0, p_prev = 1.0, p = u;
  for (std::size_t k = 0; k < c.size(); ++k) {
    if (k == 0) {
      sum += c[0];
      continue;
    }
    if (k >= 2) {
      // (k) P_k = (2k − 1) u P_{k−1} − (k − 1) P_{k−2}
      const auto kd = static_cast<double>(k);
      const double next = ((2.0 * kd - 1.0) * u * p - (kd - 1.0) * p_prev) / kd;
      p_prev = p;
      p = next;
    }
    sum += c[k] * p;
  }
  return sum;
}

std::array<int, 3> KinematicMachine::stacking() const {
  // Bridge and gantry: the bridge (or gantry) moves along y on the base, the carriage along x on
  // it, the ram along z in the carriage. Horizontal arm: the column along x, the carriage along z
  // on the column, the arm along y.
  return layout == MachineLayout::kHorizontalArm ? std::array<int, 3>{0, 2, 1}
                                                 : std::array<int, 3>{1, 0, 2};
}

Eigen::Vector3d KinematicMachine::axis_positions_mm(const Eigen::Vector3d& tip_mm,
                                                    const Eigen::Vector3d& stylus_mm) const {
  return tip_mm - stylus_mm + placement_mm;
}

Eigen::Vector3d KinematicMachine::tip_error_um(const Eigen::Vector3d& tip_mm,
                                               const Eigen::Vector3d& stylus_mm) const {
  const Eigen::Vector3d q = axis_positions_mm(tip_mm, stylus_mm);
  const std::array<int, 3> order = stacking();
  Eigen::Vector3d e = Eigen::Vector3d::Zero();
  for (int i = 0; i < 3; ++i) {
    const int a = order[static_cast<std::size_t>(i)];
    const double u = q[a] / (0.5 * travel_mm[a]);
    const AxisErrors& f = axes[static_cast<std::size_t>(a)];
    Eigen::Vector3d delta, epsilon;
    for (int k = 0; k < 3; ++k) {
      delta[k] = legendre_series(f.translation_um[static_cast<std::size_t>(k)], u);
      epsilon[k] = legendre_series(f.rotation_urad[static_cast<std::size_t>(k)], u);
    }
    // The Abbe arm: what the axis carries — the axes after it in the stack and the stylus.
    Eigen::Vector3d arm = stylus_mm;
    for (int j = i + 1; j < 3; ++j) {
      const int b = order[static_cast<std::size_t>(j)];
      arm[b] += q[b];
    }
    e += delta + 1e-3 * epsilon.cross(arm);
  }
  e.x() += 1e-3 * (squareness_xy_urad * q.y() + squareness_xz_urad * q.z());
  e.y() += 1e-3 * squareness_yz_urad * q.z();
  return e;
}

}  // namespace gearmc
