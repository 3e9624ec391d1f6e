// The stylus contact on an internal (ring) gear's concave flanks, spur and helical, against the
// brute-force searches of tests/support/p1_fixtures.h (no Newton, no certificate): the nested
// local search from the planned point and, on wavy fields, the global search over the whole
// footprint (the first contact, not a local peak). Design modifications, random fields and an
// eccentricity on top. Stage 1's closed forms are those of a convex flank: an internal flank has
// no per-flank bound and every contact is proven by the sampled stage (contact_certificate.h).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>

#include "engine/contact/contact.h"
#include "engine/contact/contact_certificate.h"
#include "tests/support/p1_fixtures.h"

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
      EXPECT_TRUE(std::isinf(bound.kappa));  // no stage-1 bound on a concave flank
      for (double L = L0 + 0.3; L < L1; L += 1.9) {
        for (const double z : {0.5, 7.0, b - 1.0}) {
          for (const double R : {0.5, 1.0}) {
            const FlankPoint fp = gear.flank_point(7, side, L, z);
            const ContactResult r =
                solve_contact(flank, extent_of(gear), fp.point, fp.normal, R, L, z);
            ASSERT_EQ(r.status, ContactResult::Status::kOk) << beta << " " << L << " " << z;
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

// A wavy field (16 control points of 6 µm over the profile) puts several local maxima of the
// contact height under the ball: the solver's answer is the global one of the footprint search.
TEST(InternalContact, WavyFieldGivesTheFirstContactNotALocalPeak) {
  std::mt19937_64 rng(21);  // fixed seed
  std::normal_distribution<double> coefficient(0.0, 6.0);
  int checked = 0, restarted = 0;
  for (const double beta : {0.0, 12.0}) {
    const InvoluteGear gear(ring_parameters(beta, Hand::kRight));
    const double L0 = gear.active_roll_length_min_mm(), L1 = gear.active_roll_length_max_mm();
    FlankDeviation dev;
    std::vector<double> pc(16), hc(10);
    for (double& c : pc) c = coefficient(rng);
    for (double& c : hc) c = coefficient(rng);
    dev.profile_form = CubicBSpline(L0, L1, pc);
    dev.helix_form = CubicBSpline(0.0, gear.face_width_mm(), hc);
    const FlankSide side = FlankSide::kRight;
    const AnalyticFlank flank(gear, 2, side, dev, Eigen::Vector2d::Zero());
    const double R = 1.0;
    for (double L = L0 + 2.0; L < L1 - 2.0; L += 2.2) {
      for (const double z : {4.0, 11.0}) {
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
  std::printf("internal wavy flanks: %d contacts, %d restarted from a higher point\n", checked,
              restarted);
  EXPECT_GE(checked, 2 * 5 * 2);
}

}  // namespace
}  // namespace gearmc
