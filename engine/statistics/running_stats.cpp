// Welford's single-value update and Chan-Golub-LeVeque's pairwise merge (see running_stats.h).
#include "engine/statistics/running_stats.h"

#include <cmath>
#include <limits>

#include "core/constants.h"

namespace gearmc {
namespace {}  // namespace

void RunningStats::add(double x) {
  if (n_ == 0) {
    min_ = x;
    max_ = x;
  } else {
    if (x < min_) min_ = x;
    if (x > max_) max_ = x;
  }
  ++n_;
  // Welford (1962); also Knuth, TAOCP vol. 2, 4.2.2.
  const double delta = x - mean_;
  mean_ += delta / static_cast<double>(n_);
  m2_ += delta * (x - mean_);
}

void RunningStats::merge(const RunningStats& other) {
  if (other.n_ == 0) return;
  if (n_ == 0) {
    *this = other;
    return;
  }
  // Chan, Golub & LeVeque (1979), eq. 2.1.
  const double na = static_cast<double>(n_);
  const double nb = static_cast<double>(other.n_);
  const double n = na + nb;
  const double d = other.mean_ - mean_;
  mean_ += d * (nb / n);
  m2_ += other.m2_ + d * d * (na * nb / n);
  n_ += other.n_;
  if (other.min_ < min_) min_ = other.min_;
  if (other.max_ > max_) max_ = other.max_;
}

void RunningStats::encode(std::string& out) const {
  ByteWriter w(out);
  w.put(n_);
  w.put(mean_);
  w.put(m2_);
  w.put(min_);
  w.put(max_);
}

RunningStats RunningStats::decode(ByteReader& in) {
  RunningStats s;
  s.n_ = in.get<std::uint64_t>();
  s.mean_ = in.get<double>();
  s.m2_ = in.get<double>();
  s.min_ = in.get<double>();
  s.max_ = in.get<double>();
  return s;
}

double RunningStats::mean() const { return n_ == 0 ? kNaN : mean_; }

double RunningStats::variance() const { return n_ < 2 ? kNaN : m2_ / static_cast<double>(n_ - 1); }

double RunningStats::stddev() const { return std::sqrt(variance()); }

double RunningStats::min() const { return n_ == 0 ? kNaN : min_; }

double RunningStats::max() const { return n_ == 0 ? kNaN : max_; }

}  // namespace gearmc
