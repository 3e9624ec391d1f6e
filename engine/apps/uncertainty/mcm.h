// The Monte Carlo method of JCGM 101:2008 ("Propagation of distributions using a Monte Carlo
// method"): M trials of the model with inputs drawn from their laws (§7.2–7.4), the estimate and
// standard uncertainty (§7.6), the probabilistically symmetric and the shortest coverage
// intervals (§7.7), the adaptive procedure (§7.9) and the validation of the GUM against it (§8).
// Trials run in parallel (oneTBB), and over the ranks of an MPI job, but every trial's draws come
// from its own counter-based stream (TrialStream, core/random_stream.h) and writes its own slot,
// and all statistics are taken afterwards in trial order, so results are bit-identical for any
// number of threads and ranks. Memory: 8 bytes per trial per output for the values, and 8 more per
// trial for the output being sorted while its intervals are found: at most 16 bytes per trial per
// output (kBytesPerTrialPerOutput).
#pragma once

#include <atomic>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "core/ranks.h"
#include "engine/apps/uncertainty/model.h"

namespace gearmc::uncertainty {

// [lo, hi] from the sorted values y_(1) <= … <= y_(M) (JCGM 101 §7.7.2): q = pM when that is an
// integer, else floor(pM + 1/2); the probabilistically symmetric interval is [y_(r), y_(r+q)]
// with r = (M − q)/2 when that is an integer, else floor((M − q + 1)/2); the shortest is the
// [y_(r), y_(r+q)] of least width (an O(M) scan; the first r on ties). Needs q < M.
// Sorts finite values ascending: a least-significant-digit radix sort on the IEEE-754 bit
// patterns (4 passes of 16 bits; negative numbers have all bits flipped, the others the sign
// bit, which maps their order to unsigned order; −0 sorts before +0). O(M); while it runs, the
// keys and a scratch buffer take 16 bytes per value (the values themselves are freed).
void sort_values(std::vector<double>& values);

struct Interval {
  double lo = 0.0, hi = 0.0;
};
Interval symmetric_interval(const std::vector<double>& sorted, double p);
Interval shortest_interval(const std::vector<double>& sorted, double p);
std::uint64_t coverage_count(std::uint64_t M, double p);  // q above

// The numerical tolerance of JCGM 101 §7.9.2: write u as c 10^l with c an integer of `ndig`
// digits; δ = 10^l / 2. E.g. u = 0.00035, ndig 2: c = 35, l = −5, δ = 5e-6.
double numerical_tolerance(double u, int ndig);

// Block size of the adaptive procedure, JCGM 101 §7.9.4 b): max(ceil(100/(1−p)), 10^4).
std::uint64_t adaptive_block_size(double p);

struct McmOptions {
  std::uint64_t seed = 1;
  std::optional<std::uint64_t> trials;  // nullopt: adaptive
  double coverage_probability = 0.95;
  int significant_digits = 2;
  std::uint64_t max_trials = 50'000'000;
  int threads = 0;  // 0: oneTBB's default
  const std::atomic<bool>* cancel = nullptr;
  // Called after each block (adaptive) or chunk (fixed M): trials done, trials planned (0 when
  // unknown: adaptive).
  std::function<void(std::uint64_t done, std::uint64_t planned)> progress;
  // The ranks of an MPI job (null: this process alone): each chunk of trials is split into
  // contiguous shares, and every rank receives every value, so the values, the adaptive decisions
  // (taken at block ends from all values so far) and the results are those of one process.
  const Ranks* ranks = nullptr;
};

// One block of the adaptive procedure: its results per output.
struct BlockValues {
  std::vector<double> estimate, u, lo, hi, short_lo, short_hi;
};

struct McmOutput {
  std::string name;
  double estimate = 0.0, u = 0.0;
  Interval symmetric, shortest;
  std::vector<double> sorted;  // all M values, ascending (kept for the report)
  // Adaptive: δ from u(y) at the stop (§7.9.4 h) and the last 2 s values (§7.9.4 g).
  double delta = 0.0;
  double two_s_estimate = 0.0, two_s_u = 0.0, two_s_lo = 0.0, two_s_hi = 0.0;
};

struct McmResult {
  std::uint64_t trials = 0;
  bool adaptive = false;
  std::uint64_t block_size = 0;
  int blocks = 0;
  bool converged = true;  // adaptive: the stop rule was met before max_trials
  bool cancelled = false;
  std::vector<McmOutput> outputs;
  std::vector<BlockValues> block_values;  // adaptive: one per block
  double wall_s = 0.0;
  int threads = 0;
  int ranks = 1;
};

// The smallest M whose coverage interval exists at probability p: q = coverage_count(M, p) with
// 1 ≤ q ≤ M − 1 (11 for p = 0.95, 2 for p = 0.5).
std::uint64_t smallest_trials(double p);

// Checks a planned fixed M against the coverage probability (1 ≤ q < M: smallest_trials) and
// the memory cap; throws InputError naming `where`.
void check_trials(std::uint64_t M, std::size_t outputs, double p, const InputLocation& where,
                  const std::string& key);

McmResult run_mcm(const UncertaintyModel& model, const McmOptions& options);

// The trials [first, first + count) into values[j][t] (the vectors must be that long;
// parallel, deterministic).
// Throws InputError when an output is not finite in some trial (naming the first such trial).
void run_trials(const UncertaintyModel& model, std::uint64_t seed, std::uint64_t first,
                std::uint64_t count, std::vector<std::vector<double>>& values);

// §8 validation of the GUM interval y ± U against an MCM interval [lo, hi] at tolerance δ, with
// the MCM's own error: each endpoint's Monte-Carlo standard error s from the order statistics
// around it (the values k = ⌈√(M a(1 − a))⌉ ranks either side, a its rank fraction: half their
// distance estimates √(a(1 − a)/M)/f, the standard error of a sample quantile; Serfling,
// "Approximation Theorems of Mathematical Statistics", 1980, §2.3.3). Decided at z = 3 standard
// errors: validated when d + 3s ≤ δ at both ends, NOT validated when d − 3s > δ at either,
// otherwise undecided, with about the M that would decide (s falls as 1/√M). Three, not the two
// of JCGM 101 §7.9's stop: s is itself estimated, and an adaptive run stops early when its blocks
// happen to agree; at two, JCGM 101 §9.2.3 (exactly within δ) was NOT validated for 3 of 60 seeds.
inline constexpr double kValidationZ = 3.0;
struct Validation {
  double delta = 0.0, d_low = 0.0, d_high = 0.0;
  double s_low = 0.0, s_high = 0.0;  // the MCM endpoints' standard errors
  bool validated = false;            // decided, validated
  bool undecided = false;            // d within 3s of δ at an end (and not NOT validated)
  double trials_to_decide = 0.0;     // when undecided: about the M that would decide
  const char* verdict() const {
    return undecided ? "undecided" : validated ? "validated" : "NOT validated";
  }
};
Validation validate_gum(double y, double U, double u_gum, const Interval& mcm, int ndig,
                        const std::vector<double>& sorted);
// The Monte-Carlo standard error of the sample quantile `value` of the ascending `sorted` values
// (see Validation).
double quantile_standard_error(const std::vector<double>& sorted, double value);

}  // namespace gearmc::uncertainty
