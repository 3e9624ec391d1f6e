// Tests of the diagnosis core (engine/diagnose, docs/diagnosis.md): the numerical tools against
// closed forms and textbook values, the candidates' columns against the effects' closed-form
// signatures, the prediction against simulate_readings, and the whole diagnosis on readings in
// which one effect is hidden: readings simulated with simulate_readings from a truth scenario =
// the built-in reference (P1's gear and 10 × 5 grid on every flank, nominal master) + ONE effect
// + probing noise σ 0.3 µm, diagnosed against the baseline model (the reference with noise
// 0.3 µm only). The truth reaches the diagnosis only through the readings. Reference values are
// the truth's own parameters (the battery's sizes at 1×, docs/diagnosis.md); every test uses fixed
// seeds, so each assertion is deterministic (seed 1 of the simulation, seed 1 of the null
// simulation).
#include <gtest/gtest.h>

#include <unistd.h>
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <nlohmann/json.hpp>
#include <numbers>
#include <random>
#include <sstream>

#include "engine/diagnose/diagnosis.h"
#include "engine/diagnose/diagnosis_json.h"
#include "engine/diagnose/diagnosis_stages.h"
#include "engine/diagnose/fitted_scenario.h"
#include "engine/diagnose/linear_model.h"
#include "engine/diagnose/point_law_stage.h"
#include "engine/diagnose/report_plot_data.h"
#include "engine/effects/effect_config.h"
#include "engine/io/input_error.h"
#include "engine/mc/simulate.h"
#include "engine/stats/histogram.h"

namespace gearmc {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kNoiseUm = 0.3;  // the battery's probing noise σ 0.3 µm (docs/diagnosis.md)

Scenario with_effects(const std::string& effects_yaml) {
  Scenario s = reference_scenario();
  s.effects = std::make_shared<const EffectChain>(
      parse_effects(parse_yaml_document(effects_yaml, "effects.yaml")));
  return s;
}

// Readings of the nominal master (P1's gear, 2 400 points) with the truth's effects.
Readings master_readings(const Scenario& truth, std::uint64_t seed = 1) {
  SimulateOptions o;
  o.master = true;
  o.seed = seed;
  return simulate_readings(truth, o).readings;
}

// Truth = the reference + `effect_yaml` + noise 0.3 µm.
Readings hidden(const std::string& effect_yaml, std::uint64_t seed = 1) {
  return master_readings(with_effects(effect_yaml + "noise: {sigma_um: 0.3}\n"), seed);
}

Scenario baseline() { return with_effects("noise: {sigma_um: 0.3}\n"); }

const FittedValue& value(const FittedEffect& e, const std::string& name) {
  for (const FittedValue& v : e.parameters) {
    if (v.name == name) return v;
  }
  for (const FittedValue& v : e.coefficients) {
    if (v.name == name) return v;
  }
  ADD_FAILURE() << "no parameter " << name << " in " << e.name;
  static const FittedValue none;
  return none;
}

bool contains(const std::vector<std::string>& list, const std::string& name) {
  return std::find(list.begin(), list.end(), name) != list.end();
}

// --- Numerical tools --------------------------------------------------------------------------

TEST(DiagnoseTools, FDistributionTailMatchesClosedFormsAndTables) {
  // d1 = 2: P(F > f) = (1 + 2f/d2)^(−d2/2); d1 = d2 = 1: 1 − (2/π) atan √f (both follow from
  // the F density, Johnson, Kotz & Balakrishnan vol. 2, ch. 27).
  for (double f : {0.1, 1.0, 3.0, 10.0}) {
    for (double d2 : {5.0, 40.0, 2400.0}) {
      EXPECT_NEAR(f_distribution_upper_tail(f, 2, d2), std::pow(1.0 + 2.0 * f / d2, -d2 / 2),
                  1e-12);
    }
    EXPECT_NEAR(f_distribution_upper_tail(f, 1, 1), 1.0 - 2.0 / kPi * std::atan(std::sqrt(f)),
                1e-12);
  }
  // Table values (Abramowitz & Stegun table 26.9): F_0.05(1, 10) = 4.96, F_0.05(5, 10) = 3.33,
  // F_0.01(3, 120) = 3.95; more digits from the quantile function: 4.964603, 3.325835, 3.949163.
  EXPECT_NEAR(f_distribution_upper_tail(4.964603, 1, 10), 0.05, 1e-6);
  EXPECT_NEAR(f_distribution_upper_tail(3.325835, 5, 10), 0.05, 1e-6);
  EXPECT_NEAR(f_distribution_upper_tail(3.949163, 3, 120), 0.01, 1e-6);
}

TEST(DiagnoseTools, HolmAdjustmentOfATextbookExample) {
  // p = {0.01, 0.04, 0.03, 0.005}, m = 4: sorted 0.005·4 = 0.02, 0.01·3 = 0.03, 0.03·2 = 0.06,
  // 0.04·1 = 0.04 → monotone 0.06 (Holm 1979's step-down rule, by hand).
  const std::vector<double> adjusted = holm_adjust({0.01, 0.04, 0.03, 0.005});
  EXPECT_NEAR(adjusted[0], 0.03, 1e-15);
  EXPECT_NEAR(adjusted[1], 0.06, 1e-15);
  EXPECT_NEAR(adjusted[2], 0.06, 1e-15);
  EXPECT_NEAR(adjusted[3], 0.02, 1e-15);
}

TEST(DiagnoseTools, CanonicalCorrelationsAndConditionNumberOfKnownAngles) {
  // span{e1, e2} and span{e1, cos t e2 + sin t e3}: principal angles 0 and t.
  const double t = 0.3;
  Eigen::MatrixXd a(3, 2), b(3, 2);
  a << 1, 0, 0, 1, 0, 0;
  b << 1, 0, 0, std::cos(t), 0, std::sin(t);
  const std::vector<double> cc = canonical_correlations(a, b);
  ASSERT_EQ(cc.size(), 2u);
  EXPECT_NEAR(cc[0], 1.0, 1e-14);
  EXPECT_NEAR(cc[1], std::cos(t), 1e-14);
  // Two columns at cosine c (any lengths): singular values √(1 ± c) once scaled.
  Eigen::MatrixXd x(2, 2);
  x << 5.0, 0.2 * std::cos(t), 0.0, 0.2 * std::sin(t);
  const double c = std::cos(t);
  EXPECT_NEAR(scaled_condition_number(x), std::sqrt((1 + c) / (1 - c)), 1e-12);
}

TEST(DiagnoseTools, KolmogorovTailAtItsFivePercentPoint) {
  // Q_KS(1.358) = 0.05 (Kolmogorov's limiting law, the usual 5 % critical value 1.358).
  const int n = 2400;
  const double sn = std::sqrt(static_cast<double>(n));
  EXPECT_NEAR(ks_p_value(1.358 / (sn + 0.12 + 0.11 / sn), n), 0.05, 2e-4);
  // The distance of a sample equal to the normal quantiles (i − 1/2)/n is 1/(2n).
  // Φ⁻¹(0.1, 0.3, 0.5, 0.7, 0.9) (standard normal quantiles), scaled by σ = 0.3.
  std::vector<double> v;
  for (double q :
       {-1.2815515655446004, -0.5244005127080407, 0.0, 0.5244005127080407, 1.2815515655446004}) {
    v.push_back(0.3 * q);
  }
  EXPECT_NEAR(ks_distance_normal(v, 0.3), 0.1, 1e-12);
}

TEST(DiagnoseTools, LeastSquaresLeavesDependentColumnsOut) {
  Eigen::MatrixXd x(6, 3);
  Eigen::VectorXd y(6);
  for (int r = 0; r < 6; ++r) {
    x(r, 0) = 1.0;
    x(r, 1) = 2.0;  // = 2 × column 0
    x(r, 2) = r;
    y[r] = 0.5 + 0.25 * r;
  }
  const LeastSquaresFit fit = least_squares(x, y);
  EXPECT_EQ(fit.rank, 2);
  EXPECT_TRUE(fit.estimable[0]);
  EXPECT_FALSE(fit.estimable[1]);
  EXPECT_NEAR(fit.beta[0], 0.5, 1e-12);
  EXPECT_NEAR(fit.beta[2], 0.25, 1e-12);
  EXPECT_NEAR(fit.rss, 0.0, 1e-20);
  // (XᵀX)⁻¹ of [1, r], r = 0..5 by hand: det = 6·55 − 15² = 105 → [55, −15; −15, 6] / 105.
  EXPECT_NEAR(fit.cov_unscaled(0, 0), 55.0 / 105.0, 1e-12);
  EXPECT_NEAR(fit.cov_unscaled(2, 2), 6.0 / 105.0, 1e-12);
  EXPECT_NEAR(fit.cov_unscaled(0, 2), -15.0 / 105.0, 1e-12);
}

TEST(DiagnoseTools, HarmonicSpectrumRecoversAmplitudesOnUnevenAzimuths) {
  std::vector<double> phi;
  Eigen::VectorXd r(300);
  for (int k = 0; k < 300; ++k) {
    const double a = 2.0 * kPi * std::pow((k + 0.5) / 300.0, 1.3);  // uneven sampling
    phi.push_back(a);
    r[k] = 0.2 + 0.5 * std::cos(3.0 * a - 1.0) + 0.3 * std::sin(7.0 * a);
  }
  const std::vector<double> amp = HarmonicSpectrum(phi, 12).amplitudes(r);
  ASSERT_EQ(amp.size(), 13u);
  for (int k = 0; k <= 12; ++k) {
    const double expected = k == 0 ? 0.2 : k == 3 ? 0.5 : k == 7 ? 0.3 : 0.0;
    EXPECT_NEAR(amp[k], expected, 1e-9) << "order " << k;
  }
}

// --- Prediction, noise floor and candidates --------------------------------------------------

TEST(DiagnosePrediction, AModelWithTheTruthsEffectsLeavesNoResidual) {
  // The truth's deterministic effects (lobing, drift) without noise; the model has the same
  // effects plus noise and repeatability, which the prediction must switch off.
  const Scenario truth = with_effects(R"(
probe_lobing: {harmonics: [{order: 6, amplitude_um: 0.75, phase_deg: 90}]}
drift: {x_um: 1}
)");
  const Scenario model = with_effects(R"(
probe_lobing: {harmonics: [{order: 6, amplitude_um: 0.75, phase_deg: 90}], repeatability_um: 0.4}
drift: {x_um: 1}
noise: {sigma_um: 0.3}
)");
  const Residuals r = compute_residuals(model, master_readings(truth));
  ASSERT_EQ(r.points.size(), 2400u);
  EXPECT_EQ(r.nominal_fallback, 0);
  double largest = 0.0;
  for (const ResidualPoint& p : r.points) largest = std::max(largest, std::abs(p.residual_um));
  EXPECT_LT(largest, 1e-6);  // the contact solver's tolerance (tests/engine/simulate_test.cpp)
  // Noise floor from the model: √(0.3² + 0.4²) = 0.5 µm.
  const NoiseFloor floor = estimate_noise_floor(model, r);
  EXPECT_EQ(floor.source, "model");
  EXPECT_NEAR(floor.sigma_um, 0.5, 1e-12);
}

TEST(DiagnosePrediction, ModelGearsPredictEachPerturbedGear) {
  // Two perturbed gears (not masters), no noise: with kModelGears the model's contact on the same
  // gears (same scenario and seed) predicts the readings exactly; each gear's sequence restarts.
  const Scenario truth = with_effects("drift: {x_um: 2}\n");
  SimulateOptions o;
  o.gears = 2;
  const Readings readings = simulate_readings(truth, o).readings;
  PredictionOptions p;
  p.artefact = ArtefactModel::kModelGears;
  const Residuals r = compute_residuals(truth, readings, p);
  ASSERT_EQ(r.points.size(), 4800u);
  double largest = 0.0;
  for (const ResidualPoint& q : r.points) largest = std::max(largest, std::abs(q.residual_um));
  EXPECT_LT(largest, 1e-6);
  EXPECT_EQ(r.points[2400].gear, 1);
  EXPECT_EQ(r.points[2400].context.order, 0);
  EXPECT_EQ(r.points[4799].context.order, 2399);
  EXPECT_EQ(r.points[4799].context.sequence_length, 2400);
}

TEST(DiagnosePrediction, RobustNoiseFloorFromSecondDifferences) {
  // Noise-only readings against a model without a random part: the floor is estimated from the
  // residuals' second differences along the profile scans (240 scans × 8 = 1 920 differences).
  // Tolerance 10 %: MAD has 37 % efficiency and neighbouring differences overlap, so the
  // estimate's relative standard error here is ≈ 3 %; 10 % is about 3 standard errors.
  const Residuals r = compute_residuals(reference_scenario(), hidden(""));
  const NoiseFloor floor = estimate_noise_floor(reference_scenario(), r);
  EXPECT_EQ(floor.source, "residual_second_differences");
  EXPECT_EQ(floor.differences, 1920);
  EXPECT_NEAR(floor.sigma_um, kNoiseUm, 0.1 * kNoiseUm);
}

TEST(DiagnoseCandidates, ColumnsAreTheLibrarysSignatures) {
  const Residuals r = compute_residuals(baseline(), hidden(""));
  std::vector<PointContext> points;
  for (const ResidualPoint& p : r.points) points.push_back(p.context);
  const std::vector<CandidateDesign> c = candidate_designs(points);
  // Every library effect but artefact_form, a candidate only when asked for (candidates.h).
  ASSERT_EQ(c.size() + 1, candidate_effect_names().size());
  auto column = [&](const std::string& effect, const std::string& coefficient) {
    for (const CandidateDesign& d : c) {
      if (d.name != effect) continue;
      for (std::size_t k = 0; k < d.coefficients.size(); ++k) {
        if (d.coefficients[k] == coefficient) return std::make_pair(&d, static_cast<int>(k));
      }
    }
    ADD_FAILURE() << effect << "." << coefficient;
    return std::make_pair(&c.front(), 0);
  };
  // Closed forms (effects.h, probe_lobing.h): reading change per unit parameter along n.
  for (std::size_t k = 0; k < points.size(); k += 37) {
    const PointContext& q = points[k];
    const int row = static_cast<int>(k);
    const Eigen::Vector3d centre = q.p + q.stylus_radius_mm * q.n;
    const double f = static_cast<double>(q.order) / (q.sequence_length - 1);
    const double phi = q.azimuth_rad;
    const std::vector<std::tuple<std::string, std::string, double>> expected = {
        {"probe_lobing", "pretravel_um", -1.0},
        {"probe_lobing", "cos_6_um", -std::cos(6 * phi)},
        {"probe_lobing", "sin_6_um", -std::sin(6 * phi)},
        {"probe_lobing", "cos_3_um", -std::cos(3 * phi)},
        {"stylus_radius", "error_um", -1.0},
        {"scale", "x_ppm", 1e-3 * centre.x() * q.n.x()},
        {"thermal_expansion", "workpiece_delta_t_k", 11.5e-3 * centre.dot(q.n)},
        {"drift", "y_um", f * q.n.y()},
        {"squareness", "xz_urad", 1e-3 * q.n.x() * centre.z()},
        {"eccentricity", "x_um", q.n.x()},
        {"step_quantization", "step_um", -0.5},
    };
    for (const auto& [effect, coefficient, value] : expected) {
      const auto [design, col] = column(effect, coefficient);
      // 1e-7: probe_lobing's and thermal expansion's signatures are numerical (central
      // differences of stylus-centre coordinates in mm, round-off ≈ 1e-8 µm per unit).
      EXPECT_NEAR(design->x(row, col), value, 1e-7) << effect << "." << coefficient;
    }
  }
  // On a spur gear n_z = 0: scale z and drift z carry no information.
  EXPECT_FALSE(column("scale", "z_ppm").first->observable[column("scale", "z_ppm").second]);
  EXPECT_FALSE(column("drift", "z_um").first->observable[column("drift", "z_um").second]);
  EXPECT_TRUE(column("squareness", "yz_urad").first->observable[2]);
}

TEST(DiagnoseSelection, NullSimulationIsReproducibleAndBonferroniBounded) {
  const Residuals r = compute_residuals(baseline(), hidden(""));
  std::vector<PointContext> points;
  for (const ResidualPoint& p : r.points) points.push_back(p.context);
  const std::vector<CandidateDesign> c = candidate_designs(points);
  const NullSelectionDistribution a = simulate_null_selection(c, {}, kNoiseUm, 200, 7);
  const NullSelectionDistribution b = simulate_null_selection(c, {}, kNoiseUm, 200, 7);
  ASSERT_EQ(a.max_f.size(), 200u);
  EXPECT_EQ(a.max_f, b.max_f);
  EXPECT_EQ(a.min_p, b.min_p);
  // Under the null each candidate's p is uniform, so P(min p ≤ 0.05/8) ≤ 0.05 (Bonferroni);
  // allow 3 binomial standard errors for 200 replicates.
  const double bound = 0.05 + 3.0 * std::sqrt(0.05 * 0.95 / 200.0);
  const double hits = static_cast<double>(
      std::count_if(a.min_p.begin(), a.min_p.end(), [](double p) { return p <= 0.05 / 8; }));
  EXPECT_LE(hits / 200.0, bound);
  for (double f : a.max_f) EXPECT_TRUE(f > 0.0 && std::isfinite(f));
}

// --- Bounded report data, zero noise floor, statuses ------------------------------------------

TEST(DiagnoseReportData, HistogramBinsComeFromTheCentralQuantilesNotTheRange) {
  // 10 000 residuals in [−1, 1) µm plus one at 10¹¹ µm (a reading 10⁸ mm off) and one at −10⁹:
  // the old range-based bin count would have been 10¹¹ / 50 = 2·10⁹ bins. Now at most 62 bins of a
  // 1-2-5 width covering the 0.5 %–99.5 % quantiles (−0.99, 0.99 µm: the 51st and 9 952nd of the
  // 10 002 sorted values) widened by half their span, 0.99 µm, each side: ±1.98 µm (more than
  // ±3σ, σ = 0.3), so the width is 3.96 / 60 = 0.066 → 0.1 µm, from ⌊−1.98 / 0.1⌋ · 0.1 = −2.0.
  std::vector<double> v;
  for (int k = 0; k < 10000; ++k) v.push_back(-1.0 + 2.0 * k / 10000.0);
  v.push_back(1e11);
  v.push_back(-1e9);
  const DisplayBins b = display_bins(v, 0.3);
  EXPECT_LE(b.bins, 62u);
  EXPECT_DOUBLE_EQ(b.width_um, 0.1);
  EXPECT_NEAR(b.lo_um, -2.0, 1e-12);
  Histogram h(b.lo_um, b.width_um, b.bins);
  for (double x : v) h.add(x);
  EXPECT_EQ(h.overflow(), 1u);
  EXPECT_EQ(h.underflow(), 1u);
  EXPECT_EQ(h.overflow_max(), 1e11);
  // Degenerate inputs still give a valid histogram: all equal, σ 0; empty; non-finite ignored.
  const DisplayBins same = display_bins(std::vector<double>(5, 2.5), 0.0);
  EXPECT_GT(same.width_um, 0.0);
  EXPECT_LE(same.bins, 62u);
  EXPECT_LE(same.lo_um, 0.0);
  EXPECT_GE(same.lo_um + same.width_um * static_cast<double>(same.bins), 2.5);
  const DisplayBins none = display_bins(std::vector<double>{}, 0.0);
  EXPECT_GE(none.bins, 1u);
  const DisplayBins wild =
      display_bins(std::vector<double>{std::numeric_limits<double>::quiet_NaN(), 1.0, 3.0}, 0.0);
  EXPECT_TRUE(std::isfinite(wild.lo_um) && std::isfinite(wild.width_um));
}

TEST(DiagnoseReportData, ScatterSampleIsBoundedDeterministicAndKeepsTheExtremes) {
  std::vector<double> v;
  for (int k = 0; k < 100000; ++k) v.push_back(std::sin(0.001 * k));
  v[77777] = 50.0;   // the largest
  v[12345] = -40.0;  // the smallest
  const std::vector<std::size_t> a = plotted_sample(v, 5000, 1);
  EXPECT_EQ(a.size(), 5000u);
  EXPECT_TRUE(std::is_sorted(a.begin(), a.end()));
  EXPECT_TRUE(std::binary_search(a.begin(), a.end(), 77777u));
  EXPECT_TRUE(std::binary_search(a.begin(), a.end(), 12345u));
  EXPECT_EQ(a, plotted_sample(v, 5000, 1));
  // Uniform over the indices: each tenth of the file holds 500 ± 3·√(5000·0.1·0.9) ≈ 500 ± 64.
  for (int tenth = 0; tenth < 10; ++tenth) {
    const auto in = std::count_if(
        a.begin(), a.end(), [&](std::size_t k) { return static_cast<int>(k / 10000) == tenth; });
    EXPECT_NEAR(static_cast<double>(in), 500.0, 64.0) << "tenth " << tenth;
  }
  EXPECT_EQ(plotted_sample(std::vector<double>(10, 1.0), 5000, 1).size(), 10u);
}

TEST(DiagnoseNoiseFloor, AModelWithoutARandomPartIsJudgedAgainstTheNumericalFloor) {
  // Readings of the nominal master with a 2 µm stylus radius error and no noise, against the
  // reference (no random part): the residuals are −2 µm everywhere (error_um 2 shortens every
  // reading along n: candidates.h, stylus_radius column −1), so the second differences and the
  // MAD are 0 and the floor is raised to kNumericalFloorUm. The residuals are 2000 × that floor:
  // a gap, named stylus_radius (or one of its constant-shift twins).
  const Diagnosis d = diagnose(reference_scenario(),
                               master_readings(with_effects("stylus_radius: {error_um: 2}\n")));
  EXPECT_EQ(d.status, "tested");
  EXPECT_TRUE(d.noise.at_numerical_floor);
  EXPECT_DOUBLE_EQ(d.noise.sigma_um, kNumericalFloorUm);
  EXPECT_TRUE(d.gap_detected);
  EXPECT_NE(d.named_effect, "none");
  EXPECT_TRUE(std::isfinite(d.gap_before.chi2_dof));
  // The same readings of a perfect master: residuals at the solver's 1e-6 µm, within the floor.
  const Diagnosis exact = diagnose(reference_scenario(), master_readings(reference_scenario()));
  EXPECT_FALSE(exact.gap_detected);
  EXPECT_EQ(exact.named_effect, "none");
}

TEST(DiagnoseNoiseFloor, TooFewReadingsForAFloorGiveNoVerdictAndNoNullInTheJson) {
  // 5 readings (fewer than kMinFloorSamples = 10; one scan of 5 gives 3 second differences) against
  // a model without a random part, the first moved 100 mm (10⁵ µm) off: no floor can be estimated,
  // so no verdict.
  Readings r = master_readings(reference_scenario());
  r.rows.resize(5);
  r.rows[0].c += 100.0 * r.rows[0].n;
  const Diagnosis d = diagnose(reference_scenario(), r);
  EXPECT_EQ(d.status, "not_enough_readings");
  EXPECT_NE(d.status_reason.find("not enough readings: 5, need ≥ 10"), std::string::npos)
      << d.status_reason;
  EXPECT_FALSE(d.gap_detected);
  EXPECT_EQ(d.named_effect, "not_tested");
  const std::string json = diagnosis_json(d);
  EXPECT_EQ(json.find(": null"), std::string::npos) << json;
  EXPECT_EQ(json.find("NaN"), std::string::npos);
  EXPECT_NE(json.find("\"not_computed\""), std::string::npos);
  // With a model that has its noise (σ 0.3 µm) the same 5 readings are tested: 10⁵ µm is a gap.
  const Diagnosis tested = diagnose(baseline(), r);
  EXPECT_EQ(tested.status, "tested");
  EXPECT_TRUE(tested.gap_detected);
  EXPECT_EQ(diagnosis_json(tested).find(": null"), std::string::npos);
}

TEST(DiagnoseInput, RowsOutsideTheModelsGearOrPlanAreRefused) {
  // The reference gear has 24 teeth and a 10 × 5 grid (i 0…9, j 0…4).
  const Readings good = master_readings(reference_scenario());
  auto refused = [&](auto change, const std::string& expect) {
    Readings r = good;
    change(r.rows[3]);
    try {
      diagnose(baseline(), r);
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(expect), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("row 4"), std::string::npos) << e.what();
      return;
    }
    ADD_FAILURE() << "accepted: " << expect;
  };
  refused([](ReadingRow& row) { row.tooth = 1000; }, "a tooth in 1 … 24");
  refused([](ReadingRow& row) { row.i = 10; }, "i in 0 … 9");
  refused([](ReadingRow& row) { row.j = 7; }, "j in 0 … 4");
  refused([](ReadingRow& row) { row.c += 1e8 * row.n; }, "within ±1e+09 µm");
  refused([](ReadingRow& row) { row.c += 1e300 * row.n; }, "within ±1e+09 µm");
  // A nominal point 5·10¹⁷ mm off the gear (and its stylus centre with it, so the deviation is
  // fine): the effects' columns would take it as a lever.
  refused(
      [](ReadingRow& row) {
        row.p.z() += 5e17;
        row.c.z() += 5e17;
      },
      "a nominal point on the model's gear");
}

// --- The selection's gates, each deciding alone -------------------------------------------------
// Hand-made designs on n = 32 points with Walsh columns (±1 Rademacher functions of periods 2, 4,
// 8, 16 and 32, mutually orthogonal), residual y = a·R1 + e with e = R1·R2 (a Walsh product,
// orthogonal to every column): adding R1 leaves RSS = |e|² = 32 from |y|² = 32(1 + a²), so
// F = 31 a² (1 and 31 degrees of freedom) and ΔBIC = 32 ln(1/(1 + a²)) + ln 32 (selection.h's
// formulas), every other candidate adds nothing (F = 0). No null simulation (null_replicates 0),
// so "significant" is the Holm-adjusted F test alone; the noise floor (0.01 µm) keeps the
// practical size out of the way. α = 0.01.

CandidateDesign walsh_candidate(const std::string& name, int period) {
  CandidateDesign c;
  c.name = name;
  c.coefficients = {"c_um"};
  c.units = {"µm"};
  c.observable = {true};
  c.x.resize(32, 1);
  for (int k = 0; k < 32; ++k) c.x(k, 0) = (k % period) < period / 2 ? 1.0 : -1.0;
  return c;
}

Eigen::VectorXd walsh_residual(double a) {
  const CandidateDesign r1 = walsh_candidate("r1", 2), r2 = walsh_candidate("r2", 4);
  return a * r1.x.col(0) + r1.x.col(0).cwiseProduct(r2.x.col(0));
}

SelectionOptions gate_options() {
  SelectionOptions o;
  o.alpha = 0.01;
  o.null_replicates = 0;
  o.max_effects = 1;
  return o;
}

TEST(DiagnoseSelection, HolmDecidesWhenTheRawFTestPassesButTheAdjustedOneDoesNot) {
  // a = 0.55: F = 31 · 0.3025 = 9.38, raw p ≈ 0.0045 < α; with 5 candidates Holm multiplies the
  // smallest p by 5 (Holm 1979): ≈ 0.022 > α. ΔBIC = 32 ln(1/1.3025) + ln 32 = −5.0, so the
  // BIC gate is set to 4 here and only Holm can refuse.
  std::vector<CandidateDesign> five;
  for (int period : {2, 4, 8, 16, 32}) {
    five.push_back(walsh_candidate("w" + std::to_string(period), period));
  }
  SelectionOptions o = gate_options();
  o.min_delta_bic = 4.0;
  const Eigen::VectorXd y = walsh_residual(0.55);
  const Selection s = forward_select(five, y, 0.01, o);
  ASSERT_EQ(s.steps.size(), 1u);
  const CandidateTest& t = s.steps[0].tests[0];
  EXPECT_NEAR(t.f, 31.0 * 0.3025, 1e-9);
  ASSERT_LT(t.p_f, o.alpha);  // the unadjusted test would pass
  EXPECT_NEAR(t.p_holm, 5.0 * t.p_f, 1e-12);
  EXPECT_GE(t.p_holm, o.alpha);
  EXPECT_TRUE(t.bic_support);
  EXPECT_TRUE(t.practical);
  EXPECT_FALSE(t.significant);
  EXPECT_TRUE(s.selected.empty());
  // Control: the same residuals with R1 the only candidate (Holm over one test is the raw p):
  // every gate passes and it is selected, so it was Holm that refused it above.
  const Selection alone = forward_select({five[0]}, y, 0.01, o);
  ASSERT_EQ(alone.selected.size(), 1u);
  EXPECT_TRUE(alone.steps[0].tests[0].significant);
}

TEST(DiagnoseSelection, TheBicGateDecidesBetweenTwoSignificantEffects) {
  // One candidate (Holm = raw p). a² = 0.344: F = 10.7 (p ≈ 0.003 < α), ΔBIC = 32 ln(1/1.344) +
  // ln 32 = −6.0 > −10: significant and practical, refused by the BIC gate alone.
  // a² = 0.78: F = 24.2, ΔBIC = 32 ln(1/1.78) + ln 32 = −15.0 ≤ −10: selected.
  const std::vector<CandidateDesign> one = {walsh_candidate("r1", 2)};
  const SelectionOptions o = gate_options();
  const Selection weak = forward_select(one, walsh_residual(std::sqrt(0.344)), 0.01, o);
  const CandidateTest& w = weak.steps.at(0).tests.at(0);
  EXPECT_NEAR(w.delta_bic, 32.0 * std::log(1.0 / 1.344) + std::log(32.0), 1e-9);
  EXPECT_TRUE(w.significant);
  EXPECT_TRUE(w.practical);
  EXPECT_FALSE(w.bic_support);
  EXPECT_TRUE(weak.selected.empty());
  const Selection strong = forward_select(one, walsh_residual(std::sqrt(0.78)), 0.01, o);
  const CandidateTest& t = strong.steps.at(0).tests.at(0);
  EXPECT_NEAR(t.delta_bic, 32.0 * std::log(1.0 / 1.78) + std::log(32.0), 1e-9);
  EXPECT_TRUE(t.significant);
  EXPECT_TRUE(t.bic_support);
  ASSERT_EQ(strong.selected.size(), 1u);
  // Between the two: a gate of 5 accepts the weak one, so the threshold's sign matters.
  SelectionOptions loose = o;
  loose.min_delta_bic = 5.0;
  EXPECT_EQ(forward_select(one, walsh_residual(std::sqrt(0.344)), 0.01, loose).selected.size(), 1u);
}

// --- The diagnosis on readings with one hidden effect -----------------------------------------

struct HiddenEffect {
  const char* yaml;
  const char* name;
  std::vector<std::pair<const char*, double>> truth;  // parameter or coefficient → true value
};

// gtest prints parameters in test names (ctest): the effect's name, not the struct's bytes.
void PrintTo(const HiddenEffect& h, std::ostream* os) { *os << h.name; }

class DiagnoseHiddenEffect : public ::testing::TestWithParam<HiddenEffect> {};

TEST_P(DiagnoseHiddenEffect, NamesFitsAndClosesTheGap) {
  const HiddenEffect& h = GetParam();
  const Diagnosis d = diagnose(baseline(), hidden(h.yaml));
  EXPECT_TRUE(d.gap_detected);
  EXPECT_EQ(d.named_effect, h.name);
  ASSERT_FALSE(d.effects.empty());
  EXPECT_EQ(d.effects.size(), 1u);
  const FittedEffect& e = d.effects.front();
  for (const auto& [parameter, truth] : h.truth) {
    const FittedValue& v = value(e, parameter);
    EXPECT_TRUE(v.estimable) << parameter;
    EXPECT_LE(std::abs(v.value - truth), 3.0 * v.std_error)
        << parameter << " = " << v.value << " ± " << v.std_error << ", truth " << truth;
  }
  EXPECT_EQ(d.noise.source, "model");
  EXPECT_DOUBLE_EQ(d.noise.sigma_um, kNoiseUm);
  EXPECT_LE(d.gap_after.rms_um, 1.1 * kNoiseUm);
  EXPECT_LE(d.held_out_rms_um, 1.1 * kNoiseUm);
  EXPECT_GT(d.gap_before.rms_um, 1.3 * kNoiseUm);
  EXPECT_GE(d.explained_fraction, 0.95);
  EXPECT_FALSE(d.unexplained_structure);
  // Cluster-aware evidence: after the fit the residuals do not differ from a simulation of the
  // model (flank swaps); the teeth bootstrap interval brackets the RMS after the fit. (Before the
  // fit the energy test compares marginal laws only: it is strong for a shift — the stylus radius
  // case below and DiagnosePointLaw — but weak for zero-mean patterns such as drift along x,
  // whose marginal is a slight widening: p 0.015 there, so it is not asserted for every effect.)
  EXPECT_GT(d.gap_after.energy_p, 0.01);
  EXPECT_LE(d.gap_after.rms_lo_um, d.gap_after.rms_um);
  EXPECT_GE(d.gap_after.rms_hi_um, d.gap_after.rms_um);
  EXPECT_LE(d.gap_after.rms_lo_um, 1.1 * kNoiseUm);
}

// Truth values from the effects' definitions: lobing p(φ) = 0.75 cos(6(φ − 90°)), so its
// coefficients (candidates.h) are cos_6 = 0.75 cos 540° = −0.75, sin_6 = 0, phase 90° ≡ 30°
// modulo the 60° period; the others are the parameters themselves (scale z and drift z are not
// observable on a spur gear).
INSTANTIATE_TEST_SUITE_P(
    Battery, DiagnoseHiddenEffect,
    ::testing::Values(
        HiddenEffect{"probe_lobing: {harmonics: [{order: 6, amplitude_um: 0.75, phase_deg: 90}]}\n",
                     "probe_lobing",
                     {{"amplitude_6_um", 0.75},
                      {"phase_6_deg", 30.0},
                      {"cos_6_um", -0.75},
                      {"sin_6_um", 0.0},
                      {"cos_3_um", 0.0},
                      {"sin_3_um", 0.0},
                      {"pretravel_um", 0.0}}},
        HiddenEffect{"scale: {x_ppm: 10}\n", "scale", {{"x_ppm", 10.0}, {"y_ppm", 0.0}}},
        HiddenEffect{"drift: {x_um: 1}\n", "drift", {{"x_um", 1.0}, {"y_um", 0.0}}},
        HiddenEffect{
            "eccentricity: {x_um: 3, y_um: 4}\n", "eccentricity", {{"x_um", 3.0}, {"y_um", 4.0}}},
        HiddenEffect{"stylus_radius: {error_um: 0.5}\n", "stylus_radius", {{"error_um", 0.5}}}),
    [](const ::testing::TestParamInfo<HiddenEffect>& p) { return std::string(p.param.name); });

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
  ASSERT_EQ(d.named_effect, "probe_lobing");
  EXPECT_EQ(d.held_out_split, "alternating_teeth");
  EXPECT_GT(d.gap_before.rms_um, 0.5);
  EXPECT_GT(d.held_out_rms_um, 0.27);
  EXPECT_LT(d.held_out_rms_um, 0.36);
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
  EXPECT_EQ(d.named_effect, "none");
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
    ASSERT_EQ(d.named_effect, "eccentricity") << varies;
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

TEST(Diagnose, NullDatasetsNameNothing) {
  for (std::uint64_t seed : {1, 2}) {
    const Diagnosis d = diagnose(baseline(), hidden("", seed));
    EXPECT_FALSE(d.gap_detected) << "seed " << seed;
    EXPECT_EQ(d.named_effect, "none") << "seed " << seed;
    EXPECT_TRUE(d.effects.empty());
    EXPECT_FALSE(d.unexplained_structure);
    EXPECT_LE(d.gap_before.rms_um, 1.1 * kNoiseUm);
    EXPECT_GT(d.gap_before.energy_p, 0.01) << "seed " << seed;
    EXPECT_LE(d.gap_before.rms_lo_um, kNoiseUm * 1.02);
    EXPECT_GE(d.gap_before.rms_hi_um, kNoiseUm * 0.98);
  }
}

TEST(Diagnose, StructureLeftAfterAPartialLibraryFitLeadsTheVerdict) {
  // Lobing (6 lobes, 1.5 µm: in the library) plus a waviness across the face outside it,
  // 0.6 sin(2π z / 20 mm) µm: the lobing explains most of the excess variance, but structure
  // remains along the face, so the verdict is "unexplained" with probe_lobing as the partial
  // explanation and face_position as the axis (the waviness varies with z alone, i.e. with the
  // section index j). Seeds 1.
  Scenario truth = with_effects(
      "probe_lobing: {harmonics: [{order: 6, amplitude_um: 1.5, phase_deg: 90}]}\n"
      "noise: {sigma_um: 0.3}\n");
  truth.normal_expression_um = "0.6*sin(2*_pi*z/20)";
  const Diagnosis d = diagnose(baseline(), master_readings(truth));
  EXPECT_TRUE(d.gap_detected);
  EXPECT_TRUE(d.unexplained_structure);
  EXPECT_EQ(d.named_effect, "unexplained");
  EXPECT_GE(d.explained_fraction, 0.5);
  EXPECT_EQ(d.partially_explained_by, "probe_lobing");
  EXPECT_EQ(d.unexplained_along.axis, "face_position");
  EXPECT_LT(d.unexplained_along.p_value, 1e-6);
  ASSERT_FALSE(d.notes.empty());
  EXPECT_NE(d.notes.front().find("structure remains"), std::string::npos);
}

TEST(Diagnose, AnEffectOutsideTheLibraryIsNotNamedWithConfidence) {
  // A waviness across the face, the same on every flank: 0.8 sin(2π z / 20 mm) µm (normal_um).
  // No library signature varies with z alone, so "unexplained structure remains" is the answer.
  Scenario truth = with_effects("noise: {sigma_um: 0.3}\n");
  truth.normal_expression_um = "0.8*sin(2*_pi*z/20)";
  const Diagnosis d = diagnose(baseline(), master_readings(truth));
  EXPECT_TRUE(d.gap_detected);
  EXPECT_EQ(d.named_effect, "unexplained");
  EXPECT_TRUE(d.unexplained_structure);
  EXPECT_LT(d.explained_fraction, 0.5);
  EXPECT_GT(d.gap_after.rms_um, 1.5 * kNoiseUm);
  // Constant along each profile scan, so the second differences show no extra spread: neither a
  // larger noise nor a step quantisation is named for it.
  EXPECT_TRUE(d.point_law.ran);
  EXPECT_EQ(d.point_law.chosen, 0);
  EXPECT_GT(d.point_law.white_p, 0.01);
}

// --- The point-law stage ----------------------------------------------------------------------

TEST(DiagnosePointLaw, ResidualLawIntegratesToItsMomentsAndCdf) {
  // r = o + e − u, e ~ N(0, 0.3²), u ~ U(0, 1), o = 0.2: mean o − w/2 = −0.3, variance
  // σ² + w²/12 (independent parts). Trapezoid integration of exp(log_density) on [−6, 6] (step
  // 1e-3; the tails beyond carry < 1e-15) gives 1, the mean and the variance; the closed-form
  // cdf equals the running integral of the density. Draws: sample mean and variance of 20 000
  // within 4 standard errors.
  const ResidualLaw law{0.3, 1.0, 0.2};
  const double h = 1e-3;
  double mass = 0.0, mean = 0.0, second = 0.0, running = 0.0;
  double previous = std::exp(law.log_density(-6.0));
  for (int k = 1; k <= 12000; ++k) {
    const double x = -6.0 + k * h;
    const double f = std::exp(law.log_density(x));
    const double slice = 0.5 * h * (f + previous);
    mass += slice;
    mean += 0.5 * h * (x * f + (x - h) * previous);
    second += 0.5 * h * (x * x * f + (x - h) * (x - h) * previous);
    running += slice;
    previous = f;
    if (k % 1500 == 0) {
      EXPECT_NEAR(law.cdf(x), running, 1e-6) << "x = " << x;
    }
  }
  EXPECT_NEAR(mass, 1.0, 1e-6);
  EXPECT_NEAR(mean, law.mean_um(), 1e-6);
  EXPECT_NEAR(mean, -0.3, 1e-6);
  EXPECT_NEAR(second - mean * mean, law.variance_um2(), 1e-6);
  EXPECT_NEAR(law.variance_um2(), 0.09 + 1.0 / 12.0, 1e-15);
  // In the upper tail the density is [Q(b) − Q(a)]/w, b = (x − o)/σ, a = (x − o + w)/σ (Q the
  // normal upper tail, by erfc); beyond double range it follows the Gaussian edge with Mills'
  // ratio Q(b) ≈ φ(b)/b (relative error ≈ 1/b² = 4e-4 at b = 49.3).
  auto upper = [](double z) { return 0.5 * std::erfc(z / std::sqrt(2.0)); };
  EXPECT_NEAR(law.log_density(3.0), std::log(upper(2.8 / 0.3) - upper(3.8 / 0.3)), 1e-9);
  const double b = 14.8 / 0.3;
  EXPECT_NEAR(law.log_density(15.0), -0.5 * b * b - 0.5 * std::log(2.0 * kPi) - std::log(b), 1e-3);
  EXPECT_TRUE(std::isfinite(law.log_density(40.0)));
  RandomStream rng(5, 0, StreamPurpose::kDiagnoseNull, 77);
  const int n = 20000;
  double s1 = 0.0, s2 = 0.0;
  for (int k = 0; k < n; ++k) {
    const double x = law.draw(rng);
    s1 += x;
    s2 += x * x;
  }
  const double m = s1 / n, v = s2 / n - m * m;
  EXPECT_NEAR(m, -0.3, 4.0 * std::sqrt(law.variance_um2() / n));
  EXPECT_NEAR(v, law.variance_um2(), 4.0 * law.variance_um2() * std::sqrt(2.0 / n));
  // The residual law of a model with a step: centred, the largest width kept.
  PointLaw model;
  model.gaussian_variance_um2 = 0.09;
  model.uniform_widths_um = {0.5, 1.0};
  const ResidualLaw centred = residual_law(model);
  EXPECT_DOUBLE_EQ(centred.width_um, 1.0);
  EXPECT_NEAR(centred.mean_um(), 0.0, 1e-15);
  EXPECT_NEAR(centred.variance_um2(), model.variance_um2(), 1e-15);
}

TEST(DiagnosePointLaw, StepQuantizationIsNamedByTheSpreadOfSingleReadings) {
  // Hidden: step_quantization q = 1 µm (the battery's size at 1×) on the master: every reading gets
  // −U(0, 1) µm, mean −0.5 µm, exactly a stylus radius error of +0.5 µm in the mean; the spread
  // √(0.3² + 1/12) = 0.416 µm (not 0.3) and its flat top name the step. The fitted model (q̂ in
  // the model) then has no gap.
  const Diagnosis d = diagnose(baseline(), hidden("step_quantization: {step_um: 1}\n"));
  EXPECT_TRUE(d.gap_detected);
  EXPECT_EQ(d.named_effect, "step_quantization");
  EXPECT_FALSE(contains(d.ambiguous_with, "stylus_radius"));
  ASSERT_EQ(d.effects.size(), 1u);  // it replaced the constant shift stylus_radius had taken
  const FittedEffect& e = d.effects.front();
  EXPECT_TRUE(e.absolute);
  const FittedValue& q = value(e, "step_um");
  EXPECT_LE(std::abs(q.value - 1.0), 3.0 * q.std_error) << q.value << " ± " << q.std_error;
  EXPECT_LT(q.std_error, 0.05);
  EXPECT_TRUE(d.point_law.best().tied);
  EXPECT_LT(d.point_law.white_p, 0.01);
  EXPECT_NEAR(d.noise_floor_after_um, std::sqrt(0.09 + q.value * q.value / 12.0), 1e-12);
  EXPECT_LE(d.held_out_rms_um, 1.1 * d.noise_floor_after_um);
  EXPECT_FALSE(d.unexplained_structure);
  EXPECT_GE(d.explained_fraction, 0.9);
  EXPECT_GT(d.gap_after.energy_p, 0.01);  // the fitted law matches a simulation of itself

  std::ostringstream fitted;
  fitted << "step_quantization: {step_um: " << q.value << "}\nnoise: {sigma_um: 0.3}\n";
  const Diagnosis again =
      diagnose(with_effects(fitted.str()), hidden("step_quantization: {step_um: 1}\n"));
  EXPECT_EQ(again.named_effect, "none");
  EXPECT_FALSE(again.gap_detected);
}

TEST(DiagnosePointLaw, ALargerProbingNoiseIsNamedNoise) {
  // Truth: noise σ 0.45 µm, model 0.3 µm; no systematic effect. The fitted σ is the truth's
  // within 3 standard errors, and a step (which would shift the mean) is not named.
  const Diagnosis d =
      diagnose(baseline(), master_readings(with_effects("noise: {sigma_um: 0.45}\n")));
  EXPECT_EQ(d.named_effect, "noise");
  ASSERT_EQ(d.effects.size(), 1u);
  const FittedValue& s = value(d.effects.front(), "sigma_um");
  EXPECT_LE(std::abs(s.value - 0.45), 3.0 * s.std_error) << s.value << " ± " << s.std_error;
  EXPECT_FALSE(contains(d.ambiguous_with, "step_quantization"));
  EXPECT_FALSE(d.unexplained_structure);
}

TEST(DiagnosePointLaw, AStylusRadiusErrorIsNotAmbiguousWithStepQuantization) {
  // +0.5 µm radius error: the mean −0.5 µm a 1 µm step would also give, without its spread.
  const Diagnosis d = diagnose(baseline(), hidden("stylus_radius: {error_um: 0.5}\n"));
  EXPECT_LT(d.gap_before.energy_p, 0.01);  // a shift of 1.7 σ: the marginal laws differ
  EXPECT_EQ(d.named_effect, "stylus_radius");
  EXPECT_FALSE(contains(d.ambiguous_with, "step_quantization"));
  EXPECT_EQ(d.point_law.chosen, 0);
  const PointLawHypothesis* step = d.point_law.find("step_quantization");
  ASSERT_NE(step, nullptr);
  EXPECT_GT(step->delta_bic, 6.0);
}

TEST(Diagnose, ConstantPretravelAndStylusRadiusAreAmbiguous) {
  // A pure constant pre-travel p0 = 0.5 µm reads exactly like a stylus radius 0.5 µm too large.
  const Diagnosis d = diagnose(baseline(), hidden("probe_lobing: {pretravel_um: 0.5}\n"));
  ASSERT_TRUE(d.named_effect == "stylus_radius" || d.named_effect == "probe_lobing")
      << d.named_effect;
  const std::string other = d.named_effect == "stylus_radius" ? "probe_lobing" : "stylus_radius";
  EXPECT_TRUE(contains(d.ambiguous_with, other));
  const FittedEffect& e = d.effects.front();
  const auto it = std::find_if(e.ambiguous.begin(), e.ambiguous.end(),
                               [&](const Ambiguity& a) { return a.with == other; });
  ASSERT_NE(it, e.ambiguous.end());
  EXPECT_NEAR(it->signal_correlation, 1.0, 1e-9);
  EXPECT_NE(it->separate_by.find("sphere"), std::string::npos);
  // The fitted constant is the pre-travel (or radius error) itself.
  const FittedValue& v = value(e, d.named_effect == "stylus_radius" ? "error_um" : "pretravel_um");
  EXPECT_LE(std::abs(v.value - 0.5), 3.0 * v.std_error);
}

TEST(Diagnose, ThermalExpansionIsAmbiguousWithScaleAndSaysMeasureTheTemperature) {
  // ΔT_w = 1 K on steel (11.5 ppm/K) is an isotropic scale on a spur gear (n_z = 0).
  const Diagnosis d = diagnose(baseline(), hidden("thermal_expansion: {workpiece_delta_t_k: 1}\n"));
  EXPECT_EQ(d.named_effect, "thermal_expansion");
  EXPECT_TRUE(contains(d.ambiguous_with, "scale"));
  const FittedEffect& e = d.effects.front();
  const FittedValue& v = value(e, "workpiece_delta_t_k");
  EXPECT_LE(std::abs(v.value - 1.0), 3.0 * v.std_error);
  for (const Ambiguity& a : e.ambiguous) {
    if (a.with == "scale") {
      EXPECT_NE(a.separate_by.find("temperature"), std::string::npos);
    }
  }
}

TEST(Diagnose, SameSeedSameResultAndTheJsonOfInterfaceMd) {
  const Readings readings =
      hidden("probe_lobing: {harmonics: [{order: 6, amplitude_um: 0.75, phase_deg: 90}]}\n");
  const std::string first = diagnosis_json(diagnose(baseline(), readings));
  const std::string second = diagnosis_json(diagnose(baseline(), readings));
  EXPECT_EQ(first, second);

  const auto dir = std::filesystem::path(::testing::TempDir()) /
                   ("gearmc_diagnose_test_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  write_diagnosis_json((dir / "diagnosis.json").string(), diagnose(baseline(), readings));
  std::ifstream in(dir / "diagnosis.json");
  std::stringstream text;
  text << in.rdbuf();
  EXPECT_EQ(text.str(), first);
  const nlohmann::json j = nlohmann::json::parse(first);
  // docs/formats.md: the keys diagnosis.json has at least.
  EXPECT_TRUE(j.at("gap_detected").get<bool>());
  EXPECT_EQ(j.at("named_effect"), "probe_lobing");
  EXPECT_TRUE(j.at("ambiguous_with").is_array());
  const nlohmann::json& e = j.at("effects").at(0);
  EXPECT_EQ(e.at("name"), "probe_lobing");
  EXPECT_NEAR(e.at("parameters").at("amplitude_6_um").get<double>(), 0.75, 0.03);
  EXPECT_GT(e.at("std_errors").at("amplitude_6_um").get<double>(), 0.0);
  EXPECT_TRUE(e.at("evidence").is_object());
  for (const char* gap : {"gap_before", "gap_after"}) {
    EXPECT_TRUE(j.at(gap).at("rms_um").is_number());
    EXPECT_TRUE(j.at(gap).at("ks").is_number());
  }
  EXPECT_DOUBLE_EQ(j.at("noise_floor_um").get<double>(), kNoiseUm);
  EXPECT_EQ(j.at("spectrum").at("before_um").size(), 13u);
  // Beyond docs/formats.md: the fitted floor, how parameters are meant, the point-law stage and the
  // cluster-aware evidence.
  EXPECT_DOUBLE_EQ(j.at("noise_floor_after_um").get<double>(), kNoiseUm);
  EXPECT_EQ(e.at("parameters_are"), "increments");
  EXPECT_TRUE(j.at("point_law").at("ran").get<bool>());
  EXPECT_EQ(j.at("point_law").at("chosen"), "none");
  EXPECT_EQ(j.at("point_law").at("hypotheses").size(), 4u);
  for (const char* gap : {"gap_before", "gap_after"}) {
    EXPECT_TRUE(j.at(gap).at("energy_p").is_number());
    EXPECT_EQ(j.at(gap).at("rms_ci95_um").size(), 2u);
  }
  std::filesystem::remove_all(dir);
}

TEST(Diagnose, TheLobingOrderStandsOutOfTheNullBandOfTheSpectrum) {
  const Diagnosis d = diagnose(
      baseline(),
      hidden("probe_lobing: {harmonics: [{order: 6, amplitude_um: 0.75, phase_deg: 90}]}\n"));
  ASSERT_EQ(d.spectrum_before_um.size(), 13u);
  // Before: order 6 carries the 0.75 µm lobing, far above its null band; after: within the band
  // at every order but a few (5 % of orders exceed a 95 % band by chance).
  EXPECT_NEAR(d.spectrum_before_um[6], 0.75, 0.05);
  EXPECT_GT(d.spectrum_before_um[6], 5.0 * d.spectrum_null95_before_um[6]);
  int above = 0;
  for (int k = 0; k <= 12; ++k) above += d.spectrum_after_um[k] > d.spectrum_null95_after_um[k];
  EXPECT_LE(above, 2);
}

}  // namespace
}  // namespace gearmc
