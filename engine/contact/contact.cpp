// Stylus–flank contact by safeguarded Newton maximisation of the contact height (contact.h).
// Gradient and Hessian of f = w.n + q, q = sqrt(R^2 - |w_perp|^2):
//   f_u  = S_u.n - (w_perp.S_u) / q
//   f_uv = S_uv.n - (S_v_perp.S_u + w_perp.S_uv) / q - (w_perp.S_u)(w_perp.S_v) / q^3
#include "engine/contact/contact.h"

#include "engine/contact/contact_certificate.h"
#include "surfaces/flank_frame.h"

#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <type_traits>

namespace gearmc {
namespace {

constexpr double kHuge = 1e300;
constexpr double kStepTolerance = 1e-10;  // mm in (L, z): C to far below a nanometre
constexpr int kMaxIterations = 60;
constexpr double kNewtonRegion = 1e-4;  // mm: steps this small skip the line search
constexpr double kFinishStep = 1e-5;    // mm: a Newton step this small is the last one

struct Local {
  double f;
  Eigen::Vector2d gradient;
  Eigen::Matrix2d hessian;
  bool reachable;
  Eigen::Vector3d point;  // S(L, z), mm
};

// Where one solve's evaluations take the base point's angle from: its value at the start's
// roll length, turned by the small angle to each new L (base_angle_near, gears/base_angle.h),
// so a solve calls sincos once.
// A helical flank's angle also turns with z (helix_turn_per_mm): the anchor keeps its z.
struct AngleAnchor {
  double L;
  BaseAngle angle;
  double per_mm;        // base_angle_per_mm: one division per solve
  double z = 0.0;       // helical: the anchor's z (mm)
  double per_mm_z = 0;  // helical: helix_turn_per_mm (rad/mm)
  BaseAngle at(const AnalyticFlank& flank, double L_new) const {
    return base_angle_near(flank.gear(), flank.tooth(), flank.side(), angle, L, per_mm, L_new);
  }
  BaseAngle at(const AnalyticFlank& flank, double L_new, double z_new) const {
    const double d = (L_new - L) * per_mm + (z_new - z) * per_mm_z;
    if (!(std::abs(d) <= 1.0 / 32.0)) {
      return base_angle(flank.gear(), flank.tooth(), flank.side(), L_new, z_new);
    }
    return turn_small(angle, d);
  }
};

// The sphere's part of the local model at the frame point s, shared by both kinds of flank:
// fills m's point, reachability and f = w.n + q; the scalar products of the frame's t, m, e_z
// with n and with w_perp, and 1/q (inline: the same operations as written out in place).
struct SphereTerms {
  double tn, mn, tw, mw, zn, zw, inv_q;
};
inline SphereTerms sphere_terms(const FlankFramePoint& s, const Eigen::Vector3d& p,
                                const Eigen::Vector3d& n, double R, Local* m) {
  const Eigen::Vector3d w = s.point - p;
  const double wn = w.dot(n);
  const Eigen::Vector3d w_perp = w - wn * n;
  const double q2 = R * R - w_perp.squaredNorm();
  m->point = s.point;
  if (q2 <= 0.0) {
    m->reachable = false;
    m->f = -std::numeric_limits<double>::infinity();
    return {};
  }
  m->reachable = true;
  const double q = std::sqrt(q2);
  m->f = wn + q;
  return {s.t.x() * n.x() + s.t.y() * n.y(),
          s.m.x() * n.x() + s.m.y() * n.y(),
          s.t.x() * w_perp.x() + s.t.y() * w_perp.y(),
          s.m.x() * w_perp.x() + s.m.y() * w_perp.y(),
          n.z(),
          w_perp.z(),
          1.0 / q};
}

// The local model of f at (L, z) from S's partials in the flank's frame (t, m, e_z;
// analytic_flank.h): every scalar product below is one of S_a.n, w_perp.S_a, S_a.S_b, written
// with t.n, m.n, e_z.n and t.w_perp, m.w_perp, e_z.w_perp (t, m, e_z orthonormal, so e.g.
// S_L.S_z = delta_L delta_z and |S_L|^2 = a^2 + delta_L^2).
Local local_model(const AnalyticFlank& flank, const Eigen::Vector3d& p, const Eigen::Vector3d& n,
                  double R, double L, double z, const AngleAnchor& anchor,
                  FlankFramePoint* keep = nullptr) {
  const FlankFramePoint s = evaluate_frame(flank, L, z, anchor.at(flank, L));
  if (keep) *keep = s;
  Local m{};
  const SphereTerms k = sphere_terms(s, p, n, R, &m);
  if (!m.reachable) return m;
  const double tn = k.tn, mn = k.mn, tw = k.tw, mw = k.mw, zn = k.zn, zw = k.zw, inv_q = k.inv_q;
  // First derivatives: S_a.n, w_perp.S_a (a = L, z); the Hessian is symmetric, and
  // S_b_perp.S_a = S_a.S_b - (S_a.n)(S_b.n).
  const double nL = s.a * tn + s.d_L * mn, nz = zn + s.d_z * mn;
  const double wL = s.a * tw + s.d_L * mw, wz = zw + s.d_z * mw;
  m.gradient[0] = nL - wL * inv_q;
  m.gradient[1] = nz - wz * inv_q;
  const double inv_q3 = inv_q * inv_q * inv_q;
  const double hLL = (s.b * tn + s.c * mn) -
                     (s.a * s.a + s.d_L * s.d_L - nL * nL + (s.b * tw + s.c * mw)) * inv_q -
                     wL * wL * inv_q3;
  const double hLz = (s.d_z_over_rb * tn + s.d_Lz * mn) -
                     (s.d_L * s.d_z - nL * nz + (s.d_z_over_rb * tw + s.d_Lz * mw)) * inv_q -
                     wL * wz * inv_q3;
  const double hzz =
      s.d_zz * mn - (1.0 + s.d_z * s.d_z - nz * nz + s.d_zz * mw) * inv_q - wz * wz * inv_q3;
  m.hessian << hLL, hLz, hLz, hzz;
  return m;
}

// The same on a helical flank: S_z, S_Lz and S_zz gain transverse components (flank_frame.h),
// so S_L.S_z = a z_t + delta_L z_m and |S_z|^2 = 1 + z_t^2 + z_m^2.
Local local_model_helical(const AnalyticFlank& flank, const Eigen::Vector3d& p,
                          const Eigen::Vector3d& n, double R, double L, double z,
                          const AngleAnchor& anchor, HelicalFramePoint* keep = nullptr) {
  const HelicalFramePoint h = evaluate_helical_frame(flank, L, z, anchor.at(flank, L, z));
  const FlankFramePoint& s = h.f;
  if (keep) *keep = h;
  Local m{};
  const SphereTerms k = sphere_terms(s, p, n, R, &m);
  if (!m.reachable) return m;
  const double tn = k.tn, mn = k.mn, tw = k.tw, mw = k.mw, zn = k.zn, zw = k.zw, inv_q = k.inv_q;
  const double nL = s.a * tn + s.d_L * mn, nz = zn + h.z_t * tn + h.z_m * mn;
  const double wL = s.a * tw + s.d_L * mw, wz = zw + h.z_t * tw + h.z_m * mw;
  m.gradient[0] = nL - wL * inv_q;
  m.gradient[1] = nz - wz * inv_q;
  const double inv_q3 = inv_q * inv_q * inv_q;
  const double LL = s.a * s.a + s.d_L * s.d_L, Lz = s.a * h.z_t + s.d_L * h.z_m,
               zz = 1.0 + h.z_t * h.z_t + h.z_m * h.z_m;
  const double hLL =
      (s.b * tn + s.c * mn) - (LL - nL * nL + (s.b * tw + s.c * mw)) * inv_q - wL * wL * inv_q3;
  const double hLz = (h.lz_t * tn + h.lz_m * mn) -
                     (Lz - nL * nz + (h.lz_t * tw + h.lz_m * mw)) * inv_q - wL * wz * inv_q3;
  const double hzz = (h.zz_t * tn + h.zz_m * mn) -
                     (zz - nz * nz + (h.zz_t * tw + h.zz_m * mw)) * inv_q - wz * wz * inv_q3;
  m.hessian << hLL, hLz, hLz, hzz;
  return m;
}

// The model of either kind of flank.
template <bool kHelical>
Local model_at(const AnalyticFlank& flank, const Eigen::Vector3d& p, const Eigen::Vector3d& n,
               double R, double L, double z, const AngleAnchor& anchor) {
  if constexpr (kHelical) {
    return local_model_helical(flank, p, n, R, L, z, anchor);
  } else {
    return local_model(flank, p, n, R, L, z, anchor);
  }
}

// The base point's angle at (L, z) from the anchor, of either kind of flank.
template <bool kHelical>
BaseAngle angle_at(const AnalyticFlank& flank, const AngleAnchor& anchor, double L, double z) {
  if constexpr (kHelical) {
    return anchor.at(flank, L, z);
  } else {
    return anchor.at(flank, L);
  }
}

// f at (L, z) and the flank point S(L, z) there (mm), the base point's angle given.
double height_at(const AnalyticFlank& flank, const Eigen::Vector3d& p, const Eigen::Vector3d& n,
                 double R, double L, double z, const BaseAngle& angle, Eigen::Vector3d* point) {
  *point = surface_point_at(flank, L, z, angle);
  const Eigen::Vector3d w = *point - p;
  const double q2 = R * R - (w - w.dot(n) * n).squaredNorm();
  return q2 <= 0.0 ? -std::numeric_limits<double>::infinity() : w.dot(n) + std::sqrt(q2);
}

}  // namespace

double contact_height(const AnalyticFlank& flank, const Eigen::Vector3d& p,
                      const Eigen::Vector3d& n, double R, double L, double z) {
  Eigen::Vector3d point;
  const BaseAngle angle = flank.gear().helical()
                              ? base_angle(flank.gear(), flank.tooth(), flank.side(), L, z)
                              : base_angle(flank.gear(), flank.tooth(), flank.side(), L);
  return height_at(flank, p, n, R, L, z, angle, &point);
}

namespace {

// One local maximisation from x: the nearest local maximum of f (or the edge, or a failure).
struct LocalSolution {
  ContactResult::Status status;
  Eigen::Vector2d x;
  double height;          // f(x), mm (kOk)
  double gradient_bound;  // >= |grad f(x)| (kOk)
  int iterations;
  Eigen::Vector3d point;  // S(x), mm (kOk)
};

template <bool kHelical>
using FrameOf = std::conditional_t<kHelical, HelicalFramePoint, FlankFramePoint>;

template <bool kHelical>
LocalSolution local_solve(const AnalyticFlank& flank, const FlankExtent& extent,
                          const Eigen::Vector3d& p, const Eigen::Vector3d& n, double R,
                          Eigen::Vector2d x, const AngleAnchor& anchor,
                          FrameOf<kHelical>* start = nullptr) {
  Local m;
  if constexpr (kHelical) {
    m = local_model_helical(flank, p, n, R, x[0], x[1], anchor, start);
  } else {
    m = local_model(flank, p, n, R, x[0], x[1], anchor, start);
  }
  bool converged = false, at_edge = false;
  double final_height = 0.0, gradient_bound = 0.0;
  Eigen::Vector3d final_point = Eigen::Vector3d::Zero();
  int it = 0;
  for (; it < kMaxIterations && m.reachable; ++it) {
    // Newton step for the maximum; where the Hessian is not negative definite, shift it
    // (Levenberg) so the step still goes uphill.
    Eigen::Matrix2d H = m.hessian;
    const double trace = H.trace();
    double det = H.determinant();
    const bool shifted = !(trace < 0.0 && det > 0.0);
    if (shifted) {
      const double largest = 0.5 * trace + std::sqrt(std::max(0.0, 0.25 * trace * trace - det));
      H -= (largest + 1.0 / R) * Eigen::Matrix2d::Identity();
      det = H.determinant();
    }
    // -H^-1 g of the symmetric 2 x 2 H by its adjugate: one division.
    const double inverse_det = 1.0 / det;
    Eigen::Vector2d step((H(0, 1) * m.gradient[1] - H(1, 1) * m.gradient[0]) * inverse_det,
                         (H(1, 0) * m.gradient[0] - H(0, 0) * m.gradient[1]) * inverse_det);
    // Backtracking: never accept a large step that lowers f (or leaves the sphere's reach).
    // Near the maximum f changes by ~|step|^2 / R, below its rounding error once the step is
    // under ~1e-6 mm, so there the pure Newton step (quadratic convergence) is taken.
    const double step2 = step.squaredNorm();  // compared squared: no square root in the chain
    const bool newton_region = !shifted && step2 < kNewtonRegion * kNewtonRegion;
    if (newton_region && step2 < kFinishStep * kFinishStep) {
      // Quadratic convergence: the error after this step is ~(3/2) |step|^2 / R (f''' / 2f''
      // with f'' ~ 1/R, f''' ~ 3/R^2): below 1e-9 mm = 0.001 nm for any stylus of R >= 0.15 mm,
      // so the step is taken and only the point (not the derivatives) is evaluated there. The
      // gradient there is the Newton remainder, at most (1/2) max|f'''| |step|^2; f''' of a
      // sphere on a flank is of order 3 / R^2, taken here as 1e3 / R^2 (the resulting
      // certificate term, ~1e-17 mm, is nine orders below its tolerance).
      x += step;
      final_height = height_at(flank, p, n, R, x[0], x[1],
                               angle_at<kHelical>(flank, anchor, x[0], x[1]), &final_point);
      at_edge = x[0] < extent.roll_length_min || x[0] > extent.roll_length_max ||
                x[1] < extent.z_min || x[1] > extent.z_max;
      converged = std::isfinite(final_height);
      gradient_bound = 0.5 * (1e3 / (R * R)) * step.squaredNorm() + 1e-15 * m.gradient.norm();
      ++it;
      break;
    }
    Local trial;
    for (int halvings = 0;; ++halvings) {
      trial = model_at<kHelical>(flank, p, n, R, x[0] + step[0], x[1] + step[1], anchor);
      if (trial.reachable && (newton_region || trial.f >= m.f)) break;
      if (halvings == 40) break;
      step *= 0.5;
    }
    if (!trial.reachable) break;
    x += step;
    m = trial;
    if (x[0] < extent.roll_length_min || x[0] > extent.roll_length_max || x[1] < extent.z_min ||
        x[1] > extent.z_max) {
      at_edge = true;
      break;
    }
    if (step.squaredNorm() < kStepTolerance * kStepTolerance) {
      converged = true;
      final_height = m.f;
      final_point = m.point;
      gradient_bound = m.gradient.norm();
      ++it;
      break;
    }
  }
  return {at_edge     ? ContactResult::Status::kEdge
          : converged ? ContactResult::Status::kOk
                      : ContactResult::Status::kNotConverged,
          x,
          final_height,
          gradient_bound,
          it,
          final_point};
}

// What the certificate checks p and n against: S(L0, z0), the nominal normal there and the
// deviation (contact_certificate.h).
ContactStart start_of(const FlankFramePoint& f, const AnalyticFlank&) {
  return ContactStart(f.point, Eigen::Vector3d(f.m.x(), f.m.y(), 0.0), f.deviation_um);
}

template <bool kHelical>
ContactResult solve(const AnalyticFlank& flank, const FlankExtent& extent, const Eigen::Vector3d& p,
                    const Eigen::Vector3d& n, double R, double L0, double z0,
                    const BaseAngle& angle_at_L0, const FlankCurvatureBound* flank_bound);

}  // namespace

ContactResult solve_contact(const AnalyticFlank& flank, const FlankExtent& extent,
                            const Eigen::Vector3d& p, const Eigen::Vector3d& n, double R, double L0,
                            double z0) {
  if (flank.gear().helical()) {
    return solve_contact(flank, extent, p, n, R, L0, z0,
                         base_angle(flank.gear(), flank.tooth(), flank.side(), L0, z0));
  }
  return solve_contact(flank, extent, p, n, R, L0, z0,
                       base_angle(flank.gear(), flank.tooth(), flank.side(), L0));
}

ContactResult solve_contact(const AnalyticFlank& flank, const FlankExtent& extent,
                            const Eigen::Vector3d& p, const Eigen::Vector3d& n, double R, double L0,
                            double z0, const BaseAngle& angle_at_L0,
                            const FlankCurvatureBound* flank_bound) {
  return flank.gear().helical()
             ? solve<true>(flank, extent, p, n, R, L0, z0, angle_at_L0, flank_bound)
             : solve<false>(flank, extent, p, n, R, L0, z0, angle_at_L0, flank_bound);
}

namespace {

// The first contact on the ridge of a linear relief: a kink of the flank at its start c, along
// the face at roll length c (tip and root reliefs) or across it at face position c (end reliefs,
// `across_face`). Where the Newton iteration cannot converge (the contact height f has a crease
// there), f is maximised along the ridge (over z at L = c, or over L at z = c) by sampling and
// golden sections (f along the ridge is smooth), and the point is certified like any other: the
// relief removes material beyond c, so the flank's
// graph over the plane normal to n is the smaller of its two smooth branches (each continued
// across c) and its crease is concave; f = min(f1, f2) with both branches' curvature within
// stage 1's bound (the derivative ranges hold both slopes) is then strongly concave, and at the
// ridge point the smallest supergradient is the point of the segment between the two one-sided
// gradients nearest to zero (in u, each side's gradient turned by its own Jacobian); that is the
// gradient certify_contact's concavity bound takes. Returns false when no ridge point is
// reachable or proven.
template <bool kHelical>
bool solve_on_ridge(const AnalyticFlank& flank, const FlankExtent& extent, const Eigen::Vector3d& p,
                    const Eigen::Vector3d& n, double R, double L0, double z0,
                    const Eigen::Vector2d& stop, const ContactStart& start, double c,
                    bool across_face, ContactResult* result) {
  // The ridge's free coordinate u and the range searched: around both the planned point and
  // where the Newton iteration stopped (it oscillates across the crease near the contact).
  double u_lo, u_hi;
  if (!across_face) {  // u = z, |S_z| >= 1: 1.5 R of face either side
    u_lo = std::max(extent.z_min, std::min(z0, stop[1]) - 1.5 * R);
    u_hi = std::min(extent.z_max, std::max(z0, stop[1]) + 1.5 * R);
  } else {  // u = L: the involute's arc length from the base circle is L^2 / (2 r_b), 2 R of it
    const double arc = 2.0 * (2.0 * R) * flank.base_radius();
    const double L_lo = std::min(L0, stop[0]), L_hi = std::max(L0, stop[0]);
    u_lo = std::max(extent.roll_length_min, std::sqrt(std::max(0.0, L_lo * L_lo - arc)));
    u_hi = std::min(extent.roll_length_max, std::sqrt(L_hi * L_hi + arc));
  }
  if (!(u_hi > u_lo)) return false;
  const auto at = [&](double u) {
    return across_face ? Eigen::Vector2d(u, c) : Eigen::Vector2d(c, u);
  };
  const auto height = [&](double u) {
    const Eigen::Vector2d x = at(u);
    return contact_height(flank, p, n, R, x[0], x[1]);
  };
  constexpr int kSamples = 128;
  double best_u = u_lo, best = -std::numeric_limits<double>::infinity();
  for (int k = 0; k <= kSamples; ++k) {
    const double u = u_lo + (u_hi - u_lo) * k / kSamples;
    const double h = height(u);
    if (h > best) best = h, best_u = u;
  }
  if (!std::isfinite(best)) return false;
  // Golden sections on the bracket around the best sample (f along the ridge is smooth and, over
  // the footprint, concave: the sphere's curvature dominates).
  const double step = (u_hi - u_lo) / kSamples;
  double a = std::max(u_lo, best_u - step), b = std::min(u_hi, best_u + step);
  const double g = 0.5 * (std::sqrt(5.0) - 1.0);
  double x1 = b - g * (b - a), x2 = a + g * (b - a), f1 = height(x1), f2 = height(x2);
  while (b - a > 1e-12) {
    if (f1 < f2) {
      a = x1, x1 = x2, f1 = f2, x2 = a + g * (b - a), f2 = height(x2);
    } else {
      b = x2, x2 = x1, f2 = f1, x1 = b - g * (b - a), f1 = height(x1);
    }
  }
  const Eigen::Vector2d x_ridge = at(0.5 * (a + b));
  // The one-sided gradients and their Jacobians J = d(u)/d(L, z), u = (w.tau, w.e2).
  const Eigen::Vector3d tau = Eigen::Vector3d::UnitZ().cross(n).normalized();
  const Eigen::Vector3d e2 = n.cross(tau);
  Eigen::Vector2d g_u[2];
  double j_norm = 0.0;
  // One ulp on either side of c: one is the relief's branch (x > 0), the other the inner one.
  const double sides[2] = {std::nextafter(c, -kHuge), std::nextafter(c, kHuge)};
  for (int s = 0; s < 2; ++s) {
    Eigen::Vector2d x = x_ridge;
    x[across_face ? 1 : 0] = sides[s];
    const double L = x[0], z = x[1];
    const FlankSurfacePoint fp = flank.evaluate(L, z);
    const AngleAnchor anchor{L,
                             kHelical ? base_angle(flank.gear(), flank.tooth(), flank.side(), L, z)
                                      : base_angle(flank.gear(), flank.tooth(), flank.side(), L),
                             base_angle_per_mm(flank.gear(), flank.side()), z,
                             kHelical ? flank.gear().helix_turn_per_mm() : 0.0};
    const Local m = model_at<kHelical>(flank, p, n, R, L, z, anchor);
    if (!m.reachable) return false;
    Eigen::Matrix2d J;
    J << fp.d_dL.dot(tau), fp.d_dz.dot(tau), fp.d_dL.dot(e2), fp.d_dz.dot(e2);
    g_u[s] = J.transpose().inverse() * m.gradient;
    j_norm = std::max(j_norm, J.norm());
  }
  // The point of the segment [g_u0, g_u1] nearest to zero.
  const Eigen::Vector2d d = g_u[1] - g_u[0];
  const double lambda =
      d.squaredNorm() > 0.0 ? std::clamp(-g_u[0].dot(d) / d.squaredNorm(), 0.0, 1.0) : 0.0;
  const double g_min = (g_u[0] + lambda * d).norm();
  // certify_contact multiplies the gradient it is given by its bound of |J^-1| >= 1 / |J|.
  const double t_star = height(across_face ? x_ridge[0] : x_ridge[1]);
  const ContactCertificate cert =
      certify_contact(flank, p, n, R, L0, start, x_ridge, t_star, g_min * j_norm,
                      extent.roll_length_min, extent.roll_length_max);
  if (cert.verdict != ContactCertificate::Verdict::kCertified) return false;
  result->status = ContactResult::Status::kOk;
  result->failure = ContactFailure::kNone;
  result->roll_length_mm = x_ridge[0];
  result->z_mm = x_ridge[1];
  result->contact = flank.point(x_ridge[0], x_ridge[1]);
  result->centre = p + t_star * n;
  result->reported = result->centre - R * n;
  result->delta_um = 1e3 * (result->contact - result->reported).norm();
  result->normal_error_um = 1e3 * (result->reported - result->contact).dot(n);
  return true;
}

template <bool kHelical>
ContactResult solve(const AnalyticFlank& flank, const FlankExtent& extent, const Eigen::Vector3d& p,
                    const Eigen::Vector3d& n, double R, double L0, double z0,
                    const BaseAngle& angle_at_L0, const FlankCurvatureBound* flank_bound) {
  ContactResult result;
  AngleAnchor anchor{L0, angle_at_L0, base_angle_per_mm(flank.gear(), flank.side())};
  if constexpr (kHelical) {
    anchor.z = z0;
    anchor.per_mm_z = flank.gear().helix_turn_per_mm();
  }
  FlankFramePoint start_frame;  // spur: S(L0, z0), the certificate checks p and n against it
  ContactStart start(Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(), 0.0);
  LocalSolution s;
  if constexpr (kHelical) {
    // On a helicoid the probing normal n is not the transverse n_t along which the deviation
    // and the eccentricity move the flank, so the contact lies |w_perp| (w = S(L0, z0) - p)
    // from S(L0, z0) in the tangent plane: ~ delta0 sin(beta_b) along the generator, 15 µm for
    // P1's 60 µm. Newton from (L0, z0) then needs a third iteration; the foot of p's line on the
    // tangent plane at S(L0, z0) is within the spur start's distance (the normal's turn over R):
    // start there, one step of S_a.dx = -w_perp by the 2 x 2 normal equations.
    // S(L0, z0) from the deviation's value alone (the certificate's start), the tangents of
    // the flank there to first order in the deviation (its slopes move the foot by |w_perp|
    // times them: nanometres).
    const FlankPoint nominal = flank_point_at(flank.gear(), flank.side(), L0, z0, angle_at_L0);
    double d = flank.deviation().normal_um(L0, z0);
    if (const DesignModification* modification = flank.modification()) {
      d += modification->value_um(L0, z0);
    }
    if (const NormalExpression* expression = flank.expression()) {
      d += expression->value_um(L0, z0, flank.tooth(), side_sign(flank.side()));
    }
    const Eigen::Vector3d S0 = nominal.point + 1e-3 * d * nominal.normal + flank.eccentricity();
    const double c = flank.cos_base_helix();
    start = ContactStart(
        S0, Eigen::Vector3d(c * nominal.normal.x(), c * nominal.normal.y(), flank.normal_z()), d);
    const Eigen::Vector3d w = S0 - p;
    const Eigen::Vector3d w_perp = w - w.dot(n) * n;
    const Eigen::Vector3d& t = nominal.profile_tangent;
    const Eigen::Vector3d& m = nominal.normal;
    const double tw = t.x() * w_perp.x() + t.y() * w_perp.y();
    const double mw = m.x() * w_perp.x() + m.y() * w_perp.y();
    const double g_rb = flank.frame_turn_per_mm() * flank.base_radius();
    const double sigma = flank.roll_sign();
    const double a = (L0 + sigma * (1e-3 * d)) * flank.inverse_base_radius();
    const double z_t = -(sigma * g_rb) * a, z_m = g_rb;
    const double gL = a * tw, gz = w_perp.z() + z_t * tw + z_m * mw;
    const double GLL = a * a, GLz = a * z_t, Gzz = 1.0 + z_t * z_t + z_m * z_m;
    const double inverse_det = 1.0 / (GLL * Gzz - GLz * GLz);
    Eigen::Vector2d x((GLz * gz - Gzz * gL) * inverse_det, (GLz * gL - GLL * gz) * inverse_det);
    x += Eigen::Vector2d(L0, z0);
    if (!(x - Eigen::Vector2d(L0, z0)).allFinite() ||
        (x - Eigen::Vector2d(L0, z0)).squaredNorm() > R * R) {
      x = Eigen::Vector2d(L0, z0);
    }
    s = local_solve<kHelical>(flank, extent, p, n, R, x, anchor);
  } else {
    s = local_solve<kHelical>(flank, extent, p, n, R, Eigen::Vector2d(L0, z0), anchor,
                              &start_frame);
    start = start_of(start_frame, flank);
  }
  result.iterations = s.iterations;
  // The certificate (contact_certificate.h): restart from a higher point until none is left.
  // The flank's stage-1 bound first, inline (certify_contact would try it first as well).
  while (s.status == ContactResult::Status::kOk) {
    if (flank_bound != nullptr &&
        flank_bound->proves(flank, p, n, R, L0, start, s.gradient_bound, extent.roll_length_min,
                            extent.roll_length_max)) {
      break;
    }
    const ContactCertificate c =
        certify_contact(flank, p, n, R, L0, start, s.x, s.height, s.gradient_bound,
                        extent.roll_length_min, extent.roll_length_max);
    if (c.verdict == ContactCertificate::Verdict::kCertified) break;
    if (c.verdict == ContactCertificate::Verdict::kUnproven) {
      s.status = ContactResult::Status::kUncertified;
      result.failure = c.reason;
      break;
    }
    if (result.restarts == kMaxCertificateRestarts) {
      s.status = ContactResult::Status::kUncertified;
      result.failure = ContactFailure::kRestartCap;
      break;
    }
    ++result.restarts;
    s = local_solve<kHelical>(flank, extent, p, n, R, c.higher_point, anchor);
    result.iterations += s.iterations;
  }
  result.roll_length_mm = s.x[0];
  result.z_mm = s.x[1];
  result.status = s.status;
  if (result.status != ContactResult::Status::kOk &&
      result.status != ContactResult::Status::kEdge) {
    // A linear relief's ridge near the stopping point: the contact may rest on it.
    if (const DesignModification* modification = flank.modification()) {
      for (const double c : modification->profile_kinks) {
        if (c <= extent.roll_length_min || c >= extent.roll_length_max) continue;
        if (std::abs(c - s.x[0]) > 2.0 * R + 1.0) continue;
        if (solve_on_ridge<kHelical>(flank, extent, p, n, R, L0, z0, s.x, start, c, false,
                                     &result)) {
          return result;
        }
      }
      for (const double c : modification->helix_kinks) {
        if (c <= extent.z_min || c >= extent.z_max) continue;
        if (std::abs(c - s.x[1]) > 2.0 * R + 1.0) continue;
        if (solve_on_ridge<kHelical>(flank, extent, p, n, R, L0, z0, s.x, start, c, true,
                                     &result)) {
          return result;
        }
      }
    }
  }
  if (result.status != ContactResult::Status::kOk) return result;
  result.contact = s.point;  // S(x), evaluated where the solver stopped
  result.centre = p + s.height * n;
  result.reported = result.centre - R * n;
  result.delta_um = 1e3 * (result.contact - result.reported).norm();
  result.normal_error_um = 1e3 * (result.reported - result.contact).dot(n);
  return result;
}

}  // namespace

}  // namespace gearmc
