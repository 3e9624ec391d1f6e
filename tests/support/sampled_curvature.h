// The curvature of a flank sampled by central differences of its points alone, for tests of the
// contact certificate's curvature bounds (tests/engine/contact/flank_curvature_bound_test.cpp,
// helical_contact_test.cpp): independent of the bounds' closed forms.
#pragma once

#include <Eigen/Core>
#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>

#include "surfaces/analytic_flank.h"

namespace gearmc::testing_support {

// The largest eigenvalue of the graph Hessian H_uu at (L, z) (1/mm) over the plane normal to n,
// u = (w.tau, w.e2), tau = e_z x n, e2 = n x tau, h = w.n, w = S - p: H_uu = J^-T (h_xy -
// s.u_xy) J^-1 with J = d(u)/d(L, z), s = J^-T (h_L, h_z), every partial by central differences
// (step 1e-3 mm) of flank.point alone (on a spur flank n is horizontal and e2 = e_z). The rounding
// error of the step: ~1e-14 mm / e^2 = 1e-8 /mm.
inline double fd_curvature(const AnalyticFlank& flank, const Eigen::Vector3d& p,
                           const Eigen::Vector3d& n, double L, double z) {
  const Eigen::Vector3d tau = Eigen::Vector3d::UnitZ().cross(n).normalized();
  const Eigen::Vector3d e2 = n.cross(tau);
  auto uh = [&](double l, double zz) {
    const Eigen::Vector3d w = flank.point(l, zz) - p;
    return Eigen::Vector3d(w.dot(tau), w.dot(e2), w.dot(n));
  };
  const double e = 1e-3;
  const Eigen::Vector3d c = uh(L, z);
  const Eigen::Vector3d Lp = uh(L + e, z), Lm = uh(L - e, z), zp = uh(L, z + e), zm = uh(L, z - e);
  const Eigen::Vector3d pp = uh(L + e, z + e), pm = uh(L + e, z - e), mp = uh(L - e, z + e),
                        mm = uh(L - e, z - e);
  const Eigen::Vector3d dL = (Lp - Lm) / (2 * e), dz = (zp - zm) / (2 * e);
  const Eigen::Vector3d dLL = (Lp - 2 * c + Lm) / (e * e), dzz = (zp - 2 * c + zm) / (e * e);
  const Eigen::Vector3d dLz = (pp - pm - mp + mm) / (4 * e * e);
  Eigen::Matrix2d J;
  J << dL.x(), dz.x(), dL.y(), dz.y();
  const Eigen::Matrix2d Jinv = J.inverse();
  const Eigen::Vector2d slope = Jinv.transpose() * Eigen::Vector2d(dL.z(), dz.z());
  auto M = [&](const Eigen::Vector3d& d2) { return d2.z() - slope.dot(d2.head<2>()); };
  Eigen::Matrix2d m;
  m << M(dLL), M(dLz), M(dLz), M(dzz);
  const Eigen::Matrix2d H = Jinv.transpose() * m * Jinv;
  return Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d>(0.5 * (H + H.transpose()))
      .eigenvalues()
      .maxCoeff();
}

}  // namespace gearmc::testing_support
