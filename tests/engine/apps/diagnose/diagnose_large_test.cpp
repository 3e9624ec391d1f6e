// Tests of the diagnosis's large-file mode (DiagnoseOptions::null_rows, diagnosis_gap.cpp and
// point_law_stage.h): above 2 × null_rows readings the gap's χ² and KS null laws are simulated on
// a subsample and rescaled, the spectrum's bands come from the harmonic fit's exact covariance and
// the white-variance test from its normal approximation. Here null_rows is lowered so that the
// mode runs on 8 gears (19 200 readings, a subsample of about 3 900), and every p-value it gives
// is compared with an independent value: on the model's own readings the exact χ² tail of Σr²/σ²
// (regularised incomplete gamma function) and Kolmogorov's limit law, and otherwise the full
// simulation of all 19 200 readings. K = 999 replicates, seed 1 (gearmc's streams).
// Tolerance on a p-value: 0.07, 3.2 standard deviations of the difference of two Monte-Carlo
// p-values from 999 replicates at p = 0.5 (√(2 · 0.25/1000) = 0.022); on the spectrum's null
// 95 % bands: 5 % on their mean over the orders (the sampling error of one band from 999
// replicates is about 3 %, of the mean over 26 bands well under 1 %) and 20 % on each.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <string>
#include <vector>

#include "core/random_stream.h"
#include "core/special_functions.h"
#include "engine/apps/diagnose/diagnosis.h"
#include "engine/apps/diagnose/linear_model.h"
#include "engine/apps/diagnose/point_law_stage.h"
#include "tests/support/diagnose_readings.h"

namespace gearmc {
namespace {

using testing_support::with_effects;

Readings eight_gears(const std::string& effects) {
  Scenario truth = with_effects(effects);
  SimulateOptions o;
  o.master = true;
  o.gears = 8;
  truth.seed = 5;
  return simulate_readings(truth, o).readings;
}

DiagnoseOptions options_with(int null_rows) {
  DiagnoseOptions o;
  o.selection.null_replicates = 999;
  o.selection.seed = 1;
  o.null_rows = null_rows;
  return o;
}

// Orders the fit takes out entirely (its own harmonics) have bands of rounding size (1e-11 µm)
// in both: they must stay below 1e-6 of the largest band, the others agree in ratio.
void expect_bands_close(const std::vector<double>& sub, const std::vector<double>& full) {
  ASSERT_EQ(sub.size(), full.size());
  const double largest = *std::max_element(full.begin(), full.end());
  double mean_rel = 0.0;
  int compared = 0;
  for (std::size_t k = 0; k < sub.size(); ++k) {
    if (full[k] < 1e-6 * largest) {
      EXPECT_LT(sub[k], 1e-6 * largest) << "order " << k;
      continue;
    }
    const double rel = std::abs(sub[k] / full[k] - 1.0);
    EXPECT_LT(rel, 0.2) << "order " << k << ": " << sub[k] << " vs " << full[k];
    mean_rel += rel;
    ++compared;
  }
  ASSERT_GT(compared, 5);
  EXPECT_LT(mean_rel / compared, 0.05);
}

TEST(DiagnoseLarge, TheSubsampledNullGivesTheFullSimulationsPValues) {
  // The truth has probe lobing the model lacks (so an effect is fitted and the statistics after
  // it are projected) and the model's noise; the model: the reference with noise 0.3 µm.
  const Scenario model = with_effects("noise: {sigma_um: 0.3}\n");
  const Readings readings = eight_gears(
      "probe_lobing: {harmonics: [{order: 6, amplitude_um: 0.75, phase_deg: 90}]}\n"
      "noise: {sigma_um: 0.3}\n");
  const Diagnosis full = diagnose(model, readings, options_with(1000000));
  const Diagnosis sub = diagnose(model, readings, options_with(4000));
  const int n = sub.points;
  ASSERT_GT(n, 8000);
  EXPECT_EQ(full.null_rows, n);
  EXPECT_GT(sub.null_rows, 3000);
  EXPECT_LT(sub.null_rows, 4800);
  ASSERT_FALSE(sub.effects.empty());
  EXPECT_EQ(sub.effects.front().name, full.effects.front().name);

  // Before any fit the lobing makes both extreme (p at its floor 1/(K + 1)).
  EXPECT_NEAR(sub.gap_before.chi2_p, full.gap_before.chi2_p, 0.07);
  EXPECT_NEAR(sub.gap_before.ks_p, full.gap_before.ks_p, 0.07);
  // After the fit: the full simulation.
  EXPECT_NEAR(sub.gap_after.chi2_p, full.gap_after.chi2_p, 0.07);
  EXPECT_NEAR(sub.gap_after.ks_p, full.gap_after.ks_p, 0.07);
  expect_bands_close(sub.spectrum_null95_before_um, full.spectrum_null95_before_um);
  expect_bands_close(sub.spectrum_null95_after_um, full.spectrum_null95_after_um);
  // The white-variance test by its normal approximation against its simulation.
  EXPECT_NEAR(sub.point_law.white_p, full.point_law.white_p, 0.07);
  // The note says how the subsample was taken: 19 200 readings, null_rows 9 000 → every 3rd run.
  const Diagnosis third = diagnose(model, readings, options_with(9000));
  bool said = false;
  for (const std::string& note : third.notes) {
    if (note.find("was simulated on") == std::string::npos) continue;
    said = true;
    EXPECT_NE(note.find("every 3rd run of 64 points"), std::string::npos) << note;
  }
  EXPECT_TRUE(said);
}

TEST(DiagnoseLarge, OnTheModelsOwnReadingsTheRescaledNullHasTheExactLaws) {
  // Readings of the model itself (Gaussian noise 0.3 µm, nothing else): before any fit
  // Σr²/σ² ~ χ²_n exactly, so its p-value is the regularised gamma tail, and √n·KS follows
  // Kolmogorov's law (ks_p_value) — both independent of the simulation.
  const Scenario model = with_effects("noise: {sigma_um: 0.3}\n");
  const Readings readings = eight_gears("noise: {sigma_um: 0.3}\n");
  const Diagnosis sub = diagnose(model, readings, options_with(4000));
  ASSERT_LT(sub.null_rows, sub.points / 2);
  const double chi2 = sub.gap_before.chi2_dof * sub.gap_before.dof;
  const double exact_chi2_p = regularized_gamma_q(0.5 * sub.gap_before.dof, 0.5 * chi2);
  ASSERT_GT(exact_chi2_p, 0.05);  // not at a floor, so the comparison can tell
  EXPECT_NEAR(sub.gap_before.chi2_p, exact_chi2_p, 0.07);
  const double kolmogorov_p = ks_p_value(sub.gap_before.ks, sub.points);
  ASSERT_GT(kolmogorov_p, 0.05);
  EXPECT_NEAR(sub.gap_before.ks_p, kolmogorov_p, 0.07);
}

TEST(DiagnoseLarge, TheWhiteTestsNormalApproximationHoldsForAUniformPart) {
  // The model's law with a uniform part (step quantisation 1.2 µm), readings from the model
  // itself: the normal approximation (mean through the fit's projection, variance with the law's
  // κ₄) against the simulation of all readings.
  const std::string law = "step_quantization: {step_um: 1.2}\nnoise: {sigma_um: 0.3}\n";
  const Scenario model = with_effects(law);
  const Readings readings = eight_gears(law);
  const Diagnosis full = diagnose(model, readings, options_with(1000000));
  const Diagnosis sub = diagnose(model, readings, options_with(4000));
  ASSERT_TRUE(full.point_law.ran);
  EXPECT_DOUBLE_EQ(sub.point_law.white_variance_um2, full.point_law.white_variance_um2);
  EXPECT_NEAR(sub.point_law.white_p, full.point_law.white_p, 0.07);
}

// The variance of Σd² over second differences of independent readings (point_law_stage.h,
// white_sum_variance) against the sample variance of Σd² by brute force: 20 000 replicates of
// one scan of 60 readings, uniform of width 3 µm plus N(0, 0.05²) — a law whose fourth cumulant
// (−3⁴/120 = −0.675 µm⁴) takes 31 % off the Gaussian formula's variance, so a formula without it
// fails. Tolerance 4 %: the sample variance of 20 000 values has a relative standard error of
// √((κ/σ⁴ − 1)/20 000) ≈ 1 % for this nearly normal sum. Seed 3.
TEST(DiagnoseLarge, TheWhiteSumVarianceHasTheLawsFourthCumulant) {
  constexpr int kPoints = 60, kReplicates = 20000;
  constexpr double kWidth = 3.0, kSigma = 0.05;
  std::vector<std::array<int, 3>> triplets;
  for (int i = 0; i + 2 < kPoints; ++i) triplets.push_back({i, i + 1, i + 2});
  RandomStream rng(3, 0, StreamPurpose::kDiagnoseNull, 77);
  double sum = 0.0, sum2 = 0.0;
  std::vector<double> e(kPoints);
  for (int k = 0; k < kReplicates; ++k) {
    for (double& v : e) v = kWidth * (rng.uniform() - 0.5) + kSigma * rng.normal();
    double s = 0.0;
    for (const auto& t : triplets) {
      const double d = e[t[0]] - 2.0 * e[t[1]] + e[t[2]];
      s += d * d;
    }
    sum += s;
    sum2 += s * s;
  }
  const double mean = sum / kReplicates;
  const double brute = (sum2 - kReplicates * mean * mean) / (kReplicates - 1);
  const double v = kSigma * kSigma + kWidth * kWidth / 12.0;
  const double kappa4 = -std::pow(kWidth, 4) / 120.0;
  EXPECT_NEAR(white_sum_variance(triplets, v, kappa4) / brute, 1.0, 0.04);
  EXPECT_GT(white_sum_variance(triplets, v, 0.0) / brute, 1.2);  // the Gaussian formula is off
}

}  // namespace
}  // namespace gearmc
