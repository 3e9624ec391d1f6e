// The empirical term along one axis (see empirical_effect.h).
#include "engine/effects/empirical_effect.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace gearmc {
namespace {

constexpr std::pair<EmpiricalAxis, std::string_view> kAxes[] = {
    {EmpiricalAxis::kRollLength, "roll_length"},
    {EmpiricalAxis::kFacePosition, "face_position"},
    {EmpiricalAxis::kTooth, "tooth"},
    {EmpiricalAxis::kFlank, "flank"},
    {EmpiricalAxis::kApproachAzimuth, "approach_azimuth"},
    {EmpiricalAxis::kProbingOrder, "probing_order"},
};

}  // namespace

std::string_view empirical_axis_name(EmpiricalAxis axis) {
  for (const auto& [a, name] : kAxes) {
    if (a == axis) return name;
  }
  return "";
}

EmpiricalAxis parse_empirical_axis(std::string_view name) {
  for (const auto& [a, n] : kAxes) {
    if (n == name) return a;
  }
  throw std::invalid_argument("unknown empirical axis '" + std::string(name) + "'");
}

std::string_view empirical_basis_name(EmpiricalBasis basis) {
  return basis == EmpiricalBasis::kLegendre ? "legendre" : "harmonic";
}

EmpiricalBasis natural_basis(EmpiricalAxis axis) {
  return axis == EmpiricalAxis::kTooth || axis == EmpiricalAxis::kApproachAzimuth
             ? EmpiricalBasis::kHarmonic
             : EmpiricalBasis::kLegendre;
}

double empirical_coordinate(EmpiricalAxis axis, const PointContext& point) {
  switch (axis) {
    case EmpiricalAxis::kRollLength: {
      const double r2 = point.p.x() * point.p.x() + point.p.y() * point.p.y();
      const double rb = point.base_radius_mm;
      return std::sqrt(std::max(0.0, r2 - rb * rb));
    }
    case EmpiricalAxis::kFacePosition:
      return point.p.z();
    case EmpiricalAxis::kTooth:
      return std::atan2(point.p.y(), point.p.x());
    case EmpiricalAxis::kFlank:
      return point.side == FlankSide::kRight ? 1.0 : -1.0;
    case EmpiricalAxis::kApproachAzimuth:
      return point.azimuth_rad;
    case EmpiricalAxis::kProbingOrder:
      return point.sequence_length > 1
                 ? static_cast<double>(point.order) / (point.sequence_length - 1)
                 : 0.0;
  }
  return 0.0;
}

std::vector<double> legendre_values(double t, int order) {
  std::vector<double> p(static_cast<std::size_t>(std::max(order, 0)) + 1, 1.0);
  if (order >= 1) p[1] = t;
  for (int k = 1; k < order; ++k) {
    p[k + 1] = ((2.0 * k + 1.0) * t * p[k] - k * p[k - 1]) / (k + 1.0);
  }
  return p;
}

std::vector<double> empirical_basis_values(EmpiricalBasis basis, double x, double from, double to,
                                           int order) {
  std::vector<double> out;
  if (basis == EmpiricalBasis::kLegendre) {
    const double t = to > from ? 2.0 * (x - from) / (to - from) - 1.0 : 0.0;
    const std::vector<double> p = legendre_values(t, order);
    out.assign(p.begin() + 1, p.end());
  } else {
    for (int k = 1; k <= order; ++k) {
      out.push_back(std::cos(k * x));
      out.push_back(std::sin(k * x));
    }
  }
  return out;
}

EmpiricalEffect::EmpiricalEffect(EmpiricalAxis axis, EmpiricalBasis basis, double from, double to,
                                 std::vector<int> orders, std::vector<EffectParameter> parameters)
    : MeasurementEffect(std::move(parameters)),
      axis_(axis),
      basis_(basis),
      from_(from),
      to_(to),
      orders_(std::move(orders)) {}

void EmpiricalEffect::signature(const PointContext& point, std::span<const double>,
                                std::span<double> out) const {
  const double x = empirical_coordinate(axis_, point);
  int highest = 0;
  for (int k : orders_) highest = std::max(highest, k);
  const std::vector<double> b = empirical_basis_values(basis_, x, from_, to_, highest);
  std::size_t at = 0;
  for (int k : orders_) {
    if (basis_ == EmpiricalBasis::kLegendre) {
      out[at++] = b[static_cast<std::size_t>(k - 1)];
    } else {
      out[at++] = b[static_cast<std::size_t>(2 * (k - 1))];
      out[at++] = b[static_cast<std::size_t>(2 * (k - 1) + 1)];
    }
  }
}

void EmpiricalEffect::apply(const PointContext& point, std::span<const double> values,
                            Eigen::Vector3d& centre_mm, RandomStream&) const {
  std::vector<double> s(values.size());
  signature(point, values, s);
  double f = 0.0;
  for (std::size_t i = 0; i < values.size(); ++i) f += s[i] * values[i];
  centre_mm += 1e-3 * f * point.n;
}

}  // namespace gearmc
