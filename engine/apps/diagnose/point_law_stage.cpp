// The point-law stage: residual laws with a uniform latch-delay part, the white-variance test
// and the BIC comparison of the model's law with a fitted noise or step quantisation (see
// point_law_stage.h).
#include "engine/apps/diagnose/point_law_stage.h"

#include "core/constants.h"
#include "core/special_functions.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>

#include <tbb/parallel_for.h>

#include "engine/apps/diagnose/linear_model.h"
#include "engine/apps/diagnose/selection.h"

namespace gearmc {
namespace {

constexpr double kInvSqrt2 = 0.70710678118654752440;
// Stream sub-index of the white-variance null simulation (selection steps use 0, 1, 2; the gap
// null 1000).
constexpr std::uint32_t kWhiteNullSubIndex = 2000;
// A Gaussian part below this (µm) is treated as this: a model with a purely uniform law would
// give the data zero density outside its support.
constexpr double kMinSigmaUm = 1e-4;

double upper_tail(double z) { return 0.5 * std::erfc(z * kInvSqrt2); }   // Q(z) = 1 − Φ(z)
double lower_tail(double z) { return 0.5 * std::erfc(-z * kInvSqrt2); }  // Φ(z)
double log_phi(double z) { return -0.5 * z * z - 0.5 * std::log(2.0 * std::numbers::pi); }
// G(z) = ∫Φ = z Φ(z) + φ(z).
double integral_of_phi(double z) { return z * lower_tail(z) + std::exp(log_phi(z)); }

// Σd²/(6 m) of the second differences of `e` over `triplets`.
double white_variance(const Eigen::VectorXd& e, const std::vector<std::array<int, 3>>& triplets) {
  double s = 0.0;
  for (const auto& t : triplets) {
    const double d = e[t[0]] - 2.0 * e[t[1]] + e[t[2]];
    s += d * d;
  }
  return s / (6.0 * static_cast<double>(triplets.size()));
}

// Σ_a |Qᵀc_a|² over the triplets: how much of the second differences' weight the fit's
// projection (orthonormal columns q) takes; E[v_w] = v (1 − this / (6 m)) under the null.
double projected_difference_weight(const Eigen::MatrixXd& q,
                                   const std::vector<std::array<int, 3>>& triplets) {
  if (q.cols() == 0) return 0.0;
  double total = 0.0;
  for (const auto& t : triplets) {
    total += (q.row(t[0]) - 2.0 * q.row(t[1]) + q.row(t[2])).squaredNorm();
  }
  return total;
}

// Maximises f on [lo, hi]: the best of a grid of 41 points, then Brent's method (parabolic
// interpolation safeguarded by golden-section steps; R. P. Brent, "Algorithms for Minimization
// without Derivatives", 1973, ch. 5, procedure fmin) on the bracket of its neighbours (f assumed
// unimodal there), to a bracket of 1e-9 of the range: about 10 evaluations of f where golden
// section alone takes 40 (each is a pass over every reading).
template <class F>
double maximise(F f, double lo, double hi) {
  constexpr int kGrid = 41;
  int best = 0;
  double best_value = -std::numeric_limits<double>::infinity();
  for (int k = 0; k < kGrid; ++k) {
    const double x = lo + (hi - lo) * k / (kGrid - 1);
    const double value = f(x);
    if (value > best_value) {
      best_value = value;
      best = k;
    }
  }
  double a = lo + (hi - lo) * std::max(0, best - 1) / (kGrid - 1);
  double b = lo + (hi - lo) * std::min(kGrid - 1, best + 1) / (kGrid - 1);
  const double golden = 0.5 * (3.0 - std::sqrt(5.0));
  const double tol_abs = 0.25e-9 * std::max(1.0, std::abs(hi - lo));
  // Brent's minimisation of g = −f: x the best point, w the second best, v the previous w.
  double x = a + golden * (b - a), w = x, v = x;
  double gx = -f(x), gw = gx, gv = gx;
  double d = 0.0, e = 0.0;
  for (int it = 0; it < 100; ++it) {
    const double mid = 0.5 * (a + b);
    const double tol = 1e-10 * std::abs(x) + tol_abs, tol2 = 2.0 * tol;
    if (std::abs(x - mid) <= tol2 - 0.5 * (b - a)) break;
    bool parabolic = false;
    if (std::abs(e) > tol) {  // a parabola through x, w, v
      const double r = (x - w) * (gx - gv);
      double q = (x - v) * (gx - gw);
      double p = (x - v) * q - (x - w) * r;
      q = 2.0 * (q - r);
      if (q > 0.0) p = -p;
      q = std::abs(q);
      const double e_before = e;
      e = d;
      if (std::abs(p) < std::abs(0.5 * q * e_before) && p > q * (a - x) && p < q * (b - x)) {
        d = p / q;
        const double u = x + d;
        if (u - a < tol2 || b - u < tol2) d = x < mid ? tol : -tol;
        parabolic = true;
      }
    }
    if (!parabolic) {
      e = (x < mid ? b : a) - x;
      d = golden * e;
    }
    const double u = x + (std::abs(d) >= tol ? d : (d > 0.0 ? tol : -tol));
    const double gu = -f(u);
    if (gu <= gx) {
      (u < x ? b : a) = x;
      v = w;
      gv = gw;
      w = x;
      gw = gx;
      x = u;
      gx = gu;
    } else {
      (u < x ? a : b) = u;
      if (gu <= gw || w == x) {
        v = w;
        gv = gw;
        w = u;
        gw = gu;
      } else if (gu <= gv || v == x || v == w) {
        v = u;
        gv = gu;
      }
    }
  }
  const double edge = lo + (hi - lo) * best / (kGrid - 1);
  return -gx >= best_value ? x : edge;
}

// The least-squares projection onto the complement of a set of columns, with the pieces the
// profile likelihood needs: ε(μ) = P⊥ r + μ (1 − P⊥ 1) for a law of mean μ.
// The basis q (n × rank) is kept only when asked for (the white-variance test needs it).
struct Projection {
  Eigen::MatrixXd q;
  Eigen::VectorXd r_perp, one_perp;
  int columns = 0;
  Projection(const Eigen::MatrixXd& x, const Eigen::VectorXd& r, bool keep_basis = false) {
    q = orthonormal_basis(x).q;
    columns = static_cast<int>(q.cols());
    const Eigen::VectorXd one = Eigen::VectorXd::Ones(r.size());
    r_perp = r - q * (q.transpose() * r);
    one_perp = one - q * (q.transpose() * one);
    if (!keep_basis) release_basis();
  }
  void release_basis() { q.resize(0, 0); }
  Eigen::VectorXd residual(double mean) const {
    return r_perp + mean * (Eigen::VectorXd::Ones(r_perp.size()) - one_perp);
  }
  int rank() const { return columns; }
};

// Σ log f(e_i). Above kLikelihoodChunk points in chunks of that many, summed in parallel and
// then in chunk order (the same value for any number of threads).
constexpr int kLikelihoodChunk = 1 << 16;
double log_likelihood(const Eigen::VectorXd& e, const ResidualLaw& law) {
  const int n = static_cast<int>(e.size());
  auto sum = [&](int from, int to) {
    double s = 0.0;
    for (int i = from; i < to; ++i) s += law.log_density(e[i]);
    return s;
  };
  if (n <= kLikelihoodChunk) return sum(0, n);
  const int chunks = (n + kLikelihoodChunk - 1) / kLikelihoodChunk;
  std::vector<double> part(static_cast<std::size_t>(chunks));
  tbb::parallel_for(0, chunks, [&](int c) {
    part[static_cast<std::size_t>(c)] =
        sum(c * kLikelihoodChunk, std::min(n, (c + 1) * kLikelihoodChunk));
  });
  double s = 0.0;
  for (double v : part) s += v;
  return s;
}

}  // namespace

// The joint cumulant of d_a, d_a, d_b, d_b of sums of independent terms (Isserlis' theorem when
// κ₄ = 0).
double white_sum_variance(const std::vector<std::array<int, 3>>& triplets, double v,
                          double kappa4) {
  const std::array<double, 3> c = {1.0, -2.0, 1.0};
  double total = 0.0;
  for (std::size_t a = 0; a < triplets.size(); ++a) {
    // Triplets of one scan are consecutive in the list; overlaps are at most 2 apart.
    for (std::size_t b = a >= 2 ? a - 2 : 0; b < std::min(triplets.size(), a + 3); ++b) {
      double cov = 0.0, fourth = 0.0;
      for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) {
          if (triplets[a][i] == triplets[b][j]) {
            cov += c[i] * c[j];
            fourth += c[i] * c[i] * c[j] * c[j];
          }
        }
      }
      total += 2.0 * v * v * cov * cov + kappa4 * fourth;
    }
  }
  return total;
}

double ResidualLaw::log_density(double r) const {
  const double sigma = std::max(sigma_um, kMinSigmaUm);
  const double x = r - offset_um;
  if (width_um <= 1e-9 * sigma) return log_phi(x / sigma) - std::log(sigma);
  const double a = (x + width_um) / sigma, b = x / sigma;  // a > b
  const double mass = b > 0.0 ? upper_tail(b) - upper_tail(a) : lower_tail(a) - lower_tail(b);
  if (mass > 1e-300) return std::log(mass / width_um);
  // Far in a tail: the mass is ≈ the tail beyond the nearer edge, φ(z)/|z| (Mills ratio).
  const double z = b > 0.0 ? b : a;
  return log_phi(z) - std::log(std::abs(z)) - std::log(width_um);
}

double ResidualLaw::cdf(double r) const {
  const double x = r - offset_um;
  if (sigma_um < kMinSigmaUm) {
    if (width_um <= 0.0) return x >= 0.0 ? 1.0 : 0.0;
    return std::clamp((x + width_um) / width_um, 0.0, 1.0);
  }
  if (width_um <= 1e-9 * sigma_um) return lower_tail(x / sigma_um);
  const double value = sigma_um / width_um *
                       (integral_of_phi((x + width_um) / sigma_um) - integral_of_phi(x / sigma_um));
  return std::clamp(value, 0.0, 1.0);
}

double ResidualLaw::draw(RandomStream& rng) const {
  const double e = sigma_um * rng.normal();
  return offset_um + e - width_um * rng.uniform();
}

ResidualLaw residual_law(const PointLaw& law) {
  ResidualLaw out;
  double variance = law.gaussian_variance_um2;
  std::vector<double> widths = law.uniform_widths_um;
  std::sort(widths.begin(), widths.end());
  if (!widths.empty()) {
    out.width_um = widths.back();
    widths.pop_back();
  }
  for (double w : widths) variance += w * w / 12.0;
  out.sigma_um = std::sqrt(std::max(0.0, variance));
  out.offset_um = 0.5 * out.width_um;
  return out;
}

double ks_distance(std::vector<double> values, const ResidualLaw& law) {
  return ks_distance(std::move(values), [&law](double x) { return law.cdf(x); });
}

const PointLawHypothesis* PointLawStage::find(const std::string& name) const {
  const PointLawHypothesis* best_of = nullptr;
  for (const PointLawHypothesis& h : hypotheses) {
    if (h.name == name && (!best_of || h.bic < best_of->bic)) best_of = &h;
  }
  return best_of;
}

PointLawStage point_law_stage(const Eigen::VectorXd& r, const Eigen::MatrixXd& x_selected,
                              const std::vector<ResidualPoint>& points, const NoiseFloor& floor,
                              const PointLawOptions& options) {
  PointLawStage stage;
  if (floor.source != NoiseFloorSource::kModel) {
    stage.skipped_because = "the noise floor is not the model's own (" +
                            std::string(spelling(floor.source)) +
                            "): it says nothing about the spread of a reading";
    return stage;
  }
  const ResidualLaw law0 = residual_law(floor.law);
  const double v0 = law0.variance_um2();
  stage.model_variance_um2 = v0;
  if (!(v0 > 0.0)) {
    stage.skipped_because = "the model has no random part";
    return stage;
  }
  const std::vector<std::array<int, 3>> triplets = scan_triplets(points);
  stage.differences = static_cast<int>(triplets.size());
  if (triplets.empty()) {
    stage.skipped_because = "no profile scans of three consecutive points";
    return stage;
  }
  stage.ran = true;
  const int n = static_cast<int>(r.size());
  const double ln_n = std::log(static_cast<double>(n));

  // Constant columns of X_S (a radius error, a pre-travel p0, a quantisation mean).
  std::vector<int> all, varying;
  bool has_constant = false;
  for (int c = 0; c < x_selected.cols(); ++c) {
    all.push_back(c);
    const auto col = x_selected.col(c);
    const double spread = col.maxCoeff() - col.minCoeff();
    if (spread <= 1e-9 * std::max(1.0, col.cwiseAbs().maxCoeff())) {
      has_constant = true;
    } else {
      varying.push_back(c);
    }
  }
  auto columns_of = [&](const std::vector<int>& which, bool add_constant) {
    Eigen::MatrixXd x(n, static_cast<int>(which.size()) + (add_constant ? 1 : 0));
    for (std::size_t k = 0; k < which.size(); ++k)
      x.col(static_cast<int>(k)) = x_selected.col(which[k]);
    if (add_constant) x.col(x.cols() - 1).setOnes();
    return x;
  };

  Projection full(columns_of(all, false), r, /*keep_basis=*/true);
  // The leverage correction (PointLawOptions::leverage_correction): residuals in the likelihoods
  // scaled by 1/√(1 − p/n), the white variance divided by its expectation factor.
  const double residual_scale =
      options.leverage_correction && n > full.rank()
          ? std::sqrt(static_cast<double>(n) / static_cast<double>(n - full.rank()))
          : 1.0;
  auto log_likelihood_of = [&](const Eigen::VectorXd& e, const ResidualLaw& law) {
    return residual_scale == 1.0 ? log_likelihood(e, law) : log_likelihood(residual_scale * e, law);
  };
  double white_scale = 1.0;
  if (options.leverage_correction && !triplets.empty()) {
    const double m = static_cast<double>(triplets.size());
    const double factor = 1.0 - projected_difference_weight(full.q, triplets) / (6.0 * m);
    if (factor > 0.0) white_scale = 1.0 / factor;
  }
  // Model law.
  PointLawHypothesis model;
  model.name = "model";
  model.columns = all;
  model.law = law0;
  model.parameters = full.rank();
  model.residual = full.residual(law0.mean_um());
  model.log_likelihood = log_likelihood_of(model.residual, law0);
  model.bic = -2.0 * model.log_likelihood + model.parameters * ln_n;
  stage.hypotheses.push_back(model);

  // White variance and its null.
  stage.white_variance_um2 = white_scale * white_variance(model.residual, triplets);
  stage.white_excess_rms_um = std::sqrt(std::max(0.0, stage.white_variance_um2 - v0));
  if (options.null_replicates > 0 && !options.white_normal_approximation) {
    // In parallel: replicate k from its own stream into its own slot (any number of threads
    // gives the same values).
    std::vector<double> null_values(static_cast<std::size_t>(options.null_replicates));
    tbb::parallel_for(0, options.null_replicates, [&](int k) {
      Eigen::VectorXd e(n);
      RandomStream rng(options.seed, static_cast<std::uint32_t>(k), kDiagnoseNullStream,
                       kWhiteNullSubIndex);
      for (int i = 0; i < n; ++i) e[i] = law0.draw(rng);
      const Eigen::VectorXd e_perp = e - full.q * (full.q.transpose() * e);
      null_values[static_cast<std::size_t>(k)] = white_scale * white_variance(e_perp, triplets);
    });
    stage.white_p = empirical_p_value(stage.white_variance_um2, null_values);
  } else {
    const double m = static_cast<double>(triplets.size());
    const double w = law0.width_um;
    const double kappa4 = -w * w * w * w / 120.0;  // a uniform part's; a Gaussian's is 0
    const double sd = white_scale *
                      std::sqrt(std::max(0.0, white_sum_variance(triplets, v0, kappa4))) /
                      (6.0 * m);
    const double mean =
        white_scale * v0 * (1.0 - projected_difference_weight(full.q, triplets) / (6.0 * m));
    stage.white_p = upper_tail((stage.white_variance_um2 - mean) / sd);
  }
  full.release_basis();  // the alternatives need only its projections

  // The alternatives.
  const double rms = std::sqrt(model.residual.squaredNorm() / n);
  const double sigma0 = law0.sigma_um;
  auto finish = [&](PointLawHypothesis h, const Projection& proj, auto law_of, double lo,
                    double hi) {
    auto profile = [&](double theta) {
      const ResidualLaw law = law_of(theta);
      return log_likelihood_of(proj.residual(law.mean_um()), law);
    };
    const double theta = maximise(profile, lo, hi);
    h.estimate = theta;
    h.law = law_of(theta);
    h.residual = proj.residual(h.law.mean_um());
    h.log_likelihood = log_likelihood_of(h.residual, h.law);
    h.parameters = proj.rank() + 1;
    h.bic = -2.0 * h.log_likelihood + h.parameters * ln_n;
    h.delta_bic = h.bic - model.bic;
    const double step = 1e-3 * std::max(theta, 1e-2 * (hi - lo));
    if (theta - step > lo) {
      const double curvature =
          (profile(theta + step) - 2.0 * h.log_likelihood + profile(theta - step)) / (step * step);
      if (curvature < 0.0) h.std_error = 1.0 / std::sqrt(-curvature);
    }
    // β of the kept columns: the least-squares fit of r − mean(law).
    Eigen::MatrixXd x = columns_of(h.columns, h.constant_added);
    const Eigen::VectorXd shifted = r - h.law.mean_um() * Eigen::VectorXd::Ones(n);
    h.beta = least_squares(x, shifted).beta;
    stage.hypotheses.push_back(std::move(h));
  };

  {  // noise: the Gaussian part's σ
    PointLawHypothesis h;
    h.name = "noise";
    h.columns = all;
    auto law_of = [&](double sigma) {
      ResidualLaw law = law0;
      law.sigma_um = sigma;
      return law;
    };
    finish(std::move(h), full, law_of, 0.05 * std::sqrt(v0), 3.0 * std::max(rms, std::sqrt(v0)));
  }
  const double w_max = 2.0 * (std::sqrt(12.0) * rms + 2.0 * std::abs(r.mean())) + law0.width_um;
  auto step_law = [&](double w) {
    ResidualLaw law;
    law.sigma_um = sigma0;
    law.width_um = w;
    law.offset_um = law0.offset_um;  // the prediction contains −q₀/2
    return law;
  };
  {  // step_quantization, tied: the constant columns dropped
    PointLawHypothesis h;
    h.name = "step_quantization";
    h.tied = true;
    h.columns = varying;
    const Projection proj(columns_of(varying, false), r);
    finish(std::move(h), proj, step_law, 0.0, w_max);
  }
  {  // step_quantization, free: with a constant column (a radius error as well)
    PointLawHypothesis h;
    h.name = "step_quantization";
    h.columns = all;
    h.constant_added = !has_constant;
    const Projection proj(columns_of(all, h.constant_added), r);
    finish(std::move(h), proj, step_law, 0.0, w_max);
  }

  // Acceptance.
  const bool white = stage.white_p < options.alpha &&
                     stage.white_excess_rms_um >= options.min_effect_rms_fraction * std::sqrt(v0);
  for (std::size_t k = 1; k < stage.hypotheses.size(); ++k) {
    PointLawHypothesis& h = stage.hypotheses[k];
    const double extra = h.law.variance_um2() - v0;
    if (!white) {
      h.note = "no white excess variance in the second differences";
    } else if (stage.white_variance_um2 - v0 < options.white_fraction * extra) {
      h.note = "its extra variance is not white (structure along the scans)";
    } else if (h.delta_bic > -options.min_delta_bic) {
      h.note = "ΔBIC not below −" + std::to_string(static_cast<int>(options.min_delta_bic));
    } else {
      h.accepted = true;
    }
  }
  for (std::size_t k = 1; k < stage.hypotheses.size(); ++k) {
    if (stage.hypotheses[k].accepted &&
        (stage.chosen == 0 || stage.hypotheses[k].bic < stage.best().bic)) {
      stage.chosen = static_cast<int>(k);
    }
  }
  if (stage.chosen > 0) {
    for (std::size_t k = 1; k < stage.hypotheses.size(); ++k) {
      const PointLawHypothesis& h = stage.hypotheses[k];
      if (h.accepted && h.name != stage.best().name && stage.find(h.name) == &h &&
          h.bic - stage.best().bic < options.ambiguity_delta_bic) {
        stage.ambiguous.push_back(static_cast<int>(k));
      }
    }
  }
  return stage;
}

}  // namespace gearmc
