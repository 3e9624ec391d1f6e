// A wavy deviation form for the contact certificate's tests: `count` B-spline coefficients
// alternating -amplitude, +amplitude (µm) over [t0, t1] (mm), shared by the curvature-bound
// tests of spur, helical and internal flanks.
#pragma once

#include <vector>

#include "gears/deviations.h"

namespace gearmc::testing_support {

inline CubicBSpline alternating_form(double t0, double t1, int count, double amplitude) {
  std::vector<double> c;
  for (int i = 0; i < count; ++i) c.push_back(i % 2 ? amplitude : -amplitude);
  return CubicBSpline(t0, t1, c);
}

}  // namespace gearmc::testing_support
