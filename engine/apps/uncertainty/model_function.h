// The measurement function Y = f(X) of an UncertaintyModel, ready to evaluate: its output
// expressions compiled by muParser (bound to a private input array), or a compiled C++ model
// from the builtin registry. muParser keeps evaluation state, so a ModelFunction is not
// thread-safe: each worker thread makes its own (construction costs one parse per output).
#pragma once

#include <functional>
#include <map>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

namespace gearmc::uncertainty {

struct UncertaintyModel;

// A measurement model written in C++ (e.g. a later R-Test model), selected in the model file by
// `builtin: {model: NAME, key: number, ...}`. evaluate() must be thread-safe (const, no state).
class BuiltinModel {
 public:
  virtual ~BuiltinModel() = default;
  virtual std::vector<std::string> output_names() const = 0;
  // x: the inputs in model-file order; y: one value per output.
  virtual void evaluate(const double* x, double* y) const = 0;
};

// What a builtin factory throws when one key of `builtin:` is wrong: the reader then points at
// that key (`unknown_key`: a key the model does not have) or at its value in the model file; a
// `key` that names an input instead points at that input; an empty key at the `builtin:` map.
// what(): the expectation, e.g. "a radius in [1, 100] mm".
struct BuiltinParameterError : std::invalid_argument {
  BuiltinParameterError(std::string key_, const std::string& what, bool unknown)
      : std::invalid_argument(what), key(std::move(key_)), unknown_key(unknown) {}
  std::string key;
  bool unknown_key = false;
};

// Makes a builtin model for the named inputs and the numeric keys of `builtin:` (besides
// `model`); throws std::invalid_argument with the reason when they do not fit.
using BuiltinFactory = std::function<std::shared_ptr<const BuiltinModel>(
    const std::vector<std::string>& inputs, const std::map<std::string, double>& parameters)>;

// Adds a model to the registry (a later name replaces an earlier one). Built in: `sum`
// (output Y = the sum of all inputs; a reference for the registry and its tests).
void register_builtin_model(const std::string& name, BuiltinFactory factory);
std::vector<std::string> builtin_model_names();
// Null when no model has that name.
std::shared_ptr<const BuiltinModel> make_builtin_model(
    const std::string& name, const std::vector<std::string>& inputs,
    const std::map<std::string, double>& parameters);

class ModelFunction {
 public:
  // Compiles the model's expressions (throws InputError at an output whose expression muParser
  // refuses, naming an unknown name with a "did you mean"), or makes its builtin model.
  explicit ModelFunction(const UncertaintyModel& model);
  ~ModelFunction();
  ModelFunction(const ModelFunction&) = delete;
  ModelFunction& operator=(const ModelFunction&) = delete;

  std::size_t inputs() const { return n_inputs_; }
  std::size_t outputs() const { return n_outputs_; }
  // y = f(x): x has inputs() values (model order), y receives outputs() values.
  void evaluate(const double* x, double* y);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  std::size_t n_inputs_ = 0, n_outputs_ = 0;
};

}  // namespace gearmc::uncertainty
