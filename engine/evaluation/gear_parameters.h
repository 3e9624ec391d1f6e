// The ISO 1328-1:2013 flank parameters of a gear evaluated from deviation traces, the way
// gear-measuring software evaluates a measurement: profile (F_α, f_Hα, f_fα) and helix (F_β,
// f_Hβ, f_fβ) from a trace of normal deviations over its evaluation range, single and cumulative
// pitch (f_pt, F_p) from the flanks' positions on one circle, and radial runout (F_r) from a ball
// in every tooth space; and the size deviations a workshop gauges (ISO 21771 / DIN 3960): tooth
// thickness E_sn, base tangent length E_Wk, dimension over balls E_MdK. Pure functions of the
// deviations: the Monte-Carlo run feeds them measured and true deviations (parameter_evaluation.h).
// Deviations in µm along the nominal outward flank normal (+ = material added), lengths in mm, gear
// frame (axis +Z, tooth 1 on +X, teeth counter-clockwise).
#pragma once

#include <Eigen/Core>
#include <array>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "gears/involute_gear.h"
#include "gears/tolerances.h"

namespace gearmc {

// The parameters, in the order they are printed.
// The size deviations come last: E_sn (normal tooth thickness on the reference cylinder), E_Wk
// (base tangent length over k teeth), E_MdK (dimension over or between two balls), each the
// actual size minus the nominal (size_dimensions.h), µm, + = larger.
enum class GearParameter {
  kFalpha,
  kfHalpha,
  kffalpha,
  kFbeta,
  kfHbeta,
  kffbeta,
  kfpt,
  kFp,
  kFr,
  kEsn,
  kEWk,
  kEMdK
};
inline constexpr int kGearParameterCount = 12;
const std::array<GearParameter, kGearParameterCount>& all_gear_parameters();
// "F_alpha", "f_Halpha", "f_falpha", "F_beta", "f_Hbeta", "f_fbeta", "f_pt", "F_p", "F_r",
// "E_sn", "E_Wk", "E_MdK".
const std::string& parameter_symbol(GearParameter p);
std::optional<GearParameter> parameter_from_symbol(const std::string& symbol);
// Slope deviations are signed (tolerance ±T); the others are >= 0 (tolerance T). f_pt is
// reported per tooth, signed, with the tolerance ±f_pT. The size deviations are signed.
bool parameter_signed(GearParameter p);
// A size deviation (E_sn, E_Wk, E_MdK): not an ISO 1328-1 flank parameter, no tolerance class.
bool parameter_is_size(GearParameter p);
// Whether an item of the parameter takes both flanks (F_r and the sizes: reported as "both").
bool parameter_of_both_flanks(GearParameter p);
// The tolerance kind that bounds the parameter (F_α: kProfileTotal, …, f_pt: kSinglePitch);
// nullopt for the size deviations (their allowances are the drawing's, DIN 3967).
std::optional<ToleranceKind> parameter_tolerance_kind(GearParameter p);
// The parameter's tolerance in `tolerances`, µm (nullopt: none given, or a size deviation).
std::optional<double> parameter_tolerance_um(const ToleranceSet& tolerances, GearParameter p);

// A trace's ISO evaluation over [range_start, range_end] (ISO 1328-1:2013 §3.3, §3.4): only the
// samples within the range count; the mean line is their least-squares line (trapezoid-weighted,
// gears/deviations.h evaluate_trace); slope = mean line at range_end − at range_start (signed,
// + = more material at the range end: towards the tip for a profile, towards z = b for a helix);
// form = distance of the two parallels to the mean line that enclose the trace; total = distance
// of the two parallels to the design line (d = const) that enclose it = max − min.
struct TraceResult {
  double total_um = 0.0, slope_um = 0.0, form_um = 0.0;
  // The mean line d = intercept_um + slope_um_per_mm · (x − range_start), for charts.
  double intercept_um = 0.0, slope_um_per_mm = 0.0;
  int samples = 0;  // samples within the range
};
// x ascending (mm), d in µm. Needs at least 3 samples within the range (a sample within 1 µm of
// an end counts): nullopt otherwise.
std::optional<TraceResult> evaluate_trace_over(std::span<const double> x, std::span<const double> d,
                                               double range_start, double range_end);

// d(x) at `at` by linear interpolation of the samples (x ascending; clamped at the ends).
double interpolate_trace(std::span<const double> x, std::span<const double> d, double at);

// A flank's position on the measuring circle as an arc, µm, positive counter-clockwise, from its
// normal deviation d at that circle: a rotation of the flank by an arc t on the circle of
// pressure angle α_y moves an involute along its normal by t·cos α_y, so t = ±d / cos α_y with +
// for R flanks (their normal points counter-clockwise) and − for L flanks.
double flank_arc_position_um(FlankSide side, double normal_deviation_um,
                             double pressure_angle_at_circle_rad);

// Pitch from the arc positions u_k of the same-side flanks of teeth 1 … z, in tooth order
// (ISO 1328-1:2013 §3.2): the single pitch deviation of the pitch from tooth k to k + 1 (z to 1)
// f_pt,k = u_{k+1} − u_k (signed: + = the pitch is longer than nominal, measured
// counter-clockwise); the cumulative pitch deviations F_pk = u_k − u_1 and
// F_p = max_k F_pk − min_k F_pk; the gear's single pitch deviation max_k |f_pt,k|.
struct PitchResult {
  std::vector<double> single_um;  // f_pt,k, k = 1 … z
  double single_max_abs_um = 0.0;
  double cumulative_um = 0.0;  // F_p
};
PitchResult evaluate_pitch(std::span<const double> arc_positions_um);

// Radial runout with a ball in every tooth space (ISO 10064-4 / ISO 1328-2 F_r), to first order
// in the deviations: the ball of space k (between the R flank of tooth k and the L flank of
// tooth k + 1) touches them in the transverse plane at the nominal contact points with unit
// normals n_R, n_L pointing into the space; deviations d_R, d_L along those normals move its
// centre by Δ with n_R·Δ = d_R and n_L·Δ = d_L; the radial displacement is Δ·e, e the unit
// vector from the axis to the nominal ball centre. F_r = max − min over the spaces.
struct BallContact {
  Eigen::Vector2d normal_right, normal_left;  // transverse outward unit normals of the flanks
  Eigen::Vector2d radial;                     // unit vector towards the nominal ball centre
};
double ball_radial_displacement_um(const BallContact& contact, double d_right_um, double d_left_um);
// The whole displacement Δ of the ball's centre (transverse, µm; its radial component is the
// above): a ball between flanks of unequal deviations also moves sideways.
Eigen::Vector2d ball_displacement_um(const BallContact& contact, double d_right_um,
                                     double d_left_um);
// The nominal ball contacts of every space of `gear` at height z: the ball touches both flanks
// at roll length `contact_roll_length_mm`. Space k (0-based) lies between tooth k+1 and k+2.
std::vector<BallContact> ball_contacts(const InvoluteGear& gear, double contact_roll_length_mm,
                                       double z_mm);
// F_r from the flanks' deviations at the ball contacts: d_right[k] of the R flank of tooth k+1,
// d_left[k] of the L flank of tooth k+1 (0-based arrays over the teeth), µm.
double runout_um(const std::vector<BallContact>& contacts, std::span<const double> d_right_um,
                 std::span<const double> d_left_um);

// Size deviations, µm (+ = larger), to first order in the flanks' transverse deviations d (µm,
// + = material added, as in the traces):
// E_sn of one tooth from its flanks' deviations on the reference circle, where the pressure
// angle is α_t: each flank moves by d / cos α_t along the circle's arc (flank_arc_position_um),
// so Δs_t = (d_L + d_R) / cos α_t and the normal thickness E_sn = Δs_t cos β.
double tooth_thickness_deviation_um(double d_left_um, double d_right_um, double alpha_t_rad,
                                    double beta_rad);
// E_Wk from the deviations of the span's two outer flanks (L of its first tooth, R of its last)
// where the jaws touch: the jaws' common normal is the flanks' normal in the base plane, along
// which a transverse deviation d is d cos β_b, so E_Wk = (d_first + d_last) cos β_b
// (= Δs_n cos α_n for a uniform thickness change, DIN 3967's A_Wk = A_sn cos α_n).
double span_deviation_um(double d_first_um, double d_last_um, double base_helix_angle_rad);
// E_MdK from the displacements Δ_a, Δ_b of the two balls' centres (ball_displacement_um): the
// change of the distance between the centres, u·(Δ_a − Δ_b) with u the unit vector from b's
// centre to a's. With the balls opposite (even z) that is the sum of their radial displacements;
// on an odd number of teeth (centres 180° − 180°/z apart) their sideways moves count too,
// cos(π/2z)(Δr_a + Δr_b) − sin(π/2z)(Δt_a − Δt_b) (a brute-force check in
// tests/gears/size_dimensions_reference.py found the radial part alone off by 1–3 %). The same on
// an internal gear (dimension between balls).
double ball_dimension_deviation_um(const BallContact& a, const Eigen::Vector2d& delta_a_um,
                                   const BallContact& b, const Eigen::Vector2d& delta_b_um);

}  // namespace gearmc
