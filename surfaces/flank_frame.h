// The real flank S(L, z) = P + delta n + eps (analytic_flank.h) at one (L, z) in the nominal
// involute's orthonormal frame there, for the contact solver's hot path: t the profile tangent,
// m the nominal outward normal n(L) (both transverse) and e_z. With sigma the roll sign (+1
// external, -1 internal: P = r_b e(phi_b) + sigma L m) and a = (L + sigma delta) / r_b
// (analytic_flank.cpp derives the partials):
//   S_L  = a t + delta_L m,                   S_z  = e_z + delta_z m,
//   S_LL = b t + c m  (b = (1 + 2 sigma delta_L) / r_b, c = delta_LL - sigma a / r_b),
//   S_Lz = (sigma delta_z / r_b) t + delta_Lz m,    S_zz = delta_zz m.
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
  Eigen::Vector3d point;                     // S(L, z), mm
  Eigen::Vector2d t, m;                      // transverse unit vectors (z component 0)
  double a, b, c;                            // see above
  double d_L, d_z, d_Lz, d_zz, d_z_over_rb;  // d_z_over_rb: sigma delta_z / r_b
  double deviation_um;                       // delta(L, z), µm
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
  if (const DesignModification* modification = flank.modification()) {
    double v, d1, d2;
    modification->profile.evaluate(L, &v, &d1, &d2);
    d += v, dL += d1, dLL += d2;
    modification->helix.evaluate(z, &v, &d1, &d2);
    d += v, dz += d1, dzz += d2;
  }
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
  const double sigma = flank.roll_sign();
  FlankFramePoint out;
  out.point = nominal.point + delta * nominal.normal + flank.eccentricity();
  out.t = nominal.profile_tangent.head<2>();
  out.m = nominal.normal.head<2>();
  out.a = (L + sigma * delta) * inv_rb;
  out.b = (1.0 + 2.0 * (sigma * dL)) * inv_rb;
  out.c = dLL - sigma * out.a * inv_rb;
  out.d_L = dL;
  out.d_z = dz;
  out.d_Lz = dLz;
  out.d_zz = dzz;
  out.d_z_over_rb = sigma * dz * inv_rb;
  out.deviation_um = d;
  return out;
}

// A helical flank (involute helicoid, gears/involute_gear.h) in the same frame. The deviation
// delta is transverse, along m = n_t (as gear measuring instruments report it, ISO 1328-1: in
// the transverse plane along the base tangent; the deviation normal to the flank is delta
// cos(beta_b)), so S = P + delta m + eps stays in the frame (t, m, e_z). With g = side sign *
// helix_turn_per_mm (rad/mm; t_z = g m, m_z = -g t, t_L = -sigma m / r_b, m_L = sigma t / r_b)
// and P_z = e_z + g (r_b m - sigma L t), the partials are (derived in analytic_flank.cpp)
//   S_L  = a t + delta_L m                        (as for a spur flank)
//   S_z  = e_z + z_t t + z_m m,         z_t = -sigma g r_b a,  z_m = g r_b + delta_z
//   S_LL = b t + c m                              (as for a spur flank)
//   S_Lz = lz_t t + lz_m m,  lz_t = sigma delta_z / r_b - g delta_L,  lz_m = delta_Lz + g a
//   S_zz = zz_t t + zz_m m,  zz_t = -g (2 delta_z + g r_b),  zz_m = delta_zz - sigma g^2 r_b a.
// At g = 0 these are the spur partials.
struct HelicalFramePoint {
  FlankFramePoint f;  // point, t, m, a, b, c and the deviation's partials
  double z_t, z_m, lz_t, lz_m, zz_t, zz_m;
};

// S and its partials at (L, z) of a helical flank with phi_b's cos and sin at (L, z) given
// (base_angle.h, the five-argument form).
inline HelicalFramePoint evaluate_helical_frame(const AnalyticFlank& flank, double L, double z,
                                                const BaseAngle& angle) {
  HelicalFramePoint out;
  out.f = evaluate_frame(flank, L, z, angle);  // the point is the helicoid's: P_z = z
  const FlankFramePoint& f = out.f;
  const double g = flank.frame_turn_per_mm();
  const double g_rb = g * flank.base_radius();
  const double sigma = flank.roll_sign();
  out.z_t = -(sigma * g_rb) * f.a;
  out.z_m = g_rb + f.d_z;
  out.lz_t = f.d_z_over_rb - g * f.d_L;
  out.lz_m = f.d_Lz + g * f.a;
  out.zz_t = -g * (2.0 * f.d_z + g_rb);
  out.zz_m = f.d_zz - (sigma * g) * g_rb * f.a;
  return out;
}

// The vectors of FlankSurfacePoint from the frame form (AnalyticFlank::evaluate is this of
// evaluate_frame: the same values).
FlankSurfacePoint frame_to_surface(const FlankFramePoint& f);
// The same of a helical flank; its nominal normal is the helicoid's, cos(beta_b) m - side hand
// sin(beta_b) e_z (InvoluteGear::flank_point).
FlankSurfacePoint frame_to_surface(const HelicalFramePoint& h, const InvoluteGear& gear,
                                   FlankSide side);
// S(L, z) with phi_b's cos and sin at L given (AnalyticFlank::point is this with base_angle;
// of a helical flank the angle at (L, z)).
inline Eigen::Vector3d surface_point_at(const AnalyticFlank& flank, double L, double z,
                                        const BaseAngle& angle) {
  const FlankPoint nominal = flank_point_at(flank.gear(), flank.side(), L, z, angle);
  double d = flank.deviation().normal_um(L, z);
  if (const DesignModification* modification = flank.modification()) {
    d += modification->value_um(L, z);
  }
  if (const NormalExpression* expression = flank.expression()) {
    d += expression->value_um(L, z, flank.tooth(), side_sign(flank.side()));
  }
  return nominal.point + 1e-3 * d * nominal.normal + flank.eccentricity();
}

}  // namespace gearmc
