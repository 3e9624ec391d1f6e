// The scales' resolution: coordinates latched on each axis's grid (see scale_resolution.h).
#include "engine/effects/scale_resolution.h"

#include <algorithm>
#include <cmath>

namespace gearmc {

double latch_to_grid_mm(double coordinate_mm, double step_um) {
  if (!(step_um > 0.0)) return coordinate_mm;
  const double step_mm = 1e-3 * step_um;
  return step_mm * std::round(coordinate_mm / step_mm);
}

ScaleResolutionEffect::ScaleResolutionEffect(EffectParameter x_um, EffectParameter y_um,
                                             EffectParameter z_um)
    : MeasurementEffect({named(std::move(x_um), "x_um", "µm"), named(std::move(y_um), "y_um", "µm"),
                         named(std::move(z_um), "z_um", "µm")}) {}

void ScaleResolutionEffect::apply(const PointContext&, std::span<const double> v,
                                  Eigen::Vector3d& c, RandomStream&) const {
  for (int i = 0; i < 3; ++i) c[i] = latch_to_grid_mm(c[i], v[i]);
}

void ScaleResolutionEffect::signature(const PointContext&, std::span<const double>,
                                      std::span<double> out) const {
  std::fill(out.begin(), out.end(), 0.0);
}

PointLaw ScaleResolutionEffect::point_law(std::span<const double> v) const {
  double largest = 0.0;
  for (int i = 0; i < 3; ++i) largest = std::max(largest, std::max(0.0, v[i]));
  return PointLaw{largest * largest / 12.0, {}};
}

}  // namespace gearmc
