// Conformity decisions with measurement uncertainty (ISO 14253-1:2017, JCGM 106:2012) and the
// shortest coverage interval of a sample (JCGM 101:2008 §7.7.2): the pure algebra shared by the
// Monte-Carlo run's gear parameters and `gearmc uncertainty`. Values in the caller's unit.
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <vector>

namespace gearmc {

// JCGM 106:2012 §7.6: the probability that a measurand with the Gaussian law N(y, u²) lies
// within [lower, upper] (an absent limit is infinite), p_c = Φ((T_U − y)/u) − Φ((T_L − y)/u).
// u = 0: 1 or 0 by where y is.
double conformance_probability(double y, double u, std::optional<double> lower,
                               std::optional<double> upper);

// A coverage interval [lo, hi].
struct CoverageInterval {
  double lo = 0.0, hi = 0.0;
};
// q of JCGM 101 §7.7.2 for M values: pM when that is an integer, else floor(pM + 1/2).
std::uint64_t coverage_count(std::uint64_t M, double p);
// The shortest [y_(r), y_(r+q)] of the ascending `sorted` values (JCGM 101 §7.7.2, an O(M)
// scan, the first r on ties). Needs q < M (for p = 0.95 at least 21 values): nullopt otherwise.
std::optional<CoverageInterval> shortest_coverage_interval(std::span<const double> sorted,
                                                           double p);

// The probabilistically symmetric [y_(r), y_(r+q)] of the ascending `sorted` values (JCGM 101
// §7.7.1): r = (M − q)/2 when that is an integer, else floor((M − q + 1)/2), at least 1 — as many
// values below the interval as above it, up to one. Needs q < M: nullopt otherwise.
std::optional<CoverageInterval> symmetric_coverage_interval(std::span<const double> sorted,
                                                            double p);

// The fraction of the ascending `sorted` errors e = measured − true with lower ≤ y − e ≤ upper:
// the probability that the true value of an item measured as y conforms, from the error's own
// distribution (JCGM 106:2012 §7.5, the conformance probability of any law; an absent limit is
// infinite). NaN without values.
double empirical_conformance_probability(std::span<const double> sorted_errors, double y,
                                         std::optional<double> lower, std::optional<double> upper);

// The decision rules of ISO 14253-1:2017 for a tolerance interval [lower, upper]:
//  kSimple       accept when the measured value lies within the tolerance (shared risk);
//  kGuardBanded  accept when it lies within the tolerance narrowed by the guard band g at each
//                given limit (ISO 14253-1 §5.2 "conformance zone", g = U): stringent acceptance.
enum class DecisionRule { kSimple, kGuardBanded };

struct ToleranceLimits {
  std::optional<double> lower, upper;  // at least one is given
};

// The acceptance zone of `rule` for the limits and guard band g >= 0 (ignored by kSimple).
ToleranceLimits acceptance_limits(const ToleranceLimits& tolerance, DecisionRule rule,
                                  double guard_band);
// The same with a guard band of its own at each limit (a skewed error law: the band at the
// upper limit is how far the error reaches below zero, at the lower limit above it).
ToleranceLimits acceptance_limits(const ToleranceLimits& tolerance, DecisionRule rule,
                                  double lower_guard_band, double upper_guard_band);
bool within(const ToleranceLimits& limits, double value);

// The outcome of a decision rule over a population of (true, measured) pairs:
// false_accept = items accepted although the true value is out of tolerance (consumer's risk),
// false_reject = items rejected although the true value conforms (producer's risk), both as
// fractions of all items (ISO 14253-1 / JCGM 106 §9 "global risks", estimated by counting).
struct DecisionRates {
  std::uint64_t items = 0, accepted = 0, false_accepts = 0, false_rejects = 0, nonconforming = 0;
  double false_accept_rate() const;
  double false_reject_rate() const;
};
DecisionRates decision_rates(std::span<const double> true_values,
                             std::span<const double> measured_values,
                             const ToleranceLimits& tolerance, const ToleranceLimits& acceptance);

}  // namespace gearmc
