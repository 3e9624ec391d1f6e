// The coordinate-grid stage: a Rayleigh test of the coordinates' phases on grids of k · 0.01 µm
// (see coordinate_grid.h).
#include "engine/apps/diagnose/coordinate_grid.h"

#include <algorithm>
#include <cmath>
#include <complex>
#include <numbers>
#include <sstream>
#include <tuple>
#include <utility>

#include "engine/effects/scale_resolution.h"

namespace gearmc {
namespace {

constexpr double kUnitUm = 0.01;    // the finest step tried, µm
constexpr int kMaxMultiple = 1000;  // the coarsest: 10 µm
constexpr double kThreshold = 0.5;
constexpr int kMinPoints = 100;

// R(k · 0.01 µm) of `u` (coordinates in units of 0.01 µm).
double resultant(const std::vector<double>& u, int k) { return grid_resultant(u, k); }

// The largest multiple k with R ≥ threshold on `u` and R < threshold on the nominal `nominal`;
// 0 when there is none (or not even k = 1).
int largest_grid(const std::vector<double>& u, const std::vector<double>& nominal, double* r) {
  if (resultant(u, 1) < kThreshold) return 0;
  for (int k = kMaxMultiple; k >= 1; --k) {
    const double value = resultant(u, k);
    if (value >= kThreshold && resultant(nominal, k) < kThreshold) {
      *r = value;
      return k;
    }
  }
  return 0;
}

}  // namespace

double grid_resultant(const std::vector<double>& values, double step) {
  std::complex<double> sum = 0.0;
  for (double v : values) {
    const double turns = v / step;
    const double phase = 2.0 * std::numbers::pi * (turns - std::floor(turns));
    sum += std::complex<double>(std::cos(phase), std::sin(phase));
  }
  return std::abs(sum) / static_cast<double>(values.size());
}

CoordinateGrid detect_coordinate_grid(const Readings& readings, const std::vector<bool>& excluded,
                                      const std::array<double, 3>& model_steps_um,
                                      double noise_floor_um, double min_effect_rms_fraction) {
  CoordinateGrid out;
  std::vector<const ReadingRow*> rows;
  for (std::size_t k = 0; k < readings.rows.size(); ++k) {
    if (k < excluded.size() && excluded[k]) continue;
    rows.push_back(&readings.rows[k]);
  }
  if (static_cast<int>(rows.size()) < kMinPoints) {
    out.skipped_because = "fewer than " + std::to_string(kMinPoints) + " readings";
    return out;
  }
  out.ran = true;
  const double n = static_cast<double>(rows.size());
  const double radius = readings.stylus_radius_mm;
  for (int which = 0; which < 2 && !out.found(); ++which) {  // centres, then compensated points
    for (int a = 0; a < 3; ++a) {
      std::vector<double> u, nominal;
      double largest_normal = 0.0;
      for (const ReadingRow* row : rows) {
        const double coordinate = which == 0 ? row->c[a] : row->c[a] - radius * row->n[a];
        u.push_back(coordinate * 1e3 / kUnitUm);
        nominal.push_back(row->p[a] * 1e3 / kUnitUm);
        largest_normal = std::max(largest_normal, std::abs(row->n[a]));
      }
      CoordinateGridAxis& axis = out.axes[static_cast<std::size_t>(a)];
      axis = CoordinateGridAxis{};
      axis.observable = largest_normal > 1e-6;
      // An axis no normal has a component along changes no reading: not searched (its few
      // distinct values, e.g. five sections, would also show chance grids).
      const int k = axis.observable ? largest_grid(u, nominal, &axis.resultant) : 0;
      axis.step_um = k / (1.0 / kUnitUm);  // k / 100: exact for k = 50, 100, …
    }
    out.points = which == 0 ? "recorded_centres" : "compensated_points";
  }
  if (!out.found()) {
    out.points.clear();
    out.note = "the coordinates lie on no grid of 0.01 µm or coarser";
    return out;
  }
  double variance = 0.0, weakest = 1.0;
  for (const ReadingRow* row : rows) {
    for (int a = 0; a < 3; ++a) {
      const CoordinateGridAxis& axis = out.axes[static_cast<std::size_t>(a)];
      if (axis.observable) variance += row->n[a] * row->n[a] * axis.step_um * axis.step_um / 12.0;
    }
  }
  for (const CoordinateGridAxis& axis : out.axes) {
    if (axis.observable && axis.step_um > 0.0) weakest = std::min(weakest, axis.resultant);
  }
  out.rms_um = std::sqrt(variance / n);
  out.false_alarm = std::min(1.0, 2.0 * 3.0 * kMaxMultiple * std::exp(-n * weakest * weakest));
  out.in_model = true;
  for (int a = 0; a < 3; ++a) {
    const CoordinateGridAxis& axis = out.axes[static_cast<std::size_t>(a)];
    if (axis.observable && std::abs(axis.step_um - model_steps_um[a]) > 1e-9) {
      out.in_model = false;
    }
  }
  const bool practical = out.rms_um >= min_effect_rms_fraction * noise_floor_um;
  out.named = !out.in_model && practical;
  std::ostringstream text;
  text << "the " << (out.points == "recorded_centres" ? "recorded centres" : "compensated points")
       << " lie on a grid of";
  const char* names = "xyz";
  for (int a = 0; a < 3; ++a) {
    const CoordinateGridAxis& axis = out.axes[static_cast<std::size_t>(a)];
    if (axis.observable && axis.step_um > 0.0)
      text << " " << names[a] << " " << axis.step_um << " µm";
  }
  text << " (its spread along the normal " << out.rms_um << " µm RMS)";
  if (out.in_model) {
    text << ", as the model's scale_resolution has it";
  } else if (!practical) {
    text << ", below the practical size (" << min_effect_rms_fraction
         << " of the noise floor): not named";
  }
  out.note = text.str();
  return out;
}

namespace {

// KS distance of `r` / σ against N(0, 1) and the RMS of `r`.
std::pair<double, double> ks_and_rms(std::vector<double> r, double sigma_um) {
  std::sort(r.begin(), r.end());
  const double n = static_cast<double>(r.size());
  double d = 0.0, ss = 0.0;
  for (std::size_t i = 0; i < r.size(); ++i) {
    const double f = 0.5 * std::erfc(-r[i] / (sigma_um * std::numbers::sqrt2));
    d = std::max({d, (static_cast<double>(i) + 1.0) / n - f, f - static_cast<double>(i) / n});
    ss += r[i] * r[i];
  }
  return {d, std::sqrt(ss / n)};
}

}  // namespace

LatchedModelCheck latched_model_check(const std::vector<ResidualPoint>& points,
                                      const std::array<double, 3>& steps_um, double sigma_before_um,
                                      double sigma_um, int replicates, std::uint64_t seed) {
  LatchedModelCheck out;
  if (points.empty() || !(sigma_um > 0.0) || replicates < 1) return out;
  out.ran = true;
  out.replicates = replicates;
  std::vector<double> r;
  for (const ResidualPoint& p : points) r.push_back(p.residual_um);
  std::tie(out.ks, out.rms_um) = ks_and_rms(r, sigma_um);
  int ks_above = 0, rms_above = 0, rms_below = 0;
  for (int k = 0; k < replicates; ++k) {
    // Stream sub-index 3000: the selection uses 0–2, the gap null 1000, the white test 2000.
    RandomStream rng(seed, static_cast<std::uint32_t>(k), StreamPurpose::kDiagnoseNull, 3000);
    std::vector<double> sim;
    sim.reserve(points.size());
    for (const ResidualPoint& p : points) {
      const PointContext& q = p.context;
      const Eigen::Vector3d c0 = q.p + (q.stylus_radius_mm + 1e-3 * p.predicted_um) * q.n;
      Eigen::Vector3d c;
      for (int a = 0; a < 3; ++a) {
        c[a] = latch_to_grid_mm(c0[a] + 1e-3 * sigma_before_um * rng.normal(), steps_um[a]);
      }
      sim.push_back(reading_um(q, c) - p.predicted_um);
    }
    const auto [ks, rms] = ks_and_rms(std::move(sim), sigma_um);
    ks_above += ks >= out.ks;
    rms_above += rms >= out.rms_um;
    rms_below += rms <= out.rms_um;
  }
  const double k1 = replicates + 1.0;
  const double p_ks = (1.0 + ks_above) / k1;
  const double p_rms = std::min(1.0, 2.0 * (1.0 + std::min(rms_above, rms_below)) / k1);
  out.p = std::min(1.0, 2.0 * std::min(p_ks, p_rms));
  return out;
}

}  // namespace gearmc
