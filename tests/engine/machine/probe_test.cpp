// The probing part of a drawn CMM and ISO 10360-5's probing test (engine/machine/probing_test.h),
// and the probe's share of the length test (machine_prior.h: length_test_with_probe). Reference
// values are computed by hand from the model's formula on the 25-point pattern (below).
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "engine/machine/machine_prior.h"
#include "engine/machine/probing_test.h"

namespace gearmc {
namespace {

TEST(ProbingTest, TwentyFivePointsInFiveRings) {
  const std::vector<Eigen::Vector3d> v = probing_test_directions();
  ASSERT_EQ(v.size(), 25u);
  int pole = 0, ring[4] = {0, 0, 0, 0};
  for (const Eigen::Vector3d& d : v) {
    EXPECT_NEAR(d.norm(), 1.0, 1e-12);
    const double polar = std::acos(std::clamp(d.z(), -1.0, 1.0)) * 180.0 / std::numbers::pi;
    if (polar < 1e-9) ++pole;
    for (int r = 0; r < 4; ++r) {
      if (std::abs(polar - 22.5 * (r + 1)) < 1e-9) ++ring[r];
    }
  }
  EXPECT_EQ(pole, 1);
  EXPECT_EQ(ring[0], 4);
  EXPECT_EQ(ring[1], 8);
  EXPECT_EQ(ring[2], 4);
  EXPECT_EQ(ring[3], 8);
}

TEST(ProbingTest, SphereFitTakesAShiftAndARadiusAndNothingElse) {
  const std::vector<Eigen::Vector3d> v = probing_test_directions();
  // Errors that are a sphere moved by c and grown by ρ: no form.
  const Eigen::Vector3d c(0.7, -0.3, 1.1);
  std::vector<double> e(v.size());
  for (std::size_t i = 0; i < v.size(); ++i) e[i] = v[i].dot(c) + 0.4;
  EXPECT_NEAR(sphere_form_um(v, e), 0.0, 1e-12);
  // Adding them to any errors leaves the form unchanged.
  std::vector<double> bumps(v.size(), 0.0), both(v.size());
  bumps[3] = 1.0;
  bumps[17] = -0.5;
  for (std::size_t i = 0; i < v.size(); ++i) both[i] = bumps[i] + e[i];
  EXPECT_NEAR(sphere_form_um(v, both), sphere_form_um(v, bumps), 1e-12);
  EXPECT_GT(sphere_form_um(v, bumps), 1.0);
}

TEST(ProbingTest, TwoLobesGiveTheirRangeOnThePattern) {
  // p(d) = sin θ · a cos 2φ. On every ring of the pattern (4 or 8 equally spaced azimuths)
  // cos 2φ sums to zero against 1, cos φ and sin φ, so the fitted sphere takes nothing and the
  // form is the range of the errors themselves: the 67.5° ring at azimuths 0°, 90°, … has
  // cos 2φ = ±1 with sin θ = sin 67.5° = 0.92388, the largest of the rings (equator: cos 2φ =
  // ±0.7071 at 22.5° + k·45°; 45°: 0.7071 · 0.7071; 22.5°: 0.38268). Form = 2 · 0.92388 · a.
  CmmProbe probe;
  probe.cos_um[0] = 0.5;
  EXPECT_NEAR(probing_test_form_um(probe, 1, 0),
              2.0 * std::sin(67.5 * std::numbers::pi / 180.0) * 0.5, 1e-12);
  // Along the stylus (the pole) the pre-travel is zero.
  EXPECT_DOUBLE_EQ(probe.pretravel_um(Eigen::Vector3d(0, 0, -1)), 0.0);
}

TEST(ProbingTest, ScatterAloneGivesAFormOfItsSize) {
  // σ = 0.2 µm, no lobing: the range of 25 values of N(0, σ²) has mean 3.93 σ (Tippett's
  // tables); the residuals of a 4-parameter fit scatter a little less (about √(21/25) of it,
  // 3.6 σ). Over 400 seeds the mean range must lie in [3.2, 4.1] σ (its own standard error is
  // about 0.04 σ): wide enough for the fit, narrow enough to catch σ used twice or not at all.
  CmmProbe probe;
  probe.noise_um = 0.2;
  double sum = 0.0;
  for (int i = 0; i < 400; ++i)
    sum += probing_test_form_um(probe, 7, static_cast<std::uint64_t>(i));
  const double mean_sigma = sum / 400.0 / 0.2;
  EXPECT_GT(mean_sigma, 3.2);
  EXPECT_LT(mean_sigma, 4.1);
}

TEST(LengthTestWithProbe, EvenLobesShortenEveryLengthOddOnesCancel) {
  KinematicMachine perfect;
  // Two lobes, a = 0.3 µm, maximum along x: p(±x̂) = 0.3, p(±ŷ) = −0.3, p(±ẑ) = 0 (along the
  // stylus). A bidirectional length loses p(û) + p(−û).
  CmmProbe two;
  two.cos_um[0] = 0.3;
  const std::vector<LengthTestPosition> positions = length_test_positions(perfect.travel_mm);
  for (const LengthError& e : length_test_with_probe(perfect, two)) {
    const Eigen::Vector3d& u = positions[static_cast<std::size_t>(e.position)].direction;
    const double h = std::hypot(u.x(), u.y());
    const double phi = std::atan2(u.y(), u.x());
    // p(û) = p(−û) = h · 0.3 cos 2φ (cos 2(φ + π) = cos 2φ).
    EXPECT_NEAR(e.error_um, -2.0 * h * 0.3 * std::cos(2.0 * phi), 1e-12) << e.position;
  }
  // Positions 4, 5, 6 are x, y, z, five lengths each: −2a along x, +2a along y, 0 along z.
  const std::vector<LengthError> errors = length_test_with_probe(perfect, two);
  EXPECT_NEAR(errors[20].error_um, -0.6, 1e-12);
  EXPECT_NEAR(errors[25].error_um, 0.6, 1e-12);
  EXPECT_NEAR(errors[30].error_um, 0.0, 1e-12);
  // Three lobes: p(−û) = −p(û), the two ends cancel in every length.
  CmmProbe three;
  three.cos_um[1] = 0.4;
  three.sin_um[1] = -0.2;
  for (const LengthError& e : length_test_with_probe(perfect, three)) {
    EXPECT_NEAR(e.error_um, 0.0, 1e-12);
  }
}

TEST(LengthTestWithProbe, KeptMachinesPassBothTestsAndTheRefusalsAddUp) {
  const LengthMpe mpe = parse_length_mpe("1.8 + L/300");
  const MachinePrior prior = prior_for(mpe, MachineLayout::kBridge, {700, 1000, 600});
  const ProbePrior probe = probe_prior_for(1.7);
  const ConstrainedMachines c = draw_constrained(prior, mpe, 30, 5000, 11, {}, probe);
  ASSERT_FALSE(c.refused) << c.why;
  ASSERT_EQ(c.kept.size(), 30u);
  ASSERT_EQ(c.probes.size(), 30u);
  for (std::size_t i = 0; i < c.kept.size(); ++i) {
    // Each kept machine's own tests, run again here.
    for (const LengthError& e : length_test_with_probe(c.kept[i], c.probes[i])) {
      EXPECT_LE(std::abs(e.error_um), mpe.at(e.length_mm) + 1e-12);
    }
    EXPECT_LE(c.probing_form_um[i], 1.7);
    EXPECT_LE(c.length_ratio[i], 1.0);
  }
  // Every refused machine failed at least one test; some failed each.
  EXPECT_GE(c.failed_length + c.failed_probing, c.drawn - 30);
  EXPECT_GT(c.failed_probing, 0);
  EXPECT_GT(c.failed_length, 0);
  // Without MPE_P the machines have a perfect probe.
  const CmmProbe none = draw_probe(ProbePrior{}, 11, 0);
  EXPECT_EQ(none.noise_um, 0.0);
  EXPECT_EQ(none.cos_um[0], 0.0);
}

}  // namespace
}  // namespace gearmc
