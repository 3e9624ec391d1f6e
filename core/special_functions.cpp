// Implementation of special_functions.h; sources cited per function there.
#include "core/special_functions.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <utility>

#include "core/constants.h"

namespace gearmc {
namespace {

constexpr double kMachineEpsilon = std::numeric_limits<double>::epsilon();

// --- Incomplete gamma (Press et al., Numerical Recipes 3rd ed., §6.2) -------------------------

// ln(e^-x x^a / Gamma(a)), the common prefactor of the series and the continued fraction.
double log_gamma_prefactor(double a, double x) { return -x + a * std::log(x) - std::lgamma(a); }

// P(a, x) by the series of Abramowitz & Stegun 6.5.29, for x < a + 1.
double gamma_p_series(double a, double x) {
  double term = 1.0 / a, sum = term, ap = a;
  for (int n = 0; n < 100000; ++n) {
    ap += 1.0;
    term *= x / ap;
    sum += term;
    if (std::abs(term) < std::abs(sum) * kMachineEpsilon) break;
  }
  return sum * std::exp(log_gamma_prefactor(a, x));
}

// Q(a, x) by the continued fraction of Abramowitz & Stegun 6.5.31 (modified Lentz), x >= a + 1.
double gamma_q_continued_fraction(double a, double x) {
  constexpr double kTiny = 1e-300;
  double b = x + 1.0 - a, c = 1.0 / kTiny, d = 1.0 / b, h = d;
  for (int i = 1; i < 100000; ++i) {
    const double an = -i * (i - a);
    b += 2.0;
    d = an * d + b;
    if (std::abs(d) < kTiny) d = kTiny;
    c = b + an / c;
    if (std::abs(c) < kTiny) c = kTiny;
    d = 1.0 / d;
    const double delta = d * c;
    h *= delta;
    if (std::abs(delta - 1.0) < kMachineEpsilon) break;
  }
  return std::exp(log_gamma_prefactor(a, x)) * h;
}

// {P(a, x), Q(a, x)}, each computed directly where it is the smaller one.
std::pair<double, double> regularized_gamma_pq(double a, double x) {
  if (!(a > 0.0) || std::isnan(x)) return {kNaN, kNaN};
  if (x <= 0.0) return {0.0, 1.0};
  if (std::isinf(x)) return {1.0, 0.0};
  if (x < a + 1.0) {
    const double p = gamma_p_series(a, x);
    return {p, 1.0 - p};
  }
  const double q = gamma_q_continued_fraction(a, x);
  return {1.0 - q, q};
}

// Continued fraction for I_x(a, b) (Numerical Recipes 3rd ed. §6.4, betacf).
double beta_continued_fraction(double a, double b, double x) {
  constexpr double kTiny = 1e-300;
  constexpr double kEps = 1e-16;
  const double qab = a + b, qap = a + 1.0, qam = a - 1.0;
  double c = 1.0;
  double d = 1.0 - qab * x / qap;
  if (std::fabs(d) < kTiny) d = kTiny;
  d = 1.0 / d;
  double h = d;
  for (int m = 1; m <= 10000; ++m) {
    const double m2 = 2.0 * m;
    double aa = m * (b - m) * x / ((qam + m2) * (a + m2));
    d = 1.0 + aa * d;
    if (std::fabs(d) < kTiny) d = kTiny;
    c = 1.0 + aa / c;
    if (std::fabs(c) < kTiny) c = kTiny;
    d = 1.0 / d;
    h *= d * c;
    aa = -(a + m) * (qab + m) * x / ((a + m2) * (qap + m2));
    d = 1.0 + aa * d;
    if (std::fabs(d) < kTiny) d = kTiny;
    c = 1.0 + aa / c;
    if (std::fabs(c) < kTiny) c = kTiny;
    d = 1.0 / d;
    const double del = d * c;
    h *= del;
    if (std::fabs(del - 1.0) < kEps) break;
  }
  return h;
}

}  // namespace

double normal_cdf(double z) { return 0.5 * std::erfc(-z / std::numbers::sqrt2); }

double normal_quantile(double p) {
  if (!(p > 0.0 && p < 1.0)) {
    if (p == 0.0) return -std::numeric_limits<double>::infinity();
    if (p == 1.0) return std::numeric_limits<double>::infinity();
    return kNaN;
  }
  // P. J. Acklam, "An algorithm for computing the inverse normal cumulative distribution
  // function" (2003), coefficients as published.
  static constexpr double a[] = {-3.969683028665376e+01, 2.209460984245205e+02,
                                 -2.759285104469687e+02, 1.383577518672690e+02,
                                 -3.066479806614716e+01, 2.506628277459239e+00};
  static constexpr double b[] = {-5.447609879822406e+01, 1.615858368580409e+02,
                                 -1.556989798598866e+02, 6.680131188771972e+01,
                                 -1.328068155288572e+01};
  static constexpr double c[] = {-7.784894002430293e-03, -3.223964580411365e-01,
                                 -2.400758277161838e+00, -2.549732539343734e+00,
                                 4.374664141464968e+00,  2.938163982698783e+00};
  static constexpr double d[] = {7.784695709041462e-03, 3.224671290700398e-01,
                                 2.445134137142996e+00, 3.754408661907416e+00};
  constexpr double p_low = 0.02425;
  double x;
  if (p < p_low) {
    const double q = std::sqrt(-2.0 * std::log(p));
    x = (((((c[0] * q + c[1]) * q + c[2]) * q + c[3]) * q + c[4]) * q + c[5]) /
        ((((d[0] * q + d[1]) * q + d[2]) * q + d[3]) * q + 1.0);
  } else if (p <= 1.0 - p_low) {
    const double q = p - 0.5;
    const double r = q * q;
    x = (((((a[0] * r + a[1]) * r + a[2]) * r + a[3]) * r + a[4]) * r + a[5]) * q /
        (((((b[0] * r + b[1]) * r + b[2]) * r + b[3]) * r + b[4]) * r + 1.0);
  } else {
    const double q = std::sqrt(-2.0 * std::log1p(-p));
    x = -(((((c[0] * q + c[1]) * q + c[2]) * q + c[3]) * q + c[4]) * q + c[5]) /
        ((((d[0] * q + d[1]) * q + d[2]) * q + d[3]) * q + 1.0);
  }
  // One Halley step on Φ(x) − p (Acklam's refinement).
  const double e = (p < 0.5 ? normal_cdf(x) - p : -(normal_cdf(-x) - (1.0 - p)));
  const double u = e * std::sqrt(2.0 * std::numbers::pi) * std::exp(0.5 * x * x);
  return x - u / (1.0 + 0.5 * x * u);
}

double incomplete_beta(double a, double b, double x) {
  if (!(a > 0.0 && b > 0.0) || !(x >= 0.0 && x <= 1.0)) return kNaN;
  if (x == 0.0) return 0.0;
  if (x == 1.0) return 1.0;
  const double log_front =
      std::lgamma(a + b) - std::lgamma(a) - std::lgamma(b) + a * std::log(x) + b * std::log1p(-x);
  const double front = std::exp(log_front);
  if (x < (a + 1.0) / (a + b + 2.0)) return front * beta_continued_fraction(a, b, x) / a;
  return 1.0 - front * beta_continued_fraction(b, a, 1.0 - x) / b;
}

double student_t_cdf(double t, double nu) {
  if (std::isnan(t) || !(nu > 0.0)) return kNaN;
  if (std::isinf(nu)) return normal_cdf(t);
  if (std::isinf(t)) return t > 0 ? 1.0 : 0.0;
  // Tail: I_{ν/(ν+t²)}(ν/2, 1/2)/2, computed with x = ν/(ν+t²) directly.
  const double x = nu / (nu + t * t);
  const double tail = 0.5 * incomplete_beta(0.5 * nu, 0.5, x);
  return t >= 0.0 ? 1.0 - tail : tail;
}

double student_t_quantile(double p, double nu) {
  if (!(p > 0.0 && p < 1.0) || !(nu > 0.0)) return kNaN;
  if (std::isinf(nu)) return normal_quantile(p);
  if (p == 0.5) return 0.0;
  if (p < 0.5) return -student_t_quantile(1.0 - p, nu);
  // Bracket above the normal quantile (t quantiles exceed it for p > 1/2).
  const double z = normal_quantile(p);
  return invert_cdf([nu](double t) { return student_t_cdf(t, nu); }, p, z, 2.0 * z + 1.0);
}

double invert_cdf(const std::function<double(double)>& cdf, double p, double lo, double hi) {
  if (!(hi > lo)) hi = lo + 1.0;
  double width = hi - lo;
  for (int i = 0; i < 2000 && cdf(lo) > p; ++i) {
    lo -= width;
    width *= 2.0;
  }
  width = hi - lo;
  for (int i = 0; i < 2000 && cdf(hi) < p; ++i) {
    hi += width;
    width *= 2.0;
  }
  for (int i = 0; i < 2000; ++i) {
    const double mid = 0.5 * (lo + hi);
    if (!(mid > lo && mid < hi)) break;
    if (cdf(mid) < p) {
      lo = mid;
    } else {
      hi = mid;
    }
  }
  return 0.5 * (lo + hi);
}

double f_distribution_upper_tail(double f, double d1, double d2) {
  if (!(d1 > 0.0) || !(d2 > 0.0) || std::isnan(f)) return kNaN;
  if (f <= 0.0) return 1.0;
  if (std::isinf(f)) return 0.0;
  return incomplete_beta(0.5 * d2, 0.5 * d1, d2 / (d2 + d1 * f));
}

double ks_p_value(double d, int n) {
  if (n <= 0 || std::isnan(d)) return kNaN;
  const double sn = std::sqrt(static_cast<double>(n));
  const double lambda = (sn + 0.12 + 0.11 / sn) * d;
  if (lambda < 0.2) return 1.0;
  double sum = 0.0, sign = 1.0;
  for (int j = 1; j <= 100; ++j) {
    const double term = sign * std::exp(-2.0 * j * j * lambda * lambda);
    sum += term;
    if (std::abs(term) < 1e-16 * std::abs(sum)) break;
    sign = -sign;
  }
  return std::clamp(2.0 * sum, 0.0, 1.0);
}

double regularized_gamma_p(double a, double x) { return regularized_gamma_pq(a, x).first; }
double regularized_gamma_q(double a, double x) { return regularized_gamma_pq(a, x).second; }

}  // namespace gearmc
