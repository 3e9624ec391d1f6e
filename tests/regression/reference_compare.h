// What the regression tests share (tests/regression/): the --update switch of the test binary
// and the comparison of a command's JSON view with its stored reference.
//
// Comparison: counts and strings exactly; real numbers to a relative 1e-9 (absolute 1e-12 near
// zero unless the caller gives another floor). Reason for not comparing the reals bit for bit:
// glibc's libm selects FMA or non-FMA code for sin/cos/atan2/tan at run time from the CPU, and the
// two can differ in the last bit; the commands are otherwise bit-reproducible, a last-bit change
// moves a value by ~1e-15 relative, far below 1e-9, while any change of the model moves it by far
// more.
#pragma once

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

namespace gearmc::regression {

// --update (scripts/update-references): write the references instead of comparing.
inline bool& update_mode() {
  static bool update = false;
  return update;
}

// Recursive comparison; appends one line per difference to `out`. `absolute` is the tolerance of
// a real number near zero, in its own unit.
inline void compare(const nlohmann::ordered_json& expected, const nlohmann::ordered_json& actual,
                    const std::string& path, std::vector<std::string>& out,
                    double absolute = 1e-12) {
  if (expected.is_number_integer() && actual.is_number_integer()) {
    // A count read back from a file is unsigned, the same count just written may be signed:
    // compare their decimal text.
    const bool equal = expected.dump() == actual.dump();
    if (!equal) out.push_back(path + ": expected " + expected.dump() + ", got " + actual.dump());
    return;
  }
  if (expected.is_number_float() || actual.is_number_float()) {
    if (!expected.is_number() || !actual.is_number()) {
      out.push_back(path + ": expected " + expected.dump() + ", got " + actual.dump());
      return;
    }
    const double e = expected.get<double>(), a = actual.get<double>();
    if (std::abs(a - e) > std::max(absolute, 1e-9 * std::abs(e))) {
      out.push_back(path + ": expected " + expected.dump() + ", got " + actual.dump());
    }
    return;
  }
  if (expected.type() != actual.type()) {
    out.push_back(path + ": expected " + expected.dump() + ", got " + actual.dump());
    return;
  }
  if (expected.is_object()) {
    for (const auto& [key, value] : expected.items()) {
      if (!actual.contains(key)) {
        out.push_back(path + "/" + key + ": missing from the output");
      } else {
        compare(value, actual[key], path + "/" + key, out, absolute);
      }
    }
    for (const auto& [key, value] : actual.items()) {
      if (!expected.contains(key)) {
        out.push_back(path + "/" + key + ": new in the output (not in the reference)");
      }
    }
    return;
  }
  if (expected.is_array()) {
    if (expected.size() != actual.size()) {
      out.push_back(path + ": expected " + expected.dump() + ", got " + actual.dump());
      return;
    }
    for (size_t i = 0; i < expected.size(); ++i) {
      compare(expected[i], actual[i], path + "/" + std::to_string(i), out, absolute);
    }
    return;
  }
  if (expected != actual) {
    out.push_back(path + ": expected " + expected.dump() + ", got " + actual.dump());
  }
}

// The differences of `actual` from the stored reference as one text ("" when equal); the
// reference's "_about" key is ignored.
inline std::string differences_from(nlohmann::ordered_json reference,
                                    const nlohmann::ordered_json& actual, double absolute = 1e-12) {
  reference.erase("_about");
  std::vector<std::string> differences;
  compare(reference, actual, "", differences, absolute);
  std::string report;
  for (const auto& d : differences) report += "  " + d + "\n";
  return report;
}

}  // namespace gearmc::regression
