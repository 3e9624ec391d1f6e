// The five two-parameter laws of distribution.h: densities, tails, moments, quantiles (the
// gamma law's tails from core/special_functions.h).
#include "engine/statistics/distribution.h"

#include "core/constants.h"
#include "core/special_functions.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <utility>

namespace gearmc {
namespace {

constexpr double kEps = std::numeric_limits<double>::epsilon();
constexpr double kLogSqrt2Pi = 0.91893853320467274178;  // ln sqrt(2 pi)

DistributionTails normal_tails(double z) {
  return {0.5 * std::erfc(-z / std::numbers::sqrt2), 0.5 * std::erfc(z / std::numbers::sqrt2)};
}

}  // namespace

std::string_view law_name(DistributionLaw law) {
  switch (law) {
    case DistributionLaw::kNormal:
      return "normal";
    case DistributionLaw::kLognormal:
      return "lognormal";
    case DistributionLaw::kGamma:
      return "gamma";
    case DistributionLaw::kWeibull:
      return "weibull";
    case DistributionLaw::kGumbelMax:
      return "gumbel_max";
  }
  return "?";
}

bool positive_support(DistributionLaw law) {
  return law == DistributionLaw::kLognormal || law == DistributionLaw::kGamma ||
         law == DistributionLaw::kWeibull;
}

std::array<std::string_view, 2> Distribution::parameter_names() const {
  switch (law) {
    case DistributionLaw::kNormal:
      return {"mu", "sigma"};
    case DistributionLaw::kLognormal:
      return {"mu_log", "sigma_log"};
    case DistributionLaw::kGamma:
    case DistributionLaw::kWeibull:
      return {"shape", "scale"};
    case DistributionLaw::kGumbelMax:
      return {"location", "scale"};
  }
  return {"?", "?"};
}

double Distribution::log_pdf(double x) const {
  switch (law) {
    case DistributionLaw::kNormal: {
      const double z = (x - a) / b;
      return -0.5 * z * z - std::log(b) - kLogSqrt2Pi;
    }
    case DistributionLaw::kLognormal: {
      if (x <= 0.0) return -kInf;
      const double lx = std::log(x), z = (lx - a) / b;
      return -0.5 * z * z - lx - std::log(b) - kLogSqrt2Pi;
    }
    case DistributionLaw::kGamma:
      if (x < 0.0) return -kInf;
      if (x == 0.0) return a < 1.0 ? kInf : (a == 1.0 ? -std::log(b) : -kInf);
      return (a - 1.0) * std::log(x) - x / b - std::lgamma(a) - a * std::log(b);
    case DistributionLaw::kWeibull:
      if (x < 0.0) return -kInf;
      if (x == 0.0) return a < 1.0 ? kInf : (a == 1.0 ? -std::log(b) : -kInf);
      return std::log(a / b) + (a - 1.0) * std::log(x / b) - std::pow(x / b, a);
    case DistributionLaw::kGumbelMax: {
      const double z = (x - a) / b;
      return -std::log(b) - z - std::exp(-z);
    }
  }
  return kNaN;
}

double Distribution::pdf(double x) const { return std::exp(log_pdf(x)); }

// The normal and lognormal tails from erfc, the gamma law's from the incomplete gamma function,
// the Weibull and Gumbel laws' in closed form with expm1 for the smaller tail.
DistributionTails Distribution::tails(double x) const {
  const Distribution& d = *this;
  switch (d.law) {
    case DistributionLaw::kNormal:
      return normal_tails((x - d.a) / d.b);
    case DistributionLaw::kLognormal:
      if (x <= 0.0) return {0.0, 1.0};
      return normal_tails((std::log(x) - d.a) / d.b);
    case DistributionLaw::kGamma: {
      if (x <= 0.0) return {0.0, 1.0};
      const double p = regularized_gamma_p(d.a, x / d.b), q = regularized_gamma_q(d.a, x / d.b);
      return {p, q};
    }
    case DistributionLaw::kWeibull: {
      if (x <= 0.0) return {0.0, 1.0};
      const double t = std::pow(x / d.b, d.a);
      return {-std::expm1(-t), std::exp(-t)};
    }
    case DistributionLaw::kGumbelMax: {
      const double e = std::exp(-(x - d.a) / d.b);
      return {std::exp(-e), -std::expm1(-e)};
    }
  }
  return {kNaN, kNaN};
}

double Distribution::cdf(double x) const { return tails(x).cdf; }
double Distribution::survival(double x) const { return tails(x).survival; }

double Distribution::mean() const {
  switch (law) {
    case DistributionLaw::kNormal:
      return a;
    case DistributionLaw::kLognormal:
      return std::exp(a + 0.5 * b * b);
    case DistributionLaw::kGamma:
      return a * b;
    case DistributionLaw::kWeibull:
      return b * std::tgamma(1.0 + 1.0 / a);
    case DistributionLaw::kGumbelMax:
      return a + kEulerGamma * b;
  }
  return kNaN;
}

double Distribution::stddev() const {
  switch (law) {
    case DistributionLaw::kNormal:
      return b;
    case DistributionLaw::kLognormal:
      return std::sqrt(std::expm1(b * b)) * std::exp(a + 0.5 * b * b);
    case DistributionLaw::kGamma:
      return std::sqrt(a) * b;
    case DistributionLaw::kWeibull: {
      const double g1 = std::tgamma(1.0 + 1.0 / a), g2 = std::tgamma(1.0 + 2.0 / a);
      return b * std::sqrt(std::max(g2 - g1 * g1, 0.0));
    }
    case DistributionLaw::kGumbelMax:
      return b * std::numbers::pi / std::sqrt(6.0);
  }
  return kNaN;
}

double Distribution::quantile(double p) const {
  if (!(p > 0.0 && p < 1.0)) throw std::invalid_argument("Distribution::quantile: need 0<p<1");
  // Compare in the tail where the probability is resolved: cdf below the median, survival above.
  auto below = [&](double x) {  // true when x is left of the quantile
    const DistributionTails t = tails(x);
    return p <= 0.5 ? t.cdf < p : t.survival > 1.0 - p;
  };
  const double centre = mean(), spread = std::max(stddev(), 1e-300);
  double lo = centre - spread, hi = centre + spread, step = spread;
  if (positive_support(law)) lo = std::max(lo, 0.0);
  while (!below(lo) && lo > -1e300) {
    step *= 2.0;
    lo = positive_support(law) ? lo * 0.5 : lo - step;
    if (positive_support(law) && lo < 1e-300) break;
  }
  step = spread;
  while (below(hi) && hi < 1e300) {
    step *= 2.0;
    hi += step;
  }
  for (int i = 0; i < 400 && hi - lo > 1e-14 * std::max(std::abs(lo), std::abs(hi)); ++i) {
    const double mid = 0.5 * (lo + hi);
    if (mid <= lo || mid >= hi) break;
    (below(mid) ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

}  // namespace gearmc
