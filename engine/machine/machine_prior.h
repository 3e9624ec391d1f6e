// Machines drawn for a data sheet: the first half of the constrained Monte Carlo of virtual CMMs
// (Phillips et al., "A constrained Monte Carlo simulation method for the calculation of CMM
// measurement uncertainty", Precision Engineering; PTB's virtual CMM, Trapet et al.): draw many
// possible machines from a prior over the 21 error functions (kinematic_machine.h), simulate the
// ISO 10360-2 length test on each (length_test.h), and keep those whose length errors all lie
// within the stated MPE_E = A + L/K. What is known of the real machine is then what its kept
// siblings have in common.
//
// The prior (an assumption, stated in docs/cmm.md): every function's Legendre coefficients of
// orders k = 1 … order are independent N(0, (s/k)²) — smoother functions more likely than wiggly
// ones, no constant term (a constant translation is an offset of the whole volume; the squareness
// carries the constant angular part) — with the scales taken from the MPE itself: translations
// s = (T_a/2)/K µm (a positioning error of that size at the end of the travel is the L/K term's
// slope), rotations s = 1e3 A/(2 · 300 mm) µrad (an Abbe arm of 300 mm turns it into half of A),
// squareness N(0, (1e3/K)²) µrad (the L/K slope again, as a shear). Every scale can be set.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <vector>

#include "engine/machine/kinematic_machine.h"
#include "engine/machine/length_test.h"
#include "engine/machine/probing_test.h"

namespace gearmc {

struct MachinePosterior;  // verification.h

// ISO 10360-2's MPE_E = A + L/K (µm, L in mm).
struct LengthMpe {
  double a_um = 0.0;
  double k_mm_per_um = 0.0;
  double at(double length_mm) const { return a_um + length_mm / k_mm_per_um; }
};

// Reads "A + L/K" (spaces free; A ≥ 0, K > 0), e.g. "1.8 + L/300". Throws std::invalid_argument
// saying what was expected.
LengthMpe parse_length_mpe(const std::string& text);

struct MachinePrior {
  MachineLayout layout = MachineLayout::kBridge;
  Eigen::Vector3d travel_mm = Eigen::Vector3d(700.0, 1000.0, 600.0);
  int order = 3;
  Eigen::Vector3d translation_um = Eigen::Vector3d::Zero();  // s per axis
  double rotation_urad = 0.0;
  double squareness_urad = 0.0;
};

// The prior above for a machine of `layout` and `travel_mm` with MPE_E `mpe`.
MachinePrior prior_for(const LengthMpe& mpe, MachineLayout layout,
                       const Eigen::Vector3d& travel_mm);

// Machine `index` of the draw with `seed` (TrialStream(seed, index, kMachineDraw)).
KinematicMachine draw_machine(const MachinePrior& prior, std::uint64_t seed, std::uint64_t index);

// The probe's prior (an assumption, docs/cmm.md), scaled by ISO 10360-5's MPE_P: each lobing
// component c_k, s_k (k = 2, 3, 4) N(0, (MPE_P/6)²), the touch scatter σ ~ U(0, MPE_P/4).
// mpe_p_um 0: the machines have no probing part (a perfect, qualified probe).
struct ProbePrior {
  double mpe_p_um = 0.0;
  double component_um = 0.0;
  double noise_max_um = 0.0;
};
ProbePrior probe_prior_for(double mpe_p_um);
// Machine `index`'s probe (TrialStream(seed, index, kProbeDraw): a geometry draw does not move
// when a probe is added).
CmmProbe draw_probe(const ProbePrior& prior, std::uint64_t seed, std::uint64_t index);

struct ConstrainedMachines {
  std::vector<KinematicMachine> kept;
  std::vector<CmmProbe> probes;  // the kept machines' probes (all zero without MPE_P)
  // Per kept machine: max over its length test of |E| / MPE_E(L), and its P_FTU (µm).
  std::vector<double> length_ratio, probing_form_um;
  int drawn = 0;
  int failed_length = 0, failed_probing = 0;  // drawn machines refused by each test
  double acceptance_rate = 0.0;
  double largest_ratio = 0.0;     // max over the kept machines' tests of |E| / MPE_E(L)
  double largest_error_um = 0.0;  // max over the kept machines' tests of |E|
  bool refused = false;           // fewer than wanted kept within max_draws
  std::string why;                // when refused
};

// The length errors of `machine` with `probe` (length_test plus, at the gauge's two ends, the
// probe's pre-travel along the two approaches: E −= p(û) + p(−û); a bidirectional measurement
// sees the probe's even lobes, not its odd ones).
std::vector<LengthError> length_test_with_probe(const KinematicMachine& machine,
                                                const CmmProbe& probe,
                                                const LengthTestOptions& test = {});

// Draws machines 0, 1, … until `wanted` pass (every |E| ≤ MPE_E(L) in the length test with
// `test`, and with a probe prior P_FTU ≤ MPE_P) or `max_draws` were drawn — or, with
// `min_acceptance` > 0, once 2000 were drawn with fewer than that fraction kept (refused early:
// the rate would not reach it). With `posterior` (the user's verification results,
// verification.h) the machines are drawn from it instead of the prior.
ConstrainedMachines draw_constrained(const MachinePrior& prior, const LengthMpe& mpe, int wanted,
                                     int max_draws, std::uint64_t seed,
                                     const LengthTestOptions& test = {},
                                     const ProbePrior& probe = {}, double min_acceptance = 0.0,
                                     const MachinePosterior* posterior = nullptr);

}  // namespace gearmc
