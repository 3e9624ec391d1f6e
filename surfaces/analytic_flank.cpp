// Real flank surface S(L, z) = P + delta n + eps and its derivatives (see analytic_flank.h).
// With t the unit profile tangent, r_b the base radius, sigma the roll sign (+1 external, -1
// internal: P = r_b e(phi_b) + sigma L n, phi_b moving by -side sigma / r_b per mm of L) and the
// involute relations dP/dL = (L / r_b) t, dn/dL = sigma t / r_b, dt/dL = -sigma n / r_b (all
// involutes of one base circle share their normals), the partials are
//   S_L  = t (L + sigma delta) / r_b + delta_L n,     S_z  = e_z + delta_z n,
//   S_LL = t (1 + 2 sigma delta_L) / r_b + n (delta_LL - sigma (L + sigma delta) / r_b^2),
//   S_Lz = t sigma delta_z / r_b + delta_Lz n,        S_zz = delta_zz n.
// A helical flank (flank_frame.h): the transverse section at z is the one at 0 turned by g z
// (g = side sign * helix_turn_per_mm), so phi_b = phi_b(L) + g' z and t_z = g n, n_z = -g t with
// n = n_t the transverse normal; P = r_b e(phi_b) + L n + z e_z gives P_z = e_z + g (r_b n - L t)
// and S = P + delta n + eps (sigma = +1; an internal flank: P_z = e_z + g (r_b n - sigma L t))
//   S_z  = e_z - g (L + delta) t + (g r_b + delta_z) n,
//   S_Lz = (delta_z / r_b - g delta_L) t + (delta_Lz + g (L + delta) / r_b) n,
//   S_zz = -g (2 delta_z + g r_b) t + (delta_zz - g^2 (L + delta)) n,
// S_L and S_LL as above (t_L and n_L do not see z).
#include "surfaces/analytic_flank.h"

#include "core/check.h"

#include "surfaces/flank_frame.h"

#include <Eigen/Geometry>
#include <cmath>

namespace gearmc {

Eigen::Vector3d FlankSurfacePoint::real_normal() const {
  Eigen::Vector3d n = d_dL.cross(d_dz).normalized();
  return n.dot(nominal_normal) < 0.0 ? Eigen::Vector3d(-n) : n;
}

AnalyticFlank::AnalyticFlank(const InvoluteGear& gear, int tooth, FlankSide side,
                             const FlankDeviation& deviation,
                             const Eigen::Vector2d& eccentricity_mm,
                             const NormalExpression* expression)
    : gear_(gear),
      tooth_(tooth),
      side_(side),
      deviation_(deviation),
      eccentricity_(eccentricity_mm.x(), eccentricity_mm.y(), 0.0),
      expression_(expression),
      modification_(gear.design_modification()),
      ranges_(deviation.derivative_ranges()),
      inverse_base_radius_(2.0 / gear.base_diameter_mm()),
      base_radius_(0.5 * gear.base_diameter_mm()),
      roll_sign_(gear.roll_sign()),
      frame_turn_per_mm_(side_sign(side) * gear.helix_turn_per_mm()),
      cos_base_helix_(std::cos(gear.base_helix_angle_rad())),
      sin_base_helix_(std::sin(gear.base_helix_angle_rad())),
      normal_z_(-side_sign(side) * hand_sign(gear.hand()) * sin_base_helix_) {
  if (modification_ != nullptr) {  // the sum's derivatives lie within the sum of the ranges
    const ModificationCurve::Bounds p = modification_->profile.derivative_bounds();
    const ModificationCurve::Bounds h = modification_->helix.derivative_bounds();
    ranges_.dL = {ranges_.dL.lo + p.first_lo, ranges_.dL.hi + p.first_hi};
    ranges_.dLL = {ranges_.dLL.lo + p.second_lo, ranges_.dLL.hi + p.second_hi};
    ranges_.dz = {ranges_.dz.lo + h.first_lo, ranges_.dz.hi + h.first_hi};
    ranges_.dzz = {ranges_.dzz.lo + h.second_lo, ranges_.dzz.hi + h.second_hi};
  }
}

FlankSurfacePoint frame_to_surface(const FlankFramePoint& f) {
  const Eigen::Vector3d t(f.t.x(), f.t.y(), 0.0), n(f.m.x(), f.m.y(), 0.0);
  FlankSurfacePoint out;
  out.point = f.point;
  out.d_dL = t * f.a + f.d_L * n;
  out.d_dz = Eigen::Vector3d::UnitZ() + f.d_z * n;
  out.d2_dL2 = t * f.b + n * f.c;
  out.d2_dLdz = t * f.d_z_over_rb + f.d_Lz * n;
  out.d2_dz2 = f.d_zz * n;
  out.nominal_normal = n;
  out.deviation_um = f.deviation_um;
  return out;
}

FlankSurfacePoint frame_to_surface(const HelicalFramePoint& h, const InvoluteGear& gear,
                                   FlankSide side) {
  FlankSurfacePoint out = frame_to_surface(h.f);
  const Eigen::Vector3d t(h.f.t.x(), h.f.t.y(), 0.0), m(h.f.m.x(), h.f.m.y(), 0.0);
  out.d_dz = Eigen::Vector3d::UnitZ() + h.z_t * t + h.z_m * m;
  out.d2_dLdz = h.lz_t * t + h.lz_m * m;
  out.d2_dz2 = h.zz_t * t + h.zz_m * m;
  const double beta_b = gear.base_helix_angle_rad();
  out.nominal_normal = std::cos(beta_b) * m - side_sign(side) * hand_sign(gear.hand()) *
                                                  std::sin(beta_b) * Eigen::Vector3d::UnitZ();
  return out;
}

FlankSurfacePoint AnalyticFlank::evaluate(double L, double z) const {
  if (gear_.helical()) {
    return frame_to_surface(
        evaluate_helical_frame(*this, L, z, base_angle(gear_, tooth_, side_, L, z)), gear_, side_);
  }
  return frame_to_surface(evaluate_frame(*this, L, z, base_angle(gear_, tooth_, side_, L)));
}

Eigen::Vector3d AnalyticFlank::point(double L, double z) const {
  if (gear_.helical()) return surface_point_at(*this, L, z, base_angle(gear_, tooth_, side_, L, z));
  return surface_point_at(*this, L, z, base_angle(gear_, tooth_, side_, L));
}

}  // namespace gearmc
