// GEARMC_CHECK stays on with NDEBUG: this file is compiled with NDEBUG defined whatever the build
// type (it is defined before any header), and the gears library's own checks are compiled in the
// build's configuration (Release: -DNDEBUG). Each death test proves the check aborts and prints
// file:line and its message.
#undef NDEBUG
#define NDEBUG 1

#include "core/check.h"

#include <gtest/gtest.h>

#include <vector>

#include "gears/deviations.h"

namespace gearmc {
namespace {

int checked_half(int even) {
  GEARMC_CHECK(even % 2 == 0, "an even number");
  return even / 2;
}

TEST(CheckDeathTest, FiresWithNdebugAndNamesTheFileLineAndMessage) {
  GTEST_FLAG_SET(death_test_style, "threadsafe");
  EXPECT_EQ(checked_half(4), 2);  // a condition that holds costs nothing and returns
  // Exit code 4 is every command's internal error (docs/running.md); not a signal, so a crash
  // (SIGSEGV, SIGABRT) stays told apart from a check that fired.
  EXPECT_EXIT(
      checked_half(3), testing::ExitedWithCode(kInternalErrorExit),
      R"(check_test\.cpp:[0-9]+: gearmc internal error: an even number \(failed: even % 2 == 0\))");
  EXPECT_EQ(kInternalErrorExit, 4);
}

TEST(CheckDeathTest, FiresInsideTheLibraryAsBuilt) {
  GTEST_FLAG_SET(death_test_style, "threadsafe");
  // A cubic B-spline with three coefficients has no span: gears/cubic_bspline.cpp checks it. In the
  // Release build that file is compiled with -DNDEBUG, where an assert would be gone.
  EXPECT_EXIT(
      CubicBSpline(0.0, 1.0, std::vector<double>{1.0, 2.0, 3.0}), testing::ExitedWithCode(4),
      "cubic_bspline\\.cpp:[0-9]+: gearmc internal error: a cubic B-spline needs at least 4");
}

}  // namespace
}  // namespace gearmc
