// A measurement model for `gearmc uncertainty` (JCGM 101:2008 §6): named inputs with their
// probability laws, named constants, correlations between inputs (of any laws), and one or more
// outputs written as muParser expressions of the inputs, the constants and the earlier outputs
// — or a compiled (builtin) model — plus the settings of the evaluation. Read from YAML as
// strictly as a scenario: every mistake is an InputError at file:line:column (docs/uncertainty.md
// lists every key).
#pragma once

#include <Eigen/Dense>

#include <cstdint>
#include <limits>
#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "core/input_error.h"
#include "engine/apps/uncertainty/laws.h"
#include "engine/apps/uncertainty/units.h"

namespace gearmc::uncertainty {

struct ModelInput {
  std::string name;
  Law law;
  std::string law_text;  // as written, e.g. "uniform: [1.10, 1.30]"
  // Degrees of freedom of the standard uncertainty for the GUM: the stated `dof:` of a Type B
  // input (default +inf), n − 1 for `data:`, ν for `student_t:`.
  double dof = std::numeric_limits<double>::infinity();
  InputLocation where;
};

struct ModelOutput {
  std::string name;
  std::string expression;  // empty for a builtin model's output
  InputLocation where;
  // Tolerance limits of the output (model file `tolerances:`; JCGM 106 conformity): absent =
  // no such limit. At least one is set when `has_tolerance`.
  bool has_tolerance = false;
  std::optional<double> lower, upper;
};

// A quantity's unit as the model file states it (`units:`).
struct ModelUnit {
  Unit unit;
  std::string text;  // as written, e.g. "kg/m^3"
  InputLocation where;
};

struct ModelSettings {
  double coverage_probability = 0.95;
  std::optional<std::uint64_t> trials;  // nullopt: adaptive (JCGM 101 §7.9)
  int significant_digits = 2;           // ndig of JCGM 101 §7.9.2 (1 to 4)
  std::uint64_t seed = 1;
  bool second_order = false;  // the GUM's higher-order terms (JCGM 100 5.1.2, note)
  // Cap of the adaptive procedure (trials), reached: results with converged = false.
  std::uint64_t max_trials = 50'000'000;
};

struct UncertaintyModel {
  std::string name;
  std::string source_path, source_text;
  std::vector<ModelInput> inputs;
  std::vector<std::pair<std::string, double>> constants;
  // Correlation matrix of all inputs (identity where nothing is stated) and whether any
  // correlation is stated; its Cholesky factor (lower) when correlated.
  Eigen::MatrixXd correlation;
  // The Gaussian copula's correlation of the normal variables behind the inputs (laws.h: equal
  // to `correlation` between normal inputs) and its Cholesky factor (lower) when correlated.
  Eigen::MatrixXd copula;
  Eigen::MatrixXd cholesky;
  bool correlated = false;
  std::vector<ModelOutput> outputs;
  std::string builtin;  // name of a compiled model, or empty
  std::map<std::string, double> builtin_parameters;
  ModelSettings settings;
  InputLocation settings_where;
  // `units:` per input, constant and output (every one, when given; empty: no units), checked
  // against the expressions when read (units.h).
  std::map<std::string, ModelUnit> units;
};

// " (mg)": a quantity's unit for labels, "" when the model states no units.
inline std::string unit_label(const UncertaintyModel& model, const std::string& name) {
  const auto it = model.units.find(name);
  return it == model.units.end() ? "" : " (" + it->second.text + ")";
}

// Parses the YAML text of a model file (`file` names it in messages). Throws InputError.
UncertaintyModel parse_uncertainty_model(const std::string& text, const std::string& file);
// Reads and parses a model file (regular file, at most 64 MiB, UTF-8).
UncertaintyModel load_uncertainty_model(const std::string& path);

// Largest memory for the stored output values: 8 bytes per trial per output, and 8 more per
// trial while one output is sorted for its coverage intervals — counted as 16 bytes per trial
// per output. Larger runs are refused.
inline constexpr double kMaxValueBytes = 8.0 * (1ull << 30);
inline constexpr double kBytesPerTrialPerOutput = 16.0;

}  // namespace gearmc::uncertainty
