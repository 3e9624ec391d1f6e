// The stylus shaft in the tooth space (engine/contact/tooth_space.h), against independent
// answers:
//  * a shaft parallel to the axis: its clearance is a lower bound of, and within 0.1 µm of, a
//    brute-force search (heights on a fine grid, then golden refinement; in each section the
//    distance to the flank's own points flank_point(L, z) over a dense grid of roll lengths,
//    refined) on helical gears of both hands and a helical ring gear;
//  * a radial shaft: its clearance is a lower bound of the distance in space from the shaft's
//    axis to the flanks (nested grid search over the helicoid, tests/support/
//    nearest_flank_point.h) minus the shaft radius (above 0.1 mm the bound is not refined);
//  * physics: a spur gear's shaft (thinner than the ball) never collides in either direction (the
//    section does not turn; outwards the space widens); on a helical gear the space turns under
//    an axial shaft: on one flank side the probed flank meets it, on the other the facing flank,
//    after the heights the first-order estimate (d - r_s) / (tan(beta_y) cos(alpha_y)) predicts,
//    and the hand swaps the sides.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "engine/contact/tooth_space.h"
#include "tests/support/helical_fixtures.h"
#include "tests/support/nearest_flank_point.h"
#include "tests/support/p1_fixtures.h"

namespace gearmc {
namespace {

using testing_support::helical_gear;
using testing_support::helical_ring;
using testing_support::p1_gear;

// The flank facing (tooth, side) across the space (R of k faces L of k+1), written out here.
std::pair<int, FlankSide> facing(const InvoluteGear& g, int tooth, FlankSide side) {
  const int z = g.teeth();
  if (side == FlankSide::kRight) return {tooth == z ? 1 : tooth + 1, FlankSide::kLeft};
  return {tooth == 1 ? z : tooth - 1, FlankSide::kRight};
}

// Minimum of f on [a, b] by golden-section search (f unimodal near its minimum there).
template <class F>
double golden_minimum(const F& f, double a, double b) {
  const double r = 0.5 * (std::sqrt(5.0) - 1.0);
  double c = b - r * (b - a), d = a + r * (b - a), fc = f(c), fd = f(d);
  for (int k = 0; k < 80; ++k) {
    if (fc < fd) {
      b = d, d = c, fd = fc, c = b - r * (b - a), fc = f(c);
    } else {
      a = c, c = d, fc = fd, d = a + r * (b - a), fd = f(d);
    }
  }
  return std::min({fc, fd, f(a), f(b)});
}

// Minimum of f over [a, b]: a grid of n, then golden refinement between the best node's
// neighbours.
template <class F>
double brute_minimum(const F& f, double a, double b, int n) {
  int best_k = 0;
  double best = f(a);
  for (int k = 1; k <= n; ++k) {
    const double v = f(a + (b - a) * k / n);
    if (v < best) best = v, best_k = k;
  }
  const double lo = a + (b - a) * std::max(0, best_k - 1) / n;
  const double hi = a + (b - a) * std::min(n, best_k + 1) / n;
  return std::min(best, golden_minimum(f, lo, hi));
}

// Distance in the section at height z from Y to the flank's points there, over the active
// profile (the flank's own points, flank_point(L, z): no transverse closed form).
double section_distance(const InvoluteGear& g, int tooth, FlankSide side, const Eigen::Vector2d& Y,
                        double z) {
  return brute_minimum(
      [&](double L) { return (g.flank_point(tooth, side, L, z).point.head<2>() - Y).norm(); },
      g.active_roll_length_min_mm(), g.active_roll_length_max_mm(), 400);
}

// The axial shaft's clearance by brute force: min over the heights from where the shaft leaves
// the ball (sqrt(R^2 - r_s^2) above the centre) to the top face of the sections' distances to
// both flanks, minus r_s; the root circle's clearance beside it.
double brute_axial_clearance(const InvoluteGear& g, int tooth, FlankSide side,
                             const Eigen::Vector3d& O, double R, double r_s) {
  const auto [ft, fs] = facing(g, tooth, side);
  const Eigen::Vector2d X = O.head<2>();
  const double z0 = O.z() + std::sqrt(R * R - r_s * r_s);
  const double flanks = brute_minimum(
      [&](double z) {
        return std::min(section_distance(g, tooth, side, X, z), section_distance(g, ft, fs, X, z));
      },
      z0, g.face_width_mm(), 300);
  const double r_root = 0.5 * g.root_diameter_mm();
  const double root = g.internal() ? r_root - X.norm() : X.norm() - r_root;
  return std::min(flanks, root) - r_s;
}

TEST(StylusShaft, AxialClearanceIsWithinATenthOfAMicronBelowABruteForceSearch) {
  int checked = 0, colliding = 0;
  double worst_above = -1e300, worst_below = 0.0;
  const InvoluteGear gears[] = {helical_gear(Hand::kRight, 15.0), helical_gear(Hand::kLeft, 30.0),
                                helical_ring(Hand::kRight)};
  for (const InvoluteGear& g : gears) {
    ASSERT_NEAR(
        g.flank_point(2, FlankSide::kLeft, g.active_roll_length_min_mm() + 1.0, 7.5).point.z(), 7.5,
        1e-12);  // flank_point(L, z) lies in the section at height z
    const double L_lo = g.active_roll_length_min_mm(), L_hi = g.active_roll_length_max_mm();
    for (FlankSide side : {FlankSide::kLeft, FlankSide::kRight}) {
      for (double f : {0.15, 0.5, 0.85}) {
        for (double zf : {0.1, 0.5, 0.9}) {
          const double R = 0.75, r_s = 0.3;
          const double L = L_lo + f * (L_hi - L_lo), z = zf * g.face_width_mm();
          const FlankPoint fp = g.flank_point(2, side, L, z);
          const Eigen::Vector3d O = fp.point + R * fp.normal;
          const double v = shaft_clearance(g, 2, side, O, StylusShape{R, r_s, ShaftAxis::kZ});
          const double truth = brute_axial_clearance(g, 2, side, O, R, r_s);
          worst_above = std::max(worst_above, v - truth);  // must stay <= 0: a lower bound
          if (truth < 0.1) worst_below = std::max(worst_below, truth - v);
          colliding += truth < 0.0;
          ++checked;
        }
      }
    }
  }
  std::printf(
      "axial shaft: %d ball centres (%d colliding), bound - truth at most %.3g mm, "
      "truth - bound at most %.3g mm where below 0.1 mm\n",
      checked, colliding, worst_above, worst_below);
  EXPECT_EQ(checked, 54);
  EXPECT_GT(colliding, 5);  // the cases include collisions, not only clear shafts
  EXPECT_LE(worst_above, 1e-9);
  EXPECT_LE(worst_below, 1e-4 + 1e-6);  // kShaftTolerance, plus the brute force's own error
}

TEST(StylusShaft, RadialClearanceIsALowerBoundOfTheDistanceInSpace) {
  int checked = 0, inside_ball = 0;
  double worst_ratio = 1.0;
  for (const InvoluteGear& g : {helical_gear(Hand::kRight, 15.0), helical_ring(Hand::kLeft)}) {
    const double L_lo = g.active_roll_length_min_mm(), L_hi = g.active_roll_length_max_mm();
    for (FlankSide side : {FlankSide::kLeft, FlankSide::kRight}) {
      const auto [ft, fs] = facing(g, 2, side);
      for (double f : {0.2, 0.5, 0.8}) {
        const double R = 1.0, r_s = 0.4, z = 0.5 * g.face_width_mm();
        const FlankPoint fp = g.flank_point(2, side, L_lo + f * (L_hi - L_lo), z);
        const Eigen::Vector3d O = fp.point + R * fp.normal;
        const double v = shaft_clearance(g, 2, side, O, StylusShape{R, r_s, ShaftAxis::kRadial});
        // The shaft's axis: from where it leaves the ball along the radius, out to the tip
        // circle + r_s (a ring gear: inwards to its tip circle - r_s).
        const double r = O.head<2>().norm(), r_a = 0.5 * g.tip_diameter_mm();
        const Eigen::Vector3d u =
            (g.internal() ? -1.0 : 1.0) * Eigen::Vector3d(O.x(), O.y(), 0.0) / r;
        const double s0 = std::sqrt(R * R - r_s * r_s);
        const double s1 = g.internal() ? r - (r_a - r_s) : r_a + r_s - r;
        if (s1 <= s0) {  // the shaft leaves the tooth space inside the ball: nothing to check
          EXPECT_TRUE(std::isinf(v) || v > R);  // the root circle's clearance only
          ++inside_ball;
          continue;
        }
        double truth = 1e300;
        for (int k = 0; k <= 40; ++k) {
          const Eigen::Vector3d Y = O + (s0 + (s1 - s0) * k / 40.0) * u;
          for (const auto& [tooth, flank_side] : {std::pair{2, side}, std::pair{ft, fs}}) {
            // Start the search at the nearest of a coarse grid of the flank's points.
            double L0 = L_lo, z0 = z, d0 = 1e300;
            for (int a = 0; a <= 40; ++a) {
              for (double zz = 0.0; zz <= g.face_width_mm(); zz += 1.0) {
                const double La = L_lo + (L_hi - L_lo) * a / 40.0;
                const double d = (g.flank_point(tooth, flank_side, La, zz).point - Y).norm();
                if (d < d0) d0 = d, L0 = La, z0 = zz;
              }
            }
            truth = std::min(
                truth,
                testing_support::nearest_flank_point(g, tooth, flank_side, Y, L0, z0).distance_mm);
          }
        }
        truth -= r_s;
        ASSERT_GT(truth, 0.0);  // a radial shaft leaves the space the way the space widens
        EXPECT_LE(v, truth + 1e-9) << "side " << static_cast<int>(side) << " f " << f;
        worst_ratio = std::min(worst_ratio, v / truth);
        ++checked;
      }
    }
  }
  std::printf(
      "radial shaft: %d ball centres (%d more whose shaft leaves the space inside the "
      "ball), bound / clearance in space %.3f at least\n",
      checked, inside_ball, worst_ratio);
  EXPECT_EQ(checked + inside_ball, 12);
  EXPECT_GE(checked, 10);
  EXPECT_GT(worst_ratio, 0.0);  // positive: no false collision of a shaft that clears
}

TEST(StylusShaft, ASpurGearsShaftNeverCollides) {
  const InvoluteGear g = p1_gear();
  const double L_lo = g.active_roll_length_min_mm(), L_hi = g.active_roll_length_max_mm();
  int checked = 0;
  for (ShaftAxis axis : {ShaftAxis::kZ, ShaftAxis::kRadial}) {
    for (FlankSide side : {FlankSide::kLeft, FlankSide::kRight}) {
      for (int i = 0; i <= 10; ++i) {
        const double R = 0.5, r_s = 0.45;  // nearly as thick as the ball
        const FlankPoint fp = g.flank_point(3, side, L_lo + (L_hi - L_lo) * i / 10.0, 1.0);
        const Eigen::Vector3d O = fp.point + R * fp.normal;
        // The ball's own transverse distance to the probed flank is R; the shaft's is R too
        // (axial) or grows (radial): the clearance is at least R - r_s.
        EXPECT_GT(shaft_clearance(g, 3, side, O, StylusShape{R, r_s, axis}), R - r_s - 1e-4);
        ++checked;
      }
    }
  }
  EXPECT_EQ(checked, 44);
}

// First order: the section at height z_0 + h is turned by h k (k = helix_turn_per_mm) about the
// axis; a flank's point at the shaft's radius r moves r k h = h tan(beta_y) along the circle, of
// which cos(alpha_y) along the flank's transverse normal. One flank comes towards the shaft, the
// other goes away: the shaft, d (transverse, in the ball centre's section) from the flank that
// comes, meets it h* = (d - r_s) / (tan(beta_y) cos(alpha_y)) above the ball centre. The lowest
// ball whose shaft clears the gear lies h* below the top face.
TEST(StylusShaft, AHelicalSpaceTurnsUnderAnAxialShaftAsFirstOrderPredicts) {
  const double R = 1.0, r_s = 0.4;
  bool probed_side[2] = {false, false};  // right hand, left hand: the R flank's probed flank meets
  for (Hand hand : {Hand::kRight, Hand::kLeft}) {
    const InvoluteGear g = helical_gear(hand, 15.0);
    const double L = 0.5 * (g.active_roll_length_min_mm() + g.active_roll_length_max_mm());
    bool probed_flank_meets[2] = {false, false};  // L, R
    for (FlankSide side : {FlankSide::kLeft, FlankSide::kRight}) {
      // The lowest ball centre (probing at L, z on a 0.01 mm scan) whose shaft clears.
      Eigen::Vector3d lowest_clear(0, 0, -1);
      for (double z = 1.0; z <= g.face_width_mm() - 0.5; z += 0.01) {
        const FlankPoint fp = g.flank_point(2, side, L, z);
        const Eigen::Vector3d O = fp.point + R * fp.normal;
        const bool clear = shaft_clearance(g, 2, side, O, StylusShape{R, r_s, ShaftAxis::kZ}) >= 0;
        if (!clear) lowest_clear.z() = -1;
        if (clear && lowest_clear.z() < 0) lowest_clear = O;
      }
      ASSERT_GT(lowest_clear.z(), 1.5) << "the low balls' shafts collide";
      const Eigen::Vector2d X = lowest_clear.head<2>();
      const double r = X.norm(), r_b = 0.5 * g.base_diameter_mm();
      const double tan_beta_y = r * std::abs(g.helix_turn_per_mm()), cos_alpha_y = r_b / r;
      const auto [ft, fs] = facing(g, 2, side);
      const double d_probed = section_distance(g, 2, side, X, lowest_clear.z());
      const double d_facing = section_distance(g, ft, fs, X, lowest_clear.z());
      const double h = g.face_width_mm() - lowest_clear.z();
      const double h_probed = (d_probed - r_s) / (tan_beta_y * cos_alpha_y);
      const double h_facing = (d_facing - r_s) / (tan_beta_y * cos_alpha_y);
      std::printf(
          "%s hand, %s flank: the shaft clears from %.2f mm below the top; first order: "
          "%.2f (probed flank), %.2f (facing flank)\n",
          hand == Hand::kRight ? "right" : "left", side == FlankSide::kRight ? "R" : "L", h,
          h_probed, h_facing);
      const bool probed = std::abs(h - h_probed) < std::abs(h - h_facing);
      EXPECT_NEAR(h, probed ? h_probed : h_facing, 0.02 * (probed ? h_probed : h_facing));
      probed_flank_meets[side == FlankSide::kRight ? 1 : 0] = probed;
    }
    // The turn brings one side's probed flank and the other side's facing flank.
    EXPECT_NE(probed_flank_meets[0], probed_flank_meets[1]);
    probed_side[hand == Hand::kRight ? 0 : 1] = probed_flank_meets[1];
  }
  // The hand swaps them.
  EXPECT_NE(probed_side[0], probed_side[1]);
}

}  // namespace
}  // namespace gearmc
