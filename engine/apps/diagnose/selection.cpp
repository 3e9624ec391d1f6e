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

// One step's geometry, reduced to what its tests and their null law need: with Q_S an
// orthonormal basis of the selected columns and A_e one of what candidate e's columns add
// (⟂ Q_S), the products Q_Sᵀy and A_eᵀy with the residuals y, and the Gram matrix of
// A = [Q_S, A_1, …, A_E]. The bases A_e are made one candidate at a time and dropped: only Q_S
// (n × the selected columns) and the tasks' own A_e are ever held (memory at 10⁶ readings).
struct StepDesign {
  int rows = 0;
  std::vector<int> candidates;           // candidate index of each entry below
  Eigen::VectorXd selected_y;            // Q_Sᵀ y
  std::vector<Eigen::VectorXd> added_y;  // A_eᵀ y
  std::vector<int> block_start;    // first row of each block of A's Gram: Q_S, then A_1, …, A_E
  std::vector<int> block_columns;  // its columns
  Eigen::MatrixXd gram;            // AᵀA (empty unless asked for)
  // ‖X_e β_e‖² of each entry in the fit of y on the selected columns and its own: X_e its kept
  // columns, β_e = R_e⁻¹ A_eᵀy (X_e = Q_S Q_SᵀX_e + A_e R_e, so the fit Q_S Q_Sᵀy + A_e A_eᵀy is
  // X_S β_S + X_e β_e with that β_e). At least A_eᵀy's own ‖A_eᵀy‖² (the RSS it removes).
  std::vector<double> joint_reduction;
  int selected_columns() const { return block_columns.front(); }
  int added_columns(std::size_t e) const { return block_columns[e + 1]; }
};

// The step design for residuals y (any vector of the columns' length; zero when only the null law
// is wanted), with AᵀA when `with_gram`, for `rows` points (y.size() on the N rows themselves,
// N on compressed columns: compressed_candidate_designs). The blocks of AᵀA: Q_SᵀQ_S and A_eᵀA_e
// and Q_SᵀA_e directly; A_eᵀA_f (e ≠ f) as (A_eᵀX_f) R_f⁻¹, where X_f are f's kept columns and R_f
// = A_fᵀX_f the triangle of their Gram–Schmidt (P⊥X_f = A_f R_f, and A_eᵀP⊥ = A_eᵀ as A_e ⟂ Q_S),
// so that only one A_e is needed at a time.
StepDesign step_design(const std::vector<CandidateDesign>& candidates,
                       const std::vector<int>& selected, const Eigen::VectorXd& y, bool with_gram,
                       int rows) {
  StepDesign d;
  d.rows = rows;
  const Eigen::MatrixXd q_selected = orthonormal_basis(joint_columns(candidates, selected)).q;
  d.selected_y = q_selected.transpose() * y;
  for (int c = 0; c < static_cast<int>(candidates.size()); ++c) {
    if (std::find(selected.begin(), selected.end(), c) == selected.end()) d.candidates.push_back(c);
  }
  const std::size_t entries = d.candidates.size();
  d.added_y.resize(entries);
  d.joint_reduction.assign(entries, 0.0);
  // Per entry: its kept columns (indices into x), R_e, Q_SᵀA_e, A_eᵀA_e and A_eᵀX_f of every f.
  std::vector<std::vector<int>> kept(entries);
  std::vector<Eigen::MatrixXd> triangle(entries), with_selected(entries), own(entries);
  std::vector<std::vector<Eigen::MatrixXd>> with_columns(entries);
  // Each candidate on its own (in parallel, into its own slots).
  tbb::parallel_for(0, static_cast<int>(entries), [&](int e) {
    const std::size_t u = static_cast<std::size_t>(e);
    const CandidateDesign& candidate = candidates[d.candidates[u]];
    const std::vector<int> observable = candidate.observable_indices();
    Eigen::MatrixXd copy;
    ColumnBasis basis = orthonormal_basis(candidate.observable_columns(copy), q_selected);
    const Eigen::MatrixXd& a = basis.q;
    d.added_y[u] = a.transpose() * y;
    for (int k : basis.kept) kept[u].push_back(observable[static_cast<std::size_t>(k)]);
    if (a.cols() == 0) return;
    Eigen::MatrixXd r(a.cols(), a.cols()), xk(candidate.x.rows(), a.cols());
    for (int k = 0; k < static_cast<int>(a.cols()); ++k) {
      xk.col(k) = candidate.x.col(kept[u][static_cast<std::size_t>(k)]);
      r.col(k) = a.transpose() * xk.col(k);
    }
    const Eigen::VectorXd beta = r.triangularView<Eigen::Upper>().solve(d.added_y[u]);
    d.joint_reduction[u] = std::max((xk * beta).squaredNorm(), d.added_y[u].squaredNorm());
    triangle[u] = r;
    if (!with_gram) return;
    with_selected[u] = q_selected.transpose() * a;
    own[u] = a.transpose() * a;
    with_columns[u].resize(entries);
    for (std::size_t f = 0; f < entries; ++f) {
      if (f == u) continue;
      with_columns[u][f] = a.transpose() * candidates[d.candidates[f]].x;  // q_e × all of f's
    }
  });
  int total = 0;
  d.block_start.push_back(0);
  d.block_columns.push_back(static_cast<int>(q_selected.cols()));
  total += static_cast<int>(q_selected.cols());
  for (std::size_t e = 0; e < entries; ++e) {
    d.block_start.push_back(total);
    d.block_columns.push_back(static_cast<int>(d.added_y[e].size()));
    total += static_cast<int>(d.added_y[e].size());
  }
  if (!with_gram) return d;
  d.gram = Eigen::MatrixXd::Zero(total, total);
  const int s = d.selected_columns();
  d.gram.topLeftCorner(s, s) = q_selected.transpose() * q_selected;
  for (std::size_t e = 0; e < entries; ++e) {
    const int qe = d.added_columns(e), at = d.block_start[e + 1];
    if (qe == 0) continue;
    d.gram.block(at, at, qe, qe) = own[e];
    d.gram.block(0, at, s, qe) = with_selected[e];
    d.gram.block(at, 0, qe, s) = with_selected[e].transpose();
    for (std::size_t f = e + 1; f < entries; ++f) {
      const int qf = d.added_columns(f), bt = d.block_start[f + 1];
      if (qf == 0) continue;
      Eigen::MatrixXd ex(qe, qf);  // A_eᵀX_f on f's kept columns
      for (int k = 0; k < qf; ++k)
        ex.col(k) = with_columns[e][f].col(kept[f][static_cast<std::size_t>(k)]);
      const Eigen::MatrixXd part =
          triangle[f].triangularView<Eigen::Upper>().solve<Eigen::OnTheRight>(ex);
      d.gram.block(at, bt, qe, qf) = part;
      d.gram.block(bt, at, qf, qe) = part.transpose();
    }
  }
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

// The nested test of adding candidate entry `e` with RSS_S = rss_selected.
Statistic nested_test(const StepDesign& d, std::size_t e, double rss_selected) {
  const int q_cols = d.added_columns(e);
  const int dof = d.rows - d.selected_columns() - q_cols;
  if (q_cols == 0 || dof <= 0) return nested_statistic(q_cols, dof, 0.0, rss_selected);
  return nested_statistic(q_cols, dof, d.added_y[e].squaredNorm(), rss_selected);
}

double rss_after_selected(const StepDesign& d, const Eigen::VectorXd& y) {
  return std::max(y.squaredNorm() - d.selected_y.squaredNorm(), 0.0);
}

// The null law of a step's statistics, simulated in the space of its bases. For ε ~ N(0, σ² I_n)
// the statistics depend on ε only through z = Aᵀε, A = [Q_S, Q_1, …, Q_E] (n × C, the selected
// basis and each candidate's added basis), and through ‖ε‖². With any root L (C × r, rank r) of
// the Gram matrix, L Lᵀ = AᵀA, U = A L⁺ᵀ is an orthonormal basis of span A (UᵀU = L⁺L LᵀL⁺ᵀ = I)
// with AᵀU = L, so w = Uᵀε ~ N(0, σ² I_r), z = L w, and ‖ε‖² = ‖w‖² + σ² χ²(n − r) with the χ²
// term independent of w (Cochran's theorem). A replicate therefore draws r normals and one χ²
// instead of n normals and n·C products: the same law, exactly, at any number of readings. The
// root is gram_root's (Cholesky in column order), which moves only with rounding when the
// columns are summed another way (compressed or not; linear_model.h), so the same data give the
// same replicates.
struct GramNull {
  Eigen::MatrixXd root;  // C × r
  int rank = 0;
};

GramNull gram_null(const StepDesign& d) {
  GramNull g;
  g.root = gram_root(d.gram);
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
  const int selected_columns = d.selected_columns();
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
      const int q = d.added_columns(e);
      const int dof = rows - selected_columns - q;
      if (q == 0 || dof <= 0) continue;
      const Statistic s =
          nested_statistic(q, dof, z.segment(d.block_start[e + 1], q).squaredNorm(), rss);
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
    for (int k : candidates[c].observable_indices()) x.col(at++) = candidates[c].x.col(k);
  }
  return x;
}

NullSelectionDistribution simulate_null_selection(const std::vector<CandidateDesign>& candidates,
                                                  const std::vector<int>& selected, double sigma_um,
                                                  int replicates, std::uint64_t seed, int step) {
  if (candidates.empty()) return {};
  const int rows = static_cast<int>(candidates.front().x.rows());
  const StepDesign d =
      step_design(candidates, selected, Eigen::VectorXd::Zero(rows), replicates > 0, rows);
  return simulate(d, rows, sigma_um, replicates, seed, step);
}

Eigen::MatrixXd step_gram(const std::vector<CandidateDesign>& candidates,
                          const std::vector<int>& selected) {
  if (candidates.empty()) return {};
  const int rows = static_cast<int>(candidates.front().x.rows());
  return step_design(candidates, selected, Eigen::VectorXd::Zero(rows), true, rows).gram;
}

namespace {

// forward_select on columns and residuals of `rows` points (their own length, or compressed).
// Every selected effect tested as the last one in: the nested test of adding it to all the
// others (selection.h). Drops the weakest failing effect and repeats until all pass; then orders
// `selected` by the RMS each removes given the others, largest first.
void retest_selected(const std::vector<CandidateDesign>& candidates,
                     const Eigen::VectorXd& residual_um, int rows, double noise_floor_um,
                     const SelectionOptions& options, Selection& out) {
  const double n = static_cast<double>(rows);
  for (;;) {
    std::vector<CandidateTest> tests;
    std::vector<double> p;
    for (const int e : out.selected) {
      std::vector<int> others;
      for (const int o : out.selected) {
        if (o != e) others.push_back(o);
      }
      const StepDesign d = step_design(candidates, others, residual_um, false, rows);
      const double rss_others = rss_after_selected(d, residual_um);
      const std::size_t entry = static_cast<std::size_t>(
          std::find(d.candidates.begin(), d.candidates.end(), e) - d.candidates.begin());
      const Statistic st = nested_test(d, entry, rss_others);
      CandidateTest t;
      t.candidate = e;
      t.name = candidates[e].name;
      t.added_rank = st.q;
      t.dof_residual = st.dof;
      t.f = st.f;
      t.p_f = st.q > 0 && st.dof > 0 ? st.p : 1.0;
      t.delta_bic = rss_others > 0.0 && st.rss > 0.0
                        ? n * std::log(st.rss / rss_others) + st.q * std::log(n)
                        : std::numeric_limits<double>::quiet_NaN();
      t.effect_rms_um = std::sqrt(st.reduction / n);
      t.joint_rms_um = std::sqrt(d.joint_reduction[entry] / n);
      if (st.q == 0) t.note = "nested in the other selected effects";
      tests.push_back(std::move(t));
      p.push_back(tests.back().p_f);
    }
    const std::vector<double> holm = holm_adjust(p);
    int weakest = -1;
    for (std::size_t k = 0; k < tests.size(); ++k) {
      CandidateTest& t = tests[k];
      t.p_holm = holm[k];
      t.significant = t.added_rank > 0 && t.p_holm < options.alpha;
      t.bic_support = t.delta_bic <= -options.min_delta_bic;
      t.practical = !(noise_floor_um > 0.0) ||
                    t.joint_rms_um >= options.min_effect_rms_fraction * noise_floor_um;
      t.accepted = t.eligible();
      if (t.accepted) continue;
      const auto worse = [](const CandidateTest& a, const CandidateTest& b) {
        if (a.p_holm != b.p_holm) return a.p_holm > b.p_holm;
        const double da = std::isnan(a.delta_bic) ? INFINITY : a.delta_bic;
        const double db = std::isnan(b.delta_bic) ? INFINITY : b.delta_bic;
        return da > db;
      };
      if (weakest < 0 || worse(t, tests[static_cast<std::size_t>(weakest)])) {
        weakest = static_cast<int>(k);
      }
    }
    if (weakest < 0) {
      // All kept: the one removing most given the others first (ties: selection order).
      std::vector<std::size_t> order(tests.size());
      for (std::size_t k = 0; k < order.size(); ++k) order[k] = k;
      std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
        return tests[a].effect_rms_um > tests[b].effect_rms_um;
      });
      out.selected.clear();
      out.retest.clear();
      for (const std::size_t k : order) {
        out.selected.push_back(tests[k].candidate);
        out.retest.push_back(tests[k]);
      }
      return;
    }
    CandidateTest drop = tests[static_cast<std::size_t>(weakest)];
    std::string others;
    for (const CandidateTest& t : tests) {
      if (t.candidate != drop.candidate) others += (others.empty() ? "" : ", ") + t.name;
    }
    drop.note = "dropped: " +
                std::string(!drop.significant   ? "not significant"
                            : !drop.bic_support ? "no BIC support"
                                                : "below the practical size") +
                " given " + others;
    out.selected.erase(std::find(out.selected.begin(), out.selected.end(), drop.candidate));
    out.dropped.push_back(std::move(drop));
  }
}

// After the re-test: a kept effect that a smaller candidate (fewer observable columns) replaces
// with no loss, given the other kept effects, is replaced by it — BIC = n ln RSS + rank · ln n of
// the others with the smaller one at most that of the others with the kept one (Schwarz 1978; the
// two models need not be nested). An effect chosen early because its extra columns carried part
// of an effect selected later (a rotary table's harmonics taking a drift's once-around part, then
// kept for the eccentricity its first harmonics also span) gives way to what the others leave it
// to explain. The replaced effect is listed in `dropped` with the reason; the re-test runs again.
void replace_by_smaller(const std::vector<CandidateDesign>& candidates,
                        const Eigen::VectorXd& residual_um, int rows, double noise_floor_um,
                        const SelectionOptions& options, Selection& out) {
  const double n = static_cast<double>(rows);
  auto bic_of = [&](const std::vector<int>& set) {
    const StepDesign d = step_design(candidates, set, residual_um, false, rows);
    const double rss = rss_after_selected(d, residual_um);
    const int rank = static_cast<int>(d.selected_y.size());
    return std::pair<double, double>{n * std::log(std::max(rss, 1e-300)) + rank * std::log(n), rss};
  };
  for (std::size_t round = 0; round < candidates.size(); ++round) {
    bool replaced = false;
    for (std::size_t k = 0; k < out.selected.size() && !replaced; ++k) {
      const int e = out.selected[k];
      const std::size_t width = candidates[e].observable_indices().size();
      const auto [bic_kept, rss_kept] = bic_of(out.selected);
      int best = -1;
      double best_bic = bic_kept;
      for (int a = 0; a < static_cast<int>(candidates.size()); ++a) {
        if (std::find(out.selected.begin(), out.selected.end(), a) != out.selected.end()) continue;
        if (candidates[a].observable_indices().size() >= width) continue;
        std::vector<int> swapped = out.selected;
        swapped[k] = a;
        const double bic = bic_of(swapped).first;
        if (bic <= best_bic) {
          best = a;
          best_bic = bic;
        }
      }
      if (best < 0) continue;
      CandidateTest note;
      note.candidate = e;
      note.name = candidates[e].name;
      note.delta_bic = best_bic - bic_kept;
      note.note = "replaced by " + candidates[best].name +
                  ": with the other kept effects it explains the readings as well with fewer "
                  "columns (BIC lower by " +
                  std::to_string(bic_kept - best_bic) + ")";
      out.dropped.push_back(std::move(note));
      out.selected[k] = best;
      retest_selected(candidates, residual_um, rows, noise_floor_um, options, out);
      replaced = true;
    }
    if (!replaced) break;
  }
}

Selection select(const std::vector<CandidateDesign>& candidates, const Eigen::VectorXd& residual_um,
                 int rows, double noise_floor_um, const SelectionOptions& options) {
  Selection out;
  const double n = static_cast<double>(rows);
  for (int step = 0; step < options.max_effects; ++step) {
    if (out.selected.size() == candidates.size()) break;
    SelectionStep s;
    s.selected_before = out.selected;
    const int replicates = effective_null_replicates(options);
    const StepDesign d = step_design(candidates, out.selected, residual_um, replicates > 0, rows);
    s.rss_before = rss_after_selected(d, residual_um);
    std::vector<double> p_testable;
    std::vector<std::size_t> testable;
    for (std::size_t e = 0; e < d.candidates.size(); ++e) {
      CandidateTest t;
      t.candidate = d.candidates[e];
      t.name = candidates[t.candidate].name;
      const Statistic st = nested_test(d, e, s.rss_before);
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
        t.joint_rms_um = std::sqrt(d.joint_reduction[e] / n);
        testable.push_back(s.tests.size());
        p_testable.push_back(st.p);
      }
      s.tests.push_back(std::move(t));
    }
    if (testable.empty()) break;
    const std::vector<double> holm = holm_adjust(p_testable);
    const NullSelectionDistribution null = simulate(
        d, rows, noise_floor_um > 0.0 ? noise_floor_um : 1.0, replicates, options.seed, step);
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
                    t.joint_rms_um >= options.min_effect_rms_fraction * noise_floor_um;
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
  retest_selected(candidates, residual_um, rows, noise_floor_um, options, out);
  replace_by_smaller(candidates, residual_um, rows, noise_floor_um, options, out);
  return out;
}

}  // namespace

Selection forward_select(const std::vector<CandidateDesign>& candidates,
                         const Eigen::VectorXd& residual_um, double noise_floor_um,
                         const SelectionOptions& options) {
  return select(candidates, residual_um, static_cast<int>(residual_um.size()), noise_floor_um,
                options);
}

Selection forward_select(const CompressedDesigns& compressed, double noise_floor_um,
                         const SelectionOptions& options) {
  return select(compressed.candidates, compressed.residual_um, compressed.rows, noise_floor_um,
                options);
}

}  // namespace gearmc
