// Streaming moments of a stream of values (docs/architecture.md, principle 3): count, mean, sample
// standard deviation, exact min and max, in O(1) memory. Values are added one at a time with
// Welford's update and partial results (e.g. one per gear) are combined with the pairwise update of
// Chan, Golub & LeVeque (1979). Floating-point addition is not associative, so the result depends
// on how the stream was split and in which order the parts were merged: the same split merged in
// the same order is bit-identical (the Monte-Carlo runner splits per gear and merges in gear
// order, so its result does not depend on the thread count); a different split agrees to a
// relative ~1e-13 (rounding only). Units are those of the values (µm for δRcomp).
// Public API (docs/api.md): a stable part of the C++ interface, installed with its includes.
#pragma once

#include <cstdint>
#include <string>

#include "core/bytes.h"

namespace gearmc {

class RunningStats {
 public:
  // Adds one value (µm). Precondition: x is finite (a NaN would poison mean and std).
  // Welford (1962): delta = x - mean; mean += delta / n; M2 += delta (x - mean).
  void add(double x);

  // Folds `other` into this, as if its values had been added after this one's (up to rounding).
  // Chan, Golub & LeVeque (1979), "Updating formulae and a pairwise algorithm for computing
  // sample variances", eq. 2.1: with d = mean_b - mean_a, n = n_a + n_b,
  //   mean = mean_a + d n_b / n,   M2 = M2_a + M2_b + d^2 n_a n_b / n.
  void merge(const RunningStats& other);

  std::uint64_t count() const { return n_; }
  // Arithmetic mean (µm); NaN when empty.
  double mean() const;
  // Sample variance M2 / (n - 1) (µm^2); NaN when n < 2.
  double variance() const;
  // Sample standard deviation sqrt(variance) (µm); NaN when n < 2.
  double stddev() const;
  // Exact smallest / largest value added (µm); NaN when empty.
  double min() const;
  double max() const;
  // Sum of squared deviations from the mean (µm^2), the merge state.
  double sum_squared_deviations() const { return m2_; }

  // The whole state as bytes (core/bytes.h), and back bit for bit: partial results of other
  // processes.
  void encode(std::string& out) const;
  static RunningStats decode(ByteReader& in);

  // Bitwise equality of the whole state (for determinism checks).
  bool operator==(const RunningStats&) const = default;

 private:
  std::uint64_t n_ = 0;
  double mean_ = 0.0;
  double m2_ = 0.0;
  double min_ = 0.0;
  double max_ = 0.0;
};

}  // namespace gearmc
