// sort_doubles (core/sort_doubles.h) against std::sort: the same ascending sequence, value for
// value, on samples of every sign, magnitude and kind (normals, denormals, zeros of both signs,
// infinities, repeated values), at sizes on both sides of the radix threshold.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include "core/sort_doubles.h"

namespace gearmc {
namespace {

TEST(SortDoubles, SameOrderAsStdSortForEveryKindOfValue) {
  std::mt19937_64 rng(42);  // fixed seed
  std::normal_distribution<double> normal(0.0, 1.0);
  std::uniform_int_distribution<int> kind(0, 9);
  for (const std::size_t n : {std::size_t{0}, std::size_t{1}, std::size_t{100}, std::size_t{2047},
                              std::size_t{2048}, std::size_t{100000}}) {
    std::vector<double> v(n);
    for (double& x : v) {
      switch (kind(rng)) {
        case 0:
          x = 0.0;
          break;
        case 1:
          x = -0.0;
          break;
        case 2:
          x = std::numeric_limits<double>::denorm_min() * (normal(rng) > 0 ? 7 : -3);
          break;
        case 3:
          x = normal(rng) > 0 ? std::numeric_limits<double>::infinity()
                              : -std::numeric_limits<double>::infinity();
          break;
        case 4:
          x = 1e300 * normal(rng);
          break;
        case 5:
          x = std::round(normal(rng) * 4.0) / 4.0;
          break;  // many ties
        default:
          x = normal(rng) * std::pow(10.0, static_cast<int>(normal(rng) * 5));
          break;
      }
    }
    std::vector<double> expected = v;
    std::sort(expected.begin(), expected.end());
    sort_doubles(v);
    ASSERT_EQ(v.size(), expected.size());
    for (std::size_t i = 0; i < n; ++i) {
      ASSERT_EQ(v[i], expected[i]) << "n " << n << " at " << i;  // -0.0 == +0.0
    }
    EXPECT_TRUE(std::is_sorted(v.begin(), v.end()));
  }
}

}  // namespace
}  // namespace gearmc
