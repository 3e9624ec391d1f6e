// The artefact's own form (`artefact_form`): the profile and helix form deviations of the master
// gear that is measured. They are a property of the workpiece, not of the CMM: the same on every
// measurement of that artefact, and on every tooth they follow the flank's own coordinates (roll
// length along the profile, face position along the helix) — unlike machine errors, which follow
// the machine's axes and so change from tooth to tooth as the flank turns with the tooth.
//
// Form deviations of gear flanks are described, as in the gear standards, by their low-order
// shape over the evaluation range: ISO 1328-1:2013 splits the total profile and helix deviations
// (F_α, F_β) into a slope about the design trace (f_Hα, f_Hβ) and the form about that mean line
// (f_fα, f_fβ); the typical form traces are curved (barrelled: order 2) or S-shaped (order 3).
// Here the form is
// a sum of Legendre polynomials (Abramowitz & Stegun 22.2.10) in the normalised position on the
// flank, x ∈ [−1, 1] along the roll length L = √(r² − r_b²) from profile_from_mm to profile_to_mm
// and y ∈ [−1, 1] along the face position z from face_from_mm to face_to_mm:
//   f(x, y) = a₂ P₂(x) + a₃ P₃(x) + b₂ P₂(y) + b₃ P₃(y)  (µm),   P₂ = (3t² − 1)/2, P₃ = (5t³ −
//   3t)/2,
// with (a₂, a₃, b₂, b₃) the flank side's own values. Since P_k(1) = 1, each coefficient is the
// term's deviation at the end of its range (P₂: a barrel of a₂ at both ends against −a₂/2 in the
// middle; P₃: +a₃ at the end, −a₃ at the start). Orders 0 and 1 are left out on purpose: order 0
// (a constant on every flank) is the stylus radius error, order 1 in the profile (a slope) is a
// uniform scale or thermal error (the reading of an involute flank changes with the roll length,
// c·n = ±L), and on a spur gear a helix slope is what a tilted gear axis makes.
// A positive f is material added on the flank's outward side: the stylus touches f earlier, the
// recorded centre moves by f along the outward normal n, c ← c + f n / 1000; the reading changes
// by +f. The signature is exact (P_k at the nominal point).
//
// Parameters (µm): left_profile_2_um, left_profile_3_um, left_helix_2_um, left_helix_3_um, and
// the same for right_. Settings (mm): profile_from_mm, profile_to_mm (roll lengths of the
// evaluation range), face_from_mm, face_to_mm. Typical sizes: a master gear's form deviations
// f_fα, f_fβ are a few tenths of a µm to about 2 µm (accuracy grades 1–4 of ISO 1328-1 for small
// modules; recalled, unchecked).
#pragma once

#include "engine/effects/measurement_effect.h"

namespace gearmc {

// The evaluation ranges of the form terms (mm): roll length along the profile, z along the face.
struct FormRanges {
  double profile_from_mm = 0.0, profile_to_mm = 1.0;
  double face_from_mm = 0.0, face_to_mm = 1.0;
};

// The number of parameters: 2 sides × (profile, helix) × orders 2, 3.
inline constexpr int kArtefactFormParameters = 8;

class ArtefactFormEffect : public MeasurementEffect {
 public:
  // `parameters` in the order left_profile_2_um, left_profile_3_um, left_helix_2_um,
  // left_helix_3_um, right_profile_2_um, …, right_helix_3_um (names and units set here).
  ArtefactFormEffect(std::vector<EffectParameter> parameters, FormRanges ranges);
  std::string_view name() const override { return "artefact_form"; }
  EffectStage stage() const override { return EffectStage::kWorkpiece; }
  void apply(const PointContext& point, std::span<const double> values, Eigen::Vector3d& centre_mm,
             RandomStream& rng) const override;
  void signature(const PointContext& point, std::span<const double> values,
                 std::span<double> out) const override;
  const FormRanges& ranges() const { return ranges_; }
  // The parameter names in order (as in a scenario's effects.artefact_form).
  static const std::vector<std::string>& parameter_names();
  // Roll length √(r² − r_b²) of the point's nominal position (r_b from the context; r when 0).
  static double roll_length_mm(const PointContext& point);

 private:
  FormRanges ranges_;
};

}  // namespace gearmc
