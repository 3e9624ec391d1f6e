// Stylus bending (`stylus_bending`): the stylus bends under the probing force, so the machine has
// travelled further than the tip when the probe triggers. The stylus is a cantilever clamped in
// the probe; a lateral force F at the tip bends it by δ = F L³ / (3 E I) (Euler–Bernoulli
// cantilever with an end load; e.g. Gere & Goodno, Mechanics of Materials, table of beam
// deflections; I = π d⁴ / 64 for a round stem of diameter d), and its axial stiffness is orders
// larger, so only the force's component across the stylus bends it. With the contact force along
// the surface normal n and the stylus axis s (unit), the lateral component is F (n − (n·s) s), of
// size F sin γ (γ: the angle between the approach direction −n and the stylus axis), and the tip
// deflects by δ₉₀ (n − (n·s) s), δ₉₀ = F L³ / (3 E I) the deflection at γ = 90°. The recorded
// centre lies that far behind the tip:
//   c ← c − 10⁻³ δ₉₀ (n_c − (n_c·s) s),   reading change −δ₉₀ sin²γ = −δ₉₀ (1 − (n·s)²) µm,
// n_c the real surface's normal at contact (the force's direction), n the nominal one.
// Parameter deflection_um = δ₉₀ (µm): the part of the bending that the stylus's qualification on
// the reference sphere did not take up (the qualification's effective radius already contains
// the mean bending over its own directions). Setting stylus_axis: z (default, a vertical stylus),
// x or y (a horizontal stylus of a star).
//
// What a plan can tell: with a vertical stylus every approach to a spur gear's flanks is
// horizontal (γ = 90°), so the signature is the constant −1 — exactly a stylus radius error (and
// the constant part of probe lobing). Only approaches with a component along the stylus (a
// helical gear's flanks, faces or a sphere probed at several elevations) or a stylus across the
// gear axis, where sin²γ = 1 − n_x² varies around the gear, separate the two.
#pragma once

#include "engine/effects/measurement_effect.h"

namespace gearmc {

class StylusBendingEffect : public MeasurementEffect {
 public:
  // `stylus_axis`: unit vector of the stylus axis (its sign does not matter).
  StylusBendingEffect(EffectParameter deflection_um, const Eigen::Vector3d& stylus_axis);
  std::string_view name() const override { return "stylus_bending"; }
  EffectStage stage() const override { return EffectStage::kProbe; }
  void apply(const PointContext& point, std::span<const double> values, Eigen::Vector3d& centre_mm,
             RandomStream& rng) const override;
  void signature(const PointContext& point, std::span<const double> values,
                 std::span<double> out) const override;
  const Eigen::Vector3d& stylus_axis() const { return axis_; }

 private:
  Eigen::Vector3d axis_;
};

}  // namespace gearmc
