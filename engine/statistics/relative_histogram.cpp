// Log-bucketed histogram with exact integer counts and a relative resolution of 2^-12 (see
// relative_histogram.h): buckets from the bits of the double, blocks of 4096 counters per
// power of two allocated when first used.
#include "engine/statistics/relative_histogram.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>
#include <memory>
#include <stdexcept>

#include "core/constants.h"

namespace gearmc {
namespace {

constexpr int kShift = 52 - RelativeHistogram::kMantissaBits;  // bits below the bucket key
constexpr std::size_t kBucketsPerBlock = std::size_t{1} << RelativeHistogram::kMantissaBits;
constexpr std::size_t kBlocks = 2047;  // biased exponents of finite doubles, 0 .. 2046

// The lower edge of bucket `key` (a magnitude); key + 1 gives the upper edge (+inf past the
// largest finite bucket).
double edge_of(std::uint64_t key) { return std::bit_cast<double>(key << kShift); }

}  // namespace

struct RelativeHistogram::Side {
  // blocks[e]: the kBucketsPerBlock counts of biased exponent e followed by their total, or null
  // until a value with that exponent comes (adding a value is an index and two increments).
  std::vector<std::unique_ptr<std::uint64_t[]>> blocks =
      std::vector<std::unique_ptr<std::uint64_t[]>>(kBlocks);

  Side() = default;
  Side(const Side& other) {
    for (std::size_t e = 0; e < kBlocks; ++e) {
      if (!other.blocks[e]) continue;
      blocks[e] = std::make_unique<std::uint64_t[]>(kBucketsPerBlock + 1);
      std::copy_n(other.blocks[e].get(), kBucketsPerBlock + 1, blocks[e].get());
    }
  }
  Side& operator=(const Side&) = delete;

  void add(std::uint64_t key, std::uint64_t count) {
    std::unique_ptr<std::uint64_t[]>& block =
        blocks[static_cast<std::size_t>(key >> kMantissaBits)];
    if (!block) block = std::make_unique<std::uint64_t[]>(kBucketsPerBlock + 1);  // zeroed
    block[key & (kBucketsPerBlock - 1)] += count;
    block[kBucketsPerBlock] += count;
  }
  void merge(const Side& other) {
    for (std::size_t e = 0; e < kBlocks; ++e) {
      if (other.block_total(e) == 0) continue;
      const std::uint64_t* src = other.blocks[e].get();
      for (std::size_t i = 0; i < kBucketsPerBlock; ++i) {
        if (src[i] != 0) add((static_cast<std::uint64_t>(e) << kMantissaBits) | i, src[i]);
      }
    }
  }
  std::uint64_t block_total(std::size_t e) const {
    return blocks[e] ? blocks[e][kBucketsPerBlock] : 0;
  }
  std::uint64_t count(std::size_t e, std::size_t i) const { return blocks[e] ? blocks[e][i] : 0; }
};

RelativeHistogram::RelativeHistogram()
    : positive_(std::make_unique<Side>()), negative_(std::make_unique<Side>()) {}
RelativeHistogram::RelativeHistogram(const RelativeHistogram& o)
    : positive_(std::make_unique<Side>(*o.positive_)),
      negative_(std::make_unique<Side>(*o.negative_)),
      zero_(o.zero_),
      plus_inf_(o.plus_inf_),
      minus_inf_(o.minus_inf_),
      total_(o.total_),
      invalid_(o.invalid_),
      min_(o.min_),
      max_(o.max_) {}
RelativeHistogram& RelativeHistogram::operator=(const RelativeHistogram& o) {
  if (this != &o) *this = RelativeHistogram(o);
  return *this;
}
RelativeHistogram::RelativeHistogram(RelativeHistogram&&) noexcept = default;
RelativeHistogram& RelativeHistogram::operator=(RelativeHistogram&&) noexcept = default;
RelativeHistogram::~RelativeHistogram() = default;

void RelativeHistogram::add(double x) {
  // The common case first: x finite and not zero, i.e. its magnitude's bits lie strictly
  // between those of 0 and of +inf (NaN's are above); its bucket key is magnitude >> kShift.
  const std::uint64_t bits = std::bit_cast<std::uint64_t>(x);
  const std::uint64_t magnitude = bits & ~(std::uint64_t{1} << 63);
  constexpr std::uint64_t kInfBits = std::bit_cast<std::uint64_t>(kInf);
  if (magnitude - 1 < kInfBits - 1) {
    count_value(x);
    (bits == magnitude ? positive_ : negative_)->add(magnitude >> kShift, 1);
    return;
  }
  if (std::isnan(x)) {
    ++invalid_;
    return;
  }
  count_value(x);
  if (x == 0.0) {
    ++zero_;
  } else if (x == kInf) {
    ++plus_inf_;
  } else {
    ++minus_inf_;
  }
}

void RelativeHistogram::merge(const RelativeHistogram& o) {
  if (o.total_ > 0) {
    min_ = total_ == 0 ? o.min_ : std::min(min_, o.min_);
    max_ = total_ == 0 ? o.max_ : std::max(max_, o.max_);
  }
  positive_->merge(*o.positive_);
  negative_->merge(*o.negative_);
  zero_ += o.zero_;
  plus_inf_ += o.plus_inf_;
  minus_inf_ += o.minus_inf_;
  total_ += o.total_;
  invalid_ += o.invalid_;
}

double RelativeHistogram::min() const { return total_ == 0 ? kNaN : min_; }
double RelativeHistogram::max() const { return total_ == 0 ? kNaN : max_; }

void RelativeHistogram::for_each_bucket(
    const std::function<void(double, double, std::uint64_t)>& f) const {
  if (minus_inf_ > 0) f(-kInf, -kInf, minus_inf_);
  // Negative values, most negative first: magnitudes in decreasing order; bucket [a, b) of
  // magnitudes holds the values (-b, -a].
  for (std::size_t e = kBlocks; e-- > 0;) {
    if (negative_->block_total(e) == 0) continue;
    for (std::size_t i = kBucketsPerBlock; i-- > 0;) {
      const std::uint64_t c = negative_->count(e, i);
      if (c == 0) continue;
      const std::uint64_t key = (static_cast<std::uint64_t>(e) << kMantissaBits) | i;
      f(-edge_of(key + 1), -edge_of(key), c);
    }
  }
  if (zero_ > 0) f(0.0, 0.0, zero_);
  for (std::size_t e = 0; e < kBlocks; ++e) {
    if (positive_->block_total(e) == 0) continue;
    for (std::size_t i = 0; i < kBucketsPerBlock; ++i) {
      const std::uint64_t c = positive_->count(e, i);
      if (c == 0) continue;
      const std::uint64_t key = (static_cast<std::uint64_t>(e) << kMantissaBits) | i;
      f(edge_of(key), edge_of(key + 1), c);
    }
  }
  if (plus_inf_ > 0) f(kInf, kInf, plus_inf_);
}

double RelativeHistogram::quantile(double p) const {
  if (!(p >= 0.0 && p <= 1.0)) {
    throw std::invalid_argument("RelativeHistogram::quantile: need 0 <= p <= 1");
  }
  if (total_ == 0) return kNaN;
  if (p == 0.0) return min_;
  if (p == 1.0) return max_;
  const std::uint64_t k = quantile_rank(p, total_);
  // Walk the buckets in value order, skipping whole blocks by their totals.
  std::uint64_t cumulative = minus_inf_;
  if (cumulative >= k) return -kInf;
  for (std::size_t e = kBlocks; e-- > 0;) {
    const std::uint64_t bt = negative_->block_total(e);
    if (cumulative + bt < k) {
      cumulative += bt;
      continue;
    }
    for (std::size_t i = kBucketsPerBlock; i-- > 0;) {
      cumulative += negative_->count(e, i);
      if (cumulative >= k) {
        const std::uint64_t key = (static_cast<std::uint64_t>(e) << kMantissaBits) | i;
        return std::clamp(-edge_of(key), min_, max_);
      }
    }
  }
  cumulative += zero_;
  if (cumulative >= k) return 0.0;
  for (std::size_t e = 0; e < kBlocks; ++e) {
    const std::uint64_t bt = positive_->block_total(e);
    if (cumulative + bt < k) {
      cumulative += bt;
      continue;
    }
    for (std::size_t i = 0; i < kBucketsPerBlock; ++i) {
      cumulative += positive_->count(e, i);
      if (cumulative >= k) {
        const std::uint64_t key = (static_cast<std::uint64_t>(e) << kMantissaBits) | i;
        return std::clamp(edge_of(key + 1), min_, max_);
      }
    }
  }
  return kInf;  // x_(k) is +inf
}

std::uint64_t RelativeHistogram::min_count_for_quantile(double p) {
  if (!(p >= 0.0 && p < 1.0)) {
    throw std::invalid_argument("min_count_for_quantile: need 0 <= p < 1");
  }
  // The smallest n with n (1 - p) >= 1. 1 - p is computed as written; the ceiling is corrected
  // so that (n - 1)(1 - p) < 1 <= n (1 - p) holds in double arithmetic.
  const double q = 1.0 - p;
  double n = std::ceil(1.0 / q);
  while (n > 1.0 && (n - 1.0) * q >= 1.0) n -= 1.0;
  while (n * q < 1.0) n += 1.0;
  return static_cast<std::uint64_t>(n);
}

RelativeHistogram::CountBounds RelativeHistogram::count_at_least(double t) const {
  CountBounds bounds{0, 0};
  for_each_bucket([&](double lo, double hi, std::uint64_t c) {
    if (lo >= t) {
      bounds.at_least += c;
      bounds.at_most += c;
    } else if (hi > t || (hi == t && lo < hi && hi < 0.0)) {
      // The bucket straddles t (for negative buckets (lo, hi] the upper edge itself is a value).
      bounds.at_most += c;
    }
  });
  return bounds;
}

Histogram RelativeHistogram::to_histogram(double lo, double width, std::size_t bins) const {
  Histogram h(lo, width, bins);
  for_each_bucket([&](double a, double b, std::uint64_t c) {
    const double centre = std::isinf(a) ? a : a == b ? a : 0.5 * (a + b);
    h.add(centre, c);
  });
  h.set_extremes(min_, max_);
  return h;
}

void RelativeHistogram::encode(std::string& out) const {
  ByteWriter w(out);
  for (std::uint64_t v : {zero_, plus_inf_, minus_inf_, total_, invalid_}) w.put(v);
  w.put(min_);
  w.put(max_);
  for (const Side* side : {positive_.get(), negative_.get()}) {
    std::uint64_t occupied = 0;
    for (std::size_t e = 0; e < kBlocks; ++e) {
      if (side->block_total(e) == 0) continue;
      for (std::size_t i = 0; i < kBucketsPerBlock; ++i) occupied += side->count(e, i) != 0;
    }
    w.put(occupied);
    for (std::size_t e = 0; e < kBlocks; ++e) {
      if (side->block_total(e) == 0) continue;
      for (std::size_t i = 0; i < kBucketsPerBlock; ++i) {
        const std::uint64_t c = side->count(e, i);
        if (c == 0) continue;
        w.put((static_cast<std::uint64_t>(e) << kMantissaBits) | i);
        w.put(c);
      }
    }
  }
}

RelativeHistogram RelativeHistogram::decode(ByteReader& in) {
  RelativeHistogram h;
  h.zero_ = in.get<std::uint64_t>();
  h.plus_inf_ = in.get<std::uint64_t>();
  h.minus_inf_ = in.get<std::uint64_t>();
  h.total_ = in.get<std::uint64_t>();
  h.invalid_ = in.get<std::uint64_t>();
  h.min_ = in.get<double>();
  h.max_ = in.get<double>();
  for (Side* side : {h.positive_.get(), h.negative_.get()}) {
    const auto occupied = in.get<std::uint64_t>();
    for (std::uint64_t b = 0; b < occupied; ++b) {
      const auto key = in.get<std::uint64_t>();
      const auto count = in.get<std::uint64_t>();
      if ((key >> kMantissaBits) >= kBlocks) {
        throw std::runtime_error("RelativeHistogram::decode: bucket key out of range");
      }
      side->add(key, count);
    }
  }
  return h;
}

bool RelativeHistogram::operator==(const RelativeHistogram& o) const {
  if (total_ != o.total_ || invalid_ != o.invalid_ || zero_ != o.zero_ ||
      plus_inf_ != o.plus_inf_ || minus_inf_ != o.minus_inf_) {
    return false;
  }
  if (total_ > 0 && (min_ != o.min_ || max_ != o.max_)) return false;
  for (const auto& [a, b] : {std::pair{positive_.get(), o.positive_.get()},
                             std::pair{negative_.get(), o.negative_.get()}}) {
    for (std::size_t e = 0; e < kBlocks; ++e) {
      if (a->block_total(e) != b->block_total(e)) return false;
      if (a->block_total(e) == 0) continue;
      for (std::size_t i = 0; i < kBucketsPerBlock; ++i) {
        if (a->count(e, i) != b->count(e, i)) return false;
      }
    }
  }
  return true;
}

}  // namespace gearmc
