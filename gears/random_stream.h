// Counter-based random streams (Random123 Philox4x32-10). A stream is named by
// (seed, gear index, purpose, sub-index) and its n-th draw is a pure function of that name
// and n, so results never depend on thread count, scheduling or the order gears are drawn,
// and any single gear can be re-drawn alone (docs/architecture.md, principle 2).
#pragma once

#include <Random123/philox.h>
#include <Random123/uniform.hpp>

#include <cmath>
#include <cstdint>
#include <numbers>

namespace gearmc {

// What a stream is used for; a new purpose must get a new, never reused, number.
enum class StreamPurpose : std::uint32_t {
  kThickness = 1,
  kPitch = 2,
  kEccentricity = 3,
  kProfile = 4,  // sub-index: flank index
  kHelix = 5,    // sub-index: flank index
  // 16: reserved (was planned for probing noise, never used).
  kEffectParameters = 17,  // sub-index: effect index in the chain (per-gear parameter draws)
  kEffectNoise = 18,       // sub-index: point order (random parts of effects at one point)
  kDiagnoseNull = 19,      // gear index = null replicate; sub-index: selection step (diagnosis)
};

class RandomStream {
 public:
  RandomStream(std::uint64_t seed, std::uint32_t gear, StreamPurpose purpose,
               std::uint32_t sub_index = 0) {
    key_ = {{static_cast<std::uint32_t>(seed ^ (seed >> 32) * 0x9E3779B9u), gear}};
    ctr_ = {{0u, static_cast<std::uint32_t>(seed >> 32), static_cast<std::uint32_t>(purpose),
             sub_index}};
  }

  // Uniform in (0, 1]: never 0, so log() is safe.
  double uniform() {
    if (used_ == 4) refill();
    return r123::u01<double>(buffer_[used_++]);
  }
  // Uniform in [lo, hi].
  double uniform(double lo, double hi) { return lo + (hi - lo) * uniform(); }
  // Standard normal (Box–Muller on two uniforms; the pair's second value is not kept, so a
  // draw's value depends only on its position in the stream).
  double normal() {
    const double u1 = uniform();
    const double u2 = uniform();
    return std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * std::numbers::pi * u2);
  }

 private:
  void refill() {
    buffer_ = generator_(ctr_, key_);
    ++ctr_.v[0];
    used_ = 0;
  }
  r123::Philox4x32 generator_;
  r123::Philox4x32::ctr_type ctr_;
  r123::Philox4x32::key_type key_;
  r123::Philox4x32::ctr_type buffer_{};
  int used_ = 4;
};

}  // namespace gearmc
