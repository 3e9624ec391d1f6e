// ISO 1328-1 flank parameters from deviation traces (see gear_parameters.h).
#include "engine/evaluation/gear_parameters.h"

#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <limits>

#include "gears/deviations.h"

namespace gearmc {

const std::array<GearParameter, kGearParameterCount>& all_gear_parameters() {
  static const std::array<GearParameter, kGearParameterCount> all = {
      GearParameter::kFalpha, GearParameter::kfHalpha, GearParameter::kffalpha,
      GearParameter::kFbeta,  GearParameter::kfHbeta,  GearParameter::kffbeta,
      GearParameter::kfpt,    GearParameter::kFp,      GearParameter::kFr,
      GearParameter::kEsn,    GearParameter::kEWk,     GearParameter::kEMdK};
  return all;
}

const std::string& parameter_symbol(GearParameter p) {
  static const std::array<std::string, kGearParameterCount> symbols = {
      "F_alpha", "f_Halpha", "f_falpha", "F_beta", "f_Hbeta", "f_fbeta",
      "f_pt",    "F_p",      "F_r",      "E_sn",   "E_Wk",    "E_MdK"};
  return symbols[static_cast<int>(p)];
}

std::optional<GearParameter> parameter_from_symbol(const std::string& symbol) {
  for (GearParameter p : all_gear_parameters()) {
    if (parameter_symbol(p) == symbol) return p;
  }
  return std::nullopt;
}

bool parameter_signed(GearParameter p) {
  return p == GearParameter::kfHalpha || p == GearParameter::kfHbeta || p == GearParameter::kfpt ||
         parameter_is_size(p);
}

std::optional<double> parameter_tolerance_um(const ToleranceSet& tolerances, GearParameter p) {
  const std::optional<ToleranceKind> kind = parameter_tolerance_kind(p);
  return kind ? tolerances.get_um(*kind) : std::nullopt;
}

bool parameter_is_size(GearParameter p) {
  return p == GearParameter::kEsn || p == GearParameter::kEWk || p == GearParameter::kEMdK;
}

bool parameter_of_both_flanks(GearParameter p) {
  return p == GearParameter::kFr || parameter_is_size(p);
}

std::optional<ToleranceKind> parameter_tolerance_kind(GearParameter p) {
  switch (p) {
    case GearParameter::kFalpha:
      return ToleranceKind::kProfileTotal;
    case GearParameter::kfHalpha:
      return ToleranceKind::kProfileSlope;
    case GearParameter::kffalpha:
      return ToleranceKind::kProfileForm;
    case GearParameter::kFbeta:
      return ToleranceKind::kHelixTotal;
    case GearParameter::kfHbeta:
      return ToleranceKind::kHelixSlope;
    case GearParameter::kffbeta:
      return ToleranceKind::kHelixForm;
    case GearParameter::kfpt:
      return ToleranceKind::kSinglePitch;
    case GearParameter::kFp:
      return ToleranceKind::kCumulativePitch;
    case GearParameter::kFr:
      return ToleranceKind::kRunout;
    case GearParameter::kEsn:
    case GearParameter::kEWk:
    case GearParameter::kEMdK:
      return std::nullopt;
  }
  return std::nullopt;
}

std::optional<TraceResult> evaluate_trace_over(std::span<const double> x, std::span<const double> d,
                                               double range_start, double range_end) {
  // A sample on a range end counts: grid points are placed on the ends up to rounding, and a
  // user's program (`--plan`) prints its coordinates rounded (to 0.1 µm or so: its matched roll
  // lengths then differ from the ends by up to about a micrometre). 1 µm (x in mm) is far below
  // any sample spacing of a trace.
  const double eps = std::max(1e-9 * std::abs(range_end - range_start), 1e-3);
  std::vector<double> xs, ds;
  for (std::size_t i = 0; i < x.size() && i < d.size(); ++i) {
    if (x[i] >= range_start - eps && x[i] <= range_end + eps) {
      xs.push_back(x[i]);
      ds.push_back(d[i]);
    }
  }
  if (xs.size() < 3 || !(xs.back() > xs.front())) return std::nullopt;
  const TraceEvaluation e = evaluate_trace(xs, ds);
  TraceResult r;
  r.samples = static_cast<int>(xs.size());
  r.slope_um_per_mm = e.slope_um / (xs.back() - xs.front());
  r.slope_um = r.slope_um_per_mm * (range_end - range_start);  // over the whole range (ISO)
  r.form_um = e.form_um;
  r.total_um = e.total_um;
  // The mean line passes through the trapezoid-weighted centroid (as evaluate_trace's does).
  double W = 0.0, mx = 0.0, md = 0.0;
  for (std::size_t i = 0; i < xs.size(); ++i) {
    const double w =
        0.5 * ((i > 0 ? xs[i] - xs[i - 1] : 0.0) + (i + 1 < xs.size() ? xs[i + 1] - xs[i] : 0.0));
    W += w;
    mx += w * xs[i];
    md += w * ds[i];
  }
  mx /= W;
  md /= W;
  r.intercept_um = md + r.slope_um_per_mm * (range_start - mx);
  return r;
}

double interpolate_trace(std::span<const double> x, std::span<const double> d, double at) {
  if (x.empty()) return std::numeric_limits<double>::quiet_NaN();
  if (at <= x.front()) return d.front();
  if (at >= x.back()) return d.back();
  const auto it = std::upper_bound(x.begin(), x.end(), at);
  const std::size_t i = static_cast<std::size_t>(it - x.begin());
  const double t = (at - x[i - 1]) / (x[i] - x[i - 1]);
  return d[i - 1] + t * (d[i] - d[i - 1]);
}

double flank_arc_position_um(FlankSide side, double normal_deviation_um,
                             double pressure_angle_at_circle_rad) {
  return side_sign(side) * normal_deviation_um / std::cos(pressure_angle_at_circle_rad);
}

PitchResult evaluate_pitch(std::span<const double> u) {
  PitchResult r;
  const std::size_t z = u.size();
  if (z < 2) return r;
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (std::size_t k = 0; k < z; ++k) {
    const double f = u[(k + 1) % z] - u[k];
    r.single_um.push_back(f);
    r.single_max_abs_um = std::max(r.single_max_abs_um, std::abs(f));
    lo = std::min(lo, u[k] - u[0]);
    hi = std::max(hi, u[k] - u[0]);
  }
  r.cumulative_um = hi - lo;
  return r;
}

Eigen::Vector2d ball_displacement_um(const BallContact& c, double d_right_um, double d_left_um) {
  Eigen::Matrix2d A;
  A.row(0) = c.normal_right.transpose();
  A.row(1) = c.normal_left.transpose();
  return A.inverse() * Eigen::Vector2d(d_right_um, d_left_um);
}

double ball_radial_displacement_um(const BallContact& c, double d_right_um, double d_left_um) {
  return ball_displacement_um(c, d_right_um, d_left_um).dot(c.radial);
}

std::vector<BallContact> ball_contacts(const InvoluteGear& gear, double L, double z) {
  std::vector<BallContact> contacts;
  const int teeth = gear.teeth();
  const double half = gear.angular_pitch_rad() / 2.0;
  for (int k = 1; k <= teeth; ++k) {
    const int next = k % teeth + 1;
    BallContact c;
    c.normal_right = gear.flank_point(k, FlankSide::kRight, L, z).normal.head<2>().normalized();
    c.normal_left = gear.flank_point(next, FlankSide::kLeft, L, z).normal.head<2>().normalized();
    // The space's centre line in the section z (turned by the helix on a helical gear).
    const double angle = gear.tooth_centre_angle_rad(k) + half + z * gear.helix_turn_per_mm();
    c.radial = Eigen::Vector2d(std::cos(angle), std::sin(angle));
    contacts.push_back(c);
  }
  return contacts;
}

double runout_um(const std::vector<BallContact>& contacts, std::span<const double> d_right,
                 std::span<const double> d_left) {
  const std::size_t z = contacts.size();
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (std::size_t k = 0; k < z; ++k) {
    const double r = ball_radial_displacement_um(contacts[k], d_right[k], d_left[(k + 1) % z]);
    lo = std::min(lo, r);
    hi = std::max(hi, r);
  }
  return z ? hi - lo : 0.0;
}

double tooth_thickness_deviation_um(double d_left_um, double d_right_um, double alpha_t_rad,
                                    double beta_rad) {
  return (d_left_um + d_right_um) / std::cos(alpha_t_rad) * std::cos(beta_rad);
}

double span_deviation_um(double d_first_um, double d_last_um, double base_helix_angle_rad) {
  return (d_first_um + d_last_um) * std::cos(base_helix_angle_rad);
}

double ball_dimension_deviation_um(const BallContact& a, const Eigen::Vector2d& delta_a_um,
                                   const BallContact& b, const Eigen::Vector2d& delta_b_um) {
  // The centres lie at r_K e_a and r_K e_b: their distance changes along (e_a − e_b).
  const Eigen::Vector2d u = (a.radial - b.radial).normalized();
  return u.dot(delta_a_um - delta_b_um);
}

}  // namespace gearmc
