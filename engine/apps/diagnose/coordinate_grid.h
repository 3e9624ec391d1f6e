// The coordinate-grid stage of the discrepancy diagnosis: do the readings' coordinates lie on a
// grid per axis, as they do when the CMM's scales latch them with a finite resolution
// (engine/effects/scale_resolution.h)? Along the flank normal the latching adds a zero-mean spread
// Σ n_i² s_i²/12 that, once the probing noise is added, is close to Gaussian: the point-law stage
// (point_law_stage.h) would see only "more noise". What identifies it is the lattice itself: the
// recorded coordinates are integer multiples of the step. So this stage looks at the coordinates,
// not at the residuals.
//
// Test (per axis a, on the recorded centres c and on the compensated points E = c − R n):
// the mean resultant length of the phases 2π c_a / s (the Rayleigh statistic of circular
// statistics: Mardia & Jupp, Directional Statistics, 2000, §6.3.1),
//   R(s) = |(1/n) Σ exp(2πi c_a,k / s)|,
// is 1 when every coordinate is a multiple of s and of order 1/√n when the coordinates' fractional
// parts are spread over the grid. Steps tried: s = k · 0.01 µm, k = 1 … 1000 (a grid of step s is
// also a grid of 0.01 µm when s is a multiple of it, so k = 1 is tried first and nothing else when
// it fails); the step is the largest s with R(s) ≥ 0.5. Under the null (coordinates not latched,
// fractional parts uniform) P(n R² ≥ x) ≈ e^(−x) (Rayleigh), so with n ≥ 100 points the chance of
// any false grid over the 2 × 3 × 1000 steps is below 6000 · e^(−25) ≈ 1e-7. Steps at which the
// nominal points p themselves lie on the grid (R ≥ 0.5 for p_a: e.g. z sections at round face
// positions) are not taken: those coordinates cannot show a latching. An axis along which no normal
// has a component (z on a spur gear: n_z = 0) is not observable: its grid changes no reading and
// it is not searched.
//
// The grid is `named` (reported as the effect scale_resolution, diagnosis.h) when the model's own
// scale_resolution does not have these steps and its spread along n, √(mean Σ n_i² s_i²/12), is of
// practical size: at least min_effect_rms_fraction of the noise floor (the selection's rule,
// selection.h). A finer grid (e.g. an export printing 0.1 µm) is reported, not named.
//
// A step larger than the probing noise makes the latching error a deterministic function of each
// point's position (the coordinate is rounded, not blurred): readings of points whose positions
// repeat (the gear's symmetry, the same profile position in every section) share their errors, and
// the residuals' distribution is lumpy, which the gap's Kolmogorov–Smirnov test rejects against
// any smooth law. latched_model_check tests whether the latched model explains that: it simulates
// the model's readings at the same points — centre c₀ = p + (R + predicted/1000) n, per-axis
// noise N(0, σ₀²) (σ₀ the model's noise floor without the grid's spread), then latched on the grid
// — and compares the data's KS distance against N(0, σ²) (σ the floor with the spread) and RMS with
// the simulations' (p-values (1 + #{sim ≥ data})/(K + 1), the RMS two-sided, the smaller doubled
// for the two statistics). Other random parts of the model (probe repeatability, step
// quantisation) are not simulated: the check is for a model whose randomness is its noise.
#pragma once

#include <array>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "engine/apps/diagnose/prediction.h"
#include "engine/readings/readings_csv.h"

namespace gearmc {

struct CoordinateGridAxis {
  double step_um = 0.0;     // the grid's step (0: no grid found on this axis)
  double resultant = 0.0;   // R(step)
  bool observable = false;  // some reading's normal has a component along this axis
};

struct LatchedModelCheck {
  bool ran = false;
  int replicates = 0;
  double ks = std::numeric_limits<double>::quiet_NaN();  // the data's KS distance
  double rms_um = std::numeric_limits<double>::quiet_NaN();
  double p = std::numeric_limits<double>::quiet_NaN();  // min(1, 2 min(p_ks, p_rms))
};

struct CoordinateGrid {
  bool ran = false;
  std::string skipped_because;
  std::string points;  // "recorded_centres" or "compensated_points" (where a grid was found)
  std::array<CoordinateGridAxis, 3> axes;  // x, y, z
  double rms_um = 0.0;       // √(mean over readings of Σ n_i² s_i²/12) of the observable axes
  double false_alarm = 0.0;  // the bound on the chance of a grid this strong without latching
  bool in_model = false;     // the model's scale_resolution has these steps
  bool named = false;
  std::string note;
  LatchedModelCheck check;  // made by the diagnosis when the grid is named or in the model
  bool found() const {
    for (const CoordinateGridAxis& a : axes) {
      if (a.observable && a.step_um > 0.0) return true;
    }
    return false;
  }
};

// The mean resultant length R = |(1/n) Σ exp(2πi v/step)| of `values` on a grid of `step` (the
// same unit): 1 when every value is a multiple of the step plus one common offset (the Rayleigh
// statistic, above). Shared with the readings' own grid (reading_grid.h).
double grid_resultant(const std::vector<double>& values, double step);

// The stage on `readings` (rows marked in `excluded` left out) with the model's scale_resolution
// steps (µm per axis, 0 = none) and the noise floor σ (µm).
CoordinateGrid detect_coordinate_grid(const Readings& readings, const std::vector<bool>& excluded,
                                      const std::array<double, 3>& model_steps_um,
                                      double noise_floor_um, double min_effect_rms_fraction);

// The latched model's check on `points` (residuals and predictions, µm) with the grid's
// `steps_um` per axis (0: not latched), the noise before latching σ₀ and the floor σ (µm).
LatchedModelCheck latched_model_check(const std::vector<ResidualPoint>& points,
                                      const std::array<double, 3>& steps_um, double sigma_before_um,
                                      double sigma_um, int replicates, std::uint64_t seed);

}  // namespace gearmc
