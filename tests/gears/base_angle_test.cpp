// The contact solver's shortcut for the flank point's base angle (gears/base_angle.h) against the
// direct evaluation: turning a known cos/sin by a small angle must give std::cos/std::sin of the
// sum, and the flank point built from it must be InvoluteGear::flank_point's.
#include "gears/base_angle.h"

#include <gtest/gtest.h>

#include <cmath>

#include "tests/support/p1_fixtures.h"

namespace gearmc {
namespace {

using testing_support::p1_gear_parameters;

TEST(BaseAngle, TurningBySmallAnglesMatchesDirectSinCos) {
  // Reference: std::cos, std::sin of phi + d (libm, correctly rounded to ~1 ulp). The Taylor
  // polynomials to d^8 / d^7 leave < 1e-18 relative at |d| = 1/32; allow 4e-16 for the rounding
  // of the two products and sums.
  for (double phi : {-2.9, -0.4, 0.0, 0.7, 1.5707963267948966, 3.1}) {
    const BaseAngle at{std::cos(phi), std::sin(phi)};
    for (double d : {0.0, 1e-9, -3e-5, 1e-3, -0.01, 1.0 / 32.0, -1.0 / 32.0}) {
      const BaseAngle t = turn_small(at, d);
      EXPECT_NEAR(t.cos, std::cos(phi + d), 4e-16) << phi << " " << d;
      EXPECT_NEAR(t.sin, std::sin(phi + d), 4e-16) << phi << " " << d;
    }
    // d = 0 returns the start exactly.
    EXPECT_EQ(turn_small(at, 0.0).cos, at.cos);
    EXPECT_EQ(turn_small(at, 0.0).sin, at.sin);
  }
}

TEST(BaseAngle, FlankPointFromANearbyAngleIsTheGearsFlankPoint) {
  // P1's gear, both flanks of two teeth; start at roll length 30 mm and evaluate within a stylus
  // radius (the solver's case) and beyond 1/32 rad (the fall-back to base_angle itself).
  const InvoluteGear gear(p1_gear_parameters());
  const double r_b = gear.base_diameter_mm() / 2.0;
  for (int tooth : {0, 7}) {
    for (FlankSide side : {FlankSide::kLeft, FlankSide::kRight}) {
      const double L0 = 30.0;
      const BaseAngle at = base_angle(gear, tooth, side, L0);
      const double per_mm = base_angle_per_mm(gear, side);
      for (double L : {L0, L0 + 0.2, L0 - 0.45, L0 + 1.0, L0 + 0.03125 * r_b + 1.0}) {
        const FlankPoint a = flank_point_at(gear, side, L, 12.0,
                                            base_angle_near(gear, tooth, side, at, L0, per_mm, L));
        const FlankPoint b = gear.flank_point(tooth, side, L, 12.0);
        // 1e-12 mm: a few rounding errors of coordinates of size r_b ≈ 63 mm.
        EXPECT_NEAR((a.point - b.point).norm(), 0.0, 1e-12) << tooth << " " << L;
        EXPECT_NEAR((a.normal - b.normal).norm(), 0.0, 1e-14) << tooth << " " << L;
        EXPECT_NEAR((a.base_point - b.base_point).norm(), 0.0, 1e-12) << tooth << " " << L;
      }
    }
  }
}

TEST(BaseAngle, APlannedPointCarriesItsAngleBitForBit) {
  // The contact solver takes phi_b at the planned roll length from the planned point's profile
  // tangent (planned_base_angle) instead of calling sincos: it must be base_angle's own two
  // numbers, exactly, on every tooth and side and along the whole profile.
  const InvoluteGear gear(p1_gear_parameters());
  for (int tooth = 1; tooth <= gear.teeth(); ++tooth) {
    for (FlankSide side : {FlankSide::kLeft, FlankSide::kRight}) {
      for (double L = gear.form_roll_length_mm(); L <= gear.tip_roll_length_mm(); L += 0.37) {
        const BaseAngle direct = base_angle(gear, tooth, side, L);
        const BaseAngle planned = planned_base_angle(gear.flank_point(tooth, side, L, 5.0));
        EXPECT_EQ(planned.cos, direct.cos) << tooth << " " << L;
        EXPECT_EQ(planned.sin, direct.sin) << tooth << " " << L;
      }
    }
  }
}

}  // namespace
}  // namespace gearmc
