// Clamped uniform cubic B-splines of the deviation model (declared in deviations.h): the basis
// of n coefficients as fixed per-span maps from coefficients to Taylor coefficients (Piegl &
// Tiller's algorithm A2.3, once per n), a spline's span cubics built from them, and the exact
// ranges of its values and derivatives from those cubics. Evaluation is in deviations.cpp, next
// to the flank deviation field that calls it on the contact solver's hot path.
#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <memory>
#include <mutex>

#include "core/check.h"
#include "gears/cubic_range.h"
#include "gears/deviations.h"

namespace gearmc {
namespace {

// Knot vector of a clamped uniform cubic B-spline with n coefficients on [t0, t1].
double knot(int i, int n, double t0, double t1) {
  const int spans = n - 3;
  const int j = std::clamp(i - 3, 0, spans);
  return t0 + (t1 - t0) * j / spans;
}

}  // namespace

namespace {

// The basis functions N_{span-3} .. N_span and their first two derivatives at t on knot span
// `span` (3 .. n - 1) of the clamped uniform knot vector with n coefficients on [t0, t1]
// (Piegl & Tiller, The NURBS Book, algorithm A2.3, degree 3): ders[k][j] = N^(k)_{span-3+j}(t).
void basis_derivatives(int span, double t, int n, double t0, double t1, double ders[3][4]) {
  constexpr int p = 3;
  auto U = [&](int i) { return knot(i, n, t0, t1); };
  double ndu[p + 1][p + 1], left[p + 1], right[p + 1];
  ndu[0][0] = 1.0;
  for (int j = 1; j <= p; ++j) {
    left[j] = t - U(span + 1 - j);
    right[j] = U(span + j) - t;
    double saved = 0.0;
    for (int r = 0; r < j; ++r) {
      ndu[j][r] = right[r + 1] + left[j - r];
      const double temp = ndu[r][j - 1] / ndu[j][r];
      ndu[r][j] = saved + right[r + 1] * temp;
      saved = left[j - r] * temp;
    }
    ndu[j][j] = saved;
  }
  for (int j = 0; j <= p; ++j) ders[0][j] = ndu[j][p];
  double a[2][p + 1];
  for (int r = 0; r <= p; ++r) {
    int s1 = 0, s2 = 1;
    a[0][0] = 1.0;
    for (int k = 1; k <= 2; ++k) {
      double d = 0.0;
      const int rk = r - k, pk = p - k;
      if (r >= k) {
        a[s2][0] = a[s1][0] / ndu[pk + 1][rk];
        d = a[s2][0] * ndu[rk][pk];
      }
      const int j1 = rk >= -1 ? 1 : -rk;
      const int j2 = (r - 1 <= pk) ? k - 1 : p - r;
      for (int j = j1; j <= j2; ++j) {
        a[s2][j] = (a[s1][j] - a[s1][j - 1]) / ndu[pk + 1][rk + j];
        d += a[s2][j] * ndu[rk + j][pk];
      }
      if (r <= pk) {
        a[s2][k] = -a[s1][k - 1] / ndu[pk + 1][r];
        d += a[s2][k] * ndu[r][pk];
      }
      ders[k][r] = d;
      std::swap(s1, s2);
    }
  }
  for (int j = 0; j <= p; ++j) {
    ders[1][j] *= p;
    ders[2][j] *= p * (p - 1);
  }
}

}  // namespace

CubicBSplineBasis::CubicBSplineBasis(int coefficients) : n_(coefficients) {
  GEARMC_CHECK(n_ >= 4, "a cubic B-spline needs at least 4 coefficients");
  const int spans = n_ - 3;
  matrices_.resize(spans);
  for (int k = 0; k < spans; ++k) {
    // On the integer knots (h = 1): value, slope and half the curvature at the span start, and
    // the constant third derivative from the curvature at both ends.
    double start[3][4], end[3][4];
    basis_derivatives(k + 3, k, n_, 0.0, spans, start);
    basis_derivatives(k + 3, k + 1, n_, 0.0, spans, end);
    for (int j = 0; j < 4; ++j) {
      matrices_[k][0][j] = start[0][j];
      matrices_[k][1][j] = start[1][j];
      matrices_[k][2][j] = 0.5 * start[2][j];
      matrices_[k][3][j] = (end[2][j] - start[2][j]) / 6.0;
    }
  }
}

const CubicBSplineBasis& CubicBSplineBasis::of(int coefficients) {
  static std::mutex mutex;
  static std::map<int, std::unique_ptr<const CubicBSplineBasis>> cache;
  const std::lock_guard<std::mutex> lock(mutex);
  std::unique_ptr<const CubicBSplineBasis>& basis = cache[coefficients];
  if (!basis) basis = std::make_unique<const CubicBSplineBasis>(coefficients);
  return *basis;
}

CubicBSpline::CubicBSpline(double t0, double t1, std::vector<double> coefficients)
    : t0_(t0), t1_(t1), c_(std::move(coefficients)) {
  GEARMC_CHECK(c_.size() >= 4 && t1_ > t0_,
               "a cubic B-spline needs at least 4 coefficients and t1 > t0");
  build(CubicBSplineBasis::of(static_cast<int>(c_.size())));
}

CubicBSpline::CubicBSpline(double t0, double t1, std::vector<double> coefficients,
                           const CubicBSplineBasis& basis)
    : t0_(t0), t1_(t1), c_(std::move(coefficients)) {
  GEARMC_CHECK(c_.size() >= 4 && t1_ > t0_,
               "a cubic B-spline needs at least 4 coefficients and t1 > t0");
  GEARMC_CHECK(basis.coefficients() == static_cast<int>(c_.size()),
               "a cubic B-spline's basis must have as many coefficients as the spline");
  build(basis);
}

void CubicBSpline::build(const CubicBSplineBasis& basis) {
  const int spans = static_cast<int>(c_.size()) - 3;
  h_ = (t1_ - t0_) / spans;
  inverse_h_ = spans / (t1_ - t0_);
  // Taylor coefficients in u = t - t_k from those in s = u / h: q_m / h^m.
  const double g1 = 1.0 / h_, g2 = g1 * g1, g3 = g2 * g1;
  poly_.resize(spans);
  for (int k = 0; k < spans; ++k) {
    const CubicBSplineBasis::Matrix& M = basis.matrix(k);
    const double* c = c_.data() + k;
    std::array<double, 4> q;
    for (int m = 0; m < 4; ++m) {
      q[m] = M[m][0] * c[0] + M[m][1] * c[1] + M[m][2] * c[2] + M[m][3] * c[3];
    }
    poly_[k] = {q[0], q[1] * g1, q[2] * g2, q[3] * g3};
  }
}

double CubicBSpline::greville(int i) const {
  const int n = static_cast<int>(c_.size());
  return (knot(i + 1, n, t0_, t1_) + knot(i + 2, n, t0_, t1_) + knot(i + 3, n, t0_, t1_)) / 3.0;
}

// Widens [*lo, *hi] by the values of the cubic q0 + q1 u + q2 u^2 + q3 u^3 on [0, h]: its
// extremes lie at the ends or where the derivative q1 + 2 q2 u + 3 q3 u^2 vanishes inside; the
// roots of that quadratic in the cancellation-free form (Press et al., Numerical Recipes,
// 3rd ed., §5.6): Q = -(B + sgn(B) sqrt(B^2 - 4AC)) / 2, roots Q / A and C / Q.
void widen_by_cubic(const std::array<double, 4>& q, double h, double* lo, double* hi) {
  auto add = [&](double u) {
    const double v = q[0] + u * (q[1] + u * (q[2] + u * q[3]));
    *lo = std::min(*lo, v);
    *hi = std::max(*hi, v);
  };
  add(0.0);
  add(h);
  const double A = 3.0 * q[3], B = 2.0 * q[2], C = q[1];
  const double discriminant = B * B - 4.0 * A * C;
  if (discriminant < 0.0) return;
  const double Q = -0.5 * (B + std::copysign(std::sqrt(discriminant), B));
  if (A != 0.0) {
    const double u = Q / A;
    if (u > 0.0 && u < h) add(u);
  }
  if (Q != 0.0) {
    const double u = C / Q;
    if (u > 0.0 && u < h) add(u);
  }
}

CubicBSpline::Range CubicBSpline::value_range(double slope, double mid) const {
  if (c_.empty()) {
    const double a = slope * (t0_ - mid), b = slope * (t1_ - mid);
    return {std::min(a, b), std::max(a, b)};
  }
  Range r{std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity()};
  for (std::size_t k = 0; k < poly_.size(); ++k) {
    std::array<double, 4> q = poly_[k];
    q[0] += slope * (t0_ + static_cast<double>(k) * h_ - mid);
    q[1] += slope;
    widen_by_cubic(q, h_, &r.lo, &r.hi);
  }
  return r;
}

CubicBSpline::Ranges CubicBSpline::derivative_ranges() const {
  constexpr double inf = std::numeric_limits<double>::infinity();
  if (c_.empty()) return {{-inf, inf}, {0.0, 0.0}, {0.0, 0.0}};
  Ranges r{{-inf, inf}, {inf, -inf}, {0.0, 0.0}};  // the continuation's second derivative 0
  auto add = [](Range& range, double v) {
    range.lo = std::min(range.lo, v);
    range.hi = std::max(range.hi, v);
  };
  for (const std::array<double, 4>& q : poly_) {
    auto first = [&](double u) { return q[1] + u * (2.0 * q[2] + 3.0 * u * q[3]); };
    add(r.first, first(0.0));
    add(r.first, first(h_));
    add(r.second, 2.0 * q[2]);
    add(r.second, 2.0 * q[2] + 6.0 * h_ * q[3]);
    if (q[3] != 0.0) {
      const double u = -q[2] / (3.0 * q[3]);
      if (u > 0.0 && u < h_) add(r.first, first(u));
    }
  }
  return r;
}

}  // namespace gearmc
