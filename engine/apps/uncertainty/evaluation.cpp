// uncertainty.json and the terminal table (evaluation.h); the HTML report is in report.cpp.
#include "engine/apps/uncertainty/evaluation.h"

#include <tbb/task_arena.h>

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <sstream>

#include "core/constants.h"
#include "core/number_text.h"
#include "core/special_functions.h"

namespace gearmc::uncertainty {
namespace {

nlohmann::ordered_json number_or_null(double v) {
  return std::isfinite(v) ? nlohmann::ordered_json(v) : nlohmann::ordered_json(nullptr);
}

std::string fixed(double v, int decimals) {
  std::ostringstream s;
  s << std::fixed << std::setprecision(decimals) << v;
  return s.str();
}

}  // namespace

int display_decimals(double u, int ndig) {
  if (!(u > 0) || !std::isfinite(u)) return 6;
  return std::max(0, -static_cast<int>(std::floor(std::log10(u))) + ndig + 1);
}

Evaluation evaluate(const UncertaintyModel& model, const McmOptions& options) {
  Evaluation e;
  e.gum = evaluate_gum(model);
  e.mcm = run_mcm(model, options);
  if (e.mcm.cancelled) return e;
  for (std::size_t j = 0; j < model.outputs.size(); ++j) {
    const GumOutput& g = e.gum.outputs[j];
    const McmOutput& m = e.mcm.outputs[j];
    e.validation.push_back(
        validate_gum(g.estimate, g.U, g.u, m.symmetric, options.significant_digits, m.sorted));
    e.validation_shortest.push_back(
        validate_gum(g.estimate, g.U, g.u, m.shortest, options.significant_digits, m.sorted));
    Evaluation::Conformity c;
    const ModelOutput& o = model.outputs[j];
    if (o.has_tolerance) {
      c.set = true;
      c.gum_probability = conformance_probability(g.estimate, g.u, o.lower, o.upper);
      const auto first =
          o.lower ? std::lower_bound(m.sorted.begin(), m.sorted.end(), *o.lower) : m.sorted.begin();
      const auto last =
          o.upper ? std::upper_bound(m.sorted.begin(), m.sorted.end(), *o.upper) : m.sorted.end();
      c.mcm_probability =
          m.sorted.empty() || last <= first
              ? 0.0
              : static_cast<double>(last - first) / static_cast<double>(m.sorted.size());
    }
    e.conformity.push_back(c);
  }
  for (const std::string& w : e.gum.warnings) e.warnings.push_back(w);
  if (e.mcm.adaptive && !e.mcm.converged) {
    e.warnings.push_back("the adaptive procedure reached max_trials (" +
                         std::to_string(options.max_trials) +
                         ") before its stop rule held: the MCM results are not stable to " +
                         std::to_string(options.significant_digits) +
                         " significant digits (uncertainty.json: \"converged\": false)");
  }
  for (const ModelInput& in : model.inputs) {
    // A draw is the mean plus a deviation of about u, rounded to the doubles near the mean: with
    // u under 1000 of their spacings the Monte-Carlo values of the input are coarse steps (an
    // input N(1e20, 1) is drawn as exactly 1e20).
    const double mean = std::fabs(in.law.mean()), u = in.law.gum_u();
    const double spacing = std::nextafter(mean, kInf) - mean;
    if (u > 0.0 && u < 1e3 * spacing) {
      e.warnings.push_back("input " + in.name + ": its u (" + shortest_text(u) +
                           ") is under 1000 steps of a double at its mean (" +
                           shortest_text(in.law.mean()) + ", steps of " + shortest_text(spacing) +
                           "): its Monte-Carlo draws are rounded to those steps; subtract a "
                           "constant from it (measure the deviation from a nominal) instead");
    }
    if (in.law.kind() == LawKind::kStudentT && in.law.parameters()[2] <= 2.0) {
      e.warnings.push_back("input " + in.name +
                           " is a t law with ν <= 2: it has no variance, so the MCM u(y) does "
                           "not converge (JCGM 101 §6.4.9.4 asks for at least 4 observations)");
    }
  }
  if (!e.mcm.adaptive && e.mcm.trials < adaptive_block_size(options.coverage_probability)) {
    e.warnings.push_back("M = " + std::to_string(e.mcm.trials) +
                         " is below JCGM 101's recommended 10^4 and 100/(1 − p) trials");
  }
  return e;
}

nlohmann::ordered_json evaluation_json(const UncertaintyModel& model, const McmOptions& o,
                                       const Evaluation& e, const Provenance& provenance) {
  nlohmann::ordered_json j;
  j["model"] = model.name;
  j["source"] = model.source_path;
  j["seed"] = o.seed;
  j["coverage_probability"] = o.coverage_probability;
  j["significant_digits"] = o.significant_digits;
  nlohmann::ordered_json inputs = nlohmann::ordered_json::object();
  for (std::size_t i = 0; i < model.inputs.size(); ++i) {
    const ModelInput& in = model.inputs[i];
    inputs[in.name] = {{"law", in.law_text},
                       {"expectation", e.gum.x[i]},
                       {"u", e.gum.u[i]},
                       {"dof", number_or_null(in.dof)}};
    if (const auto u = model.units.find(in.name); u != model.units.end()) {
      inputs[in.name]["unit"] = u->second.text;
    }
  }
  j["inputs"] = inputs;
  nlohmann::ordered_json outputs = nlohmann::ordered_json::object();
  for (std::size_t k = 0; k < model.outputs.size(); ++k) {
    const GumOutput& g = e.gum.outputs[k];
    const McmOutput& m = e.mcm.outputs[k];
    nlohmann::ordered_json gj;
    gj["estimate"] = g.estimate;
    gj["u"] = g.u;
    gj["nu_eff"] = g.first_order_vanishes ? nlohmann::ordered_json() : number_or_null(g.nu_eff);
    if (g.first_order_vanishes) {
      gj["nu_eff_note"] =
          "undefined: every first-order term is zero; u from the JCGM 100 5.1.2 higher-order "
          "terms, k from the normal law";
    }
    gj["k"] = g.k;
    gj["U"] = g.U;
    gj["interval"] = {g.lo, g.hi};
    nlohmann::ordered_json sens = nlohmann::ordered_json::object(),
                           contrib = nlohmann::ordered_json::object();
    for (std::size_t i = 0; i < model.inputs.size(); ++i) {
      sens[model.inputs[i].name] = g.sensitivities[i];
      contrib[model.inputs[i].name] = g.contributions[i];
    }
    gj["sensitivities"] = sens;
    gj["contributions"] = contrib;
    gj["sensitivity_method"] = kSensitivityMethod;
    gj["u_first_order"] = g.u_first_order;
    gj["second_order"] = e.gum.second_order;
    if (e.gum.second_order) {
      gj["second_order_variance"] = g.second_order_variance;
      gj["second_order_method"] = kSecondOrderMethod;
    }
    gj["correlated_inputs"] = model.correlated;

    nlohmann::ordered_json mj;
    mj["estimate"] = m.estimate;
    mj["u"] = m.u;
    mj["interval_symmetric"] = {m.symmetric.lo, m.symmetric.hi};
    mj["interval_shortest"] = {m.shortest.lo, m.shortest.hi};
    mj["trials"] = e.mcm.trials;
    nlohmann::ordered_json aj;
    aj["blocks"] = e.mcm.blocks;
    aj["delta"] = m.delta;
    aj["enabled"] = e.mcm.adaptive;
    if (e.mcm.adaptive) {
      aj["block_size"] = e.mcm.block_size;
      aj["converged"] = e.mcm.converged;
      aj["two_s"] = {{"estimate", m.two_s_estimate},
                     {"u", m.two_s_u},
                     {"low", m.two_s_lo},
                     {"high", m.two_s_hi}};
    }
    mj["adaptive"] = aj;

    const Validation& v = e.validation[k];
    const Validation& vs = e.validation_shortest[k];
    nlohmann::ordered_json vj;
    vj["delta"] = v.delta;
    vj["d_low"] = v.d_low;
    vj["d_high"] = v.d_high;
    vj["s_low"] = v.s_low;
    vj["s_high"] = v.s_high;
    vj["gum_validated"] = v.validated;
    vj["verdict"] = v.undecided ? "undecided" : v.validated ? "validated" : "not_validated";
    vj["trials_to_decide"] = v.undecided && std::isfinite(v.trials_to_decide)
                                 ? nlohmann::ordered_json(std::ceil(v.trials_to_decide))
                                 : nlohmann::ordered_json();
    vj["mcm_interval"] = "symmetric";
    vj["shortest"] = {{"d_low", vs.d_low},
                      {"d_high", vs.d_high},
                      {"gum_validated", vs.validated},
                      {"verdict", vs.undecided   ? "undecided"
                                  : vs.validated ? "validated"
                                                 : "not_validated"}};
    outputs[g.name] = {{"gum", gj}, {"mcm", mj}, {"validation", vj}};
    if (const auto u = model.units.find(g.name); u != model.units.end()) {
      outputs[g.name]["unit"] = u->second.text;
    }
    if (e.conformity[k].set) {
      const ModelOutput& limits = model.outputs[k];
      nlohmann::ordered_json cj;
      cj["lower"] =
          limits.lower ? nlohmann::ordered_json(*limits.lower) : nlohmann::ordered_json(nullptr);
      cj["upper"] =
          limits.upper ? nlohmann::ordered_json(*limits.upper) : nlohmann::ordered_json(nullptr);
      cj["gum_probability"] = e.conformity[k].gum_probability;
      cj["mcm_probability"] = e.conformity[k].mcm_probability;
      cj["method"] = "JCGM 106:2012 §7.6 (GUM: Gaussian N(y, u^2)); MCM: share of the values";
      outputs[g.name]["conformity"] = cj;
    }
  }
  j["outputs"] = outputs;
  j["warnings"] = e.warnings;
  j["ranks"] = e.mcm.ranks;
  j["threads"] = e.mcm.threads > 0 ? e.mcm.threads : tbb::this_task_arena::max_concurrency();
  j["wall_s"] = e.mcm.wall_s;
  j["provenance"] = provenance_json(provenance);
  return j;
}

void print_evaluation(std::ostream& out, const UncertaintyModel& model, const McmOptions& o,
                      const Evaluation& e) {
  const double p = o.coverage_probability;
  std::ostringstream pct;
  pct << p * 100 << " %";
  out << "MCM: " << e.mcm.trials << " trials";
  if (e.mcm.adaptive) {
    out << " (adaptive, " << e.mcm.blocks << " blocks of " << e.mcm.block_size << ", "
        << (e.mcm.converged ? "stable" : "NOT stable") << " to " << o.significant_digits
        << " significant digits)";
  }
  out << " in " << fixed(e.mcm.wall_s, 2) << " s\n";
  for (std::size_t k = 0; k < model.outputs.size(); ++k) {
    const GumOutput& g = e.gum.outputs[k];
    const McmOutput& m = e.mcm.outputs[k];
    const Validation& v = e.validation[k];
    const int d = display_decimals(std::min(g.u, m.u), o.significant_digits);
    auto iv = [&](double lo, double hi) { return "[" + fixed(lo, d) + ", " + fixed(hi, d) + "]"; };
    const std::string nu = g.first_order_vanishes    ? "undefined"
                           : std::isfinite(g.nu_eff) ? fixed(g.nu_eff, 1)
                                                     : "inf";
    out << "\noutput " << g.name << unit_label(model, g.name) << "\n";
    out << std::left << std::setw(22) << "" << std::setw(28) << "GUM (JCGM 100)"
        << "MCM (JCGM 101)\n";
    out << std::setw(22) << "  estimate y" << std::setw(28) << fixed(g.estimate, d)
        << fixed(m.estimate, d) << "\n";
    out << std::setw(22) << "  u(y)" << std::setw(28)
        << fixed(g.u, d) + (e.gum.second_order ? " (with 2nd order)" : "") << fixed(m.u, d) << "\n";
    out << std::setw(22) << "  nu_eff, k" << std::setw(28) << nu + ", " + fixed(g.k, 3) << "-\n";
    out << std::setw(22) << "  " + pct.str() + " interval" << std::setw(28) << iv(g.lo, g.hi)
        << "symmetric " << iv(m.symmetric.lo, m.symmetric.hi) << "\n";
    out << std::setw(22) << "" << std::setw(28) << ""
        << "shortest  " << iv(m.shortest.lo, m.shortest.hi) << "\n";
    out << "  validation (JCGM 101 §8, ndig " << o.significant_digits << "): delta "
        << std::defaultfloat << std::setprecision(3) << v.delta << ", d_low " << v.d_low
        << ", d_high " << v.d_high << " -> GUM " << v.verdict();
    if (v.undecided) {
      out << " (the MCM endpoints' own standard errors " << v.s_low << ", " << v.s_high
          << " blur d against delta";
      if (std::isfinite(v.trials_to_decide)) {
        out << "; about " << std::setprecision(2) << v.trials_to_decide << " trials would decide";
      }
      out << ")";
    }
    out << "\n";
    if (e.conformity[k].set) {
      const ModelOutput& mo = model.outputs[k];
      out << "  conformity (JCGM 106) within [" << (mo.lower ? fixed(*mo.lower, d) : "-inf") << ", "
          << (mo.upper ? fixed(*mo.upper, d) : "inf") << "]: probability GUM "
          << fixed(e.conformity[k].gum_probability, 4) << ", MCM "
          << fixed(e.conformity[k].mcm_probability, 4) << "\n";
    }
    out << std::right;
  }
}

}  // namespace gearmc::uncertainty
