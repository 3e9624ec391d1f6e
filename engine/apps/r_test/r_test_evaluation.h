// The evaluation of P3's R-Test calibration (docs/r-test.md), the routes side by side:
//  1. the calibration: a simulated calibration of the instrument ("observed"), fitted per sensor;
//  2. P3's GUM route: the standard uncertainty of every base-point coordinate C_i1,k from the
//     Type-B inputs, with sensitivities both by P3's varied-parameter method and exactly
//     (implicit function theorem), ν_eff by Welch–Satterthwaite, k from Student's t; and the
//     ball centre at the measured position P_m propagated from those C_i1 (taken as
//     independent, as in P3), r and R by the same law of propagation;
//  3. P3's GUM+MCM route: C_i1 ~ N(Ĉ_i1, u²), r ~ N, R ~ N, M trials of the ball centre;
//  4. the whole chain linearised (every raw input through calibration and measurement, so the
//     correlations the calibration makes between the C_i1 are kept) — the GUM done fully;
//  5. the full Monte-Carlo method: every raw input drawn, the calibration inside the loop;
//  6. the verification: the calibrated R-Test measuring random positions many times with fresh
//     errors, the actual 95 % error per axis against each route's expanded uncertainty.
// Routes 2 and 3 also come in a variant that adds the indication errors of the three measuring
// readings (P3 lists C_i1, r and R only). Every Monte-Carlo draw comes from a counter-based
// stream keyed by (seed, trial, purpose) and trials write their own slots, so results are
// bit-identical for any thread count. Units: mm inside; the presentations show µm.
#pragma once

#include <array>
#include <atomic>
#include <cstdint>
#include <string>
#include <vector>

#include "engine/apps/r_test/r_test_model.h"

namespace gearmc::rtest {

struct AxisResult {
  double estimate = 0.0;  // mm (ball centre) or mm (an error, for the full MCM: mean error)
  double u = 0.0;         // standard uncertainty, mm
  double nu_eff = 0.0;    // GUM: Welch–Satterthwaite (+inf: none finite); MCM: 0
  double k = 0.0;         // GUM: t_{(1+p)/2}(ν_eff); MCM: U/u
  double U = 0.0;         // GUM: k u; MCM: half the width of the symmetric p interval
  double lo = 0.0, hi = 0.0;
};

struct BudgetItem {
  std::string name;
  Vector3d contribution = Vector3d::Zero();  // |c| u per axis (classes: root-sum-square), mm
};

struct Prediction {
  std::string id, label;
  bool monte_carlo = false;
  std::array<AxisResult, 3> axis;
  std::vector<BudgetItem> budget;  // GUM routes
  std::uint64_t trials = 0, failed = 0;
  double wall_s = 0.0;
};

// One base-point coordinate C_i1,k by P3's GUM route.
struct BaseCoordinate {
  double true_value = 0.0, estimate = 0.0;  // mm
  double u_exact = 0.0, u_varied = 0.0;     // sensitivities exact / varied-parameter
  double nu_eff = 0.0, k = 0.0, U = 0.0;    // from the exact sensitivities
  std::array<double, kClasses> budget{};    // per class, root-sum-square of |c| u (exact)
};

struct Verification {
  std::vector<Vector3d> positions;
  std::vector<Vector3d> actual95;        // per position: the p quantile of |error| over repetitions
  Vector3d pooled95 = Vector3d::Zero();  // over every position and repetition
  // At P_m itself (measured once per repetition too): the actual counterpart of the routes.
  Vector3d at_measured95 = Vector3d::Zero();
  Vector3d mean = Vector3d::Zero(), rms = Vector3d::Zero();
  // The whole-chain GUM and P3's GUM (with readings) U at each position, for the plot.
  std::vector<Vector3d> gum_chain_U, gum_p3_U;
  std::uint64_t measurements = 0, failed = 0;
  double wall_s = 0.0;
};

struct RTestResult {
  Calibration observed;
  std::array<std::array<BaseCoordinate, 3>, kSensors> base;
  double sensitivity_max_rel_diff = 0.0;  // varied vs exact, worst input
  bool varied_ok = true;
  Vector3d measured_readings = Vector3d::Zero();
  BallCentre estimate;  // P̂ at P_m from the observed calibration and readings
  std::vector<Prediction> predictions;
  Verification verification;
  std::vector<std::string> warnings;
  bool cancelled = false;
};

struct RTestRunOptions {
  std::uint64_t trials = 1'000'000;  // each Monte-Carlo route
  int threads = 0;                   // 0: oneTBB's default
  const std::atomic<bool>* cancel = nullptr;
};

RTestResult evaluate_r_test(const RTestModel& m, const RTestRunOptions& o);

// The GUM of one C_i1 coordinate set from given per-input sensitivity vectors (exposed for
// tests): contributions c_n u_n, ν_n per input; returns u, ν_eff, k, U per coordinate.
AxisResult combine(const std::vector<Vector3d>& contributions, const std::vector<double>& dof,
                   int coordinate, double p);

// The RMS of every sensor's calibration-fit residuals, µm (NaN without residuals).
double residual_rms_um(const Calibration& c);

// Why the results cannot be vouched for, or "" when they can: the observed calibration fit or
// the ball centre at P_m did not converge, or a Monte-Carlo route or the verification lost more
// than kMaxFailedShare of its trials (leaving them out would bias its U). Input laws far wider
// than an R-Test's errors (P3's are a few µm) lead here; the command refuses them (exit 2).
inline constexpr double kMaxFailedShare = 0.01;
std::string r_test_refusal(const RTestResult& r);

// The full-MCM error e = P̂ − P_m of one trial (exposed for tests): false when the calibration
// or the ball solve failed.
bool full_mcm_trial(const RTestModel& m, std::uint64_t trial, Vector3d& error);

// The p quantile of |x|: the order statistic ⌈p n⌉ (1-based) of the n finite |x| (NaN and inf
// left out); NaN when none is finite. Used for the verification's 95 % of |error| (exposed for
// tests).
double abs_quantile(std::vector<double> v, double p);

// The whole-chain GUM at ball position `ball` (noise-free readings of the fitted instrument),
// with the calibration derivatives of `cal`: per class contribution and the result per axis.
Prediction whole_chain_gum(const RTestModel& m, const Calibration& cal, const Vector3d& ball);

}  // namespace gearmc::rtest
