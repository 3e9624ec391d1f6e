// The one toolbox of special functions and distribution tails every layer uses: the standard
// normal and Student t distribution functions and their quantiles (the coverage factor k of the
// GUM, JCGM 100 G.3), the regularised incomplete beta and gamma functions, Fisher's F tail, the
// chi-square tail, the one-sample Kolmogorov–Smirnov distance and its asymptotic p-value, and a
// bracketing inverse of any continuous CDF. Sources are cited per function.
#pragma once

#include <algorithm>
#include <cstddef>
#include <functional>
#include <limits>
#include <vector>

#include "core/sort_doubles.h"

namespace gearmc {

// Standard normal CDF Φ(z) = erfc(−z/√2)/2 and its inverse (Acklam's rational approximation,
// relative error 1.15e-9, refined by one Halley step to full double precision). p in (0, 1).
double normal_cdf(double z);
double normal_quantile(double p);

// Regularised incomplete beta function I_x(a, b), a, b > 0, 0 <= x <= 1 (continued fraction of
// Press et al., "Numerical Recipes", 3rd ed., §6.4, modified Lentz; symmetry I_x(a,b) =
// 1 − I_{1−x}(b,a) for x > (a+1)/(a+b+2)). About 1e-14 relative accuracy. NaN outside the domain.
double incomplete_beta(double a, double b, double x);

// Student t with ν > 0 degrees of freedom (ν may be non-integer; ν = +inf is the normal):
// F(t) = 1 − I_{ν/(ν+t²)}(ν/2, 1/2)/2 for t >= 0 (Abramowitz & Stegun 26.7.1, 26.5.27).
double student_t_cdf(double t, double nu);
// Its p-quantile, p in (0, 1), by inverting the CDF (to about 1e-13 relative).
double student_t_quantile(double p, double nu);

// Upper tail P(F > f) of Fisher's F distribution with (d1, d2) degrees of freedom:
// I_{d2/(d2 + d1 f)}(d2/2, d1/2) (Abramowitz & Stegun 26.6.2).
double f_distribution_upper_tail(double f, double d1, double d2);

// Regularised incomplete gamma functions P(a, x) and Q(a, x) = 1 - P(a, x), a > 0, x >= 0
// (Abramowitz & Stegun 6.5.1; the series 6.5.29 for x < a + 1, the continued fraction 6.5.31
// otherwise, evaluated as in Press et al., "Numerical Recipes", 3rd ed., §6.2, with the modified
// Lentz method). Accurate to about 1e-14 relative. The chi-square tail with k degrees of freedom
// is Q(k/2, x/2).
double regularized_gamma_p(double a, double x);
double regularized_gamma_q(double a, double x);

// One-sample Kolmogorov–Smirnov distance D = sup |F_n(x) − F(x)| of `values` against a continuous
// CDF `cdf` (Kolmogorov 1933; the exact sup over the sample's jumps). NaN for no values.
template <class Cdf>
double ks_distance(std::vector<double> values, const Cdf& cdf) {
  if (values.empty()) return std::numeric_limits<double>::quiet_NaN();
  sort_doubles(values);
  const double n = static_cast<double>(values.size());
  double d = 0.0;
  for (std::size_t i = 0; i < values.size(); ++i) {
    const double f = cdf(values[i]);
    d = std::max({d, (static_cast<double>(i) + 1.0) / n - f, f - static_cast<double>(i) / n});
  }
  return d;
}
// Asymptotic p-value of D for n values, Q_KS((√n + 0.12 + 0.11/√n) D) (Stephens, J. R. Statist.
// Soc. B 32, 1970; Numerical Recipes §14.3.3). Valid for a fully specified law.
double ks_p_value(double d, int n);

// The x with cdf(x) = p for a continuous non-decreasing `cdf`: widens [lo, hi] until it
// brackets p, then bisects to the last bit (about 100 steps). For tests and single values.
double invert_cdf(const std::function<double(double)>& cdf, double p, double lo, double hi);

}  // namespace gearmc
