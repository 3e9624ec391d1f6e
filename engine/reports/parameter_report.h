// What a run with `evaluation:` says about the gear parameters (docs/parameters.md): per ISO
// 1328-1 parameter and flank side the distributions of the true (dense-trace) value, the measured
// value and the error = measured − true, with bias, standard uncertainty u, the shortest 95 %
// interval and U (k = 2); the split of the error into measurement error (measured − true at the
// same points) and sampling error (true at the points − dense true); the error budget (each
// effect alone, δRcomp alone); and the conformity decisions against the scenario's tolerances
// with their false-accept and false-reject rates. summary.json keys, the terminal table and the
// report's figures. Values in µm.
#pragma once

#include <cstdint>
#include <nlohmann/json.hpp>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include "engine/reports/run_report.h"
#include "engine/run/monte_carlo.h"
#include "engine/statistics/conformity.h"
#include "engine/statistics/relative_histogram.h"
#include "engine/statistics/running_stats.h"

namespace gearmc {

// The statistics of one parameter on one side ("left", "right", or "both" for F_r).
struct ParameterSideSummary {
  std::string side;
  std::uint64_t items = 0, not_evaluated = 0;  // items without a value (NaN) are counted only
  RunningStats true_moments, measured_moments, error_moments, measurement_error, sampling_error;
  RelativeHistogram true_values, measured_values, error_values;
  std::vector<double> errors;  // sorted ascending (for the interval and the histogram)
  double bias_um = 0.0, u_um = 0.0, U95_um = 0.0;
  std::optional<CoverageInterval> interval95;  // shortest (JCGM 101 §7.7.2)
  // Probabilistically symmetric (JCGM 101 §7.7.1): 2.5 % of the errors below, 2.5 % above.
  std::optional<CoverageInterval> symmetric95;
  // Per budget variant (each effect alone, then δRcomp alone): the error against the true value
  // at the same points.
  std::vector<RunningStats> budget;
};

// The largest Q_MP of a capable measurement process that ISO 22514-7 and VDA 5 recommend (30 %).
inline constexpr double kCapabilityRatioLimit = 0.30;

struct ParameterConformity {
  std::optional<double> tolerance_um;  // absent: the tolerance set has none for this parameter
  std::string tolerance_symbol;        // the set's symbol, e.g. "F_alpha" or "f_f"
  bool two_sided = false;              // ±T (slope, single pitch), or a size's allowances
  // A size deviation with the drawing's allowances (evaluation.size_allowances_um): the limits
  // are [lower, upper] and tolerance_um is their width.
  bool allowances = false;
  // "±T", "≤ T" or "[lower, upper]" (µm, one decimal; empty without a tolerance).
  std::string tolerance_text() const;
  DecisionRule rule = DecisionRule::kSimple;
  // guard_banded's band at each limit, from the error's own law (each side's probabilistically
  // symmetric 95 % interval [e_lo, e_hi], the largest over the sides): at the upper limit
  // max(0, −e_lo) — the true value exceeds the measured one by more than that 2.5 % of the time —
  // and at the lower limit max(0, e_hi); a side with too few errors for the interval takes U95.
  // An item measured at an acceptance limit then has a 2.5 % chance of a true value beyond the
  // tolerance (JCGM 106 §8.3, specific risk), also when the error law is skewed.
  double guard_band_lower_um = 0.0, guard_band_upper_um = 0.0;
  // U/T: the largest U95 of the sides over the tolerance interval's width (2T for ±T, T for ≤ T).
  double u_over_t = 0.0;
  // The measurement-process capability ratio Q_MP = 2U/(T_U − T_L) (ISO 22514-7:2021 §9, VDA 5
  // §5): 2 · u_over_t, the one-sided F ≤ T taking its natural lower limit 0. Capable when
  // Q_MP ≤ kCapabilityRatioLimit.
  double capability_ratio = 0.0;
  bool capable() const { return tolerance_um && capability_ratio <= kCapabilityRatioLimit; }
  ToleranceLimits tolerance, acceptance;
  DecisionRates simple, guard_banded;  // over every item of both sides (true = dense value)
  const DecisionRates& chosen() const {
    return rule == DecisionRule::kSimple ? simple : guard_banded;
  }
  // JCGM 106 §7.5 for one measured value: the run's worst measured item y (largest value, or
  // largest |value| for ±T): the probability that its true value conforms, from the error law of
  // the side it is on ("left", "right", or "both" for F_r) — the fraction of that side's errors e
  // with T_L ≤ y − e ≤ T_U (empirical_conformance_probability; for a normal law N(b, u²) this is
  // Φ((T_U − y + b)/u) − Φ((T_L − y + b)/u), JCGM 106 §7.6).
  double worst_measured_um = 0.0, conformance_probability_of_worst = 0.0;
  std::string worst_side;
};

struct ParameterSummary {
  GearParameter parameter;
  std::vector<ParameterSideSummary> sides;
  ParameterConformity conformity;
};

struct ParameterPresentation {
  std::vector<ParameterSummary> parameters;
  std::vector<std::string> budget_sources;  // effect names, then "δRcomp alone"
  std::vector<std::string> notes;           // parameters left out, items without a value
};

// Null when the run has no parameter evaluation.
std::optional<ParameterPresentation> present_parameters(const MonteCarloRun& mc,
                                                        const RunResults& r);

// summary.json "parameters", "conformity" and "parameter_evaluation" (how they were evaluated).
void add_parameter_json(nlohmann::ordered_json& summary, const MonteCarloRun& mc,
                        const ParameterPresentation& p);

// What a run decided about its parameters, for the report's opening box: capable for which
// toleranced parameters (Q_MP against its limit), with U, T, U/T and the decision risks of each.
struct ParameterVerdict {
  std::string headline;
  std::vector<std::string> lines;
  int capable = 0, assessed = 0;  // toleranced parameters with a value, and those capable
};
ParameterVerdict parameter_verdict(const ParameterPresentation& p);

// The terminal tables: parameters with U, then conformity with the decision risks, then the
// error budget (with effects).
void print_parameter_tables(std::ostream& out, const MonteCarloRun& mc,
                            const ParameterPresentation& p);

// The report's figures: profile and helix charts of the chart gear (4 teeth × L/R), pitch and
// runout bars, the error histogram of each parameter with its interval.
std::vector<RunFigure> parameter_figures(const MonteCarloRun& mc, const RunResults& r,
                                         const ParameterPresentation& p);

class HtmlReport;
// The report's gear-parameter section: the parameter and conformity tables first, then the
// figures (parameter_figures) and how the parameters were evaluated.
void add_parameter_section(HtmlReport& report, const MonteCarloRun& mc,
                           const ParameterPresentation& p, const std::vector<RunFigure>& figures);

// A value of the parameter tables and figures with `decimals` decimals; "–" when not finite.
std::string parameter_text(double v, int decimals);
// The size gauges of the run, one sentence (empty when no size deviation is evaluated):
// nominal s_n, W_k over k teeth and M_dK over balls of D_M, with where each touches.
std::string size_gauges_text(const MonteCarloRun& mc);

}  // namespace gearmc
