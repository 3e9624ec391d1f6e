// The effect interface's shared parts: parameter draws, the numerical signature, and the chain
// that applies effects in physical order (see measurement_effect.h).
#include "engine/effects/measurement_effect.h"

#include <algorithm>
#include <cmath>

namespace gearmc {

double EffectParameter::draw(RandomStream& rng) const {
  switch (law) {
    case Law::kFixed:
      return value;
    case Law::kUniform:
      return rng.uniform(lo, hi);
    case Law::kNormal:
      return value + spread * rng.normal();
  }
  return value;
}

double EffectParameter::nominal() const { return law == Law::kUniform ? 0.5 * (lo + hi) : value; }

EffectParameter named(EffectParameter p, const char* name, const char* unit) {
  p.name = name;
  p.unit = unit;
  return p;
}

void MeasurementEffect::signature(const PointContext& point, std::span<const double> values,
                                  std::span<double> out) const {
  const Eigen::Vector3d start = point.p + point.stylus_radius_mm * point.n;
  std::vector<double> v(values.begin(), values.end());
  // A fixed stream: both sides of a difference see the same random numbers.
  const RandomStream rng0(0, 0, StreamPurpose::kEffectNoise, 0);
  auto reading = [&](const std::vector<double>& at) {
    Eigen::Vector3d c = start;
    RandomStream rng = rng0;
    apply(point, at, c, rng);
    return 1000.0 * (c - start).dot(point.n);
  };
  for (std::size_t i = 0; i < v.size(); ++i) {
    const double h = 1e-3 * std::max(1.0, std::abs(values[i]));
    v[i] = values[i] + h;
    const double up = reading(v);
    v[i] = values[i] - h;
    const double down = reading(v);
    v[i] = values[i];
    out[i] = (up - down) / (2.0 * h);
  }
}

double PointLaw::mean_um() const {
  double m = 0.0;
  for (double w : uniform_widths_um) m -= 0.5 * w;
  return m;
}

double PointLaw::variance_um2() const {
  double v = gaussian_variance_um2;
  for (double w : uniform_widths_um) v += w * w / 12.0;
  return v;
}

PointLaw& PointLaw::operator+=(const PointLaw& other) {
  gaussian_variance_um2 += other.gaussian_variance_um2;
  uniform_widths_um.insert(uniform_widths_um.end(), other.uniform_widths_um.begin(),
                           other.uniform_widths_um.end());
  return *this;
}

void MeasurementEffect::apply_mean(const PointContext& point, std::span<const double> values,
                                   Eigen::Vector3d& centre_mm) const {
  RandomStream unused(0, 0, StreamPurpose::kEffectNoise, 0);
  apply(point, values, centre_mm, unused);
}

PointLaw MeasurementEffect::point_law(std::span<const double>) const { return {}; }

void EffectChain::add(std::unique_ptr<MeasurementEffect> effect) {
  effects_.push_back(std::move(effect));
  std::stable_sort(effects_.begin(), effects_.end(), [](const auto& a, const auto& b) {
    return static_cast<int>(a->stage()) < static_cast<int>(b->stage());
  });
}

int EffectChain::find(std::string_view name) const {
  for (std::size_t i = 0; i < effects_.size(); ++i) {
    if (effects_[i]->name() == name) return static_cast<int>(i);
  }
  return -1;
}

EffectValues EffectChain::draw(std::uint64_t seed, int gear) const {
  EffectValues values(effects_.size());
  for (std::size_t e = 0; e < effects_.size(); ++e) {
    RandomStream rng(seed, static_cast<std::uint32_t>(gear), StreamPurpose::kEffectParameters,
                     static_cast<std::uint32_t>(e));
    for (const EffectParameter& parameter : effects_[e]->parameters()) {
      if (parameter.shared_stream != 0) {
        RandomStream shared(seed, static_cast<std::uint32_t>(gear),
                            StreamPurpose::kEffectParameters, parameter.shared_stream);
        values[e].push_back(parameter.draw(shared));
      } else {
        values[e].push_back(parameter.draw(rng));
      }
    }
  }
  return values;
}

EffectValues EffectChain::nominal() const {
  EffectValues values(effects_.size());
  for (std::size_t e = 0; e < effects_.size(); ++e) {
    for (const EffectParameter& parameter : effects_[e]->parameters()) {
      values[e].push_back(parameter.nominal());
    }
  }
  return values;
}

Eigen::Vector3d EffectChain::apply(const PointContext& point, const EffectValues& values,
                                   const Eigen::Vector3d& contact_centre, RandomStream& rng,
                                   std::span<double> contributions) const {
  Eigen::Vector3d c = contact_centre;
  for (std::size_t e = 0; e < effects_.size(); ++e) {
    const Eigen::Vector3d before = c;
    effects_[e]->apply(point, values[e], c, rng);
    if (!contributions.empty()) contributions[e] = 1000.0 * (c - before).dot(point.n);
  }
  return c;
}

Eigen::Vector3d EffectChain::apply_mean(const PointContext& point, const EffectValues& values,
                                        const Eigen::Vector3d& contact_centre) const {
  Eigen::Vector3d c = contact_centre;
  for (std::size_t e = 0; e < effects_.size(); ++e) effects_[e]->apply_mean(point, values[e], c);
  return c;
}

PointLaw EffectChain::point_law(const EffectValues& values) const {
  PointLaw law;
  for (std::size_t e = 0; e < effects_.size(); ++e) law += effects_[e]->point_law(values[e]);
  return law;
}

}  // namespace gearmc
