// Reading a model file (model.h). Every check names file:line:column through YamlValue/YamlMap.
#include "engine/apps/uncertainty/model.h"

#include <algorithm>
#include <cmath>
#include <set>
#include <stdexcept>

#include "core/input_file.h"
#include "core/number_text.h"
#include "core/yaml_reader.h"
#include "engine/apps/uncertainty/model_function.h"

namespace gearmc::uncertainty {
namespace {

const std::vector<std::string> kTopKeys = {"name",         "inputs",  "constants",
                                           "correlations", "outputs", "builtin",
                                           "tolerances",   "units",   "settings"};
const std::vector<std::string> kSettingKeys = {
    "coverage_probability", "trials", "significant_digits", "seed", "second_order", "max_trials"};

// [A-Za-z_][A-Za-z0-9_]* (ASCII), checked by hand: the standard regex engine recurses once per
// character.
bool valid_name(const std::string& s) {
  const auto letter = [](char c) {
    return (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z') || c == '_';
  };
  if (s.empty() || !letter(s[0])) return false;
  return std::all_of(s.begin() + 1, s.end(),
                     [&](char c) { return letter(c) || (c >= '0' && c <= '9'); });
}

void check_name(const YamlMap::Entry& e, std::set<std::string>& taken, const std::string& what) {
  // The key's own location: a bad name is pointed at where it is written.
  const InputLocation& where = e.value.key_location();
  if (!valid_name(e.key)) {
    throw InputError(where, e.value.path(), e.key,
                     "a " + what + " name of letters, digits and _ not starting with a digit");
  }
  if (!taken.insert(e.key).second) {
    throw InputError(where, e.value.path(), e.key,
                     "a name not already used by an input, constant or output");
  }
}

std::vector<double> numbers_of(const YamlValue& v) {
  std::vector<double> out;
  for (const YamlValue& x : v.as_sequence()) out.push_back(x.as_number());
  return out;
}

ModelInput read_input(const YamlMap::Entry& entry) {
  std::vector<std::string> keys = law_names();
  keys.push_back("dof");
  const std::string expected_law =
      "one law, e.g. {normal: [mean, sd]} (laws: normal, uniform, triangular, arcsine, "
      "trapezoidal, curvilinear_trapezoid, student_t, exponential, gamma, constant, data)";
  if (!entry.value.is_map()) throw entry.value.error(expected_law);
  const YamlMap m = entry.value.as_map(keys);
  std::optional<YamlMap::Entry> law_entry;
  for (const YamlMap::Entry& e : m.entries()) {
    if (e.key == "dof") continue;
    if (law_entry) {
      throw InputError(e.value.key_location(), e.value.path(), e.key,
                       "one law per input (already " + law_entry->key + ")");
    }
    law_entry = e;
  }
  if (!law_entry) throw InputError(m.location(), m.path(), "", expected_law);
  ModelInput in;
  in.name = entry.key;
  in.where = entry.value.location();
  const YamlValue& v = law_entry->value;
  in.law_text = law_entry->key + ": " + v.shown();
  const std::string expected = law_entry->key + " " + law_signature(law_entry->key);
  try {
    if (law_entry->key == "constant") {
      in.law = make_law(LawKind::kConstant, {v.as_number()});
    } else if (law_entry->key == "data") {
      if (!v.is_sequence()) throw v.error(expected);
      in.law = make_from_data(numbers_of(v));
    } else {
      if (!v.is_sequence()) throw v.error(expected);
      const auto& names = law_names();
      const auto kind = static_cast<LawKind>(std::find(names.begin(), names.end(), law_entry->key) -
                                             names.begin());
      in.law = make_law(kind, numbers_of(v));
    }
  } catch (const std::invalid_argument& e) {
    throw v.error(expected + " (" + e.what() + ")");
  }
  // The GUM and the MCM need the law's mean and variance as doubles: a uniform law over
  // [-1.7, 1e308] has a finite u whose square (the variance) overflows, and every sum over it
  // would be inf or nan.
  {
    const double mean = in.law.mean(), u = in.law.gum_u();
    if (!std::isfinite(mean) || !std::isfinite(u) || !std::isfinite(u * u * 16.0)) {
      throw v.error(expected + " whose mean and variance a double can hold (here mean " +
                    shortest_text(mean) + ", u " + shortest_text(u) + ")");
    }
  }
  in.dof = in.law.gum_dof();
  if (const auto dof = m.find("dof")) {
    if (in.law.kind() == LawKind::kStudentT) {
      throw dof->error("no dof here: the degrees of freedom of " + law_entry->key +
                       " are part of the law");
    }
    in.dof = dof->as_number(NumberRange::positive(), "degrees of freedom of u for the GUM");
  }
  return in;
}

void read_correlations(const YamlValue& v, UncertaintyModel& model) {
  const std::size_t n = model.inputs.size();
  model.correlation =
      Eigen::MatrixXd::Identity(static_cast<Eigen::Index>(n), static_cast<Eigen::Index>(n));
  model.copula = model.correlation;
  std::vector<std::string> names;
  for (const ModelInput& in : model.inputs) names.push_back(in.name);
  const std::string expected_pair = "[INPUT, INPUT, r], e.g. [X1, X2, 0.5]";
  if (!v.is_sequence()) throw v.error("a list of " + expected_pair);
  std::set<std::pair<std::size_t, std::size_t>> seen;
  for (const YamlValue& item : v.as_sequence()) {
    if (!item.is_sequence() || item.as_sequence().size() != 3) throw item.error(expected_pair);
    const std::vector<YamlValue> parts = item.as_sequence();
    std::size_t idx[2];
    for (int k = 0; k < 2; ++k) {
      const std::string name = parts[k].as_string();
      const auto it = std::find(names.begin(), names.end(), name);
      if (it == names.end()) throw parts[k].error("an input name", did_you_mean(name, names));
      idx[k] = static_cast<std::size_t>(it - names.begin());
      if (model.inputs[idx[k]].law.kind() == LawKind::kConstant) {
        throw parts[k].error("an input with a spread (" + name + " is a constant)");
      }
    }
    if (idx[0] == idx[1]) throw parts[1].error("another input than " + parts[0].as_string());
    const double r = parts[2].as_number(NumberRange::open(-1.0, 1.0), "a correlation coefficient");
    const auto key = std::minmax(idx[0], idx[1]);
    if (!seen.insert(key).second) throw item.error("each pair of inputs at most once");
    // The copula's normal correlation that gives the inputs this r (laws.h; r itself for two
    // normal inputs).
    double rho = r;
    try {
      rho = copula_correlation_for(model.inputs[idx[0]].law, model.inputs[idx[1]].law, r);
    } catch (const std::invalid_argument& e) {
      throw parts[2].error(std::string(e.what()) + " (" + parts[0].as_string() + ": " +
                           std::string(law_name(model.inputs[idx[0]].law.kind())) + ", " +
                           parts[1].as_string() + ": " +
                           std::string(law_name(model.inputs[idx[1]].law.kind())) + ")");
    }
    const auto a = static_cast<Eigen::Index>(idx[0]), b = static_cast<Eigen::Index>(idx[1]);
    model.correlation(a, b) = model.correlation(b, a) = r;
    model.copula(a, b) = model.copula(b, a) = rho;
    model.correlated = true;
  }
  if (!model.correlated) return;
  for (const Eigen::MatrixXd* m : {&model.correlation, &model.copula}) {
    const Eigen::LLT<Eigen::MatrixXd> llt(*m);
    if (llt.info() == Eigen::Success) continue;
    const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(*m);
    throw InputError(v.location(), v.path(), v.shown(),
                     std::string(m == &model.correlation
                                     ? "correlations that make a positive definite correlation "
                                       "matrix (its smallest eigenvalue is "
                                     : "correlations whose Gaussian copula has a positive "
                                       "definite correlation matrix (its smallest eigenvalue is ") +
                         std::to_string(eig.eigenvalues().minCoeff()) + ")");
  }
  model.cholesky = Eigen::LLT<Eigen::MatrixXd>(model.copula).matrixL();
}

}  // namespace

UncertaintyModel parse_uncertainty_model(const std::string& text, const std::string& file) {
  require_utf8(text, file, "model file");
  const YamlValue root = parse_yaml_document(text, file);
  const std::string expected_top =
      "a map of model keys (name, inputs, constants, correlations, outputs or builtin, "
      "settings)";
  if (root.is_null()) throw InputError(root.location(), "", "", expected_top + ", got nothing");
  if (!root.is_map()) throw root.error(expected_top);
  const YamlMap top = root.as_map(kTopKeys);
  UncertaintyModel model;
  model.source_path = file;
  model.source_text = text;
  model.name = top.get_string("name").value_or("model");
  if (!valid_name(model.name)) {
    throw top.find("name")->error("a name of letters, digits and _ (it names the output folder)");
  }

  std::set<std::string> taken;
  const YamlValue inputs_value = top.require("inputs", "inputs: {NAME: {LAW: [parameters]}, ...}");
  if (!inputs_value.is_map()) throw inputs_value.error("a map NAME: {LAW: [parameters]}");
  const YamlMap inputs = inputs_value.as_open_map();
  if (inputs.entries().empty()) throw inputs_value.error("at least one input");
  for (const YamlMap::Entry& e : inputs.entries()) {
    check_name(e, taken, "input");
    model.inputs.push_back(read_input(e));
  }
  if (const auto c = top.find("constants")) {
    if (!c->is_map()) throw c->error("a map NAME: number");
    const YamlMap constants = c->as_open_map();
    for (const YamlMap::Entry& e : constants.entries()) {
      check_name(e, taken, "constant");
      model.constants.emplace_back(e.key, e.value.as_number());
    }
  }
  if (const auto c = top.find("correlations")) {
    read_correlations(*c, model);
  } else {
    const auto n = static_cast<Eigen::Index>(model.inputs.size());
    model.correlation = Eigen::MatrixXd::Identity(n, n);
    model.copula = model.correlation;
  }

  const auto outputs = top.find("outputs");
  const auto builtin = top.find("builtin");
  if (outputs && builtin) {
    throw InputError(builtin->key_location(), "builtin", "", "either outputs or builtin, not both");
  }
  if (!outputs && !builtin) {
    throw top.missing("outputs", "outputs: {NAME: \"expression\"} (or builtin: {model: NAME})");
  }
  if (outputs) {
    if (!outputs->is_map()) throw outputs->error("a map NAME: \"muParser expression\"");
    const YamlMap outs = outputs->as_open_map();
    for (const YamlMap::Entry& e : outs.entries()) {
      check_name(e, taken, "output");
      if (!e.value.is_scalar()) throw e.value.error("a muParser expression in quotes");
      model.outputs.push_back({e.key, e.value.as_string(), e.value.location(), false, {}, {}});
    }
    if (model.outputs.empty()) throw outputs->error("at least one output");
  } else {
    if (!builtin->is_map()) throw builtin->error("{model: NAME, ...}");
    const YamlMap b = builtin->as_open_map();
    const YamlValue name = b.require("model", "model: NAME");
    model.builtin = name.as_string();
    const std::vector<std::string> known = builtin_model_names();
    if (std::find(known.begin(), known.end(), model.builtin) == known.end()) {
      std::string list;
      for (const std::string& k : known) list += (list.empty() ? "" : ", ") + k;
      throw name.error("a builtin model (" + list + ")", did_you_mean(model.builtin, known));
    }
    for (const YamlMap::Entry& e : b.entries()) {
      if (e.key != "model") model.builtin_parameters[e.key] = e.value.as_number();
    }
    std::vector<std::string> input_names;
    for (const ModelInput& in : model.inputs) input_names.push_back(in.name);
    try {
      const auto m = make_builtin_model(model.builtin, input_names, model.builtin_parameters);
      for (const std::string& o : m->output_names()) {
        model.outputs.push_back({o, "", builtin->location(), false, {}, {}});
      }
    } catch (const BuiltinParameterError& e) {
      if (const auto v = b.find(e.key)) {
        if (e.unknown_key) throw InputError(v->key_location(), v->path(), e.key, e.what());
        throw v->error(e.what());
      }
      for (const ModelInput& in : model.inputs) {
        if (in.name == e.key) throw InputError(in.where, "inputs." + e.key, e.key, e.what());
      }
      throw builtin->error(std::string("parameters the builtin model accepts (") + e.what() + ")");
    } catch (const std::invalid_argument& e) {
      throw builtin->error(std::string("parameters the builtin model accepts (") + e.what() + ")");
    }
  }

  // tolerances: {OUTPUT: {lower: TL, upper: TU}} (either may be left out): the JCGM 106
  // conformance probability of each such output.
  if (const auto tv = top.find("tolerances")) {
    if (!tv->is_map()) throw tv->error("a map of output names to {lower: …, upper: …}");
    std::vector<std::string> names;
    for (const ModelOutput& o : model.outputs) names.push_back(o.name);
    const YamlMap tolerances = tv->as_map(names);
    for (ModelOutput& o : model.outputs) {
      const auto limits = tolerances.get_map(o.name, {"lower", "upper"});
      if (!limits) continue;
      o.lower = limits->get_number("lower");
      o.upper = limits->get_number("upper");
      if (!o.lower && !o.upper) {
        throw limits->missing("upper", "a lower or an upper tolerance limit (or both)");
      }
      if (o.lower && o.upper && !(*o.lower < *o.upper)) {
        throw limits->require("upper", "")
            .error("an upper limit above the lower limit " + std::to_string(*o.lower));
      }
      o.has_tolerance = true;
    }
  }

  // units: {NAME: "unit"} for every input, constant and output, or none.
  if (const auto uv = top.find("units")) {
    std::vector<std::string> names;
    for (const ModelInput& in : model.inputs) names.push_back(in.name);
    for (const auto& [name, value] : model.constants) names.push_back(name);
    for (const ModelOutput& o : model.outputs) names.push_back(o.name);
    if (!uv->is_map()) throw uv->error("a map NAME: unit (e.g. {L: mm, alpha: um/m K})");
    const YamlMap units = uv->as_map(names);
    std::string missing;
    for (const std::string& name : names) {
      const auto v = units.find(name);
      if (!v) {
        missing += (missing.empty() ? "" : ", ") + name;
        continue;
      }
      if (!v->is_scalar()) throw v->error("a unit such as mm, kg/m^3, um/K or 1");
      try {
        model.units[name] = {parse_unit(v->as_string()), v->as_string(), v->location()};
      } catch (const std::invalid_argument& e) {
        throw v->error(std::string("a unit: ") + e.what());
      }
    }
    if (!missing.empty()) {
      throw uv->error(
          "a unit for every input, constant and output (1 for a pure number); "
          "missing: " +
          missing);
    }
  }

  ModelSettings& s = model.settings;
  if (const auto sv = top.find("settings")) {
    model.settings_where = sv->location();
    if (!sv->is_map()) throw sv->error("a map of settings");
    const YamlMap m = sv->as_map(kSettingKeys);
    if (const auto p = m.get_number("coverage_probability", NumberRange::probability())) {
      s.coverage_probability = *p;
    }
    if (const auto t = m.find("trials")) {
      if (t->is_scalar() && !t->is_quoted() && t->as_string() == "adaptive") {
        s.trials.reset();
      } else if (t->is_scalar() && !t->is_quoted() && t->as_string() != "adaptive" &&
                 std::isalpha(static_cast<unsigned char>(t->as_string()[0]))) {
        throw t->error("adaptive or a number of trials",
                       did_you_mean(t->as_string(), {"adaptive"}));
      } else {
        s.trials = static_cast<std::uint64_t>(t->as_int(1, 4'000'000'000));
      }
    }
    if (const auto d = m.get_int("significant_digits", 1, 4)) s.significant_digits = int(*d);
    if (const auto seed = m.get_uint64("seed")) s.seed = *seed;
    if (const auto so = m.get_bool("second_order")) s.second_order = *so;
    if (const auto mt = m.get_int("max_trials", 10'000, 4'000'000'000)) {
      s.max_trials = static_cast<std::uint64_t>(*mt);
    }
  }
  // Compile once now, so a bad expression is reported before any work.
  const ModelFunction check(model);
  if (!model.units.empty()) check_model_units(model);
  return model;
}

UncertaintyModel load_uncertainty_model(const std::string& path) {
  return parse_uncertainty_model(read_input_file(path, "model file", kMaxScenarioBytes), path);
}

}  // namespace gearmc::uncertainty
