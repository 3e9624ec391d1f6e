// Shared by the effect tests: an effect chain parsed from YAML text, and the change of the
// reading (µm along the nominal normal n) that a chain makes at one probed point when the true
// stylus centre is the nominal contact point p + R n (CMM frame = gear frame, mm).
#pragma once

#include <Eigen/Core>
#include <string>

#include "core/random_stream.h"
#include "core/yaml_reader.h"
#include "engine/effects/effect_config.h"
#include "engine/effects/measurement_effect.h"

namespace gearmc::testing_support {

// `file` is the name error messages give the text.
inline EffectChain chain(const std::string& yaml, const std::string& file = "effects.yaml") {
  return parse_effects(parse_yaml_document(yaml, file));
}

// 1000 · (c_recorded − c_true) · n, µm, with the chain's nominal values and stream (1, 0).
inline double reading_change(const EffectChain& c, const PointContext& point) {
  const Eigen::Vector3d start = point.p + point.stylus_radius_mm * point.n;
  RandomStream rng(1, 0, StreamPurpose::kEffectNoise, 0);
  return 1000.0 * (c.apply(point, c.nominal(), start, rng) - start).dot(point.n);
}

}  // namespace gearmc::testing_support
