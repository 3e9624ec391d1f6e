// Confidence sequences for the mean of i.i.d. values: bounds that stay valid however often they
// are looked at, so `gearmc check` may look after every batch of gears and stop as soon as a
// claim is decided without inflating its error rate.
//
// - Bounded values in [0, 1] (a gear's fraction of values beyond a limit): the betting
//   confidence sequence of Waudby-Smith & Ramdas, "Estimating means of bounded random variables
//   by betting", J. R. Stat. Soc. B 86(1) (2024), arXiv:2010.09686: a bettor's capital K_t(m) is a
//   non-negative supermartingale when the mean is m (or beyond it on the null's side), so by
//   Ville's inequality P(sup_t K_t(m) ≥ 1/α) ≤ α. Distribution-free, exact for every t.
// - Unbounded values (a gear's mean): the asymptotic confidence sequence of Waudby-Smith, Arnold,
//   Wu, Howard & Ramdas, "Time-uniform central limit theory and asymptotic confidence
//   sequences", Ann. Statist. 52(6) (2024), arXiv:2103.06476 (their Gaussian-mixture
//   asymptotic confidence sequence, the sample standard deviation in place of σ): valid as the
//   number of values grows, for values with finite variance.
// Every function is pure; the values are in the order they were drawn (gear order).
#pragma once

#include <span>

namespace gearmc {

// The betting fraction cap c of the hedged capital process (Waudby-Smith & Ramdas use
// c ∈ [1/2, 3/4]): λ_t ≤ c/m resp. c/(1 − m).
inline constexpr double kBettingCap = 0.75;

// True when the values x_1 … x_t (each in [0, 1]) reject "mean ≥ m" at level α: the capital of
// the bettor who bets on x below m, K_s = Π_{i≤s} (1 − λ_i (x_i − m)), reached 1/α at some
// s ≤ t. λ_i is Waudby-Smith & Ramdas's predictable plug-in bet (one-sided: log(1/α) in
// place of log(2/α)), capped at c/(1 − m). Requires 0 < m < 1, 0 < α < 1.
bool betting_rejects_mean_at_least(std::span<const double> x, double m, double alpha);
// The mirror image: rejects "mean ≤ m" (capital Π (1 + λ_i (x_i − m)), λ_i ≤ c/m).
bool betting_rejects_mean_at_most(std::span<const double> x, double m, double alpha);

struct MeanBounds {
  double estimate = 0.0;  // the sample mean
  double lower = 0.0;     // one-sided (1 − α) lower confidence bound
  double upper = 0.0;     // one-sided (1 − α) upper confidence bound
};

// The betting bounds on the mean of values in [0, 1]: upper = the least m that
// betting_rejects_mean_at_least rejects, lower = the largest m betting_rejects_mean_at_most
// rejects (0 and 1 when none), found by bisection to 1e-9. Bisection assumes the rejected m
// form an interval: true for bets that do not depend on m (each factor is monotone in m); the
// plug-in bets' cap depends on m, so here it is an assumption (the verdicts never rest on it:
// they test the claim's own m directly).
MeanBounds betting_mean_bounds(std::span<const double> x, double alpha);

// The asymptotic confidence sequence for the mean of x (any finite values, finite variance),
// tuned to be tightest near t_opt values: mean ± sd · sqrt(2(tρ² + 1)/(t²ρ²) ·
// log(sqrt(tρ² + 1)/α)), ρ² = (−2 log α + log(−2 log α + 1))/t_opt (Waudby-Smith et al.
// 2024, the Gaussian mixture and its tuning). Two-sided at α, so each side errs with probability ≤
// α. Needs t ≥ 2.
MeanBounds asymptotic_mean_bounds(std::span<const double> x, double alpha, double t_opt = 1000);

// The same half-width for a mean of t values with sample standard deviation sd.
double asymptotic_half_width(double sd, double t, double alpha, double t_opt = 1000);

}  // namespace gearmc
