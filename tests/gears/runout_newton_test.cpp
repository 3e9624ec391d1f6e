// The sampler's radial runout (ball at mid face touching both real flanks of every tooth space)
// solves its 2-D Newton with the flanks' closed-form distance gradients as the Jacobian. The
// independent reference here is the finite-difference Newton it replaced (same distance
// formula, Jacobian from forward differences with h = 1e-7 mm, as gears/deviations.cpp had it):
// both must find the same ball centres, so the runout agrees to far below a micrometre and
// every accept/redraw decision of the sampler (runout against F_r (1 - 1e-3)) comes out the same.
#include <gtest/gtest.h>

#include <Eigen/LU>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numbers>

#include "gears/deviations.h"
#include "tests/support/p1_fixtures.h"

namespace gearmc {
namespace {

using testing_support::p1_gear_parameters;

// Signed distance (mm) of X from the real flank, first order in the deviation.
double reference_distance(const InvoluteGear& gear, const PerturbedGear& g, int tooth,
                          FlankSide side, const Eigen::Vector2d& X, double z) {
  const Eigen::Vector2d Xg = X - g.eccentricity_mm;
  const double r_b = gear.base_diameter_mm() / 2.0;
  const double rho = Xg.norm();
  const double t = std::sqrt(std::max(0.0, rho * rho - r_b * r_b));
  const double alpha_x = std::atan2(t, r_b);
  const double phi = std::remainder(std::atan2(Xg.y(), Xg.x()) - gear.tooth_centre_angle_rad(tooth),
                                    2.0 * std::numbers::pi);
  const double s = side_sign(side);
  const double theta_b = gear.base_half_angle_rad();
  const double distance = r_b * (involute_function(alpha_x) + s * phi - theta_b);
  const double foot_L = r_b * (theta_b - s * phi + alpha_x);
  return distance - 1e-3 * g.flank(tooth, side).normal_um(foot_L, z);
}

// The finite-difference Newton (3 residual pairs = 6 distances per step).
double reference_runout_um(const InvoluteGear& gear, const PerturbedGear& g) {
  const EvaluationRanges ranges = evaluation_ranges(gear);
  const double z = 0.5 * gear.face_width_mm();
  const double L_c = 0.5 * (ranges.profile_start_mm + ranges.profile_end_mm);
  const FlankPoint c = gear.flank_point(1, FlankSide::kRight, L_c, z);
  const double half = 0.5 * gear.angular_pitch_rad();
  const Eigen::Vector2d bisector_normal(-std::sin(half), std::cos(half));
  const Eigen::Vector2d p = c.point.head<2>(), n = c.normal.head<2>();
  const double r_ball = -p.dot(bisector_normal) / n.dot(bisector_normal);
  const double rho_nominal = (p + r_ball * n).norm();
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (int k = 1; k <= gear.teeth(); ++k) {
    const int next = k % gear.teeth() + 1;
    const double angle = gear.tooth_centre_angle_rad(k) + half;
    Eigen::Vector2d X = rho_nominal * Eigen::Vector2d(std::cos(angle), std::sin(angle));
    auto residual = [&](const Eigen::Vector2d& Y) {
      return Eigen::Vector2d(reference_distance(gear, g, k, FlankSide::kRight, Y, z) - r_ball,
                             reference_distance(gear, g, next, FlankSide::kLeft, Y, z) - r_ball);
    };
    for (int iter = 0; iter < 20; ++iter) {
      const Eigen::Vector2d f = residual(X);
      if (f.cwiseAbs().maxCoeff() < 1e-10) break;
      constexpr double h = 1e-7;
      Eigen::Matrix2d J;
      J.col(0) = (residual(X + Eigen::Vector2d(h, 0)) - f) / h;
      J.col(1) = (residual(X + Eigen::Vector2d(0, h)) - f) / h;
      X -= J.partialPivLu().solve(f);
    }
    lo = std::min(lo, X.norm());
    hi = std::max(hi, X.norm());
  }
  return 1e3 * (hi - lo);
}

// Drawn gears of P1 (GOST tolerances) and of an ISO class-5 set, each as drawn and in the
// states the sampler measures (no eccentricity, pitch part scaled by 0.8^j): the closed-form
// Newton agrees with the finite-difference one to 1e-6 µm, and on which side of the sampler's
// threshold F_r (1 - 1e-3) each value lies is the same.
TEST(RadialRunout, ClosedFormNewtonMatchesFiniteDifferenceNewton) {
  const InvoluteGear gear(p1_gear_parameters());
  double worst = 0.0;
  int compared = 0;
  for (const ToleranceSet& tol :
       {testing_support::p1_tolerance_set(), testing_support::iso_class5_tolerance_set()}) {
    const double threshold = tol.get_um(ToleranceKind::kRunout).value() * (1.0 - 1e-3);
    const GearSampler sampler(gear, tol, DeviationModel{}, 11);
    for (int k = 0; k < 30; ++k) {
      PerturbedGear g = sampler.draw(k);
      for (int state = 0; state < 4; ++state) {
        if (state == 1) g.eccentricity_mm.setZero();
        if (state >= 2) {
          for (FlankDeviation& f : g.flanks) f.offset_um *= 0.8;
        }
        const double fast = radial_runout_um(gear, g), reference = reference_runout_um(gear, g);
        EXPECT_NEAR(fast, reference, 1e-6) << "gear " << k << " state " << state;
        EXPECT_EQ(fast > threshold, reference > threshold) << "gear " << k;
        worst = std::max(worst, std::abs(fast - reference));
        ++compared;
      }
    }
  }
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.3g", worst);
  RecordProperty("worst_difference_um", buffer);
  EXPECT_EQ(compared, 240);
}

// The sampler's own decisions with a tight F_r (8 µm: P1's profile and helix shapes alone often
// exceed it, so gears are redrawn): every gear it returns has, by the reference Newton, a
// runout within F_r, and gears that needed no redraw are within F_r (1 - 1e-3) without their
// eccentricity, as the sampler decided.
TEST(RadialRunout, TightRunoutDecisionsHoldByTheReference) {
  const InvoluteGear gear(p1_gear_parameters());
  ToleranceSet tight = testing_support::p1_tolerance_set();
  tight.values[ToleranceKind::kRunout] = {8, "test", true};
  const GearSampler sampler(gear, tight, DeviationModel{}, 3);
  int redrawn = 0;
  for (int k = 0; k < 40; ++k) {
    PerturbedGear g = sampler.draw(k);
    redrawn += g.runout_redraws > 0;
    EXPECT_LE(reference_runout_um(gear, g), 8.0) << "gear " << k;
    g.eccentricity_mm.setZero();
    EXPECT_LE(reference_runout_um(gear, g), 8.0 * (1.0 - 1e-3)) << "gear " << k;
  }
  EXPECT_GT(redrawn, 0);  // the redraw path is exercised
}

}  // namespace
}  // namespace gearmc
