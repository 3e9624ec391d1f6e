// The real flank S(L, z) = P + delta n + eps (analytic_flank.h) at one (L, z) in the nominal
// involute's orthonormal frame there, for the contact solver's hot path: t the profile tangent,
// m the nominal outward normal n(L) (both transverse) and e_z. With a = (L + delta) / r_b
// (analytic_flank.cpp derives the partials):
//   S_L  = a t + delta_L m,                   S_z  = e_z + delta_z m,
//   S_LL = b t + c m  (b = (1 + 2 delta_L) / r_b, c = delta_LL - a / r_b),
//   S_Lz = (delta_z / r_b) t + delta_Lz m,    S_zz = delta_zz m.
// A scalar product of any of them with a vector v is then a combination of t.v, m.v and v_z, so
// the solver needs neither the six vectors of FlankSurfacePoint nor a second sincos: the
// base point's angle is given (gears/base_angle.h). Lengths mm, deviation derivatives in mm/mm
// and 1/mm.
#pragma once

#include <Eigen/Core>

#include "gears/base_angle.h"
#include "surfaces/analytic_flank.h"

namespace gearmc {

struct FlankFramePoint {
  Eigen::Vector3d point;  // S(L, z), mm
  Eigen::Vector2d t, m;   // transverse unit vectors (z component 0)
  double a, b, c;         // see above
  double d_L, d_z, d_Lz, d_zz, d_z_over_rb;
  double deviation_um;  // delta(L, z), µm
};

// S and its partials at (L, z) with phi_b's cos and sin at L given (base_angle.h). Inline: the
// contact solver's Newton step keeps the frame in registers.
inline FlankFramePoint evaluate_frame(const AnalyticFlank& flank, double L, double z,
                                      const BaseAngle& angle) {
  const FlankPoint nominal = flank_point_at(flank.gear(), flank.side(), L, z, angle);
  const double inv_rb = flank.inverse_base_radius();  // products, not divisions, in the chain
  // Deviation and its partials, converted from µm to mm.
  double d, dL, dz, dLL, dzz, dLz = 0.0;
  flank.deviation().evaluate(L, z, &d, &dL, &dz, &dLL, &dzz);
  if (const NormalExpression* expression = flank.expression()) {
    // Five-point differences (normal_expression.h: accurate to ~1e-6 µm/mm in the slopes).
    const NormalExpression::Derivatives e =
        expression->derivatives(L, z, flank.tooth(), side_sign(flank.side()));
    d += e.value;
    dL += e.dL;
    dz += e.dz;
    dLL += e.dLL;
    dzz += e.dzz;
    dLz += e.dLz;
  }
  const double delta = 1e-3 * d;
  dL *= 1e-3, dz *= 1e-3, dLL *= 1e-3, dzz *= 1e-3, dLz *= 1e-3;
  FlankFramePoint out;
  out.point = nominal.point + delta * nominal.normal + flank.eccentricity();
  out.t = nominal.profile_tangent.head<2>();
  out.m = nominal.normal.head<2>();
  out.a = (L + delta) * inv_rb;
  out.b = (1.0 + 2.0 * dL) * inv_rb;
  out.c = dLL - out.a * inv_rb;
  out.d_L = dL;
  out.d_z = dz;
  out.d_Lz = dLz;
  out.d_zz = dzz;
  out.d_z_over_rb = dz * inv_rb;
  out.deviation_um = d;
  return out;
}

// The vectors of FlankSurfacePoint from the frame form (AnalyticFlank::evaluate is this of
// evaluate_frame: the same values).
FlankSurfacePoint frame_to_surface(const FlankFramePoint& f);
// S(L, z) with phi_b's cos and sin at L given (AnalyticFlank::point is this with base_angle).
inline Eigen::Vector3d surface_point_at(const AnalyticFlank& flank, double L, double z,
                                        const BaseAngle& angle) {
  const FlankPoint nominal = flank_point_at(flank.gear(), flank.side(), L, z, angle);
  double d = flank.deviation().normal_um(L, z);
  if (const NormalExpression* expression = flank.expression()) {
    d += expression->value_um(L, z, flank.tooth(), side_sign(flank.side()));
  }
  return nominal.point + 1e-3 * d * nominal.normal + flank.eccentricity();
}

}  // namespace gearmc
