// Forward selection with nested F tests, Holm, a null-calibrated min-P, ΔBIC and a practical
// size (see selection.h).
#include "engine/apps/diagnose/selection.h"

#include <algorithm>
#include <cmath>
#include <utility>

#include <tbb/parallel_for.h>

#include "core/special_functions.h"
#include "engine/apps/diagnose/linear_model.h"

namespace gearmc {
namespace {

// One step's geometry: an orthonormal basis of the selected columns and, for every other
// candidate, an orthonormal basis of what its columns add.
struct StepDesign {
  Eigen::MatrixXd q_selected;
  std::vector<int> candidates;           // candidate index of each entry below
  std::vector<Eigen::MatrixXd> q_added;  // basis of the candidate's columns ⟂ selected
};

StepDesign step_design(const std::vector<CandidateDesign>& candidates,
                       const std::vector<int>& selected) {
  StepDesign d;
  d.q_selected = orthonormal_basis(joint_columns(candidates, selected)).q;
  for (int c = 0; c < static_cast<int>(candidates.size()); ++c) {
    if (std::find(selected.begin(), selected.end(), c) == selected.end()) d.candidates.push_back(c);
  }
  // Each candidate's basis on its own (in parallel, into its own slot).
  d.q_added.resize(d.candidates.size());
  tbb::parallel_for(0, static_cast<int>(d.candidates.size()), [&](int e) {
    d.q_added[static_cast<std::size_t>(e)] =
        orthonormal_basis(
            candidates[d.candidates[static_cast<std::size_t>(e)]].observable_columns(),
            d.q_selected)
            .q;
  });
  return d;
}

struct Statistic {
  int q = 0, dof = 0;
  double reduction = 0.0, rss = 0.0, f = 0.0, p = 1.0;
};

// The nested test of adding a candidate whose q columns (beyond the selected ones) remove
// `reduction` from RSS_S = rss_selected, with `dof` = n − p − q.
Statistic nested_statistic(int q, int dof, double reduction, double rss_selected) {
  Statistic s;
  s.q = q;
  s.dof = dof;
  if (s.q == 0 || s.dof <= 0) return s;
  s.reduction = reduction;
  s.rss = std::max(rss_selected - s.reduction, 0.0);
  s.f =
      s.rss > 0.0 ? (s.reduction / s.q) / (s.rss / s.dof) : std::numeric_limits<double>::infinity();
  s.p = f_distribution_upper_tail(s.f, s.q, s.dof);
  return s;
}

// The nested test of adding candidate entry `e` for residuals y with RSS_S = rss_selected.
Statistic nested_test(const StepDesign& d, std::size_t e, const Eigen::VectorXd& y,
                      double rss_selected) {
  const Eigen::MatrixXd& q = d.q_added[e];
  const int q_cols = static_cast<int>(q.cols());
  const int dof = static_cast<int>(y.size()) - static_cast<int>(d.q_selected.cols()) - q_cols;
  if (q_cols == 0 || dof <= 0) return nested_statistic(q_cols, dof, 0.0, rss_selected);
  return nested_statistic(q_cols, dof, (q.transpose() * y).squaredNorm(), rss_selected);
}

double rss_after_selected(const StepDesign& d, const Eigen::VectorXd& y) {
  return std::max(y.squaredNorm() - (d.q_selected.transpose() * y).squaredNorm(), 0.0);
}

// The null law of a step's statistics, simulated in the space of its bases. For ε ~ N(0, σ² I_n)
// the statistics depend on ε only through z = Aᵀε, A = [Q_S, Q_1, …, Q_E] (n × C, the selected
// basis and each candidate's added basis), and through ‖ε‖². With the Gram matrix
// AᵀA = V Λ Vᵀ of rank r, U = A V_r Λ_r^(−1/2) is an orthonormal basis of span A, so
// w = Uᵀε ~ N(0, σ² I_r), z = V_r Λ_r^(1/2) w, and ‖ε‖² = ‖w‖² + σ² χ²(n − r) with the χ² term
// independent of w (Cochran's theorem). A replicate therefore draws r normals and one χ² instead
// of n normals and n·C products: the same law, exactly, at any number of readings.
struct GramNull {
  Eigen::MatrixXd root;            // C × r: V_r Λ_r^(1/2)
  std::vector<int> block_start;    // first row of each block of z: Q_S, then Q_1, …, Q_E
  std::vector<int> block_columns;  // its columns
  int rank = 0;
};

GramNull gram_null(const StepDesign& d) {
  GramNull g;
  std::vector<const Eigen::MatrixXd*> blocks = {&d.q_selected};
  for (const Eigen::MatrixXd& q : d.q_added) blocks.push_back(&q);
  int total = 0;
  for (const Eigen::MatrixXd* b : blocks) {
    g.block_start.push_back(total);
    g.block_columns.push_back(static_cast<int>(b->cols()));
    total += static_cast<int>(b->cols());
  }
  Eigen::MatrixXd gram = Eigen::MatrixXd::Zero(total, total);
  // Each block pair on its own (in parallel; each writes only its own cells).
  std::vector<std::pair<int, int>> pairs;
  for (int a = 0; a < static_cast<int>(blocks.size()); ++a) {
    for (int b = a; b < static_cast<int>(blocks.size()); ++b) {
      if (g.block_columns[a] > 0 && g.block_columns[b] > 0) pairs.emplace_back(a, b);
    }
  }
  tbb::parallel_for(0, static_cast<int>(pairs.size()), [&](int k) {
    const auto [a, b] = pairs[static_cast<std::size_t>(k)];
    const Eigen::MatrixXd part = blocks[a]->transpose() * *blocks[b];
    gram.block(g.block_start[a], g.block_start[b], part.rows(), part.cols()) = part;
    if (a != b) {
      gram.block(g.block_start[b], g.block_start[a], part.cols(), part.rows()) = part.transpose();
    }
  });
  // The blocks are orthonormal, so every eigenvalue lies in [0, blocks]; the root drops those of
  // rounding size.
  g.root = covariance_root(gram);
  g.rank = static_cast<int>(g.root.cols());
  return g;
}

NullSelectionDistribution simulate(const StepDesign& d, int rows, double sigma_um, int replicates,
                                   std::uint64_t seed, int step) {
  // The replicates in parallel, each from its own stream into its own slot, kept in replicate
  // order: the same result for any number of threads.
  std::vector<double> max_fs(static_cast<std::size_t>(std::max(replicates, 0)));
  std::vector<double> min_ps(max_fs.size());
  std::vector<char> tested(max_fs.size(), 0);
  const GramNull g = replicates > 0 ? gram_null(d) : GramNull{};
  const int selected_columns = static_cast<int>(d.q_selected.cols());
  tbb::parallel_for(0, replicates, [&](int k) {
    RandomStream rng(seed, static_cast<std::uint32_t>(k), kDiagnoseNullStream,
                     static_cast<std::uint32_t>(step));
    Eigen::VectorXd w(g.rank);
    for (int c = 0; c < g.rank; ++c) w[c] = sigma_um * rng.normal();
    const Eigen::VectorXd z = g.root * w;
    const double outside =
        rows > g.rank ? 2.0 * sample_standard_gamma(0.5 * (rows - g.rank), rng) : 0.0;
    const double norm2 = w.squaredNorm() + sigma_um * sigma_um * outside;
    const double rss = std::max(norm2 - z.head(selected_columns).squaredNorm(), 0.0);
    double max_f = 0.0, min_p = 1.0;
    bool any = false;
    for (std::size_t e = 0; e < d.candidates.size(); ++e) {
      const int q = g.block_columns[e + 1];
      const int dof = rows - selected_columns - q;
      if (q == 0 || dof <= 0) continue;
      const Statistic s =
          nested_statistic(q, dof, z.segment(g.block_start[e + 1], q).squaredNorm(), rss);
      any = true;
      max_f = std::max(max_f, s.f);
      min_p = std::min(min_p, s.p);
    }
    max_fs[k] = max_f;
    min_ps[k] = min_p;
    tested[k] = any ? 1 : 0;
  });
  NullSelectionDistribution out;
  for (std::size_t k = 0; k < max_fs.size(); ++k) {
    if (!tested[k]) continue;
    out.max_f.push_back(max_fs[k]);
    out.min_p.push_back(min_ps[k]);
  }
  return out;
}

}  // namespace

int effective_null_replicates(const SelectionOptions& options) {
  if (options.null_replicates <= 0) return 0;
  const int needed = static_cast<int>(std::ceil(2.0 / options.alpha - 1e-9)) - 1;
  return std::max(options.null_replicates, needed);
}

Eigen::MatrixXd joint_columns(const std::vector<CandidateDesign>& candidates,
                              const std::vector<int>& which) {
  int cols = 0;
  const int rows = candidates.empty() ? 0 : static_cast<int>(candidates.front().x.rows());
  for (int c : which) cols += static_cast<int>(candidates[c].observable_indices().size());
  Eigen::MatrixXd x(rows, cols);
  int at = 0;
  for (int c : which) {
    const Eigen::MatrixXd part = candidates[c].observable_columns();
    x.middleCols(at, part.cols()) = part;
    at += static_cast<int>(part.cols());
  }
  return x;
}

NullSelectionDistribution simulate_null_selection(const std::vector<CandidateDesign>& candidates,
                                                  const std::vector<int>& selected, double sigma_um,
                                                  int replicates, std::uint64_t seed, int step) {
  if (candidates.empty()) return {};
  const StepDesign d = step_design(candidates, selected);
  return simulate(d, static_cast<int>(candidates.front().x.rows()), sigma_um, replicates, seed,
                  step);
}

Selection forward_select(const std::vector<CandidateDesign>& candidates,
                         const Eigen::VectorXd& residual_um, double noise_floor_um,
                         const SelectionOptions& options) {
  Selection out;
  const int rows = static_cast<int>(residual_um.size());
  const double n = static_cast<double>(rows);
  for (int step = 0; step < options.max_effects; ++step) {
    if (out.selected.size() == candidates.size()) break;
    SelectionStep s;
    s.selected_before = out.selected;
    const StepDesign d = step_design(candidates, out.selected);
    s.rss_before = rss_after_selected(d, residual_um);
    std::vector<double> p_testable;
    std::vector<std::size_t> testable;
    for (std::size_t e = 0; e < d.candidates.size(); ++e) {
      CandidateTest t;
      t.candidate = d.candidates[e];
      t.name = candidates[t.candidate].name;
      const Statistic st = nested_test(d, e, residual_um, s.rss_before);
      t.added_rank = st.q;
      t.dof_residual = st.dof;
      if (st.q == 0) {
        t.note = out.selected.empty() ? "no observable column on this plan"
                                      : "nested in the selected effects";
      } else if (st.dof <= 0) {
        t.note = "too few points";
      } else {
        t.f = st.f;
        t.p_f = st.p;
        t.delta_bic = s.rss_before > 0.0 && st.rss > 0.0
                          ? n * std::log(st.rss / s.rss_before) + st.q * std::log(n)
                          : std::numeric_limits<double>::quiet_NaN();
        t.effect_rms_um = std::sqrt(st.reduction / n);
        testable.push_back(s.tests.size());
        p_testable.push_back(st.p);
      }
      s.tests.push_back(std::move(t));
    }
    if (testable.empty()) break;
    const std::vector<double> holm = holm_adjust(p_testable);
    const NullSelectionDistribution null =
        simulate(d, rows, noise_floor_um > 0.0 ? noise_floor_um : 1.0,
                 effective_null_replicates(options), options.seed, step);
    if (!null.max_f.empty()) s.null_max_f_95 = sample_quantile(null.max_f, 0.95);
    for (std::size_t a = 0; a < testable.size(); ++a) {
      CandidateTest& t = s.tests[testable[a]];
      t.p_holm = holm[a];
      // min-P: how often the smallest null p-value of a step is at least as extreme as this one.
      std::size_t as_small = 0;
      for (double p : null.min_p) as_small += p <= t.p_f ? 1 : 0;
      if (!null.min_p.empty()) {
        t.p_null =
            (1.0 + static_cast<double>(as_small)) / (1.0 + static_cast<double>(null.min_p.size()));
      }
      t.significant = t.p_holm < options.alpha && (null.min_p.empty() || t.p_null < options.alpha);
      t.bic_support = t.delta_bic <= -options.min_delta_bic;
      t.practical = !(noise_floor_um > 0.0) ||
                    t.effect_rms_um >= options.min_effect_rms_fraction * noise_floor_um;
    }
    // The eligible candidate with the lowest ΔBIC; ties (within rounding) go to the library order,
    // which is the order of the tests.
    int best = -1;
    for (std::size_t a = 0; a < testable.size(); ++a) {
      const CandidateTest& t = s.tests[testable[a]];
      if (!t.eligible()) continue;
      if (best < 0) {
        best = static_cast<int>(testable[a]);
        continue;
      }
      const double b = s.tests[best].delta_bic;
      if (t.delta_bic < b - 1e-9 * std::max(1.0, std::abs(b))) best = static_cast<int>(testable[a]);
    }
    s.accepted = best;
    if (best >= 0) {
      s.tests[best].accepted = true;
      out.selected.push_back(s.tests[best].candidate);
    }
    out.steps.push_back(std::move(s));
    if (best < 0) break;
  }
  return out;
}

}  // namespace gearmc
