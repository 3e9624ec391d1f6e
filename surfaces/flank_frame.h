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

// S and its partials at (L, z) with phi_b's cos and sin at L given (base_angle.h).
FlankFramePoint evaluate_frame(const AnalyticFlank& flank, double L, double z,
                               const BaseAngle& angle);
// The vectors of FlankSurfacePoint from the frame form (AnalyticFlank::evaluate is this of
// evaluate_frame: the same values).
FlankSurfacePoint frame_to_surface(const FlankFramePoint& f);
// S(L, z) with phi_b's cos and sin at L given (AnalyticFlank::point is this with base_angle).
Eigen::Vector3d surface_point_at(const AnalyticFlank& flank, double L, double z,
                                 const BaseAngle& angle);

}  // namespace gearmc
