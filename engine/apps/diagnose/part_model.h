// The workpiece's own deviations in the diagnosis of a production gear (`diagnose --workpiece
// production`). A master gear is nominal or calibrated (ref_dev_um), so every residual the model
// leaves is the machine's; a production gear has its own form, and that form is not a CMM error.
// So the model of a production gear always contains, per measured flank (gear, tooth, side), the
// low-order deviations a gear's flank has in the terms of ISO 1328-1:2013 and VDI/VDE 2607:
//   position      a₀                     (1: the flank's mean normal deviation; on the base
//                                          circle its tooth's pitch, runout and thickness)
//   profile       a₁ P₁(x), a₂ P₂(x)     (slope f_Hα = 2 a₁, crowning C_α = −1.5 a₂)
//   helix         b₁ P₁(y), b₂ P₂(y)     (slope f_Hβ = 2 b₁, crowning C_β = −1.5 b₂)
// with P₁(t) = t, P₂(t) = (3t² − 1)/2 (Legendre, Abramowitz & Stegun 22.2.10), x ∈ [−1, 1] the
// roll length L = √(r² − r_b²) normalised on the flank's measured range [L_from, L_to] and y ∈
// [−1, 1] the face position z on [z_from, z_to]. A deviation is material along the flank's
// outward normal (the reading's sign: docs/formats.md), so f_Hα is the rise of the slope line
// from the start of the measured roll length to its end (P₁(1) − P₁(−1) = 2) and the crowning the
// height of the middle over the ends (P₂(0) − P₂(±1) = −1.5). A term is left out when the flank
// has too few distinct positions along its axis (slope: 2, crowning: 3).
//
// The columns of every flank are fitted jointly with the machine effects; the machine effects are
// selected on what the part cannot explain (the candidates' columns and the residuals projected
// off the part's columns: Frisch–Waugh–Lovell, so every fit equals the joint fit; Seber & Lee,
// "Linear Regression Analysis", 2003, §3.7). A machine effect whose columns lie in the part's span
// cannot be told from the part on this set-up (a stylus radius error is a constant on every flank
// = the teeth's thickness; a profile slope on every tooth is the part or a scale error; a pitch
// pattern is the part or the rotary table): `confounded` says so, with the smallest canonical
// correlation of the candidate's columns with the part's (1: wholly inside) and what separates
// them.
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "engine/apps/diagnose/prediction.h"

namespace gearmc {

// The flank deviations the part model fits (the terms of one flank, in column order).
enum class PartTerm { kPosition, kProfileSlope, kProfileCrowning, kHelixSlope, kHelixCrowning };
inline constexpr int kPartTerms = 5;

// One measured flank of the part and where its columns are.
struct PartFlank {
  int gear = 0, tooth = 0;
  FlankSide side = FlankSide::kLeft;
  int points = 0;
  double profile_from_mm = 0.0, profile_to_mm = 0.0;  // measured roll lengths
  double face_from_mm = 0.0, face_to_mm = 0.0;        // measured face positions
  std::vector<PartTerm> terms;                        // the flank's columns, in order
  int first_column = 0;
};

// The part's columns at the points: block-diagonal by flank, dense (points × columns).
struct PartColumns {
  std::vector<PartFlank> flanks;
  Eigen::MatrixXd x;  // µm of reading per µm of each term
  Eigen::MatrixXd q;  // an orthonormal basis of x's columns (points × rank)
  int columns() const { return static_cast<int>(x.cols()); }
  int rank() const { return static_cast<int>(q.cols()); }
};

// The largest part design (points × columns doubles, 160 MB) a diagnosis builds.
inline constexpr double kMaxPartCells = 2e7;

// The part's columns at `points` (their nominal points, roll length from the gear's base radius,
// the radius r itself when the readings do not know it). Flanks are ordered by gear, tooth, side.
// Each gear index is its own workpiece, unless `turned_by_teeth` is given (one entry per gear
// index 0, 1, …): then every gear index is a measurement of the same gear — repeated runs, or set-
// ups with the gear turned on the table — and in set-up g the plan's tooth t (the CMM's place)
// holds the gear's tooth ((t − 1 + turned_by_teeth[g]) mod z) + 1. The part's flank then follows
// the gear from place to place while the machine's errors stay at theirs: the reversal (closure)
// that separates the two (PartFlank::gear is 0, PartFlank::tooth the gear's tooth).
PartColumns part_columns(const std::vector<ResidualPoint>& points,
                         const std::vector<int>& turned_by_teeth = {});

// A flank deviation as a gear metrologist reads it, with its expanded uncertainty (k = 2).
struct PartValue {
  double value_um = 0.0;
  double u_um = 0.0;  // expanded, k = 2 (2 × the fit's standard error)
  bool estimable = false;
};

struct PartFlankDeviations {
  PartFlank flank;
  PartValue position, f_h_alpha, c_alpha, f_h_beta, c_beta;
};

// Per flank side, over the measured flanks: the mean slopes and crownings (ISO 1328-1's f_Hαm,
// f_Hβm) and the position's range (the pitch and runout pattern along the normal).
struct PartSideSummary {
  FlankSide side = FlankSide::kLeft;
  int flanks = 0;
  double f_h_alpha_mean_um = 0.0, f_h_alpha_min_um = 0.0, f_h_alpha_max_um = 0.0;
  double c_alpha_mean_um = 0.0;
  double f_h_beta_mean_um = 0.0, f_h_beta_min_um = 0.0, f_h_beta_max_um = 0.0;
  double c_beta_mean_um = 0.0;
  double position_mean_um = 0.0, position_range_um = 0.0;
  int estimable_alpha = 0, estimable_beta = 0;
};

// A machine candidate that the part's columns explain (wholly or mostly) on this set-up.
struct PartConfounding {
  std::string effect;
  double correlation = 0.0;        // smallest canonical correlation with the part's columns
  bool indistinguishable = false;  // every column inside the part's span (correlation ≥ 0.999)
  std::string separate_by;
};

struct PartDeviations {
  bool fitted = false;
  std::vector<int> turned_by_teeth;  // the set-ups (part_columns), empty: one per gear
  int columns = 0, rank = 0;
  std::vector<PartFlankDeviations> flanks;
  std::vector<PartSideSummary> sides;
  std::vector<PartConfounding> confounded;  // correlation ≥ kPartConfoundedCorrelation
  // The RMS of the part's fitted deviations over the points (µm).
  double fitted_rms_um = 0.0;
};
inline constexpr double kPartConfoundedCorrelation = 0.9;
inline constexpr double kPartIndistinguishable = 0.999;

// The part's deviations from the joint fit's coefficients `beta` of the part's columns (their
// order in `part`), their unscaled covariance block `cov` and the residual variance σ̂² (µm²).
PartDeviations part_deviations(const PartColumns& part, const Eigen::VectorXd& beta,
                               const Eigen::MatrixXd& cov, const std::vector<bool>& estimable,
                               double sigma2_um2);

// What separates machine effect `effect` from the part's own deviations (a measurement to make).
std::string separate_from_part(const std::string& effect);

}  // namespace gearmc
