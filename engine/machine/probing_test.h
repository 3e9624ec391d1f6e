// The probing part of a drawn CMM and the ISO 10360-5 probing test that constrains it. A
// touch-trigger probe's recorded centre lies a direction-dependent pre-travel p(d) further along
// the approach direction d than the touch (docs/effects.md, `probe_lobing`; P2), plus a random
// scatter. After the stylus qualification has taken out the constant part (the qualified radius),
// what remains is modelled as low-order lobing in the approach azimuth φ, fading towards the
// stylus axis (a trigger probe's pre-travel is least along its own axis):
//   p(d) = sin θ · Σ_{k=2..4} (c_k cos kφ + s_k sin kφ)   [µm],
// θ the angle between d and the stylus axis (−z), plus N(0, σ²) per touch. Order 1 would be a
// shift of every measured centre, which the qualification's sphere centre takes out too.
// The probing test (ISO 10360-5:2010 §6.2, form error P_FTU — standing: the point pattern is
// recalled, not checked against the text): 25 points on a reference sphere — one at the pole,
// four at 22.5° below it, eight at 45° (turned 22.5°), four at 67.5°, eight on the equator
// (turned 22.5°) — a least-squares sphere with free radius through them, and the range of the
// radial residuals. Units: µm for errors, directions unit vectors in the machine (= gear) frame.
#pragma once

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <vector>

namespace gearmc {

struct CmmProbe {
  std::array<double, 3> cos_um{}, sin_um{};  // c_k, s_k for k = 2, 3, 4
  double noise_um = 0.0;                     // σ of one touch
  // p(d), µm: the systematic pre-travel left after qualification for approach direction `d`.
  double pretravel_um(const Eigen::Vector3d& approach) const;
};

// The 25 outward directions of ISO 10360-5's sphere points (the stylus along −z, the pole +z).
std::vector<Eigen::Vector3d> probing_test_directions();

// P_FTU (µm) of `probe`: the 25 points touched once each (approach = −direction), the touch's
// scatter drawn from TrialStream(seed, index, kProbingTest), a least-squares sphere with free
// centre and radius fitted (linearised: errors of µm on a sphere of mm), the range of the radial
// residuals.
double probing_test_form_um(const CmmProbe& probe, std::uint64_t seed, std::uint64_t index);

// The same for given radial errors at the 25 directions (the fit and the range alone).
double sphere_form_um(const std::vector<Eigen::Vector3d>& directions,
                      const std::vector<double>& radial_error_um);

}  // namespace gearmc
