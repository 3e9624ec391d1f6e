// The rotary table's radial, axial and angular errors against the table angle (see
// rotary_table.h).
#include "engine/effects/rotary_table.h"

#include <cmath>
#include <numbers>
#include <stdexcept>

namespace gearmc {
namespace {

constexpr double kRadPerArcsec = std::numbers::pi / (180.0 * 3600.0);

// The table's displacement (mm) and turn (rad) at the point's table angle.
struct TableError {
  Eigen::Vector3d shift_mm;
  double turn_rad;
};

TableError table_error(const PointContext& point, std::span<const double> v) {
  const double t = table_angle_rad(point);
  const double c1 = std::cos(t), s1 = std::sin(t), c2 = std::cos(2 * t), s2 = std::sin(2 * t);
  const double radial_um = v[0] * c1 + v[1] * s1;
  const double axial_um = v[2] * c1 + v[3] * s1;
  const double turn_arcsec = v[4] * c1 + v[5] * s1 + v[6] * c2 + v[7] * s2;
  return {1e-3 * Eigen::Vector3d(radial_um * c1, radial_um * s1, axial_um),
          turn_arcsec * kRadPerArcsec};
}

}  // namespace

double table_angle_rad(const PointContext& point) {
  if (point.teeth < 1) {
    throw std::logic_error("rotary_table: the point's context has no number of teeth");
  }
  return 2.0 * std::numbers::pi * (point.tooth - 1) / point.teeth;
}

const std::vector<std::string>& RotaryTableEffect::parameter_names() {
  static const std::vector<std::string> names = {"radial_cos_um",        "radial_sin_um",
                                                 "axial_cos_um",         "axial_sin_um",
                                                 "angular_cos_1_arcsec", "angular_sin_1_arcsec",
                                                 "angular_cos_2_arcsec", "angular_sin_2_arcsec"};
  return names;
}

RotaryTableEffect::RotaryTableEffect(std::vector<EffectParameter> parameters)
    : MeasurementEffect([&] {
        if (parameters.size() != parameter_names().size()) {
          throw std::logic_error("rotary_table: 8 parameters expected");
        }
        for (std::size_t i = 0; i < parameters.size(); ++i) {
          parameters[i].name = parameter_names()[i];
          parameters[i].unit = i < 4 ? "µm" : "arcsec";
        }
        return std::move(parameters);
      }()) {}

void RotaryTableEffect::apply(const PointContext& point, std::span<const double> v,
                              Eigen::Vector3d& c, RandomStream&) const {
  const TableError e = table_error(point, v);
  // The turn about the gear axis, then the shift (first order: the two commute to 10⁻¹⁰ mm).
  const Eigen::Vector3d turned(-c.y(), c.x(), 0.0);
  c += e.turn_rad * turned + e.shift_mm;
}

void RotaryTableEffect::signature(const PointContext& point, std::span<const double>,
                                  std::span<double> out) const {
  const double t = table_angle_rad(point);
  const double c1 = std::cos(t), s1 = std::sin(t), c2 = std::cos(2 * t), s2 = std::sin(2 * t);
  const Eigen::Vector3d& n = point.n;
  const double radial_n = c1 * n.x() + s1 * n.y();  // e_r(θ)·n
  const Eigen::Vector3d c = point.p + point.stylus_radius_mm * point.n;
  const double turn_n = 1e3 * kRadPerArcsec * (-c.y() * n.x() + c.x() * n.y());  // µm per arcsec
  out[0] = c1 * radial_n;
  out[1] = s1 * radial_n;
  out[2] = c1 * n.z();
  out[3] = s1 * n.z();
  out[4] = c1 * turn_n;
  out[5] = s1 * turn_n;
  out[6] = c2 * turn_n;
  out[7] = s2 * turn_n;
}

}  // namespace gearmc
