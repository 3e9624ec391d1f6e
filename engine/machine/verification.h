// Machines drawn for a CMM's own verification results: the user's measured ISO 10360-2 length
// errors (docs/cmm.md, "Your verification results") condition the prior of machine_prior.h.
// To first order every length error is linear in the machine's parameters θ — the Legendre
// coefficients of the 21 functions, the three squareness errors and the probe's six lobing
// components (kinematic_machine.h, probing_test.h) — E = A θ, and θ's prior is Gaussian,
// N(0, diag(s²)). A measured error y_j = (A θ)_j + ε_j with ε_j ~ N(0, u_j²) (u_j the test's
// standard uncertainty for that length) makes the machines that agree with the measurement
// a Gaussian posterior (Bayesian linear regression; e.g. Gelman et al., "Bayesian Data
// Analysis", §14.2):
//   Σ_post = (Aᵀ U⁻¹ A + S⁻¹)⁻¹,  μ_post = Σ_post Aᵀ U⁻¹ y,
// drawn exactly (θ = μ + L z, L Lᵀ = Σ_post), then kept by the MPE tests as before. The probe's
// touch scatter σ has no part in a length error (the test's mean) and keeps its prior.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <vector>

#include "engine/machine/machine_prior.h"

namespace gearmc {

// One measured length error of the user's verification.
struct VerificationRow {
  int position = 0;  // index into length_test_positions()
  double length_mm = 0.0;
  double error_um = 0.0;
  double u_um = 0.0;  // standard uncertainty of the measured error
};

// The kinematic-plus-probe length error (µm) of the gauge of `length_mm` centred in the middle
// of the travel along position `position` (length_test.h's geometry, any length).
double length_error_um(const KinematicMachine& machine, const CmmProbe& probe, int position,
                       double length_mm, const LengthTestOptions& options = {});

// θ's layout: per axis a = x, y, z, per direction c = x, y, z: translation coefficients of orders
// 1 … order, then rotation coefficients 1 … order; then squareness xy, xz, yz; then the probe's
// c₂, s₂, c₃, s₃, c₄, s₄ (only with a probe prior).
int machine_parameter_count(const MachinePrior& prior, const ProbePrior& probe);
// The prior's standard deviations of θ (machine_prior.h's scales).
Eigen::VectorXd machine_prior_sd(const MachinePrior& prior, const ProbePrior& probe);
// The machine and probe θ describes (the probe's scatter `noise_um` given apart).
KinematicMachine machine_of(const MachinePrior& prior, const Eigen::VectorXd& theta);
CmmProbe probe_of(const MachinePrior& prior, const ProbePrior& probe, const Eigen::VectorXd& theta,
                  double noise_um);

struct MachinePosterior {
  Eigen::VectorXd mean;
  Eigen::MatrixXd factor;  // lower Cholesky factor of the posterior covariance
  // How far the rows move the machines: per row the posterior predictive mean and standard
  // deviation of its error (µm) — what the kept machines say of each measured length.
  std::vector<double> predicted_um, predicted_sd_um;
  // Whether the measured errors are what the prior's machines make: y ~ N(0, A S Aᵀ + U) under
  // the model, so yᵀ (A S Aᵀ + U)⁻¹ y ~ χ² with one degree of freedom per row; its upper tail.
  double chi_square = 0.0, p_value = 1.0;
};

// The posterior of θ given the rows (throws std::invalid_argument when a row's u_um is not > 0).
MachinePosterior verification_posterior(const MachinePrior& prior, const ProbePrior& probe,
                                        const std::vector<VerificationRow>& rows,
                                        const LengthTestOptions& options = {});

// Without a data sheet: the prior's scales (machine_prior.h's A and K) that make the measured
// errors most probable — type-II maximum likelihood, the log density of y ~ N(0, A S(A, K) Aᵀ + U)
// maximised over A on a log grid 0.1 … 30 µm and K on 30 … 5 000 mm/µm (41 × 41 points, each
// 1.15× the last). The machines are then drawn from the posterior under those scales, with no
// MPE to pass (docs/cmm.md).
LengthMpe prior_scales_from_table(MachineLayout layout, const Eigen::Vector3d& travel_mm, int order,
                                  const ProbePrior& probe, const std::vector<VerificationRow>& rows,
                                  const LengthTestOptions& options = {});

// Machine `index` drawn from the posterior (TrialStream(seed, index, kMachineDraw) normals), its
// probe's scatter from the probe prior (kProbeDraw).
void draw_from_posterior(const MachinePrior& prior, const ProbePrior& probe,
                         const MachinePosterior& posterior, std::uint64_t seed, std::uint64_t index,
                         KinematicMachine& machine, CmmProbe& probe_out);

}  // namespace gearmc
