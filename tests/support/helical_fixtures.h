// Helical test gears: the example (z 31, m_n 4 mm, alpha_n 20°, beta 15°, x 0.2,
// b 40 mm, ISO 53 profile A) in either hand, and a wavy deviation over its flank (L about
// 15–34 mm, z 0–40 mm).
#pragma once

#include "gears/deviations.h"
#include "gears/involute_gear.h"

namespace gearmc::testing_support {

// A gear of ISO 53 profile A with α_n 20° from its other design data (the reference dumps'
// cases): z, m_n (mm), β (deg), hand, x, b (mm), internal.
inline GearParameters gear_parameters_of(int teeth, double m_n, double beta_deg, Hand hand,
                                         double x, double b_mm, bool internal = false) {
  GearParameters p;
  p.internal = internal;
  p.teeth = teeth;
  p.module_mm = m_n;
  p.pressure_angle_deg = 20.0;
  p.helix_angle_deg = beta_deg;
  p.hand = hand;
  p.profile_shift = x;
  p.face_width_mm = b_mm;
  return p;
}

inline GearParameters helical_gear_parameters(Hand hand = Hand::kRight, double beta_deg = 15.0) {
  GearParameters p;
  p.teeth = 31;
  p.module_mm = 4.0;
  p.pressure_angle_deg = 20.0;
  p.helix_angle_deg = beta_deg;
  p.hand = hand;
  p.profile_shift = 0.2;
  p.face_width_mm = 40.0;
  return p;
}

inline InvoluteGear helical_gear(Hand hand = Hand::kRight, double beta_deg = 15.0) {
  return InvoluteGear(helical_gear_parameters(hand, beta_deg));
}

// A helical ring gear (internal, z 60, m_n 2 mm, alpha_n 20°, beta 18°, x 0.1, b 20 mm), without
// modifications: the tooth-space and point-matching tests' internal helicoid.
inline InvoluteGear helical_ring(Hand hand) {
  GearParameters p;
  p.teeth = 60;
  p.internal = true;
  p.module_mm = 2.0;
  p.pressure_angle_deg = 20.0;
  p.helix_angle_deg = 18.0;
  p.hand = hand;
  p.profile_shift = 0.1;
  p.face_width_mm = 20.0;
  return InvoluteGear(p);
}

// Offset, slopes and wavy forms (µm), like wavy_deviation (p1_fixtures.h) on this flank.
inline FlankDeviation helical_wavy_deviation() {
  FlankDeviation d;
  d.offset_um = -12.0;
  d.profile_slope_um_per_mm = 0.3;
  d.profile_mid_mm = 25.0;
  d.profile_form = CubicBSpline(14.0, 35.0, {1.0, -2.0, 3.0, 0.5, -1.5, 2.5, -0.7, 0.2});
  d.helix_slope_um_per_mm = -0.1;
  d.helix_mid_mm = 20.0;
  d.helix_form = CubicBSpline(0.0, 40.0, {0.0, 2.0, -1.0, 1.5, -2.0, 0.3});
  return d;
}

}  // namespace gearmc::testing_support
