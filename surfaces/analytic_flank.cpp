// Real flank surface S(L, z) = P + delta n + eps and its derivatives (see analytic_flank.h).
// With t the unit profile tangent, r_b the base radius and the involute relations
// dP/dL = (L / r_b) t, dn/dL = t / r_b, dt/dL = -n / r_b (all involutes of one base circle
// share their normals), the partials are
//   S_L  = t (L + delta) / r_b + delta_L n,           S_z  = e_z + delta_z n,
//   S_LL = t (1 + 2 delta_L) / r_b + n (delta_LL - (L + delta) / r_b^2),
//   S_Lz = t delta_z / r_b + delta_Lz n,              S_zz = delta_zz n.
#include "surfaces/analytic_flank.h"

#include "core/check.h"

#include "surfaces/flank_frame.h"

#include <Eigen/Geometry>

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
      ranges_(deviation.derivative_ranges()),
      inverse_base_radius_(2.0 / gear.base_diameter_mm()) {
  // The flank frame and the contact solver are transverse (spur) constructions; helical gears
  // reach gearmc's commands only through the gears layer so far (scenarios refuse them).
  GEARMC_CHECK(!gear.helical(),
               "AnalyticFlank: helical gears are not supported by the flank model");
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

FlankSurfacePoint AnalyticFlank::evaluate(double L, double z) const {
  return frame_to_surface(evaluate_frame(*this, L, z, base_angle(gear_, tooth_, side_, L)));
}

Eigen::Vector3d AnalyticFlank::point(double L, double z) const {
  return surface_point_at(*this, L, z, base_angle(gear_, tooth_, side_, L));
}

}  // namespace gearmc
