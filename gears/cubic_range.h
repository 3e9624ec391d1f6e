// The exact range of a cubic on an interval, shared by the B-spline's value ranges
// (cubic_bspline.cpp) and the sampler's trace bands (deviations.cpp). Not part of the library's
// interface.
#pragma once

#include <array>

namespace gearmc {

// Widens [*lo, *hi] by the values of the cubic q0 + q1 u + q2 u^2 + q3 u^3 on [0, h] (exact: its
// ends and the real roots of its derivative inside the interval).
void widen_by_cubic(const std::array<double, 4>& q, double h, double* lo, double* hi);

}  // namespace gearmc
