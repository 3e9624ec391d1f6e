// Conformity decisions and coverage intervals (see conformity.h).
#include "engine/statistics/conformity.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>

namespace gearmc {

double conformance_probability(double y, double u, std::optional<double> lower,
                               std::optional<double> upper) {
  const auto below = [&](double limit) {  // P(Y <= limit), Y ~ N(y, u²)
    if (!(u > 0.0)) return y <= limit ? 1.0 : 0.0;
    return 0.5 * std::erfc(-(limit - y) / (u * std::numbers::sqrt2));
  };
  const double p_upper = upper ? below(*upper) : 1.0;
  const double p_lower = lower ? below(*lower) : 0.0;
  return std::max(0.0, p_upper - p_lower);
}

std::uint64_t coverage_count(std::uint64_t M, double p) {
  const double pM = p * static_cast<double>(M);
  const double rounded = std::round(pM);
  if (std::abs(pM - rounded) < 1e-9 * std::max(1.0, pM)) {
    return static_cast<std::uint64_t>(rounded);
  }
  return static_cast<std::uint64_t>(std::floor(pM + 0.5));
}

namespace {
// q of coverage_count when the M values can hold an interval of it (q < M), else nullopt.
std::optional<std::uint64_t> interval_count(std::uint64_t M, double p) {
  if (M == 0) return std::nullopt;
  const std::uint64_t q = coverage_count(M, p);
  if (q >= M) return std::nullopt;
  return q;
}
}  // namespace

std::optional<CoverageInterval> shortest_coverage_interval(std::span<const double> sorted,
                                                           double p) {
  const std::uint64_t M = sorted.size();
  const std::optional<std::uint64_t> counted = interval_count(M, p);
  if (!counted) return std::nullopt;
  const std::uint64_t q = *counted;
  std::uint64_t best = 0;
  double width = sorted[q] - sorted[0];
  for (std::uint64_t r = 1; r + q < M; ++r) {
    const double w = sorted[r + q] - sorted[r];
    if (w < width) {
      width = w;
      best = r;
    }
  }
  return CoverageInterval{sorted[best], sorted[best + q]};
}

std::optional<CoverageInterval> symmetric_coverage_interval(std::span<const double> sorted,
                                                            double p) {
  const std::uint64_t M = sorted.size();
  const std::optional<std::uint64_t> counted = interval_count(M, p);
  if (!counted) return std::nullopt;
  const std::uint64_t q = *counted;
  // 1-based; r + q ≤ (M + q + 1)/2 ≤ M as q < M.
  std::uint64_t r = (M - q) % 2 == 0 ? (M - q) / 2 : (M - q + 1) / 2;
  if (r < 1) r = 1;
  return CoverageInterval{sorted[r - 1], sorted[r + q - 1]};
}

double empirical_conformance_probability(std::span<const double> sorted_errors, double y,
                                         std::optional<double> lower, std::optional<double> upper) {
  if (sorted_errors.empty()) return std::numeric_limits<double>::quiet_NaN();
  // lower ≤ y − e ≤ upper  ⇔  y − upper ≤ e ≤ y − lower.
  const auto from = upper ? std::lower_bound(sorted_errors.begin(), sorted_errors.end(), y - *upper)
                          : sorted_errors.begin();
  const auto to = lower ? std::upper_bound(sorted_errors.begin(), sorted_errors.end(), y - *lower)
                        : sorted_errors.end();
  const auto inside = to > from ? to - from : 0;
  return static_cast<double>(inside) / static_cast<double>(sorted_errors.size());
}

ToleranceLimits acceptance_limits(const ToleranceLimits& tolerance, DecisionRule rule,
                                  double guard_band) {
  return acceptance_limits(tolerance, rule, guard_band, guard_band);
}

ToleranceLimits acceptance_limits(const ToleranceLimits& tolerance, DecisionRule rule,
                                  double lower_guard_band, double upper_guard_band) {
  if (rule == DecisionRule::kSimple) return tolerance;
  ToleranceLimits a = tolerance;
  if (a.lower) *a.lower += lower_guard_band;
  if (a.upper) *a.upper -= upper_guard_band;
  return a;
}

bool within(const ToleranceLimits& limits, double value) {
  if (limits.lower && value < *limits.lower) return false;
  if (limits.upper && value > *limits.upper) return false;
  return true;
}

double DecisionRates::false_accept_rate() const {
  return items ? static_cast<double>(false_accepts) / static_cast<double>(items) : 0.0;
}
double DecisionRates::false_reject_rate() const {
  return items ? static_cast<double>(false_rejects) / static_cast<double>(items) : 0.0;
}

DecisionRates decision_rates(std::span<const double> true_values,
                             std::span<const double> measured_values,
                             const ToleranceLimits& tolerance, const ToleranceLimits& acceptance) {
  if (true_values.size() != measured_values.size()) {
    throw std::invalid_argument("decision_rates: as many true as measured values are needed");
  }
  DecisionRates r;
  for (std::size_t i = 0; i < true_values.size(); ++i) {
    const bool conforms = within(tolerance, true_values[i]);
    const bool accepted = within(acceptance, measured_values[i]);
    ++r.items;
    r.accepted += accepted ? 1 : 0;
    r.nonconforming += conforms ? 0 : 1;
    r.false_accepts += accepted && !conforms ? 1 : 0;
    r.false_rejects += !accepted && conforms ? 1 : 0;
  }
  return r;
}

}  // namespace gearmc
