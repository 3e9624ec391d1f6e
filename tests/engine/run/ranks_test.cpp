// The pieces that make a run over MPI ranks give the single-process files byte for byte, tested
// without MPI: the contiguous shares, the bit-exact byte round trip of the partial statistics, and
// a run split into block-aligned partial runs (as ranks would run them) merged by append_partial
// against the same run in one call. The end-to-end check with mpirun is tests/mpi/mpi_identity.sh.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <utility>

#include "core/bytes.h"
#include "core/input_error.h"
#include "core/ranks.h"
#include "engine/run/monte_carlo.h"
#include "engine/run/run_partials.h"
#include "engine/scenario/scenario.h"
#include "engine/statistics/relative_histogram.h"
#include "engine/statistics/running_stats.h"

namespace gearmc {
namespace {

TEST(RanksShare, ContiguousCoveringAndBalanced) {
  for (int size : {1, 2, 3, 7, 64}) {
    for (std::uint64_t n : {0ull, 1ull, 5ull, 64ull, 301ull, 1000003ull}) {
      std::uint64_t next = 0;
      for (int r = 0; r < size; ++r) {
        const Ranks::Share s = Ranks::share_of(n, r, size);
        EXPECT_EQ(s.begin, next) << "n " << n << " size " << size << " rank " << r;
        EXPECT_LE(s.end - s.begin, n / size + 1);
        EXPECT_GE(s.end - s.begin, n / size);
        next = s.end;
      }
      EXPECT_EQ(next, n);
    }
  }
}

TEST(RanksShare, SingleProcessWithoutMpiIsRankZeroOfOne) {
  const Ranks single;
  EXPECT_EQ(single.rank(), 0);
  EXPECT_EQ(single.size(), 1);
  // The error of the work reaches the caller with its type and message.
  EXPECT_THROW(single.agree([] { throw InputError({}, "bad"); }), InputError);
  EXPECT_EQ(single.gather([] { return std::string("abc"); }).at(0), "abc");
}

TEST(PartialBytes, StatisticsRoundTripBitForBit) {
  RunningStats moments;
  RelativeHistogram histogram;
  // Values over 12 decades, both signs, zero and infinities: every kind of bucket.
  for (int i = 0; i < 5000; ++i) {
    const double v = std::pow(10.0, -6 + 12.0 * i / 5000.0) * (i % 3 == 0 ? -1 : 1);
    moments.add(v);
    histogram.add(v);
  }
  histogram.add(0.0);
  histogram.add(INFINITY);
  histogram.add(-INFINITY);
  histogram.add(NAN);
  std::string bytes;
  moments.encode(bytes);
  histogram.encode(bytes);
  ByteReader in(bytes);
  EXPECT_TRUE(RunningStats::decode(in) == moments);
  const RelativeHistogram back = RelativeHistogram::decode(in);
  EXPECT_TRUE(in.done());
  EXPECT_TRUE(back == histogram);
  EXPECT_EQ(back.invalid(), 1u);
  EXPECT_EQ(back.quantile(0.9973), histogram.quantile(0.9973));
}

// P1's gear with few probed points (2 teeth, 3 × 2 points per flank) and an effect chain, so
// that 600 gears (3 blocks of kGearsPerBlock) run in about a second.
Scenario small_scenario() {
  const std::string path = std::string(GEARMC_SOURCE_DIR) + "/scenarios/p2_probe_mean6.yaml";
  std::string text = load_scenario_file(path).source_text;
  for (const auto& [from, to] :
       {std::pair<std::string, std::string>{"points_along_profile: 10", "points_along_profile: 3"},
        {"sections_across_face: 5", "sections_across_face: 2"},
        {"teeth: all", "teeth: [1, 13]"}}) {
    const std::size_t at = text.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    if (at != std::string::npos) text.replace(at, from.size(), to);
  }
  return parse_scenario(text, path);
}

void expect_same(const ErrorStatistics& a, const ErrorStatistics& b, const char* what) {
  EXPECT_TRUE(a.moments == b.moments)
      << what << ": mean " << a.moments.mean() << " vs " << b.moments.mean();
  EXPECT_TRUE(a.histogram == b.histogram) << what;
  EXPECT_EQ(a.non_finite, b.non_finite) << what;
}

TEST(PartialRuns, BlockAlignedSharesMergeToTheSingleRunBitForBit) {
  const Scenario scenario = small_scenario();
  const MonteCarloRun mc(scenario);
  RunOptions whole;
  whole.end_gear = 2 * kGearsPerBlock + 40;  // 3 blocks, the last one short
  whole.threads = 2;
  const RunResults single = mc.run(whole);
  ASSERT_GT(single.point[0].moments.count(), 0u);

  // The shares of 3 ranks (one block each) and of 2 ranks (1 + 2 blocks), each run with another
  // thread count, sent through the byte encoding as rank 0 receives them.
  for (const std::vector<int>& cuts : {std::vector<int>{0, 1, 2, 3}, std::vector<int>{0, 1, 3}}) {
    RunResults merged;
    for (std::size_t k = 0; k + 1 < cuts.size(); ++k) {
      RunOptions part = whole;
      part.threads = 1;
      part.first_gear = cuts[k] * kGearsPerBlock;
      part.end_gear = std::min(cuts[k + 1] * kGearsPerBlock, whole.end_gear);
      part.keep_block_moments = true;
      const RunResults r = decode_partial(encode_partial(mc.run(part)));
      if (k == 0) {
        merged = r;
      } else {
        append_partial(merged, r);
      }
    }
    for (int s = 0; s < 2; ++s) {
      expect_same(merged.point[s], single.point[s], "point");
      expect_same(merged.flank_max[s], single.flank_max[s], "flank_max");
      expect_same(merged.flank_mean[s], single.flank_mean[s], "flank_mean");
      expect_same(merged.total_abs[s], single.total_abs[s], "total_abs");
      EXPECT_TRUE(merged.effects.total_signed[s] == single.effects.total_signed[s]);
    }
    EXPECT_TRUE(merged.effects.radius_compensation == single.effects.radius_compensation);
    ASSERT_EQ(merged.effects.contribution.size(), single.effects.contribution.size());
    for (std::size_t e = 0; e < single.effects.contribution.size(); ++e) {
      EXPECT_TRUE(merged.effects.contribution[e] == single.effects.contribution[e]);
      EXPECT_TRUE(merged.effects.alone[e] == single.effects.alone[e]);
    }
    EXPECT_EQ(merged.contacts, single.contacts);
    EXPECT_EQ(merged.failed_contacts, single.failed_contacts);
    EXPECT_EQ(merged.gears, single.gears);
  }
}

TEST(PartialRuns, BlockMergedMomentsAgreeWithOneSequentialPassToRounding) {
  // The moments are Welford within each block and Chan's merge across blocks; one sequential
  // Welford pass over the same values in gear order (the reduction before blocks) may differ only
  // by rounding: |Δmean| and |Δstd| below 1e-12 relative (about 2^-40, far above the ~1e-15 of a
  // few hundred rounding steps of 2^-53, far below any physical digit).
  const Scenario scenario = small_scenario();
  const MonteCarloRun mc(scenario);
  RunOptions options;
  options.end_gear = 2 * kGearsPerBlock + 40;
  RunningStats sequential[2];
  options.on_gear = [&](const GearOutcome& g) {
    for (int s = 0; s < 2; ++s) {
      for (double v : g.point_delta[s]) sequential[s].add(v);
    }
  };
  const RunResults r = mc.run(options);
  for (int s = 0; s < 2; ++s) {
    const RunningStats& blocked = r.point[s].moments;
    ASSERT_EQ(blocked.count(), sequential[s].count());
    EXPECT_NEAR(blocked.mean(), sequential[s].mean(), 1e-12 * std::abs(sequential[s].mean()));
    EXPECT_NEAR(blocked.stddev(), sequential[s].stddev(), 1e-12 * sequential[s].stddev());
    EXPECT_EQ(blocked.min(), sequential[s].min());
    EXPECT_EQ(blocked.max(), sequential[s].max());
  }
}

}  // namespace
}  // namespace gearmc
