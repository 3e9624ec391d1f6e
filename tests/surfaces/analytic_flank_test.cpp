// The real flank surface S(L, z): its analytic partial derivatives against finite differences,
// and its normal against the geometric facts (offsets and eccentricity keep the nominal
// normal at corresponding points; a slope tilts it by atan(slope)).
#include "surfaces/analytic_flank.h"
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
