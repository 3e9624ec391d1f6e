// The diagnosis: selection, fit, gap before/after with null calibration, held-out check,
// spectrum, ambiguity and the verdict (see diagnosis.h).
#include "engine/apps/diagnose/diagnosis.h"

#include <Eigen/QR>
#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <numbers>
#include <sstream>
#include <tuple>

#include <tbb/parallel_for.h>

#include "core/constants.h"
#include "core/input_error.h"
#include "engine/apps/diagnose/cluster_tests.h"
#include "engine/apps/diagnose/diagnosis_stages.h"
#include "engine/apps/diagnose/linear_model.h"
#include "engine/apps/diagnose/readings_check.h"
#include "engine/statistics/distribution_fit.h"

namespace gearmc {

std::string_view spelling(DiagnosisStatus status) {
  return status == DiagnosisStatus::kTested ? "tested" : "not_enough_readings";
}

std::string_view spelling(DiagnosisFinding finding) {
  switch (finding) {
    case DiagnosisFinding::kNone:
      return "none";
    case DiagnosisFinding::kEffect:
      return "effect";
    case DiagnosisFinding::kUnexplained:
      return "unexplained";
    case DiagnosisFinding::kNotTested:
      return "not_tested";
  }
  return "?";
}
namespace {

using diagnosis_stages::floor_law;
using diagnosis_stages::State;

// Fitted coefficients of candidate `c` from a joint fit whose columns start at `offset`.
std::vector<FittedValue> coefficients_of(const CandidateDesign& c, const LeastSquaresFit& fit,
                                         int offset, double sigma2) {
  std::vector<FittedValue> out;
  int at = offset;
  for (std::size_t k = 0; k < c.coefficients.size(); ++k) {
    FittedValue v;
    v.name = c.coefficients[k];
    v.unit = c.units[k];
    if (c.observable[k]) {
      if (fit.estimable[at]) {
        v.estimable = true;
        v.value = fit.beta[at];
        v.std_error = std::sqrt(sigma2 * fit.cov_unscaled(at, at));
      }
      ++at;
    }
    out.push_back(v);
  }
  return out;
}

// probe_lobing: pretravel and per order amplitude / phase from the cos/sin pairs (delta method).
std::vector<FittedValue> lobing_parameters(const CandidateDesign& c,
                                           const std::vector<FittedValue>& coefficients,
                                           const LeastSquaresFit& fit, int offset, double sigma2) {
  std::vector<FittedValue> out;
  // Column of each coefficient in the joint fit (−1: not observable).
  std::vector<int> column(c.coefficients.size(), -1);
  for (std::size_t k = 0, at = static_cast<std::size_t>(offset); k < c.coefficients.size(); ++k) {
    if (c.observable[k]) column[k] = static_cast<int>(at++);
  }
  for (std::size_t k = 0; k < coefficients.size(); ++k) {
    if (coefficients[k].name == "pretravel_um") out.push_back(coefficients[k]);
  }
  for (std::size_t k = 0; k < coefficients.size(); ++k) {
    const std::string& name = coefficients[k].name;
    if (name.rfind("cos_", 0) != 0) continue;
    const std::string order_text = name.substr(4, name.size() - 4 - 3);  // cos_<k>_um
    const int order = std::stoi(order_text);
    std::size_t s = k;
    for (std::size_t m = 0; m < coefficients.size(); ++m) {
      if (coefficients[m].name == "sin_" + order_text + "_um") s = m;
    }
    FittedValue amplitude{"amplitude_" + order_text + "_um", "µm"};
    FittedValue phase{"phase_" + order_text + "_deg", "deg"};
    if (coefficients[k].estimable && coefficients[s].estimable && s != k) {
      const double a = coefficients[k].value, b = coefficients[s].value;
      const int ia = column[k], ib = column[s];
      const double vaa = sigma2 * fit.cov_unscaled(ia, ia), vbb = sigma2 * fit.cov_unscaled(ib, ib);
      const double vab = sigma2 * fit.cov_unscaled(ia, ib);
      const double amp = std::hypot(a, b);
      amplitude.value = amp;
      amplitude.estimable = true;
      phase.estimable = true;
      if (amp > 0.0) {
        amplitude.std_error =
            std::sqrt(std::max(0.0, a * a * vaa + b * b * vbb + 2 * a * b * vab)) / amp;
        double deg = std::atan2(b, a) * 180.0 / kPi / order;
        const double period = 360.0 / order;
        deg = std::fmod(deg, period);
        if (deg < 0.0) deg += period;
        phase.value = deg;
        const double var_angle =
            (b * b * vaa + a * a * vbb - 2 * a * b * vab) / (amp * amp * amp * amp);
        phase.std_error = std::sqrt(std::max(0.0, var_angle)) * 180.0 / kPi / order;
      } else {
        amplitude.std_error = std::sqrt(0.5 * (vaa + vbb));
      }
    }
    out.push_back(amplitude);
    out.push_back(phase);
  }
  return out;
}

// The point-law stage's options from the diagnosis's.
PointLawOptions point_law_options(const DiagnoseOptions& options, int replicates, int rows) {
  PointLawOptions po;
  po.alpha = options.selection.alpha;
  po.null_replicates = replicates;
  po.seed = options.selection.seed;
  po.min_delta_bic = options.selection.min_delta_bic;
  po.ambiguity_delta_bic = options.ambiguity_delta_bic;
  po.min_effect_rms_fraction = options.selection.min_effect_rms_fraction;
  po.white_fraction = options.point_law_white_fraction;
  po.white_normal_approximation = options.null_rows > 0 && rows > 2 * options.null_rows;
  po.leverage_correction = options.workpiece == Workpiece::kProduction;
  return po;
}

// The fitted effect of an accepted point law (noise σ or step q, their own values).
FittedEffect point_law_effect(const PointLawStage& stage, const std::vector<std::string>& names,
                              double model_variance) {
  const PointLawHypothesis& h = stage.best();
  FittedEffect e;
  e.name = h.name;
  e.absolute = true;
  FittedValue v{h.name == "noise" ? "sigma_um" : "step_um", "µm"};
  v.value = h.estimate;
  v.std_error = h.std_error;
  v.estimable = true;
  e.coefficients = {v};
  e.parameters = {v};
  CandidateTest& t = e.evidence;
  t.name = h.name;
  const auto found = std::find(names.begin(), names.end(), h.name);
  t.candidate = found == names.end() ? -1 : static_cast<int>(found - names.begin());
  t.added_rank = 1;
  t.dof_residual = static_cast<int>(h.residual.size()) - h.parameters;
  t.p_null = stage.white_p;
  t.delta_bic = h.delta_bic;
  t.effect_rms_um = std::sqrt(std::max(0.0, h.law.variance_um2() - model_variance));
  t.significant = t.bic_support = t.practical = t.accepted = true;
  t.note = std::string("point-law stage: the spread of single readings") +
           (h.tied ? " and the constant shift tied to it" : "") +
           "; p_null is the white-variance test's";
  e.fitted_rms_um = std::abs(h.law.mean_um());
  for (int k : stage.ambiguous) {
    const PointLawHypothesis& other = stage.hypotheses[static_cast<std::size_t>(k)];
    Ambiguity a;
    a.with = other.name;
    a.reason = "delta_bic";
    a.delta_bic_gap = other.bic - h.bic;
    a.separate_by = separating_measurement(h.name, other.name);
    e.ambiguous.push_back(std::move(a));
  }
  return e;
}

// Steps 2–4: the candidates' columns, forward selection, and the joint fit of the selected
// effects with each effect's coefficients, physical parameters and evidence.
void select_and_fit(State& state, Diagnosis& out) {
  const Residuals& residuals = state.residuals;
  const DiagnoseOptions& options = state.options;
  const SelectionOptions& so = options.selection;
  const int rows = state.rows;
  state.r.resize(rows);
  for (int k = 0; k < rows; ++k) {
    state.azimuths.push_back(residuals.points[k].context.azimuth_rad);
    state.r[k] = residuals.points[k].residual_um;
  }
  // The candidates' columns compressed with the residuals (the selection and the ambiguity checks
  // use only their inner products; candidates.h): no N-row matrix of every candidate is held.
  // A production gear: its own deviations (part_model.h) are in every model, the candidates are
  // selected on what they leave, and "before" is the part's fit alone.
  const PointContexts contexts(residuals.points, &ResidualPoint::context);
  const bool production = options.workpiece == Workpiece::kProduction;
  state.r_measured = state.r;
  const Eigen::VectorXd& r_measured = state.r_measured;
  if (production) {
    state.part = part_columns(residuals.points, options.turned_by_teeth);
    const double cells = static_cast<double>(rows) * state.part.columns();
    if (cells > kMaxPartCells) {
      throw InputError({"--workpiece", 0, 0},
                       "production: the part's deviations on " +
                           std::to_string(state.part.flanks.size()) + " flanks need " +
                           std::to_string(state.part.columns()) + " columns over " +
                           std::to_string(rows) +
                           " readings, more than this diagnosis holds (2e7 values); diagnose "
                           "fewer gears at once");
    }
    state.p_base = state.part.rank();
    if (rows - state.p_base < 2 * kPartTerms) {
      throw InputError({"--workpiece", 0, 0},
                       "production: " + std::to_string(rows) + " readings on " +
                           std::to_string(state.part.flanks.size()) +
                           " flanks leave too few beyond the part's own deviations (" +
                           std::to_string(state.p_base) +
                           " parameters): measure more points per flank");
    }
    state.r -= state.part.q * (state.part.q.transpose() * state.r);
    state.base_x = state.part.x;
    state.base_q = state.part.q;
  }
  // Several runs of one gear (a master's repeats, or a production gear's turned set-ups): their
  // set-ups' differences join the base when the readings show them (setup_model.h). A production
  // gear's gears without --turned-by are separate workpieces, their set-ups in their own part.
  if (!production || !options.turned_by_teeth.empty()) {
    state.setup = setup_columns(residuals.points);
    if (state.setup.x.cols() > 0) {
      Eigen::MatrixXd xs = state.setup.x, common = state.setup.common;
      if (state.p_base > 0) {
        xs -= state.base_q * (state.base_q.transpose() * xs);
        common -= state.base_q * (state.base_q.transpose() * common);
      }
      out.setups = test_setup_differences(xs, common, state.r, rows - state.p_base, so.alpha);
      if (out.setups.fitted) {
        const Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(xs);
        const int k = static_cast<int>(qr.rank());
        const Eigen::MatrixXd qs =
            (qr.householderQ() * Eigen::MatrixXd::Identity(rows, xs.cols())).leftCols(k);
        state.r -= qs * (qs.transpose() * state.r);
        const int before = static_cast<int>(state.base_x.cols());
        state.base_x.conservativeResize(rows, before + state.setup.x.cols());
        state.base_x.rightCols(state.setup.x.cols()) = state.setup.x;
        const int q_before = static_cast<int>(state.base_q.cols());
        state.base_q.conservativeResize(rows, q_before + k);
        state.base_q.rightCols(k) = qs;
        state.p_base += k;
        state.setup_in_base = true;
      }
    }
  }
  out.workpiece = options.workpiece;
  CompressedDesigns compressed =
      state.p_base > 0
          ? compressed_candidate_designs(contexts, state.r, options.candidates, state.base_q)
          : compressed_candidate_designs(contexts, state.r, options.candidates);
  for (const CandidateDesign& c : compressed.candidates) out.candidate_names.push_back(c.name);

  // 3. Selection.
  out.selection = forward_select(compressed, state.noise.sigma_um, so);
  const std::vector<int>& selected = out.selection.selected;
  state.candidates = std::move(compressed.candidates);
  const std::vector<CandidateDesign>& candidates = state.candidates;

  // 4. Joint fit of the selected effects, on their N-row columns (and the part's, last). Fitted
  // to the measured residuals, so that the part's coefficients are its deviations; the effects'
  // coefficients and the residuals are those of the fit to the projected ones (Frisch–Waugh), and
  // `fitted` is made the fit of the projected residuals.
  state.x_selected = full_columns(contexts, options.candidates, candidates, selected);
  const int effect_columns = static_cast<int>(state.x_selected.cols());
  if (state.p_base > 0) {
    const int base_columns = static_cast<int>(state.base_x.cols());
    state.x_selected.conservativeResize(rows, effect_columns + base_columns);
    state.x_selected.rightCols(base_columns) = state.base_x;
    state.fit = least_squares(state.x_selected, r_measured);
    state.fit.fitted -= r_measured - state.r;
  } else {
    state.fit = least_squares(state.x_selected, state.r);
  }
  const Eigen::MatrixXd& x_selected = state.x_selected;
  const LeastSquaresFit& fit = state.fit;
  const int p = fit.rank;
  const double sigma2_hat = rows - p > 0 ? fit.rss / (rows - p) : kNotAvailable;
  std::vector<int>& offsets = state.offsets;
  for (std::size_t s = 0, at = 0; s < selected.size(); ++s) {
    offsets.push_back(static_cast<int>(at));
    at += candidates[selected[s]].observable_indices().size();
  }
  for (std::size_t s = 0; s < selected.size(); ++s) {
    const CandidateDesign& c = candidates[selected[s]];
    FittedEffect e;
    e.name = c.name;
    e.step = static_cast<int>(s);
    e.settings = c.settings;
    e.coefficients = coefficients_of(c, fit, offsets[s], sigma2_hat);
    e.parameters = c.name == "probe_lobing"
                       ? lobing_parameters(c, e.coefficients, fit, offsets[s], sigma2_hat)
                       : e.coefficients;
    // The forward step that accepted this candidate (the re-test may reorder the kept effects,
    // or put a smaller one in place of one: then its drop-one test in the final model).
    const auto step = std::find_if(
        out.selection.steps.begin(), out.selection.steps.end(), [&](const SelectionStep& st) {
          return st.accepted >= 0 && st.tests[st.accepted].candidate == selected[s];
        });
    if (step != out.selection.steps.end()) {
      e.evidence = step->tests[step->accepted];
    } else if (s < out.selection.retest.size()) {
      e.evidence = out.selection.retest[s];
    }
    const int q = static_cast<int>(c.observable_indices().size());
    const Eigen::VectorXd contribution =
        x_selected.middleCols(offsets[s], q) * fit.beta.segment(offsets[s], q);
    e.fitted_rms_um = std::sqrt(contribution.squaredNorm() / rows);
    out.effects.push_back(std::move(e));
  }
  if (state.setup_in_base) {
    const int k = static_cast<int>(state.setup.x.cols());
    const int first = static_cast<int>(x_selected.cols()) - k;
    for (int run = 0; 3 * run < k; ++run) {
      SetupRun v;
      v.gear = state.setup.gears[static_cast<std::size_t>(run + 1)];
      const int at = first + 3 * run;
      auto value = [&](int c, double& x, double& se) {
        if (!fit.estimable[at + c]) return;
        x = fit.beta[at + c];
        se = std::sqrt(sigma2_hat * fit.cov_unscaled(at + c, at + c));
      };
      value(0, v.shift_x_um, v.shift_x_se_um);
      value(1, v.shift_y_um, v.shift_y_se_um);
      value(2, v.turn_urad, v.turn_se_urad);
      out.setups.runs.push_back(v);
    }
    out.setups.rms_um =
        std::sqrt((state.setup.x * fit.beta.tail(k)).squaredNorm() / std::max(1, rows));
    // A selected eccentricity or clocking is the first run's set-up; each other run's is it plus
    // that run's difference (variance var a + var b + 2 cov(a, b) from the joint fit).
    for (std::size_t s = 0; s < selected.size(); ++s) {
      FittedEffect& e = out.effects[s];
      const bool turn = e.name == "clocking";
      if (e.name != "eccentricity" && !turn) continue;
      e.varies_per_gear = true;
      e.per_gear_from_setups = true;
      e.per_gear_p = out.setups.p_value;
      const CandidateDesign& c = candidates[selected[s]];
      FittedEffect::GearValues reference;
      reference.gear = state.setup.gears.front();
      reference.coefficients = e.coefficients;
      e.per_gear.push_back(reference);
      for (std::size_t run = 1; run < state.setup.gears.size(); ++run) {
        FittedEffect::GearValues values;
        values.gear = state.setup.gears[run];
        int column = 0;
        for (std::size_t v = 0; v < e.coefficients.size(); ++v) {
          FittedValue value = e.coefficients[v];
          if (c.observable[v]) {
            const int a = offsets[s] + column++;
            // shift_x, shift_y (eccentricity x_um, y_um) or the turn (clocking angle_urad).
            const int b = first + 3 * static_cast<int>(run - 1) + (turn ? 2 : static_cast<int>(v));
            value.estimable = fit.estimable[a] && fit.estimable[b];
            value.value = value.estimable ? fit.beta[a] + fit.beta[b] : kNotAvailable;
            value.std_error =
                value.estimable
                    ? std::sqrt(sigma2_hat * (fit.cov_unscaled(a, a) + fit.cov_unscaled(b, b) +
                                              2.0 * fit.cov_unscaled(a, b)))
                    : kNotAvailable;
          }
          values.coefficients.push_back(value);
        }
        e.per_gear.push_back(std::move(values));
      }
    }
  }
  if (production) {
    const int k = state.part.columns();
    const int first = effect_columns;
    std::vector<bool> estimable(fit.estimable.begin() + first, fit.estimable.begin() + first + k);
    out.part = part_deviations(state.part, fit.beta.segment(first, k),
                               fit.cov_unscaled.block(first, first, k, k), estimable, sigma2_hat);
    out.part.turned_by_teeth = options.turned_by_teeth;
    out.part.fitted_rms_um =
        std::sqrt((state.part.x * fit.beta.segment(first, k)).squaredNorm() / std::max(1, rows));
    for (std::size_t c = 0; c < compressed.base_correlation.size(); ++c) {
      const double rho = compressed.base_correlation[c];
      if (!(rho >= kPartConfoundedCorrelation)) continue;
      PartConfounding pc;
      pc.effect = candidates[c].name;
      pc.correlation = rho;
      pc.indistinguishable = rho >= kPartIndistinguishable;
      pc.separate_by = separate_from_part(pc.effect);
      out.part.confounded.push_back(std::move(pc));
    }
  }
  // Until the point-law stage says otherwise: the linear fit's residuals under the floor's law.
  state.law_before = floor_law(state.noise);
  state.law_after = state.law_before;
  state.p_after = p;
  state.r_after = state.r - fit.fitted;
}

// Step 7: which library effects could also explain each selected effect.
void assess_ambiguity(const State& state, Diagnosis& out) {
  const DiagnoseOptions& options = state.options;
  const std::vector<CandidateDesign>& candidates = state.candidates;
  const std::vector<int>& selected = out.selection.selected;
  const LeastSquaresFit& fit = state.fit;
  const std::vector<int>& offsets = state.offsets;
  // Every column here is compressed (state.candidates: R's columns, the same inner products as
  // the N rows'), the selected effect's fitted signal too.
  // The condition number of the joint design of every selected effect and a candidate b not
  // selected: the same set of columns for each selected effect a, so computed once per b (in
  // parallel, into its own slot; the column order does not change singular values).
  std::vector<double> with_selected(candidates.size(), kNotAvailable);
  tbb::parallel_for(0, static_cast<int>(candidates.size()), [&](int b) {
    if (std::find(selected.begin(), selected.end(), b) != selected.end()) return;
    std::vector<int> joint = selected;
    joint.push_back(b);
    with_selected[static_cast<std::size_t>(b)] =
        scaled_condition_number(joint_columns(candidates, joint));
  });
  for (std::size_t s = 0; s < selected.size(); ++s) {
    FittedEffect& e = out.effects[s];
    const CandidateDesign& a = candidates[selected[s]];
    std::vector<int> others;
    for (std::size_t o = 0; o < selected.size(); ++o) {
      if (o != s) others.push_back(selected[o]);
    }
    const Eigen::MatrixXd q_others = orthonormal_basis(joint_columns(candidates, others)).q;
    const int q = static_cast<int>(a.observable_indices().size());
    Eigen::VectorXd signal =
        joint_columns(candidates, {selected[s]}) * fit.beta.segment(offsets[s], q);
    signal -= q_others * (q_others.transpose() * signal);
    Eigen::MatrixXd copy_a;
    const Eigen::MatrixXd q_a = orthonormal_basis(a.observable_columns(copy_a), q_others).q;
    copy_a.resize(0, 0);
    const SelectionStep& step = out.selection.steps[s];
    const double a_bic = step.tests[step.accepted].delta_bic;
    // Each other candidate on its own (in parallel, into its own slot; kept in library order).
    std::vector<Ambiguity> found(candidates.size());
    tbb::parallel_for(0, static_cast<int>(candidates.size()), [&](int b) {
      if (b == selected[s]) return;
      Ambiguity& amb = found[static_cast<std::size_t>(b)];
      amb.with = candidates[b].name;
      if (std::find(selected.begin(), selected.end(), b) != selected.end()) {
        // Two selected effects: separable only if their joint design is well conditioned.
        amb.condition_number = scaled_condition_number(joint_columns(candidates, {selected[s], b}));
        if (amb.condition_number > options.ambiguity_condition_number) {
          amb.reason = "condition_number";
        }
      } else {
        amb.condition_number = with_selected[static_cast<std::size_t>(b)];
        Eigen::MatrixXd copy_b;
        const Eigen::MatrixXd q_b =
            orthonormal_basis(candidates[b].observable_columns(copy_b), q_others).q;
        const std::vector<double> cc = canonical_correlations(q_a, q_b);
        amb.canonical_correlation = cc.empty() ? 0.0 : cc.front();
        const double norm = signal.norm();
        amb.signal_correlation =
            norm > 0.0 && q_b.cols() > 0 ? (q_b.transpose() * signal).norm() / norm : 0.0;
        const CandidateTest* test = nullptr;  // b's test at the step that selected a
        for (const CandidateTest& t : step.tests) {
          if (t.candidate == b) test = &t;
        }
        if (test) amb.delta_bic_gap = test->delta_bic - a_bic;
        if (amb.signal_correlation > options.ambiguity_correlation) {
          amb.reason = "signal_correlation";
        } else if (test && test->eligible() && amb.delta_bic_gap < options.ambiguity_delta_bic) {
          amb.reason = "delta_bic";
        }
      }
      if (!amb.reason.empty()) amb.separate_by = separating_measurement(a.name, amb.with);
    });
    for (Ambiguity& amb : found) {
      if (!amb.reason.empty()) e.ambiguous.push_back(std::move(amb));
    }
  }
}

// Step 4b: the point-law stage (point_law_stage.h): a fitted noise or step quantisation replaces
// the law of the residuals after, and a tied step the effects whose constant shift it explains.
void apply_point_law(State& state, Diagnosis& out) {
  const DiagnoseOptions& options = state.options;
  const int rows = state.rows;
  const std::vector<CandidateDesign>& candidates = state.candidates;
  const std::vector<int>& selected = out.selection.selected;
  const std::vector<int>& offsets = state.offsets;
  out.point_law = point_law_stage(state.r, state.x_selected, state.residuals.points, state.noise,
                                  point_law_options(options, out.null_replicates, rows));
  const PointLawStage& stage = out.point_law;
  const Eigen::MatrixXd& x_selected = state.x_selected;
  Eigen::MatrixXd& x_after = state.x_after;
  int& p_after = state.p_after;
  double& mean_after = state.mean_after;
  Eigen::VectorXd& r_after_c = state.r_after;
  ResidualLaw& law_after = state.law_after;
  const ResidualLaw& law_before = state.law_before;
  if (stage.chosen > 0) {
    const PointLawHypothesis& h = stage.best();
    x_after.resize(rows, static_cast<int>(h.columns.size()) + (h.constant_added ? 1 : 0));
    state.x_after_set = true;
    for (std::size_t k = 0; k < h.columns.size(); ++k) {
      x_after.col(static_cast<int>(k)) = x_selected.col(h.columns[k]);
    }
    if (h.constant_added) x_after.col(x_after.cols() - 1).setOnes();
    p_after = h.parameters;
    mean_after = h.law.mean_um();
    r_after_c = h.residual - Eigen::VectorXd::Constant(rows, mean_after);
    law_after = h.law;
    law_after.offset_um -= mean_after;
    // A tied step replaces the selected effects whose columns it dropped (their constant shift
    // is its mean); the other effects keep the linear fit's values.
    std::vector<FittedEffect> kept;
    int insert_at = -1;
    for (std::size_t s = 0; s < selected.size(); ++s) {
      const int q = static_cast<int>(candidates[selected[s]].observable_indices().size());
      bool any = false;
      for (int c = offsets[s]; c < offsets[s] + q; ++c) {
        any = any || std::find(h.columns.begin(), h.columns.end(), c) != h.columns.end();
      }
      if (any) {
        kept.push_back(std::move(out.effects[s]));
      } else if (insert_at < 0) {
        insert_at = static_cast<int>(kept.size());
      }
    }
    FittedEffect e = point_law_effect(stage, out.candidate_names, law_before.variance_um2());
    kept.insert(insert_at < 0 ? kept.end() : kept.begin() + insert_at, std::move(e));
    out.effects = std::move(kept);
    for (std::size_t k = 0; k < out.effects.size(); ++k) out.effects[k].step = static_cast<int>(k);
  } else if (stage.ran) {
    // The data reject a step quantisation whose mean would be the fitted constant shift: then a
    // constant-shift effect is not ambiguous with it.
    const PointLawHypothesis* tied = nullptr;
    for (const PointLawHypothesis& h : stage.hypotheses) {
      if (h.name == "step_quantization" && h.tied) tied = &h;
    }
    if (tied && tied->delta_bic >= options.ambiguity_delta_bic) {
      for (FittedEffect& e : out.effects) {
        const auto before = e.ambiguous.size();
        std::erase_if(e.ambiguous,
                      [](const Ambiguity& a) { return a.with == "step_quantization"; });
        if (e.ambiguous.size() != before) {
          std::ostringstream text;
          text << e.name << " is not ambiguous with step_quantization: a step whose mean latch "
               << "delay made the fitted shift would have widened the spread of single readings, "
               << "which the residuals do not show (ΔBIC +" << std::lround(tied->delta_bic)
               << " against the model's law)";
          out.notes.push_back(text.str());
        }
      }
    }
  }
  out.noise_floor_after_um = std::sqrt(law_after.variance_um2());
}

}  // namespace

PreparedResiduals prepare_residuals(const Scenario& model, const Readings& readings,
                                    const std::string& readings_path,
                                    const DiagnoseOptions& options) {
  check_readings_against_model(model, readings, readings_path);
  Residuals all = compute_residuals(model, readings, options.prediction);
  check_residuals(all, readings, readings_path);
  PreparedResiduals out;
  out.outliers = screen_outliers(all);
  out.residuals = without_excluded(std::move(all), out.outliers);
  // Readings printed on a grid along the normal: dithered back to a continuous law (the floor
  // estimated from residuals then includes what rounding and dither add).
  out.reading_grid = detect_reading_grid(out.residuals.points);
  if (out.reading_grid.found()) {
    dither_readings(out.residuals.points, out.reading_grid.step_um, options.selection.seed);
  }
  out.noise = estimate_noise_floor(model, out.residuals);
  if (out.reading_grid.found() && out.noise.source == NoiseFloorSource::kModel) {
    const double s = out.reading_grid.step_um;
    out.noise.law.gaussian_variance_um2 += s * s / 12.0;
    out.noise.law.uniform_widths_um.push_back(s);
    out.noise.sigma_um = std::sqrt(out.noise.law.variance_um2());
  }
  if (options.noise_floor_um) {
    out.noise.sigma_um = *options.noise_floor_um;
    out.noise.source = NoiseFloorSource::kGiven;
    out.noise.law = PointLaw{out.noise.sigma_um * out.noise.sigma_um, {}};
  }
  // The coordinate grid (scale resolution): a latched grid the model lacks widens the model's
  // per-point law by its spread (a Gaussian part of its variance, as ScaleResolutionEffect's).
  std::vector<bool> excluded(readings.rows.size(), false);
  for (const ExcludedReading& e : out.outliers.excluded) {
    if (e.row >= 0 && e.row < static_cast<int>(excluded.size())) excluded[e.row] = true;
  }
  std::array<double, 3> model_steps = {0.0, 0.0, 0.0};
  if (const int index = model.effects->find("scale_resolution"); index >= 0) {
    const std::vector<double> values = model.effects->nominal()[static_cast<std::size_t>(index)];
    for (int a = 0; a < 3; ++a) model_steps[a] = values[static_cast<std::size_t>(a)];
  }
  out.grid = detect_coordinate_grid(readings, excluded, model_steps, out.noise.sigma_um,
                                    options.selection.min_effect_rms_fraction);
  if (out.grid.named && out.noise.source == NoiseFloorSource::kModel) {
    out.noise.law.gaussian_variance_um2 += out.grid.rms_um * out.grid.rms_um;
    out.noise.sigma_um = std::sqrt(out.noise.law.variance_um2());
  }
  return out;
}

Diagnosis diagnose_prepared(const PreparedResiduals& prepared, const DiagnoseOptions& options) {
  Diagnosis d = diagnose_residuals(prepared.residuals, prepared.noise, options);
  d.outliers = prepared.outliers;
  d.coordinate_grid = prepared.grid;
  d.reading_grid = prepared.reading_grid;
  if (prepared.reading_grid.found()) {
    std::ostringstream text;
    text << "the readings are printed on a grid of " << prepared.reading_grid.step_um
         << " µm along the normal (Rayleigh resultant " << prepared.reading_grid.resultant
         << "): each residual was dithered by U(−s/2, s/2) and the model's law widened by the "
            "rounding (s²/12) and the dither (a uniform part of width s), so that the rounding is "
            "not taken for structure";
    if (prepared.reading_grid.step_um > 0.5 * prepared.noise.sigma_um) {
      text << "; the step is coarse against the noise floor (" << prepared.noise.sigma_um
           << " µm), where this law is only approximate (it holds to the order of (step/σ)²): a "
              "gap found may be the rounding's, print the readings with more digits";
    }
    d.notes.push_back(text.str());
  }
  diagnosis_stages::coordinate_grid_verdict(prepared, d);
  const OutlierScreen& screen = d.outliers;
  if (!screen.excluded.empty()) {
    std::ostringstream text;
    text << screen.excluded.size() << " reading"
         << (screen.excluded.size() == 1 ? " was" : "s were")
         << " excluded as gross outliers (|z| > " << screen.threshold_z
         << " against their profile scan's neighbours, a 1 % false-alarm rate for the whole "
            "file); the diagnosis is made without them";
    d.notes.insert(d.notes.begin(), text.str());
  }
  if (!screen.not_applied.empty()) d.notes.push_back("outlier screen: " + screen.not_applied);
  return d;
}

Diagnosis diagnose(const Scenario& model, const Readings& readings,
                   const DiagnoseOptions& options) {
  return diagnose_prepared(prepare_residuals(model, readings, "", options), options);
}

Diagnosis diagnose_residuals(const Residuals& residuals, const NoiseFloor& noise,
                             const DiagnoseOptions& options) {
  Diagnosis out;
  const SelectionOptions& so = options.selection;
  out.noise = noise;
  out.points = static_cast<int>(residuals.points.size());
  out.nominal_fallback = residuals.nominal_fallback;
  out.null_replicates = effective_null_replicates(so);
  out.seed = so.seed;
  out.alpha = so.alpha;
  const int rows = out.points;
  if (!noise.not_enough.empty()) {  // nothing to judge the residuals against: no verdict
    out.status = DiagnosisStatus::kNotEnoughReadings;
    out.status_reason = noise.not_enough;
    out.finding = DiagnosisFinding::kNotTested;
    for (const ResidualPoint& p : residuals.points) out.residual_before_um.push_back(p.residual_um);
    out.residual_after_um = out.residual_before_um;
    double ss = 0.0;
    for (double v : out.residual_before_um) ss += v * v;
    out.gap_before.rms_um = out.gap_after.rms_um = std::sqrt(ss / std::max(1, rows));
    out.point_law.skipped_because = "no verdict: " + noise.not_enough;
    out.notes.push_back(noise.not_enough);
    return out;
  }

  State state(residuals, noise, options);
  state.rows = rows;
  select_and_fit(state, out);                        // 2–4
  diagnosis_stages::per_gear_variation(state, out);  // 4c (per_gear.cpp)
  assess_ambiguity(state, out);                      // 7
  apply_point_law(state, out);                       // 4b
  diagnosis_stages::measure_gap(state, out);         // 5 (diagnosis_gap.cpp)
  diagnosis_stages::simulate_null(state, out);       // 5–6
  diagnosis_stages::make_verdict(state, out);        // 8
  // rotary_table's angular positioning error turns each tooth exactly as the gear's own pitch
  // deviation of that tooth would: no candidate can hold the gear's pitch, so the verdict says it.
  for (const FittedEffect& e : out.effects) {
    if (e.name != "rotary_table") continue;
    out.notes.push_back(
        "rotary_table: its angular positioning error turns each tooth as the gear's own pitch "
        "deviations do, so from one set-up it is ambiguous with the pitch deviations of the "
        "gear (a master's calibrated pitch, if the model has it wrong); remeasure with the gear "
        "turned on the table by a few teeth to tell them apart");
  }
  return out;
}

}  // namespace gearmc
