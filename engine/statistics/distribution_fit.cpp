// Binned maximum-likelihood fits of five two-parameter laws to a Histogram, with AIC ranking and
// binned goodness-of-fit figures (see distribution_fit.h for the method and its sources).
#include "engine/statistics/distribution_fit.h"
#include "core/constants.h"
#include "core/special_functions.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <numbers>
#include <utility>

namespace gearmc {
namespace {

// --- The binned data ---------------------------------------------------------------------------

struct OccupiedBin {
  std::size_t index;
  double count;
};

struct BinnedData {
  const Histogram* histogram;
  std::vector<OccupiedBin> occupied;
  double underflow, overflow, n;
};

BinnedData binned_data(const Histogram& h) {
  BinnedData data{&h,
                  {},
                  static_cast<double>(h.underflow()),
                  static_cast<double>(h.overflow()),
                  static_cast<double>(h.total())};
  for (std::size_t i = 0; i < h.bin_count(); ++i) {
    if (h.count(i) > 0) data.occupied.push_back({i, static_cast<double>(h.count(i))});
  }
  return data;
}

// ln P([lo, hi)) from the tails at the two edges; when the difference is lost to rounding, the
// midpoint rule (hi - lo) f(mid).
double log_interval_probability(const Distribution& d, double lo, double hi,
                                const DistributionTails& at_lo, const DistributionTails& at_hi) {
  double p, scale;
  if (at_hi.cdf <= 0.5) {
    p = at_hi.cdf - at_lo.cdf;
    scale = at_hi.cdf;
  } else {
    p = at_lo.survival - at_hi.survival;
    scale = at_lo.survival;
  }
  if (p > 1e-7 * scale && p > 1e-300) return std::log(p);
  return std::log(hi - lo) + d.log_pdf(0.5 * (lo + hi));
}

// The binned log-likelihood (file comment of distribution_fit.h); -inf when impossible.
double log_likelihood(const Distribution& d, const BinnedData& data) {
  const Histogram& h = *data.histogram;
  double ll = 0.0;
  if (data.underflow > 0) {
    const double f = d.tails(h.lo()).cdf;
    if (!(f > 0.0)) return -kInf;
    ll += data.underflow * std::log(f);
  }
  if (data.overflow > 0) {
    const double s = d.tails(h.hi()).survival;
    if (!(s > 0.0)) return -kInf;
    ll += data.overflow * std::log(s);
  }
  std::size_t cached_edge = static_cast<std::size_t>(-1);
  DistributionTails cached{};
  for (const OccupiedBin& bin : data.occupied) {
    const double lo = h.edge(bin.index), hi = h.edge(bin.index + 1);
    const DistributionTails at_lo = bin.index == cached_edge ? cached : d.tails(lo);
    const DistributionTails at_hi = d.tails(hi);
    cached_edge = bin.index + 1;
    cached = at_hi;
    ll += bin.count * log_interval_probability(d, lo, hi, at_lo, at_hi);
  }
  return std::isnan(ll) ? -kInf : ll;
}

// --- Nelder-Mead (Nelder & Mead 1965; coefficients and steps as in Lagarias et al. 1998) -------

using Point = std::array<double, 2>;

struct Minimum {
  Point x;
  double f;
  int evaluations;
};

Minimum nelder_mead(const std::function<double(const Point&)>& f, const Point& start, double step,
                    int max_evaluations, double x_tolerance) {
  std::array<Point, 3> v = {start, start, start};
  v[1][0] += step;
  v[2][1] += step;
  std::array<double, 3> fv{};
  int evaluations = 0;
  auto eval = [&](const Point& p) {
    ++evaluations;
    const double value = f(p);
    return std::isnan(value) ? kInf : value;
  };
  for (int i = 0; i < 3; ++i) fv[i] = eval(v[i]);
  auto along = [](const Point& from, const Point& to, double t) {
    return Point{from[0] + t * (to[0] - from[0]), from[1] + t * (to[1] - from[1])};
  };
  while (evaluations < max_evaluations) {
    // Order best (0) to worst (2); ties keep the earlier vertex first.
    std::array<int, 3> order = {0, 1, 2};
    std::stable_sort(order.begin(), order.end(), [&](int i, int j) { return fv[i] < fv[j]; });
    const std::array<Point, 3> vs = {v[order[0]], v[order[1]], v[order[2]]};
    const std::array<double, 3> fs = {fv[order[0]], fv[order[1]], fv[order[2]]};
    v = vs;
    fv = fs;
    double spread = 0.0;
    for (int i = 1; i < 3; ++i) {
      for (int k = 0; k < 2; ++k) spread = std::max(spread, std::abs(v[i][k] - v[0][k]));
    }
    if (spread <= x_tolerance) break;

    const Point centroid = along(v[0], v[1], 0.5);
    const Point reflected = along(centroid, v[2], -1.0);
    const double fr = eval(reflected);
    if (fr < fv[0]) {
      const Point expanded = along(centroid, v[2], -2.0);
      const double fe = eval(expanded);
      if (fe < fr) {
        v[2] = expanded;
        fv[2] = fe;
      } else {
        v[2] = reflected;
        fv[2] = fr;
      }
      continue;
    }
    if (fr < fv[1]) {
      v[2] = reflected;
      fv[2] = fr;
      continue;
    }
    if (fr < fv[2]) {  // outside contraction
      const Point contracted = along(centroid, reflected, 0.5);
      const double fc = eval(contracted);
      if (fc <= fr) {
        v[2] = contracted;
        fv[2] = fc;
        continue;
      }
    } else {  // inside contraction
      const Point contracted = along(centroid, v[2], 0.5);
      const double fc = eval(contracted);
      if (fc < fv[2]) {
        v[2] = contracted;
        fv[2] = fc;
        continue;
      }
    }
    for (int i = 1; i < 3; ++i) {  // shrink towards the best vertex
      v[i] = along(v[0], v[i], 0.5);
      fv[i] = eval(v[i]);
    }
  }
  const int best = static_cast<int>(std::min_element(fv.begin(), fv.end()) - fv.begin());
  return {v[best], fv[best], evaluations};
}

// --- Parametrisation and starting values --------------------------------------------------------

// The optimiser works on dimensionless, unconstrained coordinates u:
//   location laws (normal, gumbel_max): u = (a / s0, ln(b / s0)), s0 = the data's spread;
//   lognormal: u = (a, ln b); gamma, weibull: u = (ln a, ln(b / s0)).
struct Parametrisation {
  DistributionLaw law;
  double s0;

  Distribution to_distribution(const Point& u) const {
    switch (law) {
      case DistributionLaw::kNormal:
      case DistributionLaw::kGumbelMax:
        return {law, u[0] * s0, std::exp(u[1]) * s0};
      case DistributionLaw::kLognormal:
        return {law, u[0], std::exp(u[1])};
      case DistributionLaw::kGamma:
      case DistributionLaw::kWeibull:
        return {law, std::exp(u[0]), std::exp(u[1]) * s0};
    }
    return {};
  }
  Point to_point(const Distribution& d) const {
    switch (law) {
      case DistributionLaw::kNormal:
      case DistributionLaw::kGumbelMax:
        return {d.a / s0, std::log(d.b / s0)};
      case DistributionLaw::kLognormal:
        return {d.a, std::log(d.b)};
      case DistributionLaw::kGamma:
      case DistributionLaw::kWeibull:
        return {std::log(d.a), std::log(d.b / s0)};
    }
    return {};
  }
};

struct BinMoments {
  double mean, stddev;          // of the bin centres, variance with Sheppard's correction
  double log_mean, log_stddev;  // of ln(centre) over centres > 0
};

BinMoments bin_moments(const BinnedData& data) {
  const Histogram& h = *data.histogram;
  double n = 0, sum = 0, sum2 = 0, nl = 0, suml = 0, suml2 = 0;
  for (const OccupiedBin& bin : data.occupied) {
    const double x = h.centre(bin.index);
    n += bin.count;
    sum += bin.count * x;
    sum2 += bin.count * x * x;
    if (x > 0) {
      const double l = std::log(x);
      nl += bin.count;
      suml += bin.count * l;
      suml2 += bin.count * l * l;
    }
  }
  BinMoments m{};
  const double w = h.width();
  m.mean = sum / n;
  // Sheppard's correction (Kendall & Stuart vol. 1, §3.18): var = var(centres) - w^2 / 12,
  // kept at least w^2 / 12 so that a single occupied bin still has a spread.
  const double var = std::max(sum2 / n - m.mean * m.mean - w * w / 12.0, w * w / 12.0);
  m.stddev = std::sqrt(var);
  m.log_mean = nl > 0 ? suml / nl : kNaN;
  m.log_stddev = nl > 0 ? std::sqrt(std::max(suml2 / nl - m.log_mean * m.log_mean, 1e-12)) : kNaN;
  return m;
}

// Moment estimates (Johnson, Kotz & Balakrishnan, as cited in the header); Weibull's shape by
// Justus et al. (1978), k = (s / m)^-1.086.
Distribution starting_values(DistributionLaw law, const BinMoments& m) {
  switch (law) {
    case DistributionLaw::kNormal:
      return {law, m.mean, m.stddev};
    case DistributionLaw::kLognormal:
      return {law, m.log_mean, m.log_stddev};
    case DistributionLaw::kGamma:
      return {law, m.mean * m.mean / (m.stddev * m.stddev), m.stddev * m.stddev / m.mean};
    case DistributionLaw::kWeibull: {
      const double k = std::clamp(std::pow(m.stddev / m.mean, -1.086), 0.05, 50.0);
      return {law, k, m.mean / std::tgamma(1.0 + 1.0 / k)};
    }
    case DistributionLaw::kGumbelMax: {
      const double beta = m.stddev * std::sqrt(6.0) / std::numbers::pi;
      return {law, m.mean - kEulerGamma * beta, beta};
    }
  }
  return {};
}

// --- Goodness of fit ----------------------------------------------------------------------------

double ks_distance(const Distribution& d, const BinnedData& data) {
  const Histogram& h = *data.histogram;
  double below = data.underflow, worst = 0.0;
  for (std::size_t j = 0; j <= h.bin_count(); ++j) {
    // Empirical P(X < edge_j) against the fitted F(edge_j).
    worst = std::max(worst, std::abs(below / data.n - d.tails(h.edge(j)).cdf));
    if (j < h.bin_count()) below += static_cast<double>(h.count(j));
  }
  return worst;
}

struct ChiSquare {
  double value;
  int dof;
  double p_value;
};

ChiSquare chi_square(const Distribution& d, const BinnedData& data, const FitOptions& options) {
  const Histogram& h = *data.histogram;
  const std::size_t group = std::max<std::size_t>(
      1, static_cast<std::size_t>(std::llround(options.chi_square_cell_width_um / h.width())));
  struct Cell {
    double observed, expected;
  };
  std::vector<Cell> raw;
  DistributionTails previous = d.tails(h.lo());
  raw.push_back({data.underflow, data.n * previous.cdf});
  for (std::size_t start = 0; start < h.bin_count(); start += group) {
    const std::size_t end = std::min(start + group, h.bin_count());
    double observed = 0;
    for (std::size_t i = start; i < end; ++i) observed += static_cast<double>(h.count(i));
    const DistributionTails next = d.tails(h.edge(end));
    const double p = next.cdf <= 0.5 ? next.cdf - previous.cdf : previous.survival - next.survival;
    raw.push_back({observed, data.n * std::max(p, 0.0)});
    previous = next;
  }
  raw.push_back({data.overflow, data.n * previous.survival});
  // Pool left to right until each cell expects >= min_expected; a short remainder joins the
  // last cell.
  std::vector<Cell> cells;
  Cell pending{0, 0};
  for (const Cell& c : raw) {
    pending.observed += c.observed;
    pending.expected += c.expected;
    if (pending.expected >= options.min_expected) {
      cells.push_back(pending);
      pending = {0, 0};
    }
  }
  if (pending.observed > 0 || pending.expected > 0) {
    if (cells.empty()) {
      cells.push_back(pending);
    } else {
      cells.back().observed += pending.observed;
      cells.back().expected += pending.expected;
    }
  }
  double value = 0.0;
  for (const Cell& c : cells) {
    const double diff = c.observed - c.expected;
    value += c.expected > 0 ? diff * diff / c.expected : (c.observed > 0 ? kInf : 0.0);
  }
  const int dof = static_cast<int>(cells.size()) - 1 - 2;
  const double p = dof >= 1 ? regularized_gamma_q(0.5 * dof, 0.5 * value) : kNaN;
  return {value, dof, p};
}

DistributionFit not_applicable(const Distribution& d, std::string note) {
  DistributionFit fit;
  fit.distribution = d;
  fit.applicable = false;
  fit.note = std::move(note);
  fit.log_likelihood = -kInf;
  fit.aic = kInf;
  fit.ks_distance = kNaN;
  fit.chi_square = kNaN;
  fit.chi_square_dof = 0;
  fit.chi_square_p_value = kNaN;
  return fit;
}

}  // namespace

DistributionFit fit_distribution(const Histogram& histogram, DistributionLaw law,
                                 const FitOptions& options) {
  const BinnedData data = binned_data(histogram);
  const int occupied_cells =
      static_cast<int>(data.occupied.size()) + (data.underflow > 0) + (data.overflow > 0);
  if (occupied_cells < 2 || data.occupied.empty()) {
    return not_applicable({law, kNaN, kNaN},
                          "fewer than two occupied bins: no spread to fit a two-parameter law to");
  }
  // A value of exactly 0 is possible under the binned model (its bin has positive probability);
  // a negative one is not.
  if (positive_support(law) && histogram.min() < 0.0) {
    return not_applicable({law, kNaN, kNaN}, "the data has values < 0, outside the law's support");
  }
  const BinMoments moments = bin_moments(data);
  const Distribution start = starting_values(law, moments);
  const Parametrisation param{law, moments.stddev};
  auto objective = [&](const Point& u) { return -log_likelihood(param.to_distribution(u), data); };
  if (!std::isfinite(objective(param.to_point(start)))) {
    return not_applicable(start, "the likelihood is zero at the moment estimates");
  }
  // Two passes: the second restarts with a fresh simplex at the first optimum, the usual
  // safeguard against Nelder-Mead's premature collapse (Press et al. §10.5).
  Minimum first = nelder_mead(objective, param.to_point(start), 0.1, 4000, 1e-9);
  Minimum second = nelder_mead(objective, first.x, 0.02, 4000, 1e-10);
  const Minimum& best = second.f <= first.f ? second : first;

  DistributionFit fit;
  fit.distribution = param.to_distribution(best.x);
  fit.applicable = true;
  fit.log_likelihood = -best.f;
  fit.aic = 2.0 * 2.0 - 2.0 * fit.log_likelihood;
  fit.ks_distance = ks_distance(fit.distribution, data);
  const ChiSquare chi2 = chi_square(fit.distribution, data, options);
  fit.chi_square = chi2.value;
  fit.chi_square_dof = chi2.dof;
  fit.chi_square_p_value = chi2.p_value;
  fit.evaluations = first.evaluations + second.evaluations;
  return fit;
}

double binned_log_likelihood(const Histogram& histogram, const Distribution& distribution) {
  return log_likelihood(distribution, binned_data(histogram));
}

std::vector<DistributionFit> fit_distributions(const Histogram& histogram,
                                               const FitOptions& options) {
  std::vector<DistributionFit> fits;
  for (DistributionLaw law : kAllDistributionLaws) {
    fits.push_back(fit_distribution(histogram, law, options));
  }
  std::stable_sort(fits.begin(), fits.end(),
                   [](const DistributionFit& x, const DistributionFit& y) {
                     if (x.applicable != y.applicable) return x.applicable;
                     return x.aic < y.aic;
                   });
  return fits;
}

}  // namespace gearmc
