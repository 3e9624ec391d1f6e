// The stages of one diagnosis (diagnosis.h, steps 3–8) and the state they hand on to each other:
// diagnosis.cpp selects and fits the effects, judges their ambiguity and runs the point-law
// stage; diagnosis_gap.cpp measures the gap before and after (with the held-out check, the null
// simulation of its statistics, the spectrum and the cluster-aware evidence) and makes the
// verdict; diagnosis_grid.cpp adds the coordinate grid's part. Internal to engine/apps/diagnose.
// Residuals in µm.
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "engine/apps/diagnose/diagnosis.h"
#include "engine/apps/diagnose/linear_model.h"

namespace gearmc::diagnosis_stages {

struct State {
  State(const Residuals& residuals_in, const NoiseFloor& noise_in,
        const DiagnoseOptions& options_in)
      : residuals(residuals_in), noise(noise_in), options(options_in) {}
  const Residuals& residuals;
  const NoiseFloor& noise;
  const DiagnoseOptions& options;
  int rows = 0;
  // Residuals before: measured − predicted, and for a production gear less the part's own
  // deviations fitted alone (the part's columns, part_model.h, in `part`; p_base their rank).
  Eigen::VectorXd r;
  Eigen::VectorXd r_measured;  // measured − predicted, before the part's fit is taken out
  PartColumns part;
  // The runs' set-up differences (setup_model.h), in the base when their F test rejects.
  SetupColumns setup;
  bool setup_in_base = false;
  // The base of every model: the part's columns, then the set-ups' (base_x), an orthonormal basis
  // of their span (base_q) and its rank p_base. Empty for a master measured once.
  Eigen::MatrixXd base_x, base_q;
  int p_base = 0;
  std::vector<double> azimuths;  // approach azimuth of each residual, rad
  // The candidates with compressed columns (compressed_candidate_designs: R's columns, m + 1
  // rows).
  std::vector<CandidateDesign> candidates;
  // Steps 3–4: the selected effects' joint columns and fit, each effect's first column.
  Eigen::MatrixXd x_selected;
  LeastSquaresFit fit;
  std::vector<int> offsets;
  // Step 4b: the laws of a residual before and after (the fitted point law, when one was
  // accepted, centred by its mean), the columns fitted out after, their parameter count, the
  // point law's mean (the shift a tied step explains) and the residuals after, centred.
  ResidualLaw law_before, law_after;
  Eigen::MatrixXd x_after;  // empty while the columns after are x_selected (no copy of n rows)
  int p_after = 0;
  double mean_after = 0.0;
  Eigen::VectorXd r_after;
  // Step 4c: true when an effect's values are fitted per gear (x_after, p_after and r_after then
  // hold that fit).
  bool per_gear_fit = false;
  // The columns fitted out after: x_after once a stage has set it, otherwise x_selected.
  const Eigen::MatrixXd& columns_after() const { return x_after_set ? x_after : x_selected; }
  bool x_after_set = false;
};

// Gap statistics of residual vector r (dof = points − fitted parameters) against the centred
// residual law `law` (χ² with its variance, KS against its distribution function).
GapStatistics gap_statistics(const Eigen::VectorXd& r, int dof, const ResidualLaw& law);
// The centred law of a residual under the noise floor: the model's per-point law, or a Gaussian
// of the floor's σ when the floor carries none (given, or estimated from the residuals).
ResidualLaw floor_law(const NoiseFloor& noise);

// Step 4c: for readings of several gears, whether each selected linear effect's value varies from
// gear to gear: the selected effects are fitted again with that effect's columns split into one
// copy per gear (the others shared), and the F test of the drop in RSS, with (G − 1)·q and
// n − rank degrees of freedom, decides at the selection's α (FittedEffect::varies_per_gear).
// The effects found to vary are then fitted per gear in the "after" state (x_after, p_after,
// r_after): the gap after is judged with one value per gear for them.
void per_gear_variation(State& state, Diagnosis& out);
// The largest per-gear design (rows × columns, doubles: 40 MB, a few times that while it is
// solved) per_gear_variation builds.
inline constexpr double kMaxPerGearCells = 5e6;

// Step 5: the gap before and after and the held-out RMS.
void measure_gap(const State& state, Diagnosis& out);
// Steps 5–6: the null simulation of the gap statistics (their p-values), the spectrum and its
// null bands; then the cluster-aware evidence.
void simulate_null(const State& state, Diagnosis& out);
// Step 8: the verdict and its notes.
void make_verdict(const State& state, Diagnosis& out);

std::vector<double> to_vector(const Eigen::VectorXd& v);

// The two folds of the held-out check: the measured teeth alternately (sorted by gear and tooth
// number, so a plan of only odd teeth still splits), or with a single tooth its two flanks, or
// alternate face sections, or alternate profile points — the first of these that gives two
// folds each with more points than `columns` (the fitted parameters); `within_flanks` (a
// production gear, whose deviations are fitted per flank) only the splits that keep every flank
// in both folds (sections, profile points). `fold` is empty when none does; `why_none` then says
// so.
struct HeldOutSplit {
  std::string name;       // "alternating_teeth", "flanks", "alternating_sections",
                          // "alternating_profile_points" or "none"
  std::vector<int> fold;  // 0 or 1 per point
  std::string why_none;
};
HeldOutSplit held_out_split(const std::vector<ResidualPoint>& points, int columns,
                            bool within_flanks = false);

// The axis along which `residual_um` (one per point) varies most (Diagnosis::unexplained_along).
Diagnosis::StructureAxis structure_axis(const std::vector<ResidualPoint>& points,
                                        const std::vector<double>& residual_um);

// After the selection, the fit and the gap (diagnose_prepared): the coordinate grid of
// `prepared` (scale resolution) into `d` — named as the effect scale_resolution, or explaining a
// residual law the gap tests reject (diagnosis_grid.cpp).
void coordinate_grid_verdict(const PreparedResiduals& prepared, Diagnosis& d);

}  // namespace gearmc::diagnosis_stages
