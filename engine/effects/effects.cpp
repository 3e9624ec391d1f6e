// The measurement effects of effects.h: apply() and the closed-form signatures.
#include "engine/effects/effects.h"

#include <cmath>
#include <numbers>

#include "core/constants.h"

namespace gearmc {

EccentricityEffect::EccentricityEffect(EffectParameter x_um, EffectParameter y_um)
    : MeasurementEffect(
          {named(std::move(x_um), "x_um", "µm"), named(std::move(y_um), "y_um", "µm")}) {}
void EccentricityEffect::apply(const PointContext&, std::span<const double> v, Eigen::Vector3d& c,
                               RandomStream&) const {
  c.x() += 1e-3 * v[0];
  c.y() += 1e-3 * v[1];
}
void EccentricityEffect::signature(const PointContext& point, std::span<const double>,
                                   std::span<double> out) const {
  out[0] = point.n.x();
  out[1] = point.n.y();
}

ClockingEffect::ClockingEffect(EffectParameter angle_urad)
    : MeasurementEffect({named(std::move(angle_urad), "angle_urad", "µrad")}) {}
void ClockingEffect::apply(const PointContext&, std::span<const double> v, Eigen::Vector3d& c,
                           RandomStream&) const {
  const double angle = 1e-6 * v[0];
  const double cos_a = std::cos(angle), sin_a = std::sin(angle);
  c = Eigen::Vector3d(cos_a * c.x() - sin_a * c.y(), sin_a * c.x() + cos_a * c.y(), c.z());
}
void ClockingEffect::signature(const PointContext& point, std::span<const double>,
                               std::span<double> out) const {
  // d(c·n)/dθ at θ = 0 is (ẑ × c)·n = (ẑ × p)·n (ẑ × n ⟂ n), in µm per µrad: mm × 1e-6 × 1e3.
  out[0] = 1e-3 * (point.p.x() * point.n.y() - point.p.y() * point.n.x());
}

ThermalExpansionEffect::ThermalExpansionEffect(EffectParameter workpiece_delta_t_k,
                                               EffectParameter scale_delta_t_k,
                                               EffectParameter workpiece_cte_ppm_per_k,
                                               EffectParameter scale_cte_ppm_per_k)
    : MeasurementEffect(
          {named(std::move(workpiece_delta_t_k), "workpiece_delta_t_k", "K"),
           named(std::move(scale_delta_t_k), "scale_delta_t_k", "K"),
           named(std::move(workpiece_cte_ppm_per_k), "workpiece_cte_ppm_per_k", "ppm/K"),
           named(std::move(scale_cte_ppm_per_k), "scale_cte_ppm_per_k", "ppm/K")}) {}
void ThermalExpansionEffect::apply(const PointContext&, std::span<const double> v,
                                   Eigen::Vector3d& c, RandomStream&) const {
  c *= 1.0 + 1e-6 * (v[2] * v[0] - v[3] * v[1]);
}

StylusRadiusEffect::StylusRadiusEffect(EffectParameter error_um)
    : MeasurementEffect({named(std::move(error_um), "error_um", "µm")}) {}
void StylusRadiusEffect::apply(const PointContext& point, std::span<const double> v,
                               Eigen::Vector3d& c, RandomStream&) const {
  c -= point.n * (1e-3 * v[0]);
}
void StylusRadiusEffect::signature(const PointContext&, std::span<const double>,
                                   std::span<double> out) const {
  out[0] = -1.0;
}

TipFormEffect::TipFormEffect(int order, EffectParameter amplitude_um, EffectParameter phase_deg)
    : MeasurementEffect({named(std::move(amplitude_um), "amplitude_um", "µm"),
                         named(std::move(phase_deg), "phase_deg", "deg")}),
      order_(order) {}
void TipFormEffect::apply(const PointContext& point, std::span<const double> v, Eigen::Vector3d& c,
                          RandomStream&) const {
  const Eigen::Vector3d& m = point.contact_normal;
  const double psi = std::atan2(m.y(), m.x());
  c += m * (1e-3 * v[0] * std::cos(order_ * (psi - v[1] * kDeg)));
}

ScaleEffect::ScaleEffect(EffectParameter x_ppm, EffectParameter y_ppm, EffectParameter z_ppm)
    : MeasurementEffect({named(std::move(x_ppm), "x_ppm", "ppm"),
                         named(std::move(y_ppm), "y_ppm", "ppm"),
                         named(std::move(z_ppm), "z_ppm", "ppm")}) {}
void ScaleEffect::apply(const PointContext&, std::span<const double> v, Eigen::Vector3d& c,
                        RandomStream&) const {
  for (int i = 0; i < 3; ++i) c[i] *= 1.0 + 1e-6 * v[i];
}
void ScaleEffect::signature(const PointContext& point, std::span<const double>,
                            std::span<double> out) const {
  // 1e-6 per ppm times c_i n_i (mm) times 1000 µm/mm, at the nominal centre.
  const Eigen::Vector3d c = point.p + point.stylus_radius_mm * point.n;
  for (int i = 0; i < 3; ++i) out[i] = 1e-3 * c[i] * point.n[i];
}

SquarenessEffect::SquarenessEffect(EffectParameter xy_urad, EffectParameter xz_urad,
                                   EffectParameter yz_urad)
    : MeasurementEffect({named(std::move(xy_urad), "xy_urad", "µrad"),
                         named(std::move(xz_urad), "xz_urad", "µrad"),
                         named(std::move(yz_urad), "yz_urad", "µrad")}) {}
void SquarenessEffect::apply(const PointContext&, std::span<const double> v, Eigen::Vector3d& c,
                             RandomStream&) const {
  const Eigen::Vector3d c0 = c;
  c.x() += 1e-6 * (v[0] * c0.y() + v[1] * c0.z());
  c.y() += 1e-6 * v[2] * c0.z();
}
void SquarenessEffect::signature(const PointContext& point, std::span<const double>,
                                 std::span<double> out) const {
  const Eigen::Vector3d c = point.p + point.stylus_radius_mm * point.n;
  out[0] = 1e-3 * point.n.x() * c.y();
  out[1] = 1e-3 * point.n.x() * c.z();
  out[2] = 1e-3 * point.n.y() * c.z();
}

DriftEffect::DriftEffect(EffectParameter x_um, EffectParameter y_um, EffectParameter z_um)
    : MeasurementEffect({named(std::move(x_um), "x_um", "µm"), named(std::move(y_um), "y_um", "µm"),
                         named(std::move(z_um), "z_um", "µm")}) {}
namespace {
double sequence_fraction(const PointContext& point) {
  return point.sequence_length > 1 ? static_cast<double>(point.order) / (point.sequence_length - 1)
                                   : 0.0;
}
}  // namespace
void DriftEffect::apply(const PointContext& point, std::span<const double> v, Eigen::Vector3d& c,
                        RandomStream&) const {
  const double f = 1e-3 * sequence_fraction(point);
  c += f * Eigen::Vector3d(v[0], v[1], v[2]);
}
void DriftEffect::signature(const PointContext& point, std::span<const double>,
                            std::span<double> out) const {
  const double f = sequence_fraction(point);
  for (int i = 0; i < 3; ++i) out[i] = f * point.n[i];
}

StepQuantizationEffect::StepQuantizationEffect(EffectParameter step_um, double approach_mm)
    : MeasurementEffect({named(std::move(step_um), "step_um", "µm")}), approach_mm_(approach_mm) {}
void StepQuantizationEffect::apply(const PointContext& point, std::span<const double> v,
                                   Eigen::Vector3d& c, RandomStream& rng) const {
  const double q = 1e-3 * v[0];        // mm
  const double phase = rng.uniform();  // always drawn: fixed stream use
  if (q <= 0.0) return;
  const Eigen::Vector3d start = point.p + (point.stylus_radius_mm + approach_mm_) * point.n;
  const double s = (start - c).dot(point.n);  // travel along −n to the trigger, mm
  // The first grid position φq + kq at or beyond s.
  const double latched = (std::ceil(s / q - phase) + phase) * q;
  c -= point.n * (latched - s);
}
void StepQuantizationEffect::signature(const PointContext&, std::span<const double>,
                                       std::span<double> out) const {
  out[0] = -0.5;
}
void StepQuantizationEffect::apply_mean(const PointContext& point, std::span<const double> v,
                                        Eigen::Vector3d& c) const {
  if (v[0] > 0.0) c -= point.n * (0.5e-3 * v[0]);  // E u = q/2
}
PointLaw StepQuantizationEffect::point_law(std::span<const double> v) const {
  PointLaw law;
  if (v[0] > 0.0) law.uniform_widths_um.push_back(v[0]);
  return law;
}

NoiseEffect::NoiseEffect(EffectParameter sigma_um)
    : MeasurementEffect({named(std::move(sigma_um), "sigma_um", "µm")}) {}
void NoiseEffect::apply(const PointContext&, std::span<const double> v, Eigen::Vector3d& c,
                        RandomStream& rng) const {
  for (int i = 0; i < 3; ++i) c[i] += 1e-3 * v[0] * rng.normal();
}
PointLaw NoiseEffect::point_law(std::span<const double> v) const {
  return PointLaw{v[0] * v[0], {}};
}
void NoiseEffect::signature(const PointContext&, std::span<const double>,
                            std::span<double> out) const {
  out[0] = 0.0;  // zero-mean: no first-order systematic change of the reading
}

}  // namespace gearmc
