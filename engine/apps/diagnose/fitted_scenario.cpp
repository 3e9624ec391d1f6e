// fitted.yaml: the model scenario plus the named effect(s) with their fitted parameters (see
// fitted_scenario.h).
#include "engine/apps/diagnose/fitted_scenario.h"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <stdexcept>

#include "engine/apps/diagnose/candidates.h"
#include "engine/effects/empirical_effect.h"
#include "engine/effects/lobing_harmonic.h"
#include "engine/effects/measurement_effect.h"
#include "engine/effects/warmup_straightness.h"

namespace gearmc {
namespace {

constexpr double kSteelCtePpmPerK =
    11.5;  // the thermal_expansion candidate's column (candidates.h)

// The model's text emitted again: maps and sequences in their own (flow or block) style, scalars
// verbatim, quoted scalars quoted (a quoted "7" must stay text), null as ~.
void emit(YAML::Emitter& out, const YAML::Node& node) {
  switch (node.Type()) {
    case YAML::NodeType::Map:
      if (node.Style() == YAML::EmitterStyle::Flow) out << YAML::Flow;
      out << YAML::BeginMap;
      for (auto it = node.begin(); it != node.end(); ++it) {
        out << YAML::Key;
        emit(out, it->first);
        out << YAML::Value;
        emit(out, it->second);
      }
      out << YAML::EndMap;
      break;
    case YAML::NodeType::Sequence:
      if (node.Style() == YAML::EmitterStyle::Flow) out << YAML::Flow;
      out << YAML::BeginSeq;
      for (const YAML::Node& item : node) emit(out, item);
      out << YAML::EndSeq;
      break;
    case YAML::NodeType::Scalar:
      if (node.Tag() == "!" || node.Tag() == "tag:yaml.org,2002:str") out << YAML::DoubleQuoted;
      out << node.Scalar();
      break;
    default:
      out << YAML::Null;
  }
}

YAML::Node number_node(double value) { return YAML::Node(format_fitted_number(value)); }

YAML::Node flow_map() {
  YAML::Node n(YAML::NodeType::Map);
  n.SetStyle(YAML::EmitterStyle::Flow);
  return n;
}

// The model's parameter `name` of `effect`, or null.
const EffectParameter* model_parameter(const MeasurementEffect* effect, const std::string& name) {
  if (!effect) return nullptr;
  for (const EffectParameter& p : effect->parameters()) {
    if (p.name == name) return &p;
  }
  return nullptr;
}

// The parameter `model` (absent: 0) moved by `increment`, as a YAML value (law kept).
YAML::Node shifted(const EffectParameter* model, double increment) {
  if (!model || model->law == EffectParameter::Law::kFixed) {
    return number_node((model ? model->value : 0.0) + increment);
  }
  YAML::Node law = flow_map();
  YAML::Node pair(YAML::NodeType::Sequence);
  pair.SetStyle(YAML::EmitterStyle::Flow);
  if (model->law == EffectParameter::Law::kUniform) {
    pair.push_back(number_node(model->lo + increment));
    pair.push_back(number_node(model->hi + increment));
    law["uniform"] = pair;
  } else {
    pair.push_back(number_node(model->value + increment));
    pair.push_back(number_node(model->spread));
    law["normal"] = pair;
  }
  return law;
}

const FittedValue* fitted(const std::vector<FittedValue>& values, const std::string& name) {
  for (const FittedValue& v : values) {
    if (v.name == name && v.estimable && std::isfinite(v.value)) return &v;
  }
  return nullptr;
}

// probe_lobing: p0 and the harmonics (see the header).
void update_lobing(YAML::Node entry, const MeasurementEffect* model, const FittedEffect& e,
                   std::vector<std::string>* notes) {
  const bool from_model = entry["from_probe_model"].IsDefined();
  if (from_model) {
    entry.remove("from_probe_model");
    notes->push_back(
        "probe_lobing: the model's from_probe_model is replaced by its p0 and harmonics (the "
        "probe model's values) plus the fitted increments");
  }
  const EffectParameter* p0 = model_parameter(model, "pretravel_um");
  if (const FittedValue* v = fitted(e.coefficients, "pretravel_um")) {
    entry["pretravel_um"] = shifted(p0, v->value);
  } else if (from_model && p0) {
    entry["pretravel_um"] = shifted(p0, 0.0);
  }
  // The orders the model has (in its order) and the fitted ones.
  std::vector<int> orders;
  if (model) {
    for (const EffectParameter& p : model->parameters()) {
      int k = 0;
      if (std::sscanf(p.name.c_str(), "amplitude_%d_um", &k) == 1) orders.push_back(k);
    }
  }
  std::vector<int> fitted_orders;
  for (const FittedValue& v : e.coefficients) {
    int k = 0;
    if (std::sscanf(v.name.c_str(), "cos_%d_um", &k) != 1) continue;
    const std::string order = std::to_string(k);
    if (fitted(e.coefficients, "cos_" + order + "_um") &&
        fitted(e.coefficients, "sin_" + order + "_um")) {
      fitted_orders.push_back(k);
      if (std::find(orders.begin(), orders.end(), k) == orders.end()) orders.push_back(k);
    }
  }
  if (fitted_orders.empty() && !from_model) return;
  // The model's YAML items by order (kept verbatim when the fit does not touch them).
  std::vector<std::pair<int, YAML::Node>> items;
  if (entry["harmonics"].IsSequence()) {
    for (const YAML::Node& item : entry["harmonics"]) {
      items.emplace_back(item["order"].as<int>(), item);
    }
  }
  YAML::Node harmonics(YAML::NodeType::Sequence);
  for (int k : orders) {
    const std::string order = std::to_string(k);
    const bool refit =
        std::find(fitted_orders.begin(), fitted_orders.end(), k) != fitted_orders.end();
    const auto old =
        std::find_if(items.begin(), items.end(), [k](const auto& item) { return item.first == k; });
    if (!refit && old != items.end()) {
      harmonics.push_back(old->second);
      continue;
    }
    const EffectParameter* a = model_parameter(model, "amplitude_" + order + "_um");
    const EffectParameter* phase = model_parameter(model, "phase_" + order + "_deg");
    const LobingHarmonic model_harmonic{k, a ? a->nominal() : 0.0, phase ? phase->nominal() : 0.0};
    double c = model_harmonic.cos_component_um(), s = model_harmonic.sin_component_um();
    if (refit) {
      c += fitted(e.coefficients, "cos_" + order + "_um")->value;
      s += fitted(e.coefficients, "sin_" + order + "_um")->value;
      if ((a && a->law != EffectParameter::Law::kFixed) ||
          (phase && phase->law != EffectParameter::Law::kFixed)) {
        notes->push_back("probe_lobing: order " + order +
                         " was drawn from a law in the model; it is written as a fixed value "
                         "(the law's central value plus the fitted increment)");
      }
    }
    const LobingHarmonic written = LobingHarmonic::from_components(k, c, s);
    YAML::Node item = flow_map();
    item["order"] = k;
    item["amplitude_um"] = number_node(written.amplitude_um);
    item["phase_deg"] = number_node(written.phase_deg);
    harmonics.push_back(item);
  }
  entry["harmonics"] = harmonics;
  const YAML::Node calibration = entry["calibration"];
  if (calibration.IsDefined() && calibration.IsScalar() && calibration.Scalar() != "none") {
    notes->push_back(
        "probe_lobing: the model qualifies the probe (calibration: " + calibration.Scalar() +
        "); the fitted increments are raw pre-travel, and the qualification also compensates part "
        "of them, so this model may not reproduce the fit exactly (see the README's limits)");
  }
}

// Writes the diagnosis's empirical term into `effects` (a map). A model empirical term on the same
// axis, basis and range gets the fitted terms added order by order; one on another axis, basis or
// range is kept as it is and the new term is not written (a scenario holds one empirical term).
void write_empirical(YAML::Node effects, const MeasurementEffect* own, const EmpiricalTerm& term,
                     std::vector<std::string>* notes, std::vector<std::string>* updated) {
  const auto* model = dynamic_cast<const EmpiricalEffect*>(own);
  const bool legendre = term.basis == "legendre";
  std::map<int, std::pair<double, double>> by_order;  // order → (a, b), µm
  if (model) {
    const bool same = empirical_axis_name(model->axis()) == term.axis &&
                      empirical_basis_name(model->basis()) == term.basis &&
                      (!legendre || (std::abs(model->from() - term.from) < 1e-9 &&
                                     std::abs(model->to() - term.to) < 1e-9));
    if (!same) {
      notes->push_back("the model already has an empirical term along " +
                       std::string(empirical_axis_name(model->axis())) + "; the new one along " +
                       term.axis + " was not written (a scenario holds one empirical term)");
      return;
    }
    std::size_t at = 0;
    const std::vector<EffectParameter>& p = model->parameters();
    for (int k : model->orders()) {
      by_order[k].first = p[at++].nominal();
      if (!legendre) by_order[k].second = p[at++].nominal();
    }
  }
  for (const EmpiricalTermValue& v : term.terms) {
    const int k = std::stoi(v.name.substr(2));
    (v.name[0] == 'a' ? by_order[k].first : by_order[k].second) += v.value_um;
  }
  YAML::Node entry(YAML::NodeType::Map);
  entry.SetStyle(YAML::EmitterStyle::Block);
  entry["axis"] = term.axis;
  entry["basis"] = term.basis;
  if (legendre) {
    entry["from"] = number_node(term.from);
    entry["to"] = number_node(term.to);
  }
  YAML::Node terms(YAML::NodeType::Sequence);
  for (const auto& [k, ab] : by_order) {
    YAML::Node t = flow_map();
    t["order"] = k;
    t["a_um"] = number_node(ab.first);
    if (!legendre) t["b_um"] = number_node(ab.second);
    terms.push_back(t);
  }
  entry["terms"] = terms;
  effects["empirical"] = entry;
  updated->push_back("empirical");
  notes->push_back("empirical: a " + term.basis + " term of order " + std::to_string(term.order) +
                   " along " + term.axis +
                   " describes the structure the library leaves; it is not a physical effect");
}

}  // namespace

std::string format_fitted_number(double value) {
  if (!std::isfinite(value)) return "0";
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, "%.6f", value);
  std::string text = buffer;
  while (!text.empty() && text.back() == '0') text.pop_back();
  if (!text.empty() && text.back() == '.') text.pop_back();
  if (text == "-0" || text.empty()) text = "0";
  return text;
}

FittedScenario fitted_scenario(const Scenario& model, const Diagnosis& d,
                               const std::string& model_path, const std::string& readings_path) {
  FittedScenario result;
  YAML::Node root;
  try {
    root = YAML::Load(model.source_text);
  } catch (const YAML::Exception& e) {
    throw std::runtime_error("fitted.yaml: cannot re-read the model scenario: " +
                             std::string(e.what()));
  }
  if (!root.IsMap()) throw std::runtime_error("fitted.yaml: the model scenario is not a map");

  // Relative mesh paths were taken from the model's folder: make them absolute.
  if (root["surfaces"].IsSequence()) {
    std::size_t k = 0;
    for (YAML::Node item : root["surfaces"]) {
      if (k < model.surfaces.size() && item.IsMap()) {
        item["mesh"] = std::filesystem::absolute(model.surfaces[k].mesh_path).string();
      }
      ++k;
    }
  }

  const bool named = d.finding == DiagnosisFinding::kEffect;
  const bool with_empirical = d.finding == DiagnosisFinding::kUnexplained && d.empirical.fitted;
  // Structure remains and no empirical term describes it: the accepted fit (the library's effects
  // that passed the selection and the held-out rule) is still written, as part of the answer.
  const bool partial = d.finding == DiagnosisFinding::kUnexplained && !d.empirical.fitted &&
                       !d.effects.empty() && !d.fit_refused;
  if (named || with_empirical || partial) {
    YAML::Node effects = root["effects"];
    if (!effects.IsMap()) {
      root["effects"] = YAML::Node(YAML::NodeType::Map);
      effects = root["effects"];
    }
    effects.SetStyle(YAML::EmitterStyle::Block);
    // With an empirical term: the library effects fitted beside it (empirical_term.h).
    for (const FittedEffect& e : with_empirical ? d.effects_with_empirical : d.effects) {
      const int index = model.effects->find(e.name);
      const MeasurementEffect* own = index >= 0 ? &model.effects->effect(index) : nullptr;
      YAML::Node entry = effects[e.name];
      // Absent, empty, or switched off (its values had no effect): a fresh map.
      if (!own || !entry.IsMap()) {
        effects[e.name] = YAML::Node(YAML::NodeType::Map);
        entry = effects[e.name];
        own = nullptr;
      }
      entry.SetStyle(YAML::EmitterStyle::Block);
      if (e.absolute) {
        // Point-law effects: their own values (diagnosis.h). Noise: σ of the readings' whole
        // Gaussian part, less what the model's other Gaussian parts (probe repeatability) give.
        for (const FittedValue& v : e.parameters) {
          if (!v.estimable || !std::isfinite(v.value)) continue;
          double value = std::max(0.0, v.value);
          if (e.name == "noise") {
            const EffectValues nominal = model.effects->nominal();
            double others = model.effects->point_law(nominal).gaussian_variance_um2;
            if (index >= 0) {
              others -= model.effects->effect(index)
                            .point_law(nominal[static_cast<std::size_t>(index)])
                            .gaussian_variance_um2;
            }
            value = std::sqrt(std::max(0.0, value * value - others));
          }
          entry[v.name] = number_node(value);
        }
      } else if (e.name == "probe_lobing") {
        update_lobing(entry, own, e, &result.notes);
      } else {
        for (const FittedValue& v : e.parameters) {
          if (!v.estimable || !std::isfinite(v.value)) continue;
          double increment = v.value;
          if (e.name == "thermal_expansion" && v.name == "workpiece_delta_t_k") {
            const EffectParameter* cte = model_parameter(own, "workpiece_cte_ppm_per_k");
            if (cte && cte->nominal() > 0.0) {
              increment *= kSteelCtePpmPerK / cte->nominal();
            } else if (cte) {  // CTE 0: the model's ΔT did nothing; start from steel
              entry["workpiece_cte_ppm_per_k"] = number_node(kSteelCtePpmPerK);
              entry[v.name] = number_node(increment);
              continue;
            }
          }
          // straightness: the candidate's columns are at L = 100 mm; the model's own L scales them
          // by (L/100)² (the bow at the same travel).
          if (const auto* straight = dynamic_cast<const StraightnessEffect*>(own)) {
            const double ratio = straight->length_mm() / kStraightnessLengthMm;
            increment *= ratio * ratio;
          }
          const EffectParameter* mine = model_parameter(own, v.name);
          YAML::Node value = shifted(mine, increment);
          // Different from gear to gear: a normal law with the shared value as its mean and the
          // spread of the per-gear values as its standard deviation.
          if (e.varies_per_gear && e.per_gear.size() >= 2) {
            std::vector<double> per_gear;
            double se2 = 0.0;  // mean squared standard error of the per-gear values
            for (const FittedEffect::GearValues& g : e.per_gear) {
              for (const FittedValue& c : g.coefficients) {
                if (c.name == v.name && c.estimable) {
                  per_gear.push_back(c.value);
                  se2 += c.std_error * c.std_error;
                }
              }
            }
            if (!per_gear.empty()) se2 /= static_cast<double>(per_gear.size());
            // A law only for a parameter whose per-gear values spread more than their own
            // estimation error (sample variance > 4 × mean squared standard error); the others
            // keep the shared value.
            double spread2 = 0.0;
            if (per_gear.size() >= 2) {
              double m = 0.0;
              for (double x : per_gear) m += x;
              m /= static_cast<double>(per_gear.size());
              for (double x : per_gear) spread2 += (x - m) * (x - m);
              spread2 /= static_cast<double>(per_gear.size() - 1);
            }
            if (per_gear.size() >= 2 && spread2 > 4.0 * se2) {
              double mean = 0.0, ss = 0.0;
              for (double x : per_gear) mean += x;
              mean /= static_cast<double>(per_gear.size());
              for (double x : per_gear) ss += (x - mean) * (x - mean);
              const double sd = std::sqrt(ss / static_cast<double>(per_gear.size() - 1));
              const double centre = (mine ? mine->nominal() : 0.0) + increment;
              YAML::Node law = flow_map();
              YAML::Node pair(YAML::NodeType::Sequence);
              pair.SetStyle(YAML::EmitterStyle::Flow);
              pair.push_back(number_node(centre));
              pair.push_back(number_node(sd));
              law["normal"] = pair;
              value = law;
              result.notes.push_back(e.name + "." + v.name +
                                     " differs from gear to gear: written as a normal law, "
                                     "sd = the spread of the " +
                                     std::to_string(per_gear.size()) + " per-gear values");
            }
          }
          if (e.name == "step_quantization" && v.name == "step_um" && value.IsScalar() &&
              std::stod(value.Scalar()) < 0.0) {
            result.notes.push_back("step_quantization: the fitted step_um " +
                                   format_fitted_number(std::stod(value.Scalar())) +
                                   " µm is negative; written as 0");
            value = number_node(0.0);
          }
          entry[v.name] = value;
        }
      }
      if (e.name == "artefact_form") {  // the ranges the terms were fitted on
        for (const auto& [key, value] : e.settings) {
          if (own && entry[key].IsDefined() &&
              std::abs(entry[key].as<double>(value) - value) > 1e-9) {
            result.notes.push_back(
                "artefact_form: the model's own terms were given on another "
                "range; the fitted increments are on the measured range (" +
                key + " " + format_fitted_number(value) + "), check the terms written");
          }
          entry[key] = number_node(value);
        }
        result.notes.push_back(
            "artefact_form is the master gear's own profile and helix form (a property of the "
            "artefact, not of the CMM): keep it with this artefact, do not correct the CMM with "
            "it");
      }
      if (const auto* warmup = dynamic_cast<const ProbeWarmupEffect*>(own);
          warmup && std::abs(warmup->time_constant() - kWarmupTimeConstant) > 1e-12) {
        result.notes.push_back(
            "probe_warmup: the fit assumed the time constant " +
            format_fitted_number(kWarmupTimeConstant) + " of the sequence, the model has " +
            format_fitted_number(warmup->time_constant()) +
            "; the fitted change_um is first order only for the model's constant");
      }
      result.updated.push_back(e.name);
    }
    for (const std::string& other : d.ambiguous_with) {
      result.notes.push_back(d.named_effect + " cannot be told apart from " + other +
                             " on this probing plan; the fit is written as " + d.named_effect);
    }
    if (with_empirical) {
      const int index = model.effects->find("empirical");
      write_empirical(effects, index >= 0 ? &model.effects->effect(index) : nullptr, d.empirical,
                      &result.notes, &result.updated);
      if (!d.effects_with_empirical.empty()) {
        result.notes.push_back(
            "the library effects written with it explain only part of the gap (the verdict is "
            "unexplained)");
      }
    }
  }
  if (partial) {
    result.notes.push_back(
        "the library effects written explain only part of the gap (the verdict is unexplained: "
        "structure remains that no effect or empirical term describes)");
  } else if (!named && !with_empirical) {
    result.notes.push_back(
        d.finding == DiagnosisFinding::kUnexplained
            ? "the gap is not explained by the effect library; no effect was added (the model is "
              "unchanged)"
            : "no gap: no effect was added (the model is unchanged)");
  }

  // The model's name stays the scenario's name (without `name:` it would become "fitted").
  YAML::Node named_root(YAML::NodeType::Map);
  const bool add_name = !root["name"].IsDefined();
  if (add_name) {
    named_root["name"] = model.name;
    for (auto it = root.begin(); it != root.end(); ++it) named_root[it->first] = it->second;
  }

  YAML::Emitter out;
  emit(out, add_name ? named_root : root);
  std::string text = "# Written by gearmc diagnose: the model " + model_path +
                     " fitted to the readings " + readings_path + ".\n";
  if (!result.updated.empty()) {
    text += "# Effects added or updated with their fitted parameters:";
    for (const std::string& name : result.updated) text += " " + name;
    text += ".\n";
  }
  for (const std::string& note : result.notes) text += "# Note: " + note + ".\n";
  text += "# (The model's comments are not carried over.)\n";
  text += out.c_str();
  text += "\n";
  result.yaml = std::move(text);
  return result;
}

}  // namespace gearmc
