// The residuals arranged along the report's axes and the report's number formatting (see
// diagnosis_report_data.h).
#include "engine/apps/diagnose/diagnosis_report_data.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <sstream>

#include "gears/involute_gear.h"

namespace gearmc::diagnose_report {
namespace {
Bins binned(const std::vector<long>& key, const std::vector<double>& x,
            const std::vector<double>& before, const std::vector<double>& after) {
  struct Sum {
    double x = 0, b = 0, a = 0;
    int n = 0;
  };
  std::map<long, Sum> sums;
  for (std::size_t k = 0; k < key.size(); ++k) {
    Sum& s = sums[key[k]];
    s.x += x[k];
    s.b += before[k];
    s.a += after[k];
    ++s.n;
  }
  Bins out;
  for (const auto& [unused, s] : sums) {
    out.x.push_back(s.x / s.n);
    out.before.push_back(s.b / s.n);
    out.after.push_back(s.a / s.n);
    out.count.push_back(s.n);
  }
  return out;
}

AxisStructure axis_structure(const std::string& axis, const Bins& b, double sigma) {
  AxisStructure s;
  s.axis = axis;
  const int bins = static_cast<int>(b.count.size());
  double n = 0.0, total = 0.0;
  for (int k = 0; k < bins; ++k) {
    n += b.count[k];
    total += b.count[k] * b.before[k];
  }
  if (bins < 2 || n <= 0.0 || sigma <= 0.0) return s;
  const double mean = total / n;
  double ss = 0.0;
  for (int k = 0; k < bins; ++k) ss += b.count[k] * (b.before[k] - mean) * (b.before[k] - mean);
  s.rms_um = std::sqrt(ss / n);
  s.noise_rms_um = sigma * std::sqrt((bins - 1) / n);
  s.ratio = ss / ((bins - 1) * sigma * sigma);
  return s;
}

}  // namespace

std::string held_out_split_text(const std::string& split) {
  if (split == "alternating_teeth") return "alternate measured teeth";
  if (split == "flanks") return "L ↔ R flanks";
  if (split == "alternating_sections") return "alternate face sections";
  if (split == "alternating_profile_points") return "alternate profile points";
  if (split == "nothing_fitted") return "nothing fitted: the RMS before";
  return "no split possible";
}

std::string fixed(double v, int decimals) {
  if (!std::isfinite(v)) return "–";
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, "%.*f", decimals, v);
  std::string s = buffer;
  if (s.find_first_not_of("-0.") == std::string::npos) s = s.substr(s[0] == '-' ? 1 : 0);
  return s;
}

// A value with its standard error at a precision that follows the error (2 significant digits
// of the error, at most 4 decimals, at least 1).
std::string with_error(double value, double error) {
  if (!std::isfinite(value)) return "–";
  int decimals = 3;
  if (std::isfinite(error) && error > 0.0) {
    decimals = std::clamp(1 - static_cast<int>(std::floor(std::log10(error))), 1, 4);
  }
  std::string s = fixed(value, decimals);
  if (std::isfinite(error)) s += " ± " + fixed(error, decimals);
  return s;
}

std::string general(double v) {
  if (!std::isfinite(v)) return "–";
  std::ostringstream s;
  s.precision(3);
  s << v;
  return s.str();
}

// A null-calibrated p-value: the smallest possible value 1/(K + 1) is shown as "p ≤ …".
std::string p_text(double p, int replicates) {
  if (!std::isfinite(p)) return "p –";
  if (replicates > 0 && p <= 1.0 / (replicates + 1) + 1e-12) {
    std::ostringstream bound;
    bound.precision(1);
    bound << 1.0 / (replicates + 1);
    return "p ≤ " + bound.str();
  }
  if (p < 1e-4) return "p < 0.0001";
  return "p = " + general(p);
}

ReportData report_data(const DiagnosisReportInput& in) {
  const Diagnosis& d = in.diagnosis;
  const std::vector<ResidualPoint>& pts = in.residuals.points;
  ReportData r;
  r.n = static_cast<int>(pts.size());
  r.sigma = d.noise.sigma_um;
  r.before = d.residual_before_um;
  r.after = d.residual_after_um;
  if (static_cast<int>(r.before.size()) != r.n) r.before.assign(r.n, 0.0);
  if (static_cast<int>(r.after.size()) != r.n) r.after = r.before;
  const InvoluteGear gear(in.model.gear);
  const double base_radius = gear.base_diameter_mm() / 2.0;
  std::vector<long> k_az, k_order(r.n), k_i, k_j;
  for (int k = 0; k < r.n; ++k) {
    const ResidualPoint& p = pts[k];
    r.fitted_part.push_back(r.before[k] - r.after[k]);
    double deg = p.context.azimuth_rad * 180.0 / kPi;
    deg = std::fmod(deg, 360.0);
    if (deg < 0.0) deg += 360.0;
    r.azimuth_deg.push_back(deg);
    k_az.push_back(static_cast<long>(deg / 5.0));
    r.order.push_back(p.order);
    const double radius = std::hypot(p.context.p.x(), p.context.p.y());
    r.roll_length.push_back(std::sqrt(std::max(0.0, radius * radius - base_radius * base_radius)));
    r.z.push_back(p.context.p.z());
    k_i.push_back(p.i);
    k_j.push_back(p.j);
    r.mean_before += r.before[k] / std::max(1, r.n);
  }
  // Measurement order: up to 60 groups of equal size by rank of the order column.
  std::vector<int> rank(r.n);
  for (int k = 0; k < r.n; ++k) rank[k] = k;
  std::stable_sort(rank.begin(), rank.end(),
                   [&](int a, int b) { return pts[a].order < pts[b].order; });
  const long groups = std::min<long>(60, std::max(1, r.n));
  double first = 0.0, last = 0.0;
  int n_first = 0, n_last = 0;
  for (int q = 0; q < r.n; ++q) {
    k_order[rank[q]] = static_cast<long>(q) * groups / std::max(1, r.n);
    if (q < r.n / 10) first += r.before[rank[q]], ++n_first;
    if (q >= r.n - r.n / 10) last += r.before[rank[q]], ++n_last;
  }
  r.first_tenth = n_first ? first / n_first : 0.0;
  r.last_tenth = n_last ? last / n_last : 0.0;
  r.azimuth = binned(k_az, r.azimuth_deg, r.before, r.after);
  r.by_order = binned(k_order, r.order, r.before, r.after);
  r.roll = binned(k_i, r.roll_length, r.before, r.after);
  r.face = binned(k_j, r.z, r.before, r.after);
  for (int s = 0; s < 2; ++s) {
    std::vector<long> key;
    std::vector<double> x, b, a;
    for (int k = 0; k < r.n; ++k) {
      if ((pts[k].side == FlankSide::kRight) != (s == 1)) continue;
      key.push_back(pts[k].tooth);
      x.push_back(pts[k].tooth);
      b.push_back(r.before[k]);
      a.push_back(r.after[k]);
    }
    r.tooth[s] = binned(key, x, b, a);
  }
  // Tooth structure: both sides' bins together.
  Bins teeth = r.tooth[0];
  for (std::size_t k = 0; k < r.tooth[1].x.size(); ++k) {
    teeth.x.push_back(r.tooth[1].x[k]);
    teeth.before.push_back(r.tooth[1].before[k]);
    teeth.after.push_back(r.tooth[1].after[k]);
    teeth.count.push_back(r.tooth[1].count[k]);
  }
  r.axes = {axis_structure("approach azimuth", r.azimuth, r.sigma),
            axis_structure("measurement order", r.by_order, r.sigma),
            axis_structure("tooth and flank side", teeth, r.sigma),
            axis_structure("roll length (profile position)", r.roll, r.sigma),
            axis_structure("face position z", r.face, r.sigma)};
  std::stable_sort(
      r.axes.begin(), r.axes.end(),
      [](const AxisStructure& a, const AxisStructure& b) { return a.ratio > b.ratio; });
  return r;
}

}  // namespace gearmc::diagnose_report
