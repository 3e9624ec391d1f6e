// The Gaussian regression filter of profile and helix traces (see trace_filter.h).
#include "engine/evaluation/trace_filter.h"

#include <cmath>
#include <numbers>

namespace gearmc {

std::vector<double> gaussian_regression_filter(std::span<const double> x, std::span<const double> d,
                                               double cutoff_mm) {
  const std::size_t n = x.size();
  std::vector<double> out(d.begin(), d.end());
  if (n < 3 || !(cutoff_mm > 0.0)) return out;
  const double width = kGaussianFilterAlpha * cutoff_mm;
  // exp(−π t²) < 1e-12 beyond t = 2.97: the neighbours within 2.97 α λc = 1.40 λc count.
  const double reach = 2.97 * width;
  std::vector<double> w(n);
  for (std::size_t j = 0; j < n; ++j) {
    w[j] = 0.5 * ((j > 0 ? x[j] - x[j - 1] : 0.0) + (j + 1 < n ? x[j + 1] - x[j] : 0.0));
  }
  std::size_t lo = 0;
  for (std::size_t i = 0; i < n; ++i) {
    while (x[i] - x[lo] > reach) ++lo;
    // Weighted least squares of d = a + b (x − x_i): the normal equations' sums.
    double S0 = 0, S1 = 0, S2 = 0, T0 = 0, T1 = 0;
    for (std::size_t j = lo; j < n && x[j] - x[i] <= reach; ++j) {
      const double u = x[j] - x[i], t = u / width;
      const double g = w[j] * std::exp(-std::numbers::pi * t * t);
      S0 += g;
      S1 += g * u;
      S2 += g * u * u;
      T0 += g * d[j];
      T1 += g * u * d[j];
    }
    const double det = S0 * S2 - S1 * S1;
    // One neighbour with weight (the samples spaced far beyond λc): the sample itself.
    out[i] = det > 1e-14 * S0 * S2 ? (S2 * T0 - S1 * T1) / det : d[i];
  }
  return out;
}

double gaussian_filter_transmission(double wavelength_mm, double cutoff_mm) {
  const double r = kGaussianFilterAlpha * cutoff_mm / wavelength_mm;
  return std::exp(-std::numbers::pi * r * r);
}

}  // namespace gearmc
