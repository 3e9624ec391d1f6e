// The stylus contact on an internal (ring) gear's concave flanks, spur and helical, against the
// brute-force searches of tests/support/p1_fixtures.h (no Newton, no certificate): the nested
// local search from the planned point and, on wavy fields, the global search over the whole
// footprint (the first contact, not a local peak). Design modifications, random fields and an
// eccentricity on top. Stage 1's bound (curvature_bound.cpp) takes the concave involute's own
// curvature 1/L into the flank's: every contact is checked with and without the per-flank bound
// (which must not change a result), and the bound is at least that curvature.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>

#include "engine/contact/contact.h"
#include "engine/contact/contact_certificate.h"
#include "gears/normal_expression.h"
#include "tests/support/alternating_form.h"
#include "tests/support/p1_fixtures.h"
#include "tests/support/sampled_curvature.h"

namespace gearmc {
namespace {

GearParameters ring_parameters(double beta_deg, Hand hand) {
  GearParameters p;
  p.teeth = 60;
  p.internal = true;
  p.module_mm = 2.0;
  p.pressure_angle_deg = 20.0;
  p.helix_angle_deg = beta_deg;
  p.hand = hand;
  p.profile_shift = 0.1;
  p.face_width_mm = 20.0;
  p.modifications.tip_relief = {20.0, 2.0};
  p.modifications.root_relief = {10.0, 1.0};
  p.modifications.helix_crowning_um = 6.0;
  return p;
}

FlankExtent extent_of(const InvoluteGear& g) {
  return {g.active_roll_length_min_mm(), g.active_roll_length_max_mm(), 0.0, g.face_width_mm()};
}

TEST(InternalContact, AgreesWithBruteForceOnConcaveFlanks) {
  std::mt19937_64 rng(5);  // fixed seed
  std::normal_distribution<double> coefficient(0.0, 2.0);
  int checked = 0;
  double worst = 0.0;
  for (const double beta : {0.0, 18.0}) {
    const GearParameters p = ring_parameters(beta, Hand::kLeft);
    ASSERT_EQ(validate_gear_parameters(p), "");
    const InvoluteGear gear(p);
    const double L0 = gear.active_roll_length_min_mm(), L1 = gear.active_roll_length_max_mm();
    const double b = gear.face_width_mm();
    FlankDeviation dev;
    dev.offset_um = coefficient(rng);
    std::vector<double> pc(8), hc(6);
    for (double& c : pc) c = coefficient(rng);
    for (double& c : hc) c = coefficient(rng);
    dev.profile_form = CubicBSpline(L0, L1, pc);
    dev.helix_form = CubicBSpline(0.0, b, hc);
    for (FlankSide side : {FlankSide::kLeft, FlankSide::kRight}) {
      const AnalyticFlank flank(gear, 7, side, dev, Eigen::Vector2d(0.003, -0.002));
      const FlankCurvatureBound bound = flank_curvature_bound(flank, 1.0, L0, L1);
      // A bound exists (stage 1 proves these contacts) and holds the involute's concavity: the
      // profile curvature 1/L is at least 1/L1 anywhere on the flank.
      EXPECT_LT(bound.kappa, 1.0);
      EXPECT_GE(bound.kappa, 1.0 / L1);
      for (double L = L0 + 0.3; L < L1; L += 1.9) {
        for (const double z : {0.5, 7.0, b - 1.0}) {
          for (const double R : {0.5, 1.0}) {
            const FlankPoint fp = gear.flank_point(7, side, L, z);
            const ContactResult r =
                solve_contact(flank, extent_of(gear), fp.point, fp.normal, R, L, z);
            ASSERT_EQ(r.status, ContactResult::Status::kOk) << beta << " " << L << " " << z;
            if (R == 1.0) {  // the flank's stage-1 bound changes nothing
              const ContactResult with_bound =
                  solve_contact(flank, extent_of(gear), fp.point, fp.normal, R, L, z,
                                planned_base_angle(fp), &bound);
              ASSERT_EQ(with_bound.status, ContactResult::Status::kOk);
              EXPECT_LT((with_bound.contact - r.contact).norm(), 1e-9);
            }
            const testing_support::BruteForcePoints s =
                testing_support::brute_force_contact_points(flank, fp.point, fp.normal, R, L, z);
            EXPECT_LT((s.contact - r.contact).norm(), 1e-6) << beta << " " << L << " " << z;
            EXPECT_LT((s.centre - r.centre).norm(), 1e-6);
            worst = std::max(worst, (s.contact - r.contact).norm());
            ++checked;
          }
        }
      }
    }
  }
  std::printf("internal flanks: %d contacts, worst |C - C_brute| %.3g nm\n", checked, 1e6 * worst);
  EXPECT_GE(checked, 2 * 2 * 6 * 3 * 2);
}

// An egg-crate field, 4 sin(12 L) sin(12 z) µm (curvature up to 4e-3 x 144 = 0.58 /mm in each
// direction, so the contact height has several local maxima under a 1 mm ball): the solver's
// answer is the global one of the footprint search (the sampled certificate restarts Newton from
// a higher point where the local maximum is not the first contact).
TEST(InternalContact, WavyFieldGivesTheFirstContactNotALocalPeak) {
  int checked = 0, restarted = 0;
  const NormalExpression bumps("4*sin(12*L)*sin(12*z)");
  for (const double beta : {0.0, 12.0}) {
    const InvoluteGear gear(ring_parameters(beta, Hand::kRight));
    const double L0 = gear.active_roll_length_min_mm(), L1 = gear.active_roll_length_max_mm();
    const FlankDeviation none;
    const FlankSide side = FlankSide::kRight;
    const AnalyticFlank flank(gear, 2, side, none, Eigen::Vector2d::Zero(), &bumps);
    const double R = 1.0;
    for (double L = L0 + 2.0; L < L1 - 2.0; L += 1.1) {
      for (const double z : {4.0, 11.3}) {
        const FlankPoint fp = gear.flank_point(2, side, L, z);
        const ContactResult r = solve_contact(flank, extent_of(gear), fp.point, fp.normal, R, L, z);
        ASSERT_EQ(r.status, ContactResult::Status::kOk) << beta << " " << L << " " << z;
        // The footprint spans about 2 R of arc, (L / r_b) dL per mm of roll: half-width in L
        // 1.5 R r_b / L.
        const double half_L = 1.5 * R * 0.5 * gear.base_diameter_mm() / L;
        const testing_support::BruteForceMaximum best = testing_support::brute_force_global_contact(
            flank, fp.point, fp.normal, R, L, z, half_L);
        const Eigen::Vector3d centre = fp.point + best.height * fp.normal;
        EXPECT_LT((centre - r.centre).norm(), 1e-6) << beta << " " << L << " " << z;
        restarted += r.restarts > 0;
        ++checked;
      }
    }
  }
  std::printf("internal egg-crate flanks: %d contacts, %d restarted from a higher point\n", checked,
              restarted);
  EXPECT_GE(checked, 30);
  EXPECT_GT(restarted, 0);  // the field does put a higher point beside some local maxima
}

using testing_support::alternating_form;

// Stage 1 on concave flanks is a proof: the per-point bound is at least the largest curvature of
// the flank's graph over the plane normal to n, sampled by central differences of the flank's
// points (tests/support/sampled_curvature.h) on 9 x 9 points of the footprint (along the
// helicoid's generators: L' = L - sigma side turn r_b (z - z0)); the flank's bound is at least
// every point's own. Fields: none (the involute's own curvature 1/L, which the bound must not
// drop) and a wavy one (+-15 µm every ~1.2 mm in L, ~0.8 mm in z).
TEST(InternalContact, StageOneBoundsAreUpperBoundsOfTheSampledCurvature) {
  const double R = 0.5;
  int points = 0, proven = 0, proven_plain = 0;
  double least_margin = 1e300;
  for (const double beta : {0.0, 18.0}) {
    const InvoluteGear gear(ring_parameters(beta, Hand::kLeft));
    const FlankExtent extent = extent_of(gear);
    const double L0_ = extent.roll_length_min, L1_ = extent.roll_length_max;
    const double r_b = 0.5 * gear.base_diameter_mm();
    FlankDeviation wavy;
    wavy.profile_form = alternating_form(L0_, L1_, 14, 15.0);
    wavy.helix_form = alternating_form(0.0, gear.face_width_mm(), 26, 15.0);
    for (const FlankDeviation& dev : {FlankDeviation{}, wavy}) {
      for (FlankSide side : {FlankSide::kLeft, FlankSide::kRight}) {
        const AnalyticFlank flank(gear, 4, side, dev, Eigen::Vector2d(0.004, 0.003));
        const FlankCurvatureBound bound = flank_curvature_bound(flank, R, L0_, L1_);
        const double shear = -flank.frame_turn_per_mm() * r_b;  // sigma = -1
        for (int i = 0; i < 5; ++i) {
          for (const double z0 : {3.0, 10.0, 17.0}) {
            const double L0 = L0_ + 0.6 + (L1_ - L0_ - 1.2) * i / 4.0;
            const FlankPoint fp = gear.flank_point(4, side, L0, z0);
            const double kappa =
                exact_curvature_bound(flank, fp.point, fp.normal, R, L0, z0, L0_, L1_);
            ++points;
            ASSERT_TRUE(std::isfinite(kappa)) << beta << " L0 " << L0;
            double sampled = -1e300;
            const double half_L = R * r_b / L0;
            for (int a = -4; a <= 4; ++a) {
              for (int b = -4; b <= 4; ++b) {
                const double z = z0 + b * R / 4;
                const double L = L0 + a * half_L / 4 + shear * (z - z0);
                if (L < L0_ || L > L1_) continue;
                sampled = std::max(sampled,
                                   testing_support::fd_curvature(flank, fp.point, fp.normal, L, z));
              }
            }
            EXPECT_GE(kappa, sampled - 1e-6) << beta << " L0 " << L0 << " z0 " << z0;
            EXPECT_GE(sampled, 0.9 / L1_);  // the concave involute's curvature is there
            least_margin = std::min(least_margin, kappa - sampled);
            if (kappa < 1.0 / R) ++proven, proven_plain += dev.profile_form.coefficients().empty();
            if (std::isfinite(bound.kappa)) {
              EXPECT_GE(bound.kappa, kappa - 1e-12);
            }
          }
        }
      }
    }
  }
  std::printf(
      "internal stage 1: %d points, %d proven (%d of the plain flanks), least margin kappa - "
      "sampled %.3g /mm\n",
      points, proven, proven_plain, least_margin);
  EXPECT_EQ(points, 2 * 2 * 2 * 5 * 3);
  // The plain concave flanks (curvature 1/L < 1/R) are all proven by stage 1: the bound is not
  // so loose that every internal contact pays the sampled stage.
  EXPECT_EQ(proven_plain, points / 2);
}

}  // namespace
}  // namespace gearmc
