// Stylus–flank contact against analytic answers and an independent brute-force search:
//  * pure offset / rotation of an involute flank: delta < 1e-6 µm (all involutes of one base
//    circle share their normals, docs/sources.md);
//  * a helix slope k tilts the flank about the profile tangent; in the transverse plane the
//    contact stays on the same normal line, so delta = 2 R sin(theta/2), theta = atan(k 1e-3)
//    exactly (the tilted-plane case);
//  * a constant profile slope k (µm per mm of roll length): the arc length of the involute is
//    ds = (L / r_b) dL, so the surface tilts by atan(k 1e-3 r_b / L); the sphere rolls on the
//    convex involute (radius of curvature rho = L): theta_eff ≈ tilt rho / (rho + R);
//  * random smooth fields: Newton's C and O agree with a nested brute-force grid search to 1 nm;
//  * symmetry: the same deviation on either flank of any tooth gives the same delta.
#include "engine/contact/contact.h"
#include "engine/contact/tooth_space.h"
#include "tests/support/p1_fixtures.h"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <functional>
#include <limits>
#include <regex>
#include <set>
#include <sstream>
#include <string>

#include "engine/plan/probing_grid.h"
#include "gears/deviations.h"

namespace gearmc {
namespace {

using testing_support::p1_gear;
using testing_support::p1_gear_parameters;

FlankExtent extent_of(const InvoluteGear& g) {
  return {g.form_roll_length_mm(), g.tip_roll_length_mm(), 0.0, g.face_width_mm()};
}

ContactResult probe(const InvoluteGear& gear, const FlankDeviation& dev, int tooth, FlankSide side,
                    double L, double z, double R = 0.5,
                    Eigen::Vector2d ecc = Eigen::Vector2d::Zero()) {
  const AnalyticFlank flank(gear, tooth, side, dev, ecc);
  const FlankPoint fp = gear.flank_point(tooth, side, L, z);
  return solve_contact(flank, extent_of(gear), fp.point, fp.normal, R, L, z);
}

TEST(Contact, OffsetAndRotationGiveNoCompensationError) {
  const InvoluteGear gear = p1_gear();
  FlankDeviation offset;
  offset.offset_um = 35.0;  // also what a rotation by 35 µm / r_b is (exact for an involute)
  for (FlankSide side : {FlankSide::kLeft, FlankSide::kRight}) {
    for (double L : {23.0, 33.0, 43.0}) {
      const ContactResult r = probe(gear, offset, 4, side, L, 20.0);
      ASSERT_EQ(r.status, ContactResult::Status::kOk);
      EXPECT_LT(r.delta_um, 1e-6);
      // The reported point is the real surface point on the normal: 35 µm outside.
      EXPECT_NEAR(r.normal_error_um, 0.0, 1e-6);
      const FlankPoint fp = gear.flank_point(4, side, L, 20.0);
      EXPECT_NEAR(1e3 * (r.reported - fp.point).dot(fp.normal), 35.0, 1e-6);
      EXPECT_NEAR((r.centre - r.contact).norm(), 0.5, 1e-12);  // |C - O| = R
    }
  }
}

TEST(Contact, TiltedPlaneCase) {
  const InvoluteGear gear = p1_gear();
  for (double k : {0.5, 2.0, -4.0, 8.0}) {  // µm/mm helix slope: theta 0.5 … 8 mrad
    FlankDeviation tilt;
    tilt.helix_slope_um_per_mm = k;
    tilt.helix_mid_mm = 39.445;
    for (double R : {0.5, 1.0}) {
      const ContactResult r = probe(gear, tilt, 9, FlankSide::kRight, 30.0, 25.0, R);
      ASSERT_EQ(r.status, ContactResult::Status::kOk);
      const double theta = std::atan(std::abs(k) * 1e-3);
      EXPECT_NEAR(r.delta_um, 1e3 * 2 * R * std::sin(theta / 2), 1e-6) << "k " << k;
    }
  }
}

TEST(Contact, ConstantProfileSlopeOnTheConvexInvolute) {
  const InvoluteGear gear = p1_gear();
  const double R = 0.5;
  for (double k : {1.0, -2.0, 4.0}) {
    FlankDeviation slope;
    slope.profile_slope_um_per_mm = k;
    slope.profile_mid_mm = 32.0;
    for (double L : {24.0, 32.0, 42.0}) {
      const ContactResult r = probe(gear, slope, 2, FlankSide::kLeft, L, 30.0, R);
      ASSERT_EQ(r.status, ContactResult::Status::kOk);
      const double r_b = gear.base_diameter_mm() / 2;
      const double theta_eff = std::atan(std::abs(k) * 1e-3 * r_b / L) * L / (L + R);
      const double expected = 1e3 * 2 * R * std::sin(theta_eff / 2);
      // First-order formula: neglected terms are of relative order k 1e-3 and d / L.
      EXPECT_NEAR(r.delta_um, expected, 1e-2 * expected) << "k " << k << " L " << L;
    }
  }
}

// Independent answer: maximise the contact height over nested, shrinking grids.

TEST(Contact, RandomSmoothFieldsAgreeWithBruteForce) {
  const InvoluteGear gear = p1_gear();
  // P1's tolerances with wavy fields: 20 profile and 12 helix control values.
  const ToleranceSet tol = testing_support::p1_tolerance_set();
  DeviationModel model;
  model.profile_form_control_points = 20;
  model.helix_form_control_points = 12;
  const GearSampler sampler(gear, tol, model, 11);
  const ProbingGridSpec spec;
  int checked = 0;
  double worst = 0;
  for (int k = 0; k < 3; ++k) {
    const PerturbedGear g = sampler.draw(k);
    for (int tooth : {1, 7, 18}) {
      for (FlankSide side : {FlankSide::kLeft, FlankSide::kRight}) {
        const AnalyticFlank flank(gear, tooth, side, g.flank(tooth, side), g.eccentricity_mm);
        for (const PlannedPoint& pp : plan_flank(gear, spec, tooth, side)) {
          if ((pp.i + pp.j) % 7 != 0) continue;  // a spread-out subset of the grid
          const ContactResult r = solve_contact(flank, extent_of(gear), pp.point, pp.normal, 0.5,
                                                pp.roll_length_mm, pp.z_mm);
          ASSERT_EQ(r.status, ContactResult::Status::kOk);
          const Eigen::Vector2d b = testing_support::brute_force_contact(
              flank, pp.point, pp.normal, 0.5, pp.roll_length_mm, pp.z_mm);
          const Eigen::Vector3d C = flank.point(b[0], b[1]);
          const Eigen::Vector3d O = pp.point + testing_support::brute_force_contact_height(
                                                   flank, pp.point, pp.normal, 0.5, b[0], b[1]) *
                                                   pp.normal;
          EXPECT_LT((C - r.contact).norm(), 1e-6);  // 1 nm
          EXPECT_LT((O - r.centre).norm(), 1e-6);
          EXPECT_NEAR((r.centre - r.contact).norm(), 0.5, 1e-9);
          worst = std::max(worst, (C - r.contact).norm());
          ++checked;
        }
      }
    }
  }
  EXPECT_GT(checked, 100);
}

TEST(Contact, SameAnswerOnEitherFlankAndAnyTooth) {
  const InvoluteGear gear = p1_gear();
  FlankDeviation wavy;
  wavy.profile_form = CubicBSpline(21.4, 44.3, {0.0, 3.0, -2.0, 4.0, -1.0, 2.0, 0.0, -3.0});
  wavy.helix_form = CubicBSpline(3.9, 75.0, {1.0, -2.0, 2.5, 0.0, -1.0, 2.0});
  const ContactResult ref = probe(gear, wavy, 1, FlankSide::kRight, 28.3, 17.0);
  ASSERT_EQ(ref.status, ContactResult::Status::kOk);
  EXPECT_GT(ref.delta_um, 0.01);  // a real, non-trivial value
  for (int tooth : {1, 5, 13, 24}) {
    for (FlankSide side : {FlankSide::kLeft, FlankSide::kRight}) {
      const ContactResult r = probe(gear, wavy, tooth, side, 28.3, 17.0);
      ASSERT_EQ(r.status, ContactResult::Status::kOk);
      EXPECT_NEAR(r.delta_um, ref.delta_um, 1e-8);
      EXPECT_NEAR(r.normal_error_um, ref.normal_error_um, 1e-8);
    }
  }
}

TEST(Contact, AStylusOverTheFlankEdgeIsReportedNotMeasured) {
  const InvoluteGear gear = p1_gear();
  FlankDeviation tilt;
  tilt.helix_slope_um_per_mm = 5.0;  // the flank rises towards z = b
  // 5 mrad tilt with a 1 mm stylus: the tangency point lies R sin(theta) = 5 µm above the
  // planned point, so 2 µm below the top face it would be beyond the face: an edge contact.
  const ContactResult r =
      probe(gear, tilt, 3, FlankSide::kLeft, 30.0, gear.face_width_mm() - 0.002, 1.0);
  EXPECT_EQ(r.status, ContactResult::Status::kEdge);
}

TEST(ProbingGrid, P1GridHasMarginsAndEqualSteps) {
  const InvoluteGear gear = p1_gear();
  const ProbingGridSpec spec;  // P1: N 10, M 5, 5 % margins
  const ProbingGridCoordinates c = probing_grid_coordinates(gear, spec);
  ASSERT_EQ(c.roll_lengths.size(), 10u);
  ASSERT_EQ(c.heights.size(), 5u);
  const double L0 = gear.form_roll_length_mm(), L1 = gear.tip_roll_length_mm();
  EXPECT_NEAR(c.roll_lengths.front(), L0 + 0.05 * (L1 - L0), 1e-12);
  EXPECT_NEAR(c.roll_lengths.back(), L1 - 0.05 * (L1 - L0), 1e-12);
  EXPECT_NEAR(c.heights.front(), 0.05 * 78.89, 1e-12);
  EXPECT_NEAR(c.heights.back(), 0.95 * 78.89, 1e-12);
  EXPECT_NEAR(c.heights[1] - c.heights[0], c.heights[4] - c.heights[3], 1e-12);
  const auto points = plan_flank(gear, spec, 3, FlankSide::kRight);
  EXPECT_EQ(points.size(), 50u);
  EXPECT_EQ(points[11].i, 1);
  EXPECT_EQ(points[11].j, 1);
}

// The other two profile spacings of docs/scenario-keys.md: equal steps of the involute's arc
// length from the base circle, s = L² / (2 r_b) (the integral of L / r_b dL), or of the radius
// r = sqrt(r_b² + L²), each with the 5 % margins taken of that coordinate's extent. Checked from
// the returned roll lengths with the formulas written out here (not the planner's code).
TEST(ProbingGrid, ArcLengthAndRadiusSpacingsHaveEqualStepsOfTheirCoordinate) {
  const InvoluteGear gear = p1_gear();
  const double r_b = 0.5 * gear.base_diameter_mm();
  const double L0 = gear.form_roll_length_mm(), L1 = gear.tip_roll_length_mm();
  const auto arc = [&](double L) { return L * L / (2.0 * r_b); };
  const auto radius = [&](double L) { return std::sqrt(r_b * r_b + L * L); };
  for (const auto& [spacing, coordinate] :
       {std::pair<ProfileSpacing, std::function<double(double)>>{ProfileSpacing::kArcLength, arc},
        {ProfileSpacing::kRadius, radius}}) {
    ProbingGridSpec spec;
    spec.spacing = spacing;
    spec.points_along_profile = 7;
    const ProbingGridCoordinates c = probing_grid_coordinates(gear, spec);
    ASSERT_EQ(c.roll_lengths.size(), 7u);
    const double a = coordinate(L0), b = coordinate(L1);
    const double step = 0.9 * (b - a) / 6.0;
    for (int i = 0; i < 7; ++i) {
      EXPECT_NEAR(coordinate(c.roll_lengths[i]), a + 0.05 * (b - a) + i * step, 1e-9)
          << static_cast<int>(spacing) << " point " << i;
    }
  }
}

}  // namespace
}  // namespace gearmc

namespace gearmc {
namespace {

TEST(Contact, AStylusTooBigForTheToothSpaceCollides) {
  const InvoluteGear gear = p1_gear();
  const FlankDeviation none;
  // P1's gear has a tooth space of about p - s = 17.59 - 12.47 = 5.1 mm on the reference
  // circle and narrower towards the root: a 0.5 mm stylus fits everywhere on P1's grid, a
  // 3 mm radius (6 mm ball) cannot reach the lower profile without touching the facing flank.
  const ProbingPlanSpec plan;
  int small_collisions = 0, big_collisions = 0;
  for (FlankSide side : {FlankSide::kLeft, FlankSide::kRight}) {
    for (const PlannedPoint& pp : plan_flank(gear, plan.grid, 6, side)) {
      for (double R : {0.5, 3.0}) {
        ContactResult r = probe(gear, none, 6, side, pp.roll_length_mm, pp.z_mm, R);
        ASSERT_EQ(r.status, ContactResult::Status::kOk);
        check_tooth_space(gear, 6, side, pp.normal, StylusShape{R}, 1.0, &r);
        if (r.status == ContactResult::Status::kCollision) {
          (R == 0.5 ? small_collisions : big_collisions)++;
          EXPECT_EQ(spelling(r.collision), "neighbour_flank");
        }
      }
    }
  }
  EXPECT_EQ(small_collisions, 0);
  EXPECT_GT(big_collisions, 0);
  // The lowest profile point collides for R 3 mm; the highest does not (the space opens up).
  ContactResult low = probe(gear, none, 6, FlankSide::kRight, 22.6, 40.0, 3.0);
  check_tooth_space(gear, 6, FlankSide::kRight,
                    gear.flank_point(6, FlankSide::kRight, 22.6, 40).normal, StylusShape{3.0}, 1.0,
                    &low);
  EXPECT_EQ(low.status, ContactResult::Status::kCollision);
  ContactResult high = probe(gear, none, 6, FlankSide::kRight, 44.0, 40.0, 3.0);
  check_tooth_space(gear, 6, FlankSide::kRight,
                    gear.flank_point(6, FlankSide::kRight, 44.0, 40).normal, StylusShape{3.0}, 1.0,
                    &high);
  EXPECT_EQ(high.status, ContactResult::Status::kOk);
}

}  // namespace
}  // namespace gearmc

namespace gearmc {
namespace {

// Every state's spelling is a distinct snake_case word (kNone: empty), and docs/formats.md's
// points.csv section names each one (the table in contact_states.h is the one source).
TEST(ContactStates, EverySpellingIsDistinctAndDocumented) {
  std::ifstream in(std::string(GEARMC_SOURCE_DIR) + "/docs/formats.md");
  std::stringstream text;
  text << in.rdbuf();
  const std::string formats = text.str();
  std::set<std::string> seen;
  auto check = [&](std::string_view word) {
    ASSERT_FALSE(word.empty());
    EXPECT_TRUE(std::regex_match(std::string(word), std::regex("[a-z_]+"))) << word;
    EXPECT_TRUE(seen.insert(std::string(word)).second) << word << " spelled twice";
    EXPECT_NE(formats.find("`" + std::string(word) + "`"), std::string::npos)
        << word << " is not in docs/formats.md";
  };
  EXPECT_EQ(spelling(CollisionKind::kNone), "");
  EXPECT_EQ(spelling(ContactFailure::kNone), "");
  for (CollisionKind k :
       {CollisionKind::kNeighbourFlank, CollisionKind::kRoot, CollisionKind::kTouchingAtStart}) {
    check(spelling(k));
  }
  for (ContactFailure f :
       {ContactFailure::kNoMeshContact, ContactFailure::kRestartCap,
        ContactFailure::kNormalNotTransverse, ContactFailure::kFootprintNotBounded,
        ContactFailure::kNotConcaveAtContact, ContactFailure::kUnprovenRegion}) {
    check(spelling(f));
  }
  EXPECT_EQ(seen.size(), 9u);
}

}  // namespace
}  // namespace gearmc
