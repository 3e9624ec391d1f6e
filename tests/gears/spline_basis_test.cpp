// The cubic B-spline's per-span polynomials (built from the precomputed CubicBSplineBasis) and
// its exact value ranges, against an independent evaluation: the Cox-de Boor recursion of the
// B-spline basis on the clamped uniform knot vector (de Boor 1972; Piegl & Tiller, The NURBS
// Book, eq. 2.5), with the derivatives as lower-degree splines of the coefficient differences
// (Piegl & Tiller eq. 3.3: C' = sum p (c_{i+1} - c_i) / (u_{i+p+1} - u_{i+1}) N_{i+1,p-1}).
// The exact ranges are checked against dense sampling refined by golden-section search, and the
// sampler's traces (scaled with those exact bands) against the ISO evaluation of a very dense
// sampling (evaluate_trace).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "gears/deviations.h"
#include "tests/support/p1_fixtures.h"

namespace gearmc {
namespace {

// The clamped uniform knot vector of n cubic coefficients on [t0, t1] (n + 4 knots).
std::vector<double> knots(int n, double t0, double t1) {
  std::vector<double> u(n + 4);
  const int spans = n - 3;
  for (int i = 0; i < n + 4; ++i) {
    u[i] = t0 + (t1 - t0) * std::clamp(i - 3, 0, spans) / spans;
  }
  return u;
}

// N_{i,p}(t) by the Cox-de Boor recursion, half-open spans [u_i, u_{i+1}) except that t = t1
// belongs to the last non-empty span.
double cox_de_boor(const std::vector<double>& u, int i, int p, double t) {
  if (p == 0) {
    const double last = u.back();
    if (t == last) return u[i] < last && u[i + 1] == last ? 1.0 : 0.0;
    return u[i] <= t && t < u[i + 1] ? 1.0 : 0.0;
  }
  double v = 0.0;
  if (u[i + p] > u[i]) v += (t - u[i]) / (u[i + p] - u[i]) * cox_de_boor(u, i, p - 1, t);
  if (u[i + p + 1] > u[i + 1]) {
    v += (u[i + p + 1] - t) / (u[i + p + 1] - u[i + 1]) * cox_de_boor(u, i + 1, p - 1, t);
  }
  return v;
}

// Value of the degree-p spline with coefficients c on knots u (the derivative splines drop the
// first and last knot).
double spline_value(const std::vector<double>& u, int p, const std::vector<double>& c, double t) {
  double v = 0.0;
  for (std::size_t i = 0; i < c.size(); ++i) v += c[i] * cox_de_boor(u, static_cast<int>(i), p, t);
  return v;
}

// Value, first and second derivative by Cox-de Boor.
struct Reference {
  double v, d1, d2;
};
Reference reference(int n, double t0, double t1, const std::vector<double>& c, double t) {
  const std::vector<double> u = knots(n, t0, t1);
  std::vector<double> c1(n - 1), c2(n - 2);
  for (int i = 0; i + 1 < n; ++i) c1[i] = 3.0 * (c[i + 1] - c[i]) / (u[i + 4] - u[i + 1]);
  const std::vector<double> u1(u.begin() + 1, u.end() - 1);
  for (int i = 0; i + 2 < n; ++i) c2[i] = 2.0 * (c1[i + 1] - c1[i]) / (u1[i + 3] - u1[i + 1]);
  const std::vector<double> u2(u1.begin() + 1, u1.end() - 1);
  return {spline_value(u, 3, c, t), spline_value(u1, 2, c1, t), spline_value(u2, 1, c2, t)};
}

// Random N(0,1) coefficients on several ranges and sizes 4 .. 20: value, slope and curvature at
// random points, at every knot and at both ends agree with Cox-de Boor to 1e-13 relative to
// the scale of each (max |c|, max |c| / h, max |c| / h^2).
TEST(CubicBSplineBasis, SpanPolynomialsMatchCoxDeBoor) {
  std::mt19937_64 rng(20261123);  // seed: fixed, any would do
  std::normal_distribution<double> normal;
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  int points = 0;
  for (int n = 4; n <= 20; ++n) {
    for (const auto& [t0, t1] :
         {std::pair{0.0, 1.0}, std::pair{21.7, 44.3}, std::pair{3.9, 75.0}}) {
      std::vector<double> c(n);
      for (double& v : c) v = normal(rng);
      const CubicBSpline s(t0, t1, c);
      const double scale = std::abs(*std::max_element(
          c.begin(), c.end(), [](double a, double b) { return std::abs(a) < std::abs(b); }));
      const double h = (t1 - t0) / (n - 3);
      std::vector<double> ts;
      for (int k = 0; k <= n - 3; ++k) ts.push_back(t0 + k * h);
      for (int i = 0; i < 40; ++i) ts.push_back(t0 + (t1 - t0) * uniform(rng));
      for (double t : ts) {
        const Reference r = reference(n, t0, t1, c, t);
        double v, d1, d2;
        s.evaluate(t, &v, &d1, &d2);
        EXPECT_NEAR(v, r.v, 1e-13 * scale) << "n " << n << " t " << t;
        EXPECT_NEAR(d1, r.d1, 1e-13 * scale / h) << "n " << n << " t " << t;
        // The curvature jumps at interior knots, where rounding of (t - t0) / h may pick either
        // span: compared everywhere else.
        if (std::find(ts.begin(), ts.begin() + (n - 2), t) == ts.begin() + (n - 2) || t == t0) {
          EXPECT_NEAR(d2, r.d2, 1e-13 * scale / (h * h)) << "n " << n << " t " << t;
        }
        ++points;
      }
      // The same spline with the basis given explicitly is the same spline, bit for bit.
      const CubicBSpline same(t0, t1, c, CubicBSplineBasis::of(n));
      for (double t : ts) EXPECT_EQ(same.value(t), s.value(t));
    }
  }
  EXPECT_GT(points, 2000);
}

// The extreme of f near t (a sample of a dense grid with spacing step) by golden-section
// search on [t - step, t + step] within [t0, t1]: sign +1 for a maximum, -1 for a minimum.
template <typename F>
double refine(const F& f, double t, double step, double t0, double t1, double sign) {
  double a = std::max(t0, t - step), b = std::min(t1, t + step);
  const double r = 0.5 * (std::sqrt(5.0) - 1.0);
  double x1 = b - r * (b - a), x2 = a + r * (b - a);
  double f1 = sign * f(x1), f2 = sign * f(x2);
  for (int i = 0; i < 200 && b - a > 1e-13 * (t1 - t0); ++i) {
    if (f1 > f2) {
      b = x2, x2 = x1, f2 = f1, x1 = b - r * (b - a), f1 = sign * f(x1);
    } else {
      a = x1, x1 = x2, f1 = f2, x2 = a + r * (b - a), f2 = sign * f(x2);
    }
  }
  return std::max({sign * f(t), f1, f2}) * sign;
}

// value_range against 10 000 samples of random splines (4 .. 20 coefficients), with and without
// an added line: the exact range contains every sample (to rounding, 1e-12 of the scale), and the
// sampled extremes refined by golden-section search reach the exact ones to 1e-12. The
// unrefined sample range falls short by up to s^2/8 max|d''| (s the sample spacing): the exact
// band is what a 64-sample-per-span grid underestimated.
TEST(CubicBSpline, ValueRangeIsExact) {
  std::mt19937_64 rng(42);  // seed: fixed, any would do
  std::normal_distribution<double> normal;
  double largest_shortfall = 0.0;
  for (int n = 4; n <= 20; ++n) {
    for (int trial = 0; trial < 3; ++trial) {
      const double t0 = 21.7, t1 = 44.3, mid = 0.5 * (t0 + t1);
      std::vector<double> c(n);
      for (double& v : c) v = normal(rng);
      const CubicBSpline s(t0, t1, c);
      const double slope = trial == 0 ? 0.0 : 0.3 * normal(rng);  // µm/mm
      auto f = [&](double t) { return s.value(t) + slope * (t - mid); };
      const CubicBSpline::Range exact = s.value_range(slope, mid);
      constexpr int kSamples = 10000;
      const double step = (t1 - t0) / (kSamples - 1);
      double lo = std::numeric_limits<double>::infinity(), hi = -lo, t_lo = t0, t_hi = t0;
      for (int i = 0; i < kSamples; ++i) {
        const double t = i + 1 < kSamples ? t0 + i * step : t1;
        const double v = f(t);
        if (v < lo) lo = v, t_lo = t;
        if (v > hi) hi = v, t_hi = t;
      }
      const double scale = exact.hi - exact.lo;
      EXPECT_LE(hi, exact.hi + 1e-12 * scale) << "n " << n;
      EXPECT_GE(lo, exact.lo - 1e-12 * scale) << "n " << n;
      EXPECT_NEAR(refine(f, t_hi, step, t0, t1, 1.0), exact.hi, 1e-12 * scale) << "n " << n;
      EXPECT_NEAR(refine(f, t_lo, step, t0, t1, -1.0), exact.lo, 1e-12 * scale) << "n " << n;
      largest_shortfall = std::max(largest_shortfall, (scale - (hi - lo)) / scale);
    }
  }
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.3g", largest_shortfall);
  RecordProperty("largest_relative_shortfall_of_10000_samples", buffer);
}

// Gears drawn with every deviation at its tolerance (law kAtTolerance), P1's GOST set and an ISO
// class-5 set: each profile and helix trace (line + form spline), evaluated the ISO way on
// 20 001 samples (evaluate_trace: trapezoid least-squares mean line), is within every tolerance
// times (1 - 1e-3) (the sampler's margin; up to 1e-7 more because the trapezoid-weighted line of
// the samples differs from the continuous mean line by O(s^2), seen up to 3.3e-8), and its binding
// quantity reaches that limit to 1e-6 (the sampling's shortfall, s^2/8 max|d''|, is ~1e-7
// here): the exact scaling uses the tolerances fully without exceeding them.
TEST(GearSampler, TracesAtToleranceMeetTheirLimitsExactly) {
  const InvoluteGear gear(testing_support::p1_gear_parameters());
  DeviationModel model;
  for (DeviationDistribution* law :
       {&model.profile_slope, &model.profile_form, &model.helix_slope, &model.helix_form}) {
    law->law = DeviationDistribution::Law::kAtTolerance;
  }
  constexpr double kLimit = 1.0 - 1e-3;
  int traces = 0;
  for (const ToleranceSet& tol :
       {testing_support::p1_tolerance_set(), testing_support::iso_class5_tolerance_set()}) {
    const GearSampler sampler(gear, tol, model, 5);
    const EvaluationRanges r = sampler.ranges();
    auto check = [&](double start, double end, double slope, double mid, const CubicBSpline& form,
                     ToleranceKind slope_kind, ToleranceKind form_kind, ToleranceKind total_kind) {
      constexpr int kSamples = 20001;
      std::vector<double> x(kSamples), d(kSamples);
      for (int i = 0; i < kSamples; ++i) {
        x[i] = start + (end - start) * i / (kSamples - 1);
        d[i] = slope * (x[i] - mid) + form.value(x[i]);
      }
      const TraceEvaluation e = evaluate_trace(x, d);
      double worst = 0.0;
      auto ratio = [&](ToleranceKind kind, double value) {
        if (const auto t = tol.get_um(kind)) {
          EXPECT_LE(value, *t * kLimit * (1.0 + 1e-7));
          worst = std::max(worst, value / *t);
        }
      };
      ratio(slope_kind, std::abs(e.slope_um));
      ratio(form_kind, e.form_um);
      ratio(total_kind, e.total_um);
      EXPECT_NEAR(worst, kLimit, 1e-6);
      ++traces;
    };
    for (int k = 0; k < 4; ++k) {
      const PerturbedGear g = sampler.draw(k);
      for (const FlankDeviation& f : g.flanks) {
        check(r.profile_start_mm, r.profile_end_mm, f.profile_slope_um_per_mm, f.profile_mid_mm,
              f.profile_form, ToleranceKind::kProfileSlope, ToleranceKind::kProfileForm,
              ToleranceKind::kProfileTotal);
        check(r.helix_start_mm, r.helix_end_mm, f.helix_slope_um_per_mm, f.helix_mid_mm,
              f.helix_form, ToleranceKind::kHelixSlope, ToleranceKind::kHelixForm,
              ToleranceKind::kHelixTotal);
      }
    }
  }
  EXPECT_EQ(traces, 2 * 4 * 48 * 2);
}

}  // namespace
}  // namespace gearmc
