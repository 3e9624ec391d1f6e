// The runs' own set-ups in the diagnosis of repeated measurements. Readings of several runs of
// one gear — a master measured three times, or a production gear in set-ups turned on the table
// (`--turned-by`) — each have their own set-up: the gear re-clamped, or the machine drifted
// between runs, moves it by a shift (x, y) and a turn about its axis (z). The differences of the
// runs' set-ups from the first run's are not the machine's errors; left out of the model, they
// are what the selection sees first, and an effect with a pattern around the gear (the rotary
// table, an eccentricity "per run") takes them, while a drift common to every run drowns in them.
// So, like a production gear's own deviations (part_model.h), they join the base of every model
// when the readings show them: per run g ≥ 1 (the gear index of the readings, the first run the
// reference) the columns
//   shift_x  n_x            (µm of reading per µm)
//   shift_y  n_y
//   turn     1e-3 (ẑ × p)·n (µm of reading per µrad, ±r_b·1e-3 on an involute flank)
// on run g's rows, 0 elsewhere — the same physics as the `eccentricity` and `clocking` effects,
// which stay candidates for what is common to every run. They join when the F test of their
// columns on the residuals (after the part's, for a production gear), beside the set-up common to
// every run, rejects at the selection's α: F = ((RSS₀ − RSS₁)/k) / (RSS₁/(n − p_base − p₁)), RSS₀
// with the common columns alone, RSS₁ with the differences too, k the rank they add, p₁ the rank
// of both (Seber & Lee, "Linear
// Regression Analysis", 2003, §4.3). Their values come from the joint fit with the effects.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "engine/apps/diagnose/prediction.h"

namespace gearmc {

// The set-up columns of runs 1 … G − 1 (three per run, in the order shift_x, shift_y, turn), with
// the runs' gear numbers (gears[0] the reference run). No columns for a single run.
struct SetupColumns {
  std::vector<int> gears;
  Eigen::MatrixXd x;       // points × 3 (G − 1)
  Eigen::MatrixXd common;  // points × 3: the same three columns on every run's rows
};
SetupColumns setup_columns(const std::vector<ResidualPoint>& points);

// One run's set-up relative to the first run's, with standard errors (from the joint fit).
struct SetupRun {
  int gear = 0;
  double shift_x_um = 0.0, shift_y_um = 0.0, turn_urad = 0.0;
  double shift_x_se_um = 0.0, shift_y_se_um = 0.0, turn_se_urad = 0.0;
};

struct SetupDifferences {
  bool tested = false;  // two or more runs (master readings, or set-ups of one gear)
  bool fitted = false;  // the F test rejected: the columns are in every model
  double f = 0.0, p_value = 1.0;
  int columns = 0;             // their rank
  double rms_um = 0.0;         // RMS over the points of the set-up differences fitted
  std::vector<SetupRun> runs;  // runs 1 … G − 1 (fitted only)
};

// The F test of `x` (the set-up columns, already projected off the base: a production gear's part)
// beside `common` (the set-up common to every run, projected alike: the differences are tested
// against a model that has it, or a shift shared by every run would pass for differences) on `r`
// (the residuals, projected off the same base) with `dof` = n − p_base degrees of freedom before;
// `alpha` the level. Fills tested, fitted, f, p_value, columns.
SetupDifferences test_setup_differences(const Eigen::MatrixXd& x, const Eigen::MatrixXd& common,
                                        const Eigen::VectorXd& r, int dof, double alpha);

}  // namespace gearmc
