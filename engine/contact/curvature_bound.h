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

}  // namespace gearmc
