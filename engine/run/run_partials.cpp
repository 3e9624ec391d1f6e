// Partial Monte-Carlo results of the ranks: bytes, merge, the distributed run (run_partials.h).
#include "engine/run/run_partials.h"

#include <algorithm>
#include <chrono>
#include <optional>
#include <stdexcept>
#include <string>

#include "core/bytes.h"
#include "core/input_error.h"
#include "gears/tolerances.h"

namespace gearmc {
namespace {

void put_stats(std::string& out, const ErrorStatistics& s) {
  s.moments.encode(out);
  s.histogram.encode(out);
  ByteWriter(out).put(s.non_finite);
}
ErrorStatistics get_stats(ByteReader& in) {
  ErrorStatistics s;
  s.moments = RunningStats::decode(in);
  s.histogram = RelativeHistogram::decode(in);
  s.non_finite = in.get<std::uint64_t>();
  return s;
}

void put_effects(std::string& out, const EffectTotals& e) {
  for (const RunningStats& s : e.total_signed) s.encode(out);
  e.radius_compensation.encode(out);
  ByteWriter(out).put<std::uint64_t>(e.contribution.size());
  for (std::size_t k = 0; k < e.contribution.size(); ++k) {
    e.contribution[k].encode(out);
    e.alone[k].encode(out);
  }
}
EffectTotals get_effects(ByteReader& in) {
  EffectTotals e;
  for (RunningStats& s : e.total_signed) s = RunningStats::decode(in);
  e.radius_compensation = RunningStats::decode(in);
  const auto n = static_cast<std::size_t>(in.get<std::uint64_t>());
  for (std::size_t k = 0; k < n; ++k) {
    e.contribution.push_back(RunningStats::decode(in));
    e.alone.push_back(RunningStats::decode(in));
  }
  return e;
}

// The statistics of a run (RunResults: ErrorStatistics) or the moments of a block (BlockMoments:
// RunningStats), which name them alike, in a fixed order (for encoding, decoding and merging).
template <typename R, typename F>
void each_statistic(R& r, F f) {
  for (int s = 0; s < 2; ++s) {
    f(r.point[s]);
    f(r.flank_max[s]);
    f(r.flank_mean[s]);
    f(r.total_abs[s]);
  }
}

// MonteCarloRun::run with a gear whose tolerances cannot be met turned into bad input.
RunResults run_local(const MonteCarloRun& mc, const RunOptions& options) {
  try {
    return mc.run(options);
  } catch (const ToleranceError& e) {
    // The scenario's tolerances contradict each other for this gear (the load-time check draws
    // only the first gears).
    const std::string& path = mc.scenario().source_path;
    throw InputError({path, 0, 0}, (path.empty() ? std::string("the scenario") : path) +
                                       ": tolerances: " + e.what());
  }
}

}  // namespace

namespace {

// The gear parameters' items (scenario `evaluation:`), in gear order: per parameter and side the
// count, then each item's three values and its budget. The chart traces stay on rank 0, which
// always runs the first gear of a run or batch.
void put_values(ByteWriter& w, const std::vector<double>& v) {
  w.put<std::uint64_t>(v.size());
  for (double x : v) w.put(x);
}
void get_values(ByteReader& in, std::vector<double>& v) {
  v.resize(static_cast<std::size_t>(in.get<std::uint64_t>()));
  for (double& x : v) x = in.get<double>();
}
void put_trace(ByteWriter& w, const FlankTrace& t) {
  w.put<std::int64_t>(t.tooth);
  w.put<std::uint8_t>(t.side == FlankSide::kRight ? 1 : 0);
  for (const std::vector<double>* v :
       {&t.x_mm, &t.measured_um, &t.true_um, &t.dense_x_mm, &t.dense_um}) {
    put_values(w, *v);
  }
  w.put(t.range_start_mm);
  w.put(t.range_end_mm);
  const TraceResult& m = t.measured_line;
  for (double x : {m.total_um, m.slope_um, m.form_um, m.intercept_um, m.slope_um_per_mm}) w.put(x);
  w.put<std::int64_t>(m.samples);
}
FlankTrace get_trace(ByteReader& in) {
  FlankTrace t;
  t.tooth = static_cast<int>(in.get<std::int64_t>());
  t.side = in.get<std::uint8_t>() != 0 ? FlankSide::kRight : FlankSide::kLeft;
  for (std::vector<double>* v : {&t.x_mm, &t.measured_um, &t.true_um, &t.dense_x_mm, &t.dense_um}) {
    get_values(in, *v);
  }
  t.range_start_mm = in.get<double>();
  t.range_end_mm = in.get<double>();
  TraceResult& m = t.measured_line;
  for (double* x : {&m.total_um, &m.slope_um, &m.form_um, &m.intercept_um, &m.slope_um_per_mm}) {
    *x = in.get<double>();
  }
  m.samples = static_cast<int>(in.get<std::int64_t>());
  return t;
}

void put_parameters(std::string& out, const std::optional<ParameterSamples>& p) {
  ByteWriter w(out);
  w.put<std::uint8_t>(p ? 1 : 0);
  if (!p) return;
  // The chart gear's traces (the first gear of the run, on whichever rank ran it).
  w.put<std::int64_t>(p->chart_gear.value_or(-1));
  if (p->chart_gear) {
    const GearTraces& c = p->chart;
    for (const std::vector<FlankTrace>* traces : {&c.profile, &c.helix}) {
      w.put<std::uint64_t>(traces->size());
      for (const FlankTrace& t : *traces) put_trace(w, t);
    }
    for (int s = 0; s < 2; ++s) {
      put_values(w, c.pitch_measured[s]);
      put_values(w, c.pitch_true[s]);
    }
    put_values(w, c.ball_measured);
    put_values(w, c.ball_true);
  }
  for (const auto& sides : p->values) {
    for (const std::vector<ParameterValue>& items : sides) {
      w.put<std::uint64_t>(items.size());
      for (const ParameterValue& v : items) {
        w.put(v.measured);
        w.put(v.true_points);
        w.put(v.true_dense);
        w.put<std::uint64_t>(v.budget.size());
        for (double b : v.budget) w.put(b);
      }
    }
  }
}

std::optional<ParameterSamples> get_parameters(ByteReader& in) {
  if (in.get<std::uint8_t>() == 0) return std::nullopt;
  ParameterSamples p;
  const auto chart_gear = in.get<std::int64_t>();
  if (chart_gear >= 0) {
    p.chart_gear = static_cast<int>(chart_gear);
    GearTraces& c = p.chart;
    for (std::vector<FlankTrace>* traces : {&c.profile, &c.helix}) {
      traces->resize(static_cast<std::size_t>(in.get<std::uint64_t>()));
      for (FlankTrace& t : *traces) t = get_trace(in);
    }
    for (int s = 0; s < 2; ++s) {
      get_values(in, c.pitch_measured[s]);
      get_values(in, c.pitch_true[s]);
    }
    get_values(in, c.ball_measured);
    get_values(in, c.ball_true);
  }
  for (auto& sides : p.values) {
    for (std::vector<ParameterValue>& items : sides) {
      items.resize(static_cast<std::size_t>(in.get<std::uint64_t>()));
      for (ParameterValue& v : items) {
        v.measured = in.get<double>();
        v.true_points = in.get<double>();
        v.true_dense = in.get<double>();
        v.budget.resize(static_cast<std::size_t>(in.get<std::uint64_t>()));
        for (double& b : v.budget) b = in.get<double>();
      }
    }
  }
  return p;
}

}  // namespace

std::string encode_partial(const RunResults& r) {
  std::string out;
  ByteWriter w(out);
  each_statistic(r, [&](const ErrorStatistics& s) { put_stats(out, s); });
  put_effects(out, r.effects);
  for (std::uint64_t v : {r.contacts, r.failed_contacts, r.edge_contacts, r.collisions,
                          r.runout_redrawn_gears, r.runout_redraws}) {
    w.put(v);
  }
  w.put<std::int64_t>(r.gears);
  w.put<std::uint8_t>(r.cancelled ? 1 : 0);
  w.put<std::int64_t>(r.first_block);
  w.put<std::uint64_t>(r.block_moments.size());
  for (const BlockMoments& b : r.block_moments) {
    each_statistic(b, [&](const RunningStats& s) { s.encode(out); });
    put_effects(out, b.effects);
  }
  put_parameters(out, r.parameters);
  return out;
}

RunResults decode_partial(std::string_view bytes) {
  ByteReader in(bytes);
  RunResults r;
  each_statistic(r, [&](ErrorStatistics& s) { s = get_stats(in); });
  r.effects = get_effects(in);
  for (std::uint64_t* v : {&r.contacts, &r.failed_contacts, &r.edge_contacts, &r.collisions,
                           &r.runout_redrawn_gears, &r.runout_redraws}) {
    *v = in.get<std::uint64_t>();
  }
  r.gears = static_cast<int>(in.get<std::int64_t>());
  r.cancelled = in.get<std::uint8_t>() != 0;
  r.first_block = static_cast<int>(in.get<std::int64_t>());
  const auto blocks = static_cast<std::size_t>(in.get<std::uint64_t>());
  r.block_moments.resize(blocks);
  for (BlockMoments& b : r.block_moments) {
    each_statistic(b, [&](RunningStats& s) { s = RunningStats::decode(in); });
    b.effects = get_effects(in);
  }
  r.parameters = get_parameters(in);
  if (!in.done()) throw std::runtime_error("decode_partial: trailing bytes");
  return r;
}

void append_partial(RunResults& into, const RunResults& later) {
  // Exact parts: integer counts and the exact extremes of the histograms.
  std::vector<ErrorStatistics*> mine;
  each_statistic(into, [&](ErrorStatistics& s) { mine.push_back(&s); });
  std::size_t k = 0;
  each_statistic(later, [&](const ErrorStatistics& s) {
    mine[k]->histogram.merge(s.histogram);
    mine[k]->non_finite += s.non_finite;
    ++k;
  });
  into.contacts += later.contacts;
  into.failed_contacts += later.failed_contacts;
  into.edge_contacts += later.edge_contacts;
  into.collisions += later.collisions;
  into.runout_redrawn_gears += later.runout_redrawn_gears;
  into.runout_redraws += later.runout_redraws;
  into.gears += later.gears;
  into.cancelled = into.cancelled || later.cancelled;
  // Moments: block after block, as one process merges them.
  for (const BlockMoments& b : later.block_moments) into.fold(b);
  // Gear parameters: `later`'s items follow `into`'s in gear order.
  if (later.parameters) {
    if (!into.parameters) into.parameters.emplace();
    if (!into.parameters->chart_gear && later.parameters->chart_gear) {
      into.parameters->chart_gear = later.parameters->chart_gear;
      into.parameters->chart = later.parameters->chart;
    }
    for (std::size_t p = 0; p < later.parameters->values.size(); ++p) {
      for (int s = 0; s < 2; ++s) {
        auto& to = into.parameters->values[p][s];
        const auto& from = later.parameters->values[p][s];
        to.insert(to.end(), from.begin(), from.end());
      }
    }
  }
}

RunResults run_on_ranks(const MonteCarloRun& mc, RunOptions options, const Ranks& ranks,
                        const GearStream& stream) {
  const auto start = std::chrono::steady_clock::now();
  // The batch [batch_first, batch_end) of the run's gears.
  const int batch_first = options.first_gear;
  const int batch_end = mc.end_gear(options);
  if (batch_first % kGearsPerBlock != 0) {
    throw std::invalid_argument("run_on_ranks: first_gear is not at a block boundary");
  }
  const bool keep_blocks = options.keep_block_moments;
  if (ranks.size() == 1) {
    if (stream.encode) {
      // The caller's on_gear, kept by value: this block's variables end before the run.
      options.on_gear = [&stream, previous = options.on_gear](const GearOutcome& g) {
        if (previous) previous(g);
        std::string bytes;
        stream.encode(g, bytes);
        stream.consume(bytes);
      };
    }
    return run_local(mc, options);
  }

  // This rank's share of whole blocks (only_gear: rank 0 alone).
  const std::uint64_t blocks =
      batch_end > batch_first
          ? (static_cast<std::uint64_t>(batch_end - batch_first) + kGearsPerBlock - 1) /
                kGearsPerBlock
          : 0;
  const Ranks::Share share =
      options.only_gear ? Ranks::Share{0, ranks.is_root() ? blocks : 0} : ranks.share(blocks);
  const int local_first = batch_first + static_cast<int>(share.begin) * kGearsPerBlock;
  const int local_end =
      std::min(batch_end, batch_first + static_cast<int>(share.end) * kGearsPerBlock);
  options.first_gear = local_first;
  options.end_gear = local_end;
  options.keep_block_moments = true;
  std::string text;  // this rank's per-gear bytes (ranks other than 0)
  if (ranks.is_root()) {
    if (options.progress && !options.only_gear && local_end > local_first) {
      // Rank 0's share stands for the whole run (the shares differ by at most one block).
      const auto progress = options.progress;
      const int total = batch_end - batch_first;
      const double scale = static_cast<double>(total) / (local_end - local_first);
      options.progress = [progress, scale, total](int done, int) {
        progress(done == 0 ? 0 : std::min(total, static_cast<int>(done * scale)), total);
      };
    }
    if (stream.encode) {
      // The caller's on_gear, kept by value: this block's variables end before the run.
      options.on_gear = [&stream, previous = options.on_gear](const GearOutcome& g) {
        if (previous) previous(g);
        std::string bytes;
        stream.encode(g, bytes);
        stream.consume(bytes);
      };
    }
  } else {
    options.progress = nullptr;
    options.on_gear = nullptr;
    if (stream.encode) {
      options.on_gear = [&](const GearOutcome& g) { stream.encode(g, text); };
    }
  }

  // A binary tree toward rank 0 (Ranks::reduce_to_root): a rank absorbs the partial results of
  // the ranks right after its range, so its histograms and counts cover a contiguous range of
  // blocks and its block moments list them in block order; rank 0 folds every block's moments in
  // block order, exactly as one process does.
  RunResults mine;
  std::chrono::steady_clock::time_point own_done;
  double absorbing_s = 0.0;
  ranks.reduce_to_root(
      [&] {
        if (local_end > local_first) {
          mine = run_local(mc, options);
        } else {
          mine.first_block = local_first / kGearsPerBlock;
        }
        own_done = std::chrono::steady_clock::now();
      },
      [&] {
        std::string bytes;
        ByteWriter w(bytes);
        w.put_text(encode_partial(mine));
        w.put_text(text);
        return bytes;
      },
      [&](std::string_view bytes) {
        const auto t0 = std::chrono::steady_clock::now();
        mine.reduction_bytes += bytes.size();
        ByteReader in(bytes);
        RunResults later = decode_partial(in.get_text());
        const std::string gears_text = in.get_text();
        append_partial(mine, later);
        if (!ranks.is_root() || keep_blocks) {
          for (BlockMoments& b : later.block_moments) mine.block_moments.push_back(std::move(b));
        }
        if (ranks.is_root()) {
          if (stream.consume && !gears_text.empty()) stream.consume(gears_text);
        } else {
          text += gears_text;
        }
        absorbing_s += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      });
  if (!ranks.is_root()) return mine;
  if (!keep_blocks) mine.block_moments.clear();
  const double since_own =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - own_done).count();
  mine.merge_s = absorbing_s;
  mine.gather_s = since_own - absorbing_s;
  mine.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return mine;
}

}  // namespace gearmc
