// First-contact certificate (see contact_certificate.h): the exact interval bound of the flank's
// curvature over the footprint for B-spline fields (stage 1, curvature_bound.cpp) and a
// sampled branch-and-bound over the footprint otherwise (stage 2, here).
#include "engine/contact/contact_certificate.h"

#include "core/constants.h"
#include "engine/contact/curvature_bound.h"

#include <Eigen/Geometry>
#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

namespace gearmc {
namespace {

constexpr int kSampledCellsAcross = 64;  // stage 2's grid: cells across the footprint's 2R

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
  // A helical flank's grid is sheared (see sampled_certificate) and may reach beyond the flank's
  // roll-length extent at some z: nodes there keep h and u (the surface's smooth continuation,
  // a superset for the bounds) but are never a higher point (no flank there).
  bool mask_extent = false;
  double L_min = 0.0, L_max = kInf;
};

Node sample(const Frame& fr, double L, double z) {
  const Eigen::Vector3d w = fr.flank.point(L, z) - fr.p;
  Node k{L, z, w.dot(fr.n), Eigen::Vector2d(w.dot(fr.tau), w.dot(fr.e2)), -kInf};
  const double q2 = fr.R * fr.R - k.u.squaredNorm();
  if (fr.mask_extent && (L < fr.L_min || L > fr.L_max)) return k;
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

// Second differences of (h, u) at an interior node along L and along z (mm): psi = h - G.u is
// linear in them, so each cell's curvature estimate for its own G costs three products per node.
struct SecondDifference {
  double h_L = 0.0, h_z = 0.0;
  Eigen::Vector2d u_L = Eigen::Vector2d::Zero(), u_z = Eigen::Vector2d::Zero();
};

// The footprint grid: nodes (i, j), i along L, j along z.
struct Grid {
  int cells_L, cells_z;
  double L0, z0, dL, dz;
  std::vector<Node> nodes;
  std::vector<SecondDifference> second;  // per node; zero on the border (unused there)
  std::size_t index(int i, int j) const { return static_cast<std::size_t>(j * (cells_L + 1) + i); }
  const Node& at(int i, int j) const { return nodes[index(i, j)]; }
  const SecondDifference& second_at(int i, int j) const { return second[index(i, j)]; }
  void difference() {
    second.assign(nodes.size(), SecondDifference{});
    for (int j = 0; j <= cells_z; ++j) {
      for (int i = 0; i <= cells_L; ++i) {
        SecondDifference& d = second[index(i, j)];
        const Node& c = at(i, j);
        if (i > 0 && i < cells_L) {
          const Node &a = at(i - 1, j), &b = at(i + 1, j);
          d.h_L = b.h - 2.0 * c.h + a.h;
          d.u_L = b.u - 2.0 * c.u + a.u;
        }
        if (j > 0 && j < cells_z) {
          const Node &a = at(i, j - 1), &b = at(i, j + 1);
          d.h_z = b.h - 2.0 * c.h + a.h;
          d.u_z = b.u - 2.0 * c.u + a.u;
        }
      }
    }
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
    double lo_L = kInf, hi_L = -kInf, lo_z = kInf, hi_z = -kInf;
    for (int b = std::max(j - 1, 0); b <= std::min(j + 2, grid.cells_z); ++b) {
      for (int a = std::max(i - 1, 0); a <= std::min(i + 2, grid.cells_L); ++a) {
        const SecondDifference& d = grid.second_at(a, b);
        if (a > 0 && a < grid.cells_L) {
          const double d2 = d.h_L - G.dot(d.u_L);
          lo_L = std::min(lo_L, d2), hi_L = std::max(hi_L, d2);
        }
        if (b > 0 && b < grid.cells_z) {
          const double d2 = d.h_z - G.dot(d.u_z);
          lo_z = std::min(lo_z, d2), hi_z = std::max(hi_z, d2);
        }
      }
    }
    // Divided by the steps once (the differences above are not).
    lo_L /= grid.dL * grid.dL, hi_L /= grid.dL * grid.dL;
    lo_z /= grid.dz * grid.dz, hi_z /= grid.dz * grid.dz;
    *K_L = std::max(0.0, -lo_L + (hi_L - lo_L));
    *K_z = std::max(0.0, -lo_z + (hi_z - lo_z));
  }

  bool prove_cell(int i, int j) {
    const Node &c0 = grid.at(i, j), &c1 = grid.at(i + 1, j), &c2 = grid.at(i, j + 1),
               &c3 = grid.at(i + 1, j + 1);
    return prove(c0, c1, c2, c3, i, j, 0);
  }

  // Corners c0 (L0, z0), c1 (L1, z0), c2 (L0', z1), c3 (L1', z1), inside grid cell (i, j): a
  // parallelogram in (L, z) (L0' = L0 on a spur flank's rectangular grid; sheared on a helical
  // one), split at its edges' midpoints.
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
    const double Lm2 = 0.5 * (c2.L + c3.L);  // = Lm on a rectangular grid
    const Node s[5] = {sample(fr, Lm, c0.z), sample(fr, 0.5 * (c0.L + c2.L), zm),
                       sample(fr, 0.5 * (Lm + Lm2), zm), sample(fr, 0.5 * (c1.L + c3.L), zm),
                       sample(fr, Lm2, c2.z)};
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
  const bool helical = flank.gear().helical();
  if (!helical && std::abs(n.z()) > 1e-9) {
    out.reason = ContactFailure::kNormalNotTransverse;
    return out;
  }
  // u = (w.tau, w.e2) with tau = e_z x n (transverse) and e2 = n x tau (e_z itself when n is
  // transverse).
  const Eigen::Vector3d tau = Eigen::Vector3d::UnitZ().cross(n).normalized();
  Frame fr{flank, p, n, tau, helical ? Eigen::Vector3d(n.cross(tau)) : Eigen::Vector3d::UnitZ(), R};
  const double r_b = 0.5 * flank.gear().base_diameter_mm();
  // A helical flank's grid is sheared along the generators of the helicoid: node (i, j) at
  // L = L_lo + i dL + shear (z_j - p_z), z_j. Along a generator the transverse section turns
  // with z as L moves by shear = sigma side helix_turn_per_mm r_b (= +/- tan(beta_b); sigma the
  // roll sign, -1 on an internal gear), so the base
  // angle phi_b and with it the involute's frame stay fixed: the footprint, a disk in the plane
  // normal to n, is nearly a rectangle in (L', z) as it is for a spur flank in (L, z). Its z
  // half-extent is R cos(beta_b) (|u_e2| grows by 1 / cos(beta_b) per mm of z along a
  // generator); the grid takes 1.05 R.
  const double shear =
      helical ? flank.roll_sign() * side_sign(flank.side()) * flank.gear().helix_turn_per_mm() * r_b
              : 0.0;
  const double z_half = helical ? 1.05 * R : R;
  if (helical) {
    fr.mask_extent = true;
    fr.L_min = L_min;
    fr.L_max = L_max;
  }
  const double dz = 2.0 * z_half / kSampledCellsAcross;
  // The L range from the involute's arc length s = L^2 / (2 r_b) from the base circle: the
  // footprint spans about 2 (R + e) of arc, which near the base circle is a wide range of L on
  // the lower side and a narrow one on the upper side. Grow the arc half-width until both end
  // columns lie outside the footprint (sampled).
  const double arc0 = L0 * L0 / (2.0 * r_b);
  auto L_at_arc = [&](double arc) { return arc > 0.0 ? std::sqrt(2.0 * r_b * arc) : 0.0; };
  double arc_half = 1.2 * (R + flank.eccentricity().norm());
  // The grid is cut at the flank's extent: a cut end is the flank's edge, not a footprint bound.
  // (Helical: the flank's extent in L is a sheared band in (L', z); the grid reaches
  // |shear| z_half beyond it and masks the nodes off the flank.)
  bool bounded = false;
  double L_lo = 0.0, L_hi = 0.0;
  const double reach = std::abs(shear) * z_half;
  for (int attempt = 0; attempt < 6 && !bounded; ++attempt) {
    bounded = true;
    const double L_down = L_at_arc(arc0 - arc_half), L_up = L_at_arc(arc0 + arc_half);
    L_lo = std::max(L_down, L_min - reach);
    L_hi = std::min(L_up, L_max + reach);
    for (double L : {L_down, L_up}) {
      if (!helical && (L <= L_min || L > L_max)) continue;  // cut: the edge of the flank
      for (int j = 0; j <= kSampledCellsAcross && bounded; ++j) {
        const double z = p.z() - z_half + j * dz;
        const double L_j = L + shear * (z - p.z());
        if (helical && (L_j <= L_min || L_j > L_max)) continue;  // no flank there
        const Eigen::Vector3d w = flank.point(L_j, z) - p;
        bounded = std::abs(w.dot(fr.tau)) >= R + dz;
      }
    }
    if (!bounded) arc_half *= 1.3;
  }
  if (!bounded || !(L_hi > L_lo)) {
    out.reason = ContactFailure::kFootprintNotBounded;
    return out;
  }
  Grid grid;
  grid.cells_z = kSampledCellsAcross;
  // The same spacing in u as across at the contact: a step dL moves the involute by about
  // L dL / r_b of arc (cells further up are wider, further down narrower; the prover splits).
  const double L_ref = std::max(x_star.x(), 1e-3);
  grid.cells_L = std::max(2, static_cast<int>(std::ceil((L_hi - L_lo) / (dz * r_b / L_ref))));
  grid.L0 = L_lo;
  grid.z0 = p.z() - z_half;
  grid.dL = (L_hi - L_lo) / grid.cells_L;
  grid.dz = dz;
  grid.nodes.reserve(static_cast<std::size_t>((grid.cells_L + 1) * (grid.cells_z + 1)));
  const Node* best = nullptr;
  for (int j = 0; j <= grid.cells_z; ++j) {
    for (int i = 0; i <= grid.cells_L; ++i) {
      const double z = grid.z0 + j * dz;
      const double L = grid.L0 + i * grid.dL;
      grid.nodes.push_back(sample(fr, helical ? L + shear * (z - p.z()) : L, z));
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
        H[idx] = curvature(fr, x_star.x() + a * hL + shear * (b * hz), x_star.y() + b * hz).H_uu;
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
    out.reason = ContactFailure::kNotConcaveAtContact;
    return out;
  }
  grid.difference();
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
          out.reason = ContactFailure::kUnprovenRegion;
        }
        return out;
      }
    }
  }
  out.verdict = ContactCertificate::Verdict::kCertified;
  return out;
}

}  // namespace

ContactCertificate certify_contact(const AnalyticFlank& flank, const Eigen::Vector3d& p,
                                   const Eigen::Vector3d& n, double R, double L0,
                                   const ContactStart& start, const Eigen::Vector2d& x_star,
                                   double t_star, double gradient_bound, double L_min, double L_max,
                                   const FlankCurvatureBound* flank_bound) {
  ContactCertificate out;
  if (flank_bound != nullptr &&
      flank_bound->proves(flank, p, n, R, L0, start, gradient_bound, L_min, L_max)) {
    out.verdict = ContactCertificate::Verdict::kCertified;
    out.by_flank_bound = true;
    return out;
  }
  const ExactBound b = flank.gear().helical()
                           ? helical_exact_bound(flank, p, n, R, L0, start, L_min, L_max)
                           : exact_bound(flank, p, n, R, L0, start, L_min, L_max);
  if (concavity_proves(R, b.kappa, b.inverse_jacobian, gradient_bound)) {
    out.verdict = ContactCertificate::Verdict::kCertified;
    return out;
  }
  return sampled_certificate(flank, p, n, R, L0, x_star, t_star, L_min, L_max);
}

}  // namespace gearmc
