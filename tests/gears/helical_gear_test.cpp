// Helical gear geometry (gears/involute_gear.h) against independent references: the ISO 21771
// relations evaluated in Python (tests/gears/helical_reference.py, its printed values quoted
// below), the base tangent length W_k measured between two flank tangent planes built from
// gearmc's 3D points and normals, the screw motion that defines the helicoid and its hand
// (docs/formats.md, "Helical and internal gears"), finite-difference tangents, and the mirror
// image that turns a right-hand gear into a left-hand one.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <numbers>

#include "gears/involute_gear.h"
#include "tests/support/nearest_flank_point.h"

namespace gearmc {
namespace {

constexpr double kPi = std::numbers::pi;

// The example: z 31, m_n 4, alpha_n 20°, beta 15°, x 0.2, ISO 53 profile A.
GearParameters helical_parameters(Hand hand = Hand::kRight) {
  GearParameters p;
  p.teeth = 31;
  p.module_mm = 4.0;
  p.pressure_angle_deg = 20.0;
  p.helix_angle_deg = 15.0;
  p.hand = hand;
  p.profile_shift = 0.2;
  p.face_width_mm = 40.0;
  return p;
}

TEST(HelicalGear, TransverseQuantitiesAreIso21771s) {
  ASSERT_EQ(validate_gear_parameters(helical_parameters()), "");
  const InvoluteGear g(helical_parameters());
  // python3 tests/gears/helical_reference.py (12 decimals printed; 1e-9 mm / deg leaves room for
  // the last bits of a different evaluation order).
  EXPECT_NEAR(g.transverse_module_mm(), 4.141104721640, 1e-9);
  EXPECT_NEAR(g.transverse_pressure_angle_rad() * 180 / kPi, 20.646896487046, 1e-9);
  EXPECT_NEAR(g.reference_diameter_mm(), 128.374246370850, 1e-9);
  EXPECT_NEAR(g.base_diameter_mm(), 120.128927774273, 1e-9);
  EXPECT_NEAR(g.base_helix_angle_rad() * 180 / kPi, 14.076095421662, 1e-9);
  EXPECT_NEAR(g.lead_mm(), 1505.134557972064, 1e-8);
  EXPECT_NEAR(g.tip_diameter_mm(), 137.974246370850, 1e-9);
  EXPECT_NEAR(g.root_diameter_mm(), 119.974246370850, 1e-9);
  EXPECT_NEAR(g.tooth_thickness_mm(), 7.107727627888, 1e-9);
  EXPECT_TRUE(g.helical());
  EXPECT_EQ(g.hand(), Hand::kRight);
  // The section turns by tan(beta) / r per mm, counter-clockwise for a right hand.
  EXPECT_NEAR(g.helix_turn_per_mm(), std::tan(15 * kPi / 180) / (128.374246370850 / 2), 1e-15);
  EXPECT_LT(InvoluteGear(helical_parameters(Hand::kLeft)).helix_turn_per_mm(), 0.0);
}

TEST(HelicalGear, SpurGearKeepsItsNormalValuesExactly) {
  GearParameters p = helical_parameters();
  p.helix_angle_deg = 0.0;
  const InvoluteGear g(p);
  EXPECT_FALSE(g.helical());
  EXPECT_EQ(g.transverse_module_mm(), 4.0);  // bit for bit, not near
  EXPECT_EQ(g.transverse_pressure_angle_rad(), g.pressure_angle_rad());
  EXPECT_EQ(g.helix_turn_per_mm(), 0.0);
  EXPECT_EQ(g.base_helix_angle_rad(), 0.0);
  EXPECT_TRUE(std::isinf(g.lead_mm()));
  const FlankPoint fp = g.flank_point(3, FlankSide::kLeft, 20.0, 7.0);
  EXPECT_EQ(fp.normal.z(), 0.0);
  EXPECT_EQ(fp.base_point.z(), 7.0);
}

// W_k measured on the model: the R flank of tooth k and the L flank of tooth 1 at the same height
// and the same base angle psi have opposite normals (their tangent planes are parallel); the
// distance between the planes is W_k. ISO 21771's closed form, evaluated in Python:
// W_2 20.177200838911, W_4 43.794252311659, W_6 67.411303784408 mm.
TEST(HelicalGear, BaseTangentLengthBetweenTangentPlanesIsIso21771s) {
  const InvoluteGear g(helical_parameters());
  const double r_b = g.base_diameter_mm() / 2;
  const std::pair<int, double> cases[] = {
      {2, 20.177200838911}, {4, 43.794252311659}, {6, 67.411303784408}};
  for (const auto& [k, expected] : cases) {
    for (double z : {0.0, 7.0, 33.0}) {
      // psi: the base angle where the common normal touches the base cylinder, half-way between
      // the two flanks' starts at this height; the roll lengths follow from phi_b(L) = psi.
      const double turn = z * g.helix_turn_per_mm();
      const double start_R = (k - 1) * g.angular_pitch_rad() + g.base_half_angle_rad() + turn;
      const double start_L = -g.base_half_angle_rad() + turn;
      const double psi = 0.5 * (start_R + start_L);
      const double L_R = r_b * (start_R - psi), L_L = r_b * (psi - start_L);
      const FlankPoint R = g.flank_point(k, FlankSide::kRight, L_R, z);
      const FlankPoint L = g.flank_point(1, FlankSide::kLeft, L_L, z);
      EXPECT_NEAR((R.normal + L.normal).norm(), 0.0, 1e-14) << k << " " << z;
      EXPECT_NEAR((R.point - L.point).dot(R.normal), expected, 1e-9) << k << " " << z;
    }
  }
}

// The dimension over balls M_dK (ISO 21771 / DIN 3960): a ball of diameter D_M in a tooth space
// touching both flanks has its centre on the space's centre line at the radius r_M = r_b /
// cos(alpha_Mt), inv(alpha_Mt) = D_M / (m_n z cos(alpha_n)) + inv(alpha_t) - (pi/2 - 2 x
// tan(alpha_n)) / z, written out here from the standard's formula (not gearmc's code), and
// M_dK = 2 r_M + D_M (even z) or 2 r_M cos(pi / 2z) + D_M (odd z). Checked on the model: from
// that centre (in the section z0, on the space's centre line turned with the helix), the nearest
// point of each of the space's two flanks (found by a nested grid search over the flank's
// points, no Newton) is D_M / 2 away, to 1e-9 mm, for spur and helical gears of both hands and
// several z, beta, x.
TEST(HelicalGear, BallInEveryToothSpaceIsIso21771sDimensionOverBalls) {
  struct Case {
    int z;
    double beta_deg, x;
    Hand hand;
  };
  const Case cases[] = {{31, 15.0, 0.2, Hand::kRight},
                        {24, 0.0, 0.5, Hand::kRight},
                        {17, 30.0, -0.2, Hand::kLeft},
                        {40, 22.0, 0.6, Hand::kRight}};
  for (const Case& c : cases) {
    GearParameters p;
    p.teeth = c.z;
    p.module_mm = 4.0;
    p.pressure_angle_deg = 20.0;
    p.helix_angle_deg = c.beta_deg;
    p.hand = c.hand;
    p.profile_shift = c.x;
    p.face_width_mm = 40.0;
    ASSERT_EQ(validate_gear_parameters(p), "");
    const InvoluteGear g(p);
    // The standard's quantities, from the design data alone.
    const double m_n = 4.0, alpha_n = 20.0 * kPi / 180, beta = c.beta_deg * kPi / 180;
    const double alpha_t = std::atan(std::tan(alpha_n) / std::cos(beta));
    const double r = c.z * m_n / std::cos(beta) / 2, r_b = r * std::cos(alpha_t);
    const auto inv = [](double a) { return std::tan(a) - a; };
    const double D_M = 1.68 * m_n;  // a usual ball for alpha_n 20°
    const double target = D_M / (m_n * c.z * std::cos(alpha_n)) + inv(alpha_t) -
                          (kPi / 2 - 2 * c.x * std::tan(alpha_n)) / c.z;
    double alpha_M = 0.5;
    for (int i = 0; i < 60; ++i) {  // Newton on inv(a) = target; inv'(a) = tan²(a)
      alpha_M -= (inv(alpha_M) - target) / (std::tan(alpha_M) * std::tan(alpha_M));
    }
    const double r_M = r_b / std::cos(alpha_M);
    const double M_dK = (c.z % 2 == 0 ? 2 * r_M : 2 * r_M * std::cos(kPi / (2 * c.z))) + D_M;
    const double turn = (c.hand == Hand::kRight ? 1.0 : -1.0) * std::tan(beta) / r;
    for (const int k : {1, c.z / 2}) {
      const double z0 = 20.0;
      const double angle = (k - 1) * 2 * kPi / c.z + kPi / c.z + z0 * turn;
      const Eigen::Vector3d centre(r_M * std::cos(angle), r_M * std::sin(angle), z0);
      for (const auto& [tooth, side] :
           {std::pair<int, FlankSide>{k, FlankSide::kRight}, {k % c.z + 1, FlankSide::kLeft}}) {
        const testing_support::NearestFlankPoint near = testing_support::nearest_flank_point(
            g, tooth, side, centre, std::sqrt(r_M * r_M - r_b * r_b), z0);
        const double L = near.roll_length_mm;
        EXPECT_NEAR(near.distance_mm, D_M / 2, 1e-9)
            << c.z << " " << c.beta_deg << " tooth " << tooth;
        EXPECT_GT(L, g.form_roll_length_mm());  // the ball touches the involute itself
        EXPECT_LT(L, g.tip_roll_length_mm());
      }
    }
    EXPECT_GT(M_dK, g.tip_diameter_mm() - 2 * m_n);  // a sane size: near the tip diameter
    EXPECT_LT(M_dK, g.tip_diameter_mm() + D_M);
  }
}

// The helicoid is the transverse involute under the screw motion of the hand: the point at
// height z is the point at 0 turned counter-clockwise (right hand) by z tan(beta) / r and lifted
// by z (docs/formats.md); its normal turns with it.
TEST(HelicalGear, FlankIsTheScrewMotionOfItsSection) {
  for (Hand hand : {Hand::kRight, Hand::kLeft}) {
    const InvoluteGear g(helical_parameters(hand));
    const double per_mm = hand_sign(hand) * std::tan(15 * kPi / 180) / (128.374246370850 / 2);
    for (int tooth : {1, 9, 31}) {
      for (FlankSide side : {FlankSide::kLeft, FlankSide::kRight}) {
        for (double L : {12.0, 20.0, 27.0}) {
          const FlankPoint base = g.flank_point(tooth, side, L, 0.0);
          for (double z : {-3.0, 5.0, 40.0}) {
            const Eigen::AngleAxisd screw(z * per_mm, Eigen::Vector3d::UnitZ());
            const FlankPoint fp = g.flank_point(tooth, side, L, z);
            const Eigen::Vector3d expected = screw * base.point + Eigen::Vector3d(0, 0, z);
            EXPECT_NEAR((fp.point - expected).norm(), 0.0, 1e-12);
            EXPECT_NEAR((fp.normal - screw * base.normal).norm(), 0.0, 1e-14);
          }
        }
      }
    }
  }
}

// Normals: unit, perpendicular to the tangents along L and z (central differences of the point),
// outward as on a spur gear (the transverse part: R counter-clockwise), tilted out of the
// transverse plane by the base helix angle; the normal line meets the base cylinder at the base
// point.
TEST(HelicalGear, NormalsAreUnitPerpendicularOutwardAndTiltedByTheBaseHelixAngle) {
  for (Hand hand : {Hand::kRight, Hand::kLeft}) {
    const InvoluteGear g(helical_parameters(hand));
    const double beta_b = 14.076095421662 * kPi / 180;  // helical_reference.py
    const double r_b = g.base_diameter_mm() / 2;
    constexpr double h = 1e-4;
    for (int tooth = 1; tooth <= 31; tooth += 5) {
      for (FlankSide side : {FlankSide::kLeft, FlankSide::kRight}) {
        for (double L = 11.0; L < 29.0; L += 3.1) {
          for (double z : {0.0, 13.0, 40.0}) {
            const FlankPoint fp = g.flank_point(tooth, side, L, z);
            EXPECT_NEAR(fp.normal.norm(), 1.0, 1e-14);
            const Eigen::Vector3d along_L = (g.flank_point(tooth, side, L + h, z).point -
                                             g.flank_point(tooth, side, L - h, z).point) /
                                            (2 * h);
            const Eigen::Vector3d along_z = (g.flank_point(tooth, side, L, z + h).point -
                                             g.flank_point(tooth, side, L, z - h).point) /
                                            (2 * h);
            // 1e-8: the differences' rounding, 1e-16 x 70 mm / 2h, over |dP/dL| = L / r_b.
            EXPECT_NEAR(along_L.normalized().dot(fp.normal), 0.0, 1e-8);
            EXPECT_NEAR(along_z.normalized().dot(fp.normal), 0.0, 1e-8);
            EXPECT_NEAR(std::abs(fp.normal.z()), std::sin(beta_b), 1e-12);
            const Eigen::Vector3d ccw = Eigen::Vector3d::UnitZ().cross(fp.point).normalized();
            EXPECT_GT(side_sign(side) * fp.normal.dot(ccw), 0.0);
            // The normal line through the point reaches the base cylinder at the base point,
            // L / cos(beta_b) away.
            const Eigen::Vector3d foot = fp.point - L / std::cos(beta_b) * fp.normal;
            EXPECT_NEAR((foot - fp.base_point).norm(), 0.0, 1e-9);
            EXPECT_NEAR(std::hypot(foot.x(), foot.y()), r_b, 1e-9);
          }
        }
      }
    }
  }
}

// A left-hand gear is the mirror image of the right-hand one in the plane z = 0.
TEST(HelicalGear, LeftHandIsTheMirrorImageOfRightHand) {
  const InvoluteGear right(helical_parameters(Hand::kRight));
  const InvoluteGear left(helical_parameters(Hand::kLeft));
  const Eigen::Vector3d mirror(1, 1, -1);
  for (FlankSide side : {FlankSide::kLeft, FlankSide::kRight}) {
    for (double z : {0.0, 6.0, 25.0}) {
      const FlankPoint r = right.flank_point(4, side, 18.0, z);
      const FlankPoint l = left.flank_point(4, side, 18.0, -z);
      EXPECT_NEAR((l.point - r.point.cwiseProduct(mirror)).norm(), 0.0, 1e-12);
      EXPECT_NEAR((l.normal - r.normal.cwiseProduct(mirror)).norm(), 0.0, 1e-14);
    }
  }
}

TEST(HelicalGear, HelixAngleOutsideItsRangeIsSaid) {
  GearParameters p = helical_parameters();
  p.helix_angle_deg = 45.0;
  EXPECT_NE(validate_gear_parameters(p).find("helix_angle_deg = 45: must lie in [0, 45)"),
            std::string::npos)
      << validate_gear_parameters(p);
  p.helix_angle_deg = -5.0;
  EXPECT_NE(validate_gear_parameters(p).find("the hand gives the direction"), std::string::npos);
}

}  // namespace
}  // namespace gearmc
