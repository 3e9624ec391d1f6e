// Stage 1 of the first-contact certificate (contact_certificate.h), per planned point: the
// exact bound of the flank's curvature over the stylus's footprint, for certify_contact. (The
// per-flank bound, flank_curvature_bound, and the test-facing exact_curvature_bound are declared
// in contact_certificate.h.) Lengths mm.
#pragma once

#include <Eigen/Core>
#include <limits>

#include "engine/contact/contact_certificate.h"

namespace gearmc {

struct ExactBound {
  double kappa = std::numeric_limits<double>::infinity();  // >= largest eigenvalue of H_uu over
                                                           // the footprint, 1/mm
  double inverse_jacobian = std::numeric_limits<double>::infinity();  // >= |J^-1| (Frobenius),
                                                                      // J = d(u)/d(L, z)
};

// The bound at the planned point p (normal n, roll length L0, `start` = S(L0, p_z)) for a
// sphere of radius R on a flank of roll-length extent [L_min, L_max]; infinite where stage 1
// does not apply (an expression field, a start off the nominal flank, no half-width found).
ExactBound exact_bound(const AnalyticFlank& flank, const Eigen::Vector3d& p,
                       const Eigen::Vector3d& n, double R, double L0, const ContactStart& start,
                       double L_min, double L_max);

// The same on a helical flank (involute helicoid): the bound of the surface's principal
// curvature over a box in sheared parameters (L' = L - shear (z - p_z), z) that holds the
// footprint, turned into a bound of H_uu by the normal's tilt from n over the box (the .cpp
// derives it). Infinite where it does not apply.
ExactBound helical_exact_bound(const AnalyticFlank& flank, const Eigen::Vector3d& p,
                               const Eigen::Vector3d& n, double R, double L0,
                               const ContactStart& start, double L_min, double L_max);

// flank_curvature_bound's helical part: fills kappa, inverse_jacobian and the box of `out`
// (whose flank, R, extent and deviation_max_mm are set), or leaves kappa infinite.
void helical_flank_bound(const AnalyticFlank& flank, double R, double L_min, double L_max,
                         FlankCurvatureBound* out);

}  // namespace gearmc
