// The five two-parameter laws gearmc fits to its error values (distribution_fit.h) and states
// uncertainties with: normal, lognormal, gamma, Weibull and Gumbel (largest extreme value), each
// with its density, distribution and survival functions computed so that neither tail loses its
// accuracy, its moments and quantiles; and the regularised incomplete gamma function that the
// gamma law and chi-square p-values need. Units: x and every location/scale parameter in µm;
// shapes and the lognormal's log-parameters (of x / 1 µm) are dimensionless.
#pragma once

#include <array>
#include <string_view>

namespace gearmc {

enum class DistributionLaw { kNormal, kLognormal, kGamma, kWeibull, kGumbelMax };

inline constexpr std::array<DistributionLaw, 5> kAllDistributionLaws = {
    DistributionLaw::kNormal, DistributionLaw::kLognormal, DistributionLaw::kGamma,
    DistributionLaw::kWeibull, DistributionLaw::kGumbelMax};

// "normal", "lognormal", "gamma", "weibull", "gumbel_max".
std::string_view law_name(DistributionLaw law);

// P(X <= x) and P(X > x) of one law at one x.
struct DistributionTails {
  double cdf, survival;
};

// One member of a law, with its two parameters (a, b):
//   normal      a = mean mu (µm),            b = standard deviation sigma (µm)
//   lognormal   a = mu of ln(x / 1 µm),      b = sigma of ln(x / 1 µm)
//   gamma       a = shape k,                 b = scale theta (µm)     f ~ x^(k-1) e^(-x/theta)
//   weibull     a = shape k,                 b = scale lambda (µm)    F = 1 - e^(-(x/lambda)^k)
//   gumbel_max  a = location mu (µm),        b = scale beta (µm)      F = exp(-e^(-(x-mu)/beta))
// Formulas: Johnson, Kotz & Balakrishnan, "Continuous Univariate Distributions" (1994-95),
// chapters 13 (normal), 14 (lognormal), 17 (gamma), 21 (Weibull), 22 (extreme value).
struct Distribution {
  DistributionLaw law = DistributionLaw::kNormal;
  double a = 0.0, b = 1.0;

  // Names of a and b as above: {"mu", "sigma"}, {"mu_log", "sigma_log"}, {"shape", "scale"},
  // {"shape", "scale"}, {"location", "scale"}.
  std::array<std::string_view, 2> parameter_names() const;
  double pdf(double x_um) const;       // density, 1/µm
  double log_pdf(double x_um) const;   // ln pdf, -inf outside the support
  double cdf(double x_um) const;       // P(X <= x)
  double survival(double x_um) const;  // P(X > x), accurate in the upper tail
  // The x (µm) with cdf(x) = p, 0 < p < 1, by bisection to a relative 1e-14.
  double quantile(double p) const;
  double mean() const;    // µm
  double stddev() const;  // µm
  // cdf and survival together, the smaller of the two computed directly (the binned likelihood
  // takes P of a bin from the tail it lies in).
  DistributionTails tails(double x_um) const;
};

// True for the laws defined on x > 0 only (lognormal, gamma, Weibull).
bool positive_support(DistributionLaw law);

}  // namespace gearmc
