// Nominal involute geometry against P1's Table 1 and against the geometric properties the
// closed forms must have (normals unit, perpendicular to the flank, out of the material;
// offsets along the normal and rotations about the axis keep every normal).
#include "gears/involute_gear.h"
#include "tests/support/p1_fixtures.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <numbers>

namespace gearmc {
namespace {

using testing_support::p1_gear;
using testing_support::p1_gear_parameters;

TEST(InvoluteGear, ReproducesP1Table1) {
  const InvoluteGear gear(p1_gear_parameters());
  // P1 Table 1 values, printed to 0.001 mm (s to 0.01 mm).
  EXPECT_NEAR(gear.reference_diameter_mm(), 134.4, 1e-3);
  EXPECT_NEAR(gear.tip_diameter_mm(), 155.693, 1e-3);
  EXPECT_NEAR(gear.root_diameter_mm(), 130.493, 1e-3);
  EXPECT_NEAR(gear.base_diameter_mm(), 126.295, 1e-3);
  EXPECT_NEAR(gear.tooth_thickness_mm(), 12.47, 1e-3);
  EXPECT_NEAR(gear.angular_pitch_rad() * 180.0 / std::numbers::pi, 15.0, 1e-12);
  // p_b = pi m cos(alpha) = 17.592919 * 0.9396926 = 16.531936 mm (hand computation).
  EXPECT_NEAR(gear.base_pitch_mm(), 16.531936, 1e-5);
  EXPECT_TRUE(validate_gear_parameters(p1_gear_parameters()).empty());
}

TEST(InvoluteGear, FormCircleFromRackGeneration) {
  const InvoluteGear gear(p1_gear_parameters());
  // Independent hand computation (ISO 21771 construction), sin 20° = 0.3420201433:
  // h_FfP = 1.25 m - 0.38 m (1 - sin 20°) = 7.0 - 2.128 * 0.6579798567 = 5.599818865 mm;
  // x m = 5.046496 mm; L_Ff = 67.2 sin 20° - (5.599818865 - 5.046496) / sin 20°
  // = 22.98375363 - 1.61780773 = 21.3659459 mm.
  EXPECT_NEAR(gear.form_roll_length_mm(), 21.3659459, 1e-6);
  EXPECT_FALSE(gear.undercut());
  // L_a = sqrt(77.8465^2 - 63.14737^2) = 45.5252 mm.
  EXPECT_NEAR(gear.tip_roll_length_mm(), 45.5252, 1e-3);
  EXPECT_NEAR(gear.diameter_at_roll_length(gear.form_roll_length_mm()), gear.form_diameter_mm(),
              1e-12);
  EXPECT_NEAR(gear.roll_length_at_diameter(gear.tip_diameter_mm()), gear.tip_roll_length_mm(),
              1e-12);
  // A small gear without profile shift is undercut (z < 17 for alpha 20°, ISO 53 A).
  GearParameters small = p1_gear_parameters();
  small.teeth = 12;
  small.profile_shift = 0.0;
  EXPECT_TRUE(InvoluteGear(small).undercut());
}

TEST(InvoluteGear, PointsLieOnTheInvoluteAtTheRightRadiusAndThickness) {
  const InvoluteGear gear(p1_gear_parameters());
  const double r_b = gear.base_diameter_mm() / 2.0;
  for (int tooth : {1, 2, 13, 24}) {
    for (FlankSide side : {FlankSide::kLeft, FlankSide::kRight}) {
      for (double L : {22.0, 30.0, 44.0}) {
        const FlankPoint fp = gear.flank_point(tooth, side, L, 10.0);
        const double r = std::hypot(fp.point.x(), fp.point.y());
        EXPECT_NEAR(r, std::sqrt(r_b * r_b + L * L), 1e-9);
        EXPECT_DOUBLE_EQ(fp.point.z(), 10.0);
        // Half tooth angle at radius r: s/d + inv(alpha) - inv(alpha_r) (standard relation).
        const double alpha_r = std::acos(r_b / r);
        const double half = gear.tooth_thickness_mm() / gear.reference_diameter_mm() +
                            involute_function(gear.pressure_angle_rad()) -
                            involute_function(alpha_r);
        const double polar = std::atan2(fp.point.y(), fp.point.x());
        const double expected = gear.tooth_centre_angle_rad(tooth) + side_sign(side) * half;
        EXPECT_NEAR(std::remainder(polar - expected, 2 * std::numbers::pi), 0.0, 1e-12);
      }
    }
  }
  // At the reference circle the tooth is s wide (arc): P1's s = 12.47 mm.
  const double L_ref = gear.roll_length_at_diameter(gear.reference_diameter_mm());
  const auto r = gear.flank_point(1, FlankSide::kRight, L_ref, 0).point;
  const auto l = gear.flank_point(1, FlankSide::kLeft, L_ref, 0).point;
  const double arc =
      gear.reference_diameter_mm() / 2.0 * (std::atan2(r.y(), r.x()) - std::atan2(l.y(), l.x()));
  EXPECT_NEAR(arc, 12.47, 1e-3);
}

TEST(InvoluteGear, NormalsAreUnitPerpendicularAndOutward) {
  const InvoluteGear gear(p1_gear_parameters());
  constexpr double h = 1e-4;
  for (int tooth = 1; tooth <= 24; ++tooth) {
    for (FlankSide side : {FlankSide::kLeft, FlankSide::kRight}) {
      for (double L = 21.5; L < 45.0; L += 2.3) {
        const FlankPoint fp = gear.flank_point(tooth, side, L, 5.0);
        EXPECT_NEAR(fp.normal.norm(), 1.0, 1e-14);
        // Tangent by finite differences of the closed-form point.
        const Eigen::Vector3d tangent = (gear.flank_point(tooth, side, L + h, 5.0).point -
                                         gear.flank_point(tooth, side, L - h, 5.0).point) /
                                        (2 * h);
        EXPECT_NEAR(tangent.normalized().dot(fp.normal), 0.0, 1e-8);
        EXPECT_NEAR((tangent.normalized() - fp.profile_tangent).norm(), 0.0, 1e-7);
        EXPECT_NEAR(fp.normal.z(), 0.0, 1e-15);  // spur gear: normal in the transverse plane
        // Outward: moving along +n leaves the tooth. The point 1 µm outside is farther (in
        // angle) from the tooth centre line than the flank point at the same radius.
        const Eigen::Vector3d out = fp.point + 1e-3 * fp.normal;
        const double r_out = std::hypot(out.x(), out.y());
        const double L_out = gear.roll_length_at_diameter(2 * r_out);
        const Eigen::Vector3d same_radius = gear.flank_point(tooth, side, L_out, 5.0).point;
        const double centre = gear.tooth_centre_angle_rad(tooth);
        auto off_centre = [&](const Eigen::Vector3d& p) {
          return std::abs(std::remainder(std::atan2(p.y(), p.x()) - centre, 2 * std::numbers::pi));
        };
        EXPECT_GT(off_centre(out), off_centre(same_radius));
        // docs/formats.md: R has a positive counter-clockwise tangential component, L negative.
        const Eigen::Vector3d ccw = Eigen::Vector3d::UnitZ().cross(fp.point).normalized();
        EXPECT_GT(side_sign(side) * fp.normal.dot(ccw), 0.0);
      }
    }
  }
  // Tooth 1's R flank is on the +Y side.
  EXPECT_GT(gear.flank_point(1, FlankSide::kRight, 30.0, 0).point.y(), 0.0);
  EXPECT_LT(gear.flank_point(1, FlankSide::kLeft, 30.0, 0).point.y(), 0.0);
}

TEST(InvoluteGear, CurvatureIsOneOverRollLength) {
  const InvoluteGear gear(p1_gear_parameters());
  // Curvature from three closed-form points (circumscribed circle) must equal 1/L.
  for (double L : {22.0, 33.0, 44.0}) {
    const double h = 1e-3;
    const auto a = gear.flank_point(3, FlankSide::kLeft, L - h, 0).point;
    const auto b = gear.flank_point(3, FlankSide::kLeft, L, 0).point;
    const auto c = gear.flank_point(3, FlankSide::kLeft, L + h, 0).point;
    const double area2 = (b - a).cross(c - a).norm();
    const double kappa = 2.0 * area2 / ((b - a).norm() * (c - b).norm() * (c - a).norm());
    EXPECT_NEAR(kappa, gear.flank_point(3, FlankSide::kLeft, L, 0).profile_curvature_per_mm,
                1e-6 / L);
  }
}

TEST(InvoluteGear, OffsetAlongNormalAndRotationKeepEveryNormal) {
  // docs/sources.md: all involutes of one base circle share their normals. (1) A point moved by a
  // along its normal is the point at roll length L + a of the involute offset by a: its normal
  // equals the original one. (2) Rotating the flank about the axis by beta equals an offset of
  // r_b beta along the normal: the rotated point is on the normal line of the original point.
  const InvoluteGear gear(p1_gear_parameters());
  const double r_b = gear.base_diameter_mm() / 2.0;
  for (FlankSide side : {FlankSide::kLeft, FlankSide::kRight}) {
    for (double L = 22.0; L < 45.0; L += 3.7) {
      const FlankPoint fp = gear.flank_point(5, side, L, 0);
      const double beta = 2e-4;  // rad
      const Eigen::Matrix3d rot =
          Eigen::AngleAxisd(side_sign(side) * beta, Eigen::Vector3d::UnitZ()).toRotationMatrix();
      // Rotating by +beta (R) or -beta (L) moves the base point of roll length L + r_b beta
      // onto the base point of roll length L, so rot * P(L + r_b beta) = P(L) + r_b beta n(L).
      const Eigen::Vector3d offset_point = fp.point + r_b * beta * fp.normal;
      const FlankPoint at = gear.flank_point(5, side, L + r_b * beta, 0);
      const Eigen::Vector3d on_rotated = rot * at.point;
      // Points of the rotated flank lie on the offset involute: distance along n.
      // rot * P(L + r_b beta) = P(L) + r_b beta n(L) exactly.
      EXPECT_NEAR((on_rotated - offset_point).norm(), 0.0, 1e-9);
      // ... and the normal there is unchanged.
      EXPECT_NEAR(((rot * at.normal) - fp.normal).norm(), 0.0, 1e-12);
    }
  }
}

TEST(InvoluteGear, ValidationSaysWhatIsWrong) {
  GearParameters p = p1_gear_parameters();
  p.profile_shift = 2.5;  // pointed teeth
  EXPECT_NE(validate_gear_parameters(p).find("pointed"), std::string::npos);
  p = p1_gear_parameters();
  p.teeth = 3;
  EXPECT_NE(validate_gear_parameters(p).find("teeth"), std::string::npos);
  p = p1_gear_parameters();
  p.tip_diameter_mm = 120.0;  // below the base circle
  EXPECT_NE(validate_gear_parameters(p).find("base diameter"), std::string::npos);
}

}  // namespace
}  // namespace gearmc
