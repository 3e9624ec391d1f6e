// The real flank surface S(L, z): its analytic partial derivatives against finite differences,
// and its normal against the geometric facts (offsets and eccentricity keep the nominal
// normal at corresponding points; a slope tilts it by atan(slope)).
#include "surfaces/analytic_flank.h"
#include "tests/support/helical_fixtures.h"
#include "tests/support/p1_fixtures.h"

#include <gtest/gtest.h>

#include <cmath>

namespace gearmc {
namespace {

using testing_support::p1_gear;
using testing_support::p1_gear_parameters;
using testing_support::wavy_deviation;

TEST(AnalyticFlank, PartialsMatchFiniteDifferences) {
  const InvoluteGear gear = p1_gear();
  const FlankDeviation dev = wavy_deviation();
  const NormalExpression expr("0.5*sin(L)*cos(z/7)");
  for (const NormalExpression* e : {static_cast<const NormalExpression*>(nullptr), &expr}) {
    for (FlankSide side : {FlankSide::kLeft, FlankSide::kRight}) {
      const AnalyticFlank flank(gear, 7, side, dev, {0.01, -0.02}, e);
      const double h = 1e-4;
      for (double L : {23.0, 31.7, 42.2}) {
        for (double z : {8.0, 40.0, 70.0}) {
          const FlankSurfacePoint s = flank.evaluate(L, z);
          const Eigen::Vector3d fd_L =
              (flank.evaluate(L + h, z).point - flank.evaluate(L - h, z).point) / (2 * h);
          const Eigen::Vector3d fd_z =
              (flank.evaluate(L, z + h).point - flank.evaluate(L, z - h).point) / (2 * h);
          EXPECT_NEAR((s.d_dL - fd_L).norm(), 0.0, 1e-8);
          EXPECT_NEAR((s.d_dz - fd_z).norm(), 0.0, 1e-8);
          const Eigen::Vector3d fd_LL =
              (flank.evaluate(L + h, z).d_dL - flank.evaluate(L - h, z).d_dL) / (2 * h);
          const Eigen::Vector3d fd_Lz =
              (flank.evaluate(L, z + h).d_dL - flank.evaluate(L, z - h).d_dL) / (2 * h);
          const Eigen::Vector3d fd_zz =
              (flank.evaluate(L, z + h).d_dz - flank.evaluate(L, z - h).d_dz) / (2 * h);
          // The expression's second partials are themselves differences (step 1e-3 mm).
          const double tol = e ? 2e-6 : 1e-7;
          EXPECT_NEAR((s.d2_dL2 - fd_LL).norm(), 0.0, tol);
          EXPECT_NEAR((s.d2_dLdz - fd_Lz).norm(), 0.0, tol);
          EXPECT_NEAR((s.d2_dz2 - fd_zz).norm(), 0.0, tol);
        }
      }
    }
  }
}

// A helical flank's partials (flank_frame.h) against central differences of its points, both
// hands and sides, with a B-spline field and an expression; its nominal normal is the helicoid's
// (InvoluteGear::flank_point), its real normal with no deviation the same.
TEST(AnalyticFlank, HelicalPartialsMatchFiniteDifferences) {
  const FlankDeviation dev = testing_support::helical_wavy_deviation();
  const NormalExpression expr("0.5*sin(L)*cos(z/7) - 20*max(0, L-30)^2/16");
  for (Hand hand : {Hand::kRight, Hand::kLeft}) {
    const InvoluteGear gear = testing_support::helical_gear(hand);
    for (const NormalExpression* e : {static_cast<const NormalExpression*>(nullptr), &expr}) {
      for (FlankSide side : {FlankSide::kLeft, FlankSide::kRight}) {
        const AnalyticFlank flank(gear, 7, side, dev, {0.01, -0.02}, e);
        const FlankDeviation none;
        const AnalyticFlank nominal(gear, 7, side, none, {0.0, 0.0});
        const double h = 1e-4;
        for (double L : {17.0, 24.3, 32.2}) {
          for (double z : {3.0, 20.0, 37.0}) {
            const FlankSurfacePoint s = flank.evaluate(L, z);
            auto P = [&](double l, double zz) { return flank.point(l, zz); };
            EXPECT_NEAR((s.point - P(L, z)).norm(), 0.0, 1e-12);
            const Eigen::Vector3d fd_L = (P(L + h, z) - P(L - h, z)) / (2 * h);
            const Eigen::Vector3d fd_z = (P(L, z + h) - P(L, z - h)) / (2 * h);
            EXPECT_NEAR((s.d_dL - fd_L).norm(), 0.0, 1e-8);
            EXPECT_NEAR((s.d_dz - fd_z).norm(), 0.0, 1e-8);
            const Eigen::Vector3d fd_LL =
                (flank.evaluate(L + h, z).d_dL - flank.evaluate(L - h, z).d_dL) / (2 * h);
            const Eigen::Vector3d fd_Lz =
                (flank.evaluate(L, z + h).d_dL - flank.evaluate(L, z - h).d_dL) / (2 * h);
            const Eigen::Vector3d fd_zL =
                (flank.evaluate(L + h, z).d_dz - flank.evaluate(L - h, z).d_dz) / (2 * h);
            const Eigen::Vector3d fd_zz =
                (flank.evaluate(L, z + h).d_dz - flank.evaluate(L, z - h).d_dz) / (2 * h);
            const double tol = e ? 2e-6 : 1e-7;
            EXPECT_NEAR((s.d2_dL2 - fd_LL).norm(), 0.0, tol);
            EXPECT_NEAR((s.d2_dLdz - fd_Lz).norm(), 0.0, tol);
            EXPECT_NEAR((s.d2_dLdz - fd_zL).norm(), 0.0, tol);
            EXPECT_NEAR((s.d2_dz2 - fd_zz).norm(), 0.0, tol);
            // The nominal normal is the gear's, unit and perpendicular to the nominal partials.
            const FlankPoint fp = gear.flank_point(7, side, L, z);
            EXPECT_NEAR((s.nominal_normal - fp.normal).norm(), 0.0, 1e-15);
            const FlankSurfacePoint n0 = nominal.evaluate(L, z);
            EXPECT_NEAR((n0.point - fp.point).norm(), 0.0, 1e-12);
            EXPECT_NEAR(n0.d_dL.dot(fp.normal), 0.0, 1e-13);
            EXPECT_NEAR(n0.d_dz.dot(fp.normal), 0.0, 1e-13);
            EXPECT_NEAR((n0.real_normal() - fp.normal).norm(), 0.0, 1e-13);
            // The deviation is transverse: S - P - eps is along the transverse normal n_t, of
            // length delta (µm).
            const Eigen::Vector3d shift = s.point - fp.point - Eigen::Vector3d(0.01, -0.02, 0.0);
            EXPECT_NEAR(shift.z(), 0.0, 1e-15);
            const Eigen::Vector3d n_t =
                Eigen::Vector3d(fp.normal.x(), fp.normal.y(), 0).normalized();
            EXPECT_NEAR((shift - shift.dot(n_t) * n_t).norm(), 0.0, 1e-13);
            EXPECT_NEAR(1e3 * shift.dot(n_t), s.deviation_um, 1e-9);
          }
        }
      }
    }
  }
}

TEST(AnalyticFlank, OffsetAndEccentricityKeepNormalsSlopeTiltsThem) {
  const InvoluteGear gear = p1_gear();
  FlankDeviation offset;
  offset.offset_um = 40.0;
  const AnalyticFlank shifted(gear, 2, FlankSide::kRight, offset, {0.02, 0.03});
  for (double L = 22.0; L < 45.0; L += 4.0) {
    const FlankSurfacePoint s = shifted.evaluate(L, 30.0);
    EXPECT_NEAR((s.real_normal() - s.nominal_normal).norm(), 0.0, 1e-13);
    // The point moved by exactly 40 µm along n plus the eccentricity.
    const Eigen::Vector3d nominal = gear.flank_point(2, FlankSide::kRight, L, 30.0).point;
    EXPECT_NEAR(
        (s.point - nominal - 0.04 * s.nominal_normal - Eigen::Vector3d(0.02, 0.03, 0)).norm(), 0.0,
        1e-13);
  }
  // A helix slope k (µm/mm) tilts the normal about the profile tangent by atan(k 1e-3).
  FlankDeviation slope;
  slope.helix_slope_um_per_mm = 0.5;
  const AnalyticFlank tilted(gear, 2, FlankSide::kLeft, slope, {0, 0});
  const FlankSurfacePoint s = tilted.evaluate(30.0, 10.0);
  const double angle = std::acos(s.real_normal().dot(s.nominal_normal));
  EXPECT_NEAR(angle, std::atan(0.5e-3), 1e-12);
}

}  // namespace
}  // namespace gearmc
