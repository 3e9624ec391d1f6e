// `empirical`: a generic low-order term along one axis of the measurement, for structure that no
// physical effect of the library explains. `gearmc diagnose` fits it to what remains after the
// library's best fit (engine/apps/diagnose/empirical_term.h) and writes it into fitted.yaml, so the
// fitted scenario predicts that structure too; it is a description of the readings, not a
// physical model, and says nothing about where the structure comes from.
//
// The term adds f(x) µm to the reading along the nominal normal n (the recorded centre moves by
// f(x)/1000 · n, mm), x the point's coordinate along `axis`:
//   roll_length       x = L = √(r_xy² − r_b²), mm (ISO 21771 roll length; r_b from the context)
//   face_position     x = z, mm
//   tooth             x = θ = atan2(p_y, p_x), rad: the point's angular position on the gear
//   flank             x = −1 on left flanks, +1 on right flanks
//   approach_azimuth  x = φ, rad (the approach azimuth)
//   probing_order     x = order / (sequence_length − 1), 0 … 1 over one gear's sequence
// and f a sum of basis terms of orders k = 1 … K (no constant: a constant shift is the library's
// stylus radius / pre-travel):
//   legendre   f = Σ a_k P_k(t), t = 2 (x − from)/(to − from) − 1 (Legendre polynomials,
//              Abramowitz & Stegun 22.7.10: (k+1) P_{k+1} = (2k+1) t P_k − k P_{k−1});
//   harmonic   f = Σ a_k cos(k x) + b_k sin(k x) (x an angle in rad).
// Parameters a_<k>_um (and b_<k>_um for harmonic), µm; axis, basis, from, to are settings.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "engine/effects/measurement_effect.h"

namespace gearmc {

enum class EmpiricalAxis {
  kRollLength,
  kFacePosition,
  kTooth,
  kFlank,
  kApproachAzimuth,
  kProbingOrder
};
enum class EmpiricalBasis { kLegendre, kHarmonic };

// "roll_length", … (as Diagnosis::unexplained_along names the axes); parse throws
// std::invalid_argument for an unknown name.
std::string_view empirical_axis_name(EmpiricalAxis axis);
EmpiricalAxis parse_empirical_axis(std::string_view name);
std::string_view empirical_basis_name(EmpiricalBasis basis);
// The basis an axis is fitted with: harmonic for the angles (tooth, approach_azimuth), Legendre
// for the others.
EmpiricalBasis natural_basis(EmpiricalAxis axis);
// The coordinate x of `point` along `axis` (units above).
double empirical_coordinate(EmpiricalAxis axis, const PointContext& point);
// P_k(t) for k = 0 … order (A&S 22.7.10).
std::vector<double> legendre_values(double t, int order);

// The basis functions of orders 1 … K at coordinate x: legendre K values P_k(t); harmonic 2K
// values cos(kx), sin(kx) interleaved (order 1 cos, order 1 sin, …).
std::vector<double> empirical_basis_values(EmpiricalBasis basis, double x, double from, double to,
                                           int order);

class EmpiricalEffect : public MeasurementEffect {
 public:
  // `orders`: the orders k of the terms, in the order of their parameters (legendre: a_k each;
  // harmonic: a_k, b_k each). `from` < `to` (legendre only).
  EmpiricalEffect(EmpiricalAxis axis, EmpiricalBasis basis, double from, double to,
                  std::vector<int> orders, std::vector<EffectParameter> parameters);
  std::string_view name() const override { return "empirical"; }
  EffectStage stage() const override { return EffectStage::kMachine; }
  void apply(const PointContext& point, std::span<const double> values, Eigen::Vector3d& centre_mm,
             RandomStream& rng) const override;
  void signature(const PointContext& point, std::span<const double> values,
                 std::span<double> out) const override;
  EmpiricalAxis axis() const { return axis_; }
  EmpiricalBasis basis() const { return basis_; }
  double from() const { return from_; }
  double to() const { return to_; }
  const std::vector<int>& orders() const { return orders_; }

 private:
  EmpiricalAxis axis_;
  EmpiricalBasis basis_;
  double from_, to_;
  std::vector<int> orders_;
};

}  // namespace gearmc
