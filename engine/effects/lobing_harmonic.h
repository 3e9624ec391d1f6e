// One harmonic of a probe's pre-travel against the approach azimuth φ (docs/sources.md [P2],
// docs/reference-values.md "Probe pre-travel and lobing"):
//   p(φ) = p0 + Σ_k a_k cos(k (φ − φ_k))   [µm]
// The one type for every place that speaks of lobing harmonics: the `probe_lobing` effect's
// model (probe_lobing.h), the Fourier analysis of the CVODE probe model's p(φ)
// (probe_dynamics.h) and the diagnosis's fitted lobing. φ_k is in degrees, as scenario files
// and reports give it.
#pragma once

#include <cmath>
#include <numbers>

namespace gearmc {

struct LobingHarmonic {
  int order = 6;              // k, lobes per turn
  double amplitude_um = 0.0;  // a_k, µm
  double phase_deg = 0.0;     // φ_k: azimuth of a maximum, degrees

  // a_k cos(k (φ − φ_k)), µm, at approach azimuth φ (radians).
  double value_um(double azimuth_rad) const {
    return amplitude_um * std::cos(order * (azimuth_rad - phase_deg * (std::numbers::pi / 180.0)));
  }

  // The linear components of a_k cos(k (φ − φ_k)) = c cos kφ + s sin kφ (µm):
  // c = a_k cos(k φ_k), s = a_k sin(k φ_k).
  double cos_component_um() const {
    return amplitude_um * std::cos(order * (phase_deg * std::numbers::pi / 180.0));
  }
  double sin_component_um() const {
    return amplitude_um * std::sin(order * (phase_deg * std::numbers::pi / 180.0));
  }

  // The harmonic of order k with components c, s (µm): a_k = √(c² + s²), φ_k = atan2(s, c)/k
  // reduced to [0, 360/k) degrees.
  static LobingHarmonic from_components(int order, double c_um, double s_um) {
    const double period = 360.0 / order;
    double deg = std::atan2(s_um, c_um) * 180.0 / std::numbers::pi / order;
    deg = std::fmod(deg, period);
    if (deg < 0.0) deg += period;
    return {order, std::hypot(c_um, s_um), deg};
  }
};

}  // namespace gearmc
