// Prints gearmc's stylus contacts on helical flanks with steep designed modifications, for the
// independent reference helical_contact_reference.py (mpmath) to check: two external gears
// (right hand beta 15°, left hand beta 25°) and two internal ones (spur z 60; left hand beta
// 18°, z 71), two deterministic fields each (tip and root relief, helix crowning and a profile
// slope; a wavy field with a steep bump), both flanks of two teeth (internal: one), a grid of
// planned points, stylus radii 0.5 and 1 mm: 576 points. Lines:
//   gear ID TEETH M_N ALPHA_N BETA HAND X KIND       (KIND: external | internal)
//   expr ID EXPRESSION (µm, transverse; muParser)
//   point GEAR EXPR TOOTH SIDE L0 Z0 R px py pz nx ny nz STATUS Cx Cy Cz Ox Oy Oz   (mm)
#include <cstdio>
#include <string>
#include <vector>

#include "engine/contact/contact.h"
#include "gears/deviations.h"
#include "gears/normal_expression.h"
#include "tests/support/helical_fixtures.h"

namespace gearmc {
namespace {

struct Case {
  std::string id;
  GearParameters parameters;
};

const char* status_word(ContactResult::Status s) {
  switch (s) {
    case ContactResult::Status::kOk:
      return "ok";
    case ContactResult::Status::kEdge:
      return "edge";
    case ContactResult::Status::kCollision:
      return "collision";
    case ContactResult::Status::kNotConverged:
      return "not_converged";
    case ContactResult::Status::kUncertified:
      return "uncertified";
  }
  return "?";
}

int run() {
  const std::vector<Case> cases = {
      {"g1", testing_support::gear_parameters_of(31, 4.0, 15.0, Hand::kRight, 0.2, 40.0)},
      {"g2", testing_support::gear_parameters_of(23, 3.0, 25.0, Hand::kLeft, -0.1, 30.0)},
      {"g3", testing_support::gear_parameters_of(60, 2.0, 0.0, Hand::kRight, 0.1, 20.0, true)},
      {"g4", testing_support::gear_parameters_of(71, 2.0, 18.0, Hand::kLeft, 0.2, 25.0, true)},
  };
  const FlankDeviation none;
  for (const Case& c : cases) {
    const InvoluteGear gear(c.parameters);
    std::printf("gear %s %d %.17g 20 %.17g %s %.17g %s\n", c.id.c_str(), c.parameters.teeth,
                c.parameters.module_mm, c.parameters.helix_angle_deg,
                c.parameters.hand == Hand::kRight ? "right" : "left", c.parameters.profile_shift,
                gear.internal() ? "internal" : "external");
    // The active profile as an increasing interval (on an internal gear the tip is its low end:
    // the expressions' "tip" and "root" terms then sit at the other ends, as steep as before).
    const double L_form = gear.active_roll_length_min_mm();
    const double L_tip = gear.active_roll_length_max_mm();
    const double b = gear.face_width_mm();
    const double L_mid = 0.5 * (L_form + L_tip), span = L_tip - L_form;
    char text[2][400];
    // Tip relief 25 µm and root relief 15 µm, each quadratic over a fifth of the profile
    // (slopes up to 2 x 25 / (span / 5) µm/mm at the tip), helix crowning 6 µm, a profile slope.
    std::snprintf(text[0], sizeof text[0],
                  "0 - 25*max(0,L-%.6f)^2/%.6f - 15*max(0,%.6f-L)^2/%.6f - 6*((z-%.6f)/%.6f)^2 "
                  "+ 0.4*(L-%.6f)",
                  L_tip - 0.2 * span, 0.04 * span * span, L_form + 0.2 * span, 0.04 * span * span,
                  0.5 * b, 0.5 * b, L_mid);
    // Waviness and a steep bump of 8 µm, sigma 0.5 mm, in the middle of the flank.
    std::snprintf(text[1], sizeof text[1],
                  "3*sin(2.5*L)*cos(1.3*z) + 8*exp(0-((L-%.6f)^2+(z-%.6f)^2)/0.5)", L_mid, 0.5 * b);
    for (int e = 0; e < 2; ++e) {
      const std::string expr_id = c.id + "e" + std::to_string(e + 1);
      std::printf("expr %s %s\n", expr_id.c_str(), text[e]);
      const NormalExpression expression(text[e]);
      for (int tooth : gear.internal() ? std::vector<int>{5} : std::vector<int>{1, 9}) {
        for (FlankSide side : {FlankSide::kLeft, FlankSide::kRight}) {
          const AnalyticFlank flank(gear, tooth, side, none, Eigen::Vector2d::Zero(), &expression);
          for (int i = 0; i < 6; ++i) {
            const double L0 = L_form + 1.2 + (span - 2.4) * i / 5.0;
            for (int j = 0; j < 4; ++j) {
              const double R = (i + j) % 2 ? 0.5 : 1.0;
              const double z0 = R + 0.5 + (b - 2 * R - 1.0) * (j + 0.37 * (i % 2)) / 3.37;
              const FlankPoint fp = gear.flank_point(tooth, side, L0, z0);
              const ContactResult r =
                  solve_contact(flank, {L_form, L_tip, 0.0, b}, fp.point, fp.normal, R, L0, z0);
              const bool ok = r.status == ContactResult::Status::kOk;
              std::printf(
                  "point %s %s %d %s %.17g %.17g %.17g %.17g %.17g %.17g %.17g %.17g %.17g %s "
                  "%.17g %.17g %.17g %.17g %.17g %.17g\n",
                  c.id.c_str(), expr_id.c_str(), tooth, side == FlankSide::kRight ? "R" : "L", L0,
                  z0, R, fp.point.x(), fp.point.y(), fp.point.z(), fp.normal.x(), fp.normal.y(),
                  fp.normal.z(), status_word(r.status), ok ? r.contact.x() : 0.0,
                  ok ? r.contact.y() : 0.0, ok ? r.contact.z() : 0.0, ok ? r.centre.x() : 0.0,
                  ok ? r.centre.y() : 0.0, ok ? r.centre.z() : 0.0);
            }
          }
        }
      }
    }
  }
  return 0;
}

}  // namespace
}  // namespace gearmc

int main() { return gearmc::run(); }
