// Implementation of mcm.h; JCGM 101:2008 clauses cited where used.
#include "engine/apps/uncertainty/mcm.h"

#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstring>
#include <limits>
#include <memory>
#include <optional>
#include <sstream>
#include <utility>

#include "core/check.h"
#include "core/number_text.h"
#include "core/random_stream.h"
#include "core/special_functions.h"
#include "core/thread_arena.h"
#include "engine/apps/uncertainty/model_function.h"
#include "engine/statistics/conformity.h"

namespace gearmc::uncertainty {
namespace {

// Trials per task of the parallel loop and per progress/cancellation step.
constexpr std::uint64_t kGrain = 4096;
constexpr std::uint64_t kChunk = 1u << 18;

// Whether input i is correlated with another (then it is drawn through the copula).
bool in_copula(const UncertaintyModel& model, std::size_t i) {
  const auto row = static_cast<Eigen::Index>(i);
  for (Eigen::Index k = 0; k < model.copula.cols(); ++k) {
    if (k != row && model.copula(row, k) != 0.0) return true;
  }
  return false;
}

// The inputs of trial t into x (size n); `z` is scratch for the correlated inputs' normals.

void draw_inputs(const UncertaintyModel& model, std::uint64_t seed, std::uint64_t t, double* x,
                 double* z) {
  const std::size_t n = model.inputs.size();
  if (!model.correlated) {
    for (std::size_t i = 0; i < n; ++i) {
      TrialStream s(seed, t, static_cast<std::uint32_t>(i));
      x[i] = model.inputs[i].law.sample(s);
    }
    return;
  }
  // Correlated inputs: v = L z, L the Cholesky factor of the copula's correlation (its rows of
  // uncorrelated inputs are unit rows); normal inputs x = μ + σ v (JCGM 101 §6.4.8), the others
  // x = F⁻¹(Φ(v)) (the Gaussian copula, laws.h). An input in no correlation keeps its own sampler.
  for (std::size_t i = 0; i < n; ++i) {
    TrialStream s(seed, t, static_cast<std::uint32_t>(i));
    if (model.inputs[i].law.kind() == LawKind::kNormal || in_copula(model, i)) {
      z[i] = s.normal();
    } else {
      z[i] = 0.0;
      x[i] = model.inputs[i].law.sample(s);
    }
  }
  for (std::size_t i = 0; i < n; ++i) {
    const Law& law = model.inputs[i].law;
    if (law.kind() != LawKind::kNormal && !in_copula(model, i)) continue;
    double v = 0.0;
    for (std::size_t k = 0; k <= i; ++k)
      v += model.cholesky(Eigen::Index(i), Eigen::Index(k)) * z[k];
    if (law.kind() == LawKind::kNormal) {
      x[i] = law.parameters()[0] + law.parameters()[1] * v;
    } else {
      const double u =
          std::clamp(normal_cdf(v), std::numeric_limits<double>::min(), std::nextafter(1.0, 0.0));
      x[i] = law.quantile(u);
    }
  }
}

struct MeanSd {
  double mean = 0.0, sd = 0.0;
};
// Two-pass mean and sample standard deviation (divisor n − 1, JCGM 101 §7.6), in index order.
// When a sum overflows (values near 1e308: their sum is inf though every value is finite), the
// same passes run on the values divided by the largest |value| and the results are scaled back.
MeanSd mean_sd(const double* v, std::size_t n) {
  double s = 0.0;
  for (std::size_t i = 0; i < n; ++i) s += v[i];
  double mean = s / static_cast<double>(n);
  double ss = 0.0;
  for (std::size_t i = 0; i < n; ++i) ss += (v[i] - mean) * (v[i] - mean);
  if (!std::isfinite(mean) || !std::isfinite(ss)) {
    double scale = 0.0;
    for (std::size_t i = 0; i < n; ++i) scale = std::max(scale, std::fabs(v[i]));
    if (scale > 0.0 && std::isfinite(scale)) {
      s = 0.0;
      for (std::size_t i = 0; i < n; ++i) s += v[i] / scale;
      const double scaled_mean = s / static_cast<double>(n);
      ss = 0.0;
      for (std::size_t i = 0; i < n; ++i) {
        ss += (v[i] / scale - scaled_mean) * (v[i] / scale - scaled_mean);
      }
      mean = scaled_mean * scale;
      return {mean, n > 1 ? std::sqrt(ss / static_cast<double>(n - 1)) * scale : 0.0};
    }
  }
  return {mean, n > 1 ? std::sqrt(ss / static_cast<double>(n - 1)) : 0.0};
}

// Standard deviation of the average of block values (JCGM 101 §7.9.4 g):
// s² = Σ (v_r − v̄)² / (h (h − 1)).
double sd_of_average(const std::vector<double>& v) {
  const double h = static_cast<double>(v.size());
  double mean = 0.0;
  for (double x : v) mean += x;
  mean /= h;
  double ss = 0.0;
  for (double x : v) ss += (x - mean) * (x - mean);
  return std::sqrt(ss / (h * (h - 1.0)));
}

}  // namespace

void sort_values(std::vector<double>& v) {
  const std::size_t n = v.size();
  // Peak memory 16 bytes per value: the keys and one scratch buffer exist while `v` is freed.
  std::vector<std::uint64_t> a(n);
  for (std::size_t i = 0; i < n; ++i) {
    std::uint64_t k;
    std::memcpy(&k, &v[i], sizeof k);
    a[i] = (k >> 63) ? ~k : (k | 0x8000000000000000ull);
  }
  std::vector<double>().swap(v);
  {
    std::vector<std::uint64_t> b(n);
    std::vector<std::size_t> count(1u << 16);
    for (int pass = 0; pass < 4; ++pass) {
      const int shift = 16 * pass;
      std::fill(count.begin(), count.end(), 0);
      for (std::size_t i = 0; i < n; ++i) ++count[(a[i] >> shift) & 0xFFFF];
      std::size_t sum = 0;
      for (std::size_t& c : count) {
        const std::size_t t = c;
        c = sum;
        sum += t;
      }
      for (std::size_t i = 0; i < n; ++i) b[count[(a[i] >> shift) & 0xFFFF]++] = a[i];
      a.swap(b);
    }
  }
  v.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    const std::uint64_t k = (a[i] >> 63) ? (a[i] & 0x7FFFFFFFFFFFFFFFull) : ~a[i];
    std::memcpy(&v[i], &k, sizeof k);
  }
}

std::uint64_t coverage_count(std::uint64_t M, double p) { return gearmc::coverage_count(M, p); }

Interval symmetric_interval(const std::vector<double>& sorted, double p) {
  // JCGM 101 §7.7.1 in engine/statistics/conformity; callers check q < M first (the R-Test's
  // axes once passed 5 values left of 2000 trials at p 0.95, q = 5, and read one past the end).
  const std::optional<CoverageInterval> c = symmetric_coverage_interval(sorted, p);
  GEARMC_CHECK(c.has_value(), "symmetric_interval: fewer values than the coverage needs");
  return {c->lo, c->hi};
}

Interval shortest_interval(const std::vector<double>& sorted, double p) {
  // The O(M) scan of engine/statistics/conformity (JCGM 101 §7.7.2); callers check q < M first.
  const std::optional<CoverageInterval> c = shortest_coverage_interval(sorted, p);
  GEARMC_CHECK(c.has_value(), "shortest_interval: fewer values than the coverage needs");
  return {c->lo, c->hi};
}

double numerical_tolerance(double u, int ndig) {
  if (!(u > 0) || !std::isfinite(u)) return 0.0;
  int l = static_cast<int>(std::floor(std::log10(u))) - (ndig - 1);
  const double c = std::round(u / std::pow(10.0, l));
  if (c >= std::pow(10.0, ndig)) ++l;  // u rounds up to one more digit, e.g. 0.0996 at 2
  return 0.5 * std::pow(10.0, l);
}

std::uint64_t adaptive_block_size(double p) {
  const auto j = static_cast<std::uint64_t>(std::ceil(100.0 / (1.0 - p) - 1e-9));
  return std::max<std::uint64_t>(j, 10000);
}

std::uint64_t smallest_trials(double p) {
  // q = round(pM) must satisfy 1 ≤ q ≤ M − 1: pM ≥ 1/2 and (1 − p)M > 1/2, so the smallest M is
  // near max(1/(2p), 1/(2(1 − p))); counted up from just below it with coverage_count itself.
  const double estimate = std::max(0.5 / p, 0.5 / (1.0 - p));
  std::uint64_t M = estimate > 3.0 ? static_cast<std::uint64_t>(estimate) - 2 : 1;
  while (true) {
    const std::uint64_t q = coverage_count(M, p);
    if (q >= 1 && q < M) return M;
    ++M;
  }
}

void check_trials(std::uint64_t M, std::size_t outputs, double p, const InputLocation& where,
                  const std::string& key) {
  const std::uint64_t q = coverage_count(M, p);
  if (q >= M || q == 0) {
    throw InputError(where, key, std::to_string(M),
                     "at least " + std::to_string(smallest_trials(p)) +
                         " trials for a coverage probability of " + shortest_text(p) +
                         " (the smallest number whose coverage interval exists; JCGM 101 "
                         "recommends at least " +
                         std::to_string(adaptive_block_size(p)) + ")");
  }
  const double bytes =
      kBytesPerTrialPerOutput * static_cast<double>(M) * static_cast<double>(outputs);
  if (bytes > kMaxValueBytes) {
    std::ostringstream msg;
    msg << "at most "
        << static_cast<std::uint64_t>(kMaxValueBytes / kBytesPerTrialPerOutput /
                                      static_cast<double>(outputs))
        << " trials for " << outputs << " output(s): a run keeps 16 bytes per trial per output ("
        << bytes / 1e9 << " GB here, the limit is " << kMaxValueBytes / 1e9 << " GB)";
    throw InputError(where, key, std::to_string(M), msg.str());
  }
}

void run_trials(const UncertaintyModel& model, std::uint64_t seed, std::uint64_t first,
                std::uint64_t count, std::vector<std::vector<double>>& values) {
  const std::size_t n = model.inputs.size(), m = model.outputs.size();
  tbb::enumerable_thread_specific<std::unique_ptr<ModelFunction>> functions;
  std::atomic<std::uint64_t> bad_count{0};
  std::atomic<std::uint64_t> first_bad{UINT64_MAX};
  tbb::parallel_for(
      tbb::blocked_range<std::uint64_t>(first, first + count, kGrain),
      [&](const tbb::blocked_range<std::uint64_t>& range) {
        auto& f = functions.local();
        if (!f) f = std::make_unique<ModelFunction>(model);
        std::vector<double> x(n), z(n), y(m);
        for (std::uint64_t t = range.begin(); t != range.end(); ++t) {
          draw_inputs(model, seed, t, x.data(), z.data());
          f->evaluate(x.data(), y.data());
          for (std::size_t j = 0; j < m; ++j) {
            values[j][t] = y[j];
            if (!std::isfinite(y[j])) {
              ++bad_count;
              std::uint64_t prev = first_bad.load();
              while (t < prev && !first_bad.compare_exchange_weak(prev, t)) {
              }
            }
          }
        }
      },
      tbb::simple_partitioner());
  if (bad_count.load() == 0) return;
  // Re-draw the first bad trial alone to name its inputs (the draws are a function of t).
  const std::uint64_t t = first_bad.load();
  std::vector<double> x(n), z(n), y(m);
  draw_inputs(model, seed, t, x.data(), z.data());
  ModelFunction f(model);
  f.evaluate(x.data(), y.data());
  std::ostringstream msg;
  msg.precision(10);
  msg << model.source_path << ": the model gives a value that is not finite in " << bad_count.load()
      << " trial output(s); the first is trial " << t << " (seed " << seed << ") with";
  for (std::size_t i = 0; i < n; ++i)
    msg << (i ? ", " : " ") << model.inputs[i].name << " = " << x[i];
  msg << ":";
  for (std::size_t j = 0; j < m; ++j)
    msg << (j ? ", " : " ") << model.outputs[j].name << " = " << y[j];
  msg << "; check the expressions (division by zero, log or sqrt of a negative number) against "
         "the ranges of the input laws";
  throw InputError({model.source_path, 0, 0}, msg.str());
}

McmResult run_mcm(const UncertaintyModel& model, const McmOptions& o) {
  const auto start = std::chrono::steady_clock::now();
  const std::size_t m = model.outputs.size();
  const double p = o.coverage_probability;
  McmResult r;
  r.adaptive = !o.trials.has_value();
  r.threads = o.threads;
  r.ranks = o.ranks ? o.ranks->size() : 1;
  ThreadArena arena(o.threads);
  std::vector<std::vector<double>> values(m);

  // Trials [first, first + count) split over the ranks; every rank gets all their values.
  auto run_shared = [&](const Ranks& ranks, std::uint64_t first, std::uint64_t count) {
    const Ranks::Share mine = ranks.share(count);
    const std::vector<std::string> parts = ranks.all_gather([&] {
      if (mine.end > mine.begin) {
        arena.run(
            [&] { run_trials(model, o.seed, first + mine.begin, mine.end - mine.begin, values); });
      }
      std::string bytes;
      for (const std::vector<double>& v : values) {
        bytes.append(reinterpret_cast<const char*>(v.data() + first + mine.begin),
                     (mine.end - mine.begin) * sizeof(double));
      }
      return bytes;
    });
    for (int k = 0; k < ranks.size(); ++k) {
      const Ranks::Share share = ranks.share(count, k);
      const std::size_t n = share.end - share.begin;
      for (std::size_t j = 0; j < m; ++j) {
        std::memcpy(values[j].data() + first + share.begin,
                    parts[std::size_t(k)].data() + j * n * sizeof(double), n * sizeof(double));
      }
    }
  };

  // Runs trials [from, to) in chunks; false when cancelled.
  auto run_range = [&](std::uint64_t from, std::uint64_t to, std::uint64_t planned) {
    for (auto& v : values) v.resize(to);
    for (std::uint64_t c = from; c < to; c += kChunk) {
      // Over several ranks, an interrupt ends the job through mpirun (a rank that stopped alone
      // would leave the others waiting for its share).
      if (o.cancel && o.cancel->load() && r.ranks == 1) return false;
      const std::uint64_t count = std::min(kChunk, to - c);
      if (o.ranks == nullptr || o.ranks->size() == 1) {
        arena.run([&] { run_trials(model, o.seed, c, count, values); });
      } else {
        run_shared(*o.ranks, c, count);
      }
      if (o.progress) o.progress(c + count, planned);
    }
    return true;
  };

  if (!r.adaptive) {
    r.trials = *o.trials;
    if (!run_range(0, r.trials, r.trials)) {
      r.cancelled = true;
      return r;
    }
  } else {
    // JCGM 101 §7.9.4.
    const std::uint64_t B = adaptive_block_size(p);
    r.block_size = B;
    r.converged = false;
    std::vector<double> sum(m, 0.0);
    for (int h = 0;; ++h) {
      const std::uint64_t from = static_cast<std::uint64_t>(h) * B, to = from + B;
      const double bytes = kBytesPerTrialPerOutput * static_cast<double>(to) * double(m);
      if (to > o.max_trials || bytes > kMaxValueBytes) break;  // cap: not converged
      if (!run_range(from, to, 0)) {
        r.cancelled = true;
        return r;
      }
      r.blocks = h + 1;
      r.trials = to;
      BlockValues b;
      for (std::size_t j = 0; j < m; ++j) {
        const MeanSd ms = mean_sd(values[j].data() + from, B);
        std::vector<double> block(values[j].begin() + long(from), values[j].end());
        std::sort(block.begin(), block.end());
        const Interval sym = symmetric_interval(block, p), sh = shortest_interval(block, p);
        b.estimate.push_back(ms.mean);
        b.u.push_back(ms.sd);
        b.lo.push_back(sym.lo);
        b.hi.push_back(sym.hi);
        b.short_lo.push_back(sh.lo);
        b.short_hi.push_back(sh.hi);
      }
      r.block_values.push_back(std::move(b));
      if (r.blocks < 2) continue;
      bool all = true;
      r.outputs.assign(m, {});
      for (std::size_t j = 0; j < m; ++j) {
        std::vector<double> ye, yu, ylo, yhi, slo, shi;
        for (const BlockValues& bv : r.block_values) {
          ye.push_back(bv.estimate[j]);
          yu.push_back(bv.u[j]);
          ylo.push_back(bv.lo[j]);
          yhi.push_back(bv.hi[j]);
          slo.push_back(bv.short_lo[j]);
          shi.push_back(bv.short_hi[j]);
        }
        McmOutput& out = r.outputs[j];
        // §7.9.4 h): δ from u(y) of all h M values so far, pooled from the block means and
        // standard deviations: (hB − 1) u² = Σ_r [(B − 1) u_r² + B (ȳ_r − ȳ)²] (exact algebra,
        // O(h) instead of O(hB) per block).
        double grand = 0.0;
        for (double v : ye) grand += v;
        grand /= double(ye.size());
        double ss = 0.0;
        for (std::size_t blk = 0; blk < ye.size(); ++blk) {
          ss +=
              double(B - 1) * yu[blk] * yu[blk] + double(B) * (ye[blk] - grand) * (ye[blk] - grand);
        }
        out.delta = numerical_tolerance(std::sqrt(ss / double(to - 1)), o.significant_digits);
        out.two_s_estimate = 2 * sd_of_average(ye);
        out.two_s_u = 2 * sd_of_average(yu);
        // The endpoints of both interval kinds must be stable (both are reported).
        out.two_s_lo = 2 * std::max(sd_of_average(ylo), sd_of_average(slo));
        out.two_s_hi = 2 * std::max(sd_of_average(yhi), sd_of_average(shi));
        all = all && out.two_s_estimate <= out.delta && out.two_s_u <= out.delta &&
              out.two_s_lo <= out.delta && out.two_s_hi <= out.delta;
      }
      if (all) {
        r.converged = true;
        break;
      }
    }
    if (r.trials == 0) {
      throw InputError({model.source_path, 0, 0}, "max_trials is below one adaptive block of " +
                                                      std::to_string(B) + " trials");
    }
  }

  // Final results from all trials (§7.9.4 j).
  std::vector<McmOutput> keep = std::move(r.outputs);
  r.outputs.assign(m, {});
  for (std::size_t j = 0; j < m; ++j) {
    McmOutput& out = r.outputs[j];
    if (j < keep.size()) out = std::move(keep[j]);
    out.name = model.outputs[j].name;
    const MeanSd ms = mean_sd(values[j].data(), r.trials);
    out.estimate = ms.mean;
    out.u = ms.sd;
    if (!std::isfinite(out.estimate) || !std::isfinite(out.u)) {
      const ModelOutput& mo = model.outputs[j];
      throw InputError(mo.where, "outputs." + mo.name,
                       "a Monte-Carlo estimate " + shortest_text(out.estimate) + " and u(y) " +
                           shortest_text(out.u),
                       "an output whose values and spread a double can hold (they reach the "
                       "largest double, 1.8e308): rescale the output");
    }
    out.sorted = std::move(values[j]);
    sort_values(out.sorted);
    out.symmetric = symmetric_interval(out.sorted, p);
    out.shortest = shortest_interval(out.sorted, p);
    if (!r.adaptive) out.delta = numerical_tolerance(out.u, o.significant_digits);
  }
  r.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return r;
}

double quantile_standard_error(const std::vector<double>& sorted, double value) {
  const std::size_t m = sorted.size();
  if (m < 3) return 0.0;
  const std::size_t i = static_cast<std::size_t>(
      std::lower_bound(sorted.begin(), sorted.end(), value) - sorted.begin());
  const double a = std::clamp(static_cast<double>(i) / static_cast<double>(m), 0.0, 1.0);
  const std::size_t k = static_cast<std::size_t>(std::ceil(
      std::sqrt(static_cast<double>(m) * std::max(a * (1.0 - a), 1.0 / static_cast<double>(m)))));
  const std::size_t lo = i > k ? i - k : 0, hi = std::min(m - 1, i + k);
  // The ranks lo … hi span (hi − lo)/M of probability: scale to the ±k/M of the formula.
  const double span = static_cast<double>(hi - lo);
  return span > 0.0 ? (sorted[hi] - sorted[lo]) * static_cast<double>(k) / span : 0.0;
}

Validation validate_gum(double y, double U, double u_gum, const Interval& mcm, int ndig,
                        const std::vector<double>& sorted) {
  Validation v;
  v.delta = numerical_tolerance(u_gum, ndig);
  v.d_low = std::fabs(y - U - mcm.lo);
  v.d_high = std::fabs(y + U - mcm.hi);
  v.s_low = quantile_standard_error(sorted, mcm.lo);
  v.s_high = quantile_standard_error(sorted, mcm.hi);
  const bool fails =
      v.d_low - kValidationZ * v.s_low > v.delta || v.d_high - kValidationZ * v.s_high > v.delta;
  v.validated = !fails && v.d_low + kValidationZ * v.s_low <= v.delta &&
                v.d_high + kValidationZ * v.s_high <= v.delta;
  v.undecided = !fails && !v.validated;
  if (v.undecided) {
    // z s/√(M'/M) = |d − δ| at each end still within reach; the larger M' of the two.
    const double m = static_cast<double>(sorted.size());
    double needed = m;
    for (const auto& [d, s] : {std::pair{v.d_low, v.s_low}, std::pair{v.d_high, v.s_high}}) {
      const double gap = std::fabs(d - v.delta);
      if (std::fabs(d - v.delta) <= kValidationZ * s) {
        needed = gap > 0.0
                     ? std::max(needed, m * (kValidationZ * s / gap) * (kValidationZ * s / gap))
                     : std::numeric_limits<double>::infinity();
      }
    }
    v.trials_to_decide = needed;
  }
  return v;
}

}  // namespace gearmc::uncertainty
