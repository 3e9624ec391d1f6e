// Tests of the diagnosis's effect selection (engine/apps/diagnose/selection.h): the null simulation
// is reproducible and bounded as Bonferroni says, and each gate (Holm-adjusted F test, BIC)
// decides alone on hand-made designs whose F and ΔBIC are known in closed form. α = 0.01.
#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <Eigen/QR>
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "core/random_stream.h"
#include "core/special_functions.h"
#include "engine/apps/diagnose/diagnosis.h"
#include "engine/apps/diagnose/selection.h"
#include "engine/run/simulate.h"
#include "tests/support/diagnose_readings.h"

namespace gearmc {
namespace {

using testing_support::baseline;
using testing_support::hidden;
using testing_support::kNoiseUm;

// The library's candidate designs at the points of the baseline plan.
std::vector<CandidateDesign> baseline_candidates() {
  const Residuals r = compute_residuals(baseline(), hidden(""));
  return candidate_designs(PointContexts(r.points, &ResidualPoint::context));
}

TEST(DiagnoseSelection, NullSimulationIsReproducibleAndBonferroniBounded) {
  const std::vector<CandidateDesign> c = baseline_candidates();
  const NullSelectionDistribution a = simulate_null_selection(c, {}, kNoiseUm, 200, 7);
  const NullSelectionDistribution b = simulate_null_selection(c, {}, kNoiseUm, 200, 7);
  ASSERT_EQ(a.max_f.size(), 200u);
  EXPECT_EQ(a.max_f, b.max_f);
  EXPECT_EQ(a.min_p, b.min_p);
  // Under the null each candidate's p is uniform, so P(min p ≤ 0.05/8) ≤ 0.05 (Bonferroni);
  // allow 3 binomial standard errors for 200 replicates.
  const double bound = 0.05 + 3.0 * std::sqrt(0.05 * 0.95 / 200.0);
  const double hits = static_cast<double>(
      std::count_if(a.min_p.begin(), a.min_p.end(), [](double p) { return p <= 0.05 / 8; }));
  EXPECT_LE(hits / 200.0, bound);
  for (double f : a.max_f) EXPECT_TRUE(f > 0.0 && std::isfinite(f));
}

// The null simulation draws in the space of the step's bases (selection.cpp, GramNull: r normals
// and one χ² per replicate); the direct way draws n normals and fits every candidate. Both must
// give the same law of the step's smallest p-value and largest F. Direct here: Eigen's
// column-pivoting QR of [X_S, X_c] on each replicate (not gearmc's orthonormal_basis). For the
// baseline plan with nothing selected and with the first candidate selected, K = 1500 replicates
// each; two-sample Kolmogorov–Smirnov test at α = 0.001 (critical distance
// 1.949 √(2/K) = 0.071, Smirnov's asymptotic law); seeds 7 (gearmc) and 11 (direct).
double rss_of(const Eigen::MatrixXd& x, const Eigen::VectorXd& y, int* rank) {
  if (x.cols() == 0) {
    *rank = 0;
    return y.squaredNorm();
  }
  Eigen::MatrixXd unit = x;  // each column to unit norm, so the rank threshold is relative
  for (int c = 0; c < unit.cols(); ++c) {
    if (unit.col(c).norm() > 0.0) unit.col(c).normalize();
  }
  Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(unit);
  qr.setThreshold(1e-6);  // selection.cpp nests a column below 1e-6 of its norm
  *rank = static_cast<int>(qr.rank());
  const Eigen::VectorXd fitted = unit * qr.solve(y);
  return (y - fitted).squaredNorm();
}

double two_sample_ks(std::vector<double> a, std::vector<double> b) {
  std::sort(a.begin(), a.end());
  std::sort(b.begin(), b.end());
  double d = 0.0;
  std::size_t i = 0, j = 0;
  while (i < a.size() && j < b.size()) {
    const double v = std::min(a[i], b[j]);
    while (i < a.size() && a[i] <= v) ++i;
    while (j < b.size() && b[j] <= v) ++j;
    const double fa = static_cast<double>(i) / static_cast<double>(a.size());
    const double fb = static_cast<double>(j) / static_cast<double>(b.size());
    d = std::max(d, std::abs(fa - fb));
  }
  return d;
}

TEST(DiagnoseSelection, NullSimulationHasTheLawOfDirectSimulation) {
  const std::vector<CandidateDesign> c = baseline_candidates();
  const int n = static_cast<int>(c.front().x.rows());
  constexpr int kReplicates = 1500;
  for (const std::vector<int>& selected : {std::vector<int>{}, std::vector<int>{0}}) {
    const NullSelectionDistribution gram =
        simulate_null_selection(c, selected, kNoiseUm, kReplicates, 7);
    Eigen::MatrixXd xs = joint_columns(c, selected);
    std::vector<double> direct_min_p, direct_max_f;
    RandomStream rng(11, 0, StreamPurpose::kDiagnoseNull, 99);
    for (int k = 0; k < kReplicates; ++k) {
      Eigen::VectorXd e(n);
      for (int i = 0; i < n; ++i) e[i] = kNoiseUm * rng.normal();
      int p = 0;
      const double rss_s = rss_of(xs, e, &p);
      double min_p = 1.0, max_f = 0.0;
      bool any = false;
      for (int cand = 0; cand < static_cast<int>(c.size()); ++cand) {
        if (std::find(selected.begin(), selected.end(), cand) != selected.end()) continue;
        Eigen::MatrixXd both(n, xs.cols() + c[cand].observable_columns().cols());
        both << xs, c[cand].observable_columns();
        int pq = 0;
        const double rss_c = rss_of(both, e, &pq);
        const int q = pq - p, dof = n - pq;
        if (q == 0 || dof <= 0) continue;
        const double f = ((rss_s - rss_c) / q) / (rss_c / dof);
        any = true;
        max_f = std::max(max_f, f);
        min_p = std::min(min_p, f_distribution_upper_tail(f, q, dof));
      }
      if (!any) continue;
      direct_min_p.push_back(min_p);
      direct_max_f.push_back(max_f);
    }
    ASSERT_EQ(gram.min_p.size(), direct_min_p.size());
    const double critical = 1.949 * std::sqrt(2.0 / kReplicates);
    EXPECT_LT(two_sample_ks(gram.min_p, direct_min_p), critical) << selected.size();
    EXPECT_LT(two_sample_ks(gram.max_f, direct_max_f), critical) << selected.size();
  }
}

// The Gram matrix of a step's bases (selection.cpp builds its off-diagonal blocks from one basis at
// a time, A_eᵀA_f = (A_eᵀX_f) R_f⁻¹) against an independent route: Q_S as the thin Q of Eigen's
// Householder QR of X_S with the signs that make R's diagonal positive (Gram–Schmidt's), P⊥ = I −
// Q_S Q_Sᵀ, and A_e = P⊥X_e R_e⁻¹ with R_e the Cholesky factor of (P⊥X_e)ᵀ(P⊥X_e) (Gram–Schmidt's
// positive-diagonal triangle), X_S and X_e the columns kept by the same 1e-6 rule (kept_columns);
// every block of [Q_S, A_1, …]ᵀ[Q_S, A_1, …] within 1e-9. The baseline plan with nothing and with
// the first two candidates selected (then some columns are nested: the test requires one).
// The columns of `all` kept by selection.cpp's rule: what is left of a column off `before` and the
// columns kept before it exceeds 1e-6 of its norm (decided by least squares with Eigen's pivoting
// QR), as one matrix.
Eigen::MatrixXd kept_columns(const Eigen::MatrixXd& before, const Eigen::MatrixXd& all) {
  const int n = static_cast<int>(all.rows());
  Eigen::MatrixXd kept(n, 0);
  for (int j = 0; j < all.cols(); ++j) {
    Eigen::MatrixXd span(n, before.cols() + kept.cols());
    span << before, kept;
    Eigen::VectorXd left = all.col(j);
    if (span.cols() > 0) left -= span * span.colPivHouseholderQr().solve(left);
    if (!(left.norm() > 1e-6 * all.col(j).norm())) continue;
    Eigen::MatrixXd wider(n, kept.cols() + 1);
    wider << kept, all.col(j);
    kept = wider;
  }
  return kept;
}

TEST(DiagnoseSelection, StepGramEqualsTheProductOfIndependentlyMadeBases) {
  const std::vector<CandidateDesign> c = baseline_candidates();
  const int n = static_cast<int>(c.front().x.rows());
  int nested = 0;  // columns the rule dropped (the cases the test is about include some)
  for (const std::vector<int>& selected : {std::vector<int>{}, std::vector<int>{0, 1}}) {
    const Eigen::MatrixXd gram = step_gram(c, selected);
    const Eigen::MatrixXd xs = kept_columns(Eigen::MatrixXd(n, 0), joint_columns(c, selected));
    nested += static_cast<int>(joint_columns(c, selected).cols() - xs.cols());
    Eigen::MatrixXd qs(n, xs.cols());
    if (xs.cols() > 0) {
      const Eigen::HouseholderQR<Eigen::MatrixXd> qr(xs);
      qs = qr.householderQ() * Eigen::MatrixXd::Identity(n, xs.cols());
      for (int k = 0; k < xs.cols(); ++k) {
        if (qr.matrixQR()(k, k) < 0.0) qs.col(k) *= -1.0;
      }
    }
    Eigen::MatrixXd a = qs;
    for (int cand = 0; cand < static_cast<int>(c.size()); ++cand) {
      if (std::find(selected.begin(), selected.end(), cand) != selected.end()) continue;
      const Eigen::MatrixXd all = c[cand].observable_columns();
      const Eigen::MatrixXd x = kept_columns(qs, all);
      nested += static_cast<int>(all.cols() - x.cols());
      if (x.cols() == 0) continue;
      const Eigen::MatrixXd perp = x - qs * (qs.transpose() * x);
      const Eigen::LLT<Eigen::MatrixXd> llt(perp.transpose() * perp);
      ASSERT_EQ(llt.info(), Eigen::Success) << c[cand].name;
      const Eigen::MatrixXd upper = llt.matrixU();
      const Eigen::MatrixXd block =
          upper.transpose().triangularView<Eigen::Lower>().solve(perp.transpose()).transpose();
      Eigen::MatrixXd wider(n, a.cols() + block.cols());
      wider << a, block;
      a = wider;
    }
    ASSERT_EQ(gram.rows(), a.cols()) << selected.size();
    const Eigen::MatrixXd expected = a.transpose() * a;
    EXPECT_LT((gram - expected).cwiseAbs().maxCoeff(), 1e-9) << selected.size();
    // Not the identity: the candidates' bases overlap, so the off-diagonal blocks are tested.
    EXPECT_GT((expected - Eigen::MatrixXd::Identity(a.cols(), a.cols())).cwiseAbs().maxCoeff(),
              0.1);
  }
  EXPECT_GT(nested, 0);
}

// --- The selection's gates, each deciding alone -------------------------------------------------
// Hand-made designs on n = 32 points with Walsh columns (±1 Rademacher functions of periods 2, 4,
// 8, 16 and 32, mutually orthogonal), residual y = a·R1 + e with e = R1·R2 (a Walsh product,
// orthogonal to every column): adding R1 leaves RSS = |e|² = 32 from |y|² = 32(1 + a²), so
// F = 31 a² (1 and 31 degrees of freedom) and ΔBIC = 32 ln(1/(1 + a²)) + ln 32 (selection.h's
// formulas), every other candidate adds nothing (F = 0). No null simulation (null_replicates 0),
// so "significant" is the Holm-adjusted F test alone; the noise floor (0.01 µm) keeps the
// practical size out of the way. α = 0.01.

CandidateDesign walsh_candidate(const std::string& name, int period) {
  CandidateDesign c;
  c.name = name;
  c.coefficients = {"c_um"};
  c.units = {"µm"};
  c.observable = {true};
  c.x.resize(32, 1);
  for (int k = 0; k < 32; ++k) c.x(k, 0) = (k % period) < period / 2 ? 1.0 : -1.0;
  return c;
}

Eigen::VectorXd walsh_residual(double a) {
  const CandidateDesign r1 = walsh_candidate("r1", 2), r2 = walsh_candidate("r2", 4);
  return a * r1.x.col(0) + r1.x.col(0).cwiseProduct(r2.x.col(0));
}

SelectionOptions gate_options() {
  SelectionOptions o;
  o.alpha = 0.01;
  o.null_replicates = 0;
  o.max_effects = 1;
  return o;
}

// Residuals of 3 master gears (7 200 points: two 4 096-row chunks) simulated with `effects_yaml`
// + noise 0.3 µm at `seed`, against the baseline, and their residual vector.
struct ThreeGears {
  ThreeGears(const std::string& effects_yaml, std::uint64_t seed) {
    SimulateOptions o;
    o.master = true;
    o.gears = 3;
    Scenario truth = testing_support::with_effects(effects_yaml + "noise: {sigma_um: 0.3}\n");
    truth.seed = seed;
    residuals = compute_residuals(baseline(), simulate_readings(truth, o).readings);
    y.resize(static_cast<int>(residuals.points.size()));
    for (std::size_t k = 0; k < residuals.points.size(); ++k)
      y[static_cast<int>(k)] = residuals.points[k].residual_um;
  }
  Residuals residuals;
  Eigen::VectorXd y;
};

// Compressed columns (compressed_candidate_designs: R of [X, y] by chunked Householder QR) must
// keep every inner product of the N rows. Reference: XᵀX, Xᵀy, yᵀy summed directly over the rows
// of candidate_designs' own matrices (no QR). 3 gears × 2 400 points of lobing readings (seed 3),
// so that the 4 096-row chunks stack two triangles; within 1e-9 of the largest product.
TEST(DiagnoseSelection, CompressedColumnsKeepEveryInnerProductOfTheRows) {
  const ThreeGears g("probe_lobing: {harmonics: [{order: 6, amplitude_um: 0.4, phase_deg: 20}]}\n",
                     3);
  const Residuals& r = g.residuals;
  const Eigen::VectorXd& y = g.y;
  ASSERT_GT(r.points.size(), 4096u);
  const PointContexts contexts(r.points, &ResidualPoint::context);
  const std::vector<CandidateDesign> full = candidate_designs(contexts);
  const CompressedDesigns small = compressed_candidate_designs(contexts, y);
  EXPECT_EQ(small.rows, static_cast<int>(r.points.size()));
  ASSERT_EQ(small.candidates.size(), full.size());
  for (std::size_t c = 0; c < full.size(); ++c) {
    EXPECT_EQ(small.candidates[c].name, full[c].name);
    EXPECT_EQ(small.candidates[c].observable, full[c].observable) << full[c].name;
  }
  Eigen::MatrixXd x(full.front().x.rows(), 0), xs(small.candidates.front().x.rows(), 0);
  for (std::size_t c = 0; c < full.size(); ++c) {
    Eigen::MatrixXd grown(x.rows(), x.cols() + full[c].x.cols());
    grown << x, full[c].x;
    x = grown;
    Eigen::MatrixXd grown_small(xs.rows(), xs.cols() + small.candidates[c].x.cols());
    grown_small << xs, small.candidates[c].x;
    xs = grown_small;
  }
  EXPECT_EQ(xs.rows(), x.cols() + 1);
  Eigen::MatrixXd direct(x.cols() + 1, x.cols() + 1), compressed(x.cols() + 1, x.cols() + 1);
  for (int i = 0; i <= x.cols(); ++i) {
    for (int j = 0; j <= x.cols(); ++j) {
      double sum = 0.0;
      for (int k = 0; k < x.rows(); ++k) {
        sum += (i < x.cols() ? x(k, i) : y[k]) * (j < x.cols() ? x(k, j) : y[k]);
      }
      direct(i, j) = sum;
      compressed(i, j) = (i < x.cols() ? Eigen::VectorXd(xs.col(i)) : small.residual_um)
                             .dot(j < x.cols() ? Eigen::VectorXd(xs.col(j)) : small.residual_um);
    }
  }
  EXPECT_LE((direct - compressed).cwiseAbs().maxCoeff(), 1e-9 * direct.cwiseAbs().maxCoeff());
}

// The selection on compressed columns is the selection on the N rows: the same effects, and at
// every step the same F, F-table p, ΔBIC and removed RMS (within 1e-9 relative: rounding), the
// same null-calibrated p (the null replicates are drawn from gram_root's Cholesky root, which
// moves only by rounding between the two) and the same 95 % null quantile. Readings: 3 gears
// with probe lobing and a drift (seed 5), K = 199, σ the truth's 0.3 µm.
TEST(DiagnoseSelection, SelectionOnCompressedColumnsIsTheSelectionOnTheRows) {
  const ThreeGears g(
      "probe_lobing: {harmonics: [{order: 6, amplitude_um: 0.3, phase_deg: 20}]}\n"
      "drift: {x_um: 0.8, y_um: -0.5}\n",
      5);
  const Eigen::VectorXd& y = g.y;
  const PointContexts contexts(g.residuals.points, &ResidualPoint::context);
  SelectionOptions so;
  so.null_replicates = 199;
  so.seed = 9;
  const Selection rows = forward_select(candidate_designs(contexts), y, kNoiseUm, so);
  const Selection small = forward_select(compressed_candidate_designs(contexts, y), kNoiseUm, so);
  ASSERT_GE(rows.selected.size(), 2u);  // lobing and drift are far above the floor
  EXPECT_EQ(small.selected, rows.selected);
  ASSERT_EQ(small.steps.size(), rows.steps.size());
  auto near = [](double a, double b) {
    return (std::isnan(a) && std::isnan(b)) || std::abs(a - b) <= 1e-9 * std::max(1.0, std::abs(a));
  };
  for (std::size_t s = 0; s < rows.steps.size(); ++s) {
    const SelectionStep& a = rows.steps[s];
    const SelectionStep& b = small.steps[s];
    EXPECT_TRUE(near(a.rss_before, b.rss_before)) << s;
    EXPECT_TRUE(near(a.null_max_f_95, b.null_max_f_95)) << s;
    ASSERT_EQ(a.tests.size(), b.tests.size());
    for (std::size_t t = 0; t < a.tests.size(); ++t) {
      const CandidateTest& u = a.tests[t];
      const CandidateTest& v = b.tests[t];
      EXPECT_EQ(u.added_rank, v.added_rank) << u.name;
      EXPECT_EQ(u.dof_residual, v.dof_residual) << u.name;
      EXPECT_TRUE(near(u.f, v.f)) << u.name << " " << u.f << " " << v.f;
      EXPECT_TRUE(near(u.p_f, v.p_f)) << u.name;
      EXPECT_TRUE(near(u.delta_bic, v.delta_bic)) << u.name;
      EXPECT_TRUE(near(u.effect_rms_um, v.effect_rms_um)) << u.name;
      EXPECT_TRUE(u.p_null == v.p_null || (std::isnan(u.p_null) && std::isnan(v.p_null))) << u.name;
      EXPECT_EQ(u.accepted, v.accepted) << u.name;
    }
  }
}

TEST(DiagnoseSelection, HolmDecidesWhenTheRawFTestPassesButTheAdjustedOneDoesNot) {
  // a = 0.55: F = 31 · 0.3025 = 9.38, raw p ≈ 0.0045 < α; with 5 candidates Holm multiplies the
  // smallest p by 5 (Holm 1979): ≈ 0.022 > α. ΔBIC = 32 ln(1/1.3025) + ln 32 = −5.0, so the
  // BIC gate is set to 4 here and only Holm can refuse.
  std::vector<CandidateDesign> five;
  for (int period : {2, 4, 8, 16, 32}) {
    five.push_back(walsh_candidate("w" + std::to_string(period), period));
  }
  SelectionOptions o = gate_options();
  o.min_delta_bic = 4.0;
  const Eigen::VectorXd y = walsh_residual(0.55);
  const Selection s = forward_select(five, y, 0.01, o);
  ASSERT_EQ(s.steps.size(), 1u);
  const CandidateTest& t = s.steps[0].tests[0];
  EXPECT_NEAR(t.f, 31.0 * 0.3025, 1e-9);
  ASSERT_LT(t.p_f, o.alpha);  // the unadjusted test would pass
  EXPECT_NEAR(t.p_holm, 5.0 * t.p_f, 1e-12);
  EXPECT_GE(t.p_holm, o.alpha);
  EXPECT_TRUE(t.bic_support);
  EXPECT_TRUE(t.practical);
  EXPECT_FALSE(t.significant);
  EXPECT_TRUE(s.selected.empty());
  // Control: the same residuals with R1 the only candidate (Holm over one test is the raw p):
  // every gate passes and it is selected, so it was Holm that refused it above.
  const Selection alone = forward_select({five[0]}, y, 0.01, o);
  ASSERT_EQ(alone.selected.size(), 1u);
  EXPECT_TRUE(alone.steps[0].tests[0].significant);
}

TEST(DiagnoseSelection, TheBicGateDecidesBetweenTwoSignificantEffects) {
  // One candidate (Holm = raw p). a² = 0.344: F = 10.7 (p ≈ 0.003 < α), ΔBIC = 32 ln(1/1.344) +
  // ln 32 = −6.0 > −10: significant and practical, refused by the BIC gate alone.
  // a² = 0.78: F = 24.2, ΔBIC = 32 ln(1/1.78) + ln 32 = −15.0 ≤ −10: selected.
  const std::vector<CandidateDesign> one = {walsh_candidate("r1", 2)};
  const SelectionOptions o = gate_options();
  const Selection weak = forward_select(one, walsh_residual(std::sqrt(0.344)), 0.01, o);
  const CandidateTest& w = weak.steps.at(0).tests.at(0);
  EXPECT_NEAR(w.delta_bic, 32.0 * std::log(1.0 / 1.344) + std::log(32.0), 1e-9);
  EXPECT_TRUE(w.significant);
  EXPECT_TRUE(w.practical);
  EXPECT_FALSE(w.bic_support);
  EXPECT_TRUE(weak.selected.empty());
  const Selection strong = forward_select(one, walsh_residual(std::sqrt(0.78)), 0.01, o);
  const CandidateTest& t = strong.steps.at(0).tests.at(0);
  EXPECT_NEAR(t.delta_bic, 32.0 * std::log(1.0 / 1.78) + std::log(32.0), 1e-9);
  EXPECT_TRUE(t.significant);
  EXPECT_TRUE(t.bic_support);
  ASSERT_EQ(strong.selected.size(), 1u);
  // Between the two: a gate of 5 accepts the weak one, so the threshold's sign matters.
  SelectionOptions loose = o;
  loose.min_delta_bic = 5.0;
  EXPECT_EQ(forward_select(one, walsh_residual(std::sqrt(0.344)), 0.01, loose).selected.size(), 1u);
}

// The re-test after the forward steps (selection.h): a compound candidate a = w2 + w4 + 0.4 w16
// explains more of y = w2 + 0.5 w4 + 0.1 r on its own ((32 + 16)² / (64 + 32 · 0.16) = 33.3)
// than b = w2 (32) or c = w4 (8), so it is selected first; b and c follow (each removes the part
// of the other that a cannot carry without its w16). Given b and c, a adds only w16, which y does
// not have: its drop-one reduction is 0 (F 0, p 1), so the re-test drops it, and b, which removes
// 32 · 1² = 32 µm² given c against c's 32 · 0.5² = 8, comes first (the headline). r = w2 ∘ w8 is
// orthogonal to every column (the residual noise: RSS 0.32 µm² on 32 points).
TEST(DiagnoseSelection, TheReTestDropsAnEffectTheOthersMakeRedundantAndOrdersByWhatEachExplains) {
  const CandidateDesign w2 = walsh_candidate("w2", 2), w4 = walsh_candidate("w4", 4);
  const CandidateDesign w8 = walsh_candidate("w8", 8), w16 = walsh_candidate("w16", 16);
  CandidateDesign a = w2;
  a.name = "a";
  a.x.col(0) = w2.x.col(0) + w4.x.col(0) + 0.4 * w16.x.col(0);
  CandidateDesign b = w2, c = w4;
  b.name = "b";
  c.name = "c";
  const Eigen::VectorXd y =
      w2.x.col(0) + 0.5 * w4.x.col(0) + 0.1 * w2.x.col(0).cwiseProduct(w8.x.col(0));
  SelectionOptions o = gate_options();
  o.max_effects = 3;
  const Selection s = forward_select({a, b, c}, y, 0.01, o);
  ASSERT_EQ(s.steps.size(), 3u);
  EXPECT_EQ(s.steps[0].tests[s.steps[0].accepted].name, "a");  // the forward choice
  ASSERT_EQ(s.selected.size(), 2u);
  EXPECT_EQ(s.selected[0], 1);  // b
  EXPECT_EQ(s.selected[1], 2);  // c
  ASSERT_EQ(s.dropped.size(), 1u);
  EXPECT_EQ(s.dropped[0].name, "a");
  EXPECT_NEAR(s.dropped[0].effect_rms_um, 0.0, 1e-9);
  EXPECT_NE(s.dropped[0].note.find("dropped: not significant given b, c"), std::string::npos)
      << s.dropped[0].note;
  ASSERT_EQ(s.retest.size(), 2u);
  EXPECT_NEAR(s.retest[0].effect_rms_um, std::sqrt(32.0 / 32.0), 1e-9);  // √(ΔRSS / n)
  EXPECT_NEAR(s.retest[1].effect_rms_um, std::sqrt(8.0 / 32.0), 1e-9);
  EXPECT_TRUE(s.retest[0].accepted && s.retest[1].accepted);
  // Control: without a the forward steps already find b then c, and nothing is dropped.
  const Selection plain = forward_select({b, c}, y, 0.01, o);
  EXPECT_EQ(plain.selected, (std::vector<int>{0, 1}));
  EXPECT_TRUE(plain.dropped.empty());
}

// The min-P null p-value is a Monte-Carlo p-value, (1 + #{null min p ≤ p}) / (1 + K)
// (Davison & Hinkley 1997, eq. 4.11): never 0, at least 1/(K + 1) however strong the effect.
// A strong Walsh signal (F = 31 · 4 = 124, no null replicate comes near) with K replicates:
// p_null is exactly 1/(K + 1), K = effective_null_replicates (at least 2/α − 1 = 199 at α 0.01).
TEST(DiagnoseSelection, TheNullPValueCountsTheDataAsOneOfTheReplicates) {
  const std::vector<CandidateDesign> one = {walsh_candidate("r1", 2)};
  SelectionOptions o = gate_options();
  o.null_replicates = 50;
  const int k = effective_null_replicates(o);
  EXPECT_EQ(k, 199);
  const Selection s = forward_select(one, walsh_residual(2.0), 0.01, o);
  const CandidateTest& t = s.steps.at(0).tests.at(0);
  EXPECT_DOUBLE_EQ(t.p_null, 1.0 / (1.0 + k));
  EXPECT_TRUE(t.significant);
}

}  // namespace
}  // namespace gearmc
