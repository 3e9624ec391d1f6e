// Special functions of the uncertainty evaluation: the standard normal and Student t
// distribution functions and their quantiles (the coverage factor k of the GUM, JCGM 100 G.3),
// the regularised incomplete beta function, and a bracketing inverse of any continuous CDF.
#pragma once

#include <functional>

namespace gearmc::uncertainty {

// Standard normal CDF Φ(z) = erfc(−z/√2)/2 and its inverse (Acklam's rational approximation,
// relative error 1.15e-9, refined by one Halley step to full double precision). p in (0, 1).
double normal_cdf(double z);
double normal_quantile(double p);

// Regularised incomplete beta function I_x(a, b), a, b > 0, 0 <= x <= 1 (continued fraction of
// Press et al., "Numerical Recipes", 3rd ed., §6.4, modified Lentz; symmetry I_x(a,b) =
// 1 − I_{1−x}(b,a) for x > (a+1)/(a+b+2)). About 1e-14 relative accuracy.
double incomplete_beta(double a, double b, double x);

// Student t with ν > 0 degrees of freedom (ν may be non-integer; ν = +inf is the normal):
// F(t) = 1 − I_{ν/(ν+t²)}(ν/2, 1/2)/2 for t >= 0 (Abramowitz & Stegun 26.7.1, 26.5.27).
double student_t_cdf(double t, double nu);
// Its p-quantile, p in (0, 1), by inverting the CDF (to about 1e-13 relative).
double student_t_quantile(double p, double nu);

// The x with cdf(x) = p for a continuous non-decreasing `cdf`: widens [lo, hi] until it
// brackets p, then bisects to the last bit (about 100 steps). For tests and single values.
double invert_cdf(const std::function<double(double)>& cdf, double p, double lo, double hi);

}  // namespace gearmc::uncertainty
