// Tests of the measurement model and the per-point pipeline (engine/measurement): the plan holds
// every planned point once with the scenario's probing order, the nominal points are the gear's,
// the drawn gear is the sampler's, a nominal gear measured without effects reads zero error, the
// effects move the recorded centre as their formulas say, and the certificate deviation of an
// expression surface is the expression.
#include <gtest/gtest.h>

#include <set>
#include <tuple>

#include "engine/effects/effect_config.h"
#include "engine/measurement/gear_measurement.h"
#include "engine/measurement/measurement_model.h"
#include "engine/plan/probing_grid.h"

namespace gearmc {
namespace {

Scenario small_reference() {
  Scenario s = reference_scenario();
  s.probing.teeth = {1, 2, 7};
  return s;
}

TEST(MeasurementModel, PlanHoldsEveryPlannedPointOnceInTheScenariosOrder) {
  for (ProbingOrder order : {ProbingOrder::kToothByTooth, ProbingOrder::kSideBySide}) {
    Scenario s = small_reference();
    s.probing.order = order;
    const MeasurementModel model(s);
    // 3 teeth x 2 flanks, each N x M points (the reference grid 10 x 5).
    ASSERT_EQ(model.flanks().size(), 6u);
    EXPECT_EQ(model.points_per_flank(), 50);
    EXPECT_EQ(model.probed_teeth(), 3);
    ASSERT_EQ(model.sequence_length(), 300);
    // The sequence is probing_sequence() (probing_grid.h), point for point.
    const std::vector<PlannedPoint> expected = probing_sequence(model.gear(), s.probing);
    ASSERT_EQ(expected.size(), 300u);
    std::set<const PlanPoint*> seen;
    for (int k = 0; k < model.sequence_length(); ++k) {
      const PlanPoint& q = *model.sequence()[k];
      EXPECT_EQ(q.order, k);
      EXPECT_EQ(std::tie(q.tooth, q.side, q.i, q.j),
                std::tie(expected[k].tooth, expected[k].side, expected[k].i, expected[k].j));
      EXPECT_EQ((q.nominal.point - expected[k].point).norm(), 0.0);
      EXPECT_TRUE(seen.insert(&q).second);
    }
    // Flanks in (tooth, side) order, points j-major; nominal point = the gear's flank point.
    int index = 0;
    for (const PlanFlank& flank : model.flanks()) {
      EXPECT_EQ(flank.tooth, s.probing.teeth[index / 2]);
      EXPECT_EQ(flank.side, index % 2 == 0 ? FlankSide::kLeft : FlankSide::kRight);
      ++index;
      for (std::size_t p = 0; p < flank.points.size(); ++p) {
        const PlanPoint& q = flank.points[p];
        EXPECT_EQ(static_cast<std::size_t>(q.j * 10 + q.i), p);
        const FlankPoint fp = model.gear().flank_point(q.tooth, q.side, q.roll_length_mm, q.z_mm);
        EXPECT_EQ((fp.point - q.nominal.point).norm(), 0.0);
        EXPECT_TRUE(seen.count(&q));
      }
    }
  }
}

TEST(MeasurementModel, DrawsTheSamplersGear) {
  // The same gear as a sampler built by hand from the scenario's tolerances, law and seed.
  const Scenario s = small_reference();
  const MeasurementModel model(s);
  const InvoluteGear gear(s.gear);
  const GearSampler sampler(gear, resolve_scenario_tolerances(s, gear), s.deviations, s.seed);
  for (int k : {0, 5}) {
    const PerturbedGear a = model.draw_gear(k), b = sampler.draw(k);
    EXPECT_EQ(a.eccentricity_mm, b.eccentricity_mm);
    EXPECT_EQ(a.rack_shift_um, b.rack_shift_um);
    for (std::size_t f = 0; f < a.flanks.size(); ++f) {
      EXPECT_EQ(a.flanks[f].offset_um, b.flanks[f].offset_um);
    }
  }
}

TEST(GearMeasurement, NominalGearWithoutEffectsReadsZeroError) {
  // On the nominal flank the first contact is at the nominal point: centre p + R n, reported
  // E = p, so δRcomp = 0 and the total error 0 (contact.h; the solver's tolerance < 1 nm: 1e-6 µm
  // asserted as in contact_test.cpp).
  Scenario s = small_reference();
  s.deviations.random = false;
  const MeasurementModel model(s);
  int points = 0;
  GearMeasurement(model, 3, EffectMode::kDrawn).measure([&](const PointMeasurement& m) {
    ASSERT_TRUE(m.valid()) << m.plan->tooth << " " << m.plan->i << " " << m.plan->j;
    const double R = s.stylus_radius_mm;
    EXPECT_LT((m.recorded_centre - (m.plan->nominal.point + R * m.plan->nominal.normal)).norm(),
              1e-9);
    EXPECT_NEAR(m.total_error_um, 0.0, 1e-6);
    EXPECT_TRUE(m.contributions.empty());
    ++points;
  });
  EXPECT_EQ(points, 300);
}

TEST(GearMeasurement, FixedScaleEffectMovesTheRecordedCentreByItsFormula) {
  // scale: each coordinate of the recorded centre times 1 + 1e-6·ppm (engine/effects ScaleEffect,
  // ISO 10360 scale error). On the nominal gear the contact centre is p + R n, so the recorded
  // centre is 1.00001 (p + R n) at 10 ppm and the reading changes by 1000·1e-5·(p + R n)·n µm.
  Scenario s = small_reference();
  s.deviations.random = false;
  s.effects = std::make_shared<const EffectChain>(parse_effects(
      parse_yaml_document("scale: {x_ppm: 10, y_ppm: 10, z_ppm: 10}\n", "effects.yaml")));
  const MeasurementModel model(s);
  const double R = s.stylus_radius_mm;
  GearMeasurement(model, 0, EffectMode::kDrawn).measure([&](const PointMeasurement& m) {
    ASSERT_TRUE(m.valid());
    // The effects' view of the point: its place in the probing sequence and its azimuth.
    EXPECT_EQ(m.context.order, m.plan->order);
    EXPECT_EQ(m.context.sequence_length, 300);
    EXPECT_EQ(m.context.azimuth_rad,
              std::atan2(-m.plan->nominal.normal.y(), -m.plan->nominal.normal.x()));
    const Eigen::Vector3d centre = m.plan->nominal.point + R * m.plan->nominal.normal;
    EXPECT_LT((m.recorded_centre - 1.00001 * centre).norm(), 1e-9);
    const double expected_um = 1000.0 * 1e-5 * centre.dot(m.plan->nominal.normal);
    ASSERT_EQ(m.contributions.size(), 1u);
    EXPECT_NEAR(m.contributions[0], expected_um, 1e-6);
    EXPECT_NEAR(m.total_error_um, expected_um, 1e-6);
  });
  // Without effects the same gear records the contact centre itself.
  GearMeasurement(model, 0, EffectMode::kNone).measure([&](const PointMeasurement& m) {
    EXPECT_EQ(m.recorded_centre, m.contact.centre);
    EXPECT_NEAR(m.total_error_um, 0.0, 1e-6);
  });
}

TEST(GearMeasurement, SurfaceDeviationIsTheExpressionOnANominalGear) {
  // normal_um: a constant 2.5 µm along n (deterministic deviations, docs/scenarios.md) on a gear
  // without random deviations: the certificate value is 2.5 µm at every planned point.
  Scenario s = small_reference();
  s.deviations.random = false;
  s.normal_expression_um = "2.5";
  const MeasurementModel model(s);
  const GearMeasurement measurement(model, 0, EffectMode::kNone);
  for (const PlanPoint* q : model.sequence()) {
    EXPECT_NEAR(measurement.surface_deviation_um(*q), 2.5, 1e-9);
  }
  // And the contact sees it: the stylus stops 2.5 µm earlier (reading +2.5 µm along n).
  measurement.measure([&](const PointMeasurement& m) {
    ASSERT_TRUE(m.valid());
    const double reading =
        1000.0 * ((m.recorded_centre - m.plan->nominal.point).dot(m.plan->nominal.normal) -
                  s.stylus_radius_mm);
    EXPECT_NEAR(reading, 2.5, 1e-6);
  });
}

}  // namespace
}  // namespace gearmc
