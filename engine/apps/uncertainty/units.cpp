// Units of uncertainty models and their check against the expressions (see units.h).
#include "engine/apps/uncertainty/units.h"

#include <cmath>
#include <cstdlib>
#include <map>
#include <stdexcept>
#include <vector>

#include "core/number_text.h"
#include "engine/apps/uncertainty/model.h"
#include "engine/apps/uncertainty/model_function.h"

namespace gearmc::uncertainty {
namespace {

// Symbols without prefix: scale to SI and base exponents (m, kg, s, A, K, mol, cd).
const std::map<std::string, Unit>& symbols() {
  static const std::map<std::string, Unit> table = {
      {"m", {1, {1, 0, 0, 0, 0, 0, 0}}},
      {"g", {1e-3, {0, 1, 0, 0, 0, 0, 0}}},
      {"s", {1, {0, 0, 1, 0, 0, 0, 0}}},
      {"A", {1, {0, 0, 0, 1, 0, 0, 0}}},
      {"K", {1, {0, 0, 0, 0, 1, 0, 0}}},
      {"mol", {1, {0, 0, 0, 0, 0, 1, 0}}},
      {"cd", {1, {0, 0, 0, 0, 0, 0, 1}}},
      {"N", {1, {1, 1, -2, 0, 0, 0, 0}}},
      {"Pa", {1, {-1, 1, -2, 0, 0, 0, 0}}},
      {"J", {1, {2, 1, -2, 0, 0, 0, 0}}},
      {"W", {1, {2, 1, -3, 0, 0, 0, 0}}},
      {"Hz", {1, {0, 0, -1, 0, 0, 0, 0}}},
      {"C", {1, {0, 0, 1, 1, 0, 0, 0}}},
      {"V", {1, {2, 1, -3, -1, 0, 0, 0}}},
      {"ohm", {1, {2, 1, -3, -2, 0, 0, 0}}},
      {"L", {1e-3, {3, 0, 0, 0, 0, 0, 0}}},
      {"min", {60, {0, 0, 1, 0, 0, 0, 0}}},
      {"h", {3600, {0, 0, 1, 0, 0, 0, 0}}},
      // Pure numbers of scale 1 (units.h: the expression applies their scale itself).
      {"1", {1, {}}},
      {"rad", {1, {}}},
      {"deg", {1, {}}},
      {"%", {1, {}}},
      {"ppm", {1, {}}},
      {"degC", {1, {0, 0, 0, 0, 1, 0, 0}}},
  };
  return table;
}

const std::vector<std::pair<std::string, double>>& prefixes() {
  static const std::vector<std::pair<std::string, double>> table = {
      {"T", 1e12},      {"G", 1e9},       {"M", 1e6},  {"k", 1e3},   {"h", 1e2},
      {"da", 1e1},      {"d", 1e-1},      {"c", 1e-2}, {"m", 1e-3},  {"u", 1e-6},
      {"\u00b5", 1e-6}, {"\u03bc", 1e-6}, {"n", 1e-9}, {"p", 1e-12}, {"f", 1e-15}};
  return table;
}

// One symbol with an optional prefix ("mm", "kg", "um", "min").
Unit symbol_unit(const std::string& s) {
  const auto& table = symbols();
  if (const auto it = table.find(s); it != table.end()) return it->second;
  for (const auto& [prefix, factor] : prefixes()) {
    if (s.size() <= prefix.size() || s.compare(0, prefix.size(), prefix) != 0) continue;
    const auto it = table.find(s.substr(prefix.size()));
    if (it == table.end() || it->second.exponent == std::array<double, 7>{}) continue;
    Unit u = it->second;
    u.scale *= factor;
    return u;
  }
  throw std::invalid_argument("'" + s +
                              "' is no unit symbol (m, g, s, A, K, mol, cd, N, Pa, J, W, Hz, C, V, "
                              "ohm, L, min, h with SI prefixes T … f, u or µ for micro; rad, deg, "
                              "%, ppm, degC; 1 for a pure number)");
}

}  // namespace

Unit parse_unit(const std::string& text) {
  Unit unit;
  int sign = 1;  // after '/': the denominator
  std::size_t i = 0;
  bool any = false;
  const auto space = [&](char c) { return c == ' ' || c == '*' || c == '\t'; };
  while (i < text.size()) {
    if (space(text[i])) {
      ++i;
      continue;
    }
    if (text.compare(i, 2, "\u00b7") == 0) {  // a middle dot
      i += 2;
      continue;
    }
    if (text[i] == '/') {
      if (sign < 0) {
        throw std::invalid_argument(
            "one '/' at most: what follows it is the denominator "
            "(J/kg K), or write powers (kg m^-1 s^-2)");
      }
      sign = -1;
      ++i;
      continue;
    }
    std::size_t j = i;
    while (j < text.size() && !space(text[j]) && text[j] != '/' && text[j] != '^' &&
           text.compare(j, 2, "\u00b7") != 0) {
      ++j;
    }
    const Unit u = symbol_unit(text.substr(i, j - i));
    double power = 1.0;
    if (j < text.size() && text[j] == '^') {
      const char* start = text.c_str() + j + 1;
      char* end = nullptr;
      power = std::strtod(start, &end);
      if (end == start || !std::isfinite(power) || power == 0.0) {
        throw std::invalid_argument("a non-zero number after '^' (m^3, s^-2, Hz^0.5)");
      }
      j = static_cast<std::size_t>(end - text.c_str());
    }
    power *= sign;
    unit.scale *= std::pow(u.scale, power);
    for (std::size_t d = 0; d < 7; ++d) unit.exponent[d] += power * u.exponent[d];
    any = true;
    i = j;
  }
  if (!any) throw std::invalid_argument("a unit (1 for a pure number)");
  return unit;
}

std::string dimension_text(const Unit& unit) {
  static const std::array<const char*, 7> base = {"m", "kg", "s", "A", "K", "mol", "cd"};
  std::string out;
  for (std::size_t d = 0; d < 7; ++d) {
    const double e = unit.exponent[d];
    if (e == 0.0) continue;
    out += (out.empty() ? "" : " ") + std::string(base[d]);
    if (e != 1.0) out += "^" + shortest_text(e);
  }
  return out.empty() ? "1" : out;
}

void check_model_units(const UncertaintyModel& model) {
  const auto unit_of = [&](const std::string& name) -> const Unit& {
    return model.units.at(name).unit;
  };
  // Two points of the inputs: the estimates, and the estimates moved by the standard
  // uncertainties (by a tenth of the estimate where that is zero).
  std::vector<std::vector<double>> points(2);
  for (const ModelInput& in : model.inputs) {
    const double x = in.law.mean(), u = in.law.sd();
    points[0].push_back(x);
    points[1].push_back(x + (std::isfinite(u) && u > 0 ? u : 0.1 * std::abs(x) + 0.1));
  }
  // Factors of the dimension test, per base dimension, away from 1 and from each other's powers.
  constexpr double kLambda = 1.7;
  const std::size_t n_out = model.outputs.size();
  // The outputs in the model's units at a point, with inputs and constants scaled by `factor`
  // (per quantity: SI scale × λ^exponent of the dimension tested, or 1).
  const auto outputs_at = [&](const std::vector<double>& x, bool si, int dimension) {
    const auto factor = [&](const Unit& u) {
      double f = si ? u.scale : 1.0;
      if (dimension >= 0) f *= std::pow(kLambda, u.exponent[static_cast<std::size_t>(dimension)]);
      return f;
    };
    UncertaintyModel scaled = model;
    for (auto& [name, value] : scaled.constants) value *= factor(unit_of(name));
    std::vector<double> xs(x.size());
    for (std::size_t i = 0; i < x.size(); ++i) xs[i] = x[i] * factor(unit_of(model.inputs[i].name));
    ModelFunction f(scaled);
    std::vector<double> y(n_out);
    f.evaluate(xs.data(), y.data());
    for (std::size_t k = 0; k < n_out; ++k) y[k] /= factor(unit_of(model.outputs[k].name));
    return y;
  };
  const auto agree = [](double a, double b) {
    return std::abs(a - b) <= 1e-9 * std::max(std::abs(a), std::abs(b)) + 1e-300;
  };
  for (const std::vector<double>& x : points) {
    const std::vector<double> y = outputs_at(x, false, -1);
    const std::vector<double> y_si = outputs_at(x, true, -1);
    // Each base dimension first (a dimension slip named as such), then the SI scales.
    for (const int d : {0, 1, 2, 3, 4, 5, 6, -1}) {
      const std::vector<double> y_d = d < 0 ? y_si : outputs_at(x, false, d);
      for (std::size_t k = 0; k < n_out; ++k) {
        if (!std::isfinite(y[k]) || agree(y_d[k], y[k])) continue;
        const ModelOutput& o = model.outputs[k];
        const ModelUnit& mu = model.units.at(o.name);
        std::string why;
        if (d < 0) {
          why = "an expression whose units agree with `units:` — in SI units it gives " +
                short_text(y_d[k] * mu.unit.scale) + " " + dimension_text(mu.unit) +
                ", in the given units " + short_text(y[k]) + " " + mu.text + " = " +
                short_text(y[k] * mu.unit.scale) + " " + dimension_text(mu.unit) +
                " (prefixes mixed, e.g. mm and m in one sum?)";
        } else {
          const double ratio = y_d[k] / y[k];
          // y_d is divided by the output unit's own λ^expected: the expression's exponent is
          // the ratio's plus that.
          const double expected = mu.unit.exponent[static_cast<std::size_t>(d)];
          const double observed = std::log(std::abs(ratio)) / std::log(kLambda) + expected;
          why = std::string("an expression whose units agree with `units:` — scaling every ") +
                kBaseDimensions[static_cast<std::size_t>(d)] + " by " + shortest_text(kLambda) +
                " scales it " +
                (ratio > 0 && std::isfinite(observed)
                     ? "by " + shortest_text(kLambda) + "^" + short_text(observed, 3)
                     : std::string("by ") + short_text(ratio * std::pow(kLambda, expected))) +
                ", its unit " + mu.text + " says " + shortest_text(kLambda) + "^" +
                short_text(expected, 3) +
                " (a sum of unlike quantities, a constant without its unit, or a function of a "
                "quantity that has a dimension?)";
        }
        throw InputError(o.where, "outputs." + o.name, o.expression.empty() ? o.name : o.expression,
                         why);
      }
    }
  }
}

}  // namespace gearmc::uncertainty
