// Cluster-bootstrap bands of a sweep point's statistic and the point's verdict (sweep_bands.h).
#include "engine/apps/sweep/sweep_bands.h"

#include <algorithm>
#include <cmath>

#include "core/bytes.h"
#include "core/number_text.h"
#include "core/random_stream.h"
#include "engine/apps/sweep/sweep_report.h"
#include "engine/statistics/histogram.h"
#include "engine/statistics/relative_histogram.h"
#include "engine/statistics/running_stats.h"

namespace gearmc {

void GearValues::add_gear(const std::vector<double>& left, const std::vector<double>& right) {
  if (overflow) return;
  if (values[0].size() + values[1].size() + left.size() + right.size() > kMaxValues) {
    overflow = true;
    for (int s = 0; s < 2; ++s) {
      std::vector<double>().swap(values[s]);
      std::vector<std::uint64_t>().swap(end[s]);
    }
    return;
  }
  const std::vector<double>* from[2] = {&left, &right};
  for (int s = 0; s < 2; ++s) {
    for (double v : *from[s]) {
      if (std::isfinite(v)) values[s].push_back(v);  // as ErrorStatistics::add counts them
    }
    end[s].push_back(values[s].size());
  }
}

void GearValues::encode(std::string& out) const {
  ByteWriter w(out);
  w.put<std::uint8_t>(overflow ? 1 : 0);
  for (int s = 0; s < 2; ++s) {
    w.put<std::uint64_t>(end[s].size());
    for (std::uint64_t e : end[s]) w.put(e);
    w.put<std::uint64_t>(values[s].size());
    for (double v : values[s]) w.put(v);
  }
}

GearValues GearValues::decode(std::string_view in) {
  ByteReader r(in);
  GearValues g;
  g.overflow = r.get<std::uint8_t>() != 0;
  for (int s = 0; s < 2; ++s) {
    g.end[s].resize(r.get<std::uint64_t>());
    for (std::uint64_t& e : g.end[s]) e = r.get<std::uint64_t>();
    g.values[s].resize(r.get<std::uint64_t>());
    for (double& v : g.values[s]) v = r.get<double>();
  }
  return g;
}

std::optional<std::array<double, 2>> percentile_band(std::vector<double> x, double confidence) {
  if (x.size() < 2 || !(confidence > 0.0 && confidence < 1.0)) return std::nullopt;
  std::sort(x.begin(), x.end());
  const auto at = [&](double p) {  // Hyndman & Fan type 7: h = (n − 1) p
    const double h = (static_cast<double>(x.size()) - 1.0) * p;
    const std::size_t k = static_cast<std::size_t>(std::floor(h));
    if (k + 1 >= x.size()) return x.back();
    return x[k] + (h - static_cast<double>(k)) * (x[k + 1] - x[k]);
  };
  return std::array<double, 2>{at((1.0 - confidence) / 2.0), at((1.0 + confidence) / 2.0)};
}

std::vector<int> bootstrap_gears(std::uint64_t seed, int b, int gears) {
  TrialStream stream(seed, static_cast<std::uint64_t>(b), TrialPurpose::kSweepBootstrap);
  std::vector<int> chosen(static_cast<std::size_t>(gears));
  for (int& g : chosen) {
    g = std::min(gears - 1, static_cast<int>(stream.uniform() * gears));
  }
  return chosen;
}

bool sweep_statistic_has_band(const SweepStatistic& s) {
  return s.statistic != "n" && s.statistic != "min" && s.statistic != "max";
}

namespace {

// Why a statistic has no band, or empty when it has one.
std::string no_band_reason(const SweepStatistic& s) {
  if (s.statistic == "n") return "the count is exact";
  if (s.statistic == "min" || s.statistic == "max") {
    return "no sample bounds the " + s.statistic + " of the next gears";
  }
  return {};
}

// The band of the replicate values, or a note why none: replicates without a value (a
// quantile the resample has too few values for) make the band undefined.
SweepBand band_of(const std::vector<std::optional<double>>& replicates, double confidence) {
  SweepBand band;
  std::vector<double> x;
  std::size_t missing = 0;
  for (const std::optional<double>& v : replicates) {
    if (v) {
      x.push_back(*v);
    } else {
      ++missing;
    }
  }
  if (missing > 0) {
    band.note = std::to_string(missing) + " of " + std::to_string(replicates.size()) +
                " resamples have no value (too few values)";
    return band;
  }
  const auto b = percentile_band(std::move(x), confidence);
  if (!b) {
    band.note = "too few resamples";
    return band;
  }
  band.lower = (*b)[0];
  band.upper = (*b)[1];
  return band;
}

}  // namespace

std::array<SweepBand, 3> delta_rcomp_bands(const SweepStatistic& s, const GearValues& g,
                                           double confidence, std::uint64_t seed, int resamples) {
  std::array<SweepBand, 3> bands;
  const std::string reason = no_band_reason(s);
  if (!reason.empty() || g.overflow || g.gears() < 2) {
    for (SweepBand& b : bands) {
      b.note = !reason.empty() ? reason
               : g.overflow    ? "more than " + std::to_string(GearValues::kMaxValues) +
                                  " values to resample (fewer gears, or a flank statistic)"
                            : "fewer than 2 gears";
    }
    return bands;
  }
  const int gears = g.gears();
  const bool quantile = s.statistic == "p95" || s.statistic == "p99_73";
  const double p = s.statistic == "p95" ? 0.95 : 0.9973;
  // Moments: per gear and side (a resample merges whole gears, Chan's update). Quantiles: per
  // side (and both) every value with its gear, largest first, and per gear its count: a
  // resample's order statistic x_(k) (k = quantile_rank(p, N), as RelativeHistogram::quantile
  // takes it, which rounds it up by at most 2^-12 relative) is found from the top, each value
  // counted as often as its gear was drawn.
  std::vector<RunningStats> gear_moments[2];
  std::vector<std::uint64_t> gear_count[2];
  for (int side = 0; side < 2; ++side) {
    std::uint64_t begin = 0;
    for (int gear = 0; gear < gears; ++gear) {
      const std::uint64_t end = g.end[side][static_cast<std::size_t>(gear)];
      RunningStats m;
      for (std::uint64_t i = begin; i < end && !quantile; ++i) m.add(g.values[side][i]);
      gear_moments[side].push_back(m);
      gear_count[side].push_back(end - begin);
      begin = end;
    }
  }
  // Only the top kTail (1 − p) of the values can hold a resample's x_(k) (a resample whose tail
  // reaches deeper, beyond any plausible sampling, gets no value and the band a note).
  constexpr double kTail = 4.0;
  const auto tail = [&](std::initializer_list<int> sides) {
    std::vector<std::pair<double, int>> v;
    for (int side : sides) {
      std::uint64_t begin = 0;
      for (int gear = 0; gear < gears; ++gear) {
        const std::uint64_t end = g.end[side][static_cast<std::size_t>(gear)];
        for (std::uint64_t i = begin; i < end; ++i) v.emplace_back(g.values[side][i], gear);
        begin = end;
      }
    }
    if (v.empty()) return v;
    const auto larger = [](const auto& x, const auto& y) { return x.first > y.first; };
    const std::size_t keep = std::min(
        v.size(),
        static_cast<std::size_t>(std::ceil(kTail * (1.0 - p) * static_cast<double>(v.size()))) + 1);
    std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(keep - 1), v.end(), larger);
    v.resize(keep);
    v.shrink_to_fit();
    std::sort(v.begin(), v.end(), larger);
    return v;
  };
  std::array<std::vector<std::pair<double, int>>, 3> sorted;
  if (quantile) sorted = {tail({0}), tail({1}), tail({0, 1})};
  std::array<std::vector<std::optional<double>>, 3> replicates;
  std::vector<std::uint64_t> weight(static_cast<std::size_t>(gears));
  for (int b = 0; b < resamples; ++b) {
    const std::vector<int> chosen = bootstrap_gears(seed, b, gears);
    if (!quantile) {
      ErrorStatistics side[2];
      for (int k = 0; k < 2; ++k) {
        for (int gear : chosen)
          side[k].moments.merge(gear_moments[k][static_cast<std::size_t>(gear)]);
      }
      ErrorStatistics both = side[0];
      both.merge(side[1]);
      replicates[0].push_back(sweep_statistic_value(s, side[0], nullptr));
      replicates[1].push_back(sweep_statistic_value(s, side[1], nullptr));
      replicates[2].push_back(sweep_statistic_value(s, both, nullptr));
      continue;
    }
    std::fill(weight.begin(), weight.end(), 0);
    for (int gear : chosen) ++weight[static_cast<std::size_t>(gear)];
    for (int k = 0; k < 3; ++k) {
      std::uint64_t n = 0;
      for (int gear = 0; gear < gears; ++gear) {
        const std::size_t i = static_cast<std::size_t>(gear);
        const std::uint64_t count = k < 2 ? gear_count[k][i] : gear_count[0][i] + gear_count[1][i];
        n += weight[i] * count;
      }
      if (n < RelativeHistogram::min_count_for_quantile(p)) {
        replicates[k].push_back(std::nullopt);
        continue;
      }
      // x_(k) is the (n − k + 1)-th largest value.
      const std::uint64_t from_top = n - quantile_rank(p, n) + 1;
      std::uint64_t seen = 0;
      std::optional<double> value;
      for (const auto& [v, gear] : sorted[k]) {
        seen += weight[static_cast<std::size_t>(gear)];
        if (seen >= from_top) {
          value = v;
          break;
        }
      }
      replicates[k].push_back(value);
    }
  }
  for (int k = 0; k < 3; ++k) bands[k] = band_of(replicates[k], confidence);
  return bands;
}

std::array<SweepBand, 3> parameter_bands(const SweepStatistic& s, const MonteCarloRun& mc,
                                         const RunResults& r, double confidence, std::uint64_t seed,
                                         int resamples) {
  std::array<SweepBand, 3> bands;
  const std::array<SweepValue, 3> estimate = sweep_parameter_values(s, mc, r);
  for (int k = 0; k < 3; ++k) {
    if (!estimate[k].value) bands[k].note = estimate[k].note;
  }
  if (!r.parameters || r.gears < 2) {
    for (SweepBand& b : bands) {
      if (b.note.empty()) b.note = "fewer than 2 gears";
    }
    return bands;
  }
  int parameter = -1;
  for (int p = 0; p < kGearParameterCount; ++p) {
    if (parameter_symbol(static_cast<GearParameter>(p)) == s.parameter) parameter = p;
  }
  const auto& values = r.parameters->values[static_cast<std::size_t>(parameter)];
  std::size_t per_gear[2];
  for (int k = 0; k < 2; ++k) {
    per_gear[k] = values[k].size() / static_cast<std::size_t>(r.gears);
    if (per_gear[k] * static_cast<std::size_t>(r.gears) != values[k].size()) {
      for (SweepBand& b : bands) {
        if (b.note.empty()) b.note = "the gears have unequal numbers of items";
      }
      return bands;
    }
  }
  std::array<std::vector<std::optional<double>>, 3> replicates;
  for (int b = 0; b < resamples; ++b) {
    const std::vector<int> chosen = bootstrap_gears(seed, b, r.gears);
    RunResults resample;
    resample.gears = r.gears;
    resample.parameters.emplace();
    auto& to = resample.parameters->values[static_cast<std::size_t>(parameter)];
    for (int k = 0; k < 2; ++k) {
      to[k].reserve(values[k].size());
      for (int gear : chosen) {
        const auto from = values[k].begin() + static_cast<std::ptrdiff_t>(gear * per_gear[k]);
        to[k].insert(to[k].end(), from, from + static_cast<std::ptrdiff_t>(per_gear[k]));
      }
    }
    const std::array<SweepValue, 3> v = sweep_parameter_values(s, mc, resample);
    for (int k = 0; k < 3; ++k) replicates[k].push_back(v[k].value);
  }
  for (int k = 0; k < 3; ++k) {
    if (estimate[k].value) bands[k] = band_of(replicates[k], confidence);
  }
  return bands;
}

std::string SweepLimit::text(const char* unit) const {
  const std::string u = *unit ? std::string(" ") + unit : std::string();
  if (at_most && at_least) {
    return "in [" + shortest_text(*at_least) + ", " + shortest_text(*at_most) + "]" + u;
  }
  if (at_most) return "≤ " + shortest_text(*at_most) + u;
  if (at_least) return "≥ " + shortest_text(*at_least) + u;
  return {};
}

const char* sweep_verdict_text(SweepVerdict v) {
  switch (v) {
    case SweepVerdict::kMeets:
      return "meets";
    case SweepVerdict::kMisses:
      return "misses";
    case SweepVerdict::kUndecided:
      break;
  }
  return "undecided";
}

SweepVerdict sweep_verdict(const SweepLimit& limit, const SweepStatistic& s,
                           std::optional<double> value, const SweepBand& band) {
  const double lo = limit.at_least.value_or(-INFINITY);
  const double hi = limit.at_most.value_or(INFINITY);
  if (!value) return SweepVerdict::kUndecided;
  if (s.statistic == "n") {
    return *value >= lo && *value <= hi ? SweepVerdict::kMeets : SweepVerdict::kMisses;
  }
  if (band.lower && band.upper) {
    if (*band.lower >= lo && *band.upper <= hi) return SweepVerdict::kMeets;
    if (*band.lower > hi || *band.upper < lo) return SweepVerdict::kMisses;
    return SweepVerdict::kUndecided;
  }
  // No band: a max only grows and a min only falls with more gears, so an extreme already
  // beyond a limit stays beyond it, and one already past a limit on its far side stays past it.
  if (s.statistic == "max") {
    if (*value > hi) return SweepVerdict::kMisses;
    if (!limit.at_most && *value >= lo) return SweepVerdict::kMeets;
  }
  if (s.statistic == "min") {
    if (*value < lo) return SweepVerdict::kMisses;
    if (!limit.at_least && *value <= hi) return SweepVerdict::kMeets;
  }
  return SweepVerdict::kUndecided;
}

}  // namespace gearmc
