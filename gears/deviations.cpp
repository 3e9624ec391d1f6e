// Deviation model of perturbed gears: the evaluation of the cubic B-spline form fields (kept here
// with the flank's deviation field so that the contact solver's calls inline it; their
// construction and ranges are in cubic_bspline.cpp), the ISO evaluation of deviation traces, the
// radial-runout measurement, and the sampler that draws gear k within its tolerances.
//
// How the sampler keeps every drawn gear within tolerance (README, "Deviation model"):
//  * profile and helix: a random smooth shape (B-spline, N(0,1) control values, its mean line
//    removed exactly through the spline's linear precision) is scaled to a drawn form band,
//    a drawn slope is added, and the sum is scaled by one factor <= 1 so that slope, form and
//    total of the continuous trace, measured the ISO way and exactly (the mean line from the
//    spline's integrals, the bands from each span's cubic: its ends and the roots of its
//    quadratic derivative), are within their tolerances times (1 - kSafety). The margin keeps
//    the traces clear of their limits under rounding and under sampled evaluations (a trace
//    sampled at spacing s may read up to s^2/8 max|d''| off its continuous band).
//  * pitch: each flank's location is drawn within +/- f_pb/4 (f_pb = min(f_pb, f_pt cos alpha)),
//    then made zero-mean per side, so consecutive flanks differ by at most f_pb/2; the other half
//    of the budget is left to eccentricity, whose contribution to a single pitch is at most 2 e
//    sin(pi/z).
//  * runout: measured (ball at mid face) on the gear without eccentricity, R0; the pitch part is
//    scaled down when R0 > F_r, and when the profile and helix shapes alone break F_r they are
//    drawn again from further streams (up to 64 times; then ToleranceError); eccentricity adds
//    at most 2e, so e <= (F_r - R0)/2.
//  * thickness: the rack shift lies in [-(E_Hs + T_H), -E_Hs] (GOST 1643-81 magnitudes).
#include "gears/deviations.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <memory>
#include <numbers>

#include "core/check.h"
#include "core/constants.h"
#include "core/random_stream.h"
#include "gears/cubic_range.h"

namespace gearmc {
namespace {

constexpr double kSafety = 1e-3;  // relative margin kept below each tolerance

}  // namespace

double CubicBSpline::value(double t) const {
  double v, d1, d2;
  evaluate(t, &v, &d1, &d2);
  return v;
}

double CubicBSpline::derivative(double t) const {
  double v, d1, d2;
  evaluate(t, &v, &d1, &d2);
  return d1;
}

double CubicBSpline::second_derivative(double t) const {
  double v, d1, d2;
  evaluate(t, &v, &d1, &d2);
  return d2;
}

double FlankDeviation::d_dL(double L) const {
  return profile_slope_um_per_mm + profile_form.derivative(L);
}
double FlankDeviation::d_dz(double z) const {
  return helix_slope_um_per_mm + helix_form.derivative(z);
}
FlankDeviation::Ranges FlankDeviation::derivative_ranges() const {
  const CubicBSpline::Ranges p = profile_form.derivative_ranges();
  const CubicBSpline::Ranges h = helix_form.derivative_ranges();
  constexpr double inf = std::numeric_limits<double>::infinity();
  Ranges r;
  r.d = {-inf, inf};
  r.dL = {profile_slope_um_per_mm + p.first.lo, profile_slope_um_per_mm + p.first.hi};
  r.dz = {helix_slope_um_per_mm + h.first.lo, helix_slope_um_per_mm + h.first.hi};
  r.dLL = p.second;
  r.dzz = h.second;
  return r;
}

double FlankDeviation::d2_dL2(double L) const { return profile_form.second_derivative(L); }
double FlankDeviation::d2_dz2(double z) const { return helix_form.second_derivative(z); }

TraceEvaluation evaluate_trace(std::span<const double> x, std::span<const double> d) {
  GEARMC_CHECK(x.size() == d.size() && x.size() >= 2,
               "a trace needs as many deviations as positions, at least 2");
  // Trapezoid weights: the weighted least-squares line is the continuous one (ISO defines the
  // mean line over the trace, not over a sample) to O(h^2); plain sums would be off by O(h),
  // e.g. 0.3 µm of slope for 200 samples of a trace with 5 µm at its ends.
  const size_t n = x.size();
  double W = 0.0, mx = 0.0, md = 0.0;
  auto weight = [&](size_t i) {
    const double left = i > 0 ? x[i] - x[i - 1] : 0.0;
    const double right = i + 1 < n ? x[i + 1] - x[i] : 0.0;
    return 0.5 * (left + right);
  };
  for (size_t i = 0; i < n; ++i) {
    const double w = weight(i);
    W += w;
    mx += w * x[i];
    md += w * d[i];
  }
  mx /= W;
  md /= W;
  double sxx = 0.0, sxd = 0.0;
  for (size_t i = 0; i < n; ++i) {
    const double w = weight(i);
    sxx += w * (x[i] - mx) * (x[i] - mx);
    sxd += w * (x[i] - mx) * (d[i] - md);
  }
  const double b = sxd / sxx;  // least-squares mean line: md + b (x - mx)
  double rmin = std::numeric_limits<double>::infinity(), rmax = -rmin, dmin = rmin, dmax = -rmin;
  for (size_t i = 0; i < n; ++i) {
    const double r = d[i] - (md + b * (x[i] - mx));
    rmin = std::min(rmin, r);
    rmax = std::max(rmax, r);
    dmin = std::min(dmin, d[i]);
    dmax = std::max(dmax, d[i]);
  }
  return {b * (x.back() - x.front()), rmax - rmin, dmax - dmin};
}

EvaluationRanges evaluation_ranges(const InvoluteGear& gear) {
  const double L0 = gear.form_roll_length_mm(), L1 = gear.tip_roll_length_mm();
  const double b = gear.face_width_mm();
  const double c = std::min(0.05 * b, gear.module_mm());
  // From the form circle over 95 % of the active profile towards the tip; on an internal gear
  // the tip has the smaller roll length, and the range is given in increasing L.
  if (gear.internal()) return {L0 + 0.95 * (L1 - L0), L0, c, b - c};
  return {L0, L0 + 0.95 * (L1 - L0), c, b - c};
}

namespace {

// Signed draw in [-1, 1] (tolerance units) following the distribution law.
double signed_draw(const DeviationDistribution& law, RandomStream& rng) {
  if (law.law == DeviationDistribution::Law::kUniform) return rng.uniform(-1.0, 1.0);
  if (law.law == DeviationDistribution::Law::kAtTolerance) return rng.uniform() < 0.5 ? -1.0 : 1.0;
  for (;;) {  // truncated normal by rejection: tolerance = k sigma
    const double v = rng.normal() / law.k;
    if (std::abs(v) <= 1.0) return v;
  }
}

// Amplitude draw in [0, 1].
double amplitude_draw(const DeviationDistribution& law, RandomStream& rng) {
  if (law.law == DeviationDistribution::Law::kUniform) return rng.uniform();
  if (law.law == DeviationDistribution::Law::kAtTolerance) return 1.0;
  return std::abs(signed_draw(law, rng));
}

}  // namespace

// What drawing a trace needs of its spline basis, once per sampler: the spans' Taylor maps, the
// Greville abscissae and the two linear functionals of the least-squares mean line of the
// continuous trace over [t0, t1] (ISO 1328-1 defines it over the trace): for s(t) = sum c_j N_j,
//   mean  md = (1/R) integral s dt = mean_weights . c,
//   slope b  = integral (t - mid) s dt / (R^3 / 12) = slope_weights . c     (R = t1 - t0),
// integrated exactly from each span's cubic (sum of q_m h^(m+1) / (m+1) and the like).
struct TraceBasis {
  TraceBasis(int control_points, double start, double end)
      : t0(start),
        t1(end),
        h((end - start) / (control_points - 3)),
        mid(0.5 * (start + end)),
        spline(CubicBSplineBasis::of(control_points)) {
    const int spans = control_points - 3;
    const CubicBSpline zero(t0, t1, std::vector<double>(control_points, 0.0), spline);
    for (int j = 0; j < control_points; ++j) greville.push_back(zero.greville(j));
    const double R = t1 - t0;
    mean_weights.assign(control_points, 0.0);
    slope_weights.assign(control_points, 0.0);
    for (int k = 0; k < spans; ++k) {
      const CubicBSplineBasis::Matrix& M = spline.matrix(k);
      const double start_offset = t0 + k * h - mid;
      for (int j = 0; j < 4; ++j) {
        // In the unit parameter s = u / h: integral_0^h q(u/h) du = h sum q_m / (m + 1) and
        // integral_0^h u q(u/h) du = h^2 sum q_m / (m + 2).
        double i0 = 0.0, i1 = 0.0;
        for (int m = 0; m < 4; ++m) {
          i0 += M[m][j] / (m + 1);
          i1 += M[m][j] / (m + 2);
        }
        i0 *= h;
        i1 *= h * h;
        mean_weights[k + j] += i0 / R;
        slope_weights[k + j] += (start_offset * i0 + i1) / (R * R * R / 12.0);
      }
    }
  }
  // Taylor coefficients (in u = t - t_k) of every span of the spline with coefficients c.
  void taylor(const std::vector<double>& c, std::vector<std::array<double, 4>>& q) const {
    const int spans = spline.spans();
    q.resize(spans);
    const double g1 = 1.0 / h, g2 = g1 * g1, g3 = g2 * g1;
    for (int k = 0; k < spans; ++k) {
      const CubicBSplineBasis::Matrix& M = spline.matrix(k);
      const double* ck = c.data() + k;
      double r[4];
      for (int m = 0; m < 4; ++m) {
        r[m] = M[m][0] * ck[0] + M[m][1] * ck[1] + M[m][2] * ck[2] + M[m][3] * ck[3];
      }
      q[k] = {r[0], r[1] * g1, r[2] * g2, r[3] * g3};
    }
  }
  double t0, t1, h, mid;
  const CubicBSplineBasis& spline;  // owned by CubicBSplineBasis::of (lives for the program)
  std::vector<double> greville, mean_weights, slope_weights;
};

namespace {

// Tolerances bounding one trace (profile or helix); absent ones are infinite.
struct TraceTolerances {
  std::optional<double> slope, form, total;
  bool any() const { return slope || form || total; }
};

// One random trace shape within its tolerances: writes the slope (µm/mm) and the form spline.
void draw_trace(const TraceTolerances& tol, const DeviationDistribution& slope_law,
                const DeviationDistribution& form_law, const TraceBasis& basis, RandomStream& rng,
                double* slope_um_per_mm, CubicBSpline* form) {
  *slope_um_per_mm = 0.0;
  *form = CubicBSpline();
  if (!tol.any()) return;
  const double t0 = basis.t0, t1 = basis.t1;
  const double range = t1 - t0, mid = basis.mid;

  // Targets. With only a total tolerance (GOST f_f, F_beta) the drawn total band is split
  // between slope and form by a uniform fraction.
  double slope_target, form_target;
  std::optional<double> total_target;
  if (tol.slope || tol.form) {
    slope_target = tol.slope ? *tol.slope * signed_draw(slope_law, rng) : 0.0;
    form_target = tol.form ? *tol.form * amplitude_draw(form_law, rng) : 0.0;
  } else {
    const double total = *tol.total * amplitude_draw(form_law, rng);
    const double q = rng.uniform();
    slope_target = (rng.uniform() < 0.5 ? -1.0 : 1.0) * q * total;
    form_target = (1.0 - q) * total;
    total_target = total;
  }

  // Form shape: N(0,1) control values with their least-squares mean line removed. The spline
  // reproduces lines exactly (linear precision), so subtracting the line md + b (t - mid) from
  // the coefficients at their Greville abscissae subtracts it from the curve.
  std::vector<double> c(basis.greville.size());
  for (double& v : c) v = rng.normal();
  double md = 0.0, b = 0.0;
  for (size_t j = 0; j < c.size(); ++j) {
    md += basis.mean_weights[j] * c[j];
    b += basis.slope_weights[j] * c[j];
  }
  for (size_t j = 0; j < c.size(); ++j) c[j] -= md + b * (basis.greville[j] - mid);
  // The spans' cubics in this thread's scratch buffer (no allocation per trace; draw() runs
  // ~100 traces per gear), and the shape's form band: its mean line is now zero, so the band
  // is max - min, exact from the cubics. Scaled to the target.
  thread_local std::vector<std::array<double, 4>> q;
  basis.taylor(c, q);
  constexpr double inf = std::numeric_limits<double>::infinity();
  double lo = inf, hi = -inf;
  for (const std::array<double, 4>& span : q) widen_by_cubic(span, basis.h, &lo, &hi);
  const double band = hi - lo;
  const double to_target = band > 0.0 ? form_target / band : 0.0;

  // Compose and scale the whole trace into every tolerance. The form part has a zero mean line,
  // so the composed trace's mean line is the drawn line itself: its slope deviation is
  // slope * range and its form band the scaled band; its total band (between parallels to
  // d = 0) is max - min of line + scaled shape, exact from each span's cubic again.
  const double slope = slope_target / range;
  double total_lo = inf, total_hi = -inf;
  for (std::size_t k = 0; k < q.size(); ++k) {
    const std::array<double, 4> composed = {
        to_target * q[k][0] + slope * (t0 + static_cast<double>(k) * basis.h - mid),
        to_target * q[k][1] + slope, to_target * q[k][2], to_target * q[k][3]};
    widen_by_cubic(composed, basis.h, &total_lo, &total_hi);
  }
  const TraceEvaluation e{slope * range, band * to_target, total_hi - total_lo};
  double factor = 1.0;
  auto limit = [&](std::optional<double> tolerance, double measured) {
    if (tolerance && measured > 0.0) factor = std::min(factor, *tolerance / measured);
  };
  limit(tol.slope, std::abs(e.slope_um));
  limit(tol.form, e.form_um);
  limit(tol.total, e.total_um);
  if (total_target && e.total_um > 0.0) factor = *total_target / e.total_um;
  factor *= 1.0 - kSafety;
  for (double& v : c) v *= to_target * factor;
  *slope_um_per_mm = slope * factor;
  *form = CubicBSpline(t0, t1, std::move(c), basis.spline);
}

// The real flank's signed normal distance (mm, + outside the material) of point X (datum frame,
// mm) for the flank of `tooth` on `side` of a perturbed gear, and its gradient (per mm, datum
// frame): closed form for an involute, r_b (inv(alpha_X) +/- phi - theta_b), minus the deviation
// at the foot of roll length L = r_b (theta_b -/+ phi + alpha_X) (first order in the deviation;
// its error is d * slope^2, far below a nanometre). With the radial and tangential unit vectors
// e_rho, e_phi of X and sin(alpha_X) = sqrt(rho^2 - r_b^2) / rho, cos(alpha_X) = r_b / rho:
//   d inv(alpha)/d rho = tan^2(alpha) d alpha/d rho = sin(alpha) / r_b, so the nominal part has
//   the gradient sin(alpha) e_rho +/- cos(alpha) e_phi (the flank's unit normal at the foot);
//   grad L = cos^2(alpha) / sin(alpha) e_rho -/+ cos(alpha) e_phi, times -1e-3 d'(L) for the
//   deviation part.
struct FlankDistance {
  double distance_mm;
  Eigen::Vector2d gradient;
};
FlankDistance distance_to_real_flank(const InvoluteGear& gear, const PerturbedGear& g, int tooth,
                                     FlankSide side, const Eigen::Vector2d& X, double z) {
  const Eigen::Vector2d Xg = X - g.eccentricity_mm;  // into the gear's own frame
  // A helical gear's section at z is the section at 0 turned by z helix_turn_per_mm.
  const TransversePosition at = gear.transverse_position(
      tooth, side, Xg, gear.helical() ? z * gear.helix_turn_per_mm() : 0.0);
  const double foot_L = at.foot_roll_length_mm;
  const FlankDeviation& f = g.flank(tooth, side);
  double pv, p1, p2;
  f.profile_form.evaluate(foot_L, &pv, &p1, &p2);
  const double d_um = f.offset_um + f.profile_slope_um_per_mm * (foot_L - f.profile_mid_mm) + pv +
                      f.helix_slope_um_per_mm * (z - f.helix_mid_mm) + f.helix_form.value(z);
  const double dL_um_per_mm = f.profile_slope_um_per_mm + p1;
  // d(distance - delta(foot)) / dX.
  const Eigen::Vector2d gradient = at.distance_gradient - 1e-3 * dL_um_per_mm * at.foot_gradient;
  return {at.distance_mm - 1e-3 * d_um, gradient};
}

}  // namespace

double radial_runout_um(const InvoluteGear& gear, const PerturbedGear& g) {
  const EvaluationRanges ranges = evaluation_ranges(gear);
  const double z = 0.5 * gear.face_width_mm();
  const int teeth = gear.teeth();
  // Ball radius: touches the nominal flanks at the middle of the profile evaluation range.
  // Space 1 lies between the R flank of tooth 1 and the L flank of tooth 2, centred on tau/2.
  const double L_c = 0.5 * (ranges.profile_start_mm + ranges.profile_end_mm);
  // A helical gear: in the transverse section (the section at 0 turned by z turn; ISO 10064-4's
  // ball touches both helicoids where a circle of the same radius touches both transverse
  // involutes, to first order in the deviations: a flank's normal displacement delta cos(beta_b)
  // along N moves the ball radially as the transverse displacement delta along n_t moves the
  // circle, N.e_r = cos(beta_b) n_t.e_r). The ball's radius from the section at 0, with the
  // transverse normal.
  const double turn = gear.helical() ? z * gear.helix_turn_per_mm() : 0.0;
  const FlankPoint c = gear.flank_point(1, FlankSide::kRight, L_c, gear.helical() ? 0.0 : z);
  const double half = 0.5 * gear.angular_pitch_rad();
  const Eigen::Vector2d bisector_normal(-std::sin(half), std::cos(half));
  const Eigen::Vector2d p = c.point.head<2>();
  const Eigen::Vector2d n =
      gear.helical() ? Eigen::Vector2d(c.normal.head<2>().normalized()) : c.normal.head<2>();
  const double r_ball = -p.dot(bisector_normal) / n.dot(bisector_normal);
  const double rho_nominal = (p + r_ball * n).norm();

  double rho_min = std::numeric_limits<double>::infinity(), rho_max = -rho_min;
  for (int k = 1; k <= teeth; ++k) {
    const int next = k % teeth + 1;
    const double angle = gear.tooth_centre_angle_rad(k) + half + turn;
    Eigen::Vector2d X = rho_nominal * Eigen::Vector2d(std::cos(angle), std::sin(angle));
    // Newton on (distance to the right flank, distance to the left flank) = (r_ball, r_ball)
    // with the closed-form gradients as the Jacobian's rows: two distance evaluations per step.
    for (int iter = 0; iter < 20; ++iter) {
      const FlankDistance a = distance_to_real_flank(gear, g, k, FlankSide::kRight, X, z);
      const FlankDistance b = distance_to_real_flank(gear, g, next, FlankSide::kLeft, X, z);
      const double fa = a.distance_mm - r_ball, fb = b.distance_mm - r_ball;
      if (std::max(std::abs(fa), std::abs(fb)) < 1e-10) break;
      // The two flank normals of a space are far from parallel (about 2 alpha apart).
      const double det = a.gradient.x() * b.gradient.y() - a.gradient.y() * b.gradient.x();
      X.x() -= (fa * b.gradient.y() - fb * a.gradient.y()) / det;
      X.y() -= (a.gradient.x() * fb - b.gradient.x() * fa) / det;
    }
    rho_min = std::min(rho_min, X.norm());
    rho_max = std::max(rho_max, X.norm());
  }
  return 1e3 * (rho_max - rho_min);
}

GearSampler::GearSampler(const InvoluteGear& gear, const ToleranceSet& tolerances,
                         DeviationModel model, std::uint64_t seed)
    : gear_(gear),
      tolerances_(tolerances),
      model_(std::move(model)),
      seed_(seed),
      ranges_(evaluation_ranges(gear)),
      profile_basis_(std::make_shared<const TraceBasis>(
          model_.profile_form_control_points, ranges_.profile_start_mm, ranges_.profile_end_mm)),
      helix_basis_(std::make_shared<const TraceBasis>(
          model_.helix_form_control_points, ranges_.helix_start_mm, ranges_.helix_end_mm)) {}

GearSampler::~GearSampler() = default;

PerturbedGear GearSampler::draw(int gear_index) const {
  const int z = gear_.teeth();
  const auto k = static_cast<std::uint32_t>(gear_index);
  PerturbedGear g;
  g.index = gear_index;
  g.flanks.resize(2 * z);
  const EvaluationRanges& r = ranges_;
  for (FlankDeviation& f : g.flanks) {
    f.profile_mid_mm = 0.5 * (r.profile_start_mm + r.profile_end_mm);
    f.helix_mid_mm = 0.5 * (r.helix_start_mm + r.helix_end_mm);
  }
  if (!model_.random) return g;
  const double alpha = gear_.pressure_angle_rad();
  auto tol = [&](ToleranceKind kind) { return tolerances_.get_um(kind); };

  // Thickness: one rack shift per gear, in [-(E_Hs + T_H), -E_Hs].
  const auto E_Hs = tol(ToleranceKind::kThicknessUpper);
  const auto T_H = tol(ToleranceKind::kThicknessTolerance);
  if (E_Hs || T_H) {
    RandomStream rng(seed_, k, StreamPurpose::kThickness);
    const double half = 0.5 * T_H.value_or(0.0);
    g.rack_shift_um = -E_Hs.value_or(0.0) - half + half * signed_draw(model_.thickness, rng);
  }
  const double thickness_offset = g.rack_shift_um * std::sin(alpha);

  // Pitch: flank locations within +/- f_pb/4.
  std::optional<double> pitch_budget = tol(ToleranceKind::kBasePitch);
  if (const auto f_pt = tol(ToleranceKind::kSinglePitch)) {
    const double on_base = *f_pt * std::cos(alpha);  // arc on d -> normal: x cos(alpha)
    pitch_budget = pitch_budget ? std::min(*pitch_budget, on_base) : on_base;
  }
  std::vector<double> pitch(2 * z, 0.0);
  if (pitch_budget) {
    RandomStream rng(seed_, k, StreamPurpose::kPitch);
    for (double& w : pitch) w = 0.25 * *pitch_budget * signed_draw(model_.pitch, rng);
    // Zero mean on each side: the gear's thickness stays the drawn rack shift; differences
    // between flanks (pitch) and space widths up to a constant (runout) are unchanged.
    for (int side = 0; side < 2; ++side) {
      double mean = 0.0;
      for (int i = side; i < 2 * z; i += 2) mean += pitch[i] / z;
      for (int i = side; i < 2 * z; i += 2) pitch[i] -= mean;
    }
  }

  // Profile and helix shape, flank by flank, each from its own stream.
  const TraceTolerances profile_tol{tol(ToleranceKind::kProfileSlope),
                                    tol(ToleranceKind::kProfileForm),
                                    tol(ToleranceKind::kProfileTotal)};
  const TraceTolerances helix_tol{tol(ToleranceKind::kHelixSlope), tol(ToleranceKind::kHelixForm),
                                  tol(ToleranceKind::kHelixTotal)};
  // The shapes of attempt a come from the streams of flank index i + 2 z a: attempt 0 is the
  // plain draw, and a later attempt is made only when the earlier shapes alone break F_r (see
  // the runout step below), so gears that fit at once are unchanged.
  auto draw_shapes = [&](int attempt) {
    for (int i = 0; i < 2 * z; ++i) {
      FlankDeviation& f = g.flanks[i];
      const auto index = static_cast<std::uint32_t>(i + 2 * z * attempt);
      RandomStream profile_rng(seed_, k, StreamPurpose::kProfile, index);
      draw_trace(profile_tol, model_.profile_slope, model_.profile_form, *profile_basis_,
                 profile_rng, &f.profile_slope_um_per_mm, &f.profile_form);
      RandomStream helix_rng(seed_, k, StreamPurpose::kHelix, index);
      draw_trace(helix_tol, model_.helix_slope, model_.helix_form, *helix_basis_, helix_rng,
                 &f.helix_slope_um_per_mm, &f.helix_form);
    }
  };

  // Runout without eccentricity; shrink the pitch part if it alone breaks F_r. When even the
  // shapes alone (pitch scaled to almost nothing) break it, this gear is not within all its
  // tolerances: its shapes are drawn again from the next streams (rejection sampling: the gear
  // is then drawn from the law conditioned on meeting F_r), up to kRunoutAttempts times.
  auto set_offsets = [&](double pitch_scale) {
    for (int i = 0; i < 2 * z; ++i)
      g.flanks[i].offset_um = thickness_offset + pitch_scale * pitch[i];
  };
  const auto F_r = tol(ToleranceKind::kRunout);
  constexpr int kRunoutAttempts = 64;
  double runout = 0.0;
  for (int attempt = 0;; ++attempt) {
    draw_shapes(attempt);
    set_offsets(1.0);
    runout = radial_runout_um(gear_, g);
    if (!F_r) break;
    double scale = 1.0;
    while (runout > *F_r * (1.0 - kSafety) && scale > 1e-3) {
      scale *= 0.8;
      set_offsets(scale);
      runout = radial_runout_um(gear_, g);
    }
    if (runout <= *F_r * (1.0 - kSafety)) break;
    g.runout_redraws = attempt + 1;
    if (attempt + 1 == kRunoutAttempts) {
      throw ToleranceError("runout tolerance F_r = " + std::to_string(*F_r) +
                           " µm is smaller than the runout the profile and helix tolerances "
                           "alone give gear " +
                           std::to_string(k) + " in " + std::to_string(kRunoutAttempts) +
                           " draws (last " + std::to_string(runout) + " µm); raise F_r");
    }
  }

  // Eccentricity: within half of the pitch budget and of what is left of F_r.
  double e_max = std::numeric_limits<double>::infinity();
  if (pitch_budget) e_max = 0.5 * *pitch_budget / (2.0 * std::sin(kPi / z));
  if (F_r) e_max = std::min(e_max, 0.5 * (*F_r * (1.0 - kSafety) - runout));
  if (std::isfinite(e_max) && e_max > 0.0) {
    RandomStream rng(seed_, k, StreamPurpose::kEccentricity);
    const double e_um = e_max * amplitude_draw(model_.eccentricity, rng);
    const double angle = rng.uniform(0.0, 2.0 * kPi);
    g.eccentricity_mm = 1e-3 * e_um * Eigen::Vector2d(std::cos(angle), std::sin(angle));
  }
  return g;
}

}  // namespace gearmc
