// Designed flank modifications (gears/flank_modifications.h) against their definitions: a
// circular relief is an arc (the circle through three of its points, computed here, holds every
// other point and is tangent to the flank where the relief starts) reaching the amount at its
// length; crowning is the parabola with C at both ends; a helix slope modification changes the
// design by H over the face; the derivatives agree with central differences; the bounds the
// contact certificate relies on hold every sampled value; the gear carries the curves and checks
// that they fit on its flank.
#include <gtest/gtest.h>

#include <cmath>

#include "gears/flank_modifications.h"
#include "gears/involute_gear.h"
#include "tests/support/helical_fixtures.h"

namespace gearmc {
namespace {

// The circle through three points (x, y): centre and radius (circumcircle, by the perpendicular
// bisectors' intersection).
struct Circle {
  double cx, cy, r;
};
Circle circle_through(double x1, double y1, double x2, double y2, double x3, double y3) {
  const double d = 2 * (x1 * (y2 - y3) + x2 * (y3 - y1) + x3 * (y1 - y2));
  const double s1 = x1 * x1 + y1 * y1, s2 = x2 * x2 + y2 * y2, s3 = x3 * x3 + y3 * y3;
  const double cx = (s1 * (y2 - y3) + s2 * (y3 - y1) + s3 * (y1 - y2)) / d;
  const double cy = (s1 * (x3 - x2) + s2 * (x1 - x3) + s3 * (x2 - x1)) / d;
  return {cx, cy, std::hypot(x1 - cx, y1 - cy)};
}

TEST(FlankModifications, CircularReliefIsAnArcTangentAtItsStartWithTheAmountAtItsEnd) {
  // A steep one (40 µm over 0.5 mm) so that the circle is well conditioned in double precision.
  const double start = 20.0, length = 0.5, amount_um = 40.0;
  ModificationCurve curve;
  curve.add_relief(start, +1, FlankRelief{amount_um, length});
  // In mm: (x, m(x)) on the arc.
  const auto at = [&](double x) { return 1e-3 * curve.value(start + x); };
  const Circle c = circle_through(0.0, at(0.0), 0.5 * length, at(0.5 * length), length, at(length));
  EXPECT_NEAR(c.cx, 0.0, 1e-9);  // the centre on the start's normal: tangent to the flank there
  EXPECT_NEAR(at(length), -1e-3 * amount_um, 1e-15);
  EXPECT_EQ(curve.value(start - 1.0), 0.0);  // nothing before the start
  for (int k = 1; k < 20; ++k) {
    const double x = length * k / 20.0;
    EXPECT_NEAR(std::hypot(x - c.cx, at(x) - c.cy), c.r, 1e-12 * c.r) << x;
  }
  // Past the relief's end (beyond the tip): its tangent continued.
  double v, d1, d2;
  curve.evaluate(start + length, &v, &d1, &d2);
  EXPECT_NEAR(curve.value(start + length + 0.1), v + 0.1 * d1, 1e-12);
  // The other direction: a root relief reaching its amount at start - length.
  ModificationCurve root;
  root.add_relief(start, -1, FlankRelief{amount_um, length});
  EXPECT_NEAR(root.value(start - length), -amount_um, 1e-12);
  EXPECT_EQ(root.value(start + 1.0), 0.0);
  EXPECT_NEAR(root.value(start - 0.2), curve.value(start + 0.2), 1e-12);  // mirror images
}

// A linear relief: 0 before its start, -C x / l beyond it (C at x = l, the same line past it),
// its slope -C / l on the relieved side and 0 on the other, no curvature; its start is the
// curve's kink, and the gear's design lists the kinks of its tip and root reliefs (external: the
// tip relief's at L_a - l; internal: at L_a + l, the tip being the small roll length).
TEST(FlankModifications, LinearReliefIsAStraightLineFromItsKink) {
  const double start = 20.0, length = 2.0, amount_um = 30.0;
  ModificationCurve tip, root;
  tip.add_relief(start, +1, FlankRelief{amount_um, length, true});
  root.add_relief(start, -1, FlankRelief{amount_um, length, true});
  for (const double x : {0.25, 1.0, 2.0, 2.5}) {
    EXPECT_NEAR(tip.value(start + x), -amount_um * x / length, 1e-12) << x;
    EXPECT_NEAR(root.value(start - x), -amount_um * x / length, 1e-12) << x;
    double v, d1, d2;
    tip.evaluate(start + x, &v, &d1, &d2);
    EXPECT_NEAR(d1, -amount_um / length, 1e-12);
    EXPECT_EQ(d2, 0.0);
    root.evaluate(start - x, &v, &d1, &d2);
    EXPECT_NEAR(d1, amount_um / length, 1e-12);  // dm/dt: the relief deepens towards smaller t
  }
  EXPECT_EQ(tip.value(start), 0.0);
  EXPECT_EQ(tip.value(start - 0.5), 0.0);
  ASSERT_EQ(tip.kinks().size(), 1u);
  EXPECT_EQ(tip.kinks()[0], start);
  const ModificationCurve::Bounds b = tip.derivative_bounds();
  EXPECT_NEAR(b.first_lo, -amount_um / length, 1e-12);
  EXPECT_EQ(b.first_hi, 0.0);
  EXPECT_EQ(b.second_lo, 0.0);
  EXPECT_EQ(b.second_hi, 0.0);
  for (const bool internal : {false, true}) {
    GearParameters p;
    p.teeth = 60, p.internal = internal, p.module_mm = 2.0, p.face_width_mm = 20.0;
    p.modifications.tip_relief = {amount_um, length, true};
    p.modifications.root_relief = {10.0, 1.0, false};  // circular: no kink
    ASSERT_EQ(validate_gear_parameters(p), "");
    const InvoluteGear g(p);
    ASSERT_EQ(g.design_modification()->profile_kinks.size(), 1u);
    EXPECT_NEAR(g.design_modification()->profile_kinks[0],
                g.tip_roll_length_mm() + (internal ? length : -length), 1e-12);
  }
}

TEST(FlankModifications, CrowningIsTheParabolaWithItsAmountAtBothEnds) {
  ModificationCurve curve;
  curve.add_crowning(10.0, 30.0, 6.0);
  EXPECT_NEAR(curve.value(10.0), -6.0, 1e-12);
  EXPECT_NEAR(curve.value(30.0), -6.0, 1e-12);
  EXPECT_NEAR(curve.value(20.0), 0.0, 1e-12);
  EXPECT_NEAR(curve.value(15.0), -1.5, 1e-12);  // a quarter of the amount half-way to the end
  // Outside: the tangent at the end, slope -4C/w = -1.2 µm/mm at the upper end.
  EXPECT_NEAR(curve.value(31.0), -6.0 - 1.2, 1e-12);
}

TEST(FlankModifications, TheGearsDesignCurvesSpanItsFlank) {
  GearParameters p = testing_support::helical_gear_parameters();
  p.modifications.tip_relief = {10.0, 3.0};
  p.modifications.root_relief = {5.0, 1.5};
  p.modifications.end_relief = {8.0, 4.0};
  p.modifications.helix_crowning_um = 5.0;
  p.modifications.helix_slope_um = -6.0;
  ASSERT_EQ(validate_gear_parameters(p), "");
  const InvoluteGear gear(p);
  const DesignModification* m = gear.design_modification();
  ASSERT_NE(m, nullptr);
  const double La = gear.tip_roll_length_mm(), Lf = gear.form_roll_length_mm(), b = 40.0;
  EXPECT_NEAR(m->profile.value(La), -10.0, 1e-12);
  EXPECT_NEAR(m->profile.value(La - 3.0), 0.0, 1e-12);
  EXPECT_NEAR(m->profile.value(Lf), -5.0, 1e-12);
  EXPECT_NEAR(m->profile.value(0.5 * (La + Lf)), 0.0, 1e-12);
  // Helix: end reliefs of 8 at both faces, crowning 5 at both ends, slope -6 over b.
  EXPECT_NEAR(m->helix.value(0.0), -8.0 - 5.0 + 3.0, 1e-12);
  EXPECT_NEAR(m->helix.value(b), -8.0 - 5.0 - 3.0, 1e-12);
  EXPECT_NEAR(m->helix.value(0.5 * b), 0.0, 1e-12);
  EXPECT_NEAR(m->value_um(La, b), -10.0 - 16.0, 1e-12);
  // No modification: no curves (the flank is the involute, bit for bit).
  EXPECT_EQ(testing_support::helical_gear().design_modification(), nullptr);
}

TEST(FlankModifications, DerivativesAndTheCertificatesBoundsHold) {
  GearParameters p = testing_support::helical_gear_parameters();
  p.modifications.tip_relief = {25.0, 2.0};
  p.modifications.root_relief = {12.0, 1.0};
  p.modifications.profile_crowning_um = 4.0;
  p.modifications.end_relief = {15.0, 3.0};
  p.modifications.helix_crowning_um = 6.0;
  p.modifications.helix_slope_um = 9.0;
  const InvoluteGear gear(p);
  const DesignModification& m = *gear.design_modification();
  for (const ModificationCurve* curve : {&m.profile, &m.helix}) {
    const bool profile = curve == &m.profile;
    const double lo = profile ? gear.form_roll_length_mm() - 2 : -2.0;
    const double hi = profile ? gear.tip_roll_length_mm() + 2 : 42.0;
    const ModificationCurve::Bounds bounds = curve->derivative_bounds();
    const double magnitude = curve->magnitude_bound(lo, hi);
    for (int k = 0; k <= 4000; ++k) {
      const double t = lo + (hi - lo) * k / 4000.0;
      double v, d1, d2;
      curve->evaluate(t, &v, &d1, &d2);
      const double h = 1e-5;
      // Central differences (the curves are C1: m' everywhere; m'' away from the joints).
      EXPECT_NEAR(d1, (curve->value(t + h) - curve->value(t - h)) / (2 * h), 1e-4) << t;
      double vp, d1p, d2p, vm, d1m, d2m;
      curve->evaluate(t + h, &vp, &d1p, &d2p);
      curve->evaluate(t - h, &vm, &d1m, &d2m);
      if (std::abs(d2p - d2m) < 1e-9) {
        EXPECT_NEAR(d2, (d1p - d1m) / (2 * h), 1e-3) << t;
      }
      EXPECT_LE(std::abs(v), magnitude + 1e-12);
      EXPECT_GE(d1, bounds.first_lo - 1e-12);
      EXPECT_LE(d1, bounds.first_hi + 1e-12);
      EXPECT_GE(d2, bounds.second_lo - 1e-12);
      EXPECT_LE(d2, bounds.second_hi + 1e-12);
    }
  }
}

TEST(FlankModifications, ReliefsThatDoNotFitTheFlankAreRefused) {
  GearParameters p = testing_support::helical_gear_parameters();
  const InvoluteGear gear(p);
  const double active = gear.tip_roll_length_mm() - gear.form_roll_length_mm();
  p.modifications.tip_relief = {10.0, 0.6 * active};
  p.modifications.root_relief = {10.0, 0.6 * active};
  EXPECT_NE(validate_gear_parameters(p).find("more than the active profile"), std::string::npos);
  p.modifications = {};
  p.modifications.end_relief = {10.0, 25.0};
  EXPECT_NE(validate_gear_parameters(p).find("more than half the face width"), std::string::npos);
  p.modifications = {};
  p.modifications.tip_relief = {2000.0, 1.5};  // 2 mm over 1.5 mm
  EXPECT_NE(validate_gear_parameters(p).find("steeper than 45°"), std::string::npos);
}

}  // namespace
}  // namespace gearmc
