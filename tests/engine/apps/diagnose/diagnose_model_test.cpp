// Tests of the diagnosis's model side (engine/apps/diagnose, docs/diagnosis.md): the prediction of
// a model's readings against simulate_readings, the noise floor (robust, from the model, the
// numerical floor of a model without a random part) and the candidates' columns against the
// effects' closed-form signatures. Readings are simulated from the built-in reference (P1's
// gear, 10 × 5 grid, nominal master) with fixed seeds, so each assertion is deterministic.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "engine/apps/diagnose/diagnosis.h"
#include "engine/apps/diagnose/diagnosis_json.h"
#include "tests/support/diagnose_readings.h"

namespace gearmc {
namespace {

using testing_support::baseline;
using testing_support::hidden;
using testing_support::kNoiseUm;
using testing_support::master_readings;
using testing_support::with_effects;

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
  EXPECT_LT(largest, 1e-6);  // the contact solver's tolerance (tests/engine/run/simulate_test.cpp)
  // Noise floor from the model: √(0.3² + 0.4²) = 0.5 µm.
  const NoiseFloor floor = estimate_noise_floor(model, r);
  EXPECT_EQ(spelling(floor.source), "model");
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
  EXPECT_EQ(spelling(floor.source), "residual_second_differences");
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

TEST(DiagnoseNoiseFloor, AModelWithoutARandomPartIsJudgedAgainstTheNumericalFloor) {
  // Readings of the nominal master with a 2 µm stylus radius error and no noise, against the
  // reference (no random part): the residuals are −2 µm everywhere (error_um 2 shortens every
  // reading along n: candidates.h, stylus_radius column −1), so the second differences and the
  // MAD are 0 and the floor is raised to kNumericalFloorUm. The residuals are 2000 × that floor:
  // a gap, named stylus_radius (or one of its constant-shift twins).
  const Diagnosis d = diagnose(reference_scenario(),
                               master_readings(with_effects("stylus_radius: {error_um: 2}\n")));
  EXPECT_EQ(d.status, DiagnosisStatus::kTested);
  EXPECT_TRUE(d.noise.at_numerical_floor);
  EXPECT_DOUBLE_EQ(d.noise.sigma_um, kNumericalFloorUm);
  EXPECT_TRUE(d.gap_detected);
  EXPECT_NE(d.named_effect_text(), "none");
  EXPECT_TRUE(std::isfinite(d.gap_before.chi2_dof));
  // The same readings of a perfect master: residuals at the solver's 1e-6 µm, within the floor.
  const Diagnosis exact = diagnose(reference_scenario(), master_readings(reference_scenario()));
  EXPECT_FALSE(exact.gap_detected);
  EXPECT_EQ(exact.named_effect_text(), "none");
}

TEST(DiagnoseNoiseFloor, TooFewReadingsForAFloorGiveNoVerdictAndNoNullInTheJson) {
  // 5 readings (fewer than kMinFloorSamples = 10; one scan of 5 gives 3 second differences) against
  // a model without a random part, the first moved 100 mm (10⁵ µm) off: no floor can be estimated,
  // so no verdict.
  Readings r = master_readings(reference_scenario());
  r.rows.resize(5);
  r.rows[0].c += 100.0 * r.rows[0].n;
  const Diagnosis d = diagnose(reference_scenario(), r);
  EXPECT_EQ(d.status, DiagnosisStatus::kNotEnoughReadings);
  EXPECT_NE(d.status_reason.find("not enough readings: 5, need ≥ 10"), std::string::npos)
      << d.status_reason;
  EXPECT_FALSE(d.gap_detected);
  EXPECT_EQ(d.named_effect_text(), "not_tested");
  const std::string json = diagnosis_json(d);
  EXPECT_EQ(json.find(": null"), std::string::npos) << json;
  EXPECT_EQ(json.find("NaN"), std::string::npos);
  EXPECT_NE(json.find("\"not_computed\""), std::string::npos);
  // With a model that has its noise (σ 0.3 µm) the same 5 readings are tested: 10⁵ µm is a gap.
  const Diagnosis tested = diagnose(baseline(), r);
  EXPECT_EQ(tested.status, DiagnosisStatus::kTested);
  EXPECT_TRUE(tested.gap_detected);
  EXPECT_EQ(diagnosis_json(tested).find(": null"), std::string::npos);
}

}  // namespace
}  // namespace gearmc
