// The rotary table a gear is measured on (`rotary_table`): the gear sits on the table and the
// table turns each tooth into the same region of the machine, where the linear axes probe it.
// The table's own errors then move every point of a tooth by an amount that depends on the table
// angle at which that tooth was probed. The terms are those of ISO 230-7:2015 (geometric accuracy
// of axes of rotation: radial, axial and angular (positioning) error motions against the angle of
// rotation), as gear-measuring practice uses them for the rotary axis of gear measuring
// instruments and CMMs with a rotary table (VDI/VDE 2612 and 2613, the profile and pitch tests
// whose results these errors enter).
//
// Frames. Gear frame = the frame of every reading (gear axis +Z, tooth 1's centre line on +X,
// teeth counter-clockwise). The table angle of tooth k is its centre line's polar angle
//   θ_k = 2π (k − 1) / z,
// the angle through which the table turns to bring tooth k to the probing position (the table
// turns by −θ_k, so tooth k's centre line lies on the machine's +X axis, the probing region's
// radial direction). The table's zero is the position that probes tooth 1 (a user's own table
// zero elsewhere shifts every phase below by that angle). A displacement d of the table in the
// machine frame at angle θ is the displacement R_z(θ) d in the gear frame.
//
// The errors, each the first harmonics in θ, written as cosine and sine parts (a first harmonic
// a cos(θ − φ) of amplitude a and the table angle φ of its maximum is c cos θ + s sin θ with
// c = a cos φ, s = a sin φ; a = √(c² + s²), φ = atan2(s, c)):
//   radial (radial_cos_um, radial_sin_um): the table axis moves along the probing region's radial
//     direction (machine X) by ρ(θ) = c_r cos θ + s_r sin θ µm, the runout a dial indicator on a
//     centred test cylinder at the probing position reads. In the gear frame tooth k moves by
//     ρ(θ_k) along its own radial direction e_r(θ_k) = (cos θ_k, sin θ_k). Half of that is a
//     fixed offset of the gear ((c_r, s_r)/2: the same as a set-up eccentricity) and half turns
//     twice per table turn: only that half tells it from `eccentricity`.
//   axial (axial_cos_um, axial_sin_um): the table moves along its axis by c_a cos θ + s_a sin θ
//     µm. A spur gear's flank normals have no axial component, so no spur-gear plan sees it.
//   angular (angular_cos_1_arcsec … angular_sin_2_arcsec): the table's angular positioning error
//     δ(θ) = Σ_{k=1,2} c_k cos kθ + s_k sin kθ (arcseconds) turns the gear by δ about its axis.
//     A turn of tooth k by δ is exactly what the gear's own pitch deviation of that tooth is, so
//     from one set-up this term cannot be told from the gear's cumulative pitch deviation (the
//     separating measurement: the gear in two or more positions on the table).
// Recorded centre c (mm): c ← c + 10⁻³ ρ(θ_k) e_r(θ_k) + 10⁻³ (axial) e_z + δ_rad(θ_k) e_z × c.
// Reading along n (µm): ρ(θ_k) e_r·n + axial n_z + 10³ δ_rad (e_z × c)·n, c = p + R n; on an
// involute flank (e_z × c)·n = ±r_b, the base radius, the same along the whole flank.
#pragma once

#include "engine/effects/measurement_effect.h"

namespace gearmc {

// θ_k above, rad; the point's tooth and the gear's number of teeth from `point` (a context
// without the number of teeth is a programming error: std::logic_error).
double table_angle_rad(const PointContext& point);

class RotaryTableEffect : public MeasurementEffect {
 public:
  // Parameters in this order: radial_cos_um, radial_sin_um, axial_cos_um, axial_sin_um,
  // angular_cos_1_arcsec, angular_sin_1_arcsec, angular_cos_2_arcsec, angular_sin_2_arcsec.
  explicit RotaryTableEffect(std::vector<EffectParameter> parameters);
  std::string_view name() const override { return "rotary_table"; }
  EffectStage stage() const override { return EffectStage::kWorkpiece; }
  void apply(const PointContext& point, std::span<const double> values, Eigen::Vector3d& centre_mm,
             RandomStream& rng) const override;
  void signature(const PointContext& point, std::span<const double> values,
                 std::span<double> out) const override;
  // The parameters' names, in the order above.
  static const std::vector<std::string>& parameter_names();
};

}  // namespace gearmc
