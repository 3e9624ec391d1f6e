// Stylus–flank contact by safeguarded Newton maximisation of the contact height (contact.h).
// Gradient and Hessian of f = w.n + q, q = sqrt(R^2 - |w_perp|^2):
//   f_u  = S_u.n - (w_perp.S_u) / q
//   f_uv = S_uv.n - (S_v_perp.S_u + w_perp.S_uv) / q - (w_perp.S_u)(w_perp.S_v) / q^3
#include "engine/contact/contact.h"

#include "engine/contact/contact_certificate.h"
#include "surfaces/flank_frame.h"

#include <Eigen/LU>
#include <cmath>
#include <limits>
#include <numbers>

namespace gearmc {
namespace {

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
struct AngleAnchor {
  double L;
  BaseAngle angle;
  double per_mm;  // base_angle_per_mm: one division per solve
  BaseAngle at(const AnalyticFlank& flank, double L_new) const {
    return base_angle_near(flank.gear(), flank.tooth(), flank.side(), angle, L, per_mm, L_new);
  }
};

// The local model of f at (L, z) from S's partials in the flank's frame (t, m, e_z;
// analytic_flank.h): every scalar product below is one of S_a.n, w_perp.S_a, S_a.S_b, written
// with t.n, m.n, e_z.n and t.w_perp, m.w_perp, e_z.w_perp (t, m, e_z orthonormal, so e.g.
// S_L.S_z = delta_L delta_z and |S_L|^2 = a^2 + delta_L^2).
Local local_model(const AnalyticFlank& flank, const Eigen::Vector3d& p, const Eigen::Vector3d& n,
                  double R, double L, double z, const AngleAnchor& anchor,
                  FlankFramePoint* keep = nullptr) {
  const FlankFramePoint s = evaluate_frame(flank, L, z, anchor.at(flank, L));
  if (keep) *keep = s;
  const Eigen::Vector3d w = s.point - p;
  const double wn = w.dot(n);
  const Eigen::Vector3d w_perp = w - wn * n;
  const double q2 = R * R - w_perp.squaredNorm();
  Local m{};
  m.point = s.point;
  if (q2 <= 0.0) {
    m.reachable = false;
    m.f = -std::numeric_limits<double>::infinity();
    return m;
  }
  m.reachable = true;
  const double q = std::sqrt(q2);
  const double inv_q = 1.0 / q;
  m.f = wn + q;
  const double tn = s.t.x() * n.x() + s.t.y() * n.y(), mn = s.m.x() * n.x() + s.m.y() * n.y();
  const double tw = s.t.x() * w_perp.x() + s.t.y() * w_perp.y();
  const double mw = s.m.x() * w_perp.x() + s.m.y() * w_perp.y();
  const double zn = n.z(), zw = w_perp.z();
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
  return height_at(flank, p, n, R, L, z, base_angle(flank.gear(), flank.tooth(), flank.side(), L),
                   &point);
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

LocalSolution local_solve(const AnalyticFlank& flank, const FlankExtent& extent,
                          const Eigen::Vector3d& p, const Eigen::Vector3d& n, double R,
                          Eigen::Vector2d x, const AngleAnchor& anchor,
                          FlankFramePoint* start = nullptr) {
  Local m = local_model(flank, p, n, R, x[0], x[1], anchor, start);
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
      final_height = height_at(flank, p, n, R, x[0], x[1], anchor.at(flank, x[0]), &final_point);
      at_edge = x[0] < extent.roll_length_min || x[0] > extent.roll_length_max ||
                x[1] < extent.z_min || x[1] > extent.z_max;
      converged = std::isfinite(final_height);
      gradient_bound = 0.5 * (1e3 / (R * R)) * step.squaredNorm() + 1e-15 * m.gradient.norm();
      ++it;
      break;
    }
    Local trial;
    for (int halvings = 0;; ++halvings) {
      trial = local_model(flank, p, n, R, x[0] + step[0], x[1] + step[1], anchor);
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

}  // namespace

ContactResult solve_contact(const AnalyticFlank& flank, const FlankExtent& extent,
                            const Eigen::Vector3d& p, const Eigen::Vector3d& n, double R, double L0,
                            double z0) {
  return solve_contact(flank, extent, p, n, R, L0, z0,
                       base_angle(flank.gear(), flank.tooth(), flank.side(), L0));
}

ContactResult solve_contact(const AnalyticFlank& flank, const FlankExtent& extent,
                            const Eigen::Vector3d& p, const Eigen::Vector3d& n, double R, double L0,
                            double z0, const BaseAngle& angle_at_L0,
                            const FlankCurvatureBound* flank_bound) {
  ContactResult result;
  const AngleAnchor anchor{L0, angle_at_L0, base_angle_per_mm(flank.gear(), flank.side())};
  FlankFramePoint start_frame;  // S(L0, z0): the certificate checks p and n against it
  LocalSolution s =
      local_solve(flank, extent, p, n, R, Eigen::Vector2d(L0, z0), anchor, &start_frame);
  const ContactStart start(start_frame.point,
                           Eigen::Vector3d(start_frame.m.x(), start_frame.m.y(), 0.0),
                           start_frame.deviation_um);
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
    s = local_solve(flank, extent, p, n, R, c.higher_point, anchor);
    result.iterations += s.iterations;
  }
  result.roll_length_mm = s.x[0];
  result.z_mm = s.x[1];
  result.status = s.status;
  if (result.status != ContactResult::Status::kOk) return result;
  result.contact = s.point;  // S(x), evaluated where the solver stopped
  result.centre = p + s.height * n;
  result.reported = result.centre - R * n;
  result.delta_um = 1e3 * (result.contact - result.reported).norm();
  result.normal_error_um = 1e3 * (result.reported - result.contact).dot(n);
  return result;
}

namespace {

// Distance (mm) in the transverse plane from point X to the nominal flank `side` of `tooth`,
// limited to the flank's real extent [L_form, L_tip]: closed form r_b (inv(alpha_X) + s phi -
// theta_b) along the normal when the foot lies on the flank, else the distance to the end.
double distance_to_flank(const InvoluteGear& gear, int tooth, FlankSide side,
                         const Eigen::Vector2d& X) {
  const double r_b = 0.5 * gear.base_diameter_mm();
  const double rho = X.norm();
  const double t = std::sqrt(std::max(0.0, rho * rho - r_b * r_b));
  const double alpha_x = std::atan2(t, r_b);
  const double phi = std::remainder(std::atan2(X.y(), X.x()) - gear.tooth_centre_angle_rad(tooth),
                                    2 * std::numbers::pi);
  const double s = side_sign(side);
  const double foot_L = r_b * (gear.base_half_angle_rad() - s * phi + alpha_x);
  const double L_min = gear.form_roll_length_mm(), L_max = gear.tip_roll_length_mm();
  if (foot_L >= L_min && foot_L <= L_max) {
    return std::abs(r_b * (involute_function(alpha_x) + s * phi - gear.base_half_angle_rad()));
  }
  const double L_end = foot_L < L_min ? L_min : L_max;
  return (gear.flank_point(tooth, side, L_end, 0.0).point.head<2>() - X).norm();
}

}  // namespace

ToothSpaceClearance tooth_space_clearance(const InvoluteGear& gear, int tooth, FlankSide side,
                                          const Eigen::Vector3d& centre, const Eigen::Vector3d& n,
                                          double R, double approach_mm) {
  // The facing flank: R of tooth k faces L of tooth k+1; L of tooth k faces R of tooth k-1.
  const int z = gear.teeth();
  const int facing_tooth = side == FlankSide::kRight ? tooth % z + 1 : (tooth + z - 2) % z + 1;
  const FlankSide facing_side = side == FlankSide::kRight ? FlankSide::kLeft : FlankSide::kRight;
  const double r_root = 0.5 * gear.root_diameter_mm();
  // Along the approach the sphere moves away from the facing flank and up from the root; check
  // the path at a few stations (start, middle, end) — enough for a straight approach.
  const Eigen::Vector3d start = centre + approach_mm * n;
  ToothSpaceClearance c{std::numeric_limits<double>::infinity(),
                        std::numeric_limits<double>::infinity()};
  for (double a : {0.0, 0.25, 0.5, 0.75, 1.0}) {
    const Eigen::Vector2d X = (start + a * (centre - start)).head<2>();
    c.facing_flank_mm =
        std::min(c.facing_flank_mm, distance_to_flank(gear, facing_tooth, facing_side, X) - R);
    c.root_mm = std::min(c.root_mm, X.norm() - R - r_root);
  }
  return c;
}

void check_tooth_space(const InvoluteGear& gear, int tooth, FlankSide side,
                       const Eigen::Vector3d& n, double R, double approach_mm,
                       ContactResult* result) {
  if (result->status != ContactResult::Status::kOk) return;
  const ToothSpaceClearance c =
      tooth_space_clearance(gear, tooth, side, result->centre, n, R, approach_mm);
  if (c.facing_flank_mm < 0.0) {
    result->status = ContactResult::Status::kCollision;
    result->collision = CollisionKind::kNeighbourFlank;
  } else if (c.root_mm < 0.0) {
    result->status = ContactResult::Status::kCollision;
    result->collision = CollisionKind::kRoot;
  }
}

}  // namespace gearmc
