// Confidence bands of a sweep's statistic at each grid point, and the point's verdict against a
// limit (docs/sweep.md "Bands and limits"). A point's statistic is estimated from a finite number
// of simulated gears; its band says where the statistic of infinitely many gears lies, at the
// band's confidence. The unit of independence is the GEAR (the flanks of one gear share its
// eccentricity, runout and per-gear effect draws, so its values are correlated), so the band is
// a cluster bootstrap: B resamples of the point's gears drawn with replacement (whole gears with
// all their values), the statistic recomputed on each exactly as on the run (the same histogram
// quantile, moments, parameter presentation), and the band the (1 − c)/2 and (1 + c)/2 quantiles
// of the B values (the percentile bootstrap; Efron & Tibshirani, "An Introduction to the
// Bootstrap", 1993, §13.3; resampling clusters: Davison & Hinkley, "Bootstrap Methods and their
// Application", 1997, §3.8). The resamples are drawn from counter-based streams of the point's
// seed (TrialPurpose::kSweepBootstrap, resample b), so the band does not depend on ranks or
// threads. The count n (exact), min and max (no sample bounds the next gear's extreme) have no
// band. Values in the statistic's unit (µm, or none for ratios and rates).
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "engine/apps/sweep/sweep.h"

namespace gearmc {

// Resamples per band (B): the percentile band's ends move by about 1.5 % of the band's width
// between two sets of 1000 resamples (a 2.5 % quantile of B values has a standard error of
// √(0.025·0.975/B) in probability, 0.005 here).
inline constexpr int kSweepResamples = 1000;

// One point's per-gear values of a δRcomp quantity (sweep.h), gear after gear. At most
// kMaxValues values are kept (128 MiB): past them the point has no band (`overflow`; a flank
// statistic has 48 values per gear on P1, the point quantity 2400).
struct GearValues {
  static constexpr std::uint64_t kMaxValues = std::uint64_t{1} << 24;
  std::vector<double> values[2];      // [0] L flanks, [1] R flanks: finite values only
  std::vector<std::uint64_t> end[2];  // per gear: the end of its values in values[side]
  bool overflow = false;              // more than kMaxValues values: none kept
  int gears() const { return static_cast<int>(end[0].size()); }
  void add_gear(const std::vector<double>& left, const std::vector<double>& right);
  void encode(std::string& out) const;  // core/bytes.h, bit for bit
  static GearValues decode(std::string_view in);
};

struct SweepBand {
  std::optional<double> lower, upper;  // both set, or neither (then `note` says why)
  std::string note;
};

// The percentile band of `replicates` at confidence `confidence` (0 < c < 1): the order
// statistics at (1 − c)/2 and (1 + c)/2 by linear interpolation of the sorted values (Hyndman &
// Fan type 7). Needs at least 2 values.
std::optional<std::array<double, 2>> percentile_band(std::vector<double> replicates,
                                                     double confidence);

// The gear indices of resample `b` of `gears` gears (uniform with replacement) from the streams
// of `seed`.
std::vector<int> bootstrap_gears(std::uint64_t seed, int b, int gears);

// Whether the statistic has bands: not the count n (exact), min or max (no sample bounds the
// extremes of more gears).
bool sweep_statistic_has_band(const SweepStatistic& s);

// The bands of a δRcomp statistic at one point for the left, right and both flanks.
std::array<SweepBand, 3> delta_rcomp_bands(const SweepStatistic& s, const GearValues& gears,
                                           double confidence, std::uint64_t seed,
                                           int resamples = kSweepResamples);

// The bands of a gear parameter's statistic at one point, recomputed from the run's parameter
// samples (every parameter has a fixed number of items per gear) through the run report's
// presentation, as sweep_parameter_values computes the point's value.
std::array<SweepBand, 3> parameter_bands(const SweepStatistic& s, const MonteCarloRun& mc,
                                         const RunResults& r, double confidence, std::uint64_t seed,
                                         int resamples = kSweepResamples);

// A limit on the statistic (`--at-most`, `--at-least`, in its unit); both set: a two-sided limit.
struct SweepLimit {
  std::optional<double> at_most, at_least;
  bool any() const { return at_most || at_least; }
  std::string text(const char* unit) const;  // "≤ 4 µm", "≥ 0.1", "in [−0.3, 0.3] µm"
};

// meets: the whole band within the limit; misses: the whole band beyond it; undecided: the band
// straddles it, or there is no band. Without a band a max (min) only grows (falls) with more
// gears: one seen above at_most (below at_least) misses, one seen at or above at_least (at or
// below at_most) with no limit on the other side meets; the count n is exact: meets or misses.
enum class SweepVerdict { kMeets, kMisses, kUndecided };
const char* sweep_verdict_text(SweepVerdict v);  // "meets", "misses", "undecided"
SweepVerdict sweep_verdict(const SweepLimit& limit, const SweepStatistic& s,
                           std::optional<double> value, const SweepBand& band);

}  // namespace gearmc
