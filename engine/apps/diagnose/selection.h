// Step 3 of the discrepancy diagnosis: which candidate effects the residuals ask for.
// Forward selection of at most `max_effects` candidates by nested least-squares tests: at each
// step every candidate not yet selected is tested as an addition to the selected ones
// (intercept-free; see candidates.h), with
//   * the F test of the nested linear models, F = ((RSS_S − RSS_S+c)/q) / (RSS_S+c/(n − p − q)),
//     q = columns c adds beyond the selected ones (Seber & Lee, "Linear Regression Analysis",
//     2nd ed., 2003, ch. 4), its p-value from the F table, Holm-adjusted over the candidates of
//     the step (linear_model.h);
//   * the same p-value calibrated on simulated null data: the residuals replaced by
//     N(0, σ²) noise at the same points K times (drawn in the space of the step's bases, with
//     the same law as n draws: selection.cpp), the smallest F-table p-value over the step's
//     candidates taken in each replicate, p_null = (1 + #{min p* ≤ p}) / (K + 1) — the
//     single-step min-P adjustment of Westfall & Young ("Resampling-Based Multiple Testing",
//     Wiley 1993), which also controls the family-wise error over the candidates and does not
//     lean on the F table's assumptions;
//   * ΔBIC = n ln(RSS_S+c / RSS_S) + q ln n (Schwarz, Ann. Statist. 6, 1978; Gaussian errors,
//     σ unknown), accepted only at ≤ −min_delta_bic (10: "very strong" on the 2 ln B scale of
//     Kass & Raftery, JASA 90, 1995);
//   * a minimum practical size: the RMS of the candidate's own contribution in the joint fit with
//     the selected effects, √(‖X_c β_c‖²/n), must be ≥ min_effect_rms_fraction × the noise floor.
//     0.25 by default: an unmodelled effect of RMS 0.25 σ raises the residual RMS by 3 % only
//     (√(1 + 0.25²) = 1.03), while one of 0.46 σ would already break the 1.1 × noise goal of the
//     issue, so everything that matters for that goal is above the threshold. The contribution,
//     not only the RMS the candidate removes beyond the selected, √((RSS_S − RSS_S+c)/n): a drift
//     of 0.5 µm over each of three runs beside a set-up shift moves the readings by 0.2 µm RMS,
//     but the shift takes its mean and leaves an increment of 0.07 µm, below 0.25 × 0.3 µm,
//     although its F test, null calibration and ΔBIC (−400) are decisive. Chance stays the
//     significance tests' business (a collinear candidate's large cancelling β fails them).
// Among the candidates that pass all four, the one with the lowest ΔBIC is taken (ties: the
// library order of candidate_effect_names()); selection stops when none passes. A candidate whose
// columns are all explained by the selected ones (q = 0) is not testable at that step.
// Random numbers: counter-based streams keyed by (seed, replicate, kDiagnoseNullStream, step),
// so the same seed gives the same result.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "core/random_stream.h"
#include "engine/apps/diagnose/candidates.h"

namespace gearmc {

// The stream purpose of the diagnosis's null simulations. core/random_stream.h reserves numbers
// for purposes; 19 is the next free one and must be registered there (that file is not part of
// the diagnosis).
inline constexpr StreamPurpose kDiagnoseNullStream = StreamPurpose::kDiagnoseNull;

struct SelectionOptions {
  int max_effects = 3;
  double alpha = 0.01;  // family-wise level of each step (Holm and the null-calibrated p)
  double min_delta_bic = 10.0;
  double min_effect_rms_fraction = 0.25;  // of the noise floor
  // K, the null simulation's replicates (also for the gap tests, diagnosis.h). p_null >= 1/(K+1),
  // so a K below 2/alpha − 1 could never reject: it is raised to that (199 for alpha 0.01;
  // effective_null_replicates). 0 switches the null calibration off (F table and Holm only).
  int null_replicates = 200;
  std::uint64_t seed = 1;
};

// The K actually used: 0, or max(null_replicates, ⌈2/alpha⌉ − 1).
int effective_null_replicates(const SelectionOptions& options);

struct CandidateTest {
  int candidate = -1;  // index into the candidate list
  std::string name;
  int added_rank = 0;  // q
  int dof_residual = 0;
  double f = std::numeric_limits<double>::quiet_NaN();
  double p_f = std::numeric_limits<double>::quiet_NaN();     // F table
  double p_holm = std::numeric_limits<double>::quiet_NaN();  // Holm-adjusted over the step
  double p_null = std::numeric_limits<double>::quiet_NaN();  // calibrated on the null
  double delta_bic = std::numeric_limits<double>::quiet_NaN();
  double effect_rms_um = std::numeric_limits<double>::quiet_NaN();  // √(ΔRSS / n)
  // √(‖X_c β_c‖² / n): the RMS of the candidate's own contribution in the joint fit with the
  // selected effects (≥ effect_rms_um; the practical size is judged on it).
  double joint_rms_um = std::numeric_limits<double>::quiet_NaN();
  bool significant = false;  // p_holm < alpha and p_null < alpha
  bool bic_support = false;  // ΔBIC <= −min_delta_bic
  bool practical = false;    // joint_rms_um >= fraction × noise floor
  bool accepted = false;
  std::string note;  // e.g. "nested in the selected effects"
  bool eligible() const { return significant && bic_support && practical; }
};

// The null distribution of one step: per replicate, the largest F and the smallest F-table
// p-value over the candidates testable at that step.
struct NullSelectionDistribution {
  std::vector<double> max_f;
  std::vector<double> min_p;
};

struct SelectionStep {
  std::vector<int> selected_before;  // candidate indices
  double rss_before = 0.0;           // µm²
  std::vector<CandidateTest> tests;  // one per candidate not yet selected
  int accepted = -1;                 // index into tests, −1: none passed (selection stops)
  double null_max_f_95 = std::numeric_limits<double>::quiet_NaN();  // 95 % of max F*
};

struct Selection {
  std::vector<SelectionStep> steps;
  // Candidate indices of the kept effects, the one that explains most given the others first
  // (its drop-one effect_rms_um in `retest`): after the forward steps every selected effect is
  // re-tested in the presence of all the others (the nested test of dropping it: F table, Holm
  // over the selected, ΔBIC, practical size — the null calibration is the forward steps'); while
  // one fails, the weakest (largest Holm p, then largest ΔBIC) is dropped and the rest re-tested.
  std::vector<int> selected;
  std::vector<CandidateTest> retest;   // the final round, in `selected`'s order
  std::vector<CandidateTest> dropped;  // effects dropped by the re-test, in the order dropped
};

// Simulates the null for one step: `replicates` residual vectors of independent N(0, σ²) noise at
// the candidates' points, each tested like the data (every candidate not in `selected` added to
// `selected`). F statistics do not depend on σ, but σ is used as given. Stream sub-index = `step`.
NullSelectionDistribution simulate_null_selection(const std::vector<CandidateDesign>& candidates,
                                                  const std::vector<int>& selected, double sigma_um,
                                                  int replicates, std::uint64_t seed, int step = 0);

// The Gram matrix AᵀA of one step's orthonormal bases A = [Q_S, A_1, …, A_E] (Q_S: the selected
// candidates' columns; A_e: what candidate e, not selected, adds beyond them; each by Gram–Schmidt
// in column order, blocks in library order), whose root the null simulation draws with.
Eigen::MatrixXd step_gram(const std::vector<CandidateDesign>& candidates,
                          const std::vector<int>& selected);

// Forward selection on residuals `residual_um` (one per row of the candidates' matrices) with the
// noise floor σ (µm) for the practical size.
Selection forward_select(const std::vector<CandidateDesign>& candidates,
                         const Eigen::VectorXd& residual_um, double noise_floor_um,
                         const SelectionOptions& options = {});

// The same on compressed columns (compressed_candidate_designs): the same tests, with N =
// compressed.rows for the degrees of freedom, ΔBIC, the practical size and the null's χ².
Selection forward_select(const CompressedDesigns& compressed, double noise_floor_um,
                         const SelectionOptions& options = {});

// The observable columns of the candidates `which`, side by side in that order.
Eigen::MatrixXd joint_columns(const std::vector<CandidateDesign>& candidates,
                              const std::vector<int>& which);

}  // namespace gearmc
