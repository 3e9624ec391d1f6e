// The readings' own resolution: are the measured deviations along the normal printed on a grid
// (a CMM or gear program that exports deviations to 0.1 µm, a table rounded by hand)? Then every
// residual is a rounded number, and the gap's Kolmogorov–Smirnov test sees the lumps of the
// rounding against any smooth law (six null data sets printed to 0.1 µm with noise 0.3 µm were all
// reported as "unexplained structure"), while nothing about the machine is missing. What rounding
// does to a reading is a statement about its law, not structure.
//
// Test: the Rayleigh statistic of the readings' phases on steps s = k · 0.01 µm, k = 1 … 1000
// (as coordinate_grid.h for coordinates: Mardia & Jupp, Directional Statistics, 2000, §6.3.1),
// R(s) = |(1/n) Σ exp(2πi m_i / s)|, m the measured deviations (µm) — 1 when every reading is a
// multiple of s (plus any common offset), whatever the offset; the step is the largest s with
// R ≥ 0.999 (printed numbers lie on their grid exactly; a looser threshold would take a coarse
// rounding with few distinct values for another step) and s below the readings' spread (2 × their
// standard deviation: a grid coarser than the spread is the same as readings that hardly vary), n ≥
// 100 readings. Under continuous readings P(n R² ≥ x) ≈ e^(−x): with n ≥ 100 the chance of a false
// grid over the 1000 steps is below 1000 e^(−25) ≈ 1e-8.
//
// What the diagnosis then does (diagnosis.cpp prepare_residuals): each residual is dithered by its
// own u_i ~ U(−s/2, s/2), drawn in the readings' order from the counter-based stream (seed, 0,
// kDiagnoseNull, sub-index 4000), which makes the rounded reading continuous again with the law of
// the reading spread over its rounding cell (the randomised continuity correction; to O(s²) the
// unrounded law convolved with the cell), and the model's per-point law gains what rounding and
// dither add: s²/12 of Gaussian variance (the rounding, Sheppard's correction) and a uniform part
// of width s (the dither). The effects are fitted on the dithered residuals (the dither adds s²/12
// of variance, 0.0008 µm² at 0.1 µm).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "engine/apps/diagnose/prediction.h"

namespace gearmc {

struct ReadingGrid {
  bool ran = false;
  std::string skipped_because;
  double step_um = 0.0;    // 0: the readings are not on a grid
  double resultant = 0.0;  // R at the step
  bool found() const { return step_um > 0.0; }
};

ReadingGrid detect_reading_grid(const std::vector<ResidualPoint>& points);

// Adds u_i ~ U(−s/2, s/2) to every residual (see above); `seed` the diagnosis's.
void dither_readings(std::vector<ResidualPoint>& points, double step_um, std::uint64_t seed);

}  // namespace gearmc
