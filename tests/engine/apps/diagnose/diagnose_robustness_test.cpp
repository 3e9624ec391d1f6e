// Tests of what keeps a diagnosis honest on real data (engine/apps/diagnose, docs/diagnosis.md):
// the held-out half of every plan, the outlier screen's false-alarm rate and its catch of gross
// outliers (a dirty-ball reading), and the fit per gear of an effect that differs from gear to
// gear. Readings are simulated from the built-in reference with fixed seeds.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <random>
#include <string>
#include <tuple>
#include <vector>

#include "engine/apps/diagnose/diagnosis.h"
#include "engine/apps/diagnose/diagnosis_stages.h"
#include "engine/apps/diagnose/fitted_scenario.h"
#include "tests/support/diagnose_readings.h"

namespace gearmc {
namespace {

using testing_support::baseline;
using testing_support::master_readings;
using testing_support::with_effects;

// Residual points of a plan: the given teeth and sides, profile indices 0..n−1, sections 0..m−1.
std::vector<ResidualPoint> plan_points(const std::vector<int>& teeth,
                                       const std::vector<FlankSide>& sides, int n, int m) {
  std::vector<ResidualPoint> out;
  for (int tooth : teeth) {
    for (FlankSide side : sides) {
      for (int j = 0; j < m; ++j) {
        for (int i = 0; i < n; ++i) {
          ResidualPoint p;
          p.tooth = tooth;
          p.side = side;
          p.i = i;
          p.j = j;
          out.push_back(p);
        }
      }
    }
  }
  return out;
}

TEST(DiagnoseHeldOut, EveryPlanSplitsIntoTwoHalvesThatCanEachBeFitted) {
  using diagnosis_stages::held_out_split;
  const std::vector<FlankSide> both = {FlankSide::kLeft, FlankSide::kRight};
  // The usual 4-tooth plan has only odd teeth: the measured teeth alternate, 1 and 13 against 7
  // and 19 (an odd/even split would leave one half empty).
  const std::vector<ResidualPoint> four = plan_points({1, 7, 13, 19}, both, 10, 5);
  const diagnosis_stages::HeldOutSplit a = held_out_split(four, 14);
  EXPECT_EQ(a.name, "alternating_teeth");
  ASSERT_EQ(a.fold.size(), four.size());
  for (std::size_t k = 0; k < four.size(); ++k) {
    EXPECT_EQ(a.fold[k], four[k].tooth == 1 || four[k].tooth == 13 ? 0 : 1) << k;
  }
  // One tooth: its two flanks; one flank: alternate face sections; one section: alternate
  // profile points; one point, or halves too small for the parameters: none.
  EXPECT_EQ(held_out_split(plan_points({5}, both, 10, 5), 14).name, "flanks");
  EXPECT_EQ(held_out_split(plan_points({5}, {FlankSide::kLeft}, 10, 5), 14).name,
            "alternating_sections");
  EXPECT_EQ(held_out_split(plan_points({5}, {FlankSide::kLeft}, 10, 1), 2).name,
            "alternating_profile_points");
  const diagnosis_stages::HeldOutSplit none =
      held_out_split(plan_points({5}, {FlankSide::kLeft}, 10, 1), 5);
  EXPECT_EQ(none.name, "none");
  EXPECT_TRUE(none.fold.empty());
  EXPECT_FALSE(none.why_none.empty());
  EXPECT_EQ(held_out_split(plan_points({5}, {FlankSide::kLeft}, 1, 1), 0).name, "none");
}

TEST(DiagnoseHeldOut, OnAPlanOfOddTeethTheHeldOutRmsIsTheNoiseNotTheGapBefore) {
  // Lobing hidden (6 lobes ±0.75 µm) on P1's usual 4 teeth 1, 7, 13, 19 with noise σ 0.3 µm: the
  // lobing fitted on two teeth predicts the other two, so the held-out RMS is the noise, 0.3 µm
  // inflated by the half fit's own estimation error (√(1 + p/n) ≈ 1.03 for p = 14 of n = 200),
  // far below the RMS before (≈ 0.6 µm). Seeds 1 (simulation and null).
  Scenario truth = with_effects(
      "probe_lobing: {harmonics: [{order: 6, amplitude_um: 0.75, phase_deg: 90}]}\n"
      "noise: {sigma_um: 0.3}\n");
  truth.probing.teeth = {1, 7, 13, 19};
  Scenario model = baseline();
  model.probing.teeth = {1, 7, 13, 19};
  const Diagnosis d = diagnose(model, master_readings(truth));
  ASSERT_EQ(d.named_effect_text(), "probe_lobing");
  EXPECT_EQ(d.held_out_split, "alternating_teeth");
  EXPECT_GT(d.gap_before.rms_um, 0.5);
  EXPECT_GT(d.held_out_rms_um, 0.27);
  EXPECT_LT(d.held_out_rms_um, 0.36);
}

// profile_scans (sorted indices) groups and orders the points as a tree keyed by (gear, tooth,
// flank, section) and then roll index does when filled in file order (a later point with the same
// key replaces the earlier): reference built here with std::map. Points of 2 gears × 3 teeth ×
// 2 flanks × 3 sections × 7 roll indices, shuffled (seed 4), 40 repeated positions appended, and a
// scan of 2 points.
TEST(DiagnoseOutliers, ProfileScansGroupAndOrderThePointsAsAKeyedTreeWould) {
  std::vector<ResidualPoint> points;
  for (int gear = 0; gear < 2; ++gear) {
    for (ResidualPoint p : plan_points({1, 2, 3}, {FlankSide::kLeft, FlankSide::kRight}, 7, 3)) {
      p.gear = gear;
      points.push_back(p);
    }
  }
  std::mt19937 rng(4);
  std::shuffle(points.begin(), points.end(), rng);
  for (int k = 0; k < 40; ++k) points.push_back(points[static_cast<std::size_t>(k * 5)]);
  ResidualPoint lone;
  lone.tooth = 9;
  points.push_back(lone);
  lone.i = 1;
  points.push_back(lone);
  std::map<std::tuple<int, int, int, int>, std::map<int, int>> tree;
  for (std::size_t k = 0; k < points.size(); ++k) {
    const ResidualPoint& p = points[k];
    tree[{p.gear, p.tooth, p.side == FlankSide::kRight ? 1 : 0, p.j}][p.i] = static_cast<int>(k);
  }
  const ProfileScans scans = profile_scans(points);
  ASSERT_EQ(scans.count(), tree.size());
  std::size_t s = 0;
  for (const auto& [key, scan] : tree) {
    std::vector<int> expected;
    for (const auto& [i, k] : scan) expected.push_back(k);
    const std::vector<int> got(
        scans.points.begin() + static_cast<std::ptrdiff_t>(scans.start[s]),
        scans.points.begin() + static_cast<std::ptrdiff_t>(scans.start[s + 1]));
    EXPECT_EQ(got, expected) << "scan " << s;
    ++s;
  }
  EXPECT_EQ(profile_scans({}).count(), 0u);
}

TEST(DiagnoseOutliers, TheScreenKeepsItsFalseAlarmRateAndFindsGrossOutliers) {
  // Clean files: the 4-tooth plan (400 readings) with smooth structure along each scan
  // (2 µm·sin(0.4 i + j), far above the noise) plus Gaussian noise σ 0.3 µm. The screen's stated
  // false-alarm rate is 1 % per file (outlier_screen.h): over 300 files (std::mt19937_64 seed
  // 20261122) the count of files with any exclusion is Binomial(300, ≤ 0.01); ≥ 9 has
  // probability < 0.4 % (a test at the 0.4 % significance level). Then each file with a 6 µm
  // reading added at a random place (≥ 8σ of the noise of the prediction from its neighbours,
  // 0.3·√6 = 0.73 µm at a scan's end, where it is weakest): found, and only it.
  std::mt19937_64 rng(20261122);
  std::normal_distribution<double> noise(0.0, 0.3);
  const std::vector<ResidualPoint> plan =
      plan_points({1, 7, 13, 19}, {FlankSide::kLeft, FlankSide::kRight}, 10, 5);
  int false_alarms = 0, found = 0;
  const int files = 300;
  for (int f = 0; f < files; ++f) {
    Residuals clean;
    clean.points = plan;
    for (ResidualPoint& p : clean.points) {
      p.residual_um = 2.0 * std::sin(0.4 * p.i + p.j) + noise(rng);
    }
    if (!screen_outliers(clean).excluded.empty()) ++false_alarms;
    const int at = static_cast<int>(rng() % clean.points.size());
    clean.points[static_cast<std::size_t>(at)].residual_um += 6.0;
    const OutlierScreen dirty = screen_outliers(clean);
    if (dirty.excluded.size() == 1 && dirty.excluded[0].row == at) ++found;
  }
  EXPECT_LE(false_alarms, 8) << "of " << files;
  // A clean file's own false alarm (≤ 1 %) may add a second exclusion: ≥ 97 % exact finds.
  EXPECT_GE(found, 291) << "of " << files;
  // The excluded reading is taken out of the residuals, everything else kept in order.
  Residuals one;
  one.points = plan;
  for (ResidualPoint& p : one.points) p.residual_um = 2.0 * std::sin(0.4 * p.i + p.j);
  one.points[17].residual_um += 4.0;
  const OutlierScreen screen = screen_outliers(one);
  // The threshold z* is Bonferroni's two-sided one over the file's n readings: P(|Z| > z*) =
  // α/n, i.e. ½ erfc(z*/√2) = α/(2n) (α = 0.01, n = 400), solved here by bisection on erfc.
  {
    const double target = 0.01 / (2.0 * static_cast<double>(plan.size()));
    double lo = 0.0, hi = 10.0;
    for (int k = 0; k < 200; ++k) {
      const double mid = 0.5 * (lo + hi);
      (0.5 * std::erfc(mid / std::sqrt(2.0)) > target ? lo : hi) = mid;
    }
    EXPECT_NEAR(screen.threshold_z, 0.5 * (lo + hi), 1e-9);  // 3.66 for n = 400
  }
  ASSERT_EQ(screen.excluded.size(), 1u);
  EXPECT_EQ(screen.excluded[0].row, 17);
  const Residuals kept = without_excluded(one, screen);
  ASSERT_EQ(kept.points.size(), plan.size() - 1);
  EXPECT_EQ(kept.points[17].i, plan[18].i);
}

TEST(DiagnoseOutliers, OneDirtyReadingInANullDatasetNamesNothing) {
  // A null dataset (the model's own noise σ 0.3 µm, seed 1) with one reading 6 µm off (a dirty
  // ball): without the screen the point-law stage read the heavy tail as a larger noise and
  // named "noise" (the code before the screen did so here at 6, 10, 30 and 100 µm). Now the
  // reading is excluded (listed with its row) and the verdict on the rest is "none".
  Readings readings = master_readings(baseline());
  const std::size_t dirty = 1234;
  readings.rows[dirty].c += 0.006 * readings.rows[dirty].n;
  const Diagnosis d = diagnose(baseline(), readings);
  ASSERT_EQ(d.outliers.excluded.size(), 1u);
  EXPECT_EQ(d.outliers.excluded[0].row, static_cast<int>(dirty));
  EXPECT_EQ(d.named_effect_text(), "none");
  EXPECT_TRUE(d.effects.empty());
}

TEST(DiagnosePerGear, AnEffectThatDiffersFromGearToGearIsFittedPerGear) {
  // Six gears in one file (a nominal master measured six times, simulate --gears 6 --master):
  // the set-up eccentricity x is drawn per gear from N(5, 3²) µm (the truth's law), noise
  // 0.3 µm. The diagnosis names eccentricity, finds that it varies from gear to gear (F test,
  // α = 1 %), fits each gear's value within 4 standard errors of that gear's own draw
  // (EffectChain::draw(seed, gear), the truth's stream) and writes a normal law into fitted.yaml.
  // With the same eccentricity on every gear (x_um: 5) it does not vary. Seeds 1.
  for (const bool varies : {true, false}) {
    const Scenario truth =
        with_effects(std::string(varies ? "eccentricity: {x_um: {normal: [5, 3]}}\n"
                                        : "eccentricity: {x_um: 5}\n") +
                     "noise: {sigma_um: 0.3}\n");
    SimulateOptions o;
    o.master = true;
    o.gears = 6;
    const Readings readings = simulate_readings(truth, o).readings;
    const Diagnosis d = diagnose(baseline(), readings);
    ASSERT_EQ(d.named_effect_text(), "eccentricity") << varies;
    const FittedEffect& e = d.effects.front();
    EXPECT_EQ(e.varies_per_gear, varies) << "p = " << e.per_gear_p;
    if (!varies) {
      EXPECT_GE(e.per_gear_p, 0.01);
      EXPECT_TRUE(e.per_gear.empty());
      continue;
    }
    EXPECT_LT(e.per_gear_p, 1e-6);
    ASSERT_EQ(e.per_gear.size(), 6u);
    const int x = truth.effects->find("eccentricity");
    ASSERT_GE(x, 0);
    for (const FittedEffect::GearValues& g : e.per_gear) {
      const double drawn = truth.effects->draw(truth.seed, g.gear)[static_cast<std::size_t>(x)][0];
      const FittedValue* value = nullptr;
      for (const FittedValue& c : g.coefficients) {
        if (c.name == "x_um") value = &c;
      }
      ASSERT_NE(value, nullptr);
      ASSERT_TRUE(value->estimable);
      EXPECT_NEAR(value->value, drawn, 4.0 * value->std_error) << "gear " << g.gear;
    }
    const FittedScenario fitted = fitted_scenario(baseline(), d, "model.yaml", "readings.csv");
    EXPECT_NE(fitted.yaml.find("x_um: {normal: ["), std::string::npos) << fitted.yaml;
    // y does not vary (the truth's y_um is 0 on every gear): its per-gear values spread no more
    // than their standard errors, so it keeps one value.
    EXPECT_EQ(fitted.yaml.find("y_um: {normal:"), std::string::npos) << fitted.yaml;
  }
}

}  // namespace
}  // namespace gearmc
