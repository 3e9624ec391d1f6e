// The statistical core of `gearmc diagnose` (docs/diagnosis.md): compares a model scenario's
// prediction with measured readings, decides whether they disagree beyond the noise floor, names
// the missing effect from the library (or says none / unexplained), fits its physical parameters
// with standard errors, and shows the gap before and after, with a held-out check and the
// residuals' harmonic spectrum against approach azimuth with null bands. The result maps onto
// diagnosis.json (diagnosis_json.h). Steps:
//  1. residuals r = measured − predicted and the noise floor σ (prediction.h); when the model
//     has no random part and the residuals are too few to estimate σ, no test is made (status
//     "not_enough_readings", named_effect "not_tested");
//  2. candidate design matrices from the effects' signatures (candidates.h);
//  3. forward selection of at most 3 effects (selection.h);
//  4. the joint least-squares fit of the selected effects, β with covariance σ̂² (XᵀX)⁻¹,
//     σ̂² = RSS/(n − p) (the residual variance after the fit: an honest scale when structure
//     remains); probe lobing's cos/sin pairs converted to amplitude a = √(c² + s²) and phase
//     φ_k = atan2(s, c)/k (in [0, 360°/k)), standard errors by the delta method;
//  5. the gap before / after: RMS, χ²/dof = Σr²/(dof σ²), the Kolmogorov–Smirnov distance of
//     r/σ against N(0, 1), with p-values from K simulations of the null (N(0, σ²) noise at the
//     same points; for the "after" values with the selected columns fitted out of the noise as
//     out of the data, so the fit's own shrinkage is calibrated, and with σ re-estimated from each
//     replicate when σ itself was estimated from the residuals; with null_replicates = 0 the χ²
//     law of Σr²/σ² and Kolmogorov's asymptotic law instead); the held-out RMS: the selected
//     effects fitted on one half of the readings and evaluated on the other, and the other way
//     round, the halves alternate measured teeth (or flanks, face sections, profile points: the
//     first split the plan allows, diagnosis_stages.h; none: no held-out value and a note);
//     the cluster-aware evidence of GapStatistics (energy test by flank swaps, RMS interval by a
//     bootstrap over teeth), reported beside the gap tests;
//  6. the harmonic spectrum of the residuals (orders 0–12, linear_model.h) before and after, with
//     the 95 % quantile of each order's amplitude under the null;
//  7. ambiguity: an effect B is reported `ambiguous_with` a selected effect A when B's columns can
//     reproduce A's fitted contribution ŝ_A = X_A β_A (beyond the other selected effects):
//     ρ = |P_B ŝ_A| / |ŝ_A| > 0.9 — the canonical correlation of the two column spaces taken in
//     the direction the data excite — or when B was itself an eligible explanation at A's step
//     with ΔBIC within 6 of A's (the data do not prefer A "strongly", Kass & Raftery 1995); two
//     selected effects whose joint design has a scaled condition number > 100 are ambiguous with
//     each other. The purely structural first canonical correlation and condition number are
//     reported for each ambiguity but do not decide it alone: probe_lobing's p0 column equals
//     stylus_radius's, so structurally they always overlap, yet 6-lobed residuals say nothing
//     about a constant. Each ambiguity comes with the measurement that would separate the two.
//  8. the verdict: gap_detected when an effect is selected, the point-law stage accepts a law, or
//     the gap test rejects at alpha: one test of family-wise level alpha made of the χ² test (it
//     counts only with an excess RMS of at least the practical size) and the KS test (only when
//     the floor is not the numerical one, NoiseFloor::at_numerical_floor: that floor bounds an
//     exact prediction's rounding, it is not a law of the residuals), combined by min-P over the
//     same K null replicates (GapStatistics::combined_p; the gates apply to the replicates as to
//     the data, so the level stays alpha up to 1/(K + 1)); named_effect = the first
//     selected effect (after the re-test, the one that explains most given the others) when the
//     selected effects explain ≥ 50 % of the excess residual variance (Σr² − nσ²) and no structure
//     remains after them, "unexplained" when a gap is detected but nothing in the library explains
//     it or structure remains after the library's best fit (the verdict leads with what is not
//     explained; the fitted library effects stay listed, the first as partially_explained_by, with
//     the axis the remaining structure varies along), "none" when there is no gap;
//     unexplained_structure when the gap tests still reject after the fit.
// Units: residuals and RMS in µm, parameters in the units of their names (µm, ppm, µrad, K, deg).
// Deterministic: the same inputs and seed give the same result for any number of threads (the
// null replicates run in parallel, each from its own counter-based streams into its own slots).
#pragma once

#include <Eigen/Core>
#include <limits>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "engine/apps/diagnose/candidates.h"
#include "engine/apps/diagnose/coordinate_grid.h"
#include "engine/apps/diagnose/empirical_term.h"
#include "engine/apps/diagnose/outlier_screen.h"
#include "engine/apps/diagnose/part_model.h"
#include "engine/apps/diagnose/point_law_stage.h"
#include "engine/apps/diagnose/prediction.h"
#include "engine/apps/diagnose/reading_grid.h"
#include "engine/apps/diagnose/selection.h"
#include "engine/apps/diagnose/setup_model.h"

namespace gearmc {

// What was measured: a master (nominal, or calibrated: ref_dev_um) whose every residual is the
// machine's, or a production gear whose own flank deviations are part of every model
// (part_model.h).
enum class Workpiece { kMaster, kProduction };

struct DiagnoseOptions {
  Workpiece workpiece = Workpiece::kMaster;
  // A production gear measured in several set-ups (or runs): one entry per gear index, the teeth
  // the gear was turned by on the table (part_model.h part_columns); empty: each gear index is its
  // own gear.
  std::vector<int> turned_by_teeth;
  PredictionOptions prediction;
  CandidateOptions candidates;
  SelectionOptions selection;  // also: alpha, replicates and seed of the gap's null simulation
  std::optional<double> noise_floor_um;  // overrides the estimate (source "given")
  int spectrum_max_order = 12;
  double min_explained_fraction = 0.5;  // of the excess variance, to name an effect
  double ambiguity_correlation = 0.9;
  double ambiguity_condition_number = 100.0;
  double ambiguity_delta_bic = 6.0;
  // Fit an empirical term when structure remains (false in the library's refit beside it).
  bool fit_empirical = true;
  // Point-law stage (point_law_stage.h): the share of an alternative law's extra variance that
  // must show in the second differences.
  double point_law_white_fraction = 0.5;
  // Above 2 × null_rows readings the null laws that need every reading are not simulated on all
  // of them (diagnosis_gap.cpp, point_law_stage.h): the gap's χ² and KS statistics on a
  // subsample of about null_rows readings (every k-th run of 64 points along the scans) rescaled
  // to n by their asymptotic laws, the spectrum's bands from the harmonic fit's exact covariance,
  // and the white-variance test by its normal approximation. The cost of a null replicate then
  // stops growing with n.
  int null_rows = 100000;
};

inline constexpr double kNotAvailable = std::numeric_limits<double>::quiet_NaN();

struct FittedValue {
  std::string name, unit;
  double value = kNotAvailable;      // in `unit`
  double std_error = kNotAvailable;  // in `unit`
  bool estimable = false;            // false: not observable on this plan (no value)
};

struct Ambiguity {
  std::string with;    // the other effect
  std::string reason;  // "signal_correlation", "delta_bic", "condition_number"
  double signal_correlation = kNotAvailable;     // ρ = |P_B ŝ_A| / |ŝ_A|
  double canonical_correlation = kNotAvailable;  // first canonical correlation of the spaces
  double condition_number = kNotAvailable;       // scaled, of [others, A, B]
  double delta_bic_gap = kNotAvailable;          // ΔBIC_B − ΔBIC_A at A's step
  std::string separate_by;                       // the measurement that would tell them apart
};

struct FittedEffect {
  std::string name;
  int step = 0;                           // 0-based selection step
  std::vector<FittedValue> coefficients;  // the linear coefficients (the candidate's columns)
  // The effect's physical parameters, named as in a scenario's `effects:` section (amplitude
  // and phase per lobing order: amplitude_<k>_um, phase_<k>_deg). They are increments to the
  // model's own values of that effect (the columns are first-order signatures about them).
  std::vector<FittedValue> parameters;
  CandidateTest evidence;      // the test that selected it
  double fitted_rms_um = 0.0;  // RMS of X_A β_A over the points
  // From the point-law stage (noise, step_quantization): `parameters` are the effect's own
  // values (noise: σ of the readings' whole Gaussian part; step: q), not increments.
  bool absolute = false;
  std::vector<Ambiguity> ambiguous;  // empty: identified on this plan
  // Settings the effect's columns were made with (CandidateDesign::settings; artefact_form's
  // evaluation ranges), written to fitted.yaml beside the parameters.
  std::vector<std::pair<std::string, double>> settings;
  // Readings of several gears (or repeated measurements, numbered as gears): whether the
  // effect's value differs from gear to gear (diagnosis_stages.h per_gear_variation: an F test
  // of one value per gear against one shared value, the other effects kept shared), its p-value,
  // and the coefficients fitted per gear (in the effect's coefficient units) when it varies.
  struct GearValues {
    int gear = 0;
    std::vector<FittedValue> coefficients;
  };
  bool varies_per_gear = false;
  // The per-gear values are the first run's (the effect's) plus each run's set-up difference
  // (Diagnosis::setups; eccentricity and clocking only), not a per-gear split of the effect.
  bool per_gear_from_setups = false;
  double per_gear_p = kNotAvailable;  // NaN: one gear only, or not a linear effect
  std::vector<GearValues> per_gear;
};

struct GapStatistics {
  double rms_um = kNotAvailable;
  double chi2_dof = kNotAvailable;  // Σr² / (dof σ²)
  int dof = 0;
  double chi2_p = kNotAvailable;         // from the null simulation
  double ks = kNotAvailable;             // KS distance of r/σ against N(0, 1)
  double ks_p = kNotAvailable;           // from the null simulation
  double excess_rms_um = kNotAvailable;  // √max(0, Σr²/dof − σ²)
  // The verdict's gap test: the χ² test (only at an excess RMS of at least the practical size)
  // and the KS test (only off the numerical floor) combined into one test of family-wise level α
  // by min-P over the same null replicates (linear_model.h min_p_combined_p_value); with no null
  // simulation, Bonferroni over the two table p-values. A gap when combined_p < α.
  double combined_p = kNotAvailable;
  // Cluster-aware evidence (cluster_tests.h), reported, not part of the verdict: the energy
  // distance between the residuals and one simulation of the (fitted) model's law at the same
  // points — projected like the residuals — with its paired permutation p-value swapping whole
  // flanks; and the 95 % percentile bootstrap interval of the RMS resampling whole teeth.
  double energy_um = kNotAvailable;
  double energy_p = kNotAvailable;
  double rms_lo_um = kNotAvailable, rms_hi_um = kNotAvailable;
};

// Whether the readings were tested ("tested"), or not: "not_enough_readings", the noise floor of a
// model without a random part could not be estimated (NoiseFloor::not_enough).
enum class DiagnosisStatus { kTested, kNotEnoughReadings };
// What the diagnosis found: no gap ("none"), a library effect (its name), a gap the library does
// not explain ("unexplained"), or nothing because nothing was tested ("not_tested").
enum class DiagnosisFinding { kNone, kEffect, kUnexplained, kNotTested };
// The spellings in diagnosis.json and the report.
std::string_view spelling(DiagnosisStatus status);
std::string_view spelling(DiagnosisFinding finding);

struct Diagnosis {
  // kNotEnoughReadings (why in status_reason): no test is made, gap_detected is false and the
  // finding is kNotTested.
  DiagnosisStatus status = DiagnosisStatus::kTested;
  std::string status_reason;
  bool gap_detected = false;
  DiagnosisFinding finding = DiagnosisFinding::kNone;
  std::string named_effect;  // kEffect: the library effect's name; empty otherwise
  // diagnosis.json's "named_effect": the effect's name, or the finding's spelling.
  const std::string named_effect_text() const {
    return finding == DiagnosisFinding::kEffect ? named_effect : std::string(spelling(finding));
  }
  // Names the library effect `name` as the finding.
  void name_effect(const std::string& name) {
    finding = DiagnosisFinding::kEffect;
    named_effect = name;
  }
  std::vector<std::string> ambiguous_with;
  bool unexplained_structure = false;
  // When structure remains after the fit: the axis along which the residuals after vary most
  // (one-way analysis of variance of the residuals after, grouped along each axis: "roll_length"
  // by profile index i, "face_position" by section j, "tooth", "flank", "approach_azimuth" in 24
  // sectors of 15°, "probing_order" in 20 consecutive groups; the smallest F-test p-value), that
  // p-value and the share of the residuals' variance the groups' means carry. Empty otherwise.
  // The structure is stated only on its own evidence: the gap test after the fit rejects, and
  // either its χ² part does (an excess variance of at least the practical size that the
  // point-law stage did not take as white noise) or an axis's group means differ at α after
  // Bonferroni over the axes tested (p_value · axes_tested < α) and those group means' RMS reaches
  // the practical size (min_effect_rms_fraction × the noise floor).
  struct StructureAxis {
    std::string axis;
    double p_value = kNotAvailable;
    double variance_share = kNotAvailable;
    int axes_tested = 0;
    // A machine axis ("x_position", "y_position", "z_position"): the structure is periodic along
    // that coordinate of the stylus centre, read along the normal's component on it — a scale's
    // periodic (encoder, interpolation) error e(c_a) = A sin(2π c_a/λ + φ) moves a reading by
    // e(c_a) n_a. The best period λ of a log grid (2 mm … the measured span, steps of 0.5 %) and
    // its amplitude A (least squares). Such an axis is tested as a second family beside the
    // gear's six axes, each family at α/2 (Bonferroni within it: the periods × axes); p_value
    // and axes_tested are then the winning family's.
    double period_mm = kNotAvailable;
    double amplitude_um = kNotAvailable;
  } unexplained_along;
  // When the residuals after the fit fail the gap test but not by structure (the structure rule
  // above does not hold: no excess variance of the practical size, no axis whose group means
  // reach it): the readings' law differs from the model's, nothing is missing from
  // their mean — no structure, no effect; a statement about the noise law (heavy tails, a
  // rounding the reading-grid stage did not find). The residuals' excess kurtosis m₄/m₂² − 3
  // (standard error √(24/n)) against the model law's κ₄/v² (−w⁴/120 / v² for its uniform part).
  struct LawShape {
    bool differs = false;
    double ks_p = kNotAvailable;
    double excess_kurtosis = kNotAvailable;
    double model_excess_kurtosis = kNotAvailable;
    double kurtosis_std_error = kNotAvailable;
    std::string shape;                    // "heavier tails", "lighter tails" or "another shape"
    double spread_ratio = kNotAvailable;  // √(χ²/dof) after: the residuals' spread / the model's
  } law_shape;
  // When structure remains: the empirical term fitted along unexplained_along's axis to the
  // residuals after the library's fit (empirical_term.h), written to fitted.yaml as the
  // `empirical` effect, with the RMS it leaves. `fitted` false: not attempted or not supported.
  EmpiricalTerm empirical;
  // With a fitted empirical term: the library effects selected and fitted again on the readings
  // less the term (what fitted.yaml writes beside it; empirical_term.h).
  std::vector<FittedEffect> effects_with_empirical;
  // The library effect that explains part of an unexplained gap (the first selected), or "".
  std::string partially_explained_by;
  // The held-out rule refused the fitted effects (their held-out RMS not below the one without
  // them): fitted.yaml does not write them.
  bool fit_refused = false;
  double explained_fraction = kNotAvailable;  // of the excess variance
  std::vector<FittedEffect> effects;          // selected effects, in selection order
  // A production gear (DiagnoseOptions::workpiece): its own flank deviations, fitted jointly with
  // the effects; "before" (gap_before, residual_before_um, the spectrum before) is then the
  // model with the part's deviations fitted, so the gap is the machine's (part_model.h).
  Workpiece workpiece = Workpiece::kMaster;
  PartDeviations part;
  // Several runs (gear indices of the readings): their set-ups' differences from the first run's,
  // in every model when their F test rejects (setup_model.h).
  SetupDifferences setups;
  GapStatistics gap_before, gap_after;
  // The RMS of the residuals after, each predicted by the selected effects fitted on the other
  // fold (diagnosis_stages.h HeldOutSplit; "nothing_fitted": the RMS before).
  double held_out_rms_um = kNotAvailable;
  std::string held_out_split;
  // The same held-out RMS without the selected effects (a master: the residuals themselves; a
  // production gear: its own deviations alone, fitted on the other fold). A fit whose held-out RMS
  // is not below it predicts unseen readings no better than no fit: it is not accepted as an
  // explanation (make_verdict).
  double held_out_without_rms_um = kNotAvailable;
  // The readings excluded as gross outliers before the diagnosis (outlier_screen.h); every
  // other field is computed without them.
  OutlierScreen outliers;
  NoiseFloor noise;
  // The standard deviation of one reading under the fitted model: the model's noise floor, or the
  // accepted point law's (a fitted noise or step quantisation adds to the irreducible spread).
  double noise_floor_after_um = kNotAvailable;
  PointLawStage point_law;
  // Whether the readings' coordinates lie on a grid per axis (coordinate_grid.h); when `named`,
  // the effect scale_resolution is in `effects` (its steps, absolute) and named when nothing else
  // is, and the noise floor includes its spread.
  CoordinateGrid coordinate_grid;
  // Whether the readings themselves are printed on a grid along the normal (reading_grid.h): then
  // the residuals were dithered and the law widened by the rounding.
  ReadingGrid reading_grid;
  Selection selection;
  std::vector<std::string> candidate_names;  // index → name for `selection`
  // Harmonic spectrum against approach azimuth, orders 0..spectrum_max_order (µm).
  std::vector<double> spectrum_before_um, spectrum_after_um;
  std::vector<double> spectrum_null95_before_um, spectrum_null95_after_um;
  int points = 0;
  int nominal_fallback = 0;  // rows predicted with the nominal contact (prediction.h)
  // Remarks for the reader: rows predicted with the nominal contact; a robust residual noise
  // estimate more than 20 % away from the model's noise floor (the model's noise is then
  // probably wrong, which the χ² gap test also shows).
  std::vector<std::string> notes;
  int null_replicates = 0;
  // The readings the gap's null law was simulated on: `points`, or the subsample of
  // DiagnoseOptions::null_rows (then a note in `notes` says how the rest was done).
  int null_rows = 0;
  std::uint64_t seed = 0;
  double alpha = 0.0;
  // Per point, in the readings' order (for the report): residual before and after the fit.
  std::vector<double> residual_before_um, residual_after_um;
};

// Step 1 as `gearmc diagnose` runs it: the readings checked against the model (readings_check.h,
// InputError located in `readings_path`, "" for readings made in memory), the residuals, the
// gross outliers excluded (outlier_screen.h) and the noise floor of the remaining residuals
// (or the options' given floor).
struct PreparedResiduals {
  Residuals residuals;  // without the excluded readings
  OutlierScreen outliers;
  NoiseFloor noise;
  CoordinateGrid grid;       // the coordinate-grid stage on the kept readings
  ReadingGrid reading_grid;  // the readings' own resolution (reading_grid.h); dithered when found
};
PreparedResiduals prepare_residuals(const Scenario& model, const Readings& readings,
                                    const std::string& readings_path,
                                    const DiagnoseOptions& options);
// Steps 2–8 on prepared residuals (the excluded readings listed in Diagnosis::outliers).
Diagnosis diagnose_prepared(const PreparedResiduals& prepared, const DiagnoseOptions& options);

// The whole diagnosis of `readings` against `model` (throws InputError on empty readings):
// prepare_residuals, then diagnose_prepared.
Diagnosis diagnose(const Scenario& model, const Readings& readings,
                   const DiagnoseOptions& options = {});

// Steps 2–8 on given residuals and noise floor (the points' contexts are the design's points).
Diagnosis diagnose_residuals(const Residuals& residuals, const NoiseFloor& noise,
                             const DiagnoseOptions& options = {});

}  // namespace gearmc
