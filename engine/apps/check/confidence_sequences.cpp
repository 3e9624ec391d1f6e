// Confidence sequences for means (see confidence_sequences.h); formulas cited there.
#include "engine/apps/check/confidence_sequences.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace gearmc {
namespace {

// Runs the bettor's capital for null value m; `below` = betting that the values fall below m
// (rejects mean ≥ m), else above (rejects mean ≤ m). True when log K reached log(1/α).
bool betting_rejects(std::span<const double> x, double m, double alpha, bool below) {
  if (!(m > 0.0 && m < 1.0) || !(alpha > 0.0 && alpha < 1.0)) {
    throw std::invalid_argument("betting test: need 0 < m < 1 and 0 < alpha < 1");
  }
  const double threshold = std::log(1.0 / alpha);
  const double cap = below ? kBettingCap / (1.0 - m) : kBettingCap / m;
  // Predictable plug-in (Waudby-Smith & Ramdas): μ̂_t = (1/2 + Σ x)/(t + 1),
  // σ̂²_t = (1/4 + Σ (x_i − μ̂_i)²)/(t + 1), λ_t = sqrt(2 log(1/α) / (σ̂²_{t−1} t log(1 + t))).
  double sum = 0.0, squares = 0.0, variance = 0.25;
  double log_capital = 0.0;
  for (std::size_t i = 0; i < x.size(); ++i) {
    const double t = static_cast<double>(i + 1);
    const double lambda =
        std::min(std::sqrt(2.0 * threshold / (variance * t * std::log(1.0 + t))), cap);
    const double gain = below ? -(x[i] - m) : (x[i] - m);
    log_capital += std::log1p(lambda * gain);
    if (log_capital >= threshold) return true;
    sum += x[i];
    const double mean = (0.5 + sum) / (t + 1.0);
    squares += (x[i] - mean) * (x[i] - mean);
    variance = (0.25 + squares) / (t + 1.0);
  }
  return false;
}

}  // namespace

bool betting_rejects_mean_at_least(std::span<const double> x, double m, double alpha) {
  return betting_rejects(x, m, alpha, true);
}

bool betting_rejects_mean_at_most(std::span<const double> x, double m, double alpha) {
  return betting_rejects(x, m, alpha, false);
}

MeanBounds betting_mean_bounds(std::span<const double> x, double alpha) {
  MeanBounds b;
  double sum = 0.0;
  for (double v : x) sum += v;
  b.estimate = x.empty() ? 0.5 : sum / static_cast<double>(x.size());
  constexpr double kTol = 1e-9;
  // upper: least m rejected by "mean ≥ m"; the set of rejected m is [upper, 1).
  b.upper = 1.0;
  if (betting_rejects_mean_at_least(x, 1.0 - kTol, alpha)) {
    double lo = kTol, hi = 1.0 - kTol;  // hi rejected
    if (betting_rejects_mean_at_least(x, lo, alpha)) {
      b.upper = 0.0;
    } else {
      while (hi - lo > kTol) {
        const double mid = 0.5 * (lo + hi);
        (betting_rejects_mean_at_least(x, mid, alpha) ? hi : lo) = mid;
      }
      b.upper = hi;
    }
  }
  b.lower = 0.0;
  if (betting_rejects_mean_at_most(x, kTol, alpha)) {
    double lo = kTol, hi = 1.0 - kTol;  // lo rejected
    if (betting_rejects_mean_at_most(x, hi, alpha)) {
      b.lower = 1.0;
    } else {
      while (hi - lo > kTol) {
        const double mid = 0.5 * (lo + hi);
        (betting_rejects_mean_at_most(x, mid, alpha) ? lo : hi) = mid;
      }
      b.lower = lo;
    }
  }
  return b;
}

double asymptotic_half_width(double sd, double t, double alpha, double t_opt) {
  const double l = -2.0 * std::log(alpha);
  const double rho2 = (l + std::log(l + 1.0)) / t_opt;
  return sd * std::sqrt(2.0 * (t * rho2 + 1.0) / (t * t * rho2) *
                        std::log(std::sqrt(t * rho2 + 1.0) / alpha));
}

MeanBounds asymptotic_mean_bounds(std::span<const double> x, double alpha, double t_opt) {
  if (x.size() < 2) throw std::invalid_argument("asymptotic bounds need at least 2 values");
  const double t = static_cast<double>(x.size());
  double sum = 0.0;
  for (double v : x) sum += v;
  const double mean = sum / t;
  double squares = 0.0;
  for (double v : x) squares += (v - mean) * (v - mean);
  const double sd = std::sqrt(squares / (t - 1.0));
  const double w = asymptotic_half_width(sd, t, alpha, t_opt);
  return {mean, mean - w, mean + w};
}

}  // namespace gearmc
