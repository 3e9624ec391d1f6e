// Stylus contact on helical flanks (involute helicoids), against independent answers:
//  * the nominal helicoid: on 10^4 random points of both hands and flanks, with three stylus
//    radii, the contact is the planned point itself, |C - O| = R and O - C lies along the
//    helicoid's normal at C to 1e-9 mm (a sphere touching a surface along its normal at a point
//    of a convex, developable surface touches it there first);
//  * smooth random (B-spline) fields: C and O agree with the nested brute-force grid search
//    (tests/support/p1_fixtures.h) to 1 nm, and the exact stage-1 bound (helical_exact_bound)
//    proves nearly all of them;
//  * steep bumps that put Newton on a lower maximum: no contact reported kOk lies below the
//    brute-force global maximum (the sheared sampled certificate), and the solver restarts;
//  * the tooth-space clearance is a lower bound of the distance in space to the facing helicoid
//    (found by search) and within 10 % of it;
//  * stage 1 (per point and per flank) bounds the curvature sampled by central differences of
//    the flank's points over every footprint, and the flank's bound changes no result.
// The independent reference in another language is helical_contact_reference.py (mpmath).
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>

#include "engine/contact/contact.h"
#include "engine/contact/contact_certificate.h"
#include "engine/contact/tooth_space.h"
#include "gears/deviations.h"
#include "gears/normal_expression.h"
#include "tests/support/alternating_form.h"
#include "tests/support/helical_fixtures.h"
#include "tests/support/p1_fixtures.h"
#include "tests/support/sampled_curvature.h"

namespace gearmc {
namespace {

using testing_support::helical_gear;

FlankExtent extent_of(const InvoluteGear& g) {
  return {g.form_roll_length_mm(), g.tip_roll_length_mm(), 0.0, g.face_width_mm()};
}

TEST(HelicalContact, OnTheNominalHelicoidTheContactIsThePlannedPoint) {
  const FlankDeviation none;
  std::mt19937_64 rng(20261127);  // fixed seed: the same 10^4 points every run
  int checked = 0;
  double worst_point = 0.0, worst_radius = 0.0, worst_along = 0.0;
  for (Hand hand : {Hand::kRight, Hand::kLeft}) {
    for (double beta : {8.0, 15.0, 30.0}) {
      const InvoluteGear gear = helical_gear(hand, beta);
      std::uniform_real_distribution<double> L_of(gear.form_roll_length_mm() + 1.0,
                                                  gear.tip_roll_length_mm() - 1.0);
      for (int k = 0; k < 1667; ++k) {
        const double R = k % 3 == 0 ? 0.5 : k % 3 == 1 ? 1.0 : 1.5;
        std::uniform_real_distribution<double> z_of(R + 0.5, gear.face_width_mm() - R - 0.5);
        const FlankSide side = k % 2 ? FlankSide::kRight : FlankSide::kLeft;
        const int tooth = 1 + k % gear.teeth();
        const AnalyticFlank flank(gear, tooth, side, none, Eigen::Vector2d::Zero());
        const double L = L_of(rng), z = z_of(rng);
        const FlankPoint fp = gear.flank_point(tooth, side, L, z);
        const ContactResult r = solve_contact(flank, extent_of(gear), fp.point, fp.normal, R, L, z);
        ASSERT_EQ(r.status, ContactResult::Status::kOk) << "L " << L << " z " << z;
        const Eigen::Vector3d normal_at_C = flank.evaluate(r.roll_length_mm, r.z_mm).real_normal();
        const Eigen::Vector3d OC = r.centre - r.contact;
        worst_point = std::max(worst_point, (r.contact - fp.point).norm());
        worst_radius = std::max(worst_radius, std::abs(OC.norm() - R));
        worst_along = std::max(worst_along, (OC - OC.dot(normal_at_C) * normal_at_C).norm());
        ++checked;
      }
    }
  }
  std::printf(
      "nominal helicoid: %d points, |C - p| %.3g mm, ||O - C| - R| %.3g mm, O - C off "
      "the normal %.3g mm\n",
      checked, worst_point, worst_radius, worst_along);
  EXPECT_EQ(checked, 10002);
  EXPECT_LT(worst_point, 1e-9);
  EXPECT_LT(worst_radius, 1e-9);
  EXPECT_LT(worst_along, 1e-9);
}

TEST(HelicalContact, RandomSmoothFieldsAgreeWithBruteForceAndStageOneProvesThem) {
  std::mt19937_64 rng(7);                                  // fixed seed
  std::normal_distribution<double> coefficient(0.0, 3.0);  // µm
  int checked = 0, stage_one = 0;
  double worst = 0.0;
  for (Hand hand : {Hand::kRight, Hand::kLeft}) {
    const InvoluteGear gear = helical_gear(hand);
    const double L_lo = gear.form_roll_length_mm() + 1.0, L_hi = gear.tip_roll_length_mm() - 1.0;
    for (int field = 0; field < 4; ++field) {
      FlankDeviation dev;
      dev.offset_um = coefficient(rng);
      dev.profile_slope_um_per_mm = 0.2 * coefficient(rng);
      dev.profile_mid_mm = 0.5 * (L_lo + L_hi);
      std::vector<double> pc(10), hc(8);
      for (double& c : pc) c = coefficient(rng);
      for (double& c : hc) c = coefficient(rng);
      dev.profile_form = CubicBSpline(L_lo - 1.0, L_hi + 1.0, pc);
      dev.helix_slope_um_per_mm = 0.2 * coefficient(rng);
      dev.helix_mid_mm = 20.0;
      dev.helix_form = CubicBSpline(0.0, 40.0, hc);
      for (FlankSide side : {FlankSide::kLeft, FlankSide::kRight}) {
        const int tooth = 1 + 5 * field;
        const AnalyticFlank flank(gear, tooth, side, dev, Eigen::Vector2d(0.003, -0.002));
        for (int k = 0; k < 8; ++k) {
          const double L = L_lo + (L_hi - L_lo) * (k + 0.5) / 8.0;
          const double z = 2.0 + 36.0 * ((k * 5) % 8 + 0.5) / 8.0;
          const double R = k % 2 ? 0.5 : 1.0;
          const FlankPoint fp = gear.flank_point(tooth, side, L, z);
          const ContactResult r =
              solve_contact(flank, extent_of(gear), fp.point, fp.normal, R, L, z);
          ASSERT_EQ(r.status, ContactResult::Status::kOk);
          const testing_support::BruteForcePoints b =
              testing_support::brute_force_contact_points(flank, fp.point, fp.normal, R, L, z);
          const Eigen::Vector3d& C = b.contact;
          EXPECT_LT((C - r.contact).norm(), 1e-6);  // 1 nm
          EXPECT_LT((b.centre - r.centre).norm(), 1e-6);
          EXPECT_NEAR((r.centre - r.contact).norm(), R, 1e-9);
          worst = std::max(worst, (C - r.contact).norm());
          const double kappa =
              exact_curvature_bound(flank, fp.point, fp.normal, R, L, z, gear.form_roll_length_mm(),
                                    gear.tip_roll_length_mm());
          if (kappa < 1.0 / R) ++stage_one;
          ++checked;
        }
      }
    }
  }
  std::printf(
      "helical smooth fields: %d points, worst |C - C_brute| %.3g nm, stage 1 proves "
      "%d\n",
      checked, 1e6 * worst, stage_one);
  EXPECT_EQ(checked, 128);
  // The exact bound must carry the smooth fields (else every contact pays the sampled stage).
  EXPECT_GE(stage_one, 120);
}

using testing_support::alternating_form;

// Stage 1 on helical flanks is a proof: the per-point bound (helical_exact_bound) is at least
// the largest sampled curvature over the footprint (9 x 9 samples over |L' - L0| <= R r_b / L0,
// |z - z0| <= R, L' = L - shear (z - z0) along the helicoid's generators), the flank's bound
// (helical_flank_bound) is at least every point's own, and with the flank's bound the solver's
// results are those without it, bit for bit. Fields: the smooth wavy one and a wavier one
// (+-20 µm every ~1.2 mm in L, ~0.7 mm in z: curvatures near 0.5 /mm).
TEST(HelicalContact, StageOneBoundsAreUpperBoundsOfTheSampledCurvature) {
  const double R = 0.5;
  FlankDeviation wavier;
  wavier.profile_form = alternating_form(12.0, 36.0, 20, 20.0);
  wavier.helix_form = alternating_form(0.0, 40.0, 60, 20.0);
  int points = 0, proven_by_point = 0, proven_by_flank = 0;
  double least_margin = 1e300;
  for (Hand hand : {Hand::kRight, Hand::kLeft}) {
    const InvoluteGear gear = helical_gear(hand);
    const FlankExtent extent = extent_of(gear);
    const double r_b = 0.5 * gear.base_diameter_mm();
    for (const FlankDeviation& dev : {testing_support::helical_wavy_deviation(), wavier}) {
      for (FlankSide side : {FlankSide::kLeft, FlankSide::kRight}) {
        const AnalyticFlank flank(gear, 4, side, dev, Eigen::Vector2d(0.004, 0.003));
        const FlankCurvatureBound bound =
            flank_curvature_bound(flank, R, extent.roll_length_min, extent.roll_length_max);
        const double shear = flank.frame_turn_per_mm() * r_b;
        for (int i = 0; i < 6; ++i) {
          for (int j = 0; j < 4; ++j) {
            const double L0 = extent.roll_length_min + 0.5 +
                              (extent.roll_length_max - extent.roll_length_min - 1.0) * i / 5.0;
            const double z0 = 2.0 + 36.0 * j / 3.0;
            const FlankPoint fp = gear.flank_point(4, side, L0, z0);
            const double kappa =
                exact_curvature_bound(flank, fp.point, fp.normal, R, L0, z0, extent.roll_length_min,
                                      extent.roll_length_max);
            ++points;
            if (!std::isfinite(kappa)) continue;
            double sampled = -1e300;
            const double half_L = R * r_b / L0;
            for (int a = -4; a <= 4; ++a) {
              for (int b = -4; b <= 4; ++b) {
                const double z = z0 + b * R / 4;
                const double L = L0 + a * half_L / 4 + shear * (z - z0);
                if (L < extent.roll_length_min || L > extent.roll_length_max) continue;
                sampled = std::max(sampled,
                                   testing_support::fd_curvature(flank, fp.point, fp.normal, L, z));
              }
            }
            EXPECT_GE(kappa, sampled - 1e-6) << "L0 " << L0 << " z0 " << z0;
            least_margin = std::min(least_margin, kappa - sampled);
            if (kappa < 1.0 / R) ++proven_by_point;
            if (std::isfinite(bound.kappa)) {
              EXPECT_GE(bound.kappa, kappa - 1e-12);
              if (bound.kappa < 1.0 / R) ++proven_by_flank;
            }
            // The same contact with and without the flank's bound.
            const ContactResult with = solve_contact(flank, extent, fp.point, fp.normal, R, L0, z0,
                                                     planned_base_angle(fp), &bound);
            const ContactResult without =
                solve_contact(flank, extent, fp.point, fp.normal, R, L0, z0);
            ASSERT_EQ(with.status, without.status);
            EXPECT_EQ(with.contact, without.contact);
            EXPECT_EQ(with.centre, without.centre);
          }
        }
      }
    }
  }
  std::printf(
      "helical stage 1: %d points, proven by their own bound %d, by the flank's %d; "
      "least bound - sampled %.3g /mm\n",
      points, proven_by_point, proven_by_flank, least_margin);
  EXPECT_EQ(points, 192);
  EXPECT_GE(proven_by_point, 96);  // at least the smooth field's
  EXPECT_GE(proven_by_flank, 48);  // the smooth field's flanks at least
}

// The distance in space (mm) from X to the nominal flank `side` of `tooth` over its extent, by
// search: a 200 x 200 grid of its points, then nested shrinking grids around the nearest.
double brute_force_flank_distance(const InvoluteGear& gear, int tooth, FlankSide side,
                                  const Eigen::Vector3d& X) {
  const double L0 = gear.form_roll_length_mm(), L1 = gear.tip_roll_length_mm();
  const double b = gear.face_width_mm();
  auto dist = [&](double L, double z) {
    L = std::clamp(L, L0, L1), z = std::clamp(z, 0.0, b);
    return (gear.flank_point(tooth, side, L, z).point - X).norm();
  };
  double best = 1e300, bL = L0, bz = 0.0;
  for (int i = 0; i <= 200; ++i) {
    for (int j = 0; j <= 200; ++j) {
      const double L = L0 + (L1 - L0) * i / 200, z = b * j / 200, d = dist(L, z);
      if (d < best) best = d, bL = L, bz = z;
    }
  }
  double hL = (L1 - L0) / 100, hz = b / 100;
  for (int level = 0; level < 12; ++level, hL *= 0.3, hz *= 0.3) {
    const double cL = bL, cz = bz;
    for (int a = -10; a <= 10; ++a) {
      for (int c = -10; c <= 10; ++c) {
        const double L = std::clamp(cL + hL * a / 10, L0, L1),
                     z = std::clamp(cz + hz * c / 10, 0.0, b);
        const double d = dist(L, z);
        if (d < best) best = d, bL = L, bz = z;
      }
    }
  }
  return best;
}

// The tooth-space check on a helical gear: its facing-flank clearance is a lower bound of the
// distance in space from the stylus (on its approach) to the facing flank minus R, found by
// search, and not more than 10 % below it; the root clearance is the axis distance's.
TEST(HelicalContact, ToothSpaceClearanceIsALowerBoundInSpace) {
  int checked = 0;
  double worst_ratio = 1.0;
  for (Hand hand : {Hand::kRight, Hand::kLeft}) {
    const InvoluteGear gear = helical_gear(hand, 25.0);
    for (FlankSide side : {FlankSide::kLeft, FlankSide::kRight}) {
      const int tooth = 3;
      const int facing_tooth = side == FlankSide::kRight ? 4 : 2;
      const FlankSide facing = side == FlankSide::kRight ? FlankSide::kLeft : FlankSide::kRight;
      for (double L : {gear.form_roll_length_mm() + 0.5,
                       0.5 * (gear.form_roll_length_mm() + gear.tip_roll_length_mm())}) {
        for (double z : {8.0, 30.0}) {
          for (double R : {1.0, 2.0}) {
            const FlankPoint fp = gear.flank_point(tooth, side, L, z);
            const Eigen::Vector3d centre = fp.point + R * fp.normal;
            const ToothSpaceClearance c = tooth_space_clearance(
                gear, tooth, side, centre, fp.normal, StylusShape{R}, kProbeApproachMm);
            // The smallest over the same five stations, in space.
            double truth = 1e300;
            const Eigen::Vector3d start = centre + kProbeApproachMm * fp.normal;
            for (double a : {0.0, 0.25, 0.5, 0.75, 1.0}) {
              const Eigen::Vector3d X = start + a * (centre - start);
              truth =
                  std::min(truth, brute_force_flank_distance(gear, facing_tooth, facing, X) - R);
            }
            EXPECT_LE(c.facing_flank_mm, truth + 1e-9) << "L " << L << " z " << z << " R " << R;
            EXPECT_GE(c.facing_flank_mm + R, 0.9 * (truth + R)) << "L " << L << " z " << z;
            worst_ratio = std::min(worst_ratio, (c.facing_flank_mm + R) / (truth + R));
            ++checked;
          }
        }
      }
    }
  }
  std::printf(
      "helical tooth space: %d approaches, clearance + R at least %.4f of the distance "
      "in space\n",
      checked, worst_ratio);
  EXPECT_EQ(checked, 32);
}

// Bumps on a lattice (as contact_certificate_test.cpp's steep surface): several local maxima per
// footprint, so the solver's first maximum is often not the highest.
constexpr const char* kSteepBumps =
    "35*(0.75+0.25*sin(1.7*L+2.3*z))*exp(-(sin(_pi*L/0.7)^2+sin(_pi*z/0.9)^2)/0.35)";

TEST(HelicalContact, SteepBumpsNoOkPointBelowTheBruteForceMaximum) {
  const FlankDeviation none;
  const NormalExpression bumps(kSteepBumps);
  std::mt19937_64 rng(20261127);  // fixed seed
  int ok = 0, wrong = 0, restarted = 0, other = 0;
  double worst_below = 0.0;
  for (int k = 0; k < 200; ++k) {
    const InvoluteGear gear = helical_gear(k % 4 < 2 ? Hand::kRight : Hand::kLeft);
    std::uniform_real_distribution<double> L_of(gear.form_roll_length_mm() + 1.5,
                                                gear.tip_roll_length_mm() - 1.5);
    std::uniform_real_distribution<double> z_of(2.0, 38.0);
    const FlankSide side = k % 2 ? FlankSide::kRight : FlankSide::kLeft;
    const AnalyticFlank flank(gear, 1 + k % 31, side, none, Eigen::Vector2d::Zero(), &bumps);
    const double L = L_of(rng), z = z_of(rng), R = 0.5;
    const FlankPoint fp = gear.flank_point(flank.tooth(), side, L, z);
    const ContactResult r = solve_contact(flank, extent_of(gear), fp.point, fp.normal, R, L, z);
    if (r.restarts > 0) ++restarted;
    if (r.status != ContactResult::Status::kOk) {
      ++other;
      continue;
    }
    ++ok;
    // The footprint in L, widened by the helicoid's shear over z +/- R (tan(beta_b) R).
    const double half_L = 1.3 * R * 0.5 * gear.base_diameter_mm() / L + 0.05 +
                          std::tan(gear.base_helix_angle_rad()) * R;
    const testing_support::BruteForceMaximum brute = testing_support::brute_force_global_contact(
        flank, fp.point, fp.normal, R, L, z, half_L, 160);
    const double below = brute.height - (r.centre - fp.point).dot(fp.normal);
    worst_below = std::max(worst_below, below);
    if (below > kCertificateToleranceMm) ++wrong;
  }
  std::printf(
      "helical steep bumps: %d ok (%d below the brute force by > 1e-2 nm, worst %.3g nm), "
      "%d not ok; %d restarted\n",
      ok, wrong, 1e6 * worst_below, other, restarted);
  EXPECT_EQ(wrong, 0);
  EXPECT_GT(ok, 170);
  EXPECT_GT(restarted, 0);
}

}  // namespace
}  // namespace gearmc
