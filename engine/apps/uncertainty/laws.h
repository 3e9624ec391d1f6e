// The probability laws of the inputs of a measurement model (JCGM 101:2008, "Propagation of
// distributions using a Monte Carlo method", §6.4): their exact expectation and variance, CDF,
// quantile and a sampler on a TrialStream. A Law is a value type built by the make_* functions,
// which check the parameters and throw std::invalid_argument with the reason (the model reader
// turns it into an InputError at the law's place in the file). Units: those of the input.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "core/random_stream.h"

namespace gearmc::uncertainty {

enum class LawKind {
  kNormal,                // N(μ, σ²)                                JCGM 101 §6.4.7
  kUniform,               // R(a, b)                                 §6.4.2
  kTriangular,            // T(a, c, b), mode c (symmetric: c = (a+b)/2)   §6.4.5
  kArcsine,               // U(a, b)                                 §6.4.6
  kTrapezoidal,           // Tr(a, b, β), β = top/base width         §6.4.4
  kCurvilinearTrapezoid,  // CTr(a, b, d), limits inexact by ±d      §6.4.3
  kStudentT,              // t_ν(μ, s²)                              §6.4.9 (also `data:`)
  kExponential,           // Ex(1/mean)                              §6.4.10
  kGamma,                 // G(k, θ) from mean and sd                §6.4.11
  kConstant,              // a known value
};

// The law names of the model file, in the order of LawKind (`data` is extra: it makes a
// Student t, see make_from_data).
const std::vector<std::string>& law_names();
std::string_view law_name(LawKind kind);

class Law {
 public:
  LawKind kind() const { return kind_; }
  // Parameters as written (normal: μ, σ; uniform: a, b; triangular: a, c, b; arcsine: a, b;
  // trapezoidal: a, b, β; curvilinear: a, b, d; student_t: μ, s, ν; exponential: mean;
  // gamma: mean, sd; constant: value).
  const std::vector<double>& parameters() const { return p_; }

  double mean() const;
  // Exact variance; +inf for a Student t with ν <= 2.
  double variance() const;
  double sd() const;
  // The standard uncertainty and degrees of freedom the GUM (JCGM 100) uses for this input: the
  // standard deviation with ν = inf, except a Student t (and `data:`), whose scale s is the
  // Type A standard uncertainty with ν degrees of freedom (JCGM 101 §6.4.9 builds the t law
  // from exactly that pair).
  double gum_u() const;
  double gum_dof() const;

  double cdf(double x) const;
  double quantile(double p) const;  // p in (0, 1)
  // One draw from `s` (a law uses 1 to a few uniforms; gamma and Student t by rejection).
  double sample(TrialStream& s) const;

 private:
  friend Law make_law(LawKind kind, std::vector<double> parameters);
  LawKind kind_ = LawKind::kConstant;
  std::vector<double> p_;
  // Derived: gamma shape k and scale θ; Student t ν.
  double shape_ = 0.0, scale_ = 0.0;
};

// Checks the count and values of `parameters` for `kind` (triangular takes 2 — symmetric —
// or 3 values) and returns the law; throws std::invalid_argument saying what was expected.
Law make_law(LawKind kind, std::vector<double> parameters);
// Type A evaluation of repeated observations (JCGM 101 §6.4.9): t_{n−1}(x̄, s²/n) with s the
// sample standard deviation; needs n >= 2 values, not all equal.
Law make_from_data(const std::vector<double>& values);
// What the parameters of `name` are, for messages: "[mean, sd]".
std::string law_signature(std::string_view name);

// sample_standard_gamma (the gamma variate of the laws below) is in core/random_stream.h.

// Correlated inputs of any laws are drawn through a Gaussian copula: x_i = F_i⁻¹(Φ(z_i)) with
// (z_i) jointly normal, unit variances, correlation ρ_ij (for two normal laws x is μ + σz itself).
// The joint law is an assumption of ours (JCGM 101 §6.4.8 treats only the multivariate normal);
// ρ_ij is chosen so that the inputs have the correlation coefficient r(x_i, x_j) the model states,
// which is the one the GUM's law of propagation uses (JCGM 100 5.2.2).
//
// The correlation coefficient of F_a⁻¹(Φ(z_1)) and F_b⁻¹(Φ(z_2)) for normal (z_1, z_2) with
// correlation ρ: E[g_a(z_1) g_b(ρ z_1 + √(1 − ρ²) z_2)] by a 64 × 64-node Gauss–Hermite rule
// (Golub & Welsch, Math. Comp. 23, 1969), minus the product of the means, over the two standard
// deviations. Both laws need a finite variance and a spread.
double copula_input_correlation(const Law& a, const Law& b, double rho);
// The ρ in (−1, 1) that gives the inputs correlation r (bisection: the correlation rises with ρ);
// throws std::invalid_argument naming the correlations these two laws can have when r is not
// one of them.
double copula_correlation_for(const Law& a, const Law& b, double r);

}  // namespace gearmc::uncertainty
