// Numeric constants used across the layers, defined once: π, the radian per degree, the
// non-finite doubles, and µm per mm (every length inside gearmc is in mm; outputs print µm).
#pragma once

#include <limits>
#include <numbers>

namespace gearmc {

inline constexpr double kPi = std::numbers::pi;
inline constexpr double kDeg = std::numbers::pi / 180.0;  // rad per degree
inline constexpr double kInf = std::numeric_limits<double>::infinity();
inline constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
inline constexpr double kUmPerMm = 1000.0;
inline constexpr double kEulerGamma = std::numbers::egamma;  // γ, Euler–Mascheroni

}  // namespace gearmc
