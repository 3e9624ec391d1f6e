// Clamped uniform cubic B-splines, the form fields of the deviation model: the basis of n
// coefficients as fixed per-span maps from coefficients to Taylor coefficients (built once per
// n), the spline as one cubic per span (value and derivatives by one Horner step, linear
// continuation outside its range), and exact ranges of its values and derivatives from those
// cubics. Values in µm, abscissae in mm where the deviation model uses them.
#pragma once

#include <array>
#include <vector>

namespace gearmc {

// The clamped uniform cubic B-spline basis with n coefficients (n - 3 spans) in the unit
// parameter: on span k the spline is sum_j c[k + j] N_{k+j}, a cubic whose Taylor coefficients
// about the span start, in s = (t - t_k) / h (h the span length), are a fixed linear map of the
// span's four coefficients: q = matrix(k) (c[k], .., c[k + 3]). The map depends only on n and k
// (the same for every interior span; the first and last three differ); it is computed once from
// the basis functions and their derivatives (Piegl & Tiller, The NURBS Book, algorithm A2.3) on
// the integer knots 0, 0, 0, 0, 1, 2, .., n - 3, .., n - 3.
class CubicBSplineBasis {
 public:
  using Matrix = std::array<std::array<double, 4>, 4>;  // [Taylor order m][coefficient j]
  explicit CubicBSplineBasis(int coefficients);
  // The basis for n coefficients, built on first use and kept (thread-safe).
  static const CubicBSplineBasis& of(int coefficients);
  int coefficients() const { return n_; }
  int spans() const { return n_ - 3; }
  const Matrix& matrix(int span) const { return matrices_[span]; }

 private:
  int n_;
  std::vector<Matrix> matrices_;
};

// Clamped uniform cubic B-spline on [t0, t1], linearly continued outside (value and slope of
// the end), so it is C2 inside and C1 everywhere. Values in µm, t in mm.
class CubicBSpline {
 public:
  CubicBSpline() = default;  // identically zero
  CubicBSpline(double t0, double t1, std::vector<double> coefficients);
  // The same with the basis given (it must be CubicBSplineBasis::of(coefficients.size()) or an
  // equal one): no look-up of the shared basis.
  CubicBSpline(double t0, double t1, std::vector<double> coefficients,
               const CubicBSplineBasis& basis);
  double value(double t) const;
  double derivative(double t) const;         // µm/mm
  double second_derivative(double t) const;  // µm/mm²
  // Value and both derivatives at once (the contact solver's hot path).
  void evaluate(double t, double* value, double* first, double* second) const;
  // Greville abscissa of coefficient i: a spline with coefficients a + b*greville(i) is the
  // line a + b t exactly (linear precision).
  double greville(int i) const;
  const std::vector<double>& coefficients() const { return c_; }
  struct Range {
    double lo, hi;
  };
  struct Ranges {
    Range value, first, second;
  };
  // The exact range over [t0, t1] of value(t) + slope (t - mid) (µm; slope in µm/mm, mid in
  // mm): from each span's cubic, its ends and the roots of its quadratic derivative.
  Range value_range(double slope = 0.0, double mid = 0.0) const;
  // The ranges of the first and second derivative over the whole real line (the linear
  // continuation adds the end slopes and a zero second derivative): exact, from the spans'
  // cubics. value is left at (-inf, inf).
  Ranges derivative_ranges() const;
  double t0() const { return t0_; }
  double t1() const { return t1_; }

 private:
  void build(const CubicBSplineBasis& basis);  // h_ and poly_ from c_
  double t0_ = 0.0, t1_ = 1.0, h_ = 1.0;
  std::vector<double> c_;
  // Each span's cubic in power form about its start: v = p0 + p1 u + p2 u^2 + p3 u^3, built
  // once from the coefficients (CubicBSplineBasis) so that an evaluation is one Horner step.
  std::vector<std::array<double, 4>> poly_;
};

// Widens [*lo, *hi] by the values of the cubic q0 + q1 u + q2 u^2 + q3 u^3 on [0, h] (exact: its
// ends and the real roots of its derivative inside).
void widen_by_cubic(const std::array<double, 4>& q, double h, double* lo, double* hi);

}  // namespace gearmc
