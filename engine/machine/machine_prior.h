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

namespace gearmc {

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

struct ConstrainedMachines {
  std::vector<KinematicMachine> kept;
  int drawn = 0;
  double acceptance_rate = 0.0;
  double largest_ratio = 0.0;  // max over the kept machines' tests of |E| / MPE_E(L)
  bool refused = false;        // fewer than wanted kept within max_draws
  std::string why;             // when refused
};

// Draws machines 0, 1, … until `wanted` pass (every |E| ≤ MPE_E(L) in the length test with
// `test`) or `max_draws` were drawn.
ConstrainedMachines draw_constrained(const MachinePrior& prior, const LengthMpe& mpe, int wanted,
                                     int max_draws, std::uint64_t seed,
                                     const LengthTestOptions& test = {});

}  // namespace gearmc
