// The library of measurement effects besides probe lobing (names from docs/formats.md):
// what each models, its parameters with units, and the closed-form signature where it is
// linear. All act on the recorded stylus centre c (CMM frame = gear frame, mm). Workpiece
// effects (eccentricity, thermal expansion) move the real surface; they are applied to the
// stylus centre at contact, which is exact for a translation and first-order exact for a
// uniform expansion (the contact point moves with the surface; the normal changes by < 1e-5 rad).
#pragma once

#include "engine/effects/measurement_effect.h"

namespace gearmc {

// `eccentricity` (set-up): the gear axis sits off the datum axis by (x_um, y_um): every point of
// the real surface, hence the stylus centre at contact, moves by that vector.
class EccentricityEffect : public MeasurementEffect {
 public:
  EccentricityEffect(EffectParameter x_um, EffectParameter y_um);
  std::string_view name() const override { return "eccentricity"; }
  EffectStage stage() const override { return EffectStage::kWorkpiece; }
  void apply(const PointContext& point, std::span<const double> values, Eigen::Vector3d& centre_mm,
             RandomStream& rng) const override;
  void signature(const PointContext& point, std::span<const double> values,
                 std::span<double> out) const override;
};

// `clocking` (set-up): the gear sits turned about its axis (z, through the origin) by angle_urad
// (counter-clockwise seen from +z) from where the plan's angular datum puts it — the datum tooth
// found off, or the gear clamped turned: every point of the real surface, hence the stylus centre
// at contact, turns by that angle, c ← R_z(θ) c. Along the normal the reading moves by
// θ (ẑ × p)·n, which on an involute flank is ±r_b θ (the two flanks of a tooth in opposite
// directions, every tooth alike); a squareness xy error γ contains a rotation −γ/2 besides its
// shear.
class ClockingEffect : public MeasurementEffect {
 public:
  explicit ClockingEffect(EffectParameter angle_urad);
  std::string_view name() const override { return "clocking"; }
  EffectStage stage() const override { return EffectStage::kWorkpiece; }
  void apply(const PointContext& point, std::span<const double> values, Eigen::Vector3d& centre_mm,
             RandomStream& rng) const override;
  void signature(const PointContext& point, std::span<const double> values,
                 std::span<double> out) const override;
};

// `thermal_expansion`: the workpiece at 20 °C + workpiece_delta_t_k expands by its CTE, the
// CMM's scales at 20 °C + scale_delta_t_k by theirs, and the CMM reads positions in scale
// units: c ← c (1 + α_w ΔT_w − α_s ΔT_s) about the gear centre (ISO 1 reference temperature).
// Parameters: workpiece_delta_t_k (K), scale_delta_t_k (K), workpiece_cte_ppm_per_k (steel
// 11.5), scale_cte_ppm_per_k (glass-ceramic ≈ 0, steel 11.5).
class ThermalExpansionEffect : public MeasurementEffect {
 public:
  ThermalExpansionEffect(EffectParameter workpiece_delta_t_k, EffectParameter scale_delta_t_k,
                         EffectParameter workpiece_cte_ppm_per_k,
                         EffectParameter scale_cte_ppm_per_k);
  std::string_view name() const override { return "thermal_expansion"; }
  EffectStage stage() const override { return EffectStage::kWorkpiece; }
  void apply(const PointContext& point, std::span<const double> values, Eigen::Vector3d& centre_mm,
             RandomStream& rng) const override;
};

// `stylus_radius`: the radius the software uses (from qualification) is error_um larger than
// the stylus's effective radius, so every reading comes out error_um too small along n.
class StylusRadiusEffect : public MeasurementEffect {
 public:
  explicit StylusRadiusEffect(EffectParameter error_um);
  std::string_view name() const override { return "stylus_radius"; }
  EffectStage stage() const override { return EffectStage::kProbe; }
  void apply(const PointContext& point, std::span<const double> values, Eigen::Vector3d& centre_mm,
             RandomStream& rng) const override;
  void signature(const PointContext& point, std::span<const double> values,
                 std::span<double> out) const override;
};

// `tip_form`: the stylus ball's radius varies with the direction of contact on the ball,
// r(ψ) = R + amplitude·cos(order (ψ − phase)), ψ the azimuth of the contact normal (the ball
// touches the flank at −m, m the real outward normal). A larger radius there holds the centre
// further from the surface: c ← c + m (r(ψ) − R). Parameters: amplitude_um, phase_deg; the
// order (lobes of the ball's form) is a setting.
class TipFormEffect : public MeasurementEffect {
 public:
  TipFormEffect(int order, EffectParameter amplitude_um, EffectParameter phase_deg);
  std::string_view name() const override { return "tip_form"; }
  EffectStage stage() const override { return EffectStage::kProbe; }
  void apply(const PointContext& point, std::span<const double> values, Eigen::Vector3d& centre_mm,
             RandomStream& rng) const override;

 private:
  int order_;
};

// `scale`: each CMM axis reads (1 + s) times the true displacement from the origin (the gear
// centre): c_i ← c_i (1 + s_i 1e-6). Parameters x_ppm, y_ppm, z_ppm.
class ScaleEffect : public MeasurementEffect {
 public:
  ScaleEffect(EffectParameter x_ppm, EffectParameter y_ppm, EffectParameter z_ppm);
  std::string_view name() const override { return "scale"; }
  EffectStage stage() const override { return EffectStage::kMachine; }
  void apply(const PointContext& point, std::span<const double> values, Eigen::Vector3d& centre_mm,
             RandomStream& rng) const override;
  void signature(const PointContext& point, std::span<const double> values,
                 std::span<double> out) const override;
};

// `squareness`: out-of-squareness of the axis pairs as small shears (µrad):
// c_x ← c_x + θ_xy c_y + θ_xz c_z, c_y ← c_y + θ_yz c_z (θ > 0: the first axis leans towards
// the second one's positive direction). Parameters xy_urad, xz_urad, yz_urad.
class SquarenessEffect : public MeasurementEffect {
 public:
  SquarenessEffect(EffectParameter xy_urad, EffectParameter xz_urad, EffectParameter yz_urad);
  std::string_view name() const override { return "squareness"; }
  EffectStage stage() const override { return EffectStage::kMachine; }
  void apply(const PointContext& point, std::span<const double> values, Eigen::Vector3d& centre_mm,
             RandomStream& rng) const override;
  void signature(const PointContext& point, std::span<const double> values,
                 std::span<double> out) const override;
};

// `drift`: the CMM's reading of the workpiece drifts linearly over the probing sequence (warm-up,
// temperature change): c ← c + d·order/(sequence_length − 1), d = (x_um, y_um, z_um) reached at
// the last point.
class DriftEffect : public MeasurementEffect {
 public:
  DriftEffect(EffectParameter x_um, EffectParameter y_um, EffectParameter z_um);
  std::string_view name() const override { return "drift"; }
  EffectStage stage() const override { return EffectStage::kMachine; }
  void apply(const PointContext& point, std::span<const double> values, Eigen::Vector3d& centre_mm,
             RandomStream& rng) const override;
  void signature(const PointContext& point, std::span<const double> values,
                 std::span<double> out) const override;
};

// `step_quantization`: the controller latches the trigger at the next tick of the servo
// interpolation grid along the approach (P1 names "the discretisation step of the probe approach
// caused by the interpolation step of the servo drives" as future work, without a model). The
// grid's positions along the travel are φ q + k q (k = 0, 1, …) with q the step; the travel s
// to the trigger is rounded up to the next grid position, so the centre is recorded
// u ∈ [0, q) further along −n. The phase φ of the grid at the start of the approach is drawn
// uniform on [0, 1) at every point: it would be fixed only if the servo cycle were synchronised
// with the surface to a fraction of a step, while the start position's servo error, the probe's
// trigger jitter and the flank's own deviations each move the trigger by that much. So u is
// U(0, q) at every point, independent of s (the approach start p + (R + approach_mm) n only
// fixes s). Parameter step_um; approach_mm is a setting. Mean −q/2 along n (the first-order
// signature, −1/2 per µm of q); per-point law −U(0, q) about the travel (point_law).
class StepQuantizationEffect : public MeasurementEffect {
 public:
  StepQuantizationEffect(EffectParameter step_um, double approach_mm);
  std::string_view name() const override { return "step_quantization"; }
  EffectStage stage() const override { return EffectStage::kController; }
  void apply(const PointContext& point, std::span<const double> values, Eigen::Vector3d& centre_mm,
             RandomStream& rng) const override;
  void signature(const PointContext& point, std::span<const double> values,
                 std::span<double> out) const override;
  void apply_mean(const PointContext& point, std::span<const double> values,
                  Eigen::Vector3d& centre_mm) const override;
  PointLaw point_law(std::span<const double> values) const override;

 private:
  double approach_mm_;
};

// `noise`: random probing noise, independent N(0, sigma²) on each CMM axis at each point.
class NoiseEffect : public MeasurementEffect {
 public:
  explicit NoiseEffect(EffectParameter sigma_um);
  std::string_view name() const override { return "noise"; }
  EffectStage stage() const override { return EffectStage::kNoise; }
  void apply(const PointContext& point, std::span<const double> values, Eigen::Vector3d& centre_mm,
             RandomStream& rng) const override;
  void signature(const PointContext& point, std::span<const double> values,
                 std::span<double> out) const override;
  void apply_mean(const PointContext&, std::span<const double>, Eigen::Vector3d&) const override {}
  // Isotropic N(0, σ²) on each axis is N(0, σ²) along any unit n.
  PointLaw point_law(std::span<const double> values) const override;
};

}  // namespace gearmc
