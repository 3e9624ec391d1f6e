// Implementation of model_function.h.
#include "engine/apps/uncertainty/model_function.h"

#include <muParser.h>

#include <algorithm>
#include <mutex>
#include <numeric>
#include <optional>
#include <stdexcept>

#include "core/input_error.h"
#include "engine/apps/uncertainty/model.h"

namespace gearmc::uncertainty {
namespace {

class SumModel final : public BuiltinModel {
 public:
  explicit SumModel(std::size_t n) : n_(n) {}
  std::vector<std::string> output_names() const override { return {"Y"}; }
  void evaluate(const double* x, double* y) const override {
    y[0] = std::accumulate(x, x + n_, 0.0);
  }

 private:
  std::size_t n_;
};

struct Registry {
  std::mutex mutex;
  std::map<std::string, BuiltinFactory> factories;
  Registry() {
    factories["sum"] = [](const std::vector<std::string>& inputs,
                          const std::map<std::string, double>& parameters) {
      if (!parameters.empty()) {
        throw std::invalid_argument("the builtin model 'sum' takes no parameters besides model");
      }
      return std::make_shared<SumModel>(inputs.size());
    };
  }
};

Registry& registry() {
  static Registry r;
  return r;
}

}  // namespace

void register_builtin_model(const std::string& name, BuiltinFactory factory) {
  Registry& r = registry();
  std::lock_guard lock(r.mutex);
  r.factories[name] = std::move(factory);
}

std::vector<std::string> builtin_model_names() {
  Registry& r = registry();
  std::lock_guard lock(r.mutex);
  std::vector<std::string> names;
  for (const auto& [name, f] : r.factories) names.push_back(name);
  return names;
}

std::shared_ptr<const BuiltinModel> make_builtin_model(
    const std::string& name, const std::vector<std::string>& inputs,
    const std::map<std::string, double>& parameters) {
  BuiltinFactory factory;
  {
    Registry& r = registry();
    std::lock_guard lock(r.mutex);
    const auto it = r.factories.find(name);
    if (it == r.factories.end()) return nullptr;
    factory = it->second;
  }
  return factory(inputs, parameters);
}

struct ModelFunction::Impl {
  std::vector<double> values;  // inputs, then outputs: the variables muParser reads
  std::vector<mu::Parser> parsers;
  std::shared_ptr<const BuiltinModel> builtin;
};

namespace {

// The position of an assignment operator in a muParser expression ('=' that is not part of
// ==, !=, <= or >=; +=, -=, *= and /= are assignments too), or nothing.
std::optional<std::size_t> assignment_at(const std::string& e) {
  for (std::size_t i = 0; i < e.size(); ++i) {
    if (e[i] != '=') continue;
    if (i + 1 < e.size() && e[i + 1] == '=') {  // ==
      ++i;
      continue;
    }
    if (i > 0 && (e[i - 1] == '<' || e[i - 1] == '>' || e[i - 1] == '!')) continue;
    return i;
  }
  return std::nullopt;
}

}  // namespace

ModelFunction::ModelFunction(const UncertaintyModel& model) : impl_(std::make_unique<Impl>()) {
  n_inputs_ = model.inputs.size();
  n_outputs_ = model.outputs.size();
  std::vector<std::string> input_names;
  for (const ModelInput& in : model.inputs) input_names.push_back(in.name);
  if (!model.builtin.empty()) {
    impl_->builtin = make_builtin_model(model.builtin, input_names, model.builtin_parameters);
    if (!impl_->builtin) throw std::logic_error("unknown builtin model " + model.builtin);
    return;
  }
  impl_->values.assign(n_inputs_ + n_outputs_, 0.0);
  impl_->parsers.resize(n_outputs_);
  for (std::size_t j = 0; j < n_outputs_; ++j) {
    mu::Parser& p = impl_->parsers[j];
    std::vector<std::string> known;
    try {
      for (std::size_t i = 0; i < n_inputs_; ++i) {
        p.DefineVar(model.inputs[i].name, &impl_->values[i]);
        known.push_back(model.inputs[i].name);
      }
      for (const auto& [name, value] : model.constants) {
        p.DefineConst(name, value);
        known.push_back(name);
      }
      for (std::size_t k = 0; k < j; ++k) {
        p.DefineVar(model.outputs[k].name, &impl_->values[n_inputs_ + k]);
        known.push_back(model.outputs[k].name);
      }
      // muParser takes `X1 = 3` (and +=, -=, *=, /=) as an assignment to the input's storage: the
      // output would be the constant 3 and X1 overwritten. Refused before the parser sees it.
      if (const auto at = assignment_at(model.outputs[j].expression)) {
        const ModelOutput& out = model.outputs[j];
        throw InputError(out.where, "outputs." + out.name, out.expression,
                         "an expression, not an assignment ('=' at character " +
                             std::to_string(*at + 1) + "; comparisons are ==, !=, <= and >=)");
      }
      p.SetExpr(model.outputs[j].expression);
      (void)p.Eval();  // compiles now: unknown names and syntax errors are found here
    } catch (const mu::Parser::exception_type& e) {
      const ModelOutput& out = model.outputs[j];
      const std::string key = "outputs." + out.name;
      if (e.GetCode() == mu::ecUNASSIGNABLE_TOKEN) {
        const std::string token = shown_input(e.GetToken());
        std::string expected = "an expression of the inputs, constants";
        if (j > 0) expected += " and earlier outputs";
        expected += ": '" + token + "' is none of them";
        for (std::size_t k = j; k < n_outputs_; ++k) {
          if (model.outputs[k].name == token) {
            expected += " (outputs may use only outputs listed before them)";
          }
        }
        throw InputError(out.where, key, out.expression, expected, did_you_mean(token, known));
      }
      throw InputError(
          out.where, key, out.expression,
          "a muParser expression (muParser: " + shown_input(e.GetMsg(), 2 * kShownChars) +
              " at character " + std::to_string(e.GetPos() + 1) + ")");
    }
  }
}

ModelFunction::~ModelFunction() = default;

void ModelFunction::evaluate(const double* x, double* y) {
  if (impl_->builtin) {
    impl_->builtin->evaluate(x, y);
    return;
  }
  double* v = impl_->values.data();
  std::copy(x, x + n_inputs_, v);
  for (std::size_t j = 0; j < n_outputs_; ++j) {
    const double value = impl_->parsers[j].Eval();
    v[n_inputs_ + j] = value;
    y[j] = value;
  }
}

}  // namespace gearmc::uncertainty
