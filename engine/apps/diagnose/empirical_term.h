// The empirical term of a diagnosis: when structure remains after the library's best fit
// (Diagnosis::unexplained_structure), a generic low-order term along the axis the remaining
// structure varies along (Diagnosis::unexplained_along) is fitted to the residuals after the
// library fit, so that fitted.yaml predicts that structure too (the `empirical` effect,
// engine/effects/empirical_effect.h) and the user sees how much of the gap it takes.
//
// Basis and order. The basis is the axis's natural one (empirical_effect.h natural_basis):
// harmonics cos kx, sin kx for the angles (tooth position, approach azimuth), Legendre
// polynomials P_k on the measured range for the others (roll length, face position, flank,
// probing order). Orders K = 1 … K_max, K_max = min(6, D − 1) for Legendre and
// min(6, ⌊(D − 1)/2⌋) for harmonics, D the number of distinct coordinates (a basis with more
// functions than distinct values would interpolate). The order is the one of least
// BIC_K = n ln(RSS_K / n) + p_K ln n (Schwarz, Ann. Statist. 6, 1978; Gaussian errors, σ
// unknown; p_K the rank of the K-order basis), and the term is kept only when
// BIC_K − BIC_0 ≤ −min_delta_bic (the selection's 10: "very strong", Kass & Raftery 1995).
// Standard errors: σ̂² (BᵀB)⁻¹ with σ̂² = RSS_K / (n − p_library − p_K), p_library the
// parameters the library fit used.
//
// The order is chosen on the residuals the library's fit leaves (orthogonal to its columns). The
// coefficients are then fitted jointly with the library's selected columns, and the library is
// selected and fitted again on the readings less the term (diagnosis.cpp): an effect selected only
// because the structure leaned on its columns drops out, and the values written to fitted.yaml
// (the library's effects and the term) are those of one joint fit (Frisch–Waugh: the library's
// coefficients fitted to r − B β_B are the joint fit's). A second `diagnose` against fitted.yaml
// then sees what the two together leave.
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "engine/apps/diagnose/prediction.h"

namespace gearmc {

struct EmpiricalTermValue {
  std::string name;  // a_<k>_um (P_k or cos kx), b_<k>_um (sin kx)
  double value_um = 0.0;
  double std_error_um = 0.0;
};

struct EmpiricalTerm {
  bool fitted = false;
  std::string why_not;  // when not fitted: why (too few distinct coordinates, no BIC support)
  std::string axis;     // Diagnosis::unexplained_along's axis
  std::string basis;    // "legendre" or "harmonic"
  double from = 0.0, to = 0.0;  // the Legendre range (the measured coordinates' min and max)
  int order = 0;                // K
  int max_order = 0;            // K_max tried
  std::vector<double> bic;      // BIC_K − BIC_0 for K = 0 … K_max
  double delta_bic = 0.0;       // at the chosen K
  std::vector<EmpiricalTermValue> terms;
  double fitted_rms_um = 0.0;  // RMS of the term over the points
  // The residuals after the library fit, and after the library fit and the term: RMS and the
  // excess RMS over the noise floor √max(0, RSS/dof − σ²) (dof = n − fitted parameters).
  double rms_before_um = 0.0, rms_after_um = 0.0;
  double excess_rms_before_um = 0.0, excess_rms_after_um = 0.0;
  std::string identify_by;  // the measurement that would identify the structure
};

// Fits the term along `axis` to `residual_after_um` (one per point, the residuals after the
// library fit, which used `library_parameters` parameters), the noise floor's variance
// `noise_variance_um2` for the excess RMS. An unknown axis gives fitted = false.
EmpiricalTerm fit_empirical_term(const std::vector<ResidualPoint>& points,
                                 const Eigen::VectorXd& residual_after_um, int library_parameters,
                                 double noise_variance_um2, const std::string& axis,
                                 double min_delta_bic);

// The term's columns at `points` (one per coefficient of `term`, in its order).
Eigen::MatrixXd empirical_columns(const std::vector<ResidualPoint>& points,
                                  const EmpiricalTerm& term);

// The measurement that would tell what the structure along `axis` is (one sentence).
std::string empirical_identify_by(const std::string& axis);

}  // namespace gearmc
