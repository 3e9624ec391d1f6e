// The cubic B-spline's per-span polynomials (built from the precomputed CubicBSplineBasis) and
// its exact value ranges, against an independent evaluation: the Cox-de Boor recursion of the
// B-spline basis on the clamped uniform knot vector (de Boor 1972; Piegl & Tiller, The NURBS
// Book, eq. 2.5), with the derivatives as lower-degree splines of the coefficient differences
// (Piegl & Tiller eq. 3.3: C' = sum p (c_{i+1} - c_i) / (u_{i+p+1} - u_{i+1}) N_{i+1,p-1}).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "gears/deviations.h"

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

}  // namespace
}  // namespace gearmc
