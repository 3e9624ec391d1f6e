// Exact comparison of two Monte-Carlo runs' statistics, shared by the tests that check that
// results do not depend on the thread count (docs/architecture.md principle 2).
#pragma once

#include <gtest/gtest.h>

#include "engine/run/monte_carlo.h"

namespace gearmc::testing_support {

// Every moment (bitwise) and the p99.73 quantile of the per-point, per-flank-max and
// per-flank-mean statistics, left and right, are equal.
inline void expect_identical_statistics(const RunResults& a, const RunResults& b) {
  for (int s = 0; s < 2; ++s) {
    EXPECT_TRUE(a.point[s].moments == b.point[s].moments) << "side " << s;
    EXPECT_TRUE(a.flank_max[s].moments == b.flank_max[s].moments) << "side " << s;
    EXPECT_TRUE(a.flank_mean[s].moments == b.flank_mean[s].moments) << "side " << s;
    EXPECT_EQ(a.point[s].histogram.quantile(0.9973), b.point[s].histogram.quantile(0.9973));
    EXPECT_TRUE(a.flank_max[s].histogram == b.flank_max[s].histogram) << "side " << s;
  }
}

}  // namespace gearmc::testing_support
