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
  EXPECT_DEATH(
      checked_half(3),
      R"(check_test\.cpp:[0-9]+: gearmc internal error: an even number \(failed: even % 2 == 0\))");
}

TEST(CheckDeathTest, FiresInsideTheLibraryAsBuilt) {
  GTEST_FLAG_SET(death_test_style, "threadsafe");
  // A cubic B-spline with three coefficients has no span: gears/cubic_bspline.cpp checks it. In the
  // Release build that file is compiled with -DNDEBUG, where an assert would be gone.
  EXPECT_DEATH(
      CubicBSpline(0.0, 1.0, std::vector<double>{1.0, 2.0, 3.0}),
      "cubic_bspline\\.cpp:[0-9]+: gearmc internal error: a cubic B-spline needs at least 4");
}

}  // namespace
}  // namespace gearmc
