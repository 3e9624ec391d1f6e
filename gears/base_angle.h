// The base point's polar angle of a nominal flank point, the only transcendental part of
// InvoluteGear::flank_point: phi_b = tooth angle +/- (theta_b - sigma L / r_b) (involute_gear.h,
// sigma = +1 external, -1 internal). A
// caller that evaluates many points near one roll length (the contact solver: every evaluation
// of one solve lies within about a stylus radius of its start) turns a known cos and sin by the
// small angle between them instead of calling sincos again, and builds the flank point from
// them. Angles in rad, lengths in mm.
#pragma once

#include <cmath>

#include "gears/involute_gear.h"

namespace gearmc {

// cos and sin of phi_b.
struct BaseAngle {
  double cos, sin;
};

// phi_b at roll length L (mm) of flank `side` of `tooth`: as InvoluteGear::flank_point computes it
// for a spur gear.
inline BaseAngle base_angle(const InvoluteGear& gear, int tooth, FlankSide side, double L) {
  const double xi = gear.roll_sign() * L / (gear.base_diameter_mm() / 2.0);
  const double phi_b =
      gear.tooth_centre_angle_rad(tooth) + side_sign(side) * (gear.base_half_angle_rad() - xi);
  return {std::cos(phi_b), std::sin(phi_b)};
}

// The same at height z (mm) of a helical gear: the transverse section turned by z
// helix_turn_per_mm (InvoluteGear::flank_point).
inline BaseAngle base_angle(const InvoluteGear& gear, int tooth, FlankSide side, double L,
                            double z) {
  const double xi = gear.roll_sign() * L / (gear.base_diameter_mm() / 2.0);
  const double phi_b = gear.tooth_centre_angle_rad(tooth) +
                       side_sign(side) * (gear.base_half_angle_rad() - xi) +
                       z * gear.helix_turn_per_mm();
  return {std::cos(phi_b), std::sin(phi_b)};
}

// d phi_b / dL on flank `side`: -sigma / r_b on R, +sigma / r_b on L (rad/mm).
inline double base_angle_per_mm(const InvoluteGear& gear, FlankSide side) {
  return -side_sign(side) * gear.roll_sign() / (gear.base_diameter_mm() / 2.0);
}

// cos and sin of phi + d from those of phi (`at`), for |d| <= 1/32 rad: cos(phi + d) =
// cos phi cos d - sin phi sin d, sin(phi + d) = sin phi cos d + cos phi sin d, with cos d and
// sin d from their Taylor polynomials to d^8 and d^7 (Abramowitz & Stegun 4.3.65-66; the first
// omitted term is below 1e-18 relative for |d| <= 1/32), written as products with the reciprocal
// factorials (no division: a division chain here cost more time than the sincos it replaces).
// Exact to a few rounding errors, ~1e-16. At d = 0 it returns `at` exactly.
inline BaseAngle turn_small(const BaseAngle& at, double d) {
  const double d2 = d * d;
  const double sin_d = d + d * d2 * (-1.0 / 6.0 + d2 * (1.0 / 120.0 + d2 * (-1.0 / 5040.0)));
  const double cos_d =
      1.0 + d2 * (-0.5 + d2 * (1.0 / 24.0 + d2 * (-1.0 / 720.0 + d2 * (1.0 / 40320.0))));
  return {at.cos * cos_d - at.sin * sin_d, at.sin * cos_d + at.cos * sin_d};
}

// phi_b at roll length L from `at`, its value at roll length L_at on the same flank, and
// per_mm = base_angle_per_mm(gear, side): turn_small by d = (L - L_at) per_mm when
// |d| <= 1/32 rad, else base_angle itself.
inline BaseAngle base_angle_near(const InvoluteGear& gear, int tooth, FlankSide side,
                                 const BaseAngle& at, double L_at, double per_mm, double L) {
  const double d = (L - L_at) * per_mm;
  if (!(std::abs(d) <= 1.0 / 32.0)) return base_angle(gear, tooth, side, L);
  return turn_small(at, d);
}

// InvoluteGear::flank_point from phi_b's cos and sin: the base point r_b e(phi_b), the normal
// +/- e'(phi_b) (the string direction; R: counter-clockwise), the profile tangent e(phi_b), the
// point base + sigma L n (mm): dP/dL = (L / r_b) e(phi_b) on either kind of gear.
inline FlankPoint flank_point_at(const InvoluteGear& gear, FlankSide side, double L, double z,
                                 const BaseAngle& angle) {
  const double r_b = gear.base_diameter_mm() / 2.0;
  const double sign = side_sign(side);
  FlankPoint fp;
  fp.base_point = Eigen::Vector3d(r_b * angle.cos, r_b * angle.sin, z);
  fp.normal = Eigen::Vector3d(sign * -angle.sin, sign * angle.cos, sign * 0.0);  // sign e'
  fp.profile_tangent = Eigen::Vector3d(angle.cos, angle.sin, 0.0);
  const double sigma = gear.roll_sign();
  fp.point = fp.base_point + (sigma * L) * fp.normal;
  fp.profile_curvature_per_mm = L > 0.0 ? sigma / L : 0.0;
  return fp;
}

// phi_b's cos and sin of a nominal flank point made by InvoluteGear::flank_point (or
// flank_point_at): its profile tangent is e(phi_b), the same two numbers, so no sincos.
inline BaseAngle planned_base_angle(const FlankPoint& fp) {
  return {fp.profile_tangent.x(), fp.profile_tangent.y()};
}

}  // namespace gearmc
