// Internal (ring) gear geometry (gears/involute_gear.h) against independent references written
// out in this file from the standards' formulas, not from gearmc's code:
//  * ISO 21771:2007's relations with its signed tooth count z < 0 (d = z m_t < 0, d_a = d +
//    2 m_n (h_aP + x), d_f = d - 2 m_n (h_fP - x), s_t = m_t (pi/2 + 2 x tan(alpha_n))), compared
//    as magnitudes;
//  * the internal tooth's half angle at radius r_y (DIN 3960, Niemann/Winter vol. 2 §21): the
//    space is shaped like an external tooth, so psi_y = s_t / d - inv(alpha_t) + inv(alpha_y):
//    every flank point lies at polar angle +/- psi_y from its tooth's centre line (turned by the
//    helix at height z);
//  * the dimension between balls M_iK (DIN 3960 with signed z): inv(alpha_M) = D_M / (m_n z
//    cos(alpha_n)) + inv(alpha_t) - (pi/2 - 2 x tan(alpha_n)) / z, z < 0; a ball there touches
//    both flanks of its space, checked by a grid search over gearmc's flank points;
//  * finite-difference tangents for the normal, and "outward" tested geometrically: a step along
//    the normal leaves the tooth (its polar angle moves outside +/- psi_y).
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <numbers>

#include "gears/involute_gear.h"
#include "tests/support/nearest_flank_point.h"

namespace gearmc {
namespace {

constexpr double kPi = std::numbers::pi;

double inv(double a) { return std::tan(a) - a; }

GearParameters ring(int z, double beta_deg, double x, Hand hand = Hand::kRight) {
  GearParameters p;
  p.teeth = z;
  p.internal = true;
  p.module_mm = 2.0;
  p.pressure_angle_deg = 20.0;
  p.helix_angle_deg = beta_deg;
  p.hand = hand;
  p.profile_shift = x;
  p.face_width_mm = 25.0;
  return p;
}

struct Case {
  int z;
  double beta_deg, x;
  Hand hand;
};
const Case kCases[] = {{60, 0.0, 0.0, Hand::kRight},
                       {48, 0.0, 0.3, Hand::kRight},
                       {71, 15.0, 0.2, Hand::kRight},
                       {55, 25.0, -0.1, Hand::kLeft}};

TEST(InternalGear, DimensionsAreIso21771sWithSignedToothCount) {
  for (const Case& c : kCases) {
    const GearParameters p = ring(c.z, c.beta_deg, c.x, c.hand);
    ASSERT_EQ(validate_gear_parameters(p), "") << c.z;
    const InvoluteGear g(p);
    const double z = -c.z, m_n = 2.0, beta = c.beta_deg * kPi / 180, alpha_n = 20 * kPi / 180;
    const double m_t = m_n / std::cos(beta);
    const double alpha_t = std::atan(std::tan(alpha_n) / std::cos(beta));
    const double d = z * m_t;  // negative
    EXPECT_NEAR(g.reference_diameter_mm(), -d, 1e-12);
    EXPECT_NEAR(g.tip_diameter_mm(), -(d + 2 * m_n * (1.0 + c.x)), 1e-12);
    EXPECT_NEAR(g.root_diameter_mm(), -(d - 2 * m_n * (1.25 - c.x)), 1e-12);
    EXPECT_NEAR(g.base_diameter_mm(), -d * std::cos(alpha_t), 1e-12);
    EXPECT_NEAR(g.tooth_thickness_mm(), m_t * (kPi / 2 + 2 * c.x * std::tan(alpha_n)), 1e-12);
    EXPECT_LT(g.tip_diameter_mm(), g.reference_diameter_mm());
    EXPECT_GT(g.root_diameter_mm(), g.reference_diameter_mm());
    // The active profile runs from the tip (smallest L) out to the form circle.
    EXPECT_LT(g.tip_roll_length_mm(), g.form_roll_length_mm());
    EXPECT_EQ(g.active_roll_length_min_mm(), g.tip_roll_length_mm());
    EXPECT_EQ(g.active_roll_length_max_mm(), g.form_roll_length_mm());
    EXPECT_LT(g.form_diameter_mm(), g.root_diameter_mm());
  }
}

// Every flank point at the tooth's half angle psi_y (DIN 3960) from its centre line, at radius
// sqrt(r_b^2 + L^2), in the section turned by z tan(beta) / r (right hand counter-clockwise).
TEST(InternalGear, FlankPointsLieOnTheInternalToothOfDin3960) {
  for (const Case& c : kCases) {
    const InvoluteGear g(ring(c.z, c.beta_deg, c.x, c.hand));
    const double beta = c.beta_deg * kPi / 180, alpha_n = 20 * kPi / 180;
    const double m_t = 2.0 / std::cos(beta), r = c.z * m_t / 2;
    const double alpha_t = std::atan(std::tan(alpha_n) / std::cos(beta));
    const double r_b = r * std::cos(alpha_t);
    const double s_t = m_t * (kPi / 2 + 2 * c.x * std::tan(alpha_n));
    const double turn = (c.hand == Hand::kRight ? 1.0 : -1.0) * std::tan(beta) / r;
    for (int tooth : {1, 7, c.z}) {
      for (FlankSide side : {FlankSide::kLeft, FlankSide::kRight}) {
        for (double L = g.tip_roll_length_mm(); L <= g.form_roll_length_mm(); L += 1.7) {
          for (double z : {0.0, 9.0, 25.0}) {
            const FlankPoint fp = g.flank_point(tooth, side, L, z);
            const double r_y = std::hypot(r_b, L);
            const double psi = s_t / (2 * r) - inv(alpha_t) + inv(std::acos(r_b / r_y));
            const double angle = (tooth - 1) * 2 * kPi / c.z + side_sign(side) * psi + z * turn;
            const Eigen::Vector3d expected(r_y * std::cos(angle), r_y * std::sin(angle), z);
            EXPECT_NEAR((fp.point - expected).norm(), 0.0, 1e-11) << c.z << " L " << L;
          }
        }
      }
    }
  }
}

// Normals: unit, perpendicular to both tangents, out of the material: a small step along the
// normal moves the point out of the tooth (its polar angle beyond +/- psi_y at its own radius)
// and the transverse part turns counter-clockwise on R (docs/formats.md). The profile curvature
// is the concave involute's, -1/L.
TEST(InternalGear, NormalsAreUnitPerpendicularAndLeaveTheMaterial) {
  for (const Case& c : kCases) {
    const InvoluteGear g(ring(c.z, c.beta_deg, c.x, c.hand));
    constexpr double h = 1e-4;
    for (int tooth : {1, 5}) {
      for (FlankSide side : {FlankSide::kLeft, FlankSide::kRight}) {
        for (double L = g.tip_roll_length_mm() + 0.1; L < g.form_roll_length_mm(); L += 2.3) {
          for (double z : {0.0, 11.0}) {
            const FlankPoint fp = g.flank_point(tooth, side, L, z);
            EXPECT_NEAR(fp.normal.norm(), 1.0, 1e-14);
            const Eigen::Vector3d along_L = (g.flank_point(tooth, side, L + h, z).point -
                                             g.flank_point(tooth, side, L - h, z).point) /
                                            (2 * h);
            const Eigen::Vector3d along_z = (g.flank_point(tooth, side, L, z + h).point -
                                             g.flank_point(tooth, side, L, z - h).point) /
                                            (2 * h);
            EXPECT_NEAR(along_L.normalized().dot(fp.normal), 0.0, 1e-8);
            EXPECT_NEAR(along_z.normalized().dot(fp.normal), 0.0, 1e-8);
            const Eigen::Vector3d ccw = Eigen::Vector3d::UnitZ().cross(fp.point).normalized();
            EXPECT_GT(side_sign(side) * fp.normal.dot(ccw), 0.0);
            // The section at z turned back to z = 0: the point stepped along the normal lies
            // outside the tooth's angular extent at its radius.
            const Eigen::Vector3d q = fp.point + 0.01 * fp.normal;
            const double back = -q.z() * g.helix_turn_per_mm();
            const double phi = std::remainder(
                std::atan2(q.y(), q.x()) + back - g.tooth_centre_angle_rad(tooth), 2 * kPi);
            const double psi = g.half_tooth_angle_rad(2 * std::hypot(q.x(), q.y()));
            EXPECT_GT(std::abs(phi), psi) << c.z << " L " << L;
            EXPECT_EQ(fp.profile_curvature_per_mm, -1.0 / L);
          }
        }
      }
    }
  }
}

// M_iK: the ball of diameter D_M on the space's centre line at r_M = r_b / cos(alpha_M) (DIN
// 3960 with signed z) touches both flanks of the space: the nearest flank point, by a nested grid
// search over gearmc's flank points (no Newton), is D_M / 2 away. M_iK = 2 r_M - D_M (even z) or
// 2 r_M cos(pi / 2|z|) - D_M (odd z) lies between the tip and the root circle.
TEST(InternalGear, BallInEveryToothSpaceIsDin3960sDimensionBetweenBalls) {
  for (const Case& c : kCases) {
    const InvoluteGear g(ring(c.z, c.beta_deg, c.x, c.hand));
    const double z = -c.z, m_n = 2.0, alpha_n = 20 * kPi / 180, beta = c.beta_deg * kPi / 180;
    const double alpha_t = std::atan(std::tan(alpha_n) / std::cos(beta));
    const double r = c.z * m_n / std::cos(beta) / 2, r_b = r * std::cos(alpha_t);
    const double D_M = 1.44 * m_n;  // a usual ball for an internal gear of alpha_n 20°
    const double target = D_M / (m_n * z * std::cos(alpha_n)) + inv(alpha_t) -
                          (kPi / 2 - 2 * c.x * std::tan(alpha_n)) / z;
    double alpha_M = 0.4;
    for (int i = 0; i < 60; ++i)
      alpha_M -= (inv(alpha_M) - target) / std::pow(std::tan(alpha_M), 2);
    const double r_M = r_b / std::cos(alpha_M);
    const double M_iK = (c.z % 2 == 0 ? 2 * r_M : 2 * r_M * std::cos(kPi / (2 * c.z))) - D_M;
    EXPECT_GT(M_iK + D_M, g.tip_diameter_mm());
    EXPECT_LT(M_iK, g.root_diameter_mm());
    const double turn = (c.hand == Hand::kRight ? 1.0 : -1.0) * std::tan(beta) / r;
    for (const int k : {1, c.z / 2}) {
      const double z0 = 12.0;
      const double angle = (k - 1) * 2 * kPi / c.z + kPi / c.z + z0 * turn;
      const Eigen::Vector3d centre(r_M * std::cos(angle), r_M * std::sin(angle), z0);
      for (const auto& [tooth, side] :
           {std::pair<int, FlankSide>{k, FlankSide::kRight}, {k % c.z + 1, FlankSide::kLeft}}) {
        const testing_support::NearestFlankPoint near = testing_support::nearest_flank_point(
            g, tooth, side, centre, std::sqrt(r_M * r_M - r_b * r_b), z0);
        const double L = near.roll_length_mm;
        EXPECT_NEAR(near.distance_mm, D_M / 2, 1e-9) << c.z << " tooth " << tooth;
        EXPECT_GT(L, g.active_roll_length_min_mm());  // the ball touches the involute itself
        EXPECT_LT(L, g.active_roll_length_max_mm());
      }
    }
  }
}

// The transverse position of a point against a flank (distance along the base tangent, roll
// length of the foot) agrees with the flank point it names, and with its gradient.
TEST(InternalGear, TransversePositionNamesTheFlankPointAndItsDistance) {
  const InvoluteGear g(ring(60, 0.0, 0.1));
  for (FlankSide side : {FlankSide::kLeft, FlankSide::kRight}) {
    for (double L : {15.0, 20.0, 25.0}) {
      const FlankPoint fp = g.flank_point(3, side, L, 0.0);
      for (double d : {-0.3, 0.0, 0.2}) {
        const Eigen::Vector2d X = (fp.point + d * fp.normal).head<2>();
        const TransversePosition at = g.transverse_position(3, side, X);
        EXPECT_NEAR(at.distance_mm, d, 1e-12);
        EXPECT_NEAR(at.foot_roll_length_mm, L, 1e-11);
        EXPECT_NEAR((at.distance_gradient - fp.normal.head<2>()).norm(), 0.0, 1e-12);
        const Eigen::Vector2d step(1e-6, -2e-6);
        const double fd = (g.transverse_position(3, side, X + step).foot_roll_length_mm -
                           g.transverse_position(3, side, X - step).foot_roll_length_mm) /
                          2;
        EXPECT_NEAR(fd, at.foot_gradient.dot(step), 1e-12);
      }
    }
  }
}

TEST(InternalGear, ImpossibleRingGearsAreRefusedWithTheReason) {
  GearParameters p = ring(60, 0.0, 0.0);
  p.pressure_angle_deg = 30.0;
  p.teeth = 12;  // the tip circle falls inside the base circle
  EXPECT_NE(validate_gear_parameters(p).find("not above the base diameter"), std::string::npos)
      << validate_gear_parameters(p);
  p = ring(60, 0.0, 0.0);
  p.form_diameter_mm = 130.0;  // beyond the root circle 125
  EXPECT_NE(validate_gear_parameters(p).find("form_diameter_mm = 130"), std::string::npos)
      << validate_gear_parameters(p);
  p = ring(60, 0.0, 0.0);
  p.root_diameter_mm = 115.0;
  EXPECT_NE(validate_gear_parameters(p).find("not above its tip diameter"), std::string::npos)
      << validate_gear_parameters(p);
  p = ring(60, 0.0, 0.0);
  p.form_diameter_mm = 122.0;  // a pinion-type cutter's form circle: accepted
  EXPECT_EQ(validate_gear_parameters(p), "");
  EXPECT_NEAR(InvoluteGear(p).form_diameter_mm(), 122.0, 1e-12);
}

}  // namespace
}  // namespace gearmc
