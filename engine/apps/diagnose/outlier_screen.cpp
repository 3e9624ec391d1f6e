// Gross outliers among the readings (see outlier_screen.h).
#include "engine/apps/diagnose/outlier_screen.h"

#include <algorithm>
#include <cmath>

#include "engine/statistics/distribution_fit.h"

namespace gearmc {
namespace {

// Standardised prediction error of point `at` of `scan` (indices of the points still in it,
// ordered by i); 0 when the scan has fewer than 3 points.
double prediction_z(const std::vector<int>& scan, std::size_t at, const Residuals& residuals,
                    double sigma) {
  const auto r = [&](std::size_t k) { return residuals.points[scan[k]].residual_um; };
  const std::size_t n = scan.size();
  if (n < 3) return 0.0;
  if (at == 0) return (r(0) - (2.0 * r(1) - r(2))) / (sigma * std::sqrt(6.0));
  if (at == n - 1) return (r(n - 1) - (2.0 * r(n - 2) - r(n - 3))) / (sigma * std::sqrt(6.0));
  return (r(at) - 0.5 * (r(at - 1) + r(at + 1))) / (sigma * std::sqrt(1.5));
}

}  // namespace

OutlierScreen screen_outliers(const Residuals& residuals, double family_false_alarm) {
  OutlierScreen out;
  out.family_false_alarm = family_false_alarm;
  const int n = static_cast<int>(residuals.points.size());
  std::vector<std::vector<int>> scans;
  {
    const ProfileScans all = profile_scans(residuals.points);
    for (std::size_t s = 0; s < all.count(); ++s) {
      if (all.start[s + 1] - all.start[s] < 3) continue;
      scans.emplace_back(all.points.begin() + static_cast<std::ptrdiff_t>(all.start[s]),
                         all.points.begin() + static_cast<std::ptrdiff_t>(all.start[s + 1]));
      out.screened += static_cast<int>(scans.back().size());
    }
  }
  std::vector<double> r;
  r.reserve(residuals.points.size());
  for (const ResidualPoint& p : residuals.points) r.push_back(p.residual_um);
  const double robust = robust_noise_sigma(residuals.points, r);
  out.sigma_um = std::isfinite(robust) ? std::max(robust, kNumericalFloorUm) : kNumericalFloorUm;
  if (n == 0 || scans.empty()) return out;
  const Distribution standard_normal{DistributionLaw::kNormal, 0.0, 1.0};
  out.threshold_z = standard_normal.quantile(1.0 - family_false_alarm / (2.0 * n));

  // The largest |z| of each scan, kept up to date as readings are excluded, and which reading of
  // the scan to exclude when it exceeds z*: the one whose removal leaves the smallest Σz² of the
  // rest (an outlier spoils its neighbours' predictions too; at a scan's end its neighbour's |z|
  // is as large as its own, and only the deletion tells them apart).
  std::vector<std::pair<double, std::size_t>> worst(scans.size());
  const auto rest_sum_z2 = [&](const std::vector<int>& scan, std::size_t skip) {
    std::vector<int> rest = scan;
    rest.erase(rest.begin() + static_cast<std::ptrdiff_t>(skip));
    double sum = 0.0;
    for (std::size_t at = 0; at < rest.size(); ++at) {
      const double z = prediction_z(rest, at, residuals, out.sigma_um);
      sum += z * z;
    }
    return sum;
  };
  const auto rescan = [&](std::size_t s) {
    double largest = 0.0;
    for (std::size_t at = 0; at < scans[s].size(); ++at) {
      largest = std::max(largest, std::abs(prediction_z(scans[s], at, residuals, out.sigma_um)));
    }
    std::size_t choice = 0;
    if (largest > out.threshold_z) {
      double best = rest_sum_z2(scans[s], 0);
      for (std::size_t at = 1; at < scans[s].size(); ++at) {
        const double sum = rest_sum_z2(scans[s], at);
        if (sum < best) best = sum, choice = at;
      }
    }
    worst[s] = {largest, choice};
  };
  for (std::size_t s = 0; s < scans.size(); ++s) rescan(s);
  const int cap = static_cast<int>(std::floor(kMaxOutlierFraction * n));
  std::vector<ExcludedReading> excluded;
  while (true) {
    std::size_t s = 0;
    for (std::size_t t = 1; t < scans.size(); ++t) {
      if (worst[t].first > worst[s].first) s = t;
    }
    if (!(worst[s].first > out.threshold_z)) break;
    if (static_cast<int>(excluded.size()) >= cap) {
      out.not_applied = "more than " + std::to_string(cap) + " readings (" +
                        std::to_string(static_cast<int>(100 * kMaxOutlierFraction)) +
                        " %) stand out of their profile scans by more than z* = " +
                        std::to_string(out.threshold_z) +
                        ": that is not a few bad readings but a disagreement of model and "
                        "readings, so none is excluded";
      excluded.clear();
      break;
    }
    const std::size_t at = worst[s].second;
    const int k = scans[s][at];
    const ResidualPoint& p = residuals.points[k];
    ExcludedReading e;
    e.row = k;
    e.line = p.line;
    e.key() = p.key();
    e.residual_um = p.residual_um;
    e.z_score = prediction_z(scans[s], at, residuals, out.sigma_um);
    excluded.push_back(e);
    scans[s].erase(scans[s].begin() + static_cast<std::ptrdiff_t>(at));
    rescan(s);
  }
  std::sort(excluded.begin(), excluded.end(),
            [](const ExcludedReading& a, const ExcludedReading& b) { return a.row < b.row; });
  out.excluded = std::move(excluded);
  return out;
}

Residuals without_excluded(Residuals residuals, const OutlierScreen& screen) {
  if (screen.excluded.empty()) return residuals;
  std::vector<bool> drop(residuals.points.size(), false);
  for (const ExcludedReading& e : screen.excluded) drop[static_cast<std::size_t>(e.row)] = true;
  // Compacted in place (no second copy of the points).
  std::size_t kept = 0;
  residuals.nominal_fallback = 0;
  for (std::size_t k = 0; k < residuals.points.size(); ++k) {
    if (drop[k]) continue;
    if (kept != k) residuals.points[kept] = residuals.points[k];
    if (!residuals.points[kept].model_contact) ++residuals.nominal_fallback;
    ++kept;
  }
  residuals.points.resize(kept);
  residuals.points.shrink_to_fit();
  return residuals;
}

}  // namespace gearmc
