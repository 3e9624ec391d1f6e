// The point-law stage of the discrepancy diagnosis: effects that change the law of
// each single reading rather than its expected value. Step quantisation (engine/effects) adds a
// latch delay −U(0, q) at every point: its mean −q/2 is a constant shift along n, exactly the
// first-order signature of a stylus radius error, so the linear selection (selection.h) cannot
// tell the two apart; what tells them apart is that the quantisation also adds q²/12 of variance
// with a flat-topped shape, tied to its shift. Likewise a probing noise larger than the model's
// shows only in the spread. This stage runs after the linear selection and fit, on the
// residuals ε = r − X_S β̂ of the selected effects S, and compares by BIC (Schwarz 1978):
//   model              the model's own per-point law (NoiseFloor::law, centred: the prediction
//                      contains its mean), k = rank X_S;
//   noise              the Gaussian part's σ fitted (the model's probing noise is wrong),
//                      k = rank X_S + 1;
//   step_quantization  the step q fitted, the Gaussian part the model's. Two forms: "tied" — the
//                      constant columns of S dropped (a selected stylus_radius or
//                      step_quantization column), so q alone explains the shift −(q − q₀)/2 AND
//                      the extra variance (q² − q₀²)/12, k = rank X_{S∖const} + 1; and "free" —
//                      with a constant column kept (a radius error as well), k = rank X_S∪1 + 1.
// Each law's β is the least-squares fit of r − mean(law) (consistent, not the exact maximum
// likelihood of the non-Gaussian law: conservative for the alternatives), and the law's
// parameter maximises the profile log-likelihood Σ log f(ε_i) (grid, then golden section); its
// standard error is 1/√(observed information) of that profile (numerical second derivative).
//
// An alternative law is accepted only when all of these hold:
//   * white excess: the variance in second differences along the profile scans,
//     v_w = Σd²/(6 m) (d = ε_{i−1} − 2ε_i + ε_{i+1}: var d = 6 v for independent readings of any
//     law, and structure linear along a scan cancels, prediction.h), exceeds the model's v₀ with
//     a p-value from K simulations of the model's law at the same points through the same fit
//     < alpha — so systematic structure that the library does not explain (waviness across the
//     face) is not mistaken for a noisier or quantised reading;
//   * practical size √(v_w − v₀) ≥ min_effect_rms_fraction × √v₀ (selection.h's rule);
//   * the alternative's extra variance is mostly white: v_w − v₀ ≥ white_fraction (v_alt − v₀);
//   * ΔBIC = BIC_alt − BIC_model ≤ −min_delta_bic.
// Among the accepted, the lowest BIC wins; the other kind (noise vs step) is `ambiguous` when its
// BIC is within ambiguity_delta_bic. With no simulated null (K = 0, or many readings:
// PointLawOptions::white_normal_approximation) the white test uses the normal approximation of
// v_w: its mean v₀ (1 − Σ_a |Qᵀc_a|²/(6 m)) through the fit's projection (Q an orthonormal basis of
// the fitted columns, c_a the second-difference weights 1, −2, 1 of triplet a) and the variance of
// Σd² for independent readings of the model's law, Σ_a Σ_b [2 cov(d_a, d_b)² + κ₄ Σ_i c_a(i)²
// c_b(i)²] (κ₄ the law's fourth cumulant, −w⁴/120 for a uniform part of width w; 0 for a Gaussian
// law, where this is Isserlis' theorem). With m ≥ 10⁵ differences the normal law of their sum is
// exact to far below the K-replicate p-value's own resolution.
//
// A model whose law is not its own (noise floor estimated from the residuals, or given) says
// nothing about the spread; the stage is then skipped (reason in `skipped_because`).
// Units: µm, µm². Deterministic: counter-based streams (seed, replicate, kDiagnoseNull, sub).
#pragma once

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "core/random_stream.h"
#include "engine/apps/diagnose/prediction.h"

namespace gearmc {

// The law of one residual: r = offset + e − u, e ~ N(0, σ²), u ~ U(0, w) (w = 0: no uniform
// part). Density f(r) = [Φ((r − o + w)/σ) − Φ((r − o)/σ)] / w; distribution function
// F(r) = (σ/w) [G((r − o + w)/σ) − G((r − o)/σ)], G(z) = z Φ(z) + φ(z) (the integral of Φ).
struct ResidualLaw {
  double sigma_um = 0.0;
  double width_um = 0.0;
  double offset_um = 0.0;
  double mean_um() const { return offset_um - 0.5 * width_um; }
  double variance_um2() const { return sigma_um * sigma_um + width_um * width_um / 12.0; }
  double log_density(double r) const;
  double cdf(double r) const;
  double draw(RandomStream& rng) const;
};

// The law of r = measured − predicted when the readings follow a model with per-point law `law`
// (the prediction contains the law's mean): centred (mean 0). The largest uniform part is kept
// exactly; further uniform parts (rare: two quantising effects) are folded into σ by their
// variance w²/12.
ResidualLaw residual_law(const PointLaw& law);

// Variance of Σ_a d_a² over the second differences d_a = e_i − 2 e_{i+1} + e_{i+2} of `triplets`
// (index triples of consecutive points of one scan, scan_triplets' order) for independent
// readings e of variance v (µm²) and fourth cumulant κ₄ (µm⁴; −w⁴/120 for a uniform law of
// width w, 0 for a Gaussian): Σ_a Σ_b [2 cov(d_a, d_b)² + κ₄ Σ_i c_a(i)² c_b(i)²],
// cov(d_a, d_b) = v Σ_i c_a(i) c_b(i) over shared points (c = 1, −2, 1). µm⁴.
double white_sum_variance(const std::vector<std::array<int, 3>>& triplets, double v, double kappa4);

// One-sample Kolmogorov–Smirnov distance of `values` against `law` (exact sup over the jumps).
double ks_distance(std::vector<double> values, const ResidualLaw& law);

struct PointLawOptions {
  double alpha = 0.01;
  int null_replicates = 200;  // K (0: normal approximation)
  // The white-variance test by its normal approximation even with K > 0 (set for many readings,
  // DiagnoseOptions::null_rows).
  bool white_normal_approximation = false;
  std::uint64_t seed = 1;
  double min_delta_bic = 10.0;
  double ambiguity_delta_bic = 6.0;
  double min_effect_rms_fraction = 0.25;
  double white_fraction = 0.5;
  // A production gear's own deviations among the fitted columns (part_model.h: 5 per flank, a
  // tenth of the readings or more): the residuals' variance is then (1 − p/n) of a reading's, p
  // the fit's rank, so the laws are fitted to each residual divided by √(1 − p/n) (the mean
  // leverage: "standardised residuals", Cook & Weisberg 1982 §2.2) and the white variance, and its
  // null values, divided by its expectation factor 1 − Σ_a |Qᵀc_a|² / (6 m) (above). Off for a
  // master, whose few columns change the variance by well under 1 %.
  bool leverage_correction = false;
};

struct PointLawHypothesis {
  std::string name;          // "model", "noise", "step_quantization"
  bool tied = false;         // step_quantization without the constant columns
  std::vector<int> columns;  // columns of X_S the hypothesis keeps (the constant one added last
                             // when `constant_added`)
  bool constant_added = false;
  ResidualLaw law;
  int parameters = 0;  // k of the BIC
  double log_likelihood = -std::numeric_limits<double>::infinity();
  double bic = std::numeric_limits<double>::infinity();
  double delta_bic = 0.0;  // bic − the model's
  // The fitted law parameter: σ of the Gaussian part (noise) or q (step_quantization), µm.
  double estimate = std::numeric_limits<double>::quiet_NaN();
  double std_error = std::numeric_limits<double>::quiet_NaN();
  Eigen::VectorXd beta;      // coefficients of the kept columns (+ the constant)
  Eigen::VectorXd residual;  // ε = r − X β (its law is `law`, mean included)
  bool accepted = false;
  std::string note;  // why it was not accepted
};

struct PointLawStage {
  bool ran = false;
  std::string skipped_because;
  double model_variance_um2 = 0.0;                                       // v₀
  double white_variance_um2 = std::numeric_limits<double>::quiet_NaN();  // v_w
  int differences = 0;
  double white_p = std::numeric_limits<double>::quiet_NaN();
  double white_excess_rms_um = 0.0;            // √max(0, v_w − v₀)
  std::vector<PointLawHypothesis> hypotheses;  // [0] = the model's law
  int chosen = 0;              // index of the accepted alternative; 0: the model's law
  std::vector<int> ambiguous;  // other accepted hypotheses of the other kind, close in BIC
  const PointLawHypothesis& best() const { return hypotheses[static_cast<std::size_t>(chosen)]; }
  // The hypothesis of that name with the lowest BIC, or nullptr.
  const PointLawHypothesis* find(const std::string& name) const;
};

// The stage on residuals `r` (µm, one per point) with the selected effects' columns `x_selected`
// (points × p, may have 0 columns) and the model's noise floor.
PointLawStage point_law_stage(const Eigen::VectorXd& r, const Eigen::MatrixXd& x_selected,
                              const std::vector<ResidualPoint>& points, const NoiseFloor& floor,
                              const PointLawOptions& options = {});

}  // namespace gearmc
