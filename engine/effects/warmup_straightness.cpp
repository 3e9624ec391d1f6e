// Probe warm-up and axis straightness (see warmup_straightness.h).
#include "engine/effects/warmup_straightness.h"

#include <cmath>

namespace gearmc {

ProbeWarmupEffect::ProbeWarmupEffect(EffectParameter change_um, double time_constant)
    : MeasurementEffect({named(std::move(change_um), "change_um", "µm")}),
      time_constant_(time_constant) {}

double ProbeWarmupEffect::weight(const PointContext& point) const {
  const double s = point.sequence_length > 1
                       ? static_cast<double>(point.order) / (point.sequence_length - 1)
                       : 0.0;
  return std::expm1(-s / time_constant_) / std::expm1(-1.0 / time_constant_);
}

void ProbeWarmupEffect::apply(const PointContext& point, std::span<const double> v,
                              Eigen::Vector3d& c, RandomStream&) const {
  c -= 1e-3 * v[0] * weight(point) * point.n;
}

void ProbeWarmupEffect::signature(const PointContext& point, std::span<const double>,
                                  std::span<double> out) const {
  out[0] = -weight(point);
}

StraightnessEffect::StraightnessEffect(EffectParameter xy_um, EffectParameter xz_um,
                                       EffectParameter yx_um, EffectParameter yz_um,
                                       double length_mm)
    : MeasurementEffect(
          {named(std::move(xy_um), "xy_um", "µm"), named(std::move(xz_um), "xz_um", "µm"),
           named(std::move(yx_um), "yx_um", "µm"), named(std::move(yz_um), "yz_um", "µm")}),
      length_mm_(length_mm) {}

void StraightnessEffect::apply(const PointContext&, std::span<const double> v, Eigen::Vector3d& c,
                               RandomStream&) const {
  const Eigen::Vector3d u = c / length_mm_;
  const double dx = v[0] * u.y() * u.y() + v[1] * u.z() * u.z();
  const double dy = v[2] * u.x() * u.x() + v[3] * u.z() * u.z();
  c.x() += 1e-3 * dx;
  c.y() += 1e-3 * dy;
}

void StraightnessEffect::signature(const PointContext& point, std::span<const double>,
                                   std::span<double> out) const {
  const Eigen::Vector3d u = (point.p + point.stylus_radius_mm * point.n) / length_mm_;
  out[0] = point.n.x() * u.y() * u.y();
  out[1] = point.n.x() * u.z() * u.z();
  out[2] = point.n.y() * u.x() * u.x();
  out[3] = point.n.y() * u.z() * u.z();
}

}  // namespace gearmc
