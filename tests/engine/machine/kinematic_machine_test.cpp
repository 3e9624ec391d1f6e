// The kinematic machine (engine/machine/kinematic_machine.h) and its ISO 10360-2 length test
// (length_test.h) on machines with one error function set by hand, against length errors
// computed by hand from the geometry (not from gearmc's code): a pure x scale, a pure
// squareness, a pitch of the X carriage and a yaw with a stylus offset (Abbe); a constant angular
// error of the last axis moves only the stylus and changes no length, while one of the bridge is a
// squareness; and on the common ground with the
// `scale`, `squareness` and `straightness` effects, the machine moves P1's readings as they do.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "engine/effects/effects.h"
#include "engine/effects/warmup_straightness.h"
#include "engine/machine/kinematic_machine.h"
#include "engine/machine/length_test.h"
#include "engine/plan/probing_grid.h"
#include "tests/support/p1_fixtures.h"

namespace gearmc {
namespace {

EffectParameter fixed(double v) {
  EffectParameter p;
  p.value = v;
  return p;
}

TEST(KinematicMachine, LegendreSeriesMatchesTheClosedForms) {
  // P0 … P4 at u = 0.3 (Abramowitz & Stegun 22.3: P2 = (3u² − 1)/2, P3 = (5u³ − 3u)/2,
  // P4 = (35u⁴ − 30u² + 3)/8).
  const double u = 0.3;
  EXPECT_DOUBLE_EQ(legendre_series({1.0}, u), 1.0);
  EXPECT_DOUBLE_EQ(legendre_series({0.0, 1.0}, u), u);
  EXPECT_NEAR(legendre_series({0.0, 0.0, 1.0}, u), 0.5 * (3 * u * u - 1), 1e-15);
  EXPECT_NEAR(legendre_series({0.0, 0.0, 0.0, 1.0}, u), 0.5 * (5 * u * u * u - 3 * u), 1e-15);
  EXPECT_NEAR(legendre_series({0.0, 0.0, 0.0, 0.0, 1.0}, u),
              (35 * std::pow(u, 4) - 30 * u * u + 3) / 8.0, 1e-15);
}

TEST(KinematicMachine, APureXScaleErrorGivesLengthTimesScaleTimesUx2) {
  // δ_xx = c₁ P₁(q_x/(T_x/2)): s = c₁/(T_x/2) µm per mm. A gauge along û measured
  // bidirectionally spans L + 2R between the stylus centres: E = s (L + 2R) û_x². To 1 nm.
  KinematicMachine m;
  m.axes[0].translation_um[0] = {0.0, 3.5};  // 3.5 µm at the ends of the x travel (700 mm)
  const double s = 3.5 / 350.0;              // µm per mm = 10 ppm
  const LengthTestOptions o;
  const auto positions = length_test_positions(m.travel_mm);
  ASSERT_EQ(positions.size(), 7u);
  const auto errors = length_test(m, o);
  ASSERT_EQ(errors.size(), 35u);
  for (const LengthError& e : errors) {
    const Eigen::Vector3d& u = positions[static_cast<std::size_t>(e.position)].direction;
    EXPECT_NEAR(e.error_um, s * (e.length_mm + 2.0 * o.ball_radius_mm) * u.x() * u.x(), 1e-3);
  }
}

TEST(KinematicMachine, APureSquarenessGivesLengthTimesGammaTimesUxUy) {
  // e_x = γ q_y: E = 1e-3 γ (L + 2R) û_x û_y (µrad · mm); 0 on the axis-parallel gauges.
  KinematicMachine m;
  m.squareness_xy_urad = 20.0;
  const LengthTestOptions o;
  const auto positions = length_test_positions(m.travel_mm);
  for (const LengthError& e : length_test(m, o)) {
    const Eigen::Vector3d& u = positions[static_cast<std::size_t>(e.position)].direction;
    EXPECT_NEAR(e.error_um, 1e-3 * 20.0 * (e.length_mm + 2.0 * o.ball_radius_mm) * u.x() * u.y(),
                1e-3);
  }
}

TEST(KinematicMachine, PitchAndYawOfTheXCarriageActThroughTheirAbbeArms) {
  // Bridge: the X carriage carries Z and the stylus, so its rotation ε(q_x) turns the arm
  // r = (t_x, t_y, q_z + t_z) to the ball; along x the reading moves by (ε × r)_x =
  // ε_y r_z − ε_z r_y. On the x gauge (q_z = 0 at the centre) r_z = t_z and r_y = t_y:
  // E = 1e-3 [Δε_y t_z − Δε_z t_y], Δε = c₁ (L + 2R)/(T_x/2) for ε = c₁ P₁.
  KinematicMachine m;
  m.axes[0].rotation_urad[1] = {0.0, 10.0};  // pitch: 10 µrad at the ends of the travel
  m.axes[0].rotation_urad[2] = {0.0, -6.0};  // yaw
  LengthTestOptions o;
  o.stylus_mm = Eigen::Vector3d(0.0, 80.0, -150.0);  // a stylus reaching 80 mm sideways
  const auto positions = length_test_positions(m.travel_mm);
  int checked = 0;
  for (const LengthError& e : length_test(m, o)) {
    if (positions[static_cast<std::size_t>(e.position)].name != "x") continue;
    const double span = (e.length_mm + 2.0 * o.ball_radius_mm) / 350.0;
    const double expected = 1e-3 * (10.0 * span * -150.0 - (-6.0 * span) * 80.0);
    EXPECT_NEAR(e.error_um, expected, 1e-3) << e.length_mm;
    ++checked;
  }
  EXPECT_EQ(checked, 5);
  // Without the sideways reach the yaw does nothing on the x gauge.
  o.stylus_mm = Eigen::Vector3d(0.0, 0.0, -150.0);
  for (const LengthError& e : length_test(m, o)) {
    if (positions[static_cast<std::size_t>(e.position)].name != "x") continue;
    const double span = (e.length_mm + 2.0 * o.ball_radius_mm) / 350.0;
    EXPECT_NEAR(e.error_um, 1e-3 * 10.0 * span * -150.0, 1e-3);
  }
}

TEST(KinematicMachine, AConstantAngularErrorOfTheLastAxisTurnsOnlyTheStylusAndNoLength) {
  // The last axis of the stack carries only the stylus: a constant ε moves the ball by ε × t, the
  // same everywhere, and no length changes. Random constants, three layouts, a bent stylus.
  std::mt19937_64 rng(7);
  std::normal_distribution<double> unit(0.0, 20.0);
  for (MachineLayout layout :
       {MachineLayout::kBridge, MachineLayout::kGantry, MachineLayout::kHorizontalArm}) {
    KinematicMachine m;
    m.layout = layout;
    const int last = m.stacking()[2];
    for (auto& f : m.axes[static_cast<std::size_t>(last)].rotation_urad) f = {unit(rng)};
    LengthTestOptions o;
    o.stylus_mm = Eigen::Vector3d(30.0, -50.0, -120.0);
    for (const LengthError& e : length_test(m, o)) EXPECT_NEAR(e.error_um, 0.0, 1e-9);
  }
}

TEST(KinematicMachine, AConstantYawOfTheBridgeIsASquarenessOfXAndY) {
  // The bridge (Y, at the base) yawed by a constant ε_z turns the X axis it carries: the ball
  // moves by ε q_x along y, a shear of the pair (x, y) — by length, the same as a squareness
  // γ_xy = ε (the two differ by a rigid turn, which changes no length). ISO 230-1 counts such a
  // constant as part of the squareness; here it shows in every one of the 35 lengths.
  KinematicMachine yawed, square;
  yawed.axes[1].rotation_urad[2] = {15.0};
  square.squareness_xy_urad = 15.0;
  LengthTestOptions o;
  o.stylus_mm = Eigen::Vector3d(20.0, 10.0, -150.0);
  const auto a = length_test(yawed, o), b = length_test(square, o);
  ASSERT_EQ(a.size(), b.size());
  double largest = 0.0;
  for (std::size_t k = 0; k < a.size(); ++k) {
    EXPECT_NEAR(a[k].error_um, b[k].error_um, 1e-9);
    largest = std::max(largest, std::abs(a[k].error_um));
  }
  EXPECT_GT(largest, 1.0);  // not trivially zero: micrometres on the diagonals
}

TEST(KinematicMachine, TheStackingDecidesWhatAnAxisCarries) {
  // A rotation of the Y axis about x turns, on a bridge, the X and Z axes and the stylus (Y is at
  // the base), but on a horizontal arm only the stylus (Y is the arm, last): at the tip
  // (100, 50, 80) with no stylus and no placement, ε_x × r gives e_y = −ε_x r_z, e_z = ε_x r_y.
  KinematicMachine bridge;
  bridge.axes[1].rotation_urad[0] = {100.0};
  KinematicMachine arm = bridge;
  arm.layout = MachineLayout::kHorizontalArm;
  const Eigen::Vector3d tip(100.0, 50.0, 80.0), none = Eigen::Vector3d::Zero();
  // Bridge: r_Y = (q_x, 0, q_z) = (100, 0, 80).
  const Eigen::Vector3d eb = bridge.tip_error_um(tip, none);
  EXPECT_NEAR(eb.x(), 0.0, 1e-12);
  EXPECT_NEAR(eb.y(), -1e-3 * 100.0 * 80.0, 1e-12);
  EXPECT_NEAR(eb.z(), 0.0, 1e-12);
  // Horizontal arm: r_Y = the stylus only = 0.
  EXPECT_NEAR(arm.tip_error_um(tip, none).norm(), 0.0, 1e-12);
}

// P1's planned points as (stylus centre, normal).
std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>> p1_centres() {
  const InvoluteGear gear = testing_support::p1_gear();
  ProbingGridSpec spec;
  std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>> out;
  for (int tooth = 1; tooth <= gear.teeth(); tooth += 5) {
    for (FlankSide side : {FlankSide::kLeft, FlankSide::kRight}) {
      for (const PlannedPoint& q : plan_flank(gear, spec, tooth, side)) {
        out.emplace_back(q.point + 0.5 * q.normal, q.normal);
      }
    }
  }
  return out;
}

double effect_reading_um(const MeasurementEffect& effect, const std::vector<double>& values,
                         const Eigen::Vector3d& c, const Eigen::Vector3d& n) {
  PointContext point;
  point.p = c - 0.5 * n;
  point.n = n;
  Eigen::Vector3d moved = c;
  RandomStream rng = point_effect_stream(1, 0, 0);
  effect.apply(point, values, moved, rng);
  return 1e3 * (moved - c).dot(n);
}

TEST(KinematicMachine, TheScaleSquarenessAndStraightnessEffectsAreSpecialCases) {
  // No stylus offset, no placement (the gear centre at the middle of the travel): a linear
  // positioning error per axis is the `scale` effect, the machine's squareness the `squareness`
  // effect, a straightness of the Y axis in x, δ_x(y) = a (y/L)², the `straightness` effect's
  // xy_um = a (L = 100 mm; in Legendre terms of u = y/(T_y/2): c₀ = a (T_y/2)²/(3L²),
  // c₂ = 2 a (T_y/2)²/(3L²)). Readings along n equal to 1e-9 µm at P1's points.
  const Eigen::Vector3d none = Eigen::Vector3d::Zero();
  KinematicMachine scale;
  scale.axes[0].translation_um[0] = {0.0, 5.0 * 350.0 * 1e-3};   // 5 ppm over ±350 mm
  scale.axes[1].translation_um[1] = {0.0, -3.0 * 500.0 * 1e-3};  // −3 ppm over ±500 mm
  const ScaleEffect scale_effect(fixed(5.0), fixed(-3.0), fixed(0.0));
  KinematicMachine square;
  square.squareness_xy_urad = 20.0;
  square.squareness_xz_urad = 5.0;
  square.squareness_yz_urad = -7.0;
  const SquarenessEffect square_effect(fixed(20.0), fixed(5.0), fixed(-7.0));
  KinematicMachine bow;
  const double a = 2.0, l = 100.0, half = 500.0;
  bow.axes[1].translation_um[0] = {a * half * half / (3.0 * l * l), 0.0,
                                   2.0 * a * half * half / (3.0 * l * l)};
  const StraightnessEffect bow_effect(fixed(a), fixed(0.0), fixed(0.0), fixed(0.0), l);
  for (const auto& [c, n] : p1_centres()) {
    EXPECT_NEAR(scale.tip_error_um(c, none).dot(n),
                effect_reading_um(scale_effect, {5.0, -3.0, 0.0}, c, n), 1e-9);
    EXPECT_NEAR(square.tip_error_um(c, none).dot(n),
                effect_reading_um(square_effect, {20.0, 5.0, -7.0}, c, n), 1e-9);
    EXPECT_NEAR(bow.tip_error_um(c, none).dot(n),
                effect_reading_um(bow_effect, {a, 0.0, 0.0, 0.0}, c, n), 1e-9);
  }
}

TEST(KinematicMachine, LayoutNamesRoundTripAndBadOnesAreRefused) {
  for (const char* name : {"bridge", "gantry", "horizontal_arm"}) {
    EXPECT_EQ(machine_layout_name(parse_machine_layout(name)), name);
  }
  EXPECT_THROW(parse_machine_layout("cantilever"), std::invalid_argument);
}

}  // namespace
}  // namespace gearmc
