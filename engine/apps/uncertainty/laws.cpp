// Implementation of laws.h. Formulas per law from JCGM 101:2008 §6.4 (cited per case); the
// curvilinear trapezoid's CDF is the integral of its density (JCGM 101 6.4.3.2).
#include "engine/apps/uncertainty/laws.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <numeric>
#include <stdexcept>

#include <Eigen/Eigenvalues>
#include <cstdio>

#include "core/constants.h"
#include "core/special_functions.h"
#include "engine/statistics/distribution_fit.h"

namespace gearmc::uncertainty {
namespace {

[[noreturn]] void bad(const std::string& why) { throw std::invalid_argument(why); }

// Curvilinear trapezoid CTr(a, b, d): half-width w = (b−a)/2, centre m; density
// g = ln((w+d)/max(|x−m|, w−d))/(4d) on |x−m| <= w+d (JCGM 101 6.4.3.2). G(t) = ∫_0^t g.
double ctr_half_integral(double w, double d, double t) {
  const double lo = w - d, hi = w + d;
  const double flat = std::log(hi / lo) / (4.0 * d);
  if (t <= lo) return t * flat;
  if (t >= hi) return 0.5;
  // ∫_lo^t ln(hi/τ) dτ = (t−lo) ln hi − [τ ln τ − τ]_lo^t
  const double tail = (t - lo) * std::log(hi) - (t * std::log(t) - t - lo * std::log(lo) + lo);
  return lo * flat + tail / (4.0 * d);
}

}  // namespace

const std::vector<std::string>& law_names() {
  static const std::vector<std::string> names = {
      "normal",    "uniform",     "triangular", "arcsine",  "trapezoidal", "curvilinear_trapezoid",
      "student_t", "exponential", "gamma",      "constant", "data"};
  return names;
}

std::string_view law_name(LawKind kind) { return law_names()[static_cast<std::size_t>(kind)]; }

std::string law_signature(std::string_view name) {
  if (name == "normal") return "[mean, sd]";
  if (name == "uniform" || name == "arcsine") return "[lo, hi]";
  if (name == "triangular") return "[lo, hi] or [lo, mode, hi]";
  if (name == "trapezoidal") return "[lo, hi, beta]";
  if (name == "curvilinear_trapezoid") return "[lo, hi, d]";
  if (name == "student_t") return "[mean, scale, dof]";
  if (name == "exponential") return "[mean]";
  if (name == "gamma") return "[mean, sd]";
  if (name == "constant") return "a number";
  if (name == "data") return "[x1, x2, ...] (at least 2 values, not all equal)";
  return "";
}

Law make_law(LawKind kind, std::vector<double> p) {
  const std::string name(law_name(kind));
  auto need = [&](std::size_t n) {
    if (p.size() != n) {
      bad(std::to_string(p.size()) + " parameter" + (p.size() == 1 ? "" : "s") + " given, " + name +
          " takes " + law_signature(name));
    }
  };
  for (double v : p) {
    if (!std::isfinite(v)) bad("parameters must be finite numbers");
  }
  Law law;
  law.kind_ = kind;
  switch (kind) {
    case LawKind::kNormal:
      need(2);
      if (!(p[1] > 0)) bad("sd must be > 0");
      break;
    case LawKind::kUniform:
    case LawKind::kArcsine:
      need(2);
      if (!(p[0] < p[1])) bad("lo must be < hi");
      break;
    case LawKind::kTriangular:
      if (p.size() == 2) p = {p[0], 0.5 * (p[0] + p[1]), p[1]};
      if (p.size() != 3) need(3);
      if (!(p[0] < p[2])) bad("lo must be < hi");
      if (!(p[1] >= p[0] && p[1] <= p[2])) bad("the mode must lie in [lo, hi]");
      break;
    case LawKind::kTrapezoidal:
      need(3);
      if (!(p[0] < p[1])) bad("lo must be < hi");
      if (!(p[2] >= 0 && p[2] <= 1)) bad("beta (top width / base width) must be in [0, 1]");
      break;
    case LawKind::kCurvilinearTrapezoid:
      need(3);
      if (!(p[0] < p[1])) bad("lo must be < hi");
      if (!(p[2] > 0 && p[2] < 0.5 * (p[1] - p[0]))) bad("d must be > 0 and < (hi - lo)/2");
      break;
    case LawKind::kStudentT:
      need(3);
      if (!(p[1] > 0)) bad("scale must be > 0");
      if (!(p[2] > 0)) bad("dof must be > 0");
      law.shape_ = p[2];
      break;
    case LawKind::kExponential:
      need(1);
      if (!(p[0] > 0)) bad("mean must be > 0");
      break;
    case LawKind::kGamma:
      need(2);
      if (!(p[0] > 0)) bad("mean must be > 0");
      if (!(p[1] > 0)) bad("sd must be > 0");
      law.shape_ = (p[0] / p[1]) * (p[0] / p[1]);
      law.scale_ = p[1] * p[1] / p[0];
      break;
    case LawKind::kConstant:
      need(1);
      break;
  }
  law.p_ = std::move(p);
  return law;
}

Law make_from_data(const std::vector<double>& x) {
  if (x.size() < 2) bad("data needs at least 2 values");
  for (double v : x) {
    if (!std::isfinite(v)) bad("data values must be finite numbers");
  }
  const double n = static_cast<double>(x.size());
  const double mean = std::accumulate(x.begin(), x.end(), 0.0) / n;
  double ss = 0.0;
  for (double v : x) ss += (v - mean) * (v - mean);
  const double s = std::sqrt(ss / (n - 1.0));
  if (!(s > 0)) bad("data values are all equal (no Type A spread)");
  return make_law(LawKind::kStudentT, {mean, s / std::sqrt(n), n - 1.0});
}

double Law::mean() const {
  const auto& p = p_;
  switch (kind_) {
    case LawKind::kNormal:
    case LawKind::kStudentT:
    case LawKind::kExponential:
    case LawKind::kGamma:
    case LawKind::kConstant:
      return p[0];
    case LawKind::kTriangular:
      return (p[0] + p[1] + p[2]) / 3.0;  // JCGM 101 6.4.5.3
    default:
      return 0.5 * (p[0] + p[1]);
  }
}

double Law::variance() const {
  const auto& p = p_;
  switch (kind_) {
    case LawKind::kNormal:
      return p[1] * p[1];
    case LawKind::kUniform:
      return (p[1] - p[0]) * (p[1] - p[0]) / 12.0;  // 6.4.2.3
    case LawKind::kTriangular: {                    // general triangle, Johnson et al.
      const double a = p[0], c = p[1], b = p[2];
      return (a * a + b * b + c * c - a * b - a * c - b * c) / 18.0;
    }
    case LawKind::kArcsine:
      return (p[1] - p[0]) * (p[1] - p[0]) / 8.0;  // 6.4.6.3
    case LawKind::kTrapezoidal:                    // 6.4.4.3
      return (p[1] - p[0]) * (p[1] - p[0]) * (1.0 + p[2] * p[2]) / 24.0;
    case LawKind::kCurvilinearTrapezoid:  // 6.4.3.3
      return (p[1] - p[0]) * (p[1] - p[0]) / 12.0 + p[2] * p[2] / 9.0;
    case LawKind::kStudentT:  // 6.4.9.3
      return p[2] > 2.0 ? p[1] * p[1] * p[2] / (p[2] - 2.0) : kInf;
    case LawKind::kExponential:
      return p[0] * p[0];
    case LawKind::kGamma:
      return p[1] * p[1];
    case LawKind::kConstant:
      return 0.0;
  }
  return 0.0;
}

double Law::sd() const { return std::sqrt(variance()); }

double Law::gum_u() const { return kind_ == LawKind::kStudentT ? p_[1] : sd(); }
double Law::gum_dof() const { return kind_ == LawKind::kStudentT ? p_[2] : kInf; }

double Law::cdf(double x) const {
  const auto& p = p_;
  if (std::isnan(x)) return x;
  switch (kind_) {
    case LawKind::kNormal:
      return normal_cdf((x - p[0]) / p[1]);
    case LawKind::kUniform:
      return std::clamp((x - p[0]) / (p[1] - p[0]), 0.0, 1.0);
    case LawKind::kTriangular: {
      const double a = p[0], c = p[1], b = p[2];
      if (x <= a) return 0.0;
      if (x >= b) return 1.0;
      if (x <= c) return (x - a) * (x - a) / ((b - a) * (c - a));
      return 1.0 - (b - x) * (b - x) / ((b - a) * (b - c));
    }
    case LawKind::kArcsine: {
      if (x <= p[0]) return 0.0;
      if (x >= p[1]) return 1.0;
      return 0.5 + std::asin((2.0 * x - p[0] - p[1]) / (p[1] - p[0])) / std::numbers::pi;
    }
    case LawKind::kTrapezoidal: {
      const double a = p[0], b = p[1], w = b - a;
      const double ramp = 0.5 * (1.0 - p[2]) * w;  // width of each sloping side
      const double h = 2.0 / (w * (1.0 + p[2]));   // height of the top
      if (x <= a) return 0.0;
      if (x >= b) return 1.0;
      if (x < a + ramp) return h * (x - a) * (x - a) / (2.0 * ramp);
      if (x > b - ramp) return 1.0 - h * (b - x) * (b - x) / (2.0 * ramp);
      return 0.5 * h * ramp + h * (x - a - ramp);
    }
    case LawKind::kCurvilinearTrapezoid: {
      const double w = 0.5 * (p[1] - p[0]), m = 0.5 * (p[0] + p[1]);
      const double t = x - m;
      const double g = ctr_half_integral(w, p[2], std::fabs(t));
      return t >= 0 ? 0.5 + g : 0.5 - g;
    }
    case LawKind::kStudentT:
      return student_t_cdf((x - p[0]) / p[1], p[2]);
    case LawKind::kExponential:
      return x <= 0 ? 0.0 : -std::expm1(-x / p[0]);
    case LawKind::kGamma:
      return x <= 0 ? 0.0 : regularized_gamma_p(shape_, x / scale_);
    case LawKind::kConstant:
      return x < p[0] ? 0.0 : 1.0;
  }
  return 0.0;
}

double Law::quantile(double q) const {
  const auto& p = p_;
  switch (kind_) {
    case LawKind::kNormal:
      return p[0] + p[1] * normal_quantile(q);
    case LawKind::kUniform:
      return p[0] + (p[1] - p[0]) * q;
    case LawKind::kTriangular: {
      const double a = p[0], c = p[1], b = p[2];
      if (q < (c - a) / (b - a)) return a + std::sqrt(q * (b - a) * (c - a));
      return b - std::sqrt((1.0 - q) * (b - a) * (b - c));
    }
    case LawKind::kArcsine:
      return 0.5 * (p[0] + p[1]) + 0.5 * (p[1] - p[0]) * std::sin(std::numbers::pi * (q - 0.5));
    case LawKind::kTrapezoidal: {
      const double a = p[0], b = p[1], w = b - a;
      const double ramp = 0.5 * (1.0 - p[2]) * w;
      const double h = 2.0 / (w * (1.0 + p[2]));
      const double corner = 0.5 * h * ramp;  // probability under one sloping side
      if (q < corner) return a + std::sqrt(2.0 * ramp * q / h);
      if (q > 1.0 - corner) return b - std::sqrt(2.0 * ramp * (1.0 - q) / h);
      return a + ramp + (q - corner) / h;
    }
    case LawKind::kCurvilinearTrapezoid:
      return invert_cdf([this](double x) { return cdf(x); }, q, p[0] - p[2], p[1] + p[2]);
    case LawKind::kStudentT:
      return p[0] + p[1] * student_t_quantile(q, p[2]);
    case LawKind::kExponential:
      return -p[0] * std::log1p(-q);
    case LawKind::kGamma:
      return invert_cdf([this](double x) { return cdf(x); }, q, 0.0, p[0] + 5.0 * p[1]);
    case LawKind::kConstant:
      return p[0];
  }
  return 0.0;
}

double Law::sample(TrialStream& s) const {
  const auto& p = p_;
  switch (kind_) {
    case LawKind::kNormal:
      return p[0] + p[1] * s.normal();
    case LawKind::kUniform:
    case LawKind::kTriangular:
    case LawKind::kArcsine:
    case LawKind::kTrapezoidal:
    case LawKind::kExponential:
      return quantile(s.uniform());  // inverse transform (JCGM 101 6.4.2.4, 6.4.5.4, 6.4.6.4)
    case LawKind::kCurvilinearTrapezoid: {
      // JCGM 101 6.4.3.4: a random lower limit a_s in [a−d, a+d], b_s = a + b − a_s, then
      // uniform on [a_s, b_s].
      const double as = (p[0] - p[2]) + 2.0 * p[2] * s.uniform();
      const double bs = p[0] + p[1] - as;
      return as + (bs - as) * s.uniform();
    }
    case LawKind::kStudentT: {
      // JCGM 101 6.4.9.5: μ + s z / sqrt(χ²_ν/ν), χ²_ν = 2 G(ν/2).
      const double z = s.normal();
      const double chi2 = 2.0 * sample_standard_gamma(0.5 * shape_, s);
      return p[0] + p[1] * z / std::sqrt(chi2 / shape_);
    }
    case LawKind::kGamma:
      return scale_ * sample_standard_gamma(shape_, s);
    case LawKind::kConstant:
      return p[0];
  }
  return 0.0;
}

namespace {

// Nodes and weights of the N-point Gauss–Hermite rule for the standard normal weight φ(z): the
// eigenvalues of the symmetric tridiagonal Jacobi matrix of the probabilists' Hermite polynomials
// (off-diagonal √k) and the squared first components of its eigenvectors (Golub–Welsch).
struct NormalRule {
  std::vector<double> z, w;
};
const NormalRule& normal_rule() {
  static const NormalRule rule = [] {
    constexpr int kN = 64;
    Eigen::MatrixXd j = Eigen::MatrixXd::Zero(kN, kN);
    for (int k = 1; k < kN; ++k) j(k, k - 1) = j(k - 1, k) = std::sqrt(static_cast<double>(k));
    const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(j);
    NormalRule r;
    for (int k = 0; k < kN; ++k) {
      r.z.push_back(eig.eigenvalues()[k]);
      r.w.push_back(eig.eigenvectors()(0, k) * eig.eigenvectors()(0, k));
    }
    return r;
  }();
  return rule;
}

// F⁻¹(Φ(z)), kept inside (0, 1) where Φ rounds to 0 or 1.
double through_copula(const Law& law, double z) {
  if (law.kind() == LawKind::kNormal) return law.parameters()[0] + law.parameters()[1] * z;
  const double u =
      std::clamp(normal_cdf(z), std::numeric_limits<double>::min(), std::nextafter(1.0, 0.0));
  return law.quantile(u);
}

void require_spread(const Law& law) {
  if (law.kind() == LawKind::kConstant || !(law.variance() > 0.0) ||
      !std::isfinite(law.variance())) {
    throw std::invalid_argument(
        "a law with a finite, non-zero variance (a correlation coefficient needs one; this " +
        std::string(law_name(law.kind())) + " has variance " + std::to_string(law.variance()) +
        ")");
  }
}

}  // namespace

double copula_input_correlation(const Law& a, const Law& b, double rho) {
  require_spread(a);
  require_spread(b);
  const NormalRule& r = normal_rule();
  const std::size_t n = r.z.size();
  const double c = std::sqrt(std::max(0.0, 1.0 - rho * rho));
  double mean_a = 0.0, mean_b = 0.0, var_a = 0.0, var_b = 0.0, cross = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    const double ga = through_copula(a, r.z[i]), gb = through_copula(b, r.z[i]);
    mean_a += r.w[i] * ga;
    mean_b += r.w[i] * gb;
    var_a += r.w[i] * ga * ga;
    var_b += r.w[i] * gb * gb;
    for (std::size_t k = 0; k < n; ++k) {
      cross += r.w[i] * r.w[k] * ga * through_copula(b, rho * r.z[i] + c * r.z[k]);
    }
  }
  // The moments by the same rule, so that ρ = 0 gives 0 and equal laws at ρ = 1 give 1.
  var_a -= mean_a * mean_a;
  var_b -= mean_b * mean_b;
  return (cross - mean_a * mean_b) / std::sqrt(var_a * var_b);
}

double copula_correlation_for(const Law& a, const Law& b, double r) {
  if (a.kind() == LawKind::kNormal && b.kind() == LawKind::kNormal) return r;
  constexpr double kEdge = 0.9999;
  const double lo_r = copula_input_correlation(a, b, -kEdge);
  const double hi_r = copula_input_correlation(a, b, kEdge);
  if (!(r > lo_r && r < hi_r)) {
    char text[160];
    std::snprintf(text, sizeof text, "a correlation these two laws can have: about %.3f … %.3f",
                  lo_r, hi_r);
    throw std::invalid_argument(text);
  }
  double lo = -kEdge, hi = kEdge;
  for (int it = 0; it < 60 && hi - lo > 1e-12; ++it) {
    const double mid = 0.5 * (lo + hi);
    (copula_input_correlation(a, b, mid) < r ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

}  // namespace gearmc::uncertainty
