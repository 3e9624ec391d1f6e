// The probing part of a drawn CMM and ISO 10360-5's probing test (probing_test.h).
#include "engine/machine/probing_test.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <numbers>

#include "core/random_stream.h"

namespace gearmc {

double CmmProbe::pretravel_um(const Eigen::Vector3d& approach) const {
  // sin θ from the horizontal part of d; φ its azimuth.
  const double horizontal = std::hypot(approach.x(), approach.y());
  if (horizontal < 1e-12) return 0.0;
  const double phi = std::atan2(approach.y(), approach.x());
  double p = 0.0;
  for (int i = 0; i < 3; ++i) {
    const int k = i + 2;
    p += cos_um[static_cast<std::size_t>(i)] * std::cos(k * phi) +
         sin_um[static_cast<std::size_t>(i)] * std::sin(k * phi);
  }
  return horizontal * p;
}

std::vector<Eigen::Vector3d> probing_test_directions() {
  std::vector<Eigen::Vector3d> out;
  const double deg = std::numbers::pi / 180.0;
  out.emplace_back(0.0, 0.0, 1.0);
  // (polar angle from the pole, points, azimuth of the first)
  const struct {
    double polar_deg;
    int count;
    double start_deg;
  } rings[] = {{22.5, 4, 0.0}, {45.0, 8, 22.5}, {67.5, 4, 0.0}, {90.0, 8, 22.5}};
  for (const auto& r : rings) {
    for (int i = 0; i < r.count; ++i) {
      const double az = (r.start_deg + 360.0 * i / r.count) * deg;
      const double s = std::sin(r.polar_deg * deg);
      out.emplace_back(s * std::cos(az), s * std::sin(az), std::cos(r.polar_deg * deg));
    }
  }
  return out;
}

double sphere_form_um(const std::vector<Eigen::Vector3d>& directions,
                      const std::vector<double>& radial_error_um) {
  // A sphere shifted by c (µm) and grown by ρ (µm) moves the radial distance at direction v by
  // v·c + ρ, to first order: the fit is linear least squares of e ≈ v·c + ρ.
  const Eigen::Index n = static_cast<Eigen::Index>(directions.size());
  Eigen::MatrixXd a(n, 4);
  Eigen::VectorXd e(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    a.row(i) << directions[static_cast<std::size_t>(i)].transpose(), 1.0;
    e[i] = radial_error_um[static_cast<std::size_t>(i)];
  }
  const Eigen::VectorXd x = a.colPivHouseholderQr().solve(e);
  const Eigen::VectorXd r = e - a * x;
  return r.maxCoeff() - r.minCoeff();
}

double probing_test_form_um(const CmmProbe& probe, std::uint64_t seed, std::uint64_t index) {
  TrialStream rng(seed, index, TrialPurpose::kProbingTest);
  const std::vector<Eigen::Vector3d> v = probing_test_directions();
  std::vector<double> radial(v.size());
  for (std::size_t i = 0; i < v.size(); ++i) {
    // The recorded centre lies p further along the approach −v: the radius reads p shorter.
    radial[i] = -(probe.pretravel_um(-v[i]) + probe.noise_um * rng.normal());
  }
  return sphere_form_um(v, radial);
}

}  // namespace gearmc
