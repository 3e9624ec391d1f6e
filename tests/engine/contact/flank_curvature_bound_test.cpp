// Stage 1 of the contact certificate, per point and per flank (contact_certificate.h):
//  * both bounds are upper bounds of the flank's real curvature: the largest eigenvalue of
//    H_uu, the Hessian of the flank as a graph over the plane normal to n, computed here by
//    central differences of S(L, z) alone (no analytic partial), at sample points inside every
//    planned point's footprint, on P1's drawn fields and on a wavier hand-made one;
//  * the flank's bound is at least every planned point's own (its box contains theirs);
//  * with the flank's bound the certificate's verdicts and the solver's results are those
//    without it, bit for bit, and P1's points are proven by it;
//  * where the flank's bound is too weak (a profile wave: the box reaches the flank's low end,
//    where the involute's u_L is smallest) the point's own bound proves the point;
//  * `covers` refuses another flank, another stylus, another extent, a point off the extent and
//    a deviation beyond the bound's.
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <cmath>

#include "engine/contact/contact.h"
#include "engine/contact/contact_certificate.h"
#include "engine/plan/probing_grid.h"
#include "gears/deviations.h"
#include "tests/support/alternating_form.h"
#include "tests/support/p1_fixtures.h"
#include "tests/support/sampled_curvature.h"

namespace gearmc {
namespace {

using testing_support::p1_gear;

constexpr double kR = 0.5;  // mm, P1's stylus

FlankExtent extent_of(const InvoluteGear& g) {
  return {g.form_roll_length_mm(), g.tip_roll_length_mm(), 0.0, g.face_width_mm()};
}

// The largest sampled curvature over the footprint of the point at (L0, z0) (sphere radius R
// projected on the flank: |L - L0| <= R r_b / L0, |z - z0| <= R), 9 x 9 samples.
double sampled_footprint_curvature(const InvoluteGear& gear, const AnalyticFlank& flank,
                                   const PlannedPoint& pp) {
  const double half_L = kR * 0.5 * gear.base_diameter_mm() / pp.roll_length_mm;
  double worst = -1e300;
  for (int i = -4; i <= 4; ++i) {
    for (int j = -4; j <= 4; ++j) {
      const double L = pp.roll_length_mm + i * half_L / 4, z = pp.z_mm + j * kR / 4;
      worst = std::max(worst, testing_support::fd_curvature(flank, pp.point, pp.normal, L, z));
    }
  }
  return worst;
}

using testing_support::alternating_form;

// A wavier field than P1's: profile and helix forms of +-20 µm every ~1.5 mm (curvatures of
// the order of 0.3 /mm, still below 1/R).
FlankDeviation wavy_field() {
  FlankDeviation d;
  d.profile_form = alternating_form(20.0, 46.0, 20, 20.0);
  d.helix_form = alternating_form(0.0, 80.0, 60, 20.0);
  return d;
}

TEST(FlankCurvatureBound, BoundsAreUpperBoundsOfTheSampledCurvature) {
  const InvoluteGear gear = p1_gear();
  const FlankExtent extent = extent_of(gear);
  const GearSampler sampler(gear, testing_support::p1_tolerance_set(), DeviationModel{}, 11);
  const PerturbedGear g = sampler.draw(5);
  const FlankDeviation wavy = wavy_field();
  int points = 0;
  double largest_true = -1e300;
  for (const FlankDeviation* dev : {&g.flank(3, FlankSide::kLeft), &wavy}) {
    for (FlankSide side : {FlankSide::kLeft, FlankSide::kRight}) {
      const AnalyticFlank flank(gear, 3, side, *dev, g.eccentricity_mm);
      const FlankCurvatureBound fb =
          flank_curvature_bound(flank, kR, extent.roll_length_min, extent.roll_length_max);
      ASSERT_LT(fb.kappa, 1e300);
      for (const PlannedPoint& pp : plan_flank(gear, ProbingGridSpec{}, 3, side)) {
        const double point_kappa =
            exact_curvature_bound(flank, pp.point, pp.normal, kR, pp.roll_length_mm, pp.z_mm,
                                  extent.roll_length_min, extent.roll_length_max);
        const double real = sampled_footprint_curvature(gear, flank, pp);
        EXPECT_GE(point_kappa, real - 1e-6) << pp.roll_length_mm << " " << pp.z_mm;
        EXPECT_GE(fb.kappa, point_kappa) << pp.roll_length_mm << " " << pp.z_mm;
        largest_true = std::max(largest_true, real);
        ++points;
      }
    }
  }
  EXPECT_EQ(points, 2 * 2 * 50);
  // The wavy field's sampled curvature is of the order of 1/R: the comparison above is not
  // against a flat flank.
  EXPECT_GT(largest_true, 0.2);
}

// The flank's bound against the point's own at roll lengths from the flank's low end up, where
// a point's box is widest (its half-width is K / L0) and so its |delta| bound D largest: a
// profile wave over exactly the flank's extent, whose value at the low end is a coefficient
// (|delta0| = 40 µm, the field's extreme), so the flank's D exceeds the point's only by its
// 1 % of room and the comparison is tight (a flank box taken at L_max, not L_min, fails it).
TEST(FlankCurvatureBound, HoldsFromTheFlanksLowEndUp) {
  const InvoluteGear gear = p1_gear();
  const FlankExtent extent = extent_of(gear);
  FlankDeviation dev;
  dev.profile_form = alternating_form(extent.roll_length_min, extent.roll_length_max, 14, 40.0);
  for (FlankSide side : {FlankSide::kLeft, FlankSide::kRight}) {
    const AnalyticFlank flank(gear, 5, side, dev, Eigen::Vector2d(0.004, -0.003));
    const FlankCurvatureBound fb =
        flank_curvature_bound(flank, kR, extent.roll_length_min, extent.roll_length_max);
    ASSERT_LT(fb.kappa, 1e300);
    for (int i = 0; i <= 40; ++i) {
      const double L0 = extent.roll_length_min +
                        (extent.roll_length_max - extent.roll_length_min) * (i * i) / 1600.0;
      const FlankPoint fp = gear.flank_point(5, side, L0, 40.0);
      const double point_kappa = exact_curvature_bound(
          flank, fp.point, fp.normal, kR, L0, 40.0, extent.roll_length_min, extent.roll_length_max);
      EXPECT_GE(fb.kappa, point_kappa) << L0;
      // The box's claims, checked on the flank itself: beyond the half-width K / L0 (up to 3
      // times it, within the extent) every flank point of |z - 40| <= R lies outside the
      // stylus's footprint (|w.tau| >= R); inside it the normal turns by at most the bound's
      // turn and |delta| stays within its deviation bound.
      const double half = fb.half_width_mm2 / L0;
      const Eigen::Vector3d tau = Eigen::Vector3d::UnitZ().cross(fp.normal).normalized();
      const double r_b = 0.5 * gear.base_diameter_mm();
      for (int k = -8; k <= 8; ++k) {
        const double z = 40.0 + kR * k / 8.0;
        for (double f : {1.0, 1.5, 2.0, 3.0}) {
          for (double L : {L0 - f * half, L0 + f * half}) {
            if (L < extent.roll_length_min || L > extent.roll_length_max) continue;
            EXPECT_GE(std::abs((flank.point(L, z) - fp.point).dot(tau)), kR) << L0 << " " << L;
          }
        }
        for (int j = -8; j <= 8; ++j) {
          const double L = L0 + half * j / 8.0;
          if (L < extent.roll_length_min || L > extent.roll_length_max) continue;
          // The turn is (L - L0) / r_b; equal at L0 = L_min up to rounding.
          EXPECT_LE(std::abs(L - L0) / r_b, fb.max_turn_rad * (1.0 + 1e-12)) << L0;
          EXPECT_LE(std::abs(1e-3 * dev.normal_um(L, z)), fb.max_deviation_mm) << L0;
        }
      }
    }
  }
}

// The certificate at every planned point of drawn P1 gears: the verdict with the flank's bound
// equals the verdict without it, all are proven, and by the flank's bound; the solver's results
// with it are bit-identical.
TEST(FlankCurvatureBound, SameVerdictsAndResultsAndP1IsProvenPerFlank) {
  const InvoluteGear gear = p1_gear();
  const FlankExtent extent = extent_of(gear);
  const GearSampler sampler(gear, testing_support::p1_tolerance_set(), DeviationModel{}, 3);
  int points = 0, by_flank = 0;
  for (int k : {1, 2}) {
    const PerturbedGear g = sampler.draw(k);
    for (int tooth : {1, 7, 13, 20}) {
      for (FlankSide side : {FlankSide::kLeft, FlankSide::kRight}) {
        const AnalyticFlank flank(gear, tooth, side, g.flank(tooth, side), g.eccentricity_mm);
        const FlankCurvatureBound fb =
            flank_curvature_bound(flank, kR, extent.roll_length_min, extent.roll_length_max);
        for (const PlannedPoint& pp : plan_flank(gear, ProbingGridSpec{}, tooth, side)) {
          const ContactResult a =
              solve_contact(flank, extent, pp.point, pp.normal, kR, pp.roll_length_mm, pp.z_mm);
          const ContactResult b =
              solve_contact(flank, extent, pp.point, pp.normal, kR, pp.roll_length_mm, pp.z_mm,
                            base_angle(gear, tooth, side, pp.roll_length_mm), &fb);
          ASSERT_EQ(a.status, ContactResult::Status::kOk);
          ASSERT_EQ(b.status, a.status);
          EXPECT_EQ(b.iterations, a.iterations);
          EXPECT_EQ(b.delta_um, a.delta_um);
          EXPECT_EQ((b.contact - a.contact).norm(), 0.0);
          // The certificate itself at the found contact, with a gradient bound of 1e-6.
          const FlankSurfacePoint start = flank.evaluate(pp.roll_length_mm, pp.z_mm);
          const Eigen::Vector2d x(a.roll_length_mm, a.z_mm);
          const double t = (a.centre - pp.point).dot(pp.normal);
          const ContactCertificate with =
              certify_contact(flank, pp.point, pp.normal, kR, pp.roll_length_mm, start, x, t, 1e-6,
                              extent.roll_length_min, extent.roll_length_max, &fb);
          const ContactCertificate without =
              certify_contact(flank, pp.point, pp.normal, kR, pp.roll_length_mm, start, x, t, 1e-6,
                              extent.roll_length_min, extent.roll_length_max);
          EXPECT_EQ(with.verdict, without.verdict);
          EXPECT_EQ(with.verdict, ContactCertificate::Verdict::kCertified);
          EXPECT_FALSE(without.by_flank_bound);
          by_flank += with.by_flank_bound ? 1 : 0;
          ++points;
        }
      }
    }
  }
  EXPECT_EQ(points, 2 * 4 * 2 * 50);
  EXPECT_EQ(by_flank, points);  // P1's smooth fields: one bound per flank proves every point
}

// A profile wave whose curvature the flank's box (down to L_min = 21 mm, where u_L = L / r_b is
// smallest) bounds above 1/R while a point high on the flank bounds it below: the point's own
// bound proves it, and the contact agrees with the brute-force maximum.
TEST(FlankCurvatureBound, WhereTheFlanksBoundFailsThePointsOwnProves) {
  const InvoluteGear gear = p1_gear();
  const FlankExtent extent = extent_of(gear);
  FlankDeviation dev;
  dev.profile_form = alternating_form(20.0, 46.0, 14, 40.0);
  const AnalyticFlank flank(gear, 2, FlankSide::kRight, dev, Eigen::Vector2d::Zero());
  const FlankCurvatureBound fb =
      flank_curvature_bound(flank, kR, extent.roll_length_min, extent.roll_length_max);
  const double L0 = 44.0, z0 = 40.0;
  const FlankPoint fp = gear.flank_point(2, FlankSide::kRight, L0, z0);
  const double point_kappa = exact_curvature_bound(flank, fp.point, fp.normal, kR, L0, z0,
                                                   extent.roll_length_min, extent.roll_length_max);
  // The premise: the flank's bound cannot prove, the point's can.
  ASSERT_GE(fb.kappa, 1.0 / kR) << point_kappa;
  ASSERT_LT(point_kappa, 1.0 / kR) << fb.kappa;
  const ContactResult r = solve_contact(flank, extent, fp.point, fp.normal, kR, L0, z0,
                                        base_angle(gear, 2, FlankSide::kRight, L0), &fb);
  ASSERT_EQ(r.status, ContactResult::Status::kOk) << spelling(r.failure);
  const FlankSurfacePoint start = flank.evaluate(L0, z0);
  const double t = (r.centre - fp.point).dot(fp.normal);
  const ContactCertificate c = certify_contact(flank, fp.point, fp.normal, kR, L0, start,
                                               Eigen::Vector2d(r.roll_length_mm, r.z_mm), t, 1e-9,
                                               extent.roll_length_min, extent.roll_length_max, &fb);
  EXPECT_EQ(c.verdict, ContactCertificate::Verdict::kCertified);
  EXPECT_FALSE(c.by_flank_bound);
  EXPECT_FALSE(c.sampled);  // stage 1 at the point, not stage 2
  const testing_support::BruteForceMaximum brute = testing_support::brute_force_global_contact(
      flank, fp.point, fp.normal, kR, L0, z0, 1.3 * kR * 0.5 * gear.base_diameter_mm() / L0);
  EXPECT_GE(t, brute.height - kCertificateToleranceMm);
}

TEST(FlankCurvatureBound, CoversOnlyItsFlankStylusExtentAndDeviation) {
  const InvoluteGear gear = p1_gear();
  const FlankExtent e = extent_of(gear);
  const FlankDeviation dev = testing_support::wavy_deviation();
  const AnalyticFlank flank(gear, 1, FlankSide::kLeft, dev, Eigen::Vector2d::Zero());
  const AnalyticFlank other(gear, 2, FlankSide::kLeft, dev, Eigen::Vector2d::Zero());
  const FlankCurvatureBound fb =
      flank_curvature_bound(flank, kR, e.roll_length_min, e.roll_length_max);
  ASSERT_LT(fb.kappa, 1.0 / kR);
  // wavy_deviation: |offset| 30 µm + |profile part| <= 0.2 * 12 + 3 + |helix part| <= 0.05 * 36
  // + 2, so the bound's deviation lies between 30 and 40 µm (+1 %).
  EXPECT_GT(fb.deviation_max_mm, 30e-3);
  EXPECT_LT(fb.deviation_max_mm, 40.5e-3);
  const double L = 30.0, d = 1e3 * fb.deviation_max_mm;  // µm
  EXPECT_TRUE(fb.covers(flank, kR, L, 0.0, e.roll_length_min, e.roll_length_max));
  EXPECT_TRUE(fb.covers(flank, kR, L, -d, e.roll_length_min, e.roll_length_max));
  EXPECT_FALSE(fb.covers(other, kR, L, 0.0, e.roll_length_min, e.roll_length_max));
  EXPECT_FALSE(fb.covers(flank, 0.3, L, 0.0, e.roll_length_min, e.roll_length_max));
  EXPECT_FALSE(fb.covers(flank, kR, L, 0.0, e.roll_length_min + 1.0, e.roll_length_max));
  EXPECT_FALSE(
      fb.covers(flank, kR, e.roll_length_max + 0.1, 0.0, e.roll_length_min, e.roll_length_max));
  EXPECT_FALSE(fb.covers(flank, kR, L, 1.001 * d, e.roll_length_min, e.roll_length_max));
  // No closed form with an expression field: no bound.
  const NormalExpression expression("0.1*sin(L)");
  const AnalyticFlank with_expression(gear, 1, FlankSide::kLeft, dev, Eigen::Vector2d::Zero(),
                                      &expression);
  const FlankCurvatureBound none =
      flank_curvature_bound(with_expression, kR, e.roll_length_min, e.roll_length_max);
  EXPECT_FALSE(none.covers(with_expression, kR, L, 0.0, e.roll_length_min, e.roll_length_max));
}

}  // namespace
}  // namespace gearmc
