// The CMM as a kinematic machine: the rigid-body model of ISO 230-1 for three linear axes. Each
// axis a ∈ {x, y, z} carries six error functions of its own position q_a — one positioning error
// (along a), two straightness errors (across a) and three angular errors (roll about a, and the
// pitch and yaw about the two other axes) — and the three pairs of axes have a squareness error:
// 21 functions in all (ISO 230-1:2012 §3, the "21 parametric errors" of a three-axis machine;
// Schwenke et al., "Geometric error measurement and compensation of machines — an update",
// CIRP Annals 57, 2008). The axes are stacked in the layout's order from the base to the probe
// (bridge and gantry: Y carries X carries Z; horizontal arm: X carries Z carries Y), and an
// axis's angular error turns everything it carries: the axes after it and the stylus offset t,
// which is what makes an angular error matter (the Abbe principle). To first order (errors of
// µm and µrad) the error of the probe tip is
//   e = Σ_axes [ δ_a(q_a) + ε_a(q_a) × r_a ] + squareness,
//   r_a = Σ_{b after a} q_b ê_b + t    (the Abbe arm of axis a, mm),
//   squareness: e_x += γ_xy q_y + γ_xz q_z, e_y += γ_yz q_z  (γ > 0: the first axis leans towards
//   the second one's positive direction, as the `squareness` effect),
// with δ in µm, ε and γ in µrad (ε × r and γ q in µrad·mm = 1e-3 µm).
//
// Frames and units. Machine coordinates are those of the gear (mm, the gear's centre at the
// machine's reference point, the middle of the travel, unless `placement_mm` moves it), and an
// axis's position q_a is the coordinate of the ram's reference point: the tip position minus the
// stylus offset, plus the placement. Every function is a Legendre series in u = q_a / (T_a/2) ∈
// [−1, 1] over the axis's travel T_a (P_0 … P_K; Abramowitz & Stegun 22.2.10): coefficients in
// µm (δ) or µrad (ε). The Abbe arms are measured from the reference point, where the scales are
// taken to be.
#pragma once

#include <Eigen/Core>
#include <array>
#include <string>
#include <vector>

namespace gearmc {

enum class MachineLayout { kBridge, kGantry, kHorizontalArm };

// "bridge", "gantry", "horizontal_arm"; throws std::invalid_argument otherwise.
MachineLayout parse_machine_layout(const std::string& name);
std::string machine_layout_name(MachineLayout layout);

// The error functions of one axis, each a Legendre series in u (coefficient k of P_k).
struct AxisErrors {
  // Translations along x, y, z (µm): the component along the axis itself is its positioning
  // error, the other two its straightness errors.
  std::array<std::vector<double>, 3> translation_um;
  // Rotations about x, y, z (µrad): about the axis itself its roll, about the others pitch and yaw.
  std::array<std::vector<double>, 3> rotation_urad;
};

struct KinematicMachine {
  MachineLayout layout = MachineLayout::kBridge;
  Eigen::Vector3d travel_mm = Eigen::Vector3d(700.0, 1000.0, 600.0);
  Eigen::Vector3d placement_mm = Eigen::Vector3d::Zero();  // the gear centre's machine position
  std::array<AxisErrors, 3> axes;                          // x, y, z
  double squareness_xy_urad = 0.0, squareness_xz_urad = 0.0, squareness_yz_urad = 0.0;

  // The axes from the base to the probe (0 = x, 1 = y, 2 = z).
  std::array<int, 3> stacking() const;
  // The axes' positions (mm, from the reference point) for a tip at `tip_mm` (gear frame) with the
  // stylus offset `stylus_mm` (from the ram's reference point to the tip).
  Eigen::Vector3d axis_positions_mm(const Eigen::Vector3d& tip_mm,
                                    const Eigen::Vector3d& stylus_mm) const;
  // The error of the tip (µm, machine = gear axes): the position the machine reports minus where
  // the tip is, to first order (a positive scale error reports lengths too long).
  Eigen::Vector3d tip_error_um(const Eigen::Vector3d& tip_mm,
                               const Eigen::Vector3d& stylus_mm) const;
};

// Σ c_k P_k(u) (Legendre, by the three-term recurrence).
double legendre_series(const std::vector<double>& coefficients, double u);

}  // namespace gearmc
