// A Monte-Carlo run split over processes (core/ranks): rank r runs a contiguous share of the
// run's blocks of kGearsPerBlock gears (monte_carlo.h) and keeps each block's moments; the partial
// results go as bytes up a binary tree to rank 0 (Ranks::reduce_to_root), each rank absorbing the
// ranks right after its range: histograms and counts by exact integer sums, block moments listed
// in block order, and rank 0 folds the moments block after block in block order. Since a single
// process merges its blocks in the same order, rank 0's results are bit-identical to
// MonteCarloRun::run of the whole run in one process, for any number of ranks and threads.
//
// Per-gear output that must reach rank 0 in gear order (points.csv rows, a claim check's per-gear
// values) goes through a GearStream: bytes per gear, made on the rank that ran the gear, consumed
// on rank 0 in gear order.
#pragma once

#include <functional>
#include <string>
#include <string_view>

#include "core/ranks.h"
#include "engine/run/monte_carlo.h"

namespace gearmc {

// RunResults (with its block moments) as bytes and back, bit for bit. wall_s is not carried.
std::string encode_partial(const RunResults& r);
RunResults decode_partial(std::string_view bytes);

// Merges `later`, the partial results of the blocks that directly follow those of `into`:
// exact parts added, `later`'s block moments folded one by one (RunResults::fold).
void append_partial(RunResults& into, const RunResults& later);

struct GearStream {
  // Appends gear g's bytes (called on the rank that ran g, in gear order within its share).
  std::function<void(const GearOutcome& g, std::string& out)> encode;
  // Rank 0 only: consecutive gears' bytes, in gear order over the whole run (one call per gear of
  // rank 0's share, then one call per other rank's share).
  std::function<void(std::string_view bytes)> consume;
};

// Runs the gears [options.first_gear, mc.end_gear(options)) of `mc` (by default all of the
// scenario's run.gears; first_gear at a block boundary: a batch of a sequential procedure) over
// `ranks`: rank r runs a contiguous share of the batch's blocks. options.only_gear runs on rank 0
// alone; options.progress (with the estimate done × ranks) and options.on_gear are used on rank 0
// only and on_gear sees only rank 0's own gears: per-gear output of every gear goes through
// `stream`. With options.keep_block_moments, rank 0's results keep the block moments of the whole
// batch (to merge batches later with append_partial as one run would). Returns on rank 0 the
// results of the batch, bit-identical to mc.run(options) in one process, and on the other ranks
// their own share's partial results. Collective: every rank calls it with the same options; an
// error on any rank (a gear whose tolerances cannot be met is an InputError naming the scenario)
// is thrown on all. wall_s is rank 0's time for the whole call.
RunResults run_on_ranks(const MonteCarloRun& mc, RunOptions options, const Ranks& ranks,
                        const GearStream& stream = {});

}  // namespace gearmc
