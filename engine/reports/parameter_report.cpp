// The gear parameters of a run: statistics, conformity, JSON, terminal, figures (see
// parameter_report.h).
#include "engine/reports/parameter_report.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "core/constants.h"
#include "engine/effects/measurement_effect.h"
#include "engine/reports/svg_plot.h"
#include "engine/statistics/histogram_bins.h"
#include "engine/statistics/stats_json.h"
#include "gears/size_dimensions.h"

namespace gearmc {
namespace {

constexpr double kCoverageFactor = 2.0;  // U = k u_c, k = 2 (about 95 % for a normal law)

std::string signed_fixed(double v, int decimals) {
  if (!std::isfinite(v)) return "–";
  char b[64];
  std::snprintf(b, sizeof b, "%+.*f", decimals, v);
  return b;
}
std::string percent(double fraction) { return parameter_text(100.0 * fraction, 2) + " %"; }

nlohmann::ordered_json number_or_null(double v) {
  return std::isfinite(v) ? nlohmann::ordered_json(v) : nlohmann::ordered_json();
}

nlohmann::ordered_json moments_json(const RunningStats& m) {
  nlohmann::ordered_json j;
  j["n"] = m.count();
  j["mean"] = number_or_null(m.count() ? m.mean() : NAN);
  j["std"] = number_or_null(m.count() > 1 ? m.stddev() : NAN);
  return j;
}

nlohmann::ordered_json full_stats(const RunningStats& m, const RelativeHistogram& h) {
  if (m.count() == 0) return moments_json(m);
  return stats_json(m, h, freedman_diaconis_bins({&h}));
}

const char* rule_name(DecisionRule r) {
  return r == DecisionRule::kSimple ? "simple" : "guard_banded";
}

nlohmann::ordered_json rates_json(const DecisionRates& r) {
  return {{"items", r.items},
          {"accepted", r.accepted},
          {"nonconforming", r.nonconforming},
          {"false_accepts", r.false_accepts},
          {"false_rejects", r.false_rejects},
          {"false_accept", r.false_accept_rate()},
          {"false_reject", r.false_reject_rate()}};
}

}  // namespace

std::string parameter_text(double v, int decimals) {
  if (!std::isfinite(v)) return "–";
  char b[64];
  std::snprintf(b, sizeof b, "%.*f", decimals, v);
  return b;
}

std::string ParameterConformity::tolerance_text() const {
  if (!tolerance_um) return {};
  if (allowances) {
    return "[" + parameter_text(*tolerance.lower, 1) + ", " + parameter_text(*tolerance.upper, 1) +
           "]";
  }
  return (two_sided ? "±" : "≤ ") + parameter_text(*tolerance_um, 1);
}

std::optional<ParameterPresentation> present_parameters(const MonteCarloRun& mc,
                                                        const RunResults& r) {
  const ParameterEvaluator* evaluator = mc.parameter_evaluator();
  if (evaluator == nullptr || !r.parameters) return std::nullopt;
  ParameterPresentation view;
  view.notes = evaluator->notes();
  const EffectChain& effects = mc.model().effects();
  for (std::size_t e = 0; e < effects.size(); ++e) {
    view.budget_sources.emplace_back(effects.effect(e).name());
  }
  if (!effects.empty()) view.budget_sources.emplace_back("δRcomp alone");
  const ToleranceSet& tolerances = mc.tolerances();
  for (const GearParameter p : evaluator->parameters()) {
    ParameterSummary summary;
    summary.parameter = p;
    const auto& values = r.parameters->values[static_cast<int>(p)];
    ParameterConformity& c = summary.conformity;
    const std::optional<ToleranceKind> kind = parameter_tolerance_kind(p);
    c.tolerance_um = parameter_tolerance_um(tolerances, p);
    c.tolerance_symbol = kind ? tolerance_symbol(*kind, tolerances.standard).value_or("") : "";
    c.two_sided = parameter_signed(p);
    const auto& allowances = evaluator->spec().size_allowances_um;
    std::optional<std::pair<double, double>> allowance;
    if (const auto a = allowances.find(parameter_symbol(p)); a != allowances.end()) {
      allowance = a->second;
      c.allowances = c.two_sided = true;
      c.tolerance_um = a->second.second - a->second.first;
      c.tolerance_symbol = "allowances";
    }
    // The worst measured value is the one farthest from the tolerance zone's centre.
    const double centre = allowance ? 0.5 * (allowance->first + allowance->second) : 0.0;
    c.rule = evaluator->spec().decision_rule == "guard_banded" ? DecisionRule::kGuardBanded
                                                               : DecisionRule::kSimple;
    std::vector<double> all_true, all_measured;
    RunningStats all_error;
    // The worst measured value (largest |y| for a signed parameter) and the side it is on: its
    // conformance probability takes that side's error law (docs/parameters.md).
    double worst = kNaN;
    std::size_t worst_side = 0;
    double largest_U95 = 0.0;
    for (int s = 0; s < 2; ++s) {
      if (values[s].empty()) continue;
      ParameterSideSummary side;
      side.side = parameter_of_both_flanks(p) ? "both" : (s == 0 ? "left" : "right");
      side.budget.resize(view.budget_sources.size());
      for (const ParameterValue& v : values[s]) {
        ++side.items;
        if (!std::isfinite(v.measured) || !std::isfinite(v.true_dense) ||
            !std::isfinite(v.true_points)) {
          ++side.not_evaluated;
          continue;
        }
        const double error = v.measured - v.true_dense;
        side.true_moments.add(v.true_dense);
        side.true_values.add(v.true_dense);
        side.measured_moments.add(v.measured);
        side.measured_values.add(v.measured);
        side.error_moments.add(error);
        side.error_values.add(error);
        side.errors.push_back(error);
        side.measurement_error.add(v.measured - v.true_points);
        side.sampling_error.add(v.true_points - v.true_dense);
        for (std::size_t b = 0; b < v.budget.size() && b < side.budget.size(); ++b) {
          if (std::isfinite(v.budget[b])) side.budget[b].add(v.budget[b] - v.true_points);
        }
        if (all_measured.empty() ||
            (c.two_sided ? std::abs(v.measured - centre) > std::abs(worst - centre)
                         : v.measured > worst)) {
          worst = v.measured;
          worst_side = summary.sides.size();  // the index this side gets below
        }
        all_true.push_back(v.true_dense);
        all_measured.push_back(v.measured);
        all_error.add(error);
      }
      std::sort(side.errors.begin(), side.errors.end());
      if (side.error_moments.count() > 0) {
        side.bias_um = side.error_moments.mean();
        side.u_um = side.error_moments.count() > 1 ? side.error_moments.stddev() : 0.0;
        // The bias is not corrected in a reading, so U covers it: U = k √(u² + b²).
        side.U95_um = kCoverageFactor * std::hypot(side.u_um, side.bias_um);
        side.interval95 = shortest_coverage_interval(side.errors, 0.95);
        side.symmetric95 = symmetric_coverage_interval(side.errors, 0.95);
      }
      if (side.not_evaluated > 0) {
        view.notes.push_back(parameter_symbol(p) + " " + side.side + ": " +
                             std::to_string(side.not_evaluated) + " of " +
                             std::to_string(side.items) +
                             " items without a value (too few valid points in a trace)");
      }
      if (side.error_moments.count() > 0) {
        c.guard_band_upper_um =
            std::max(c.guard_band_upper_um,
                     side.symmetric95 ? std::max(0.0, -side.symmetric95->lo) : side.U95_um);
        c.guard_band_lower_um =
            std::max(c.guard_band_lower_um,
                     side.symmetric95 ? std::max(0.0, side.symmetric95->hi) : side.U95_um);
        largest_U95 = std::max(largest_U95, side.U95_um);
      }
      summary.sides.push_back(std::move(side));
    }
    if (c.tolerance_um) {
      const double T = *c.tolerance_um;
      c.tolerance = allowance     ? ToleranceLimits{allowance->first, allowance->second}
                    : c.two_sided ? ToleranceLimits{-T, T}
                                  : ToleranceLimits{std::nullopt, T};
      const ToleranceLimits simple = acceptance_limits(c.tolerance, DecisionRule::kSimple, 0.0);
      const ToleranceLimits guarded = acceptance_limits(
          c.tolerance, DecisionRule::kGuardBanded, c.guard_band_lower_um, c.guard_band_upper_um);
      // U over the tolerance interval's width: 2T for ±T, T for ≤ T or a size's allowances.
      c.u_over_t = largest_U95 / (c.two_sided && !c.allowances ? 2.0 * T : T);
      c.capability_ratio = 2.0 * c.u_over_t;
      c.acceptance = c.rule == DecisionRule::kSimple ? simple : guarded;
      c.simple = decision_rates(all_true, all_measured, c.tolerance, simple);
      c.guard_banded = decision_rates(all_true, all_measured, c.tolerance, guarded);
      if (!all_measured.empty() && summary.sides[worst_side].error_moments.count() > 1) {
        const ParameterSideSummary& side = summary.sides[worst_side];
        c.worst_measured_um = worst;
        c.worst_side = side.side;
        c.conformance_probability_of_worst = empirical_conformance_probability(
            side.errors, worst, c.tolerance.lower, c.tolerance.upper);
      }
    }
    view.parameters.push_back(std::move(summary));
  }
  return view;
}

void add_parameter_json(nlohmann::ordered_json& summary, const MonteCarloRun& mc,
                        const ParameterPresentation& p) {
  const ParameterEvaluator& e = *mc.parameter_evaluator();
  const EvaluationSpec& spec = e.spec();
  nlohmann::ordered_json how;
  how["standard"] = "ISO 1328-1:2013";
  how["error_definition"] =
      "measured - true; true = the evaluation of the real surface on a "
      "dense trace";
  how["coverage_factor"] = kCoverageFactor;
  how["U95_definition"] = "k * sqrt(u^2 + bias^2) (the bias is not corrected in a reading)";
  how["guard_band_definition"] =
      "guard_banded: at the upper limit max(0, -e_lo), at the lower limit max(0, e_hi), from "
      "each side's probabilistically symmetric 95 % interval [e_lo, e_hi] of the errors (the "
      "largest over the sides; U95 for a side with too few errors): an item measured at an "
      "acceptance limit has a 2.5 % chance of a true value beyond the tolerance";
  how["U_over_T_definition"] =
      "the largest U95 of the sides over the tolerance interval's width (2T for +-T, T for <= T)";
  how["Q_MP_definition"] =
      "capability ratio of the measurement process 2 U / (T_U - T_L) (ISO 22514-7, VDA 5; the "
      "natural lower limit 0 for <= T), capable when <= 0.30";
  how["profile_range_mm"] = {e.profile_start_mm(), e.profile_end_mm()};
  how["helix_range_mm"] = {e.helix_start_mm(), e.helix_end_mm()};
  how["profile_trace"] =
      e.program_traces()
          ? std::string(
                "per flank the program's transverse section with the most points in the "
                "profile range (ties: nearest mid face)")
      : spec.profile_points > 0
          ? "dedicated scan of " + std::to_string(spec.profile_points) + " points at mid face"
          : std::string("the probing grid's section nearest mid face");
  how["helix_trace"] =
      e.program_traces()
          ? std::string(
                "per flank the program's roll length with the most points in the helix "
                "range (ties: nearest mid profile)")
      : spec.helix_points > 0
          ? "dedicated scan of " + std::to_string(spec.helix_points) + " points at mid profile"
          : std::string("the probing grid's column nearest mid profile");
  how["truth_points"] = spec.truth_points;
  const auto cutoff_json = [](const std::optional<double>& c) {
    return c ? nlohmann::ordered_json(*c) : nlohmann::ordered_json(nullptr);
  };
  how["profile_cutoff_mm"] = cutoff_json(spec.profile_cutoff_mm);
  how["helix_cutoff_mm"] = cutoff_json(spec.helix_cutoff_mm);
  if (spec.profile_cutoff_mm || spec.helix_cutoff_mm) {
    how["filter"] =
        "Gaussian low-pass (ISO 16610-21, 50 % at the cut-off) as first-order Gaussian "
        "regression (a straight trace stays straight at the ends); null = unfiltered; applied to "
        "the measured and the true traces before F, f_H, f_f (pitch and sizes unfiltered)";
  }
  how["decision_rule"] = spec.decision_rule;
  how["budget_sources"] = p.budget_sources;
  how["notes"] = p.notes;
  const InvoluteGear& gear = mc.gear();
  if (e.evaluates(GearParameter::kEsn) || e.evaluates(GearParameter::kEWk) ||
      e.evaluates(GearParameter::kEMdK)) {
    nlohmann::ordered_json sizes;
    sizes["definition"] =
        "E = actual - nominal size, um, from the profile traces where the gauge touches (first "
        "order in the flank deviations, in the profile traces' transverse section)";
    if (e.evaluates(GearParameter::kEsn)) sizes["s_n_nominal_mm"] = normal_tooth_thickness_mm(gear);
    if (const auto k = e.span_teeth()) {
      sizes["span_teeth"] = *k;
      sizes["W_k_nominal_mm"] = base_tangent_length_mm(gear, *k);
      sizes["span_contact_roll_length_mm"] = e.span_contact_mm();
    }
    if (const auto D = e.ball_diameter_mm()) {
      sizes["ball_diameter_mm"] = *D;
      sizes["M_dK_nominal_mm"] = dimension_over_balls_mm(gear, *D);
      sizes["M_dK_kind"] = gear.internal() ? "between balls" : "over balls";
      sizes["ball_contact_roll_length_mm"] = e.ball_contact_mm();
    }
    how["sizes"] = sizes;
  }
  summary["parameter_evaluation"] = how;

  nlohmann::ordered_json parameters = nlohmann::ordered_json::object();
  nlohmann::ordered_json conformity = nlohmann::ordered_json::object();
  for (const ParameterSummary& s : p.parameters) {
    const std::string& symbol = parameter_symbol(s.parameter);
    nlohmann::ordered_json sides = nlohmann::ordered_json::object();
    for (const ParameterSideSummary& side : s.sides) {
      nlohmann::ordered_json j;
      j["items"] = side.items;
      j["not_evaluated"] = side.not_evaluated;
      j["true"] = full_stats(side.true_moments, side.true_values);
      j["measured"] = full_stats(side.measured_moments, side.measured_values);
      j["error"] = full_stats(side.error_moments, side.error_values);
      j["bias_um"] = side.bias_um;
      j["u_um"] = side.u_um;
      j["U95_um"] = side.U95_um;
      j["interval95_um"] = side.interval95
                               ? nlohmann::ordered_json{side.interval95->lo, side.interval95->hi}
                               : nlohmann::ordered_json();
      j["interval95_symmetric_um"] =
          side.symmetric95 ? nlohmann::ordered_json{side.symmetric95->lo, side.symmetric95->hi}
                           : nlohmann::ordered_json();
      if (!side.interval95) {
        j["interval95_note"] = "not enough values: a 95 % interval needs at least 21";
      }
      j["measurement_error"] = moments_json(side.measurement_error);
      j["sampling_error"] = moments_json(side.sampling_error);
      if (!side.budget.empty()) {
        nlohmann::ordered_json budget = nlohmann::ordered_json::array();
        for (std::size_t b = 0; b < side.budget.size(); ++b) {
          nlohmann::ordered_json line = moments_json(side.budget[b]);
          line["source"] = p.budget_sources[b];
          budget.push_back(line);
        }
        j["error_budget"] = budget;
      }
      sides[side.side] = j;
    }
    parameters[symbol] = sides;
    const ParameterConformity& c = s.conformity;
    nlohmann::ordered_json k;
    k["tolerance_um"] = c.tolerance_um ? nlohmann::ordered_json(*c.tolerance_um) : nullptr;
    k["tolerance_symbol"] = c.tolerance_symbol;
    k["two_sided"] = c.two_sided;
    k["decision_rule"] = rule_name(c.rule);
    if (!c.tolerance_um) {
      k["note"] = parameter_is_size(s.parameter)
                      ? "a size deviation: its allowances are the drawing's (DIN 3967); give "
                        "them as evaluation.size_allowances_um"
                      : "the scenario's tolerance set has no value for this parameter";
    } else {
      if (c.allowances) k["limits_um"] = {*c.tolerance.lower, *c.tolerance.upper};
      k["acceptance_limit_um"] = *c.acceptance.upper;
      if (c.acceptance.lower) k["acceptance_lower_limit_um"] = *c.acceptance.lower;
      k["guard_band_upper_um"] = c.guard_band_upper_um;
      if (c.tolerance.lower) k["guard_band_lower_um"] = c.guard_band_lower_um;
      k["U_over_T"] = c.u_over_t;
      k["Q_MP"] = c.capability_ratio;
      k["capable"] = c.capable();
      k["false_accept"] = c.chosen().false_accept_rate();
      k["false_reject"] = c.chosen().false_reject_rate();
      k["rates"] = {{"simple", rates_json(c.simple)}, {"guard_banded", rates_json(c.guard_banded)}};
      k["worst_measured_um"] = c.worst_measured_um;
      k["worst_side"] = c.worst_side;
      k["conformance_probability_of_worst"] = c.conformance_probability_of_worst;
    }
    conformity[symbol] = k;
  }
  summary["parameters"] = parameters;
  summary["conformity"] = conformity;
}

ParameterVerdict parameter_verdict(const ParameterPresentation& p) {
  ParameterVerdict v;
  std::string not_capable;
  for (const ParameterSummary& s : p.parameters) {
    const ParameterConformity& c = s.conformity;
    const bool any = std::any_of(s.sides.begin(), s.sides.end(),
                                 [](const auto& side) { return side.error_moments.count() > 0; });
    if (!c.tolerance_um || !any) continue;
    ++v.assessed;
    const std::string q = parameter_text(100.0 * c.capability_ratio, 0) + " %";
    if (c.capable()) {
      ++v.capable;
    } else {
      not_capable +=
          (not_capable.empty() ? "" : ", ") + parameter_symbol(s.parameter) + " (" + q + ")";
    }
    double U = 0.0;
    for (const ParameterSideSummary& side : s.sides) U = std::max(U, side.U95_um);
    v.lines.push_back(
        parameter_symbol(s.parameter) + ": Q_MP " + q + (c.capable() ? " ≤ " : " > ") +
        parameter_text(100.0 * kCapabilityRatioLimit, 0) + " % (U " + parameter_text(U, 2) +
        " µm, tolerance " + c.tolerance_text() + " µm, U/T " + parameter_text(c.u_over_t, 2) +
        ") — " + (c.capable() ? "capable" : "NOT capable") + "; rule " + rule_name(c.rule) + ": " +
        parameter_text(100.0 * c.chosen().false_accept_rate(), 2) + " % false accept, " +
        parameter_text(100.0 * c.chosen().false_reject_rate(), 2) + " % false reject");
  }
  if (v.assessed == 0) {
    v.headline = "No parameter has a tolerance: the measurement's capability is not assessed.";
  } else if (v.capable == v.assessed) {
    v.headline = "Capable for every toleranced parameter (" + std::to_string(v.assessed) +
                 "): Q_MP = 2U/(T_U − T_L) ≤ 30 % (ISO 22514-7, VDA 5).";
  } else {
    v.headline = "NOT capable for " + std::to_string(v.assessed - v.capable) + " of " +
                 std::to_string(v.assessed) + " toleranced parameters: " + not_capable +
                 " (capable: Q_MP = 2U/(T_U − T_L) ≤ 30 %, ISO 22514-7, VDA 5).";
  }
  return v;
}

namespace {
// `text` right-aligned in `width` terminal columns (UTF-8: a column per code point, so "±" and
// "≤" take one column as they do on screen, not their two or three bytes).
std::string right_aligned(const std::string& text, std::size_t width) {
  std::size_t columns = 0;
  for (const char ch : text) columns += (static_cast<unsigned char>(ch) & 0xC0) != 0x80 ? 1 : 0;
  return std::string(width > columns ? width - columns : 0, ' ') + text;
}
}  // namespace

void print_parameter_tables(std::ostream& out, const MonteCarloRun& mc,
                            const ParameterPresentation& p) {
  const ParameterEvaluator& e = *mc.parameter_evaluator();
  out << "\n" << parameter_verdict(p).headline << "\n";
  out << "Gear parameters (ISO 1328-1:2013), µm; error = measured − true (dense trace); "
         "U = 2·√(u² + bias²)\n";
  char line[512];
  std::snprintf(line, sizeof line, "%-9s %-5s %6s %9s %9s %8s %7s %7s %19s %8s %8s\n", "parameter",
                "side", "n", "true", "measured", "bias", "u", "U", "95 % interval", "meas.err",
                "sampl.err");
  out << line;
  for (const ParameterSummary& s : p.parameters) {
    for (const ParameterSideSummary& side : s.sides) {
      const bool any = side.error_moments.count() > 0;
      const std::string interval = side.interval95
                                       ? "[" + signed_fixed(side.interval95->lo, 2) + ", " +
                                             signed_fixed(side.interval95->hi, 2) + "]"
                                       : "–";
      std::snprintf(line, sizeof line, "%-9s %-5s %6llu %9s %9s %8s %7s %7s %19s %8s %8s\n",
                    parameter_symbol(s.parameter).c_str(), side.side.c_str(),
                    static_cast<unsigned long long>(side.error_moments.count()),
                    any ? parameter_text(side.true_moments.mean(), 2).c_str() : "–",
                    any ? parameter_text(side.measured_moments.mean(), 2).c_str() : "–",
                    any ? signed_fixed(side.bias_um, 3).c_str() : "–",
                    any ? parameter_text(side.u_um, 3).c_str() : "–",
                    any ? parameter_text(side.U95_um, 2).c_str() : "–", interval.c_str(),
                    side.measurement_error.count() > 1
                        ? parameter_text(side.measurement_error.stddev(), 3).c_str()
                        : "–",
                    side.sampling_error.count() > 1
                        ? parameter_text(side.sampling_error.stddev(), 3).c_str()
                        : "–");
      out << line;
    }
  }
  out << "  (meas.err, sampl.err: standard deviations of measured − true at the same points and "
         "of true at the points − dense true)\n";
  if (const std::string sizes = size_gauges_text(mc); !sizes.empty()) out << "  " << sizes << "\n";
  out << "\nConformity (ISO 14253-1, rule " << e.spec().decision_rule
      << "; over every flank, tooth or gear of the run)\n";
  std::snprintf(line, sizeof line, "%-9s %-10s %8s %6s %15s %11s %11s %12s %16s\n", "parameter",
                "tolerance", "T", "U/T", "accept if", "false acc.", "false rej.", "rej. (other)",
                "p_c(worst)");
  out << line;
  for (const ParameterSummary& s : p.parameters) {
    const ParameterConformity& c = s.conformity;
    if (!c.tolerance_um) {
      std::snprintf(line, sizeof line, "%-9s %-10s %8s   (%s)\n",
                    parameter_symbol(s.parameter).c_str(), "–", "–",
                    parameter_is_size(s.parameter)
                        ? "a size without allowances (size_allowances_um)"
                        : "no tolerance in the set");
      out << line;
      continue;
    }
    const bool symmetric_zone =
        !c.acceptance.lower || std::abs(*c.acceptance.lower + *c.acceptance.upper) < 0.005;
    const std::string accept = c.two_sided && symmetric_zone
                                   ? "|y| ≤ " + parameter_text(*c.acceptance.upper, 2)
                               : c.two_sided ? parameter_text(*c.acceptance.lower, 2) + " ≤ y ≤ " +
                                                   parameter_text(*c.acceptance.upper, 2)
                                             : "y ≤ " + parameter_text(*c.acceptance.upper, 2);
    const DecisionRates& other = c.rule == DecisionRule::kSimple ? c.guard_banded : c.simple;
    std::snprintf(line, sizeof line, "%-9s %-10s %s %6s %s %11s %11s %12s %16s\n",
                  parameter_symbol(s.parameter).c_str(), c.tolerance_symbol.c_str(),
                  right_aligned(c.tolerance_text(), 8).c_str(),
                  parameter_text(c.u_over_t, 2).c_str(), right_aligned(accept, 15).c_str(),
                  percent(c.chosen().false_accept_rate()).c_str(),
                  percent(c.chosen().false_reject_rate()).c_str(),
                  percent(1.0 - static_cast<double>(other.accepted) /
                                    static_cast<double>(std::max<std::uint64_t>(other.items, 1)))
                      .c_str(),
                  (parameter_text(c.worst_measured_um, 2) + ": " +
                   parameter_text(c.conformance_probability_of_worst, 3))
                      .c_str());
    out << line;
  }
  out << "  (U/T: the largest U over the tolerance interval's width; guard_banded narrows each "
         "limit by how far the error's symmetric 95 % interval reaches past zero on that side; "
         "rej. (other): the share rejected under the other rule; p_c(worst): the run's worst "
         "measured value and the probability, from the error's law, that its true value "
         "conforms)\n";
  if (!p.budget_sources.empty()) {
    out << "\nError budget per parameter: u of measured − true at the same points, each source "
           "alone (with δRcomp), µm\n";
    std::string header = "parameter  side ";
    for (const std::string& src : p.budget_sources) {
      char cell[64];
      std::snprintf(cell, sizeof cell, " %14.14s", src.c_str());
      header += cell;
    }
    out << header << "\n";
    for (const ParameterSummary& s : p.parameters) {
      for (const ParameterSideSummary& side : s.sides) {
        std::snprintf(line, sizeof line, "%-9s  %-5s", parameter_symbol(s.parameter).c_str(),
                      side.side.c_str());
        std::string row = line;
        for (const RunningStats& b : side.budget) {
          char cell[64];
          std::snprintf(cell, sizeof cell, " %14s",
                        b.count() > 1 ? parameter_text(b.stddev(), 3).c_str() : "–");
          row += cell;
        }
        out << row << "\n";
      }
    }
  }
  for (const std::string& note : p.notes) out << "note: " << note << "\n";
}

std::string size_gauges_text(const MonteCarloRun& mc) {
  const ParameterEvaluator& e = *mc.parameter_evaluator();
  const InvoluteGear& gear = mc.gear();
  std::string text;
  const auto add = [&](const std::string& part) { text += (text.empty() ? "" : "; ") + part; };
  if (e.evaluates(GearParameter::kEsn)) {
    add("E_sn: normal tooth thickness s_n " + parameter_text(normal_tooth_thickness_mm(gear), 4) +
        " mm on the reference circle");
  }
  if (const auto k = e.span_teeth()) {
    add("E_Wk: base tangent length W_" + std::to_string(*k) + " " +
        parameter_text(base_tangent_length_mm(gear, *k), 4) + " mm over " + std::to_string(*k) +
        " teeth, the jaws touching at L " + parameter_text(e.span_contact_mm(), 2) + " mm");
  }
  if (const auto D = e.ball_diameter_mm()) {
    add(std::string("E_MdK: dimension ") + (gear.internal() ? "between" : "over") + " balls M_dK " +
        parameter_text(dimension_over_balls_mm(gear, *D), 4) + " mm with D_M " +
        parameter_text(*D, 4) + " mm, touching at L " + parameter_text(e.ball_contact_mm(), 2) +
        " mm");
  }
  if (text.empty()) return text;
  return "Sizes (actual − nominal, read off the profile traces where each gauge touches): " + text +
         ".";
}

}  // namespace gearmc
