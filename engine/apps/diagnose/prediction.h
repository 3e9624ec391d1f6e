// Step 1 of the discrepancy diagnosis: what the model predicts at each measured point
// and the residual r = measured − predicted along the nominal normal n (µm), plus the noise
// floor the gap is judged against.
//
// Prediction of a reading row (gear, tooth, flank, i, j): the model scenario's stylus-centre
// contact at that planned point (the measurement pipeline, engine/measurement) moved by the model's
// measurement effects at their nominal parameter values, each averaged over its per-point random
// numbers (MeasurementEffect::apply_mean: noise and probe repeatability add nothing, step
// quantisation its mean latch delay q/2), read along n exactly as the CMM reading is (reading_um).
// Parameters drawn per gear from a law enter at their central value (EffectParameter::nominal);
// their spread is not part of the prediction.
//
// Which surface the model predicts on (ArtefactModel):
//  * kNominalMaster (default, the one to use for real CMM data): the model's nominal gear
//    (deviations.random = false, as `gearmc simulate --master`), with its deterministic
//    `normal_um` expression if it has one. For readings with ref_dev_um (a calibrated artefact)
//    measured_deviation_um already subtracts the certificate, so the prediction is made on the
//    nominal gear without the expression: what remains is the measurement error (the artefact's
//    own radius-compensation error along n, second order in its form slopes, is not predicted).
//  * kModelGears: the model's perturbed gear k as drawn from its seed — only meaningful for
//    readings simulated from a scenario with the same gear model and seed (tests).
// The contact is computed with the readings' stylus radius (the ball that measured). Rows
// matched to the gear (Readings::labels_from_matching, point_matching.h) whose nominal point is
// not a planned one get the model's contact at their own point, measured as the plan's are. A
// labelled row whose (tooth, flank, i, j) is not in the model's probing plan, whose nominal
// point differs from the plan's by more than 0.1 µm, or any row whose model contact is not a
// valid one, is predicted with the nominal contact c = p + R n (counted in `nominal_fallback`;
// exact for a nominal flank).
//
// Each point's PointContext (what the effects' signatures see) comes from the row itself: p, n,
// φ = atan2(−n_y, −n_x), and the place in its gear's measurement: order − (first order of that
// gear), with sequence_length = last − first + 1 of that gear's orders (the rows of the gear when
// no planned point was skipped; drift runs over one gear's sequence, as in `gearmc simulate`).
#pragma once

#include <array>
#include <string>
#include <string_view>
#include <vector>

#include "engine/effects/measurement_effect.h"
#include "engine/readings/readings_csv.h"
#include "engine/scenario/scenario.h"

namespace gearmc {

enum class ArtefactModel { kNominalMaster, kModelGears };

struct PredictionOptions {
  ArtefactModel artefact = ArtefactModel::kNominalMaster;
};

struct ResidualPoint : PointKey {
  int order = 0;              // the file's order column
  int line = 0;               // the reading's line in the readings file (0: made in memory)
  PointContext context;       // as the effects see the point (see the file comment)
  double measured_um = 0.0;   // measured_deviation_um(row, R)
  double predicted_um = 0.0;  // the model's deterministic reading along n
  double residual_um = 0.0;   // measured − predicted
  bool model_contact = true;  // false: predicted with the nominal contact p + R n
};

struct Residuals {
  std::vector<ResidualPoint> points;  // in the readings' row order (the ball: the model's)
  ArtefactModel artefact = ArtefactModel::kNominalMaster;
  int nominal_fallback = 0;  // rows predicted with the nominal contact
};

// Predicts every row of `readings` with `model` and returns the residuals (µm along n, CMM frame
// = gear frame), the measured deviations with the model's stylus radius (stylus.radius_mm, the
// one place it is held; check_readings refuses readings compensated with another ball). Throws
// InputError if the readings have no rows.
Residuals compute_residuals(const Scenario& model, const Readings& readings,
                            const PredictionOptions& options = {});

// The noise floor σ (µm, the standard deviation of one reading along n that the model accepts
// as pure noise) and, when it is the model's, the model's per-point law (Gaussian and uniform
// parts, engine/effects PointLaw) that the diagnosis tests the residuals against.
// Where the noise floor comes from (spelled in diagnosis.json and the report by spelling()).
enum class NoiseFloorSource {
  // "model": √variance of the model's per-point law (EffectChain::point_law at nominal values:
  // noise σ², probe repeatability², step quantisation q²/12).
  kModel,
  // "residual_second_differences": robust_noise_sigma below, when the model has no random part
  // (from ≥ kMinFloorSamples differences).
  kResidualSecondDifferences,
  // "residual_mad": 1.4826 MAD of the residuals themselves when there are fewer differences but
  // ≥ kMinFloorSamples readings (an upper bound: structure counts as noise).
  kResidualMad,
  // "numerical_floor": neither (then `not_enough` says so).
  kNumericalFloor,
  // "given": set by the caller.
  kGiven,
};
std::string_view spelling(NoiseFloorSource source);

struct NoiseFloor {
  double sigma_um = 0.0;  // the value used
  NoiseFloorSource source = NoiseFloorSource::kNumericalFloor;
  PointLaw law;            // the law used: the model's, or Gaussian with σ² = sigma_um²
  double model_um = 0.0;   // the model's value (0 when it has no random part)
  double robust_um = 0.0;  // robust_noise_sigma of the residuals (always computed)
  int differences = 0;     // second differences the robust value used
  // The smallest floor a gap is judged against (kNumericalFloorUm): a model without a random part
  // predicts each reading exactly, and a floor estimated as 0 (identical residuals) would make
  // every test undefined; a floor below it is raised to it (at_numerical_floor).
  double numerical_um = 0.0;
  bool at_numerical_floor = false;
  // Non-empty when the model has no random part and the residuals are too few to estimate the
  // floor (fewer than kMinFloorSamples second differences and readings): "not enough readings:
  // N, need ≥ M …". The diagnosis then makes no verdict (Diagnosis::status).
  std::string not_enough;
};
// 1 nm: ten times below the finest scale resolution of CMMs (0.01 µm) and a thousand times above
// the agreement of the model's contact solver with simulated readings (1e-6 µm).
inline constexpr double kNumericalFloorUm = 1e-3;
// The fewest second differences (or, without scans, readings) a floor estimate is made from.
inline constexpr int kMinFloorSamples = 10;
NoiseFloor estimate_noise_floor(const Scenario& model, const Residuals& residuals);

// The points' profile scans: the points of one gear, tooth, flank and section j, ordered by
// roll index i (of two points with the same i the later in the file), scans in that key order.
// Sorted indices rather than a tree of 10⁶ nodes (memory at 10⁶ readings).
struct ProfileScans {
  std::vector<int> points;         // point indices, scan after scan
  std::vector<std::size_t> start;  // scan s is points[start[s] .. start[s + 1])
  std::size_t count() const { return start.empty() ? 0 : start.size() - 1; }
};
ProfileScans profile_scans(const std::vector<ResidualPoint>& points);

// Index triplets (i−1, i, i+1) of consecutive points along each profile scan (same gear, tooth,
// flank and section j, consecutive i), scan after scan (the support of the second differences).
std::vector<std::array<int, 3>> scan_triplets(const std::vector<ResidualPoint>& points);

// Robust estimate of the noise σ from the residuals alone: second differences
// d = r_{i−1} − 2 r_i + r_{i+1} of consecutive points along each profile scan (same gear, tooth,
// flank and section j, consecutive i), σ = 1.4826 MAD(d) / √6. Second differences cancel any
// structure that is linear along the scan (pseudo-residuals: Gasser, Sroka & Jennen-Steinmetz,
// "Residual variance and residual pattern in nonlinear regression", Biometrika 73, 1986; for
// first differences Rice, Ann. Statist. 12, 1984); var(d) = 6σ² for independent noise; MAD
// (Hampel 1974) makes it robust to outliers and local structure. `residual_um[k]` belongs to
// points[k] (the residual vector may differ from the points' own, e.g. in the null simulation).
// `count` receives the number of differences used. NaN when there are none.
double robust_noise_sigma(const std::vector<ResidualPoint>& points,
                          const std::vector<double>& residual_um, int* count = nullptr);
// The same on triplets from scan_triplets (computed once when called for many residual vectors).
double robust_noise_sigma(const std::vector<std::array<int, 3>>& triplets,
                          const std::vector<double>& residual_um);

}  // namespace gearmc
