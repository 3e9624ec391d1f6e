// Bounded histogram bins and a bounded scatter sample for the diagnosis report (see
// report_plot_data.h).
#include "engine/apps/diagnose/report_plot_data.h"

#include <algorithm>
#include <cmath>

#include "core/random_stream.h"
#include "engine/statistics/histogram.h"

namespace gearmc {
namespace {

// Stream sub-index of the report's scatter sample (the diagnosis uses 0…3002).
constexpr std::uint32_t kPlotSampleSubIndex = 4000;

// The smallest 1-2-5 value ≥ x (x > 0, finite).
double nice_width(double x) {
  const double decade = std::pow(10.0, std::floor(std::log10(x)));
  for (double m : {1.0, 2.0, 5.0, 10.0}) {
    if (m * decade >= x) return m * decade;
  }
  return 10.0 * decade;
}

}  // namespace

DisplayBins display_bins(std::span<const double> values, double sigma_um, int max_bins,
                         double tail_fraction) {
  max_bins = std::max(max_bins, 1);
  std::vector<double> v;
  v.reserve(values.size());
  for (double x : values) {
    if (std::isfinite(x)) v.push_back(x);
  }
  double lo = 0.0, hi = 0.0;  // 0 is always shown (a residual's expected value)
  if (!v.empty()) {
    const auto n = static_cast<std::uint64_t>(v.size());
    auto order_statistic = [&](double p) {
      const auto k = static_cast<std::ptrdiff_t>(quantile_rank(p, n) - 1);
      std::nth_element(v.begin(), v.begin() + k, v.end());
      return v[static_cast<std::size_t>(k)];
    };
    const double q_lo = order_statistic(tail_fraction), q_hi = order_statistic(1.0 - tail_fraction);
    const auto [min, max] = std::minmax_element(v.begin(), v.end());
    // Half the central span again on each side (a Gaussian's ±2.6σ become ±5.2σ, so only gross
    // outliers fall outside), but not beyond the data.
    const double margin = 0.5 * (q_hi - q_lo);
    lo = std::min(lo, std::max(q_lo - margin, *min));
    hi = std::max(hi, std::min(q_hi + margin, *max));
  }
  if (std::isfinite(sigma_um) && sigma_um > 0.0) {
    lo = std::min(lo, -3.0 * sigma_um);
    hi = std::max(hi, 3.0 * sigma_um);
  }
  double raw = (hi - lo) / max_bins;
  if (!(raw > 0.0) || !std::isfinite(raw)) raw = std::max(1e-6, 1e-6 * std::abs(hi));
  DisplayBins out;
  out.width_um = nice_width(raw);
  out.lo_um = std::floor(lo / out.width_um) * out.width_um;
  const double span = std::ceil((hi - out.lo_um) / out.width_um) + 1.0;
  out.bins = static_cast<std::size_t>(std::clamp(span, 1.0, max_bins + 2.0));
  return out;
}

std::vector<std::size_t> plotted_sample(std::span<const double> values, std::size_t max_marks,
                                        std::uint64_t seed) {
  const std::size_t n = values.size();
  std::vector<std::size_t> out;
  if (n <= max_marks) {
    for (std::size_t k = 0; k < n; ++k) {
      if (std::isfinite(values[k])) out.push_back(k);
    }
    return out;
  }
  max_marks = std::max<std::size_t>(max_marks, 2);
  std::size_t lo = n, hi = n;
  for (std::size_t k = 0; k < n; ++k) {
    if (!std::isfinite(values[k])) continue;
    if (lo == n || values[k] < values[lo]) lo = k;
    if (hi == n || values[k] > values[hi]) hi = k;
  }
  if (lo == n) return out;
  // Algorithm S over the indices other than the two extremes.
  const std::size_t others = n - (lo == hi ? 1 : 2);
  std::size_t wanted = max_marks - (lo == hi ? 1 : 2), seen = 0;
  RandomStream rng(seed, 0, StreamPurpose::kDiagnoseNull, kPlotSampleSubIndex);
  for (std::size_t k = 0; k < n; ++k) {
    if (k == lo || k == hi) {
      out.push_back(k);
      continue;
    }
    if (wanted > 0 &&
        static_cast<double>(others - seen) * (1.0 - rng.uniform()) < static_cast<double>(wanted)) {
      if (std::isfinite(values[k])) out.push_back(k);
      --wanted;
    }
    ++seen;
  }
  return out;
}

}  // namespace gearmc
