// First-contact certificate (see contact_certificate.h): an exact interval bound of the
// flank's curvature over the footprint for B-spline fields, and a sampled branch-and-bound
// over the footprint otherwise.
#include "engine/probing/contact_certificate.h"

#include <Eigen/Geometry>
#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

namespace gearmc {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr int kSampledCellsAcross = 64;  // stage 2's grid: cells across the footprint's 2R

// A closed interval [lo, hi].
struct Interval {
  double lo, hi;
  double magnitude() const { return std::max(std::abs(lo), std::abs(hi)); }
};

struct ExactBound {
  double kappa = kInf;             // >= largest eigenvalue of H_uu over the footprint, 1/mm
  double inverse_jacobian = kInf;  // >= |J^-1| (Frobenius), J = d(u)/d(L, z)
};

// Stage 1. With phi the angle of the involute normal n(L) from n (phi = (L - L0) / r_b,
// n(L) = cos phi n + sin phi t0, t0 the profile tangent at L0), a = (L + delta) / r_b and the
// partials of S (analytic_flank.cpp):
//   (u_L, h_L) = Rot(a, delta_L),  (u_LL, h_LL) = Rot((1 + 2 delta_L) / r_b, delta_LL - a / r_b),
//   (u_Lz, h_Lz) = Rot(delta_z / r_b, delta_Lz),  (u_zz, h_zz) = Rot(0, delta_zz),
//   u_z(tau) = delta_z sin phi, u_z(z) = 1,
// so M_xy = h_xy - (h_L / u_L) u_xy = cross((u_L, h_L), (u_xy, h_xy)) / u_L loses the rotation:
//   M_LL = (a (delta_LL - a / r_b) - delta_L (1 + 2 delta_L) / r_b) / u_L,
//   M_Lz = (a delta_Lz - delta_L delta_z / r_b) / u_L,  M_zz = a delta_zz / u_L,
// and H_uu = J^-T M J^-1 with J = [[u_L, u_z], [0, 1]]. sin phi and cos phi are bounded over the
// box symmetric about L0, so the sign of t0 does not matter.
ExactBound exact_bound(const AnalyticFlank& flank, const Eigen::Vector3d& p,
                       const Eigen::Vector3d& n, double R, double L0, const ContactStart& start,
                       double L_min, double L_max) {
  ExactBound out;
  if (flank.expression() != nullptr) return out;  // no exact derivative bounds
  // The closed form needs p = P(L0, p_z) + 0 on the nominal flank and n = n(L0), transverse;
  // `start` = S(L0, p_z) = P + delta n(L0) + eps.
  const double delta0 = 1e-3 * start.deviation_um;
  const Eigen::Vector3d& eps = flank.eccentricity();
  if ((start.nominal_normal - n).squaredNorm() > 1e-24 || std::abs(n.z()) > 1e-12 ||
      (start.point - delta0 * n - eps - p).squaredNorm() > 1e-18 || L0 <= 0.0) {
    return out;
  }
  const double r_b = 0.5 * flank.gear().base_diameter_mm();
  const double inv_rb = 1.0 / r_b;  // divisions by r_b and u_L below are multiplications
  const double c_tau = (eps - eps.dot(n) * n).norm();  // >= |eps.t0|
  const FlankDeviation::Ranges& rg = flank.deviation_derivative_ranges();
  auto mm = [](CubicBSpline::Range r) { return Interval{1e-3 * r.lo, 1e-3 * r.hi}; };
  const Interval dL = mm(rg.dL), dz = mm(rg.dz), dLL = mm(rg.dLL), dzz = mm(rg.dzz);
  // The L half-width: |u_tau| >= |N(L)| - c_tau - |delta| sin(Phi) with the nominal
  // N(L) = (P(L) - P(L0)).t0 = L0 sin phi + r_b (phi sin phi + cos phi - 1), whose modulus grows
  // with |phi| (beyond the box it keeps growing: the footprint cannot come back). Trigonometry
  // by rigorous Taylor bounds: sin x >= x - x^3/6, x sin x + cos x - 1 <= x^2/2 + x^4/24.
  // |delta| over the box <= |delta(L0, p_z)| + max|delta_L| half + max|delta_z| R.
  // The box is cut at the flank's extent [L_min, L_max]: an end that is cut is the flank's edge
  // and needs no bound of the footprint there. On the upper side |N| >= L0 sin(Phi) (the r_b
  // term is >= 0 there), on the lower side the full expression below.
  double half = 1.2 * (R + c_tau) * r_b / L0, Phi = 0.0, D = 0.0, L_lo = 0.0, L_hi = 0.0;
  const double dL_mag = dL.magnitude(), dz_mag = dz.magnitude();
  bool bounded = false;
  for (int attempt = 0; attempt < 4 && !bounded; ++attempt) {
    if (attempt > 0) half *= 1.5;
    L_lo = std::max(L0 - half, L_min);
    L_hi = std::min(L0 + half, L_max);
    if (L_lo <= 0.0) return out;
    Phi = half * inv_rb;
    D = std::abs(delta0) + dL_mag * half + dz_mag * R;
    const double N_up = L0 * (Phi - Phi * Phi * Phi / 6.0);
    const double N_down = N_up - r_b * (0.5 * Phi * Phi + Phi * Phi * Phi * Phi / 24.0);
    const bool lower_cut = L0 - half<L_min, upper_cut = L0 + half> L_max;
    bounded =
        (lower_cut || N_down - c_tau - D * Phi >= R) && (upper_cut || N_up - c_tau - D * Phi >= R);
  }
  if (!bounded) return out;
  // Bounds with the signs known (a > 0, u_L > 0, |sin phi| <= Phi, cos phi >= 1 - Phi^2/2):
  // ub = upper bound, mag = bound of the modulus.
  const double a_lo = (L_lo - D) * inv_rb, a_hi = (L_hi + D) * inv_rb;
  const double uL_lo = a_lo * (1.0 - 0.5 * Phi * Phi) - dL_mag * Phi;
  if (a_lo <= 0.0 || uL_lo <= 0.0) return out;
  const double inv_uL = 1.0 / uL_lo;
  const double slope_term = dL_mag * (1.0 + 2.0 * dL_mag) * inv_rb;
  // M_LL = (a (delta_LL - a / r_b) - delta_L (1 + 2 delta_L) / r_b) / u_L
  const double num_LL_ub = a_hi * std::max(dLL.hi, 0.0) - a_lo * a_lo * inv_rb + slope_term;
  const double M_LL_ub = num_LL_ub >= 0.0 ? num_LL_ub * inv_uL : num_LL_ub / (a_hi + dL_mag * Phi);
  const double M_LL_mag = (a_hi * dLL.magnitude() + a_hi * a_hi * inv_rb + slope_term) * inv_uL;
  const double M_Lz_mag = dL_mag * dz_mag * inv_rb * inv_uL;     // delta_Lz = 0
  const double M_zz_ub = a_hi * std::max(dzz.hi, 0.0) * inv_uL;  // a delta_zz / u_L
  const double r_mag = dz_mag * Phi * inv_uL;                    // |u_z(tau) / u_L|
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

// Stage 2: one sample of the flank in the footprint frame (value only).
struct Node {
  double L, z;
  double h;           // w.n
  Eigen::Vector2d u;  // (w.tau, w.e2)
  double f;           // contact height, -inf out of reach
};

struct Frame {
  const AnalyticFlank& flank;
  Eigen::Vector3d p, n, tau, e2;
  double R;
};

Node sample(const Frame& fr, double L, double z) {
  const Eigen::Vector3d w = fr.flank.point(L, z) - fr.p;
  Node k{L, z, w.dot(fr.n), Eigen::Vector2d(w.dot(fr.tau), w.dot(fr.e2)), -kInf};
  const double q2 = fr.R * fr.R - k.u.squaredNorm();
  if (q2 > 0.0) k.f = k.h + std::sqrt(q2);
  return k;
}

// The graph's Hessian H_uu (1/mm) and d(u_tau)/dL at (L, z), from the analytic partials.
struct Curvature {
  Eigen::Matrix2d H_uu;
  double u_L;
};
Curvature curvature(const Frame& fr, double L, double z) {
  const FlankSurfacePoint s = fr.flank.evaluate(L, z);
  Eigen::Matrix2d J;  // d(u)/d(L, z)
  J << s.d_dL.dot(fr.tau), s.d_dz.dot(fr.tau), s.d_dL.dot(fr.e2), s.d_dz.dot(fr.e2);
  const Eigen::Matrix2d Jinv = J.inverse();
  const Eigen::Vector2d slope =
      Jinv.transpose() * Eigen::Vector2d(s.d_dL.dot(fr.n), s.d_dz.dot(fr.n));
  const Eigen::Vector3d* S2[2][2] = {{&s.d2_dL2, &s.d2_dLdz}, {&s.d2_dLdz, &s.d2_dz2}};
  Eigen::Matrix2d M;
  for (int a = 0; a < 2; ++a) {
    for (int b = 0; b < 2; ++b) {
      const Eigen::Vector3d& Sab = *S2[a][b];
      M(a, b) = Sab.dot(fr.n) - slope.x() * Sab.dot(fr.tau) - slope.y() * Sab.dot(fr.e2);
    }
  }
  return {Jinv.transpose() * M * Jinv, J(0, 0)};
}

double largest_eigenvalue(const Eigen::Matrix2d& H) {
  const double m = 0.5 * (H(0, 0) + H(1, 1));
  const double d = 0.5 * (H(0, 0) - H(1, 1));
  const double off = 0.5 * (H(0, 1) + H(1, 0));
  return m + std::sqrt(d * d + off * off);
}

// The footprint grid: nodes (i, j), i along L, j along z.
struct Grid {
  int cells_L, cells_z;
  double L0, z0, dL, dz;
  std::vector<Node> nodes;
  const Node& at(int i, int j) const {
    return nodes[static_cast<std::size_t>(j * (cells_L + 1) + i)];
  }
};

struct CellProver {
  const Frame& fr;
  const Grid& grid;
  double t_star;
  Eigen::Vector2d u_star;
  double rho;                // the proven neighbourhood |u - u*| <= rho
  std::vector<Node> higher;  // a refinement node above t* + tol, when one is met

  // psi = h - G.u's largest negative second derivative along L and z over cell (i, j), from
  // the grid's second differences at the nodes of the cell and its neighbours (each is psi''
  // somewhere within two steps), plus their spread: the sampled curvature bound.
  void curvature_bounds(int i, int j, const Eigen::Vector2d& G, double* K_L, double* K_z) const {
    auto psi = [&](int a, int b) { return grid.at(a, b).h - G.dot(grid.at(a, b).u); };
    double lo_L = kInf, hi_L = -kInf, lo_z = kInf, hi_z = -kInf;
    for (int b = std::max(j - 1, 0); b <= std::min(j + 2, grid.cells_z); ++b) {
      for (int a = std::max(i - 1, 0); a <= std::min(i + 2, grid.cells_L); ++a) {
        if (a > 0 && a < grid.cells_L) {
          const double d2 = (psi(a + 1, b) - 2.0 * psi(a, b) + psi(a - 1, b)) / (grid.dL * grid.dL);
          lo_L = std::min(lo_L, d2), hi_L = std::max(hi_L, d2);
        }
        if (b > 0 && b < grid.cells_z) {
          const double d2 = (psi(a, b + 1) - 2.0 * psi(a, b) + psi(a, b - 1)) / (grid.dz * grid.dz);
          lo_z = std::min(lo_z, d2), hi_z = std::max(hi_z, d2);
        }
      }
    }
    *K_L = std::max(0.0, -lo_L + (hi_L - lo_L));
    *K_z = std::max(0.0, -lo_z + (hi_z - lo_z));
  }

  bool prove_cell(int i, int j) {
    const Node &c0 = grid.at(i, j), &c1 = grid.at(i + 1, j), &c2 = grid.at(i, j + 1),
               &c3 = grid.at(i + 1, j + 1);
    return prove(c0, c1, c2, c3, i, j, 0);
  }

  // Corners c0 (L0, z0), c1 (L1, z0), c2 (L0, z1), c3 (L1, z1), inside grid cell (i, j).
  bool prove(const Node& c0, const Node& c1, const Node& c2, const Node& c3, int i, int j,
             int depth) {
    const Node* c[4] = {&c0, &c1, &c2, &c3};
    const double dL = c1.L - c0.L, dz = c2.z - c0.z;
    // Inside the proven neighbourhood: the cell's image (nearly a parallelogram) is within the
    // convex disk when its corners are, with a margin for the map's curvature.
    bool inside = true;
    Eigen::Vector2d centre = Eigen::Vector2d::Zero();
    double radius = 0.0;
    for (const Node* k : c) {
      inside = inside && (k->u - u_star).norm() <= 0.95 * rho;
      centre += 0.25 * k->u;
    }
    if (inside) return true;
    for (const Node* k : c) radius = std::max(radius, (k->u - centre).norm());
    // Entirely outside the footprint (5 % margin for the map's curvature).
    if (centre.norm() - 1.05 * radius >= fr.R) return true;
    // The hemisphere's tangent plane at v (inside the disk) lies below it.
    Eigen::Vector2d v = centre;
    if (v.norm() > 0.98 * fr.R) v *= 0.98 * fr.R / v.norm();
    const double q_v = std::sqrt(fr.R * fr.R - v.squaredNorm());
    const Eigen::Vector2d G = v / q_v;
    const double plane_at_zero = t_star - q_v - G.dot(v);
    double psi_max = -kInf;
    for (const Node* k : c) psi_max = std::max(psi_max, k->h - G.dot(k->u));
    double K_L, K_z;
    curvature_bounds(i, j, G, &K_L, &K_z);
    // Bilinear interpolation error, one-sided: psi <= max corner + (dL^2 / 8) max(-psi_LL) +
    // (dz^2 / 8) max(-psi_zz).
    const double bound = psi_max + dL * dL / 8.0 * K_L + dz * dz / 8.0 * K_z - plane_at_zero;
    if (bound <= kCertificateToleranceMm) return true;
    if (depth == 4) return false;
    // Split 2 x 2: five new samples.
    const double Lm = 0.5 * (c0.L + c1.L), zm = 0.5 * (c0.z + c2.z);
    const Node s[5] = {sample(fr, Lm, c0.z), sample(fr, c0.L, zm), sample(fr, Lm, zm),
                       sample(fr, c1.L, zm), sample(fr, Lm, c2.z)};
    for (const Node& k : s) {
      if (k.f > t_star + kCertificateToleranceMm) {
        higher.push_back(k);
        return false;  // a higher point: the caller reports it
      }
    }
    return prove(c0, s[0], s[1], s[2], i, j, depth + 1) &&
           prove(s[0], c1, s[2], s[3], i, j, depth + 1) &&
           prove(s[1], s[2], c2, s[4], i, j, depth + 1) &&
           prove(s[2], s[3], s[4], c3, i, j, depth + 1);
  }
};

ContactCertificate sampled_certificate(const AnalyticFlank& flank, const Eigen::Vector3d& p,
                                       const Eigen::Vector3d& n, double R, double L0,
                                       const Eigen::Vector2d& x_star, double t_star, double L_min,
                                       double L_max) {
  ContactCertificate out;
  out.sampled = true;
  if (std::abs(n.z()) > 1e-9) {
    out.reason = "normal_not_transverse";
    return out;
  }
  const Frame fr{
      flank, p, n, Eigen::Vector3d::UnitZ().cross(n).normalized(), Eigen::Vector3d::UnitZ(), R};
  const double r_b = 0.5 * flank.gear().base_diameter_mm();
  const double dz = 2.0 * R / kSampledCellsAcross;
  // The L half-width: grow until both end columns lie outside the footprint (sampled).
  const double L_ref = std::max(x_star.x(), 1e-3);
  double half = 1.2 * (R + flank.eccentricity().norm()) * r_b / L_ref;
  // The grid is cut at the flank's extent: a cut end is the flank's edge, not a footprint bound.
  bool bounded = false;
  double L_lo = 0.0, L_hi = 0.0;
  for (int attempt = 0; attempt < 6 && !bounded; ++attempt) {
    bounded = true;
    L_lo = std::max(L0 - half, L_min);
    L_hi = std::min(L0 + half, L_max);
    for (double L : {L0 - half, L0 + half}) {
      if (L < L_min || L > L_max) continue;  // cut: the edge of the flank
      for (int j = 0; j <= kSampledCellsAcross && bounded; ++j) {
        const Eigen::Vector3d w = flank.point(L, p.z() - R + j * dz) - p;
        bounded = std::abs(w.dot(fr.tau)) >= R + dz;
      }
    }
    if (!bounded) half *= 1.3;
  }
  if (!bounded || !(L_hi > L_lo)) {
    out.reason = "footprint_not_bounded";
    return out;
  }
  Grid grid;
  grid.cells_z = kSampledCellsAcross;
  grid.cells_L = std::max(2, static_cast<int>(std::ceil((L_hi - L_lo) / (dz * r_b / L_ref))));
  grid.L0 = L_lo;
  grid.z0 = p.z() - R;
  grid.dL = (L_hi - L_lo) / grid.cells_L;
  grid.dz = dz;
  grid.nodes.reserve(static_cast<std::size_t>((grid.cells_L + 1) * (grid.cells_z + 1)));
  const Node* best = nullptr;
  for (int j = 0; j <= grid.cells_z; ++j) {
    for (int i = 0; i <= grid.cells_L; ++i) {
      grid.nodes.push_back(sample(fr, grid.L0 + i * grid.dL, grid.z0 + j * dz));
    }
  }
  // A higher node: the caller restarts there.
  for (const Node& k : grid.nodes) {
    if (k.f > t_star + kCertificateToleranceMm && (!best || k.f > best->f)) best = &k;
  }
  if (best) {
    out.verdict = ContactCertificate::Verdict::kHigherPoint;
    out.higher_point = Eigen::Vector2d(best->L, best->z);
    out.higher_height = best->f;
    return out;
  }
  // The neighbourhood of the found contact, proven by concavity: H_uu on its own fine grid
  // (9 x 9 nodes over |u - u*| <= r with a 25 % margin), r from 2 cells down to 1/8 cell.
  const Node star = sample(fr, x_star.x(), x_star.y());
  const double q_star = std::sqrt(std::max(R * R - star.u.squaredNorm(), 1e-300));
  Eigen::Vector2d grad_F;
  double u_L;
  {
    const FlankSurfacePoint s = flank.evaluate(x_star.x(), x_star.y());
    Eigen::Matrix2d J;
    J << s.d_dL.dot(fr.tau), s.d_dz.dot(fr.tau), s.d_dL.dot(fr.e2), s.d_dz.dot(fr.e2);
    grad_F =
        J.inverse().transpose() * Eigen::Vector2d(s.d_dL.dot(n), s.d_dz.dot(n)) - star.u / q_star;
    u_L = std::max(std::abs(J(0, 0)), 1e-6);
  }
  double rho = 0.0;
  for (const double r : {2.0 * dz, dz, dz / 2, dz / 4, dz / 8}) {
    constexpr int m = 4;  // nodes -m..m per direction
    const double hL = 1.25 * r / u_L / m, hz = 1.25 * r / m;
    std::vector<Eigen::Matrix2d> H(static_cast<std::size_t>((2 * m + 1) * (2 * m + 1)));
    double kappa = -kInf, spread = 0.0;
    for (int b = -m; b <= m; ++b) {
      for (int a = -m; a <= m; ++a) {
        const std::size_t idx = static_cast<std::size_t>((b + m) * (2 * m + 1) + (a + m));
        H[idx] = curvature(fr, x_star.x() + a * hL, x_star.y() + b * hz).H_uu;
        kappa = std::max(kappa, largest_eigenvalue(H[idx]));
        if (a > -m) spread = std::max(spread, (H[idx] - H[idx - 1]).norm());
        if (b > -m) spread = std::max(spread, (H[idx] - H[idx - (2 * m + 1)]).norm());
      }
    }
    kappa += spread;
    const double mu = 1.0 / R - kappa;
    if (mu > 0.0 && grad_F.squaredNorm() / (2.0 * mu) <= kCertificateToleranceMm) {
      rho = r;
      break;
    }
  }
  if (rho == 0.0) {
    out.reason = "not_concave_at_contact";
    return out;
  }
  CellProver prover{fr, grid, t_star, star.u, rho, {}};
  for (int j = 0; j < grid.cells_z; ++j) {
    for (int i = 0; i < grid.cells_L; ++i) {
      if (!prover.prove_cell(i, j)) {
        if (!prover.higher.empty()) {
          const Node& k = prover.higher.back();
          out.verdict = ContactCertificate::Verdict::kHigherPoint;
          out.higher_point = Eigen::Vector2d(k.L, k.z);
          out.higher_height = k.f;
        } else {
          out.reason = "unproven_region";
        }
        return out;
      }
    }
  }
  out.verdict = ContactCertificate::Verdict::kCertified;
  return out;
}

}  // namespace

double exact_curvature_bound(const AnalyticFlank& flank, const Eigen::Vector3d& p,
                             const Eigen::Vector3d& n, double R, double L0, double z0, double L_min,
                             double L_max) {
  return exact_bound(flank, p, n, R, L0, flank.evaluate(L0, z0), L_min, L_max).kappa;
}

ContactCertificate certify_contact(const AnalyticFlank& flank, const Eigen::Vector3d& p,
                                   const Eigen::Vector3d& n, double R, double L0,
                                   const ContactStart& start, const Eigen::Vector2d& x_star,
                                   double t_star, double gradient_bound, double L_min,
                                   double L_max) {
  const ExactBound b = exact_bound(flank, p, n, R, L0, start, L_min, L_max);
  const double mu = 1.0 / R - b.kappa;
  if (mu > 0.0) {
    const double g = gradient_bound * b.inverse_jacobian;
    if (g * g / (2.0 * mu) <= kCertificateToleranceMm) {
      ContactCertificate out;
      out.verdict = ContactCertificate::Verdict::kCertified;
      return out;
    }
  }
  return sampled_certificate(flank, p, n, R, L0, x_star, t_star, L_min, L_max);
}

}  // namespace gearmc
