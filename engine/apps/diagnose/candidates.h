// Step 2 of the discrepancy diagnosis: the candidate effects' design matrices. Each
// candidate of docs/formats.md's library is a group of columns, one per linear parameter, whose
// entry at a point is the first-order change of the reading along n (µm) per unit of that
// parameter — taken from the effect's own signature() (engine/effects), evaluated on a freshly
// constructed effect with zero parameters (thermal expansion: workpiece CTE 11.5 ppm/K for steel,
// scale CTE 0, the library's defaults), so that the columns are exactly the library's
// first-order signatures:
//
//   probe_lobing       pretravel_um (−1), and for each order k (default 3 and 6) the cos/sin
//                      pair cos_k_um = −cos kφ, sin_k_um = −sin kφ: the signature with respect
//                      to the amplitude of a harmonic of phase 0 and of phase 90°/k. Linear in
//                      (p0, a_k cos kφ_k, a_k sin kφ_k); converted back to amplitude and phase
//                      by the fit (diagnosis.h). Calibration strategy `none` (the
//                      qualification's share is what the model already predicts).
//   stylus_radius      error_um (−1)
//   scale              x_ppm, y_ppm, z_ppm (1e-3 c_i n_i, c = p + R n)
//   thermal_expansion  workpiece_delta_t_k (11.5e-3 c·n)
//   drift              x_um, y_um, z_um (f n_i, f = order / (sequence_length − 1))
//   squareness         xy_urad, xz_urad, yz_urad
//   eccentricity       x_um, y_um (n_x, n_y)
//   step_quantization  step_um (−1/2: the mean latch delay, the library's first-order signature)
//   probe_warmup       change_um (−w(s), the warm-up's weight at the default time constant 0.3
//                      of the sequence: exact when the truth has that constant, first-order
//                      otherwise)
//   straightness       xy_um, xz_um, yx_um, yz_um (n_x (c_y/L)², …; L = 100 mm, the default)
//   rotary_table       radial_cos_um, radial_sin_um, axial_cos_um, axial_sin_um (not observable
//                      on a spur gear: n_z = 0), angular_cos_1_arcsec … angular_sin_2_arcsec, at
//                      the table angle θ_k = 2π(k − 1)/z of the point's tooth (rotary_table.h)
//   stylus_bending     deflection_um (−sin²γ for a vertical stylus: −1 on every spur-gear flank,
//                      the same column as stylus_radius)
//   clocking           angle_urad (1e-3 (ẑ × p)·n: ±r_b·1e-3 on an involute flank's two sides)
//   artefact_form      left_/right_ × profile_2/3, helix_2/3 _um (P_k of the normalised roll length
//                      or face position on the point's own side, 0 on the other: the artefact's
//                      form, exact), with the evaluation ranges taken from the measured points
//                      (the smallest and largest roll length and z), written to `settings`.
//                      Not a default candidate: only when CandidateOptions::only names it
//                      (`diagnose --candidates …,artefact_form`). Its helix and profile columns
//                      are the P₂, P₃ columns of an empirical term along face position or roll
//                      length, and the term's refit beside the library (refit_with_empirical in
//                      diagnosis_gap.cpp) assumes the joint design has full rank: with both, the
//                      fitted.yaml it writes double-counts the shared part.
//
// No candidate is an intercept and the base model has none: a constant shift along n is itself a
// physical effect here (stylus radius error, uncompensated pre-travel p0, the quantisation mean),
// so a free intercept would make those three unidentifiable and hide them; the model's
// prediction is taken as unbiased until an effect says otherwise.
//
// A column that vanishes on the probing plan (on a spur gear n_z = 0, so scale z and drift z)
// or that repeats an earlier column of the same candidate is marked not observable: it gets no
// estimate and is reported as such.
#pragma once

#include <Eigen/Core>
#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

#include "engine/effects/measurement_effect.h"

namespace gearmc {

struct CandidateDesign {
  std::string name;                       // docs/formats.md's effect name
  std::vector<std::string> coefficients;  // one per column, e.g. "x_ppm", "cos_6_um"
  std::vector<std::string> units;         // unit of each coefficient
  Eigen::MatrixXd x;                      // points × columns, µm of reading per unit
  std::vector<bool> observable;           // column carries information on this plan
  // Settings the columns were made with, as a scenario's keys (artefact_form's ranges).
  std::vector<std::pair<std::string, double>> settings;
  // The observable columns only (what the selection and fits use).
  Eigen::MatrixXd observable_columns() const;
  // x itself when every column is observable, otherwise a copy of the observable ones in `copy`.
  const Eigen::MatrixXd& observable_columns(Eigen::MatrixXd& copy) const;
  std::vector<int> observable_indices() const;
};

// The settings the probe_warmup and straightness candidates are built with (the effects'
// defaults, engine/schema/scenario_keys.cpp).
inline constexpr double kWarmupTimeConstant = 0.3;
inline constexpr double kStraightnessLengthMm = 100.0;

struct CandidateOptions {
  std::vector<int> lobing_orders = {3, 6};  // harmonic orders of the probe_lobing candidate
  // When not empty: only these library effects are candidates (names of
  // candidate_effect_names(), e.g. to compare the null false-positive rate of a smaller library).
  std::vector<std::string> only;
};

// The library's order of candidates (docs/formats.md): probe_lobing, stylus_radius, scale,
// thermal_expansion, drift, squareness, eccentricity, step_quantization, probe_warmup,
// straightness, rotary_table, stylus_bending, clocking, artefact_form (ties in the selection are
// broken in this order).
const std::vector<std::string>& candidate_effect_names();

// The measured points' contexts read in place from an array of records that each hold one (a
// vector of PointContext, or of residual points: no copy of 10⁶ contexts).
class PointContexts {
 public:
  PointContexts(const std::vector<PointContext>& v)  // NOLINT: implicit on purpose
      : first_(reinterpret_cast<const char*>(v.data())),
        size_(v.size()),
        stride_(sizeof(PointContext)) {}
  template <class Record>
  PointContexts(const std::vector<Record>& v, PointContext Record::*member)
      : first_(v.empty() ? nullptr : reinterpret_cast<const char*>(&(v.front().*member))),
        size_(v.size()),
        stride_(sizeof(Record)) {}
  std::size_t size() const { return size_; }
  bool empty() const { return size_ == 0; }
  // The `count` contexts from `begin` on (a view of the same records).
  PointContexts slice(std::size_t begin, std::size_t count) const {
    PointContexts s = *this;
    s.first_ = first_ + begin * stride_;
    s.size_ = count;
    return s;
  }
  const PointContext& operator[](std::size_t i) const {
    return *reinterpret_cast<const PointContext*>(first_ + i * stride_);
  }

 private:
  const char* first_;
  std::size_t size_, stride_;
};

// The candidates' design matrices at `points` (PointContext of each measured point: nominal p
// and n in the CMM frame, mm; approach azimuth; order within its gear's sequence).
std::vector<CandidateDesign> candidate_designs(const PointContexts& points,
                                               const CandidateOptions& options = {});

// The candidates' designs compressed for the selection and the ambiguity checks, which use the
// columns only through their inner products: [X_1 … X_C, y] (every candidate's columns, then the
// residuals) = Q R by Householder QR of row chunks of 4 096 points and QR of the chunks' stacked
// triangles (the tall-skinny QR of Demmel, Grigori, Hoemmen & Langou, SIAM J. Sci. Comput. 34,
// 2012), and each candidate's x replaced by its columns of R (m + 1 rows for m columns), the
// residuals by R's last column. Q has orthonormal columns, so X_iᵀX_j = R_iᵀR_j, X_iᵀy = R_iᵀr and
// |y|² = |r|²: every nested fit, F statistic, rank decision (relative norms), condition number
// and canonical correlation is the one of the N rows, up to rounding, while no N-row matrix of
// all candidates is ever held (a chunk at a time per thread). The chunks are fixed and the
// triangles stacked in chunk order: the same R for any number of threads. `rows` keeps N for
// the degrees of freedom. Observable columns are decided on the compressed columns (the same
// norms and inner products).
struct CompressedDesigns {
  std::vector<CandidateDesign> candidates;  // x: (m + 1) × the candidate's columns
  Eigen::VectorXd residual_um;              // m + 1 entries
  int rows = 0;                             // N, the points (N − k with a base: below)
  // With a base: per candidate, the smallest canonical correlation of its observable columns with
  // the base's span (1: wholly inside it, 0: some direction orthogonal to it); empty without.
  std::vector<double> base_correlation;
};
CompressedDesigns compressed_candidate_designs(const PointContexts& points,
                                               const Eigen::VectorXd& residual_um,
                                               const CandidateOptions& options = {});

// The same with the columns and the residuals first projected off the span of `base_q` (N × k
// orthonormal columns: a production gear's own deviations, part_model.h): the selection then
// tests each candidate on what the base cannot explain (Frisch–Waugh–Lovell), `rows` = N − k for
// the degrees of freedom. A column with less than 1e-6 of its norm outside the base's span is not
// observable. Built from the N-row columns at once (a production gear's diagnosis is one gear or
// a few; part_model.h kMaxPartCells bounds the base).
CompressedDesigns compressed_candidate_designs(const PointContexts& points,
                                               const Eigen::VectorXd& residual_um,
                                               const CandidateOptions& options,
                                               const Eigen::MatrixXd& base_q);

// The N-row observable columns of candidates `which` (indices into `compressed`, which says
// which columns are observable), side by side in that order: what the joint fit needs.
Eigen::MatrixXd full_columns(const PointContexts& points, const CandidateOptions& options,
                             const std::vector<CandidateDesign>& compressed,
                             const std::vector<int>& which);

// What extra measurement would tell effects `a` and `b` apart when this plan cannot (one
// sentence, for diagnosis.json and the report).
std::string separating_measurement(std::string_view a, std::string_view b);

}  // namespace gearmc
