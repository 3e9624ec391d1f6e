// Shared by the scenario parsing tests: the smallest valid gear section and the InputError a bad
// scenario text throws, with a check of the place it names (file:line:column).
#pragma once

#include <gtest/gtest.h>

#include <string>

#include "core/input_error.h"
#include "engine/scenario/scenario.h"

namespace gearmc::testing_support {

// The smallest valid gear section (P1's gear without the profile shift).
inline const std::string kGear =
    "gear:\n"
    "  teeth: 24\n"
    "  module_mm: 5.6\n"
    "  face_width_mm: 78.89\n";

// The InputError that parsing `text` throws (a test failure when it throws none).
inline InputError parse_error(const std::string& text, const std::string& source = "t.yaml") {
  try {
    parse_scenario(text, source);
  } catch (const InputError& e) {
    return e;
  }
  ADD_FAILURE() << "no InputError for:\n" << text;
  return InputError({}, "no error");
}

inline void expect_at(const InputError& e, int line, int column,
                      const std::string& file = "t.yaml") {
  EXPECT_EQ(e.where().file, file) << e.what();
  EXPECT_EQ(e.where().line, line) << e.what();
  EXPECT_EQ(e.where().column, column) << e.what();
}

}  // namespace gearmc::testing_support
