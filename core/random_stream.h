// Counter-based random streams (Random123 Philox4x32-10; Salmon et al., "Parallel random
// numbers: as easy as 1, 2, 3", SC11) and the registry of what each stream is for. A stream is
// named by a key and a counter built from (seed, index, purpose, sub-index) and its n-th number
// is a pure function of that name and n, so results never depend on thread count, scheduling,
// process count or the order in which gears or trials are drawn, and any single gear or trial can
// be re-drawn alone (docs/architecture.md, principle 2).
//
// One class, PhiloxStream, in two resolutions that are kept for byte-identical results:
// - RandomStream (gears, effects, diagnosis): uniforms from one 32-bit word, in (0, 1];
// - TrialStream (uncertainty and R-Test trials): uniforms from two words (53 bits), in (0, 1).
#pragma once

#include <Random123/philox.h>
#include <Random123/uniform.hpp>

#include <cmath>
#include <cstdint>
#include <numbers>

namespace gearmc {

// What a gear's stream (RandomStream) is used for; a new purpose must get a new, never reused,
// number.
enum class StreamPurpose : std::uint32_t {
  kThickness = 1,
  kPitch = 2,
  kEccentricity = 3,
  kProfile = 4,  // sub-index: flank index
  kHelix = 5,    // sub-index: flank index
  // 16: reserved (was planned for probing noise, never used).
  kEffectParameters = 17,  // sub-index: effect index in the chain (per-gear parameter draws),
                           // or a shared stream (EffectParameter::shared_stream)
  kEffectNoise = 18,       // sub-index: point order (random parts of effects at one point)
  kDiagnoseNull = 19,      // gear index = null replicate; sub-index: selection step (diagnosis)
};

// What a trial's stream (TrialStream) is used for when it is not one input of an uncertainty
// model (those use the input's index 0, 1, …, far below these numbers). A new purpose must get
// a new, never reused, number.
enum class TrialPurpose : std::uint32_t {
  kRTestMounting = 0x5254'0001,        // the R-Test's mounting deviation (trial 0)
  kRTestObserved = 0x5254'0002,        // the simulated observed readings (trial 0)
  kRTestGumMcm = 0x5254'0003,          // the GUM route's Monte-Carlo check, from the model
  kRTestGumMcmReadings = 0x5254'0103,  // the same, from the simulated readings
  kRTestFullMcm = 0x5254'0004,         // the full Monte-Carlo route
  kRTestVerification = 0x5254'0005,    // the simulated verification's repetitions
  kRTestPositions = 0x5254'0006,       // the positions' draws
  kSweepBootstrap = 0x5357'0001,       // a sweep point's bootstrap resamples of its gears
  kMachineDraw = 0x434D'0001,          // a drawn CMM (trial = the machine's index, cmm.md)
  kProbeDraw = 0x434D'0002,            // a drawn CMM's probe (trial = the machine's index)
  kProbingTest = 0x434D'0003,          // its ISO 10360-5 test's touches (trial = the index)
  kTableDraw = 0x434D'0004,            // a drawn CMM's rotary table (trial = its index)
};

// How many random bits one uniform takes.
enum class UniformBits { k32, k53 };

template <UniformBits kBits>
class PhiloxStream {
 public:
  // A gear's stream: key (seed folded to 32 bits, gear), counter (n, seed's high word, purpose,
  // sub_index).
  PhiloxStream(std::uint64_t seed, std::uint32_t gear, StreamPurpose purpose,
               std::uint32_t sub_index = 0) requires(kBits == UniformBits::k32) {
    key_ = {{static_cast<std::uint32_t>(seed ^ (seed >> 32) * 0x9E3779B9u), gear}};
    ctr_ = {{0u, static_cast<std::uint32_t>(seed >> 32), static_cast<std::uint32_t>(purpose),
             sub_index}};
  }

  // The stream of input `input` in trial `trial`: key = seed, counter = (n, trial's low word,
  // trial's high word, input).
  PhiloxStream(std::uint64_t seed, std::uint64_t trial,
               std::uint32_t input) requires(kBits == UniformBits::k53) {
    key_ = {{static_cast<std::uint32_t>(seed), static_cast<std::uint32_t>(seed >> 32)}};
    ctr_ = {
        {0u, static_cast<std::uint32_t>(trial), static_cast<std::uint32_t>(trial >> 32), input}};
  }
  // A trial's stream for a registered purpose instead of a model input.
  PhiloxStream(std::uint64_t seed, std::uint64_t trial,
               TrialPurpose purpose) requires(kBits == UniformBits::k53)
      : PhiloxStream(seed, trial, static_cast<std::uint32_t>(purpose)) {}

  // Uniform. 32 bits: r123::u01 of one word, in (0, 1] (never 0, so log() is safe). 53 bits:
  // (k + 1/2) 2^-53 for the 53-bit integer k of two words, in the open interval (0, 1), so log()
  // and the inverse CDFs of unbounded laws are always finite.
  double uniform() {
    if (used_ == kPerBlock) refill();
    if constexpr (kBits == UniformBits::k32) {
      return r123::u01<double>(buffer_[used_++]);
    } else {
      const std::uint64_t hi = buffer_.v[2 * used_];
      const std::uint64_t lo = buffer_.v[2 * used_ + 1];
      ++used_;
      const std::uint64_t k = ((hi << 32) | lo) >> 11;
      return (static_cast<double>(k) + 0.5) * 0x1.0p-53;
    }
  }
  // Uniform in [lo, hi].
  double uniform(double lo, double hi) { return lo + (hi - lo) * uniform(); }
  // Standard normal (Box–Muller on two uniforms, the cosine branch only, so a draw's value
  // depends only on its position in the stream).
  double normal() {
    const double u1 = uniform();
    const double u2 = uniform();
    return std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * std::numbers::pi * u2);
  }

 private:
  // Uniforms per Philox block of four 32-bit words.
  static constexpr int kPerBlock = kBits == UniformBits::k32 ? 4 : 2;

  void refill() {
    buffer_ = generator_(ctr_, key_);
    ++ctr_.v[0];
    used_ = 0;
  }
  r123::Philox4x32 generator_;
  r123::Philox4x32::ctr_type ctr_;
  r123::Philox4x32::key_type key_;
  r123::Philox4x32::ctr_type buffer_{};
  int used_ = kPerBlock;
};

// The streams of gears, effects and the diagnosis.
using RandomStream = PhiloxStream<UniformBits::k32>;
// The streams of uncertainty and R-Test trials.
using TrialStream = PhiloxStream<UniformBits::k53>;

// Standard gamma variate of shape k > 0 from stream s (Marsaglia & Tsang, "A simple method for
// generating gamma variables", ACM TOMS 26 (2000) 363; for k < 1 the boost
// G(k) = G(k + 1) U^(1/k)). 2·G(ν/2) is a χ² variate with ν degrees of freedom.
template <UniformBits kBits>
double sample_standard_gamma(double k, PhiloxStream<kBits>& s) {
  if (k < 1.0) {
    const double g = sample_standard_gamma(k + 1.0, s);
    return g * std::pow(s.uniform(), 1.0 / k);
  }
  const double d = k - 1.0 / 3.0;
  const double c = 1.0 / std::sqrt(9.0 * d);
  for (;;) {
    double x, v;
    do {
      x = s.normal();
      v = 1.0 + c * x;
    } while (v <= 0.0);
    v = v * v * v;
    const double u = s.uniform();
    if (u < 1.0 - 0.0331 * x * x * x * x) return d * v;
    if (std::log(u) < 0.5 * x * x + d * (1.0 - v + std::log(v))) return d * v;
  }
}

}  // namespace gearmc
