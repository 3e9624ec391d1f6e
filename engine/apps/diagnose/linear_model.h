// The numerical tools of the discrepancy diagnosis: orthonormal bases of design
// matrices with a column-by-column rank decision, least-squares fits with covariances, the
// F-distribution tail for nested-model tests, Holm's step-down adjustment, canonical
// correlations between column spaces, scaled condition numbers, the Kolmogorov–Smirnov
// statistic against a normal law, robust scale (MAD) and the least-squares harmonic spectrum of
// residuals against the approach azimuth. Nothing here knows about gears: vectors are residuals
// along n in µm and matrices are signatures in µm per unit of a parameter.
// Sources are cited where each method is implemented (linear_model.cpp).
#pragma once

#include <Eigen/Core>
#include <limits>
#include <vector>

namespace gearmc {

// An orthonormal basis of the part of a matrix's column space that is orthogonal to a given
// orthonormal basis, built column by column: column c is kept when what is left of it after
// removing the given basis and the columns kept before it has a norm > `relative_tolerance`
// times its own norm (zero columns are never kept). Gram–Schmidt applied twice (Kahan's "twice is
// enough", Parlett, "The Symmetric Eigenvalue Problem", 1980), in blocks of columns
// (linear_model.cpp).
struct ColumnBasis {
  Eigen::MatrixXd q;      // rows × kept.size(), orthonormal columns
  std::vector<int> kept;  // indices of the kept columns of the input, increasing
};
ColumnBasis orthonormal_basis(const Eigen::MatrixXd& x, const Eigen::MatrixXd& against,
                              double relative_tolerance = 1e-6);
inline ColumnBasis orthonormal_basis(const Eigen::MatrixXd& x, double relative_tolerance = 1e-6) {
  return orthonormal_basis(x, Eigen::MatrixXd(x.rows(), 0), relative_tolerance);
}

// Ordinary least squares y ≈ X β on the columns of X that are linearly independent (chosen in
// column order as orthonormal_basis does); the other columns get β = 0 and `estimable` false.
// cov_unscaled = (X_kᵀ X_k)⁻¹ on the kept columns (zero rows/columns elsewhere): multiply by σ²
// for the covariance of β. Solved by Householder QR on unit-norm scaled columns.
struct LeastSquaresFit {
  Eigen::VectorXd beta;
  Eigen::MatrixXd cov_unscaled;
  std::vector<bool> estimable;
  Eigen::VectorXd fitted;  // X β
  double rss = 0.0;        // |y − X β|²
  int rank = 0;
};
LeastSquaresFit least_squares(const Eigen::MatrixXd& x, const Eigen::VectorXd& y,
                              double relative_tolerance = 1e-6);

// Holm's step-down adjusted p-values (Holm, "A simple sequentially rejective multiple test
// procedure", Scand. J. Statist. 6, 1979): sort ascending, p̃_(i) = max_{j<=i} min(1,
// (m − j + 1) p_(j)); returned in the input order. Controls the family-wise error rate.
std::vector<double> holm_adjust(const std::vector<double>& p);

// Canonical correlations (cosines of the principal angles) between the column spaces of two
// orthonormal bases: the singular values of Q_aᵀ Q_b, descending (Björck & Golub, "Numerical
// methods for computing angles between linear subspaces", Math. Comp. 27, 1973).
std::vector<double> canonical_correlations(const Eigen::MatrixXd& qa, const Eigen::MatrixXd& qb);

// A root L (L Lᵀ = gram) of a Gram matrix (symmetric positive semi-definite) by Cholesky in
// column order with a rank rule: column c is kept when what is left of its diagonal after the
// kept columns before it exceeds `relative_tolerance`² times its own diagonal (the squared form
// of orthonormal_basis's rule), one column of L per kept column. Draws of N(0, gram) are L w with
// w standard normal of L.cols() entries. L moves continuously with the matrix away from rank
// decisions, unlike a root from eigenvectors (V Λ^½), which turns freely inside a repeated
// eigenvalue: rounding-level changes of the matrix (the same columns summed in another order)
// would then change every draw made from it.
Eigen::MatrixXd gram_root(const Eigen::MatrixXd& gram, double relative_tolerance = 1e-6);

// Condition number (largest / smallest singular value) of X with every column scaled to unit
// length (Belsley, Kuh & Welsch, "Regression Diagnostics", 1980, ch. 3). Zero columns are left
// out; +inf when the scaled columns are linearly dependent. X by value: it is overwritten (move a
// temporary in).
double scaled_condition_number(Eigen::MatrixXd x);

// One-sample Kolmogorov–Smirnov distance D = sup |F_n(x) − Φ(x/σ)| of `values` against
// N(0, σ²) (ks_distance of core/special_functions.h with Φ(x/σ)); NaN unless σ > 0. The
// F tail, the KS p-value and the other special functions are in core/special_functions.h.
double ks_distance_normal(std::vector<double> values, double sigma);

// 1.4826 × median |x − median x| (Hampel, JASA 69, 1974): σ of normal data, robust to outliers.
double mad_sigma(std::vector<double> values);

// The empirical p-value of an observed statistic against its simulated null values, for a test
// that rejects for large values: (1 + #{null >= observed}) / (K + 1) (Davison & Hinkley,
// "Bootstrap Methods and their Application", 1997, ch. 4; never 0, Phipson & Smyth 2010).
double empirical_p_value(double observed, const std::vector<double>& null_values);

// One test of a family combined by min-P (below): its statistic, which rejects for large values,
// on the data and on each of the K null replicates (the same replicates, in the same order, for
// every test of the family), and a gate: a statistic below `gate` (or NaN) cannot reject, on the
// data and on every replicate alike (e.g. a minimum practical size; −inf: no gate).
struct ResampledTest {
  double observed = 0.0;
  std::vector<double> null_values;
  double gate = -std::numeric_limits<double>::infinity();
};
// The single-step min-P combination of a family of tests calibrated on the same null replicates
// (Westfall & Young, "Resampling-Based Multiple Testing", Wiley 1993; each replicate's p-values
// taken from the replicates themselves, as in Ge, Dudoit & Speed, TEST 12, 2003):
// the data and the K replicates are K + 1 samples, exchangeable under the null. Each sample i gets
// each test's empirical p-value among all K + 1, p_j(i) = #{l : t_j(l) ≥ t_j(i)} / (K + 1) (1 when
// t_j(i) is gated or NaN), and its smallest, m(i) = min_j p_j(i); the combined p-value is
// #{i : m(i) ≤ m(data)} / (K + 1). For the data p_j is empirical_p_value. The m(i) are
// exchangeable under the null, so P(combined p ≤ c/(K + 1)) ≤ c/(K + 1): the family-wise level is
// exact up to the Monte-Carlo resolution 1/(K + 1), whatever the tests' dependence (a test that
// repeats another costs nothing, an independent one about halves the level of each). NaN when no
// test has a finite statistic on the data or the family has no replicates.
double min_p_combined_p_value(const std::vector<ResampledTest>& family);
// The q-quantile (0..1) of values, linear interpolation between order statistics (Hyndman &
// Fan 1996, type 7).
double sample_quantile(std::vector<double> values, double q);

// Least-squares harmonic spectrum of residuals against the approach azimuth φ (rad):
// r ≈ a_0 + Σ_{k=1..K} (a_k cos kφ + b_k sin kφ), fitted jointly (the orders are not
// orthogonal on an uneven azimuth sampling); amplitude_0 = |a_0|, amplitude_k = √(a_k² + b_k²)
// in the residuals' unit (µm). Only cos φ, sin φ of each point and the pseudo-inverse of the
// (2K + 1)² Gram matrix are held (16 bytes a point, not the (2K + 1) × N operator: 200 MB at 10⁶
// readings); X's rows are made again, block by block, whenever it is applied.
class HarmonicSpectrum {
 public:
  HarmonicSpectrum(const std::vector<double>& azimuth_rad, int max_order);
  int max_order() const { return max_order_; }
  // Amplitudes of orders 0..max_order (µm).
  std::vector<double> amplitudes(const Eigen::VectorXd& residual_um) const;
  // The covariance of the fitted coefficients (cos/sin pairs, 2K + 1) for white residuals of
  // unit variance projected off the orthonormal columns q (n × p, may be empty):
  // S (I − q qᵀ) Sᵀ, with S the least-squares operator.
  Eigen::MatrixXd unit_covariance(const Eigen::MatrixXd& q) const;
  // Amplitudes of orders 0..max_order from fitted coefficients c (2K + 1).
  std::vector<double> amplitudes_of(const Eigen::VectorXd& c) const;

 private:
  // Xᵀm (gram false; m: rows × any columns) or XᵀX (gram true; m unused).
  Eigen::MatrixXd design_transpose_times(const Eigen::MatrixXd& m, bool gram) const;
  int max_order_;
  Eigen::VectorXd cos_, sin_;  // of each point's azimuth
  Eigen::MatrixXd pinv_;       // (XᵀX)⁺, (2K + 1)²
};

}  // namespace gearmc
