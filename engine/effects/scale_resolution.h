// The scales' resolution (`scale_resolution`): a CMM reads each axis from an incremental scale
// whose count has a finite step (the grating period divided by the interpolation factor), so the
// coordinates it records lie on a grid per axis: c_i ← s_i · round(c_i / s_i), s_i the step of
// axis i (the resolution of the indicating device, VIM 4.15; typical steps: 0.1–1 µm on older
// CMMs, 0.05 µm or finer on modern ones; recalled, unchecked).
//
// How it differs from `step_quantization` (engine/effects/effects.h): that effect latches the
// trigger at the next tick of the servo interpolation ALONG THE APPROACH (one-sided: the centre is
// recorded U(0, q) further along −n, mean shift −q/2 of the reading); the scale resolution rounds
// EACH AXIS COORDINATE to its own grid (symmetric about the true value: mean 0), whatever the
// approach direction. Along n a reading changes by Σ_i n_i δ_i with δ_i ∈ [−s_i/2, s_i/2]: over
// points whose true coordinates fall anywhere on the grid (the flank's positions vary by mm, the
// probing noise by tenths of a µm) δ_i is uniform, so the change has mean 0 and variance
// Σ n_i² s_i²/12 — s²/12 for equal steps, whatever n. It has no first-order signature (0: the
// expected reading does not move); what identifies it is that the recorded coordinates
// themselves lie on the grid (engine/apps/diagnose/coordinate_grid.h).
//
// Stage: kReadout, the last — the scales are read after everything else (probing noise included)
// has moved the ram. Parameters x_um, y_um, z_um (µm; 0 = that axis not latched).
#pragma once

#include "engine/effects/measurement_effect.h"

namespace gearmc {

class ScaleResolutionEffect : public MeasurementEffect {
 public:
  ScaleResolutionEffect(EffectParameter x_um, EffectParameter y_um, EffectParameter z_um);
  std::string_view name() const override { return "scale_resolution"; }
  EffectStage stage() const override { return EffectStage::kReadout; }
  void apply(const PointContext& point, std::span<const double> values, Eigen::Vector3d& centre_mm,
             RandomStream& rng) const override;
  // 0 for every parameter: the rounding's mean over the grid phase (see above).
  void signature(const PointContext& point, std::span<const double> values,
                 std::span<double> out) const override;
  // The expected recorded centre is the true one (mean 0 of the rounding): nothing moves.
  void apply_mean(const PointContext&, std::span<const double>, Eigen::Vector3d&) const override {}
  // The rounding's spread along n as a Gaussian part of the same variance: max_i s_i²/12 (exact
  // for equal steps on the axes n spans, an upper bound otherwise; the law along n is the sum of
  // uniforms n_i U(−s_i/2, s_i/2), close to Gaussian once the probing noise is added).
  PointLaw point_law(std::span<const double> values) const override;
};

// c_i rounded to the grid of step `step_um` (µm) on that axis, in mm; a step ≤ 0 leaves it.
double latch_to_grid_mm(double coordinate_mm, double step_um);

}  // namespace gearmc
