// Prints gearmc's nominal size dimensions (gears/size_dimensions.h) and the first-order size
// deviations (engine/evaluation/gear_parameters.h) of a fixed list of gears, for the independent
// brute-force reference size_dimensions_reference.py to check: spur even and odd z, profile
// shifted, helical even and odd, internal even and odd, and two span (W_k) cases. One line per
// gear, `case ID` then KEY=VALUE fields (mm, rad, µm):
//   internal z m_n alpha_n_deg beta_deg hand(+1 R, -1 L) x D(ball, 0 none) k(span, 0 none) d_a
//   s_n [W_k span_L] [alpha_Kt r_K ball_L M]
//   E_sn (d_L, d_R) = (0.3, 0.5)            [E_Wk (d_first, d_last) = (0.3, 0.5)]
//   [space_b dRa dLa dRb dLb radial_a radial_b E_MdK]: balls in space 0 (R of tooth 1, L of
//   tooth 2) and space_b (R of tooth space_b + 1, L of tooth space_b + 2), z/2 or (z - 1)/2,
//   with those flanks' transverse deviations.
#include <cstdio>
#include <string>
#include <vector>

#include "engine/evaluation/gear_parameters.h"
#include "gears/involute_gear.h"
#include "gears/size_dimensions.h"
#include "tests/support/helical_fixtures.h"

namespace gearmc {
namespace {

struct Case {
  std::string id;
  GearParameters parameters;
  double ball_diameter_mm;  // 0: no ball
  int span_teeth;           // 0: no span (internal gears)
};

int run() {
  const std::vector<Case> cases = {
      {"spur_even", testing_support::gear_parameters_of(20, 1.0, 0.0, Hand::kRight, 0.0, 40.0), 1.7,
       3},
      {"spur_odd", testing_support::gear_parameters_of(21, 1.0, 0.0, Hand::kRight, 0.0, 40.0), 1.7,
       3},
      {"spur_shifted", testing_support::gear_parameters_of(25, 2.0, 0.0, Hand::kRight, 0.3, 40.0),
       3.5, 4},
      {"helical_even", testing_support::gear_parameters_of(20, 1.0, 15.0, Hand::kRight, 0.2, 40.0),
       1.75, 3},
      {"helical_odd", testing_support::gear_parameters_of(23, 2.0, 20.0, Hand::kLeft, 0.1, 40.0),
       3.5, 3},
      {"internal_even",
       testing_support::gear_parameters_of(40, 1.0, 0.0, Hand::kRight, 0.0, 40.0, true), 1.7, 0},
      {"internal_odd",
       testing_support::gear_parameters_of(41, 1.0, 0.0, Hand::kRight, 0.0, 40.0, true), 1.7, 0},
      {"span_spur", testing_support::gear_parameters_of(24, 3.0, 0.0, Hand::kRight, 0.4, 40.0), 5.0,
       4},
      {"span_helical", testing_support::gear_parameters_of(24, 3.0, 25.0, Hand::kRight, 0.4, 40.0),
       5.0, 5},
  };
  // Flank deviations (µm, transverse, + = material added).
  const double d_left = 0.3, d_right = 0.5;
  const double dRa = 0.2, dLa = 0.4, dRb = -0.3, dLb = 0.6;
  for (const Case& c : cases) {
    const GearParameters& p = c.parameters;
    if (const std::string why = validate_gear_parameters(p); !why.empty()) {
      std::fprintf(stderr, "case %s: invalid gear: %s\n", c.id.c_str(), why.c_str());
      return 1;
    }
    const InvoluteGear gear(p);
    std::printf(
        "case %s internal=%d z=%d m_n=%.12g alpha_n_deg=%.12g beta_deg=%.12g hand=%d "
        "x=%.12g D=%.12g k=%d d_a=%.12g s_n=%.12g",
        c.id.c_str(), p.internal ? 1 : 0, p.teeth, p.module_mm, p.pressure_angle_deg,
        p.helix_angle_deg, p.hand == Hand::kRight ? 1 : -1, p.profile_shift, c.ball_diameter_mm,
        c.span_teeth, gear.tip_diameter_mm(), normal_tooth_thickness_mm(gear));
    if (c.span_teeth > 0) {
      std::printf(" W_k=%.12g span_L=%.12g", base_tangent_length_mm(gear, c.span_teeth),
                  span_contact_roll_length_mm(gear, c.span_teeth));
    }
    if (c.ball_diameter_mm > 0) {
      const BallPosition b = ball_position(gear, c.ball_diameter_mm);
      std::printf(" alpha_Kt=%.12g r_K=%.12g ball_L=%.12g M=%.12g", b.pressure_angle_rad,
                  b.centre_radius_mm, b.contact_roll_length_mm,
                  dimension_over_balls_mm(gear, c.ball_diameter_mm));
    }
    std::printf(" E_sn=%.12g",
                tooth_thickness_deviation_um(d_left, d_right, gear.transverse_pressure_angle_rad(),
                                             gear.helix_angle_rad()));
    if (c.span_teeth > 0) {
      std::printf(" E_Wk=%.12g", span_deviation_um(d_left, d_right, gear.base_helix_angle_rad()));
    }
    if (c.ball_diameter_mm > 0) {
      const BallPosition b = ball_position(gear, c.ball_diameter_mm);
      const std::vector<BallContact> contacts =
          ball_contacts(gear, b.section_foot_roll_length_mm, 0.0);
      const int space_b = p.teeth / 2;  // z/2 (even) or (z - 1)/2 (odd)
      const double radial_a = ball_radial_displacement_um(contacts[0], dRa, dLa);
      const double radial_b = ball_radial_displacement_um(contacts[space_b], dRb, dLb);
      std::printf(
          " space_b=%d dRa=%.12g dLa=%.12g dRb=%.12g dLb=%.12g radial_a=%.12g "
          "radial_b=%.12g E_MdK=%.12g",
          space_b, dRa, dLa, dRb, dLb, radial_a, radial_b,
          ball_dimension_deviation_um(contacts[0], ball_displacement_um(contacts[0], dRa, dLa),
                                      contacts[space_b],
                                      ball_displacement_um(contacts[space_b], dRb, dLb)));
    }
    std::printf("\n");
  }
  return 0;
}

}  // namespace
}  // namespace gearmc

int main() { return gearmc::run(); }
