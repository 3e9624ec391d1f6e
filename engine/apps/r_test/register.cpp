// Implementation of register.h.
#include "engine/apps/r_test/register.h"

#include <stdexcept>

#include "engine/apps/r_test/r_test_model.h"
#include "engine/apps/uncertainty/model_function.h"

namespace gearmc::rtest {
namespace {

class RTestBuiltin final : public uncertainty::BuiltinModel {
 public:
  std::vector<std::string> output_names() const override { return {"x", "y", "z"}; }
  // Never called by the command (it runs evaluate_r_test); a caller that tries gets an error
  // rather than numbers.
  void evaluate(const double*, double*) const override {
    throw std::logic_error(
        "the r_test model is evaluated by evaluate_r_test (calibration, GUM, GUM+MCM, full MCM, "
        "verification), not trial by trial");
  }
};

}  // namespace

void register_r_test_model() {
  uncertainty::register_builtin_model(
      "r_test",
      [](const std::vector<std::string>& inputs, const std::map<std::string, double>& parameters) {
        (void)parse_r_test_settings(inputs, parameters);  // throws std::invalid_argument
        return std::make_shared<RTestBuiltin>();
      });
}

}  // namespace gearmc::rtest
