// The rotary table of a CMM as part of the machine (`cmm.rotary_table`, docs/cmm.md): its error
// motions against the table angle θ as ISO 230-7:2015 names them — radial, axial and angular
// (positioning) — each as the first harmonics the `rotary_table` effect uses
// (engine/effects/rotary_table.h, where the frames and signs are explained): radial
// ρ(θ) = c_r cos θ + s_r sin θ µm along the probing region's radial direction, axial
// c_a cos θ + s_a sin θ µm along the axis, angular δ(θ) = Σ_{k=1,2} c_k cos kθ + s_k sin kθ
// arcsec about it. A data sheet gives each motion's value (its range over a turn, max − min);
// a drawn table is kept when its three ranges lie within them, as a drawn machine is kept by
// its length test. Units: µm, arcsec, mm; the gear frame as the effect's.
#pragma once

#include <Eigen/Core>
#include <array>
#include <cstdint>

namespace gearmc {

struct RotaryTableErrors {
  // radial_cos, radial_sin, axial_cos, axial_sin (µm), angular_cos_1, angular_sin_1,
  // angular_cos_2, angular_sin_2 (arcsec): the `rotary_table` effect's parameters, in its order.
  std::array<double, 8> terms{};
  // Where the table moves a point c (gear frame, mm) of a tooth probed at table angle θ (rad):
  // c + 10⁻³ ρ(θ) e_r(θ) + 10⁻³ axial e_z + δ(θ) e_z × c (first order), returned as the change, mm.
  Eigen::Vector3d displacement_mm(double table_angle_rad, const Eigen::Vector3d& c_mm) const;
  // The ranges (max − min) over a turn: radial and axial 2·√(c² + s²); angular sampled at 0.1°.
  double radial_range_um() const;
  double axial_range_um() const;
  double angular_range_arcsec() const;
};

// A data sheet's error motion values (ranges over a turn); 0: that motion is perfect.
struct RotaryTableSpec {
  double radial_um = 0.0, axial_um = 0.0, angular_arcsec = 0.0;
};

// Table `index` from the prior: every component N(0, (value/4)²) of its motion's value
// (TrialStream(seed, index, kTableDraw)).
RotaryTableErrors draw_rotary_table(const RotaryTableSpec& spec, std::uint64_t seed,
                                    std::uint64_t index);
// Whether a table meets the data sheet (every range within its value).
bool meets(const RotaryTableErrors& table, const RotaryTableSpec& spec);

}  // namespace gearmc
