// Real flank surface S(L, z) = P + delta n + eps and its derivatives (see analytic_flank.h).
// With t the unit profile tangent, r_b the base radius and the involute relations
// dP/dL = (L / r_b) t, dn/dL = t / r_b, dt/dL = -n / r_b (all involutes of one base circle
// share their normals), the partials are
//   S_L  = t (L + delta) / r_b + delta_L n,           S_z  = e_z + delta_z n,
//   S_LL = t (1 + 2 delta_L) / r_b + n (delta_LL - (L + delta) / r_b^2),
//   S_Lz = t delta_z / r_b + delta_Lz n,              S_zz = delta_zz n.
#include "surfaces/analytic_flank.h"

#include <Eigen/Geometry>

namespace gearmc {

Eigen::Vector3d FlankSurfacePoint::real_normal() const {
  Eigen::Vector3d n = d_dL.cross(d_dz).normalized();
  return n.dot(nominal_normal) < 0.0 ? Eigen::Vector3d(-n) : n;
}

AnalyticFlank::AnalyticFlank(const InvoluteGear& gear, int tooth, FlankSide side,
                             const FlankDeviation& deviation,
                             const Eigen::Vector2d& eccentricity_mm,
                             const NormalExpression* expression)
    : gear_(gear),
      tooth_(tooth),
      side_(side),
      deviation_(deviation),
      eccentricity_(eccentricity_mm.x(), eccentricity_mm.y(), 0.0),
      expression_(expression),
      ranges_(deviation.derivative_ranges()) {}

FlankSurfacePoint AnalyticFlank::evaluate(double L, double z) const {
  const FlankPoint nominal = gear_.flank_point(tooth_, side_, L, z);
  const double r_b = 0.5 * gear_.base_diameter_mm();
  // Deviation and its partials, converted from µm to mm.
  double d, dL, dz, dLL, dzz, dLz = 0.0;
  deviation_.evaluate(L, z, &d, &dL, &dz, &dLL, &dzz);
  if (expression_) {
    // Five-point differences (normal_expression.h: accurate to ~1e-6 µm/mm in the slopes).
    const NormalExpression::Derivatives e =
        expression_->derivatives(L, z, tooth_, side_sign(side_));
    d += e.value;
    dL += e.dL;
    dz += e.dz;
    dLL += e.dLL;
    dzz += e.dzz;
    dLz += e.dLz;
  }
  const double delta = 1e-3 * d;
  dL *= 1e-3, dz *= 1e-3, dLL *= 1e-3, dzz *= 1e-3, dLz *= 1e-3;
  const Eigen::Vector3d& n = nominal.normal;
  const Eigen::Vector3d& t = nominal.profile_tangent;
  FlankSurfacePoint out;
  out.point = nominal.point + delta * n + eccentricity_;
  out.d_dL = t * ((L + delta) / r_b) + dL * n;
  out.d_dz = Eigen::Vector3d::UnitZ() + dz * n;
  out.d2_dL2 = t * ((1.0 + 2.0 * dL) / r_b) + n * (dLL - (L + delta) / (r_b * r_b));
  out.d2_dLdz = t * (dz / r_b) + dLz * n;
  out.d2_dz2 = dzz * n;
  out.nominal_normal = n;
  out.deviation_um = d;
  return out;
}

Eigen::Vector3d AnalyticFlank::point(double L, double z) const {
  const FlankPoint nominal = gear_.flank_point(tooth_, side_, L, z);
  double d = deviation_.normal_um(L, z);
  if (expression_) d += expression_->value_um(L, z, tooth_, side_sign(side_));
  return nominal.point + 1e-3 * d * nominal.normal + eccentricity_;
}

}  // namespace gearmc
