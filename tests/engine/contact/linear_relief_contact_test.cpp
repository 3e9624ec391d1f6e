// The stylus contact on flanks with linear tip and root reliefs (gears/flank_modifications.h: a
// straight relief from a kink, the flank's ridge along the face) and linear end reliefs (ridges
// across the face), spur, helical and internal, against the nested brute-force search of
// tests/support/p1_fixtures.h (no Newton, no certificate; a shrinking grid finds the crease's
// maximum as any other): planned points across the kinks, among them points whose ball rests on
// the ridge itself (the contact's roll length, or face position, is the kink's). Every contact
// is kOk and within 1 nm of the search.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "engine/contact/contact.h"
#include "engine/contact/contact_certificate.h"
#include "tests/support/helical_fixtures.h"
#include "tests/support/p1_fixtures.h"

namespace gearmc {
namespace {

FlankExtent extent_of(const InvoluteGear& g) {
  return {g.active_roll_length_min_mm(), g.active_roll_length_max_mm(), 0.0, g.face_width_mm()};
}

// The tests' gears, unmodified: 0 P1's spur gear, 1 the helical example, 2 a ring gear (z 60,
// m 2 mm, b 20 mm).
GearParameters relief_test_gear(int kind) {
  if (kind == 2) {
    GearParameters p;
    p.teeth = 60, p.internal = true, p.module_mm = 2.0, p.face_width_mm = 20.0;
    return p;
  }
  return kind == 1 ? testing_support::helical_gear_parameters()
                   : testing_support::p1_gear_parameters();
}

TEST(LinearReliefContact, AgreesWithBruteForceAcrossAndOnTheRidge) {
  int checked = 0, on_ridge = 0;
  double worst = 0.0;
  for (int kind = 0; kind < 3; ++kind) {  // spur, helical, internal
    GearParameters p = relief_test_gear(kind);
    p.modifications.tip_relief = {30.0, 2.0, true};
    p.modifications.root_relief = {15.0, 1.0, true};
    ASSERT_EQ(validate_gear_parameters(p), "");
    const InvoluteGear gear(p);
    const DesignModification& design = *gear.design_modification();
    ASSERT_EQ(design.profile_kinks.size(), 2u);
    const FlankDeviation none;
    for (FlankSide side : {FlankSide::kLeft, FlankSide::kRight}) {
      const AnalyticFlank flank(gear, 2, side, none, Eigen::Vector2d(0.001, -0.002));
      for (const double c : design.profile_kinks) {
        // Around each kink: far on both sides, and within the ridge's band (a few µm: the ball
        // rests on the ridge where the two branches' normals straddle the probing line).
        for (const double dL : {-1.5, -0.3, -0.004, -0.001, 0.0, 0.001, 0.004, 0.3, 1.5}) {
          const double L = c + dL;
          if (L <= extent_of(gear).roll_length_min || L >= extent_of(gear).roll_length_max)
            continue;
          for (const double z : {3.0, 0.5 * gear.face_width_mm()}) {
            for (const double R : {0.5, 1.0}) {
              const FlankPoint fp = gear.flank_point(2, side, L, z);
              const ContactResult r =
                  solve_contact(flank, extent_of(gear), fp.point, fp.normal, R, L, z);
              ASSERT_EQ(r.status, ContactResult::Status::kOk)
                  << kind << " c " << c << " dL " << dL << " z " << z << " R " << R;
              const testing_support::BruteForcePoints s =
                  testing_support::brute_force_contact_points(flank, fp.point, fp.normal, R, L, z);
              EXPECT_LT((s.centre - r.centre).norm(), 1e-6) << kind << " " << dL << " " << R;
              EXPECT_LT((s.contact - r.contact).norm(), 1e-6) << kind << " " << dL << " " << R;
              worst = std::max(worst, (s.centre - r.centre).norm());
              on_ridge += r.roll_length_mm == c;
              ++checked;
            }
          }
        }
      }
    }
  }
  std::printf("linear reliefs: %d contacts, %d on a ridge, worst |O - O_brute| %.3g nm\n", checked,
              on_ridge, 1e6 * worst);
  EXPECT_GT(on_ridge, 0);  // the ridge cases are exercised
}

// A linear end relief (gears/flank_modifications.h): its kinks run across the face at z = l and
// z = b - l, ridges along the roll length. Planned points across both kinks of spur, helical
// and internal gears, among them points whose ball rests on a ridge (the contact's z is the
// kink's), against the same brute-force search.
TEST(LinearReliefContact, EndReliefAgreesWithBruteForceAcrossAndOnTheRidge) {
  int checked = 0, on_ridge = 0;
  double worst = 0.0;
  for (int kind = 0; kind < 3; ++kind) {  // spur, helical, internal
    GearParameters p = relief_test_gear(kind);
    p.modifications.end_relief = {20.0, 0.2 * p.face_width_mm, true};
    ASSERT_EQ(validate_gear_parameters(p), "");
    const InvoluteGear gear(p);
    const DesignModification& design = *gear.design_modification();
    ASSERT_EQ(design.helix_kinks.size(), 2u);
    EXPECT_DOUBLE_EQ(design.helix_kinks[0], 0.2 * p.face_width_mm);
    EXPECT_DOUBLE_EQ(design.helix_kinks[1], 0.8 * p.face_width_mm);
    // The design: 0 on the middle part, -20 µm at each face, straight in between (the shape).
    EXPECT_DOUBLE_EQ(design.value_um(30.0, 0.5 * p.face_width_mm), 0.0);
    EXPECT_NEAR(design.value_um(30.0, 0.0), -20.0, 1e-12);
    EXPECT_NEAR(design.value_um(30.0, 0.1 * p.face_width_mm), -10.0, 1e-12);
    const FlankDeviation none;
    const FlankExtent extent = extent_of(gear);
    const double L_mid = 0.5 * (extent.roll_length_min + extent.roll_length_max);
    for (FlankSide side : {FlankSide::kLeft, FlankSide::kRight}) {
      const AnalyticFlank flank(gear, 2, side, none, Eigen::Vector2d(0.001, -0.002));
      for (const double c : design.helix_kinks) {
        for (const double dz : {-1.5, -0.3, -0.004, -0.001, 0.0, 0.001, 0.004, 0.3, 1.5}) {
          const double z = c + dz;
          for (const double L : {extent.roll_length_min + 1.0, L_mid}) {
            for (const double R : {0.5, 1.0}) {
              const FlankPoint fp = gear.flank_point(2, side, L, z);
              const ContactResult r = solve_contact(flank, extent, fp.point, fp.normal, R, L, z);
              ASSERT_EQ(r.status, ContactResult::Status::kOk)
                  << kind << " c " << c << " dz " << dz << " L " << L << " R " << R;
              const testing_support::BruteForcePoints s =
                  testing_support::brute_force_contact_points(flank, fp.point, fp.normal, R, L, z);
              EXPECT_LT((s.centre - r.centre).norm(), 1e-6) << kind << " " << dz << " " << R;
              EXPECT_LT((s.contact - r.contact).norm(), 1e-6) << kind << " " << dz << " " << R;
              worst = std::max(worst, (s.centre - r.centre).norm());
              on_ridge += r.z_mm == c;
              ++checked;
            }
          }
        }
      }
    }
  }
  std::printf("linear end reliefs: %d contacts, %d on a ridge, worst |O - O_brute| %.3g nm\n",
              checked, on_ridge, 1e6 * worst);
  EXPECT_GT(on_ridge, 0);  // the ridge cases are exercised
}

// Where a linear tip relief's ridge (along the face) crosses a linear end relief's ridge (across
// it), the ball can rest on the corner, on both creases at once. Whatever the solver says there
// must be true: every `ok` contact within 1 nm of the brute-force search, anything else a counted
// status (`uncertified`, `not converged`), never a wrong point. Points on a 5 × 5 pattern of a few
// µm around each of the four corners of a flank (spur and helical), two stylus radii.
TEST(LinearReliefContact, CornersOfTwoRidgesAreRightOrCounted) {
  int ok = 0, counted = 0;
  double worst = 0.0;
  for (int kind = 0; kind < 2; ++kind) {  // spur, helical
    GearParameters p = relief_test_gear(kind);
    p.modifications.tip_relief = {30.0, 2.0, true};
    p.modifications.end_relief = {20.0, 0.2 * p.face_width_mm, true};
    ASSERT_EQ(validate_gear_parameters(p), "");
    const InvoluteGear gear(p);
    const DesignModification& design = *gear.design_modification();
    ASSERT_EQ(design.profile_kinks.size(), 1u);
    ASSERT_EQ(design.helix_kinks.size(), 2u);
    const FlankDeviation none;
    const FlankExtent extent = extent_of(gear);
    for (FlankSide side : {FlankSide::kLeft, FlankSide::kRight}) {
      const AnalyticFlank flank(gear, 2, side, none, Eigen::Vector2d(0.0, 0.0));
      for (const double cz : design.helix_kinks) {
        const double cL = design.profile_kinks[0];
        for (const double dL : {-0.004, -0.001, 0.0, 0.001, 0.004}) {
          for (const double dz : {-0.004, -0.001, 0.0, 0.001, 0.004}) {
            for (const double R : {0.5, 1.0}) {
              const double L = cL + dL, z = cz + dz;
              const FlankPoint fp = gear.flank_point(2, side, L, z);
              const ContactResult r = solve_contact(flank, extent, fp.point, fp.normal, R, L, z);
              if (r.status != ContactResult::Status::kOk) {
                ++counted;
                EXPECT_NE(r.status, ContactResult::Status::kEdge) << L << " " << z;
                continue;
              }
              const testing_support::BruteForcePoints s =
                  testing_support::brute_force_contact_points(flank, fp.point, fp.normal, R, L, z);
              EXPECT_LT((s.centre - r.centre).norm(), 1e-6) << kind << " " << dL << " " << dz;
              worst = std::max(worst, (s.centre - r.centre).norm());
              ++ok;
            }
          }
        }
      }
    }
  }
  std::printf("ridge corners: %d ok (worst |O - O_brute| %.3g nm), %d with a counted status\n", ok,
              1e6 * worst, counted);
  EXPECT_GT(ok, 0);
}

}  // namespace
}  // namespace gearmc
