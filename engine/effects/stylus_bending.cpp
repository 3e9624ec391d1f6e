// Stylus bending under the lateral part of the probing force (see stylus_bending.h).
#include "engine/effects/stylus_bending.h"

namespace gearmc {

StylusBendingEffect::StylusBendingEffect(EffectParameter deflection_um,
                                         const Eigen::Vector3d& stylus_axis)
    : MeasurementEffect({[&] {
        deflection_um.name = "deflection_um";
        deflection_um.unit = "µm";
        return std::move(deflection_um);
      }()}),
      axis_(stylus_axis.normalized()) {}

void StylusBendingEffect::apply(const PointContext& point, std::span<const double> v,
                                Eigen::Vector3d& c, RandomStream&) const {
  const Eigen::Vector3d& n = point.contact_normal;
  c -= 1e-3 * v[0] * (n - n.dot(axis_) * axis_);
}

void StylusBendingEffect::signature(const PointContext& point, std::span<const double>,
                                    std::span<double> out) const {
  const double along = point.n.dot(axis_);
  out[0] = -(1.0 - along * along);
}

}  // namespace gearmc
