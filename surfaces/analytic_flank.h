// The real flank of a perturbed gear as an analytic surface in the datum (CMM) frame:
//   S(L, z) = P(L, z) + delta(L, z) n(L) + eps,
// P and n the nominal involute point and outward normal (gears/involute_gear.h), delta the
// normal deviation (random part + the gear's design modification + optional expression, mm)
// and eps the gear's eccentricity.
// Of a helical gear P is the involute helicoid's point and delta the transverse deviation,
// along the transverse normal n_t (flank_frame.h); nominal_normal is the helicoid's normal.
// Gives the point, its first and second partial derivatives and the real unit normal, the
// ingredients of the exact stylus contact (Newton on (L, z)). Lengths mm, deviations µm.
#pragma once

#include <Eigen/Core>

#include "gears/deviations.h"
#include "gears/involute_gear.h"
#include "gears/normal_expression.h"

namespace gearmc {

struct FlankSurfacePoint {
  Eigen::Vector3d point;                    // S(L, z), mm
  Eigen::Vector3d d_dL, d_dz;               // ∂S/∂L, ∂S/∂z
  Eigen::Vector3d d2_dL2, d2_dLdz, d2_dz2;  // second partials
  Eigen::Vector3d nominal_normal;           // n(L), unit, outward (helical: n(L, z))
  double deviation_um;                      // delta(L, z) along n (helical: along n_t), µm
  // Unit outward normal of the real surface: ∂S/∂L × ∂S/∂z oriented like n.
  Eigen::Vector3d real_normal() const;
};

class AnalyticFlank {
 public:
  // `deviation` and `expression` (may be null) must outlive the flank.
  AnalyticFlank(const InvoluteGear& gear, int tooth, FlankSide side,
                const FlankDeviation& deviation, const Eigen::Vector2d& eccentricity_mm,
                const NormalExpression* expression = nullptr);

  FlankSurfacePoint evaluate(double roll_length_mm, double z_mm) const;
  Eigen::Vector3d point(double roll_length_mm, double z_mm) const;
  int tooth() const { return tooth_; }
  FlankSide side() const { return side_; }
  // The ingredients, for bounds over a region (the contact certificate, contact.h).
  const InvoluteGear& gear() const { return gear_; }
  const FlankDeviation& deviation() const { return deviation_; }
  const NormalExpression* expression() const { return expression_; }
  // The gear's design modification (null: none), part of delta (gears/flank_modifications.h).
  const DesignModification* modification() const { return modification_; }
  const Eigen::Vector3d& eccentricity() const { return eccentricity_; }
  // 1 / r_b (1/mm): the partials divide by the base radius at every evaluation.
  double inverse_base_radius() const { return inverse_base_radius_; }
  double base_radius() const { return base_radius_; }  // r_b, mm
  // sigma: +1 on an external gear, -1 on an internal one (InvoluteGear::roll_sign).
  double roll_sign() const { return roll_sign_; }
  // Helical flanks (0 on a spur flank): g = side sign * helix_turn_per_mm (rad/mm), the turn of
  // the flank's transverse frame per mm of z (flank_frame.h), and cos, sin of beta_b (cos 1).
  double frame_turn_per_mm() const { return frame_turn_per_mm_; }
  double cos_base_helix() const { return cos_base_helix_; }
  double sin_base_helix() const { return sin_base_helix_; }
  // The nominal normal's axial component: -side hand sin(beta_b) (InvoluteGear::flank_point).
  double normal_z() const { return normal_z_; }
  // The deviation's partials' ranges over all (L, z), µm/mm and µm/mm² (exact; computed once
  // here, FlankDeviation::derivative_ranges, widened by the design modification's bounds);
  // without the expression.
  const FlankDeviation::Ranges& deviation_derivative_ranges() const { return ranges_; }

 private:
  const InvoluteGear& gear_;
  int tooth_;
  FlankSide side_;
  const FlankDeviation& deviation_;
  Eigen::Vector3d eccentricity_;
  const NormalExpression* expression_;
  const DesignModification* modification_;
  FlankDeviation::Ranges ranges_;
  double inverse_base_radius_;
  double base_radius_;
  double roll_sign_;
  double frame_turn_per_mm_, cos_base_helix_, sin_base_helix_, normal_z_;
};

}  // namespace gearmc
