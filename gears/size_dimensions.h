// The nominal size dimensions of an involute gear that a workshop measures instead of the tooth
// thickness itself (ISO 21771:2007 §5.5, DIN 3960): the normal tooth thickness on the reference
// cylinder s_n, the base tangent length W_k over k teeth (span measurement, external gears) and
// the dimension over (external) or between (internal) two balls M_dK, with where each gauge
// touches the flanks — as a roll length, so a measured profile trace can be read there. Lengths
// in mm, angles in rad, transverse values unless a name says normal (docs/parameters.md).
#pragma once

#include <optional>

#include "gears/involute_gear.h"

namespace gearmc {

// Normal arc tooth thickness on the reference cylinder, s_n = m_n (π/2 + 2 x tan α_n)
// (ISO 21771); s_t = s_n / cos β.
double normal_tooth_thickness_mm(const InvoluteGear& gear);

// Base tangent length over k teeth in the normal section (ISO 21771):
// W_k = m_n cos α_n [(k − 0.5) π + z inv α_t] + 2 x m_n sin α_n. External gears only.
double base_tangent_length_mm(const InvoluteGear& gear, int span_teeth);
// Where the two parallel jaws touch, placed symmetrically about the point where their common
// normal touches the base cylinder: the transverse length W_k / cos β_b split in two, as a roll
// length on each of the two outer flanks of the span.
double span_contact_roll_length_mm(const InvoluteGear& gear, int span_teeth);

// A ball (or pin, on a spur gear) of diameter D_M in a tooth space. Its centre lies on the
// space's centre line, at the transverse pressure angle α_Kt where the base-tangent distance to
// either flank is ρ, written for both kinds from the space's half angle:
// inv α_Kt = σ (ρ / r_b + θ_b − π / z), ρ = D_M / (2 cos β_b), θ_b the base half tooth angle
// (InvoluteGear::base_half_angle_rad), σ = +1 external, −1 internal; for an external gear this
// is ISO 21771's inv α_Kt = inv α_t + D_M/(m_n z cos α_n) − π/(2z) + 2 x tan α_n / z.
struct BallPosition {
  double pressure_angle_rad = 0.0;  // α_Kt
  double centre_radius_mm = 0.0;    // r_K = r_b / cos α_Kt
  // Where it touches either flank of its space: r_b tan α_Kt − σ (D_M/2) cos β_b, the roll
  // length of the 3-D contact (along the helicoid's normal the centre is D_M/2 away, of which
  // (D_M/2) cos β_b lies in the transverse plane; the contact's section is (D_M/2) sin β_b from
  // the centre's — on a spur gear the same section and r_b tan α_Kt − σ D_M/2).
  double contact_roll_length_mm = 0.0;
  // Where the centre's transverse base tangent meets the flank in the centre's own section,
  // r_b tan α_Kt − σ D_M / (2 cos β_b): there the flank's transverse normal points at the centre
  // (it is the 3-D contact's normal seen in that section), so the ball's displacement is solved
  // with the normals there (equal to the contact on a spur gear).
  double section_foot_roll_length_mm = 0.0;
};
BallPosition ball_position(const InvoluteGear& gear, double ball_diameter_mm);
// The dimension over two balls (external: 2 r_K + D_M) or between two balls (internal:
// 2 r_K − D_M) in spaces opposite each other (even z) or as nearly opposite as the teeth allow
// (odd z: 2 r_K cos(π/(2z)) ± D_M, ISO 21771).
double dimension_over_balls_mm(const InvoluteGear& gear, double ball_diameter_mm);
// The ball diameter whose contact lies at roll length L (mm), by bisection on D_M (the contact
// moves monotonically with it); nullopt when no ball of diameter in (0, 10 m_n] touches there.
std::optional<double> ball_diameter_touching_at(const InvoluteGear& gear, double roll_length_mm);

}  // namespace gearmc
