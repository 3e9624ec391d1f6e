// Ascending sort of doubles by their bits: a least-significant-digit radix sort (four passes of
// 16 bits) of the IEEE 754 keys mapped to unsigned integers in the same order (negative values:
// every bit flipped; others: the sign bit set), for the large samples the diagnosis sorts once per
// null replicate (10⁵–10⁶ residuals; about 3× faster than std::sort there). The order of finite
// values and infinities is std::sort's (-0.0 comes before +0.0, which compare equal); NaN sorts by
// its bits (std::sort is undefined with NaN). Small inputs go to std::sort.
#pragma once

#include <algorithm>
#include <array>
#include <bit>
#include <cstdint>
#include <vector>

namespace gearmc {

inline void sort_doubles(std::vector<double>& values) {
  constexpr std::size_t kRadixFrom = 2048;  // below: std::sort is as fast
  const std::size_t n = values.size();
  if (n < kRadixFrom) {
    std::sort(values.begin(), values.end());
    return;
  }
  constexpr std::uint64_t kSign = std::uint64_t{1} << 63;
  std::vector<std::uint64_t> keys(n), buffer(n);
  for (std::size_t i = 0; i < n; ++i) {
    const std::uint64_t u = std::bit_cast<std::uint64_t>(values[i]);
    keys[i] = (u & kSign) ? ~u : (u | kSign);
  }
  std::array<std::size_t, 65536> count;
  for (int pass = 0; pass < 4; ++pass) {
    const int shift = 16 * pass;
    count.fill(0);
    for (const std::uint64_t k : keys) ++count[(k >> shift) & 0xFFFF];
    std::size_t at = 0;
    for (std::size_t& c : count) {
      const std::size_t here = c;
      c = at;
      at += here;
    }
    for (const std::uint64_t k : keys) buffer[count[(k >> shift) & 0xFFFF]++] = k;
    keys.swap(buffer);
  }
  for (std::size_t i = 0; i < n; ++i) {
    const std::uint64_t k = keys[i];
    values[i] = std::bit_cast<double>((k & kSign) ? (k & ~kSign) : ~k);
  }
}

}  // namespace gearmc
