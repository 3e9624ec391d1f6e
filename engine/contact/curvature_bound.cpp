// Stage 1 of the first-contact certificate (contact_certificate.h): exact interval bounds of the
// flank's curvature over a box of parameters that provably holds the stylus's footprint, per
// planned point and per flank, for B-spline deviation fields. Lengths mm.
#include "engine/contact/curvature_bound.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/constants.h"

namespace gearmc {
namespace {

// A closed interval [lo, hi].
struct Interval {
  double lo, hi;
  double magnitude() const { return std::max(std::abs(lo), std::abs(hi)); }
};

// The parameter box stage 1 bounds H_uu over: L in [L_lo, L_hi] (mm), the involute normal's
// turn from n at most Phi (rad) and |delta| at most D (mm) there.
struct ParameterBox {
  double L_lo, L_hi, Phi, D;
};

// The involute's own term of M_LL's numerator, -sigma a^2 / r_b (a = (L + sigma delta) / r_b),
// bounded above over a in [a_lo, a_hi]: -a_lo^2 / r_b on an external flank (convex: it lowers
// the bound), +a_hi^2 / r_b on an internal one (concave: the sphere's curvature 1/L is what the
// flank takes from the sphere's 1/R).
double involute_term_ub(double sigma, double a_lo, double a_hi, double inv_rb) {
  return sigma > 0.0 ? -a_lo * a_lo * inv_rb : a_hi * a_hi * inv_rb;
}

// The deviation's partials' ranges in mm/mm and 1/mm (FlankDeviation::derivative_ranges, µm).
struct DeviationIntervals {
  Interval dL, dz, dLL, dzz;
  double dL_mag, dz_mag;
  explicit DeviationIntervals(const FlankDeviation::Ranges& rg) {
    auto mm = [](CubicBSpline::Range r) { return Interval{1e-3 * r.lo, 1e-3 * r.hi}; };
    dL = mm(rg.dL), dz = mm(rg.dz), dLL = mm(rg.dLL), dzz = mm(rg.dzz);
    dL_mag = dL.magnitude(), dz_mag = dz.magnitude();
  }
};

// The footprint of the sphere over the planned point at roll length L0 within |L - L0| <= half
// (mm): the L half-width. |u_tau| >= |N(L)| - c_tau - |delta| sin(Phi) with the nominal N(L) =
// (P(L) - P(L0)).t0 = L0 sin phi + r_b (phi sin phi + cos phi - 1), whose modulus grows with
// |phi| (beyond the box it keeps growing: the footprint cannot come back). Trigonometry by
// rigorous Taylor bounds: sin x >= x - x^3/6, x sin x + cos x - 1 <= x^2/2 + x^4/24. On the
// upper side |N| >= L0 sin(Phi) (the r_b term is >= 0 there), on the lower side the full
// expression. c_tau >= |eps.t0|, D >= |delta| over the box. The margins (mm) are what |u_tau|
// exceeds R by at the box's ends, at least; the footprint is inside where both are >= 0.
// Both only grow with L0 at a fixed half * L0 (N_up grows, the r_b term, Phi and D shrink):
// flank_curvature_bound relies on that.
struct FootprintMargins {
  double upper, lower;
};
FootprintMargins footprint_margins(double L0, double half, double R, double r_b, double c_tau,
                                   double D) {
  const double Phi = half * (1.0 / r_b);
  const double N_up = L0 * (Phi - Phi * Phi * Phi / 6.0);
  const double N_down = N_up - r_b * (0.5 * Phi * Phi + Phi * Phi * Phi * Phi / 24.0);
  return {N_up - c_tau - D * Phi - R, N_down - c_tau - D * Phi - R};
}

// The same test with the box cut at the flank's extent [L_min, L_max]: an end that is cut is the
// flank's edge and needs no bound of the footprint there.
bool footprint_within(double L0, double half, double R, double r_b, double c_tau, double D,
                      double L_min, double L_max) {
  const FootprintMargins m = footprint_margins(L0, half, R, r_b, c_tau, D);
  return (L0 - half < L_min || m.lower >= 0.0) && (L0 + half > L_max || m.upper >= 0.0);
}

// Stage 1's bound of H_uu over `box`. With phi the angle of the involute normal n(L) from n
// (phi = (L - L0) / r_b, n(L) = cos phi n + sin phi t0, t0 the profile tangent at L0), a = (L +
// sigma delta) / r_b (sigma the roll sign: +1 external, -1 internal) and the partials of S
// (analytic_flank.cpp):
//   (u_L, h_L) = Rot(a, delta_L),
//   (u_LL, h_LL) = Rot((1 + 2 sigma delta_L) / r_b, delta_LL - sigma a / r_b),
//   (u_Lz, h_Lz) = Rot(sigma delta_z / r_b, delta_Lz),  (u_zz, h_zz) = Rot(0, delta_zz),
//   u_z(tau) = delta_z sin phi, u_z(z) = 1,
// so M_xy = h_xy - (h_L / u_L) u_xy = cross((u_L, h_L), (u_xy, h_xy)) / u_L loses the rotation:
//   M_LL = (a (delta_LL - sigma a / r_b) - delta_L (1 + 2 sigma delta_L) / r_b) / u_L,
//   M_Lz = (a delta_Lz - sigma delta_L delta_z / r_b) / u_L,  M_zz = a delta_zz / u_L,
// and H_uu = J^-T M J^-1 with J = [[u_L, u_z], [0, 1]]. sin phi and cos phi are bounded over the
// box symmetric about L0, so the sign of t0 does not matter; the footprint's margins
// (footprint_margins) hold for either sigma: N(L) = ∫ (l / r_b) cos((l - L0) / r_b) dl does not
// see the direction the involute bends. Every bound below is monotone in the box (wider [L_lo,
// L_hi], larger Phi and D give a larger bound), so a box containing another gives a bound valid
// for both. The sigma terms other than the involute's own (involute_term_ub) enter through
// moduli, bounded alike for both signs.
ExactBound curvature_over_box(const ParameterBox& box, const DeviationIntervals& dv, double r_b,
                              double sigma) {
  ExactBound out;
  const double inv_rb = 1.0 / r_b;  // divisions by r_b and u_L below are multiplications
  const double Phi = box.Phi, D = box.D, dL_mag = dv.dL_mag, dz_mag = dv.dz_mag;
  // Bounds with the signs known (a > 0, u_L > 0, |sin phi| <= Phi, cos phi >= 1 - Phi^2/2):
  // ub = upper bound, mag = bound of the modulus.
  const double a_lo = (box.L_lo - D) * inv_rb, a_hi = (box.L_hi + D) * inv_rb;
  const double uL_lo = a_lo * (1.0 - 0.5 * Phi * Phi) - dL_mag * Phi;
  if (a_lo <= 0.0 || uL_lo <= 0.0) return out;
  const double inv_uL = 1.0 / uL_lo;
  const double slope_term = dL_mag * (1.0 + 2.0 * dL_mag) * inv_rb;
  // M_LL = (a (delta_LL - a / r_b) - delta_L (1 + 2 delta_L) / r_b) / u_L
  const double num_LL_ub =
      a_hi * std::max(dv.dLL.hi, 0.0) + involute_term_ub(sigma, a_lo, a_hi, inv_rb) + slope_term;
  const double M_LL_ub = num_LL_ub >= 0.0 ? num_LL_ub * inv_uL : num_LL_ub / (a_hi + dL_mag * Phi);
  const double M_LL_mag = (a_hi * dv.dLL.magnitude() + a_hi * a_hi * inv_rb + slope_term) * inv_uL;
  const double M_Lz_mag = dL_mag * dz_mag * inv_rb * inv_uL;        // delta_Lz = 0
  const double M_zz_ub = a_hi * std::max(dv.dzz.hi, 0.0) * inv_uL;  // a delta_zz / u_L
  const double r_mag = dz_mag * Phi * inv_uL;                       // |u_z(tau) / u_L|
  // H_tt = M_LL / u_L^2, H_tz = (M_Lz - r M_LL) / u_L, H_zz = r^2 M_LL - 2 r M_Lz + M_zz.
  const double H_tt_ub = M_LL_ub >= 0.0 ? M_LL_ub * inv_uL * inv_uL : 0.0;
  const double H_tz_mag = (M_Lz_mag + r_mag * M_LL_mag) * inv_uL;
  const double H_zz_ub = r_mag * r_mag * std::max(M_LL_ub, 0.0) + 2.0 * r_mag * M_Lz_mag + M_zz_ub;
  // Gershgorin: the largest eigenvalue is at most max(H_tt + |H_tz|, H_zz + |H_tz|). (H_tt's
  // negative part, the involute's convexity, is dropped: a bound, not an estimate.)
  out.kappa = std::max(H_tt_ub, H_zz_ub) + H_tz_mag;
  out.inverse_jacobian = std::sqrt(inv_uL * inv_uL + r_mag * r_mag + 1.0);
  return out;
}

// |slope (t - mid) + form(t)| over [a, b] (µm), at least: the B-spline lies within its
// coefficients' range on [t0, t1] (convex hull property) and continues linearly outside.
double trace_part_magnitude(const CubicBSpline& form, double slope, double mid, double a,
                            double b) {
  const double lo = std::min(a, form.t0()), hi = std::max(b, form.t1());
  double m = std::abs(slope) * std::max(std::abs(lo - mid), std::abs(hi - mid));
  if (form.coefficients().empty()) return m;
  double c_max = 0.0;
  for (double c : form.coefficients()) c_max = std::max(c_max, std::abs(c));
  const double overhang = std::max(std::abs(form.derivative(form.t0())) * (form.t0() - lo),
                                   std::abs(form.derivative(form.t1())) * (hi - form.t1()));
  return m + c_max + overhang;
}

}  // namespace

// Stage 1 at one planned point: the smallest box (four tries, each 1.5 times wider) that holds
// the footprint, and the bound over it.
ExactBound exact_bound(const AnalyticFlank& flank, const Eigen::Vector3d& p,
                       const Eigen::Vector3d& n, double R, double L0, const ContactStart& start,
                       double L_min, double L_max) {
  if (!nominal_start(flank, p, n, L0, start)) return {};
  const Eigen::Vector3d& eps = flank.eccentricity();
  const double r_b = 0.5 * flank.gear().base_diameter_mm();
  const double c_tau = (eps - eps.dot(n) * n).norm();  // >= |eps.t0|
  const DeviationIntervals dv(flank.deviation_derivative_ranges());
  // |delta| over the box <= |delta(L0, p_z)| + max|delta_L| half + max|delta_z| R.
  const double delta0 = std::abs(1e-3 * start.deviation_um);
  double half = 1.2 * (R + c_tau) * r_b / L0;
  for (int attempt = 0; attempt < 4; ++attempt, half *= 1.5) {
    const double D = delta0 + dv.dL_mag * half + dv.dz_mag * R;
    if (footprint_within(L0, half, R, r_b, c_tau, D, L_min, L_max)) {
      const ParameterBox box{std::max(L0 - half, L_min), std::min(L0 + half, L_max),
                             half * (1.0 / r_b), D};
      if (box.L_lo <= 0.0) return {};
      return curvature_over_box(box, dv, r_b, flank.roll_sign());
    }
  }
  return {};
}

// Stage 1 on a helical flank. In the sheared parameters (lambda, zeta) with L = lambda + g r_b
// (zeta - p_z), g = side * helix_turn_per_mm, the transverse frame (t, m) depends on lambda only
// (the generators of the helicoid are the lines of constant phi_b) and the partials of S = P +
// delta m + eps (flank_frame.h) become those of a spur flank with delta_z replaced by
// Z' = g r_b + delta_zeta:
//   S_lambda = a t + delta_lambda m,  S_zeta = e_z + Z' m,
//   S_ll = b t + c m,  S_lz = (Z' / r_b) t + delta_lz m,  S_zz = delta_zz m
// (delta_zeta = delta_z + g r_b delta_L, delta_lz = delta_Lz + g r_b delta_LL, delta_zz' =
// delta_zz + 2 g r_b delta_Lz + (g r_b)^2 delta_LL; the B-spline fields have delta_Lz = 0).
// With the outward normal N' = (-delta_lambda, a, -a Z') in (t, m, e_z), the second fundamental
// form's numerators are those of the spur bound (a c - b delta_lambda, a delta_lz - Z'
// delta_lambda / r_b, a delta_zz) over |N'| >= a sqrt(1 + Z'^2), and the first fundamental form
// is diag(a^2, 1) plus a rank-one positive term, so the largest principal curvature is at most
// the largest eigenvalue of diag(1/a, 1) II diag(1/a, 1) (Gershgorin). For the graph h(u) over
// the plane normal to n, v^T H_uu v = W II(X_v, X_v) with X_v the lift of v, |X_v| <= W =
// 1 / cos(theta) and theta the largest angle between the real normal and n over the box:
// H_uu <= k_max / cos^3(theta). theta <= Phi (the nominal normal turns with phi_b only) plus
// asin(cos(beta_b) |(delta_lambda / a, delta_zeta)|) (the deviation's tilt of the normal).
// The box: |lambda - L0| <= half (the spur margins of u_tau = w.t0, with the generator's turn
// g r_b zeta sin(psi) added to the deviation term) and |zeta - p_z| <= Z, from
// u_e2 = zeta (cos(beta_b) + sin^2(beta_b) cos(psi) / cos(beta_b)) - sigma (T_m + delta cos(psi)
// + eps.m0), sigma = n_z, |T_m| <= L0 Phi^2 / 2 + r_b Phi^3 / 3 (the involute's sag along m0).
// J = d(u)/d(lambda, zeta) has the diagonal a cos(psi) - delta_lambda sin(psi), the same
// denominator as Z's, and off-diagonal terms (Z' sin(psi), sigma (a sin(psi) + delta_lambda
// cos(psi))): |J^-1| <= 1 / (smallest diagonal - largest off-diagonal) (Weyl), times
// |d(lambda, zeta)/d(L, z)| = (G + sqrt(G^2 + 4)) / 2, G = tan(beta_b), for the solver's (L, z)
// gradient. The same dominance makes u one-to-one on the (convex) box: the footprint is a graph.
namespace {

// What the helical bound needs of a flank: the gear's helix and the deviation's sheared
// partials' bounds (mm, mm/mm, 1/mm).
struct HelicalFlank {
  double r_b, cb, sb, G;    // base radius, cos and sin of beta_b, tan(beta_b)
  double sigma;             // roll sign: +1 external, -1 internal
  double D_l, D_z, D_lz;    // |delta_lambda|, |delta_zeta|, |delta_lz|
  double D_ll_hi, D_zz_hi;  // upper bounds of delta_ll, delta_zz'
  double e_norm, c_tau;     // |eps|, >= |eps.t0|
  explicit HelicalFlank(const AnalyticFlank& flank, const Eigen::Vector3d& n) {
    const InvoluteGear& gear = flank.gear();
    r_b = 0.5 * gear.base_diameter_mm();
    sigma = flank.roll_sign();
    const double beta_b = gear.base_helix_angle_rad();
    cb = std::cos(beta_b), sb = std::sin(beta_b);
    G = std::abs(gear.helix_turn_per_mm()) * r_b;
    const DeviationIntervals dv(flank.deviation_derivative_ranges());
    D_l = dv.dL_mag;
    D_z = dv.dz_mag + G * D_l;
    D_lz = G * dv.dLL.magnitude();  // delta_Lz = 0
    D_ll_hi = dv.dLL.hi;
    D_zz_hi = dv.dzz.hi + G * G * dv.dLL.hi;
    const Eigen::Vector3d& eps = flank.eccentricity();
    e_norm = eps.norm();
    // Per point: |eps - (eps.n) n| >= |eps.t0|; per flank (n unknown): |eps|.
    c_tau = n.allFinite() ? (eps - eps.dot(n) * n).norm() : e_norm;
  }
  // den: the smallest |u_e2| per mm of |zeta - p_z| and J's smallest e2 diagonal term.
  double den(double Phi) const { return cb + sb * sb * (1.0 - 0.5 * Phi * Phi) / cb - sb * D_z; }
  // Z: the footprint's |zeta - p_z| bound for a box of half-width `half` at L0 with |delta(L0,
  // p_z)| <= delta0 (infinite when den <= 0).
  double Z(double L0, double half, double delta0) const {
    const double Phi = half / r_b, d = den(Phi);
    if (!(d > 0.0)) return kInf;
    const double sag = L0 * 0.5 * Phi * Phi + r_b * Phi * Phi * Phi / 3.0;
    return (R_ + sb * (sag + delta0 + D_l * half + e_norm)) / d;
  }
  double R_ = 0.0;
};

// The bound over the box: L in [L_lo, L_hi] (the flank's part), turn Phi, |delta| <= D.
ExactBound helical_box_bound(const HelicalFlank& h, double L_lo, double L_hi, double Phi,
                             double D) {
  const double r_b = h.r_b, G = h.G;
  const double a_lo = (L_lo - D) / r_b, a_hi = (L_hi + D) / r_b;
  if (!(a_lo > 0.0) || !(L_hi >= L_lo)) return {};
  const double Zp_lo = std::max(0.0, G - h.D_z);
  const double N_lo = a_lo * std::sqrt(1.0 + Zp_lo * Zp_lo);
  const double num_ll_ub = a_hi * std::max(h.D_ll_hi, 0.0) +
                           involute_term_ub(h.sigma, a_lo, a_hi, 1.0 / r_b) +
                           h.D_l * (1.0 + 2.0 * h.D_l) / r_b;
  const double K_ll = std::max(num_ll_ub, 0.0) / (N_lo * a_lo * a_lo);
  const double K_lz = (a_hi * h.D_lz + (G + h.D_z) * h.D_l / r_b) / (N_lo * a_lo);
  const double K_zz = a_hi * std::max(h.D_zz_hi, 0.0) / N_lo;
  const double k_max = std::max(K_ll, K_zz) + K_lz;
  const double tilt = std::sqrt((h.D_l / a_lo) * (h.D_l / a_lo) + h.D_z * h.D_z) * h.cb;
  // asin(x) <= x asin(0.5) / 0.5 for x <= 0.5 (asin(x) / x grows with x); cos(theta) >= 1 -
  // theta^2 / 2.
  if (!(tilt <= 0.5)) return {};
  const double theta = Phi + 1.0472 * tilt;
  const double cos_theta = 1.0 - 0.5 * theta * theta;
  if (!(cos_theta > 0.1)) return {};
  const double j11 = a_lo * (1.0 - 0.5 * Phi * Phi) - h.D_l * Phi;
  const double off = std::max((G + h.D_z) * Phi, h.sb * (a_hi * Phi + h.D_l));
  const double smallest = std::min(j11, h.den(Phi)) - off;
  if (!(smallest > 0.0)) return {};
  ExactBound out;
  out.kappa = k_max / (cos_theta * cos_theta * cos_theta);
  out.inverse_jacobian = 0.5 * (G + std::sqrt(G * G + 4.0)) / smallest;
  return out;
}

}  // namespace

// p on the nominal helicoid and n its normal there: S(L0, p_z) = p + delta0 m0 + eps.
ExactBound helical_exact_bound(const AnalyticFlank& flank, const Eigen::Vector3d& p,
                               const Eigen::Vector3d& n, double R, double L0,
                               const ContactStart& start, double L_min, double L_max) {
  if (!nominal_helical_start(flank, p, n, L0, start)) return {};
  HelicalFlank h(flank, n);
  h.R_ = R;
  const double delta0 = std::abs(1e-3 * start.deviation_um);
  const double r_b = h.r_b, G = h.G;
  double half = 1.2 * (R + h.c_tau) * r_b / L0;
  for (int attempt = 0; attempt < 4; ++attempt, half *= 1.5) {
    const double Phi = half / r_b;
    const double Z = h.Z(L0, half, delta0);
    if (!std::isfinite(Z)) return {};
    const double D = delta0 + h.D_l * half + h.D_z * Z;
    const bool lower_cut = L0 - half + G * Z<L_min, upper_cut = L0 + half - G * Z> L_max;
    const FootprintMargins m = footprint_margins(L0, half, R, r_b, h.c_tau, D + G * Z);
    if (!((lower_cut || m.lower >= 0.0) && (upper_cut || m.upper >= 0.0))) continue;
    return helical_box_bound(h, std::max(L_min, L0 - half - G * Z),
                             std::min(L_max, L0 + half + G * Z), Phi, D);
  }
  return {};
}

// The per-flank bound of a helical flank (flank_curvature_bound): as for a spur flank, one K
// (half-width K / L0) for every planned point, the margins checked at the smallest L0 whose end
// is not cut, now with the generator's term G Z in the deviation's place and the cut conditions
// widened by G Z_max (Z is largest at L_min: its turn and sag shrink with L0, so every margin
// still grows with L0 and a superset of the uncut points starts at the roots below).
void helical_flank_bound(const AnalyticFlank& flank, double R, double L_min, double L_max,
                         FlankCurvatureBound* out) {
  HelicalFlank h(flank, Eigen::Vector3d::Constant(kInf));
  h.R_ = R;
  const double r_b = h.r_b, G = h.G, dev = out->deviation_max_mm;
  for (int attempt = 0; attempt < 4; ++attempt) {
    const double K = 1.2 * std::pow(1.5, attempt) * (R + h.e_norm) * r_b;
    auto Z_at = [&](double L0) { return h.Z(L0, K / L0, dev); };
    auto D_at = [&](double L0) { return dev + h.D_l * K / L0 + h.D_z * Z_at(L0); };
    auto margins = [&](double L0) {
      return footprint_margins(L0, K / L0, R, r_b, h.c_tau, D_at(L0) + G * Z_at(L0));
    };
    const double Z_max = Z_at(L_min);
    if (!std::isfinite(Z_max)) return;
    bool holds = true;
    const double B = L_max + G * Z_max;  // upper end uncut => L0 + K / L0 <= B
    if (B * B >= 4.0 * K) {
      const double l1 = 2.0 * K / (B + std::sqrt(B * B - 4.0 * K));
      const double L_up = std::max(L_min, l1) * (1.0 - 1e-9);
      holds = margins(L_up).upper >= 0.0;
    }
    const double A = L_min - G * Z_max;  // lower end uncut => L0 - K / L0 >= A
    const double L_c = 0.5 * (A + std::sqrt(A * A + 4.0 * K));
    if (holds && L_c <= L_max) holds = margins(std::max(L_min, L_c * (1.0 - 1e-9))).lower >= 0.0;
    if (!holds) continue;
    out->half_width_mm2 = K;
    out->max_turn_rad = K / (L_min * r_b);
    out->max_deviation_mm = D_at(L_min);
    const ExactBound b =
        helical_box_bound(h, L_min, L_max, out->max_turn_rad, out->max_deviation_mm);
    out->kappa = b.kappa;
    out->inverse_jacobian = b.inverse_jacobian;
    return;
  }
}

double exact_curvature_bound(const AnalyticFlank& flank, const Eigen::Vector3d& p,
                             const Eigen::Vector3d& n, double R, double L0, double z0, double L_min,
                             double L_max) {
  if (flank.gear().helical()) {
    return helical_exact_bound(flank, p, n, R, L0, flank.evaluate(L0, z0), L_min, L_max).kappa;
  }
  return exact_bound(flank, p, n, R, L0, flank.evaluate(L0, z0), L_min, L_max).kappa;
}

FlankCurvatureBound flank_curvature_bound(const AnalyticFlank& flank, double R, double L_min,
                                          double L_max) {
  FlankCurvatureBound out;
  out.flank = &flank;
  out.R = R;
  out.L_min = L_min;
  out.L_max = L_max;
  if (flank.expression() != nullptr || !(L_min > 0.0) || !(L_max > L_min)) return out;

  const FlankDeviation& dev = flank.deviation();
  // The profile part over the extent, the helix part over its own domain (a planned point
  // beyond it fails `covers`' check of |delta0| and takes the per-point bound): 1 % and 1 nm of
  // room, so that a point at the extreme is not refused for a rounding.
  double deviation_um =
      std::abs(dev.offset_um) +
      trace_part_magnitude(dev.profile_form, dev.profile_slope_um_per_mm, dev.profile_mid_mm, L_min,
                           L_max) +
      trace_part_magnitude(dev.helix_form, dev.helix_slope_um_per_mm, dev.helix_mid_mm,
                           dev.helix_form.t0(), dev.helix_form.t1());
  if (const DesignModification* modification = flank.modification()) {
    deviation_um += modification->profile.magnitude_bound(L_min, L_max) +
                    modification->helix.magnitude_bound(0.0, flank.gear().face_width_mm());
  }
  out.deviation_max_mm = 1e-3 * (1.01 * deviation_um + 1e-3);
  if (flank.gear().helical()) {
    helical_flank_bound(flank, R, L_min, L_max, &out);
    return out;
  }
  const double r_b = 0.5 * flank.gear().base_diameter_mm();
  const double c = flank.eccentricity().norm();  // >= c_tau at every planned point
  const DeviationIntervals dv(flank.deviation_derivative_ranges());
  // The per-point box's half-width at attempt k is K / L0 (exact_bound, with c for c_tau). One
  // K for all points: the margins grow with L0 at fixed K (footprint_margins), so the upper end
  // holds for every point whose upper end is not cut once it holds at the smallest such L0
  // (L0 + K / L0 <= L_max: L0 >= l1, the smaller root), and the lower end likewise at the
  // smallest L0 whose lower end is not cut (L0 - K / L0 >= L_min: L0 >= L_c). Both are tested a
  // hair below those roots (1e-9 relative), so a rounding of the roots cannot skip a point.
  for (int attempt = 0; attempt < 4; ++attempt) {
    const double K = 1.2 * std::pow(1.5, attempt) * (R + c) * r_b;
    auto D_at = [&](double L0) {
      return out.deviation_max_mm + dv.dL_mag * K / L0 + dv.dz_mag * R;
    };
    bool holds = true;
    if (L_max * L_max >= 4.0 * K) {
      const double l1 = 2.0 * K / (L_max + std::sqrt(L_max * L_max - 4.0 * K));  // no cancellation
      const double L_up = std::max(L_min, l1) * (1.0 - 1e-9);
      holds = footprint_margins(L_up, K / L_up, R, r_b, c, D_at(L_up)).upper >= 0.0;
    }
    const double L_c = 0.5 * (L_min + std::sqrt(L_min * L_min + 4.0 * K));
    if (holds && L_c <= L_max) {
      const double L_low = L_c * (1.0 - 1e-9);
      holds = footprint_margins(L_low, K / L_low, R, r_b, c, D_at(L_low)).lower >= 0.0;
    }
    if (!holds) continue;
    // Every point's box lies in [L_min, L_max], turns by at most K / (L_min r_b) and has |delta|
    // at most D_at(L_min): the box below contains them all, and the bound is monotone in it.
    out.half_width_mm2 = K;
    out.max_turn_rad = K / (L_min * r_b);
    out.max_deviation_mm = D_at(L_min);
    const ExactBound b = curvature_over_box({L_min, L_max, out.max_turn_rad, out.max_deviation_mm},
                                            dv, r_b, flank.roll_sign());
    out.kappa = b.kappa;
    out.inverse_jacobian = b.inverse_jacobian;
    return out;
  }
  return out;
}

}  // namespace gearmc
