// Counter-based random numbers for the uncertainty command (Random123 Philox4x32-10, Salmon et
// al., "Parallel random numbers: as easy as 1, 2, 3", SC11). The stream of input i in trial t is
// a pure function of (seed, t, i): its n-th number is Philox(key = seed, counter = (n, t_lo,
// t_hi, i)). So a trial's draws never depend on the thread that runs it, on the order trials
// are run or on how trials are split across threads or processes; any trial can be re-drawn
// alone. Uniforms have 53 random bits (two 32-bit words per double).
#pragma once

#include <Random123/philox.h>

#include <cmath>
#include <cstdint>
#include <numbers>

namespace gearmc::uncertainty {

class TrialStream {
 public:
  TrialStream(std::uint64_t seed, std::uint64_t trial, std::uint32_t input) {
    key_ = {{static_cast<std::uint32_t>(seed), static_cast<std::uint32_t>(seed >> 32)}};
    ctr_ = {
        {0u, static_cast<std::uint32_t>(trial), static_cast<std::uint32_t>(trial >> 32), input}};
  }

  // Uniform in the open interval (0, 1): (k + 1/2) 2^-53 for a 53-bit integer k, so log() and
  // the inverse CDFs of unbounded laws are always finite.
  double uniform() {
    if (used_ == 2) refill();
    const std::uint64_t hi = buffer_.v[2 * used_];
    const std::uint64_t lo = buffer_.v[2 * used_ + 1];
    ++used_;
    const std::uint64_t k = ((hi << 32) | lo) >> 11;
    return (static_cast<double>(k) + 0.5) * 0x1.0p-53;
  }
  // Standard normal by Box–Muller (the cosine branch only, so each value depends only on its
  // position in the stream).
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
  int used_ = 2;
};

}  // namespace gearmc::uncertainty
