// Nominal size dimensions of an involute gear (see size_dimensions.h).
#include "gears/size_dimensions.h"

#include <cmath>

#include "core/constants.h"

namespace gearmc {

double normal_tooth_thickness_mm(const InvoluteGear& gear) {
  const GearParameters& p = gear.parameters();
  return gear.module_mm() * (kPi / 2 + 2 * p.profile_shift * std::tan(gear.pressure_angle_rad()));
}

double base_tangent_length_mm(const InvoluteGear& gear, int span_teeth) {
  const double m = gear.module_mm(), a = gear.pressure_angle_rad();
  return m * std::cos(a) *
             ((span_teeth - 0.5) * kPi +
              gear.teeth() * involute_function(gear.transverse_pressure_angle_rad())) +
         2 * gear.parameters().profile_shift * m * std::sin(a);
}

double span_contact_roll_length_mm(const InvoluteGear& gear, int span_teeth) {
  return 0.5 * base_tangent_length_mm(gear, span_teeth) / std::cos(gear.base_helix_angle_rad());
}

namespace {

// inv α = v for α in (0, π/2), by Newton from a start above the root (inv is convex there).
double inverse_involute(double v) {
  double a = std::cbrt(3 * v);  // inv α ≈ α³/3 for small α
  if (a > 1.4) a = 1.4;
  for (int i = 0; i < 60; ++i) {
    const double t = std::tan(a);
    const double step = (t - a - v) / (t * t);  // d inv/dα = tan² α
    a -= step;
    if (std::abs(step) < 1e-15) break;
  }
  return a;
}

}  // namespace

BallPosition ball_position(const InvoluteGear& gear, double ball_diameter_mm) {
  const double rb = gear.base_diameter_mm() / 2, sigma = gear.roll_sign();
  const double rho = ball_diameter_mm / (2 * std::cos(gear.base_helix_angle_rad()));
  const double inv = sigma * (rho / rb + gear.base_half_angle_rad() - kPi / gear.teeth());
  BallPosition b;
  b.pressure_angle_rad = inv > 0 ? inverse_involute(inv) : 0.0;
  b.centre_radius_mm = rb / std::cos(b.pressure_angle_rad);
  b.section_foot_roll_length_mm = rb * std::tan(b.pressure_angle_rad) - sigma * rho;
  b.contact_roll_length_mm = rb * std::tan(b.pressure_angle_rad) -
                             sigma * 0.5 * ball_diameter_mm * std::cos(gear.base_helix_angle_rad());
  return b;
}

double dimension_over_balls_mm(const InvoluteGear& gear, double ball_diameter_mm) {
  const BallPosition b = ball_position(gear, ball_diameter_mm);
  const int z = gear.teeth();
  const double across =
      z % 2 == 0 ? 2 * b.centre_radius_mm : 2 * b.centre_radius_mm * std::cos(kPi / (2 * z));
  return across + gear.roll_sign() * ball_diameter_mm;
}

std::optional<double> ball_diameter_touching_at(const InvoluteGear& gear, double roll_length_mm) {
  // The contact's roll length grows with D_M on an external gear (the ball rides higher) and
  // shrinks on an internal one (it sinks towards the axis, into the space's wider part).
  const double sigma = gear.roll_sign();
  const auto contact = [&](double D) { return ball_position(gear, D).contact_roll_length_mm; };
  double lo = 1e-6 * gear.module_mm(), hi = 10 * gear.module_mm();
  const double f_lo = sigma * (contact(lo) - roll_length_mm);
  const double f_hi = sigma * (contact(hi) - roll_length_mm);
  if (!(f_lo <= 0 && f_hi >= 0)) return std::nullopt;
  for (int i = 0; i < 200 && hi - lo > 1e-13; ++i) {
    const double mid = 0.5 * (lo + hi);
    (sigma * (contact(mid) - roll_length_mm) < 0 ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

}  // namespace gearmc
