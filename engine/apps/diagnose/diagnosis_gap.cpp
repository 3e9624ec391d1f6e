// The gap before and after, its null simulation, the spectrum, the cluster-aware evidence and
// the verdict of a diagnosis (steps 5, 6 and 8 of diagnosis.h; see diagnosis_stages.h).
#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <map>
#include <numbers>
#include <sstream>
#include <tuple>
#include <type_traits>

#include <tbb/parallel_for.h>

#include "core/special_functions.h"
#include "engine/apps/diagnose/cluster_tests.h"
#include "engine/apps/diagnose/diagnosis_stages.h"
#include "engine/apps/diagnose/readings_check.h"
#include "engine/statistics/distribution_fit.h"

namespace gearmc::diagnosis_stages {
namespace {

// Stream sub-index of the gap's null simulation (the selection steps use 0, 1, 2, …).
constexpr std::uint32_t kGapNullSubIndex = 1000;
// Stream sub-indices of the cluster-aware evidence (the point-law stage uses 2000).
constexpr std::uint32_t kClusterSubIndex = 3000;
constexpr int kBootstrapReplicates = 999;  // (R + 1) · 0.025 an integer (cluster_tests.h)

}  // namespace

HeldOutSplit held_out_split(const std::vector<ResidualPoint>& points, int columns,
                            bool within_flanks) {
  // Candidate splits, coarsest first: each gives a group key per point; the groups, in sorted
  // order, alternate between the two folds.
  struct Candidate {
    const char* name;
    std::function<std::tuple<int, int, int>(const ResidualPoint&)> key;
  };
  const std::vector<Candidate> candidates = {
      {"alternating_teeth",
       [](const ResidualPoint& p) {
         return std::tuple{p.gear, p.tooth, 0};
       }},
      {"flanks",
       [](const ResidualPoint& p) {
         return std::tuple{p.side == FlankSide::kRight ? 1 : 0, 0, 0};
       }},
      {"alternating_sections",
       [](const ResidualPoint& p) {
         return std::tuple{p.j, 0, 0};
       }},
      {"alternating_profile_points",
       [](const ResidualPoint& p) {
         return std::tuple{p.i, 0, 0};
       }},
  };
  HeldOutSplit out;
  // Within flanks: profile points first (each fold keeps every section, so a flank's helix terms
  // stay estimable in both folds), then sections.
  const std::vector<Candidate> inside = {candidates[3], candidates[2]};
  for (const Candidate& c : within_flanks ? inside : candidates) {
    std::map<std::tuple<int, int, int>, int> groups;
    for (const ResidualPoint& p : points) groups.emplace(c.key(p), 0);
    if (groups.size() < 2) continue;
    int index = 0;
    for (auto& [key, fold] : groups) fold = index++ % 2;
    std::vector<int> fold(points.size());
    int counts[2] = {0, 0};
    for (std::size_t k = 0; k < points.size(); ++k) {
      fold[k] = groups.at(c.key(points[k]));
      ++counts[fold[k]];
    }
    // Each fold must be able to fit the effects on its own (more points than columns).
    if (counts[0] <= columns || counts[1] <= columns) continue;
    out.name = c.name;
    out.fold = std::move(fold);
    return out;
  }
  out.name = "none";
  out.why_none =
      (within_flanks ? std::string("the readings cannot be split into two halves within every "
                                   "flank (by face sections or profile points: the part's "
                                   "deviations are fitted per flank) each with more points than "
                                   "the ")
                     : std::string("the readings cannot be split into two halves (by teeth, "
                                   "flanks, face sections or profile points) each with more "
                                   "points than the ")) +
      std::to_string(columns) + " fitted parameters";
  return out;
}

// The periodic family of structure_axis: for each machine axis a whose normals have a part on it
// (max |n_a| ≥ 0.1) and each period λ of the log grid 2 mm · 1.005^k up to the span of the
// stylus centres' c_a, the F test of the two columns n_a cos(2π c_a/λ), n_a sin(2π c_a/λ) on the
// residuals (no intercept: the gear's axes and the library carry constants). The smallest p, with
// axes_tested the number of (axis, period) pairs tried.
Diagnosis::StructureAxis periodic_machine_axis(const std::vector<ResidualPoint>& points,
                                               const std::vector<double>& residual_um) {
  Diagnosis::StructureAxis best;
  const std::size_t n = points.size();
  if (n < 8) return best;
  double ss = 0.0;
  for (double r : residual_um) ss += r * r;
  if (!(ss > 0.0)) return best;
  int tried = 0;
  double best_f = -1.0;  // by F, not p: p underflows to 0 over a range of periods near the truth
  const char* names[3] = {"x_position", "y_position", "z_position"};
  for (int a = 0; a < 3; ++a) {
    double lo = std::numeric_limits<double>::infinity(), hi = -lo, largest = 0.0;
    std::vector<double> c(n), w(n);
    for (std::size_t k = 0; k < n; ++k) {
      const PointContext& p = points[k].context;
      c[k] = p.p[a] + p.stylus_radius_mm * p.n[a];
      w[k] = p.n[a];
      lo = std::min(lo, c[k]);
      hi = std::max(hi, c[k]);
      largest = std::max(largest, std::abs(w[k]));
    }
    if (largest < 0.1 || !(hi - lo > 4.0)) continue;
    for (double period = 2.0; period <= hi - lo; period *= 1.005) {
      ++tried;
      // Normal equations of the two columns (2 × 2), solved in closed form.
      double cc = 0.0, cs = 0.0, s2 = 0.0, cr = 0.0, sr = 0.0;
      for (std::size_t k = 0; k < n; ++k) {
        const double phase = 2.0 * std::numbers::pi * c[k] / period;
        const double u = w[k] * std::cos(phase), v = w[k] * std::sin(phase);
        cc += u * u;
        cs += u * v;
        s2 += v * v;
        cr += u * residual_um[k];
        sr += v * residual_um[k];
      }
      const double det = cc * s2 - cs * cs;
      if (!(det > 1e-12 * cc * s2)) continue;
      const double ca = (s2 * cr - cs * sr) / det, sa = (cc * sr - cs * cr) / det;
      const double reduction = ca * cr + sa * sr;
      const double rest = std::max(ss - reduction, 1e-300);
      const double f = (reduction / 2.0) / (rest / (static_cast<double>(n) - 2.0));
      if (f > best_f) {
        best_f = f;
        best.axis = names[a];
        best.p_value =
            f_distribution_upper_tail(std::max(f, 0.0), 2.0, static_cast<double>(n) - 2.0);
        best.variance_share = reduction / ss;
        best.period_mm = period;
        best.amplitude_um = std::hypot(ca, sa);
      }
    }
  }
  best.axes_tested = tried;
  return best;
}

Diagnosis::StructureAxis structure_axis(const std::vector<ResidualPoint>& points,
                                        const std::vector<double>& residual_um) {
  struct Axis {
    const char* name;
    std::function<long(const ResidualPoint&, std::size_t)> group;
  };
  const std::size_t n = points.size();
  int first_order = 0, last_order = 0;
  for (std::size_t k = 0; k < n; ++k) {
    first_order = k == 0 ? points[k].order : std::min(first_order, points[k].order);
    last_order = k == 0 ? points[k].order : std::max(last_order, points[k].order);
  }
  const double order_span = std::max(1, last_order - first_order + 1);
  const std::vector<Axis> axes = {
      {"roll_length", [](const ResidualPoint& p, std::size_t) { return long{p.i}; }},
      {"face_position", [](const ResidualPoint& p, std::size_t) { return long{p.j}; }},
      {"tooth",
       [](const ResidualPoint& p, std::size_t) { return long{p.gear} * 100000L + p.tooth; }},
      {"flank",
       [](const ResidualPoint& p, std::size_t) { return p.side == FlankSide::kRight ? 1L : 0L; }},
      {"approach_azimuth",
       [](const ResidualPoint& p, std::size_t) {
         double a = std::fmod(p.context.azimuth_rad, 2.0 * std::numbers::pi);
         if (a < 0.0) a += 2.0 * std::numbers::pi;
         return static_cast<long>(std::floor(a / (2.0 * std::numbers::pi) * 24.0));
       }},
      {"probing_order",
       [&](const ResidualPoint& p, std::size_t) {
         return static_cast<long>(std::floor(20.0 * (p.order - first_order) / order_span));
       }},
  };
  Diagnosis::StructureAxis best;
  int tested = 0;
  double total_mean = 0.0;
  for (double r : residual_um) total_mean += r;
  total_mean /= static_cast<double>(std::max<std::size_t>(1, n));
  double total_ss = 0.0;
  for (double r : residual_um) total_ss += (r - total_mean) * (r - total_mean);
  for (const Axis& axis : axes) {
    std::map<long, std::pair<double, int>> groups;  // sum, count
    for (std::size_t k = 0; k < n; ++k) {
      auto& g = groups[axis.group(points[k], k)];
      g.first += residual_um[k];
      ++g.second;
    }
    const double g = static_cast<double>(groups.size());
    if (groups.size() < 2 || n <= groups.size() || !(total_ss > 0.0)) continue;
    double between = 0.0;
    for (const auto& [key, sc] : groups) {
      const double mean = sc.first / sc.second;
      between += sc.second * (mean - total_mean) * (mean - total_mean);
    }
    const double within = std::max(total_ss - between, 1e-300);
    const double f = (between / (g - 1.0)) / (within / (static_cast<double>(n) - g));
    const double p = f_distribution_upper_tail(f, g - 1.0, static_cast<double>(n) - g);
    ++tested;
    // Ties (p underflowing to 0 on several axes) go to the larger share of the variance.
    if (best.axis.empty() || p < best.p_value ||
        (p == best.p_value && between / total_ss > best.variance_share)) {
      best.axis = axis.name;
      best.p_value = p;
      best.variance_share = between / total_ss;
    }
  }
  best.axes_tested = tested;
  // The second family: a periodic error along a machine axis (Diagnosis::StructureAxis). Both
  // families at α/2: the winner is the one of smaller p · (family size) · 2, reported as
  // p_value · axes_tested with axes_tested = 2 × its family's size.
  Diagnosis::StructureAxis periodic = periodic_machine_axis(points, residual_um);
  const double periodic_p = periodic.p_value * periodic.axes_tested;
  const double gear_p = best.p_value * std::max(1, tested);
  if (best.axis.empty() ||
      (!periodic.axis.empty() &&
       (periodic_p < gear_p ||
        (periodic_p == gear_p && periodic.variance_share > best.variance_share)))) {
    if (!periodic.axis.empty()) {
      periodic.axes_tested *= 2;
      return periodic;
    }
  }
  best.axes_tested = 2 * tested;
  return best;
}

std::vector<double> to_vector(const Eigen::VectorXd& v) {
  return std::vector<double>(v.data(), v.data() + v.size());
}

// Gap statistics of residual vector r (dof = points − fitted parameters) against the centred
// residual law `law` (χ² with its variance, KS against its distribution function).
GapStatistics gap_statistics(const Eigen::VectorXd& r, int dof, const ResidualLaw& law) {
  GapStatistics g;
  const double n = static_cast<double>(r.size());
  const double ss = r.squaredNorm();
  const double variance = law.variance_um2();
  g.rms_um = std::sqrt(ss / n);
  g.dof = dof;
  if (dof > 0 && variance > 0.0) {
    g.chi2_dof = ss / (dof * variance);
    g.excess_rms_um = std::sqrt(std::max(0.0, ss / dof - variance));
    g.ks = ks_distance(to_vector(r), law);
  }
  return g;
}

// The verdict's gap test (GapStatistics::combined_p): the χ² test counts only when the excess
// RMS √max(0, Σr²/dof − v) reaches the practical size — as a gate on χ²/dof = Σr²/(dof v):
// χ²/dof ≥ 1 + practical²/v — and the KS test only off the numerical floor.
struct GapFamily {
  double chi2_gate = -std::numeric_limits<double>::infinity();
  bool shape_test = true;
};
GapFamily gap_family(const State& state, const ResidualLaw& law) {
  GapFamily f;
  const double practical = state.options.selection.min_effect_rms_fraction * state.noise.sigma_um;
  const double v = law.variance_um2();
  if (practical > 0.0 && v > 0.0) f.chi2_gate = 1.0 + practical * practical / v;
  f.shape_test = !state.noise.at_numerical_floor;
  return f;
}

// The combined p-value of the gap test on g, from the replicates' χ²/dof and KS values (K ≥ 1,
// min-P) or, with none, from g's table p-values (Bonferroni over the family's tests).
double combined_gap_p(const GapStatistics& g, const GapFamily& f, const std::vector<double>& chi2,
                      const std::vector<double>& ks) {
  if (!chi2.empty()) {
    std::vector<ResampledTest> family = {{g.chi2_dof, chi2, f.chi2_gate}};
    if (f.shape_test) family.push_back({g.ks, ks});
    return min_p_combined_p_value(family);
  }
  const double p_chi2 = g.chi2_dof >= f.chi2_gate ? g.chi2_p : 1.0;
  const double p_ks = f.shape_test ? g.ks_p : 1.0;
  if (std::isnan(g.chi2_p) && std::isnan(p_ks)) return kNotAvailable;
  const double smallest =
      std::min(std::isnan(p_chi2) ? 1.0 : p_chi2, std::isnan(p_ks) ? 1.0 : p_ks);
  return std::min(1.0, (f.shape_test ? 2.0 : 1.0) * smallest);
}

// The centred law of a residual under the noise floor: the model's per-point law, or a Gaussian
// of the floor's σ when the floor carries none (given, or estimated from the residuals).
ResidualLaw floor_law(const NoiseFloor& noise) {
  if (noise.law.variance_um2() > 0.0) return residual_law(noise.law);
  ResidualLaw law;
  law.sigma_um = noise.sigma_um;
  return law;
}

void measure_gap(const State& state, Diagnosis& out) {
  const int rows = state.rows;
  const Eigen::VectorXd& r = state.r;
  const Eigen::MatrixXd& x_after = state.columns_after();
  const double mean_after = state.mean_after;
  // 5. Gap before / after and held-out check.
  out.residual_before_um = to_vector(r);
  out.residual_after_um = to_vector(state.r_after);
  out.gap_before = gap_statistics(r, rows - state.p_base, state.law_before);
  out.gap_after = gap_statistics(state.r_after, rows - state.p_after, state.law_after);
  if (out.effects.empty()) {
    out.held_out_rms_um = out.gap_before.rms_um;  // nothing fitted: nothing to hold out
    out.held_out_split = "nothing_fitted";
    return;
  }
  const HeldOutSplit split = held_out_split(
      state.residuals.points, static_cast<int>(x_after.cols()), state.part.columns() > 0);
  out.held_out_split = split.name;
  if (split.fold.empty()) {
    out.held_out_rms_um = kNotAvailable;
    out.notes.push_back("no held-out check: " + split.why_none);
    return;
  }
  double ss = 0.0, ss_without = 0.0;
  // Fit on one fold, evaluate on the other, and the other way round; the same without the
  // effects (a production gear's own deviations alone, or nothing).
  for (int half = 0; half < 2; ++half) {
    std::vector<int> train, test;
    for (int k = 0; k < rows; ++k) (split.fold[k] == half ? train : test).push_back(k);
    Eigen::MatrixXd xt(static_cast<int>(train.size()), x_after.cols());
    Eigen::VectorXd yt(static_cast<int>(train.size()));
    for (std::size_t k = 0; k < train.size(); ++k) {
      xt.row(static_cast<int>(k)) = x_after.row(train[k]);
      yt[static_cast<int>(k)] = r[train[k]] - mean_after;
    }
    const LeastSquaresFit half_fit = least_squares(xt, yt);
    for (int k : test) {
      const double e = r[k] - mean_after - x_after.row(k).dot(half_fit.beta);
      ss += e * e;
    }
    const Eigen::MatrixXd& base = state.base_x;
    if (state.p_base > 0) {
      Eigen::MatrixXd bt(static_cast<int>(train.size()), base.cols());
      Eigen::VectorXd ut(static_cast<int>(train.size()));
      for (std::size_t k = 0; k < train.size(); ++k) {
        bt.row(static_cast<int>(k)) = base.row(train[k]);
        ut[static_cast<int>(k)] = state.r_measured[train[k]];
      }
      const LeastSquaresFit base_fit = least_squares(bt, ut);
      for (int k : test) {
        const double e = state.r_measured[k] - base.row(k).dot(base_fit.beta);
        ss_without += e * e;
      }
    } else {
      for (int k : test) ss_without += r[k] * r[k];
    }
  }
  out.held_out_rms_um = std::sqrt(ss / rows);
  out.held_out_without_rms_um = std::sqrt(ss_without / rows);
}

namespace {

// The gap's null subsample for n > 2 × null_rows (DiagnoseOptions::null_rows): in scan order
// (gear, tooth, flank, section, roll index — scan_triplets' order), runs of kNullRunLength
// consecutive points, every k-th run, k = ⌈n / null_rows⌉; returned in the readings' order. Runs
// keep the scans' second differences (a σ re-estimated from them) and reach every part of the
// plan.
constexpr int kNullRunLength = 64;
std::vector<int> null_subsample(const std::vector<ResidualPoint>& points, int null_rows) {
  const int n = static_cast<int>(points.size());
  std::vector<int> order(static_cast<std::size_t>(n));
  for (int k = 0; k < n; ++k) order[static_cast<std::size_t>(k)] = k;
  auto key = [&](int k) {
    const ResidualPoint& p = points[static_cast<std::size_t>(k)];
    return std::tuple{p.gear, p.tooth, p.side == FlankSide::kRight ? 1 : 0, p.j, p.i};
  };
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return key(a) < key(b); });
  const int stride = (n + null_rows - 1) / null_rows;
  std::vector<int> rows;
  for (int start = 0, run = 0; start < n; start += kNullRunLength, ++run) {
    if (run % stride != 0) continue;
    for (int a = start; a < std::min(n, start + kNullRunLength); ++a) {
      rows.push_back(order[static_cast<std::size_t>(a)]);
    }
  }
  std::sort(rows.begin(), rows.end());
  return rows;
}

}  // namespace

void simulate_null(const State& state, Diagnosis& out) {
  const Residuals& residuals = state.residuals;
  const int rows = state.rows;
  const Eigen::VectorXd& r = state.r;
  const Eigen::VectorXd& r_after_c = state.r_after;
  const ResidualLaw& law_before = state.law_before;
  const ResidualLaw& law_after = state.law_after;
  const Eigen::MatrixXd& x_after = state.columns_after();
  const int p_after = state.p_after;
  const NoiseFloor& noise = state.noise;
  const DiagnoseOptions& options = state.options;
  const SelectionOptions& so = options.selection;
  const PointLawStage& stage = out.point_law;
  const std::vector<double>& azimuths = state.azimuths;
  // 5–6. Null simulation of the gap statistics and the spectrum.
  const HarmonicSpectrum spectrum(azimuths, options.spectrum_max_order);
  out.spectrum_before_um = spectrum.amplitudes(r);
  out.spectrum_after_um = spectrum.amplitudes(r_after_c);
  const Eigen::MatrixXd q_after = orthonormal_basis(x_after).q;
  const bool reestimate = noise.source == NoiseFloorSource::kResidualSecondDifferences ||
                          noise.source == NoiseFloorSource::kResidualMad;
  const int replicates = out.null_replicates;
  // The rows the χ² and KS statistics are simulated on: all, or the subsample (see
  // DiagnoseOptions::null_rows), with its own design and its statistics rescaled to n below.
  // (A production gear's part columns, state.part.q, are projected off whole: no subsample.)
  const bool subsample =
      replicates > 0 && options.null_rows > 0 && rows > 2 * options.null_rows && state.p_base == 0;
  const Eigen::MatrixXd& q_base = state.base_q;
  const std::vector<int> sub_rows =
      subsample ? null_subsample(residuals.points, options.null_rows) : std::vector<int>{};
  const int m = subsample ? static_cast<int>(sub_rows.size()) : rows;
  out.null_rows = m;
  Eigen::MatrixXd q_sim;
  std::vector<std::array<int, 3>> triplets;
  if (subsample) {
    Eigen::MatrixXd x_sub(m, x_after.cols());
    std::vector<ResidualPoint> sub_points;
    sub_points.reserve(static_cast<std::size_t>(m));
    for (int k = 0; k < m; ++k) {
      const int row = sub_rows[static_cast<std::size_t>(k)];
      x_sub.row(k) = x_after.row(row);
      sub_points.push_back(residuals.points[static_cast<std::size_t>(row)]);
    }
    q_sim = orthonormal_basis(x_sub).q;
    if (reestimate) triplets = scan_triplets(sub_points);
  } else {
    q_sim = q_after;
    if (reestimate) triplets = scan_triplets(residuals.points);
  }
  // Degrees of freedom of the simulated rows, and the rescaling to n (subsample only):
  // (χ²/dof − 1)·√dof and √n·KS have laws that do not depend on n to first order (central limit
  // theorem; Kolmogorov's limit law).
  const int dof_sim_after = m - p_after + static_cast<int>(q_after.cols() - q_sim.cols());
  const double chi2_scale_before = std::sqrt(static_cast<double>(m) / rows);
  const double chi2_scale_after =
      rows - p_after > 0 && dof_sim_after > 0
          ? std::sqrt(static_cast<double>(dof_sim_after) / (rows - p_after))
          : 1.0;
  const double ks_scale = std::sqrt(static_cast<double>(m) / rows);
  std::vector<double> chi2_before(replicates), chi2_after(replicates), ks_before(replicates),
      ks_after(replicates);
  const int orders = options.spectrum_max_order + 1;
  std::vector<std::vector<double>> amp_before(orders, std::vector<double>(replicates)),
      amp_after(orders, std::vector<double>(replicates));
  // With no spread at all (σ = 0) the null is simulated at unit σ and the bands scaled to 0.
  const bool unit = !(law_before.variance_um2() > 0.0);
  ResidualLaw sim_before = law_before, sim_after = law_after;
  if (unit) sim_before = sim_after = ResidualLaw{1.0, 0.0, 0.0};
  const double band_scale = unit ? 0.0 : 1.0;
  // With the subsample the spectrum's coefficients are drawn from their exact covariance
  // (normal: each is a weighted sum of n independent residuals).
  Eigen::MatrixXd root_before, root_after;
  if (subsample) {
    root_before =
        gram_root(spectrum.unit_covariance(Eigen::MatrixXd(rows, 0)) * sim_before.variance_um2());
    root_after = gram_root(spectrum.unit_covariance(q_after) *
                           (stage.chosen > 0 ? sim_after : sim_before).variance_um2());
  }
  // The replicates in parallel: replicate k draws from its own counter-based streams and writes
  // only its own slots, so the result is the same for any number of threads.
  tbb::parallel_for(0, replicates, [&](int k) {
    Eigen::VectorXd eps(m), eps_law_after(m);
    RandomStream rng(so.seed, static_cast<std::uint32_t>(k), kDiagnoseNullStream, kGapNullSubIndex);
    for (int i = 0; i < m; ++i) eps[i] = sim_before.draw(rng);
    Eigen::VectorXd eps_drawn;
    if (state.p_base > 0) {  // before = after the part's fit alone
      eps_drawn = eps;
      eps -= q_base * (q_base.transpose() * eps);
    }
    ResidualLaw l_before = sim_before, l_after = sim_after;
    if (reestimate) {
      const std::vector<double> e = to_vector(eps);
      const double estimate = noise.source == NoiseFloorSource::kResidualMad
                                  ? mad_sigma(e)
                                  : robust_noise_sigma(triplets, e);
      // As the data's floor: never below the numerical floor.
      l_before.sigma_um = l_after.sigma_um = std::max(estimate, noise.numerical_um);
    }
    if (stage.chosen > 0) {  // the fitted law: its own draws
      RandomStream rng_after(so.seed, static_cast<std::uint32_t>(k), kDiagnoseNullStream,
                             kGapNullSubIndex + 1);
      for (int i = 0; i < m; ++i) eps_law_after[i] = sim_after.draw(rng_after);
    } else {
      eps_law_after = state.p_base > 0 ? eps_drawn : eps;
    }
    const Eigen::VectorXd eps_after = eps_law_after - q_sim * (q_sim.transpose() * eps_law_after);
    const GapStatistics gb = gap_statistics(eps, m - state.p_base, l_before);
    const GapStatistics ga = gap_statistics(eps_after, dof_sim_after, l_after);
    chi2_before[k] = subsample ? 1.0 + (gb.chi2_dof - 1.0) * chi2_scale_before : gb.chi2_dof;
    chi2_after[k] = subsample ? 1.0 + (ga.chi2_dof - 1.0) * chi2_scale_after : ga.chi2_dof;
    ks_before[k] = subsample ? gb.ks * ks_scale : gb.ks;
    ks_after[k] = subsample ? ga.ks * ks_scale : ga.ks;
    std::vector<double> sb, sa;
    if (subsample) {
      RandomStream rng_spectrum(so.seed, static_cast<std::uint32_t>(k), kDiagnoseNullStream,
                                kGapNullSubIndex + 2);
      Eigen::VectorXd w(root_before.cols());
      for (int i = 0; i < w.size(); ++i) w[i] = rng_spectrum.normal();
      sb = spectrum.amplitudes_of(root_before * w);
      w.resize(root_after.cols());
      for (int i = 0; i < w.size(); ++i) w[i] = rng_spectrum.normal();
      sa = spectrum.amplitudes_of(root_after * w);
    } else {
      sb = spectrum.amplitudes(eps);
      sa = spectrum.amplitudes(eps_after);
    }
    for (int o = 0; o < orders; ++o) {
      amp_before[o][k] = sb[o] * band_scale;
      amp_after[o][k] = sa[o] * band_scale;
    }
  });
  if (subsample) {
    std::ostringstream text;
    const int stride = (rows + options.null_rows - 1) / options.null_rows;
    const int last_two = stride % 100, last = stride % 10;
    const char* suffix = last_two >= 11 && last_two <= 13 ? "th"
                         : last == 1                      ? "st"
                         : last == 2                      ? "nd"
                         : last == 3                      ? "rd"
                                                          : "th";
    text << "the gap's null law was simulated on " << m << " of the " << rows << " readings (every "
         << stride << suffix << " run of " << kNullRunLength
         << " points along the scans) and rescaled to all of them: χ²/dof about 1 by √dof, the "
            "KS distance by √n; the spectrum's null bands from the exact covariance of its "
            "harmonic fit; the cluster energy test on the same readings";
    if (stage.ran) text << "; the white-variance test by its normal approximation";
    out.notes.push_back(text.str());
  }
  if (out.null_replicates > 0) {
    out.gap_before.chi2_p = empirical_p_value(out.gap_before.chi2_dof, chi2_before);
    out.gap_before.ks_p = empirical_p_value(out.gap_before.ks, ks_before);
    out.gap_after.chi2_p = empirical_p_value(out.gap_after.chi2_dof, chi2_after);
    out.gap_after.ks_p = empirical_p_value(out.gap_after.ks, ks_after);
    for (int o = 0; o < orders; ++o) {
      out.spectrum_null95_before_um.push_back(sample_quantile(amp_before[o], 0.95));
      out.spectrum_null95_after_um.push_back(sample_quantile(amp_after[o], 0.95));
    }
  } else {  // no null simulation: the χ² law of Σr²/σ² and Kolmogorov's asymptotic law
    for (GapStatistics* g : {&out.gap_before, &out.gap_after}) {
      g->chi2_p = regularized_gamma_q(0.5 * g->dof, 0.5 * g->dof * g->chi2_dof);
      g->ks_p = ks_p_value(g->ks, rows);
    }
  }
  out.gap_before.combined_p =
      combined_gap_p(out.gap_before, gap_family(state, law_before), chi2_before, ks_before);
  out.gap_after.combined_p =
      combined_gap_p(out.gap_after, gap_family(state, law_after), chi2_after, ks_after);

  // 5b. Cluster-aware evidence: flanks for the paired energy test, teeth for the bootstrap.
  if (out.null_replicates > 0 && !unit) {
    std::map<std::tuple<int, int, int>, int> flank_ids;
    std::map<std::pair<int, int>, int> tooth_ids;
    std::vector<int> flank(rows), tooth(rows);
    for (int k = 0; k < rows; ++k) {
      const ResidualPoint& pt = residuals.points[k];
      const int side = pt.side == FlankSide::kRight ? 1 : 0;
      flank[k] =
          flank_ids.try_emplace({pt.gear, pt.tooth, side}, static_cast<int>(flank_ids.size()))
              .first->second;
      tooth[k] = tooth_ids.try_emplace({pt.gear, pt.tooth}, static_cast<int>(tooth_ids.size()))
                     .first->second;
    }
    RandomStream rng(so.seed, 0, kDiagnoseNullStream, kClusterSubIndex);
    Eigen::VectorXd y_before(rows), y_after(rows);
    for (int i = 0; i < rows; ++i) y_before[i] = sim_before.draw(rng);
    for (int i = 0; i < rows; ++i) y_after[i] = sim_after.draw(rng);
    if (state.p_base > 0) y_before -= q_base * (q_base.transpose() * y_before);
    y_after -= q_after * (q_after.transpose() * y_after);
    const std::vector<double> before = to_vector(r), after = to_vector(r_after_c);
    const std::vector<double> yb = to_vector(y_before), ya = to_vector(y_after);
    int sub = kClusterSubIndex + 1;
    for (auto [g, x, y] :
         {std::tuple{&out.gap_before, &before, &yb}, std::tuple{&out.gap_after, &after, &ya}}) {
      // With the subsample (DiagnoseOptions::null_rows) the energy test takes its readings only:
      // each replicate walks every value, so its cost grows with n.
      auto rows_of = [&](const std::vector<auto>& all) {
        std::remove_cvref_t<decltype(all)> part;
        part.reserve(sub_rows.size());
        for (int k : sub_rows) part.push_back(all[static_cast<std::size_t>(k)]);
        return part;
      };
      const PermutationTest test =
          subsample ? cluster_swap_energy_test(rows_of(*x), rows_of(*y), rows_of(flank),
                                               out.null_replicates, so.seed, sub++)
                    : cluster_swap_energy_test(*x, *y, flank, out.null_replicates, so.seed, sub++);
      g->energy_um = test.statistic;
      g->energy_p = test.p_value;
      const BootstrapInterval ci =
          cluster_bootstrap_rms(*x, tooth, kBootstrapReplicates, so.seed, sub++);
      g->rms_lo_um = ci.lo;
      g->rms_hi_um = ci.hi;
    }
  }
}

// With an empirical term chosen on the residuals after the library: its coefficients fitted jointly
// with the library's columns, and the library selected and fitted again on the readings less the
// term (empirical_term.h). Updates the term's values, standard errors and the RMS it leaves, and
// sets Diagnosis::effects_with_empirical.
void refit_with_empirical(const State& state, Diagnosis& out) {
  EmpiricalTerm& e = out.empirical;
  const int rows = state.rows;
  const Eigen::MatrixXd b = empirical_columns(state.residuals.points, e);
  Eigen::MatrixXd joint(rows, state.columns_after().cols() + b.cols());
  joint << state.columns_after(), b;
  const Eigen::VectorXd y =
      state.r - Eigen::VectorXd::Constant(rows, state.mean_after);  // a point law's mean taken out
  const LeastSquaresFit fit = least_squares(joint, y);
  const int first = static_cast<int>(state.columns_after().cols());
  const double sigma2 = rows - fit.rank > 0 ? fit.rss / (rows - fit.rank) : 0.0;
  Eigen::VectorXd term = Eigen::VectorXd::Zero(b.cols());
  for (int c = 0; c < b.cols(); ++c) {
    const int at = first + c;
    if (!fit.estimable[at]) continue;
    term[c] = fit.beta[at];
    e.terms[static_cast<std::size_t>(c)].value_um = fit.beta[at];
    e.terms[static_cast<std::size_t>(c)].std_error_um =
        std::sqrt(sigma2 * fit.cov_unscaled(at, at));
  }
  const Eigen::VectorXd shape = b * term;
  e.fitted_rms_um = std::sqrt(shape.squaredNorm() / rows);
  Residuals less = state.residuals;
  for (int k = 0; k < rows; ++k) less.points[k].residual_um -= shape[k];
  DiagnoseOptions options = state.options;
  options.fit_empirical = false;
  const Diagnosis library = diagnose_residuals(less, state.noise, options);
  out.effects_with_empirical = library.effects;
  e.rms_after_um = library.gap_after.rms_um;
  e.excess_rms_after_um = library.gap_after.excess_rms_um;
}

namespace {

// The shape of the residuals' law against the model's (Diagnosis::LawShape): sample excess
// kurtosis m₄/m₂² − 3 (standard error √(24/n) for a normal sample: Kendall & Stuart, The
// Advanced Theory of Statistics, vol. 1) against the model law's κ₄/v², κ₄ = −w⁴/120 for its
// uniform part of width w (a Gaussian has none).
Diagnosis::LawShape law_shape(const Eigen::VectorXd& r, const ResidualLaw& law, double ks_p) {
  Diagnosis::LawShape s;
  s.differs = true;
  s.ks_p = ks_p;
  const double n = static_cast<double>(r.size());
  const double mean = r.mean();
  double m2 = 0.0, m4 = 0.0;
  for (int k = 0; k < r.size(); ++k) {
    const double d = r[k] - mean;
    m2 += d * d;
    m4 += d * d * d * d;
  }
  m2 /= n;
  m4 /= n;
  const double v = law.variance_um2();
  const double w = law.width_um;
  s.excess_kurtosis = m2 > 0.0 ? m4 / (m2 * m2) - 3.0 : kNotAvailable;
  s.model_excess_kurtosis = v > 0.0 ? -std::pow(w, 4) / 120.0 / (v * v) : 0.0;
  s.kurtosis_std_error = std::sqrt(24.0 / n);
  const double z = (s.excess_kurtosis - s.model_excess_kurtosis) / s.kurtosis_std_error;
  s.shape = z > 3.0 ? "heavier tails" : z < -3.0 ? "lighter tails" : "another shape";
  return s;
}

}  // namespace

void make_verdict(const State& state, Diagnosis& out) {
  const int rows = state.rows;
  const Eigen::VectorXd& r = state.r;
  const Eigen::VectorXd& r_after_c = state.r_after;
  const ResidualLaw& law_before = state.law_before;
  const ResidualLaw& law_after = state.law_after;
  const NoiseFloor& noise = state.noise;
  const DiagnoseOptions& options = state.options;
  const SelectionOptions& so = options.selection;
  const PointLawStage& stage = out.point_law;
  const std::vector<int>& selected = out.selection.selected;
  // 8. The verdict. The gap test is one test of level α (combined_p: χ² at the practical size,
  // KS off the numerical floor — there the floor bounds an exact prediction's rounding, it is not
  // a law of the residuals, so only residuals beyond it make a gap, not their shape).
  auto gap_rejects = [&](const GapStatistics& g) { return g.combined_p < so.alpha; };
  // Structure only on its own evidence (Diagnosis::StructureAxis): the χ² part at the practical
  // size, or an axis significant after Bonferroni over the axes; else the shape of the law.
  const bool after_rejects = gap_rejects(out.gap_after);
  Diagnosis::StructureAxis along;
  if (after_rejects) along = structure_axis(state.residuals.points, to_vector(r_after_c));
  const GapStatistics& ga = out.gap_after;
  const bool excess_variance =
      ga.chi2_p < so.alpha && ga.chi2_dof >= gap_family(state, law_after).chi2_gate;
  // … and the axis's group means move the readings by at least the practical size (readings far
  // less noisy than the model's law have significant axes in their rounding).
  const double practical = so.min_effect_rms_fraction * noise.sigma_um;
  const bool along_axis =
      !along.axis.empty() && along.p_value * std::max(1, along.axes_tested) < so.alpha &&
      std::sqrt(along.variance_share * r_after_c.squaredNorm() / std::max(1, rows)) >= practical;
  out.unexplained_structure = after_rejects && (excess_variance || along_axis);
  if (after_rejects && !out.unexplained_structure) {
    out.law_shape = law_shape(r_after_c, law_after, ga.ks_p);
    out.law_shape.spread_ratio = std::sqrt(ga.chi2_dof);
  }
  out.gap_detected = !selected.empty() || stage.chosen > 0 ||
                     (gap_rejects(out.gap_before) && !out.law_shape.differs);
  const double v0 = law_before.variance_um2();
  const double excess = r.squaredNorm() - (rows - state.p_base) * v0;
  const double explained = stage.chosen > 0 ? r.squaredNorm() - r_after_c.squaredNorm() +
                                                  rows * (law_after.variance_um2() - v0)
                           : state.per_gear_fit ? r.squaredNorm() - r_after_c.squaredNorm()
                                                : r.squaredNorm() - state.fit.rss;
  if (excess > 0.0) {
    out.explained_fraction = std::clamp(explained / excess, 0.0, 1.0);
  } else if (!out.effects.empty()) {
    out.explained_fraction = 1.0;
  }
  if (out.nominal_fallback > 0) {
    out.notes.push_back(std::to_string(out.nominal_fallback) +
                        " points are not in the model's probing plan (or had no valid model "
                        "contact) and were predicted with the nominal contact p + R n");
  }
  if (stage.chosen == 0 && noise.source == NoiseFloorSource::kModel && noise.robust_um > 0.0 &&
      std::abs(noise.robust_um / noise.model_um - 1.0) > 0.2) {
    std::ostringstream text;
    text << "the residuals' own noise (robust estimate " << noise.robust_um
         << " µm) differs by more than 20 % from the model's noise floor " << noise.model_um
         << " µm";
    out.notes.push_back(text.str());
  }
  if (!stage.ran && !stage.skipped_because.empty()) {
    out.notes.push_back("the spread of single readings was not tested: " + stage.skipped_because);
  }
  // A fit with effect columns that predicts the readings it was not fitted on no better than no
  // fit explains nothing (a noise or step law changes no prediction: not judged so).
  const bool held_out_worse = state.columns_after().cols() > state.p_base &&
                              std::isfinite(out.held_out_rms_um) &&
                              std::isfinite(out.held_out_without_rms_um) &&
                              out.held_out_rms_um >= out.held_out_without_rms_um;
  out.fit_refused = held_out_worse && !out.effects.empty();
  if (held_out_worse && !out.effects.empty()) {
    std::ostringstream text;
    text << "the fitted effects predict the readings they were not fitted on no better than no "
            "fit (held-out RMS "
         << out.held_out_rms_um << " µm, " << out.held_out_without_rms_um
         << " µm without them): they are not accepted as the explanation";
    out.notes.push_back(text.str());
  }
  if (!out.gap_detected) {
    out.finding = DiagnosisFinding::kNone;
  } else if (!out.effects.empty() && out.explained_fraction >= options.min_explained_fraction &&
             !out.unexplained_structure && !held_out_worse) {
    out.name_effect(out.effects.front().name);
    for (const Ambiguity& a : out.effects.front().ambiguous) out.ambiguous_with.push_back(a.with);
  } else {
    out.finding = DiagnosisFinding::kUnexplained;
  }
  if (out.law_shape.differs) {
    std::ostringstream text;
    text << "the residuals' law differs from the model's in its shape (" << out.law_shape.shape
         << ": excess kurtosis " << out.law_shape.excess_kurtosis << " ± "
         << out.law_shape.kurtosis_std_error << ", the model's "
         << out.law_shape.model_excess_kurtosis << "; KS p = " << out.law_shape.ks_p
         << "; spread √(χ²/dof) = " << out.law_shape.spread_ratio
         << " × the model's), and no structure of the practical size varies along an axis (the "
            "smallest F-test p = "
         << along.p_value << " along " << along.axis << ", " << along.axes_tested
         << " axes tested): a statement about the readings' noise law, not a missing effect";
    if (out.law_shape.shape == "heavier tails") {
      text << "; an uncertainty that assumes the model's law may understate rare large readings";
    }
    out.notes.push_back(text.str());
  }
  if (out.unexplained_structure) {
    out.unexplained_along = along;
    if (!out.effects.empty()) out.partially_explained_by = out.effects.front().name;
    std::ostringstream text;
    text << "structure remains after the library's best fit";
    if (!out.partially_explained_by.empty()) {
      text << " (" << out.partially_explained_by << " explains "
           << std::lround(100.0 * out.explained_fraction) << " % of the excess variance)";
    }
    if (!out.unexplained_along.axis.empty()) {
      if (std::isfinite(out.unexplained_along.period_mm)) {
        text << "; it varies most along " << out.unexplained_along.axis << ", periodically (period "
             << out.unexplained_along.period_mm << " mm, amplitude "
             << out.unexplained_along.amplitude_um << " µm along the axis, "
             << std::lround(100.0 * out.unexplained_along.variance_share)
             << " % of the remaining variance, F-test p = " << out.unexplained_along.p_value
             << " of " << out.unexplained_along.axes_tested / 2
             << " axis × period pairs): a periodic error of that axis's scale or encoder";
      } else {
        text << "; it varies most along " << out.unexplained_along.axis
             << " (its group means carry "
             << std::lround(100.0 * out.unexplained_along.variance_share)
             << " % of the remaining variance, F-test p = " << out.unexplained_along.p_value << ")";
      }
    }
    if (!out.unexplained_along.axis.empty() && options.fit_empirical) {
      out.empirical = fit_empirical_term(state.residuals.points, r_after_c, state.p_after,
                                         law_after.variance_um2(), out.unexplained_along.axis,
                                         so.min_delta_bic);
      if (out.empirical.fitted) refit_with_empirical(state, out);
      const EmpiricalTerm& e = out.empirical;
      if (e.fitted) {
        text << "; an empirical " << e.basis << " term of order " << e.order << " along " << e.axis
             << " (ΔBIC " << std::lround(e.delta_bic)
             << ", written to fitted.yaml as `empirical`) takes the residual RMS from "
             << e.rms_before_um << " to " << e.rms_after_um << " µm (excess over the noise floor "
             << e.excess_rms_before_um << " → " << e.excess_rms_after_um
             << " µm); it describes the structure, it does not explain it: " << e.identify_by;
      } else {
        text << "; no empirical term was fitted: " << e.why_not;
      }
    }
    out.notes.insert(out.notes.begin(), text.str());
  }
}

}  // namespace gearmc::diagnosis_stages
