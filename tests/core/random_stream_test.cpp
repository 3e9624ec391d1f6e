// Tests of core/random_stream.h, the one Philox stream class. The reference is Random123's
// Philox4x32-10 called directly with the key and counter layout the header documents (a stream's
// n-th number is a pure function of its name and n), the generator itself checked against the
// known-answer vector of Random123's kat_vectors file; the 53-bit uniform against its formula
// (k + 1/2) 2^-53 computed here in integer arithmetic.
#include "core/random_stream.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <set>

namespace gearmc {
namespace {

using Philox = r123::Philox4x32;

// Random123 1.09 examples/kat_vectors (reproduced by a Python transcription of the published
// round function, multipliers D2511F53 / CD9E8D57, Weyl constants 9E3779B9 / BB67AE85):
// "philox4x32 10 243f6a88 85a308d3 13198a2e 03707344
// a4093822 299f31d0 -> d16cfe09 94fdcceb 5001e420 24126ea1" (counter, key -> output).
TEST(RandomStream, PhiloxKnownAnswer) {
  Philox g;
  const Philox::ctr_type ctr = {{0x243f6a88u, 0x85a308d3u, 0x13198a2eu, 0x03707344u}};
  const Philox::key_type key = {{0xa4093822u, 0x299f31d0u}};
  const Philox::ctr_type out = g(ctr, key);
  EXPECT_EQ(out.v[0], 0xd16cfe09u);
  EXPECT_EQ(out.v[1], 0x94fdccebu);
  EXPECT_EQ(out.v[2], 0x5001e420u);
  EXPECT_EQ(out.v[3], 0x24126ea1u);
}

// A gear's stream: key (seed folded, gear), counter (n, seed's high word, purpose, sub-index);
// four uniforms per block, r123::u01 of each word.
TEST(RandomStream, GearStreamFollowsItsDocumentedLayout) {
  const std::uint64_t seed = 0x0123'4567'89AB'CDEFull;
  const std::uint32_t gear = 41;
  RandomStream s(seed, gear, StreamPurpose::kProfile, 7);
  Philox g;
  const Philox::key_type key = {
      {static_cast<std::uint32_t>(seed ^ (seed >> 32) * 0x9E3779B9u), gear}};
  for (std::uint32_t block = 0; block < 3; ++block) {
    const Philox::ctr_type ctr = {{block, static_cast<std::uint32_t>(seed >> 32),
                                   static_cast<std::uint32_t>(StreamPurpose::kProfile), 7u}};
    const Philox::ctr_type words = g(ctr, key);
    for (int w = 0; w < 4; ++w) {
      const double u = s.uniform();
      // u01<double>(x) = (x + 1/2) 2^-32 rounded, in (0, 1].
      EXPECT_NEAR(u, (static_cast<double>(words.v[w]) + 0.5) * 0x1.0p-32, 0x1.0p-52);
      EXPECT_GT(u, 0.0);
      EXPECT_LE(u, 1.0);
    }
  }
}

// A trial's stream: key (seed low, seed high), counter (n, trial low, trial high, input); two
// uniforms per block, each from two words: k = ((w0 << 32) | w1) >> 11, u = (k + 1/2) 2^-53.
TEST(RandomStream, TrialStreamFollowsItsDocumentedLayout) {
  const std::uint64_t seed = 0xFEDC'BA98'7654'3210ull;
  const std::uint64_t trial = 0x0000'0003'0000'0009ull;  // both words in use
  TrialStream s(seed, trial, 5u);
  Philox g;
  const Philox::key_type key = {
      {static_cast<std::uint32_t>(seed), static_cast<std::uint32_t>(seed >> 32)}};
  for (std::uint32_t block = 0; block < 3; ++block) {
    const Philox::ctr_type ctr = {{block, 9u, 3u, 5u}};
    const Philox::ctr_type words = g(ctr, key);
    for (int half = 0; half < 2; ++half) {
      const std::uint64_t k =
          ((std::uint64_t{words.v[2 * half]} << 32) | words.v[2 * half + 1]) >> 11;
      EXPECT_EQ(s.uniform(), (static_cast<double>(k) + 0.5) / 9007199254740992.0);
    }
  }
}

// A registered trial purpose is the input word it names.
TEST(RandomStream, TrialPurposeIsItsInputWord) {
  TrialStream a(11, 2, TrialPurpose::kRTestFullMcm);
  TrialStream b(11, 2, static_cast<std::uint32_t>(0x5254'0004));
  for (int i = 0; i < 9; ++i) EXPECT_EQ(a.uniform(), b.uniform());
}

// Streams with another name differ; the same name repeats; the normal draw is Box–Muller's
// cosine branch of two consecutive uniforms.
TEST(RandomStream, NamesSeparateStreamsAndNormalIsBoxMuller) {
  std::set<double> first;
  for (std::uint32_t gear = 0; gear < 4; ++gear) {
    for (StreamPurpose p : {StreamPurpose::kPitch, StreamPurpose::kHelix}) {
      first.insert(RandomStream(5, gear, p).uniform());
    }
  }
  EXPECT_EQ(first.size(), 8u);
  RandomStream x(5, 1, StreamPurpose::kEffectNoise, 3), y(5, 1, StreamPurpose::kEffectNoise, 3);
  const double u1 = y.uniform(), u2 = y.uniform();
  EXPECT_EQ(x.normal(), std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * M_PI * u2));
  TrialStream t(5, 1, 0u), v(5, 1, 0u);
  const double w1 = v.uniform(), w2 = v.uniform();
  EXPECT_EQ(t.normal(), std::sqrt(-2.0 * std::log(w1)) * std::cos(2.0 * M_PI * w2));
}

}  // namespace
}  // namespace gearmc
