// The GUM uncertainty framework (JCGM 100:2008, "Guide to the expression of uncertainty in
// measurement"): the estimate y = f(x) at the input expectations, sensitivity coefficients by
// central differences, the law of propagation of uncertainty with correlations (5.2.2), on
// request the higher-order terms of 5.1.2 (note), the Welch–Satterthwaite effective degrees of
// freedom (G.4.1), the coverage factor from the Student t distribution (G.3, G.4) and the
// expanded uncertainty U = k u.
#pragma once

#include <string>
#include <vector>

#include "engine/apps/uncertainty/model.h"
#include "engine/apps/uncertainty/model_function.h"

namespace gearmc::uncertainty {

// The step of the central difference for input i: h_i = 1e-3 u(x_i) (u = 0, a constant:
// 1e-6 max(1, |x_i|)), at least kMinRelativeStep |x_i| (a step below the resolution of x_i in
// double would give x_i ± h_i = x_i: an input of mean 1e20 and u 1 once got c_i = 0), adjusted
// so that x_i ± h_i are exactly x_i ± h_i in double. Truncation error of the derivative about
// h²|f'''|/6, i.e. 1.7e-7 u²|f'''|, far below what u(y) can show; a step widened beyond 1e-3 u
// is stated in GumResult::warnings.
inline constexpr double kSensitivityStepFraction = 1e-3;
inline constexpr double kMinRelativeStep = 1.4901161193847656e-08;  // 2^-26 = √ε of a double
inline constexpr const char* kSensitivityMethod =
    "central differences, step h_i = 1e-3 u(x_i) (JCGM 100 5.1.3; error about h^2 |f'''| / 6)";
// The higher-order terms use steps h_i = 1e-2 u(x_i) (second and third difference quotients;
// their rounding error grows as eps |f| / h³, so the step is larger than for c_i).
inline constexpr const char* kSecondOrderMethod =
    "JCGM 100 5.1.2 note: sum_ij [ (d2f/dxi dxj)^2 / 2 + df/dxi d3f/dxi dxj^2 ] u_i^2 u_j^2, "
    "derivatives by central differences with steps h_i = 1e-2 u(x_i), inputs taken as uncorrelated";

struct GumOutput {
  std::string name;
  double estimate = 0.0;
  double u = 0.0;                      // combined standard uncertainty u_c(y)
  double u_first_order = 0.0;          // from the first-order terms only
  double second_order_variance = 0.0;  // the 5.1.2 terms (0 unless requested)
  double nu_eff = 0.0;                 // Welch–Satterthwaite; +inf when every input has ν = inf
  bool first_order_vanishes = false;  // every c_i u_i = 0: u from the 5.1.2 terms, ν_eff undefined
  double k = 0.0;                     // t_{(1+p)/2}(ν) with ν = floor(ν_eff) (G.4.1 note 1)
  double U = 0.0;
  double lo = 0.0, hi = 0.0;          // y ∓ U
  std::vector<double> sensitivities;  // c_i = ∂f/∂x_i, per input
  std::vector<double> contributions;  // |c_i| u(x_i)
};

struct GumResult {
  std::vector<double> x, u;   // input estimates and standard uncertainties
  std::vector<double> steps;  // the central differences' steps h_i
  std::vector<GumOutput> outputs;
  bool second_order = false;
  std::vector<std::string> warnings;  // steps widened beyond 1e-3 u(x_i)
};

// Evaluates every output of `model` at coverage probability model.settings.coverage_probability.
// InputError (at the output's place) when an output, a sensitivity or u is not a finite number
// at the input estimates: the model has no GUM linearisation there (a pole, a log of 0, an
// overflow), and a table of nan would say nothing.
GumResult evaluate_gum(const UncertaintyModel& model);

// Welch–Satterthwaite: u_c⁴ / Σ (c_i u_i)⁴ / ν_i (JCGM 100 G.2b); terms with ν_i = inf or
// c_i u_i = 0 add nothing; +inf when none is left.
double welch_satterthwaite(double u_c, const std::vector<double>& contributions,
                           const std::vector<double>& dof);
// The coverage factor for `p` and ν_eff: the normal quantile for ν = inf, else the Student t
// quantile at ν = max(1, floor(ν_eff)) (normal above 1e7).
double coverage_factor(double p, double nu_eff);

// Central-difference partial derivatives of output j at x (steps as above, `steps` per input).
std::vector<std::vector<double>> sensitivities(ModelFunction& f, const std::vector<double>& x,
                                               const std::vector<double>& steps);

}  // namespace gearmc::uncertainty
