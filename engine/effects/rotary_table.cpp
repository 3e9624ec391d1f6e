// The rotary table's radial, axial and angular errors against the table angle (see
// rotary_table.h).
#include "engine/effects/rotary_table.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>

#include "engine/machine/rotary_axis.h"

namespace gearmc {
namespace {

constexpr double kRadPerArcsec = std::numbers::pi / (180.0 * 3600.0);

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
  RotaryTableErrors table;
  std::copy(v.begin(), v.begin() + 8, table.terms.begin());
  c += table.displacement_mm(table_angle_rad(point), c);
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
