// Machines drawn for a CMM's own verification results (verification.h).
#include "engine/machine/verification.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "core/random_stream.h"
#include "core/special_functions.h"

namespace gearmc {

double length_error_um(const KinematicMachine& machine, const CmmProbe& probe, int position,
                       double length_mm, const LengthTestOptions& options) {
  const Eigen::Vector3d u =
      length_test_positions(machine.travel_mm)[static_cast<std::size_t>(position)].direction;
  // The probe's pre-travel at the two ends (machine_prior.h: length_test_with_probe).
  return kinematic_length_error_um(machine, u, length_mm, options) -
         (probe.pretravel_um(u) + probe.pretravel_um(-u));
}

int machine_parameter_count(const MachinePrior& prior, const ProbePrior& probe) {
  return 3 * 3 * 2 * prior.order + 3 + (probe.mpe_p_um > 0.0 ? 6 : 0);
}

Eigen::VectorXd machine_prior_sd(const MachinePrior& prior, const ProbePrior& probe) {
  Eigen::VectorXd sd(machine_parameter_count(prior, probe));
  int j = 0;
  for (int a = 0; a < 3; ++a) {
    for (int c = 0; c < 3; ++c) {
      for (int k = 1; k <= prior.order; ++k) sd[j++] = prior.translation_um[a] / k;
      for (int k = 1; k <= prior.order; ++k) sd[j++] = prior.rotation_urad / k;
    }
  }
  for (int i = 0; i < 3; ++i) sd[j++] = prior.squareness_urad;
  if (probe.mpe_p_um > 0.0) {
    for (int i = 0; i < 6; ++i) sd[j++] = probe.component_um;
  }
  return sd;
}

KinematicMachine machine_of(const MachinePrior& prior, const Eigen::VectorXd& theta) {
  KinematicMachine m;
  m.layout = prior.layout;
  m.travel_mm = prior.travel_mm;
  int j = 0;
  const auto order = static_cast<std::size_t>(prior.order);
  for (std::size_t a = 0; a < 3; ++a) {
    for (std::size_t c = 0; c < 3; ++c) {
      auto& t = m.axes[a].translation_um[c];
      auto& r = m.axes[a].rotation_urad[c];
      t.assign(order + 1, 0.0);
      r.assign(order + 1, 0.0);
      for (std::size_t k = 1; k <= order; ++k) t[k] = theta[j++];
      for (std::size_t k = 1; k <= order; ++k) r[k] = theta[j++];
    }
  }
  m.squareness_xy_urad = theta[j++];
  m.squareness_xz_urad = theta[j++];
  m.squareness_yz_urad = theta[j++];
  return m;
}

CmmProbe probe_of(const MachinePrior& prior, const ProbePrior& probe, const Eigen::VectorXd& theta,
                  double noise_um) {
  CmmProbe p;
  p.noise_um = noise_um;
  if (!(probe.mpe_p_um > 0.0)) return p;
  int j = 3 * 3 * 2 * prior.order + 3;
  for (std::size_t k = 0; k < 3; ++k) {
    p.cos_um[k] = theta[j++];
    p.sin_um[k] = theta[j++];
  }
  return p;
}

namespace {

// A: each row's error per unit of each parameter (exact: the errors are linear in θ and zero for
// θ = 0).
Eigen::MatrixXd unit_responses(const MachinePrior& prior, const ProbePrior& probe,
                               const std::vector<VerificationRow>& rows,
                               const LengthTestOptions& options) {
  const int n = machine_parameter_count(prior, probe);
  const auto m = static_cast<Eigen::Index>(rows.size());
  Eigen::MatrixXd a(m, n);
  for (int j = 0; j < n; ++j) {
    Eigen::VectorXd unit = Eigen::VectorXd::Zero(n);
    unit[j] = 1.0;
    const KinematicMachine machine = machine_of(prior, unit);
    const CmmProbe p = probe_of(prior, probe, unit, 0.0);
    for (Eigen::Index i = 0; i < m; ++i) {
      const VerificationRow& r = rows[static_cast<std::size_t>(i)];
      a(i, j) = length_error_um(machine, p, r.position, r.length_mm, options);
    }
  }
  return a;
}

// The measured errors y and their variances u².
void measured(const std::vector<VerificationRow>& rows, Eigen::VectorXd& y,
              Eigen::VectorXd& noise) {
  const auto m = static_cast<Eigen::Index>(rows.size());
  y.resize(m);
  noise.resize(m);
  for (Eigen::Index i = 0; i < m; ++i) {
    const VerificationRow& r = rows[static_cast<std::size_t>(i)];
    if (!(r.u_um > 0.0)) throw std::invalid_argument("a verification row's u_um must be > 0");
    y[i] = r.error_um;
    noise[i] = r.u_um * r.u_um;
  }
}

}  // namespace

MachinePosterior verification_posterior(const MachinePrior& prior, const ProbePrior& probe,
                                        const std::vector<VerificationRow>& rows,
                                        const LengthTestOptions& options) {
  const Eigen::MatrixXd a = unit_responses(prior, probe, rows, options);
  const auto m = a.rows();
  Eigen::VectorXd y, noise;
  measured(rows, y, noise);
  // Woodbury's form (S = diag(s²) may have zeros — a scale set to 0 fixes its parameter):
  //   K = S Aᵀ (A S Aᵀ + U)⁻¹,  μ = K y,  Σ = S − K A S.
  const Eigen::VectorXd s2 = machine_prior_sd(prior, probe).array().square();
  const Eigen::MatrixXd sat = s2.asDiagonal() * a.transpose();  // S Aᵀ, n × m
  Eigen::MatrixXd innovation = a * sat;                         // A S Aᵀ
  innovation.diagonal() += noise;
  const Eigen::LDLT<Eigen::MatrixXd> solve(innovation);
  const Eigen::MatrixXd gain = solve.solve(sat.transpose()).transpose();  // K, n × m
  MachinePosterior post;
  post.mean = gain * y;
  post.chi_square = y.dot(solve.solve(y));
  post.p_value = regularized_gamma_q(0.5 * static_cast<double>(m), 0.5 * post.chi_square);
  Eigen::MatrixXd cov = Eigen::MatrixXd(s2.asDiagonal()) - gain * sat.transpose();
  cov = 0.5 * (cov + cov.transpose());
  // A square root of the covariance by its eigenvalues (semi-definite when a scale is 0).
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(cov);
  post.factor = eig.eigenvectors() * eig.eigenvalues().cwiseMax(0.0).cwiseSqrt().asDiagonal();
  const Eigen::VectorXd predicted = a * post.mean;
  for (Eigen::Index i = 0; i < m; ++i) {
    post.predicted_um.push_back(predicted[i]);
    const double v = (a.row(i) * cov * a.row(i).transpose())(0, 0);
    post.predicted_sd_um.push_back(std::sqrt(std::max(0.0, v)));
  }
  return post;
}

LengthMpe prior_scales_from_table(MachineLayout layout, const Eigen::Vector3d& travel_mm, int order,
                                  const ProbePrior& probe, const std::vector<VerificationRow>& rows,
                                  const LengthTestOptions& options) {
  // The unit responses do not depend on the scales: A once, then S per grid point.
  MachinePrior shape = prior_for(LengthMpe{1.0, 1.0}, layout, travel_mm);
  shape.order = order;
  const Eigen::MatrixXd a = unit_responses(shape, probe, rows, options);
  Eigen::VectorXd y, noise;
  measured(rows, y, noise);
  LengthMpe best{1.0, 300.0};
  double best_log = -std::numeric_limits<double>::infinity();
  for (int ia = 0; ia < 41; ++ia) {
    for (int ik = 0; ik < 41; ++ik) {
      const LengthMpe mpe{0.1 * std::pow(30.0 / 0.1, ia / 40.0),
                          30.0 * std::pow(5000.0 / 30.0, ik / 40.0)};
      MachinePrior prior = prior_for(mpe, layout, travel_mm);
      prior.order = order;
      const Eigen::VectorXd s2 = machine_prior_sd(prior, probe).array().square();
      Eigen::MatrixXd cov = a * s2.asDiagonal() * a.transpose();
      cov.diagonal() += noise;
      const Eigen::LLT<Eigen::MatrixXd> llt(cov);
      if (llt.info() != Eigen::Success) continue;
      const double log_det = 2.0 * llt.matrixLLT().diagonal().array().log().sum();
      const double log_density = -0.5 * (y.dot(llt.solve(y)) + log_det);
      if (log_density > best_log) {
        best_log = log_density;
        best = mpe;
      }
    }
  }
  return best;
}

void draw_from_posterior(const MachinePrior& prior, const ProbePrior& probe,
                         const MachinePosterior& posterior, std::uint64_t seed, std::uint64_t index,
                         KinematicMachine& machine, CmmProbe& probe_out) {
  TrialStream rng(seed, index, TrialPurpose::kMachineDraw);
  Eigen::VectorXd z(posterior.mean.size());
  for (Eigen::Index i = 0; i < z.size(); ++i) z[i] = rng.normal();
  const Eigen::VectorXd theta = posterior.mean + posterior.factor * z;
  machine = machine_of(prior, theta);
  probe_out = probe_of(prior, probe, theta, draw_probe(probe, seed, index).noise_um);
}

}  // namespace gearmc
