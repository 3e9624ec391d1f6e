// Certificate that a stylus contact found by the local Newton iteration (contact.h) is the
// FIRST contact: no point of the flank within the stylus's footprint rises above the found
// sphere by more than kCertificateToleranceMm along n.
//
// Frame: u = (w.tau, w.e_z) in the plane normal to n (n transverse, tau = e_z x n), h = w.n,
// w = S(L, z) - p. Over the footprint disk |u| < R the flank is a graph h = H(u) (u_z = z - p_z
// exactly; u_tau is monotone in L because the involute turns by far less than pi/2 within the
// footprint), and the contact height is F(u) = H(u) + sqrt(R^2 - |u|^2). The lower
// hemisphere's Hessian is >= I / R everywhere on the disk, so where the surface's Hessian
// H_uu <= kappa I with kappa < 1/R, F is strongly concave and, with |grad F(u*)| = g at the
// found point, F(u) <= F(u*) + g^2 / (2 (1/R - kappa)) on the convex set considered.
//
// Two stages:
//  1. Exact, O(1) (B-spline deviation fields, no expression): interval bounds of H_uu over a
//     parameter box that provably contains the footprint, from the exact ranges of the
//     deviation's first and second partials (FlankDeviation::derivative_ranges, computed once
//     per flank) and the closed-form
//     involute terms (H_uu = J^-T M J^-1, M = h_xx - (h_L / u_L) u_xx; the rotation of the
//     involute normal cancels in the cross products). kappa < 1/R proves the whole footprint
//     at once. This is what P1's smooth fields take.
//  2. Sampled (expressions, or a field too wavy for stage 1): the footprint box on a grid of
//     surface points (64 cells across 2R, the same spacing in u along the profile); any node
//     higher than t* + tol is returned as a higher point
//     (the caller restarts Newton there). Otherwise the neighbourhood |u - u*| <= rho is
//     proved by the concavity bound above with kappa from H_uu on its own 9 x 9 grid (rho
//     from 2 cells down to 1/8 cell until it holds), and every other
//     cell by a bilinear bound of psi = h - G.u (G the slope of a tangent plane of the
//     hemisphere, which lies below it: the hemisphere is convex) plus (dL^2/8) max(-psi_LL)
//     + (dz^2/8) max(-psi_zz), the second derivatives estimated by the grid's second
//     differences around the cell; a cell that fails is split 2 x 2 (4 levels).
//     ASSUMPTION (stated, not proved): over a cell, psi'' stays within the range of the second
//     differences at the cell's and its neighbours' nodes widened by that range's width (the
//     Lipschitz estimate, a safety factor of about 2 over a linear variation); H_uu likewise
//     on the neighbourhood's own grid. A feature narrower than the sample spacing (2R/64 =
//     16 µm for R = 0.5 mm) can escape it. Expression fields are evaluated with five-point
//     differences (normal_expression.h).
// Lengths mm.
#pragma once

#include <Eigen/Core>
#include <cmath>
#include <limits>

#include "engine/contact/contact_states.h"
#include "surfaces/analytic_flank.h"

namespace gearmc {

// The certificate proves max f <= t* + this (mm): 1e-2 nm along n.
inline constexpr double kCertificateToleranceMm = 1e-8;

struct ContactCertificate {
  enum class Verdict {
    kCertified,    // proven: f <= t* + tolerance over the footprint
    kHigherPoint,  // a point with f > t* + tolerance: `higher_point`, `higher_height`
    kUnproven,     // neither: `reason`
  };
  Verdict verdict = Verdict::kUnproven;
  // kUnproven: normal not transverse, footprint not bounded, not concave at the contact (the
  // field's curvature at the found contact reaches 1/R: a saddle or a ridge the sphere cannot be
  // proven to rest on), unproven region (a cell's bound still exceeds the tolerance after
  // refinement).
  ContactFailure reason = ContactFailure::kNone;
  Eigen::Vector2d higher_point = Eigen::Vector2d::Zero();  // (L, z), mm
  double higher_height = 0.0;                              // f there, mm
  bool sampled = false;         // stage 2 was needed (stage 1 did not prove it)
  bool by_flank_bound = false;  // proven by the flank's stage-1 bound (FlankCurvatureBound)
};

// What stage 1 needs of the flank at the planned point (L0, p_z): S there, the nominal normal
// n(L0) and the deviation there. A FlankSurfacePoint converts to it.
struct ContactStart {
  Eigen::Vector3d point;           // S(L0, p_z), mm
  Eigen::Vector3d nominal_normal;  // n(L0), unit
  double deviation_um;             // delta(L0, p_z), µm
  ContactStart(const Eigen::Vector3d& point_mm, const Eigen::Vector3d& normal, double deviation)
      : point(point_mm), nominal_normal(normal), deviation_um(deviation) {}
  ContactStart(const FlankSurfacePoint& s)  // NOLINT: implicit on purpose
      : ContactStart(s.point, s.nominal_normal, s.deviation_um) {}
};

// Whether stage 1's closed form applies at the planned point: no expression field, p = P(L0,
// p_z) + 0 on the nominal flank and n = n(L0), transverse; `start` = S(L0, p_z) = P + delta
// n(L0) + eps.
inline bool nominal_start(const AnalyticFlank& flank, const Eigen::Vector3d& p,
                          const Eigen::Vector3d& n, double L0, const ContactStart& start) {
  const double delta0 = 1e-3 * start.deviation_um;
  return flank.expression() == nullptr && (start.nominal_normal - n).squaredNorm() <= 1e-24 &&
         std::abs(n.z()) <= 1e-12 &&
         (start.point - delta0 * n - flank.eccentricity() - p).squaredNorm() <= 1e-18 && L0 > 0.0;
}

// The same on a helical flank: p = P(L0, p_z) on the nominal helicoid, n its normal there,
// `start` = S(L0, p_z) = P + delta m0 + eps with m0 = n_xy / cos(beta_b) the transverse normal
// (curvature_bound.cpp). Inline and without the division (every run's contact asks it): with
// c = cos(beta_b), c (start - delta m0 - eps - p) = c (start - eps - p) - delta n_xy and
// |m0|^2 - 1 = (|n_xy|^2 - c^2) / c^2, each compared with its tolerance times c^2.
inline bool nominal_helical_start(const AnalyticFlank& flank, const Eigen::Vector3d& p,
                                  const Eigen::Vector3d& n, double L0, const ContactStart& start) {
  if (flank.expression() != nullptr || !(L0 > 0.0) || !flank.gear().helical()) return false;
  const double c = flank.cos_base_helix(), c2 = c * c;
  const double delta0 = 1e-3 * start.deviation_um;
  const Eigen::Vector3d off = start.point - flank.eccentricity() - p;
  const double ex = c * off.x() - delta0 * n.x(), ey = c * off.y() - delta0 * n.y(),
               ez = c * off.z();
  const double n_xy2 = n.x() * n.x() + n.y() * n.y();
  return (start.nominal_normal - n).squaredNorm() <= 1e-24 &&
         ex * ex + ey * ey + ez * ez <= 1e-18 * c2 && std::abs(n_xy2 - c2) <= 1e-9 * c2;
}

// The concavity bound (above): with H_uu <= kappa I over the footprint and |grad f| <=
// gradient_bound at the found point, F <= t* + g^2 / (2 (1/R - kappa)), g = gradient_bound
// |J^-1|; whether that is within the tolerance (compared without a division).
inline bool concavity_proves(double R, double kappa, double inverse_jacobian,
                             double gradient_bound) {
  const double mu = 1.0 / R - kappa;
  const double g = gradient_bound * inverse_jacobian;
  return mu > 0.0 && g * g <= 2.0 * mu * kCertificateToleranceMm;
}

// Stage 1 for all planned points of one flank at once: the run's contacts take one bound per
// flank instead of one per point (of a helical flank: helical_flank_bound, curvature_bound.h,
// with the box's turn, deviation and footprint as helical_exact_bound's). The box of every planned
// point's footprint (exact_bound in the .cpp: L within a half-width K / L0 of L0, cut at the
// flank's extent) lies in L in [L_min, L_max] with a turn of the involute normal of at most K /
// (L_min r_b) and |delta| at most deviation_max_mm + max|delta_L| K / L_min + max|delta_z| R; the
// bound over that box (c_tau taken as |eps|) holds at every point `covers` accepts. Where it does
// not prove a point, the point's own (tighter) bound is tried next, so the verdicts are those
// without it.
struct FlankCurvatureBound {
  const AnalyticFlank* flank = nullptr;      // the flank it was computed for
  double R = 0.0, L_min = 0.0, L_max = 0.0;  // stylus radius and extent, mm
  double deviation_max_mm = 0.0;  // for planned points with |delta(L0, p_z)| up to this, mm
  double kappa = std::numeric_limits<double>::infinity();  // >= largest eigenvalue of H_uu, 1/mm
  double inverse_jacobian = std::numeric_limits<double>::infinity();  // >= |J^-1|
  // The box (finite kappa only): a planned point's footprint lies within |L - L0| <=
  // half_width_mm2 / L0 (mm), where the involute normal turns by at most max_turn_rad from n
  // and |delta| <= max_deviation_mm.
  double half_width_mm2 = 0.0, max_turn_rad = 0.0, max_deviation_mm = 0.0;
  // Whether it holds for a solve on `f` with these R, L0 (mm), delta(L0, p_z) (µm) and extent
  // (and a finite bound was found).
  bool covers(const AnalyticFlank& f, double R_mm, double L0, double deviation_um, double L_min_mm,
              double L_max_mm) const {
    return flank == &f && R == R_mm && L_min == L_min_mm && L_max == L_max_mm && L0 >= L_min &&
           L0 <= L_max && std::abs(1e-3 * deviation_um) <= deviation_max_mm &&
           kappa < std::numeric_limits<double>::infinity();
  }
  // Whether it proves the contact found with |grad f| <= gradient_bound (arguments as
  // certify_contact's): the first thing certify_contact tries, inline for the solver.
  bool proves(const AnalyticFlank& f, const Eigen::Vector3d& p, const Eigen::Vector3d& n,
              double R_mm, double L0, const ContactStart& start, double gradient_bound,
              double L_min_mm, double L_max_mm) const {
    return covers(f, R_mm, L0, start.deviation_um, L_min_mm, L_max_mm) &&
           (f.gear().helical() ? nominal_helical_start(f, p, n, L0, start)
                               : nominal_start(f, p, n, L0, start)) &&
           concavity_proves(R_mm, kappa, inverse_jacobian, gradient_bound);
  }
};
// The bound for `flank` (which must outlive it), stylus radius R and roll-length extent
// [L_min, L_max] (mm); kappa = infinity where it does not apply (expression fields) or no
// half-width of the four tries holds the footprints.
FlankCurvatureBound flank_curvature_bound(const AnalyticFlank& flank, double R, double L_min,
                                          double L_max);

// p, n: planned point and nominal outward unit normal; R: tip radius; L0: the planned roll
// length and `start` = flank.evaluate(L0, p_z) (stage 1 needs p = P(L0, p_z) on the nominal
// flank and n = n(L0); it checks that with `start` and otherwise leaves the point to stage 2);
// x_star = (L*, z*), t_star = f(x_star) the found maximum; gradient_bound >=
// |grad_(L,z) f(x_star)| (mm/mm). [L_min, L_max] is the flank's roll-length extent (form to
// tip circle): the flank exists only there, so only that part of the footprint is searched (a
// contact beyond it is the flank's edge or the root, which the solver and the tooth-space check
// handle); without it, near the start of the involute the footprint reaches L <= 0 and no bound
// exists. `flank_bound` (optional): flank_curvature_bound of this flank, R and extent, tried
// first.
ContactCertificate certify_contact(const AnalyticFlank& flank, const Eigen::Vector3d& p,
                                   const Eigen::Vector3d& n, double R, double L0,
                                   const ContactStart& start, const Eigen::Vector2d& x_star,
                                   double t_star, double gradient_bound, double L_min = 0.0,
                                   double L_max = std::numeric_limits<double>::infinity(),
                                   const FlankCurvatureBound* flank_bound = nullptr);

// Stage 1 alone (exposed for tests): kappa, the proven upper bound of the largest eigenvalue of
// H_uu over the footprint (1/mm), or +infinity where stage 1 does not apply.
double exact_curvature_bound(const AnalyticFlank& flank, const Eigen::Vector3d& p,
                             const Eigen::Vector3d& n, double R, double L0, double z0,
                             double L_min = 0.0,
                             double L_max = std::numeric_limits<double>::infinity());

}  // namespace gearmc
