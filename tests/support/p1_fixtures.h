// Shared test fixtures: P1's gear (docs/sources.md, Table 1) and an independent brute-force answer
// to the stylus contact problem, used by the gears, surfaces and engine test suites.
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "gears/deviations.h"
#include "gears/involute_gear.h"
#include "gears/tolerances.h"
#include "surfaces/analytic_flank.h"

namespace gearmc::testing_support {

// P1 Table 1: z 24, m 5.6 mm, alpha 20°, x 0.90116, b 78.89 mm, ISO 53 A basic rack.
inline GearParameters p1_gear_parameters() {
  GearParameters p;
  p.teeth = 24;
  p.module_mm = 5.6;
  p.pressure_angle_deg = 20.0;
  p.profile_shift = 0.90116;
  p.face_width_mm = 78.89;
  return p;
}

inline InvoluteGear p1_gear() { return InvoluteGear(p1_gear_parameters()); }

// P1 Table 1 tolerances (F_r 50, f_pb 9, f_f 8, E_Hs 110, T_H 100 µm) plus GOST grade-5
// F_beta 10 µm (docs/reference-values.md, recalled: P1 gives no helix tolerance).
inline ToleranceSet p1_tolerance_set() {
  ToleranceSet tol;
  tol.values[ToleranceKind::kRunout] = {50, "P1", true};
  tol.values[ToleranceKind::kBasePitch] = {9, "P1", true};
  tol.values[ToleranceKind::kProfileTotal] = {8, "P1", true};
  tol.values[ToleranceKind::kHelixTotal] = {10, "docs/reference-values.md (recalled)", false};
  tol.values[ToleranceKind::kThicknessUpper] = {110, "P1", true};
  tol.values[ToleranceKind::kThicknessTolerance] = {100, "P1", true};
  return tol;
}

// ISO 1328-1:2013 class 5 for P1's gear (docs/reference-values.md, verified).
inline ToleranceSet iso_class5_tolerance_set() {
  ToleranceSet tol;
  tol.standard = ToleranceStandard::kIso1328_1_2013;
  tol.values[ToleranceKind::kSinglePitch] = {7.5, "ISO", true};
  tol.values[ToleranceKind::kRunout] = {20, "ISO", true};
  tol.values[ToleranceKind::kProfileSlope] = {6.5, "ISO", true};
  tol.values[ToleranceKind::kProfileForm] = {8.0, "ISO", true};
  tol.values[ToleranceKind::kProfileTotal] = {10, "ISO", true};
  tol.values[ToleranceKind::kHelixSlope] = {7.5, "ISO", true};
  tol.values[ToleranceKind::kHelixForm] = {9.0, "ISO", true};
  tol.values[ToleranceKind::kHelixTotal] = {12, "ISO", true};
  return tol;
}

// A hand-made flank deviation with offset, slopes and wavy profile and helix forms (µm) over
// P1's flank (L 21–45 mm, z 4–75 mm).
inline FlankDeviation wavy_deviation() {
  FlankDeviation d;
  d.offset_um = -30.0;
  d.profile_slope_um_per_mm = 0.2;
  d.profile_mid_mm = 33.0;
  d.profile_form = CubicBSpline(21.0, 45.0, {1.0, -2.0, 3.0, 0.5, -1.5, 2.5, -0.7, 0.2});
  d.helix_slope_um_per_mm = -0.05;
  d.helix_mid_mm = 39.0;
  d.helix_form = CubicBSpline(4.0, 75.0, {0.0, 2.0, -1.0, 1.5, -2.0, 0.3});
  return d;
}

// The contact height f(L, z) = w.n + sqrt(R^2 - |w_perp|^2), w = S(L, z) - p (mm): where the
// stylus centre stops on the line p + t n when the sphere touches S(L, z); -inf if out of reach.
inline double brute_force_contact_height(const AnalyticFlank& flank, const Eigen::Vector3d& p,
                                         const Eigen::Vector3d& n, double R, double L, double z) {
  const Eigen::Vector3d w = flank.point(L, z) - p;
  const double q2 = R * R - (w - w.dot(n) * n).squaredNorm();
  return q2 <= 0.0 ? -std::numeric_limits<double>::infinity() : w.dot(n) + std::sqrt(q2);
}

// First contact by search, not by Newton: maximise the contact height on nested 41 x 41 grids
// shrinking by 4 around the best point (`levels` levels, from +/- 0.6 R). Returns (L, z).
inline Eigen::Vector2d brute_force_contact(const AnalyticFlank& flank, const Eigen::Vector3d& p,
                                           const Eigen::Vector3d& n, double R, double L0, double z0,
                                           int levels = 16) {
  double L = L0, z = z0, half = 0.6 * R;
  for (int level = 0; level < levels; ++level) {
    double best = -std::numeric_limits<double>::infinity(), bL = L, bz = z;
    for (int a = -20; a <= 20; ++a) {
      for (int b = -20; b <= 20; ++b) {
        const double Lc = L + half * a / 20.0, zc = z + half * b / 20.0;
        const double f = brute_force_contact_height(flank, p, n, R, Lc, zc);
        if (f > best) best = f, bL = Lc, bz = zc;
      }
    }
    L = bL, z = bz, half *= 0.25;
  }
  return {L, z};
}

// brute_force_contact's answer as points: the contact C on the flank and the stylus centre O on
// the probing line p + h n.
struct BruteForcePoints {
  Eigen::Vector3d contact, centre;
};
inline BruteForcePoints brute_force_contact_points(const AnalyticFlank& flank,
                                                   const Eigen::Vector3d& p,
                                                   const Eigen::Vector3d& n, double R, double L0,
                                                   double z0) {
  const Eigen::Vector2d s = brute_force_contact(flank, p, n, R, L0, z0);
  return {flank.point(s[0], s[1]), p + brute_force_contact_height(flank, p, n, R, s[0], s[1]) * n};
}

// The global first contact by search over the whole footprint: the contact height on a
// (2 cells_z + 1)-node grid per unit of R, over [L0 - half_L, L0 + half_L] x [z0 - R, z0 + R],
// then brute_force_contact's nested shrinking grids (from +/- 2 grid steps) around each of the
// `candidates` highest grid nodes that are local maxima of the grid. Independent of the Newton
// solver and of its certificate. Returns (L, z, f).
struct BruteForceMaximum {
  double L, z, height;
};
inline BruteForceMaximum brute_force_global_contact(const AnalyticFlank& flank,
                                                    const Eigen::Vector3d& p,
                                                    const Eigen::Vector3d& n, double R, double L0,
                                                    double z0, double half_L, int cells = 120,
                                                    int candidates = 4, int levels = 10) {
  const int N = cells;
  const double dL = 2 * half_L / N, dz = 2 * R / N;
  std::vector<double> f(static_cast<std::size_t>((N + 1) * (N + 1)));
  auto at = [&](int i, int j) -> double& { return f[static_cast<std::size_t>(j * (N + 1) + i)]; };
  for (int j = 0; j <= N; ++j)
    for (int i = 0; i <= N; ++i)
      at(i, j) = brute_force_contact_height(flank, p, n, R, L0 - half_L + i * dL, z0 - R + j * dz);
  std::vector<std::pair<double, std::pair<int, int>>> peaks;
  for (int j = 0; j <= N; ++j) {
    for (int i = 0; i <= N; ++i) {
      if (!std::isfinite(at(i, j))) continue;
      bool peak = true;
      for (int a = -1; a <= 1; ++a)
        for (int b = -1; b <= 1; ++b)
          if ((a || b) && i + a >= 0 && i + a <= N && j + b >= 0 && j + b <= N &&
              at(i + a, j + b) > at(i, j))
            peak = false;
      if (peak) peaks.push_back({at(i, j), {i, j}});
    }
  }
  std::sort(peaks.begin(), peaks.end(),
            [](const auto& a, const auto& b) { return a.first > b.first; });
  BruteForceMaximum best{L0, z0, -std::numeric_limits<double>::infinity()};
  for (std::size_t c = 0; c < peaks.size() && c < static_cast<std::size_t>(candidates); ++c) {
    double L = L0 - half_L + peaks[c].second.first * dL, z = z0 - R + peaks[c].second.second * dz;
    double hL = 2 * dL, hz = 2 * dz, value = peaks[c].first;
    for (int level = 0; level < levels; ++level) {
      double bL = L, bz = z;
      for (int a = -10; a <= 10; ++a) {
        for (int b = -10; b <= 10; ++b) {
          const double Lc = L + hL * a / 10.0, zc = z + hz * b / 10.0;
          const double v = brute_force_contact_height(flank, p, n, R, Lc, zc);
          if (v > value) value = v, bL = Lc, bz = zc;
        }
      }
      L = bL, z = bz, hL *= 0.25, hz *= 0.25;
    }
    if (value > best.height) best = {L, z, value};
  }
  return best;
}

}  // namespace gearmc::testing_support
