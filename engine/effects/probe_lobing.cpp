// Probe pre-travel, lobing and P2's qualification strategies (see probe_lobing.h).
#include "engine/effects/probe_lobing.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "core/constants.h"

namespace gearmc {
namespace {

double wrap_2pi(double a) {
  a = std::fmod(a, 2.0 * kPi);
  return a < 0.0 ? a + 2.0 * kPi : a;
}

std::vector<EffectParameter> concat(EffectParameter first, std::vector<EffectParameter> middle,
                                    EffectParameter last) {
  std::vector<EffectParameter> all;
  all.push_back(std::move(first));
  for (auto& p : middle) all.push_back(std::move(p));
  all.push_back(std::move(last));
  return all;
}

}  // namespace

std::vector<double> qualification_directions_rad(const ProbeQualificationSpec& spec) {
  const double s = spec.start_deg * kDeg;
  std::vector<double> d;
  switch (spec.strategy) {
    case ProbeQualification::kNone:
    case ProbeQualification::kPerDirection:
      break;
    case ProbeQualification::kMean6:  // P2 variant 1: 3 at 2π/3, and the same rotated by π/6
      for (int j = 0; j < 3; ++j) d.push_back(wrap_2pi(s + j * 2.0 * kPi / 3.0));
      for (int j = 0; j < 3; ++j) d.push_back(wrap_2pi(s + kPi / 6.0 + j * 2.0 * kPi / 3.0));
      break;
    case ProbeQualification::kSixDirections:  // P2 variant 2: 3 extrema at 2π/3, +X, −X, −Y
      for (int j = 0; j < 3; ++j) d.push_back(wrap_2pi(s + j * 2.0 * kPi / 3.0));
      for (double a : {0.0, kPi, 1.5 * kPi}) d.push_back(a);
      std::sort(d.begin(), d.end());
      d.erase(std::unique(d.begin(), d.end(),
                          [](double a, double b) { return std::abs(a - b) < 1e-12; }),
              d.end());
      break;
  }
  return d;
}

double LobingModel::pretravel_at(double azimuth_rad) const {
  double p = pretravel_um;
  for (const LobingHarmonic& h : harmonics) {
    p += h.value_um(azimuth_rad);
  }
  return p;
}

double qualification_correction_um(const LobingModel& model, const ProbeQualificationSpec& spec,
                                   double azimuth_rad) {
  switch (spec.strategy) {
    case ProbeQualification::kNone:
      return 0.0;
    case ProbeQualification::kPerDirection:
      return model.pretravel_at(azimuth_rad);
    case ProbeQualification::kMean6: {
      double sum = 0.0;
      const std::vector<double> d = qualification_directions_rad(spec);
      for (double a : d) sum += model.pretravel_at(a);
      return sum / static_cast<double>(d.size());
    }
    case ProbeQualification::kSixDirections: {
      const std::vector<double> d = qualification_directions_rad(spec);  // sorted, in [0, 2π)
      const double phi = wrap_2pi(azimuth_rad);
      // Neighbours: the last direction <= phi and the next one (cyclically).
      std::size_t hi = std::upper_bound(d.begin(), d.end(), phi) - d.begin();
      const std::size_t lo = (hi + d.size() - 1) % d.size();
      hi %= d.size();
      const double a = d[lo], b = d[hi];
      const double span = wrap_2pi(b - a) == 0.0 ? 2.0 * kPi : wrap_2pi(b - a);
      const double t = wrap_2pi(phi - a) / span;  // 0 at a, 1 at b
      const double pa = model.pretravel_at(a), pb = model.pretravel_at(b);
      if (spec.use == SixDirectionUse::kNearest) return t <= 0.5 ? pa : pb;
      return pa + t * (pb - pa);
    }
  }
  return 0.0;
}

ProbeLobingEffect::ProbeLobingEffect(EffectParameter pretravel, std::vector<int> orders,
                                     std::vector<EffectParameter> amplitude_and_phase,
                                     EffectParameter repeatability,
                                     ProbeQualificationSpec qualification)
    : MeasurementEffect(
          concat(std::move(pretravel), std::move(amplitude_and_phase), std::move(repeatability))),
      orders_(std::move(orders)),
      qualification_(qualification) {}

LobingModel ProbeLobingEffect::model(std::span<const double> values) const {
  LobingModel m;
  m.pretravel_um = values[0];
  for (std::size_t k = 0; k < orders_.size(); ++k) {
    m.harmonics.push_back({orders_[k], values[1 + 2 * k], values[2 + 2 * k]});
  }
  return m;
}

double ProbeLobingEffect::residual_um(std::span<const double> values, double azimuth_rad) const {
  const LobingModel m = model(values);
  return m.pretravel_at(azimuth_rad) - qualification_correction_um(m, qualification_, azimuth_rad);
}

void ProbeLobingEffect::apply(const PointContext& point, std::span<const double> values,
                              Eigen::Vector3d& centre_mm, RandomStream& rng) const {
  const double repeatability = values.back();
  const double noise = repeatability * rng.normal();  // always drawn: fixed stream use
  // Extra travel along the approach (−n), less the qualification's compensation.
  centre_mm -= point.n * (1e-3 * (residual_um(values, point.azimuth_rad) + noise));
}

void ProbeLobingEffect::apply_mean(const PointContext& point, std::span<const double> values,
                                   Eigen::Vector3d& centre_mm) const {
  centre_mm -= point.n * (1e-3 * residual_um(values, point.azimuth_rad));
}

PointLaw ProbeLobingEffect::point_law(std::span<const double> values) const {
  const double repeatability = values.back();
  return PointLaw{repeatability * repeatability, {}};
}

}  // namespace gearmc
