// Two effects of real CMMs beyond the first library: the probe's pre-travel drifting as the probe
// warms up over a measurement (`probe_warmup`), and the straightness of the machine's axes
// (`straightness`). Both act on the recorded stylus centre c (CMM frame = gear frame, mm) and
// have closed-form signatures (linear in their parameters).
#pragma once

#include "engine/effects/measurement_effect.h"

namespace gearmc {

// `probe_warmup`: a touch-trigger probe's pre-travel changes while the probe and its stylus warm
// up after being switched on or after a probe change (the seat's springs and the stylus expand;
// the change settles like a first-order thermal system, Newton's law of heating). Over one
// gear's probing sequence, s = order / (sequence_length − 1) ∈ [0, 1]:
//   Δp(s) = change_um · w(s),  w(s) = (1 − e^(−s/τ)) / (1 − e^(−1/τ)),
// so Δp(0) = 0 and Δp(1) = change_um; τ (setting `time_constant`, a fraction of the sequence) is
// the thermal time constant. More pre-travel records the centre further along the approach −n:
// c ← c − Δp n / 1000, the reading changes by −Δp (signature −w(s)). Parameter change_um (µm);
// setting time_constant (> 0, default 0.3).
class ProbeWarmupEffect : public MeasurementEffect {
 public:
  ProbeWarmupEffect(EffectParameter change_um, double time_constant);
  std::string_view name() const override { return "probe_warmup"; }
  EffectStage stage() const override { return EffectStage::kProbe; }
  void apply(const PointContext& point, std::span<const double> values, Eigen::Vector3d& centre_mm,
             RandomStream& rng) const override;
  void signature(const PointContext& point, std::span<const double> values,
                 std::span<double> out) const override;
  // w(s) above.
  double weight(const PointContext& point) const;
  double time_constant() const { return time_constant_; }

 private:
  double time_constant_;
};

// `straightness`: the guideways of the X and Y axes are not straight: as the carriage moves along
// one axis, the position read on another axis deviates by a bow (ISO 230-1 straightness,
// quadratic in the travel). With L the setting `length_mm` and the bow's vertex at the gear centre:
//   c_x ← c_x + (xy_um (c_y/L)² + xz_um (c_z/L)²) / 1000,
//   c_y ← c_y + (yx_um (c_x/L)² + yz_um (c_z/L)²) / 1000,
// (xy_um: the X reading's deviation, µm, at a Y travel of L from the centre). Only the quadratic
// part is this effect: a straightness's linear part is the squareness effect, its constant a
// translation (eccentricity). Parameters xy_um, xz_um, yx_um, yz_um (µm at L); setting length_mm
// (default 100 mm). Signature: n_x (c_y/L)², n_x (c_z/L)², n_y (c_x/L)², n_y (c_z/L)² at
// c = p + R n.
class StraightnessEffect : public MeasurementEffect {
 public:
  StraightnessEffect(EffectParameter xy_um, EffectParameter xz_um, EffectParameter yx_um,
                     EffectParameter yz_um, double length_mm);
  std::string_view name() const override { return "straightness"; }
  EffectStage stage() const override { return EffectStage::kMachine; }
  void apply(const PointContext& point, std::span<const double> values, Eigen::Vector3d& centre_mm,
             RandomStream& rng) const override;
  void signature(const PointContext& point, std::span<const double> values,
                 std::span<double> out) const override;
  double length_mm() const { return length_mm_; }

 private:
  double length_mm_;
};

}  // namespace gearmc
