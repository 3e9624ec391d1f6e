// Deviation model of perturbed gears: what a scenario says about random deviations (their
// distributions and the smoothness of form deviations), the deviations of one drawn gear
// (eccentricity, per-flank location, profile and helix slope and form), the ISO way of
// evaluating a deviation trace, and the sampler that draws gear k from its own streams so that
// every deviation stays within its tolerance.
//
// A flank's real surface is the nominal flank moved along its outward normal by
//   d(L, z) = offset + profile(L) + helix(z)   [µm, + = material added]
// and then translated with the whole gear by the eccentricity vector. profile() and helix()
// have a least-squares mean line through zero at the middle of their evaluation range, so
// `offset` is the flank's location (thickness and pitch), and profile/helix are its shape.
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <array>
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "gears/involute_gear.h"
#include "gears/tolerances.h"

namespace gearmc {

// How a deviation is drawn within its tolerance T.
//  kUniform: signed ones uniform in [-T, T], amplitudes uniform in [0, T];
//  kNormal:  N(0, T/k) truncated to [-T, T] (amplitudes: |N(0, T/k)| truncated to [0, T]);
//  kAtTolerance: every deviation at its limit, signed ones with a random sign (worst case).
struct DeviationDistribution {
  enum class Law { kUniform, kNormal, kAtTolerance } law = Law::kUniform;
  double k = 3.0;  // tolerance = k sigma for kNormal
};

// The scenario's deviation model.
struct DeviationModel {
  bool random = true;  // false: the nominal gear (plus any expression deviation)
  DeviationDistribution eccentricity, pitch, thickness, profile_slope, profile_form, helix_slope,
      helix_form;
  // Smoothness of the form deviations: number of control values of the cubic B-spline over the
  // evaluation range (>= 4). Correlation length ≈ range / (n - 3): more = wavier = larger slopes.
  int profile_form_control_points = 8;
  int helix_form_control_points = 6;
};

// The clamped uniform cubic B-spline basis with n coefficients (n - 3 spans) in the unit
// parameter: on span k the spline is sum_j c[k + j] N_{k+j}, a cubic whose Taylor coefficients
// about the span start, in s = (t - t_k) / h (h the span length), are a fixed linear map of the
// span's four coefficients: q = matrix(k) (c[k], .., c[k + 3]). The map depends only on n and k
// (the same for every interior span; the first and last three differ); it is computed once from
// the basis functions and their derivatives (Piegl & Tiller, The NURBS Book, algorithm A2.3) on
// the integer knots 0, 0, 0, 0, 1, 2, .., n - 3, .., n - 3.
class CubicBSplineBasis {
 public:
  using Matrix = std::array<std::array<double, 4>, 4>;  // [Taylor order m][coefficient j]
  explicit CubicBSplineBasis(int coefficients);
  // The basis for n coefficients, built on first use and kept (thread-safe).
  static const CubicBSplineBasis& of(int coefficients);
  int coefficients() const { return n_; }
  int spans() const { return n_ - 3; }
  const Matrix& matrix(int span) const { return matrices_[span]; }

 private:
  int n_;
  std::vector<Matrix> matrices_;
};

// Clamped uniform cubic B-spline on [t0, t1], linearly continued outside (value and slope of
// the end), so it is C2 inside and C1 everywhere. Values in µm, t in mm.
class CubicBSpline {
 public:
  CubicBSpline() = default;  // identically zero
  CubicBSpline(double t0, double t1, std::vector<double> coefficients);
  // The same with the basis given (it must be CubicBSplineBasis::of(coefficients.size()) or an
  // equal one): no look-up of the shared basis.
  CubicBSpline(double t0, double t1, std::vector<double> coefficients,
               const CubicBSplineBasis& basis);
  double value(double t) const;
  double derivative(double t) const;         // µm/mm
  double second_derivative(double t) const;  // µm/mm²
  // Value and both derivatives at once (the contact solver's hot path).
  void evaluate(double t, double* value, double* first, double* second) const;
  // Greville abscissa of coefficient i: a spline with coefficients a + b*greville(i) is the
  // line a + b t exactly (linear precision).
  double greville(int i) const;
  const std::vector<double>& coefficients() const { return c_; }
  struct Range {
    double lo, hi;
  };
  struct Ranges {
    Range value, first, second;
  };
  // The exact range over [t0, t1] of value(t) + slope (t - mid) (µm; slope in µm/mm, mid in
  // mm): from each span's cubic, its ends and the roots of its quadratic derivative.
  Range value_range(double slope = 0.0, double mid = 0.0) const;
  // The ranges of the first and second derivative over the whole real line (the linear
  // continuation adds the end slopes and a zero second derivative): exact, from the spans'
  // cubics. value is left at (-inf, inf).
  Ranges derivative_ranges() const;
  double t0() const { return t0_; }
  double t1() const { return t1_; }

 private:
  void build(const CubicBSplineBasis& basis);  // h_ and poly_ from c_
  double t0_ = 0.0, t1_ = 1.0, h_ = 1.0;
  double inverse_h_ = 1.0;  // 1 / h_ (the span of t by a multiplication)
  std::vector<double> c_;
  // Each span's cubic in power form about its start: v = p0 + p1 u + p2 u^2 + p3 u^3, built
  // once from the coefficients (CubicBSplineBasis) so that an evaluation is one Horner step.
  std::vector<std::array<double, 4>> poly_;
};

// One flank's normal deviation d(L, z) = offset + profile_slope*(L - L_mid) + profile_form(L)
// + helix_slope*(z - z_mid) + helix_form(z), µm. L and z in mm.
struct FlankDeviation {
  double offset_um = 0.0;
  double profile_slope_um_per_mm = 0.0, profile_mid_mm = 0.0;
  CubicBSpline profile_form;
  double helix_slope_um_per_mm = 0.0, helix_mid_mm = 0.0;
  CubicBSpline helix_form;

  double normal_um(double L, double z) const;
  double d_dL(double L) const;    // ∂d/∂L, µm/mm (depends on L only)
  double d_dz(double z) const;    // ∂d/∂z, µm/mm (depends on z only)
  double d2_dL2(double L) const;  // µm/mm²
  double d2_dz2(double z) const;  // µm/mm²
  // All of the above at once (µm, µm/mm, µm/mm²): the contact solver's hot path.
  void evaluate(double L, double z, double* d, double* dL, double* dz, double* dLL,
                double* dzz) const;
  // The ranges of d and its partials (µm, µm/mm, µm/mm²; d_Lz is identically zero): the
  // contact certificate's derivative bounds.
  struct Ranges {
    CubicBSpline::Range d, dL, dz, dLL, dzz;
  };
  // The partials' ranges over all (L, z), exact (d itself unbounded: (-inf, inf)).
  Ranges derivative_ranges() const;
};

// The evaluations of the contact solver's hot path, inline so that the solver keeps their
// results in registers (each is called a few times per contact, millions of times per run).
inline void CubicBSpline::evaluate(double t, double* value, double* first, double* second) const {
  if (c_.empty()) {
    *value = *first = *second = 0.0;
    return;
  }
  const double tc = std::clamp(t, t0_, t1_);
  const int spans = static_cast<int>(poly_.size());
  // The span by a multiplication with 1 / h: where it rounds differently from (tc - t0) / h, at
  // a span's end, it picks the neighbouring span, whose cubic has the same value there to
  // rounding (the spline is C2).
  const int k = std::clamp(static_cast<int>((tc - t0_) * inverse_h_), 0, spans - 1);
  const std::array<double, 4>& q = poly_[k];
  const double u = tc - (t0_ + k * h_);
  const double v = q[0] + u * (q[1] + u * (q[2] + u * q[3]));
  const double d1 = q[1] + u * (2.0 * q[2] + 3.0 * u * q[3]);
  if (t != tc) {  // linear continuation outside [t0, t1]: C1
    *value = v + d1 * (t - tc);
    *first = d1;
    *second = 0.0;
    return;
  }
  *value = v;
  *first = d1;
  *second = 2.0 * q[2] + 6.0 * u * q[3];
}

inline double FlankDeviation::normal_um(double L, double z) const {
  double pv, p1, p2, hv, h1, h2;
  profile_form.evaluate(L, &pv, &p1, &p2);
  helix_form.evaluate(z, &hv, &h1, &h2);
  return offset_um + profile_slope_um_per_mm * (L - profile_mid_mm) + pv +
         helix_slope_um_per_mm * (z - helix_mid_mm) + hv;
}

inline void FlankDeviation::evaluate(double L, double z, double* d, double* dL, double* dz,
                                     double* dLL, double* dzz) const {
  double pv, p1, p2, hv, h1, h2;
  profile_form.evaluate(L, &pv, &p1, &p2);
  helix_form.evaluate(z, &hv, &h1, &h2);
  *d = offset_um + profile_slope_um_per_mm * (L - profile_mid_mm) + pv +
       helix_slope_um_per_mm * (z - helix_mid_mm) + hv;
  *dL = profile_slope_um_per_mm + p1;
  *dz = helix_slope_um_per_mm + h1;
  *dLL = p2;
  *dzz = h2;
}

// A drawn gear: every deviation of gear `index`.
struct PerturbedGear {
  int index = 0;
  Eigen::Vector2d eccentricity_mm = Eigen::Vector2d::Zero();  // gear centre off the datum axis
  double rack_shift_um = 0.0;          // thickness: each flank moves by rack_shift * sin(alpha)
  std::vector<FlankDeviation> flanks;  // 2 per tooth: index 2*(tooth-1) + (R ? 1 : 0)
  // How many times the profile and helix shapes were drawn again because they alone broke F_r
  // (0 for almost every gear; see GearSampler::draw).
  int runout_redraws = 0;

  const FlankDeviation& flank(int tooth, FlankSide side) const {
    return flanks[2 * (tooth - 1) + (side == FlankSide::kRight ? 1 : 0)];
  }
  FlankDeviation& flank(int tooth, FlankSide side) {
    return flanks[2 * (tooth - 1) + (side == FlankSide::kRight ? 1 : 0)];
  }
};

// The ISO evaluation of a deviation trace d(x) sampled at increasing x (ISO 1328-1:2013 §3.3,
// 3.4): the mean line is the least-squares line of the trace (trapezoid-weighted over the
// samples, so it approximates the continuous line to O(h^2)); slope = difference of the
// mean line's values at the range ends (signed); form = distance between two parallels to the
// mean line enclosing the trace; total = distance between two parallels to the design line
// (d = 0) enclosing the trace = max - min.
struct TraceEvaluation {
  double slope_um = 0.0, form_um = 0.0, total_um = 0.0;
};
TraceEvaluation evaluate_trace(std::span<const double> x, std::span<const double> d);

// Evaluation ranges (mm) used for tolerances and for placing deviation fields:
// profile: from the form circle over 95 % of the roll length up to the tip (the tip end is
// excluded as ISO 1328-1 does); helix: b minus min(5 % b, m) at each end.
struct EvaluationRanges {
  double profile_start_mm, profile_end_mm, helix_start_mm, helix_end_mm;
};
EvaluationRanges evaluation_ranges(const InvoluteGear& gear);

struct TraceBasis;  // deviations.cpp: a trace's B-spline basis and mean-line functionals

// Draws perturbed gears within the resolved tolerances. Thread-safe: draw() is const and every
// random number comes from the gear's own streams (seed, gear index, purpose, flank).
class GearSampler {
 public:
  GearSampler(const InvoluteGear& gear, const ToleranceSet& tolerances, DeviationModel model,
              std::uint64_t seed);
  ~GearSampler();
  PerturbedGear draw(int gear_index) const;
  const EvaluationRanges& ranges() const { return ranges_; }

 private:
  const InvoluteGear& gear_;
  ToleranceSet tolerances_;
  DeviationModel model_;
  std::uint64_t seed_;
  EvaluationRanges ranges_;
  // The B-spline bases of the profile and helix traces with their mean-line functionals.
  std::shared_ptr<const TraceBasis> profile_basis_, helix_basis_;
};

// Radial runout (µm) as ISO 10064-4 measures it: a ball touching both flanks of every tooth
// space at mid face width (z = b/2) in the datum frame (gear axis = Z); runout = max - min of
// the ball centre's distance from the axis. The ball's radius makes it touch the nominal flanks
// at the middle of the profile evaluation range. Form deviations are included to first order.
double radial_runout_um(const InvoluteGear& gear, const PerturbedGear& perturbed);

}  // namespace gearmc
