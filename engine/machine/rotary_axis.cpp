// The rotary table as part of the machine (rotary_axis.h).
#include "engine/machine/rotary_axis.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "core/random_stream.h"

namespace gearmc {
namespace {
constexpr double kRadPerArcsec = std::numbers::pi / (180.0 * 3600.0);
}  // namespace

Eigen::Vector3d RotaryTableErrors::displacement_mm(double t, const Eigen::Vector3d& c) const {
  const auto& v = terms;
  const double c1 = std::cos(t), s1 = std::sin(t), c2 = std::cos(2 * t), s2 = std::sin(2 * t);
  const double radial_um = v[0] * c1 + v[1] * s1;
  const double axial_um = v[2] * c1 + v[3] * s1;
  const double turn_rad = (v[4] * c1 + v[5] * s1 + v[6] * c2 + v[7] * s2) * kRadPerArcsec;
  // The turn about the gear axis, then the shift (first order: the two commute to 10⁻¹⁰ mm).
  return turn_rad * Eigen::Vector3d(-c.y(), c.x(), 0.0) +
         1e-3 * Eigen::Vector3d(radial_um * c1, radial_um * s1, axial_um);
}

double RotaryTableErrors::radial_range_um() const { return 2.0 * std::hypot(terms[0], terms[1]); }
double RotaryTableErrors::axial_range_um() const { return 2.0 * std::hypot(terms[2], terms[3]); }
double RotaryTableErrors::angular_range_arcsec() const {
  double lo = 0.0, hi = 0.0;
  for (int i = 0; i < 3600; ++i) {
    const double t = 2.0 * std::numbers::pi * i / 3600.0;
    const double d = terms[4] * std::cos(t) + terms[5] * std::sin(t) + terms[6] * std::cos(2 * t) +
                     terms[7] * std::sin(2 * t);
    lo = i == 0 ? d : std::min(lo, d);
    hi = i == 0 ? d : std::max(hi, d);
  }
  return hi - lo;
}

RotaryTableErrors draw_rotary_table(const RotaryTableSpec& spec, std::uint64_t seed,
                                    std::uint64_t index) {
  TrialStream rng(seed, index, TrialPurpose::kTableDraw);
  RotaryTableErrors t;
  const double scale[8] = {spec.radial_um,      spec.radial_um,      spec.axial_um,
                           spec.axial_um,       spec.angular_arcsec, spec.angular_arcsec,
                           spec.angular_arcsec, spec.angular_arcsec};
  for (std::size_t i = 0; i < 8; ++i) t.terms[i] = 0.25 * scale[i] * rng.normal();
  return t;
}

bool meets(const RotaryTableErrors& table, const RotaryTableSpec& spec) {
  return table.radial_range_um() <= spec.radial_um && table.axial_range_um() <= spec.axial_um &&
         table.angular_range_arcsec() <= spec.angular_arcsec;
}

}  // namespace gearmc
