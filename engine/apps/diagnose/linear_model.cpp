// Numerical tools of the diagnosis: bases, least squares, F and KS tails, Holm, canonical
// correlations, robust scale, harmonic spectrum (see linear_model.h for the sources).
#include "engine/apps/diagnose/linear_model.h"

#include "core/constants.h"
#include "core/special_functions.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <utility>

namespace gearmc {
namespace {}  // namespace

ColumnBasis orthonormal_basis(const Eigen::MatrixXd& x, const Eigen::MatrixXd& against,
                              double relative_tolerance) {
  // Block Gram–Schmidt, twice (BCGS2: Barlow & Smoktunowicz, Numer. Math. 123 (2013) 395): the
  // columns in blocks of kBlock, each block projected off the given basis and the columns kept
  // before it by two matrix products (one pass over the n rows for the whole block, not one per
  // pair of columns), then its columns one by one off the block's columns kept before them
  // (modified Gram–Schmidt, twice). The same decisions as column-by-column Gram–Schmidt.
  // The block is worked on in place, in the columns of the basis not yet filled (k ≤ start):
  // no copy of n rows beyond the basis itself.
  constexpr int kBlock = 8;
  ColumnBasis out;
  out.q.resize(x.rows(), x.cols());
  int k = 0;
  for (int start = 0; start < x.cols(); start += kBlock) {
    const int w = std::min<int>(kBlock, static_cast<int>(x.cols()) - start);
    auto v = out.q.middleCols(k, w);
    v = x.middleCols(start, w);
    Eigen::VectorXd norm0(w);
    for (int c = 0; c < w; ++c) norm0[c] = v.col(c).norm();
    for (int pass = 0; pass < 2; ++pass) {
      if (against.cols() > 0) v.noalias() -= against * (against.transpose() * v);
      if (k > 0) v.noalias() -= out.q.leftCols(k) * (out.q.leftCols(k).transpose() * v);
    }
    // Column c of the block sits at block_first + c; a kept column moves left to k ≤ that.
    const int block_first = k;
    for (int c = 0; c < w; ++c) {
      if (!(norm0[c] > 0.0) || !std::isfinite(norm0[c])) continue;
      auto col = out.q.col(block_first + c);
      for (int pass = 0; pass < 2; ++pass) {
        for (int a = block_first; a < k; ++a) col -= out.q.col(a) * out.q.col(a).dot(col);
      }
      const double norm = col.norm();
      if (norm > relative_tolerance * norm0[c]) {
        col /= norm;
        if (k != block_first + c) out.q.col(k) = col;
        ++k;
        out.kept.push_back(start + c);
      }
    }
  }
  out.q.conservativeResize(x.rows(), k);
  return out;
}

LeastSquaresFit least_squares(const Eigen::MatrixXd& x, const Eigen::VectorXd& y,
                              double relative_tolerance) {
  LeastSquaresFit fit;
  const int p = static_cast<int>(x.cols());
  fit.beta = Eigen::VectorXd::Zero(p);
  fit.cov_unscaled = Eigen::MatrixXd::Zero(p, p);
  fit.estimable.assign(p, false);
  fit.fitted = Eigen::VectorXd::Zero(x.rows());
  // Only the kept columns are needed from the basis (its n rows freed before the QR's copy).
  const std::vector<int> kept = orthonormal_basis(x, relative_tolerance).kept;
  const int k = static_cast<int>(kept.size());
  fit.rank = k;
  if (k > 0) {
    Eigen::MatrixXd xs(x.rows(), k);
    Eigen::VectorXd scale(k);
    for (int a = 0; a < k; ++a) {
      scale[a] = x.col(kept[a]).norm();
      xs.col(a) = x.col(kept[a]) / scale[a];
    }
    Eigen::Ref<Eigen::MatrixXd> in_place = xs;
    const Eigen::HouseholderQR<Eigen::Ref<Eigen::MatrixXd>> qr(in_place);  // overwrites xs
    const Eigen::VectorXd beta_s = qr.solve(y);
    const Eigen::MatrixXd r = qr.matrixQR().topLeftCorner(k, k).triangularView<Eigen::Upper>();
    const Eigen::MatrixXd r_inv =
        r.triangularView<Eigen::Upper>().solve(Eigen::MatrixXd::Identity(k, k));
    const Eigen::MatrixXd cov_s = r_inv * r_inv.transpose();
    for (int a = 0; a < k; ++a) {
      const int ca = kept[a];
      fit.beta[ca] = beta_s[a] / scale[a];
      fit.estimable[ca] = true;
      for (int b = 0; b < k; ++b) {
        fit.cov_unscaled(ca, kept[b]) = cov_s(a, b) / (scale[a] * scale[b]);
      }
    }
    fit.fitted = x * fit.beta;
  }
  fit.rss = (y - fit.fitted).squaredNorm();
  return fit;
}

std::vector<double> holm_adjust(const std::vector<double>& p) {
  const std::size_t m = p.size();
  std::vector<std::size_t> idx(m);
  std::iota(idx.begin(), idx.end(), 0);
  std::stable_sort(idx.begin(), idx.end(),
                   [&](std::size_t a, std::size_t b) { return p[a] < p[b]; });
  std::vector<double> adjusted(m);
  double running = 0.0;
  for (std::size_t r = 0; r < m; ++r) {
    const double v = std::min(1.0, static_cast<double>(m - r) * p[idx[r]]);
    running = std::max(running, v);
    adjusted[idx[r]] = running;
  }
  return adjusted;
}

std::vector<double> canonical_correlations(const Eigen::MatrixXd& qa, const Eigen::MatrixXd& qb) {
  if (qa.cols() == 0 || qb.cols() == 0) return {};
  const Eigen::MatrixXd m = qa.transpose() * qb;
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(m);
  std::vector<double> out;
  for (int i = 0; i < svd.singularValues().size(); ++i) {
    out.push_back(std::min(1.0, svd.singularValues()[i]));
  }
  return out;
}

// Cholesky–Banachiewicz by columns (Golub & Van Loan, "Matrix Computations", 4th ed., 2013,
// §4.2.5), a column left out when its pivot is below the rank rule (the semi-definite
// Cholesky of Higham, "Accuracy and Stability of Numerical Algorithms", 2nd ed., §10.3, without
// its pivoting, so that the column order decides as in orthonormal_basis).
Eigen::MatrixXd gram_root(const Eigen::MatrixXd& gram, double relative_tolerance) {
  const int c = static_cast<int>(gram.rows());
  Eigen::MatrixXd l = Eigen::MatrixXd::Zero(c, c);
  int kept = 0;
  for (int j = 0; j < c; ++j) {
    const double own = gram(j, j);
    const double left = own - l.row(j).head(kept).squaredNorm();
    if (!(own > 0.0) || !(left > relative_tolerance * relative_tolerance * own)) continue;
    const double pivot = std::sqrt(left);
    l(j, kept) = pivot;
    for (int i = j + 1; i < c; ++i) {
      l(i, kept) = (gram(i, j) - l.row(i).head(kept).dot(l.row(j).head(kept))) / pivot;
    }
    ++kept;
  }
  return l.leftCols(kept);
}

double scaled_condition_number(Eigen::MatrixXd x) {
  // The non-zero columns, scaled, moved to the front in place; then the singular values of the
  // k × k triangle R of X = QR (the same as X's), so the only n-row matrix is the argument.
  int k = 0;
  for (int c = 0; c < x.cols(); ++c) {
    const double norm = x.col(c).norm();
    if (norm > 0.0) x.col(k++) = x.col(c) / norm;
  }
  if (k == 0) return kNaN;
  if (k > x.rows()) return kInf;
  Eigen::Ref<Eigen::MatrixXd> s = x.leftCols(k);
  const Eigen::HouseholderQR<Eigen::Ref<Eigen::MatrixXd>> qr(s);
  const Eigen::MatrixXd r = qr.matrixQR().topRows(k).triangularView<Eigen::Upper>();
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(r);
  const double hi = svd.singularValues()[0];
  const double lo = svd.singularValues()[svd.singularValues().size() - 1];
  return lo > hi * 1e-15 ? hi / lo : kInf;
}

double ks_distance_normal(std::vector<double> values, double sigma) {
  if (values.empty() || !(sigma > 0.0)) return kNaN;
  return ks_distance(std::move(values), [sigma](double x) { return normal_cdf(x / sigma); });
}

double mad_sigma(std::vector<double> values) {
  if (values.empty()) return kNaN;
  const double med = sample_quantile(values, 0.5);
  for (double& v : values) v = std::abs(v - med);
  return 1.482602218505602 * sample_quantile(std::move(values), 0.5);
}

double empirical_p_value(double observed, const std::vector<double>& null_values) {
  if (std::isnan(observed)) return kNaN;
  std::size_t at_least = 0;
  for (double v : null_values) at_least += v >= observed ? 1 : 0;
  return (1.0 + static_cast<double>(at_least)) / (1.0 + static_cast<double>(null_values.size()));
}

double min_p_combined_p_value(const std::vector<ResampledTest>& family) {
  if (family.empty() || family.front().null_values.empty()) return kNaN;
  const std::size_t samples = family.front().null_values.size() + 1;  // the data is sample 0
  bool any = false;
  for (const ResampledTest& t : family) {
    if (t.null_values.size() + 1 != samples) return kNaN;  // not the same replicates
    any = any || std::isfinite(t.observed);
  }
  if (!any) return kNaN;
  // m(i) as an integer count (p = count / (K + 1)), so ties compare exactly.
  std::vector<std::size_t> smallest(samples, samples);
  for (const ResampledTest& t : family) {
    std::vector<double> all(samples);
    all[0] = t.observed;
    std::copy(t.null_values.begin(), t.null_values.end(), all.begin() + 1);
    std::vector<double> sorted;
    for (double v : all) {
      if (!std::isnan(v)) sorted.push_back(v);
    }
    std::sort(sorted.begin(), sorted.end());
    for (std::size_t i = 0; i < samples; ++i) {
      if (std::isnan(all[i]) || !(all[i] >= t.gate)) continue;  // cannot reject: p = 1
      const auto at_least = static_cast<std::size_t>(
          sorted.end() - std::lower_bound(sorted.begin(), sorted.end(), all[i]));
      smallest[i] = std::min(smallest[i], at_least);
    }
  }
  std::size_t as_small = 0;
  for (std::size_t m : smallest) as_small += m <= smallest[0] ? 1 : 0;
  return static_cast<double>(as_small) / static_cast<double>(samples);
}

double sample_quantile(std::vector<double> values, double q) {
  if (values.empty()) return kNaN;
  std::sort(values.begin(), values.end());
  const double h = (static_cast<double>(values.size()) - 1.0) * std::clamp(q, 0.0, 1.0);
  const std::size_t lo = static_cast<std::size_t>(std::floor(h));
  const std::size_t hi = std::min(lo + 1, values.size() - 1);
  return values[lo] + (h - static_cast<double>(lo)) * (values[hi] - values[lo]);
}

HarmonicSpectrum::HarmonicSpectrum(const std::vector<double>& azimuth_rad, int max_order)
    : max_order_(max_order),
      cos_(static_cast<int>(azimuth_rad.size())),
      sin_(static_cast<int>(azimuth_rad.size())) {
  for (std::size_t r = 0; r < azimuth_rad.size(); ++r) {
    cos_[static_cast<int>(r)] = std::cos(azimuth_rad[r]);
    sin_[static_cast<int>(r)] = std::sin(azimuth_rad[r]);
  }
  // Minimum-norm least squares, pinv(X) = pinv(XᵀX) Xᵀ (complete orthogonal decomposition of
  // the small Gram matrix): a plan that covers too few azimuths for the high orders still gives
  // finite amplitudes.
  const Eigen::MatrixXd gram = design_transpose_times(Eigen::MatrixXd(), true);
  pinv_ = Eigen::CompleteOrthogonalDecomposition<Eigen::MatrixXd>(gram).pseudoInverse();
}

// X's rows in blocks of kBlock, each made from cos φ and sin φ by the angle-addition recurrence
// cos (k+1)φ = cos kφ cos φ − sin kφ sin φ, sin (k+1)φ = sin kφ cos φ + cos kφ sin φ (its
// rounding grows like k ε: below 1e-14 for the orders used here), and Xᵀm (or XᵀX) accumulated
// block by block in row order.
Eigen::MatrixXd HarmonicSpectrum::design_transpose_times(const Eigen::MatrixXd& m,
                                                         bool gram) const {
  constexpr int kBlock = 512;
  const int rows = static_cast<int>(cos_.size());
  const int coefficients = 2 * max_order_ + 1;
  Eigen::MatrixXd out = Eigen::MatrixXd::Zero(coefficients, gram ? coefficients : m.cols());
  Eigen::MatrixXd xt(coefficients, kBlock);
  for (int b = 0; b < rows; b += kBlock) {
    const int w = std::min(kBlock, rows - b);
    for (int j = 0; j < w; ++j) {
      const double c1 = cos_[b + j], s1 = sin_[b + j];
      double c = 1.0, s = 0.0;
      xt(0, j) = 1.0;
      for (int k = 1; k <= max_order_; ++k) {
        const double next_c = c * c1 - s * s1;
        s = s * c1 + c * s1;
        c = next_c;
        xt(2 * k - 1, j) = c;
        xt(2 * k, j) = s;
      }
    }
    if (gram) {
      out.noalias() += xt.leftCols(w) * xt.leftCols(w).transpose();
    } else {
      out.noalias() += xt.leftCols(w) * m.middleRows(b, w);
    }
  }
  return out;
}

std::vector<double> HarmonicSpectrum::amplitudes(const Eigen::VectorXd& residual_um) const {
  return amplitudes_of(pinv_ * design_transpose_times(residual_um, false));
}

Eigen::MatrixXd HarmonicSpectrum::unit_covariance(const Eigen::MatrixXd& q) const {
  // S Sᵀ = pinv XᵀX pinv, and S q = pinv Xᵀq.
  Eigen::MatrixXd cov = pinv_ * design_transpose_times(Eigen::MatrixXd(), true) * pinv_;
  if (q.cols() > 0) {
    const Eigen::MatrixXd sq = pinv_ * design_transpose_times(q, false);
    cov -= sq * sq.transpose();
  }
  return cov;
}

std::vector<double> HarmonicSpectrum::amplitudes_of(const Eigen::VectorXd& c) const {
  std::vector<double> a(max_order_ + 1);
  a[0] = std::abs(c[0]);
  for (int k = 1; k <= max_order_; ++k) a[k] = std::hypot(c[2 * k - 1], c[2 * k]);
  return a;
}

}  // namespace gearmc
