// The diagnosis: selection, fit, gap before/after with null calibration, held-out check,
// spectrum, ambiguity and the verdict (see diagnosis.h).
#include "engine/diagnose/diagnosis.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>
#include <sstream>
#include <tuple>

#include "engine/diagnose/cluster_tests.h"
#include "engine/diagnose/linear_model.h"
#include "engine/diagnose/readings_check.h"
#include "engine/stats/distribution_fit.h"

namespace gearmc {
namespace {

constexpr double kPi = std::numbers::pi;
// Stream sub-index of the gap's null simulation (the selection steps use 0, 1, 2, …).
constexpr std::uint32_t kGapNullSubIndex = 1000;
// Stream sub-indices of the cluster-aware evidence (the point-law stage uses 2000).
constexpr std::uint32_t kClusterSubIndex = 3000;
constexpr int kBootstrapReplicates = 999;  // (R + 1) · 0.025 an integer (cluster_tests.h)

std::vector<double> to_vector(const Eigen::VectorXd& v) {
  return std::vector<double>(v.data(), v.data() + v.size());
}

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

// The centred law of a residual under the noise floor: the model's per-point law, or a Gaussian
// of the floor's σ when the floor carries none (given, or estimated from the residuals).
ResidualLaw floor_law(const NoiseFloor& noise) {
  if (noise.law.variance_um2() > 0.0) return residual_law(noise.law);
  ResidualLaw law;
  law.sigma_um = noise.sigma_um;
  return law;
}

// The point-law stage's options from the diagnosis's.
PointLawOptions point_law_options(const DiagnoseOptions& options, int replicates) {
  PointLawOptions po;
  po.alpha = options.selection.alpha;
  po.null_replicates = replicates;
  po.seed = options.selection.seed;
  po.min_delta_bic = options.selection.min_delta_bic;
  po.ambiguity_delta_bic = options.ambiguity_delta_bic;
  po.min_effect_rms_fraction = options.selection.min_effect_rms_fraction;
  po.white_fraction = options.point_law_white_fraction;
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

}  // namespace

Diagnosis diagnose(const Scenario& model, const Readings& readings,
                   const DiagnoseOptions& options) {
  check_readings_against_model(model, readings, "");
  const Residuals residuals = compute_residuals(model, readings, options.prediction);
  check_residuals(residuals, readings, "");
  NoiseFloor noise = estimate_noise_floor(model, residuals);
  if (options.noise_floor_um) {
    noise.sigma_um = *options.noise_floor_um;
    noise.source = "given";
    noise.law = PointLaw{noise.sigma_um * noise.sigma_um, {}};
  }
  return diagnose_residuals(residuals, noise, options);
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
  const double sigma = noise.sigma_um;
  if (!noise.not_enough.empty()) {  // nothing to judge the residuals against: no verdict
    out.status = "not_enough_readings";
    out.status_reason = noise.not_enough;
    out.named_effect = "not_tested";
    for (const ResidualPoint& p : residuals.points) out.residual_before_um.push_back(p.residual_um);
    out.residual_after_um = out.residual_before_um;
    double ss = 0.0;
    for (double v : out.residual_before_um) ss += v * v;
    out.gap_before.rms_um = out.gap_after.rms_um = std::sqrt(ss / std::max(1, rows));
    out.point_law.skipped_because = "no verdict: " + noise.not_enough;
    out.notes.push_back(noise.not_enough);
    return out;
  }

  std::vector<double> azimuths;
  Eigen::VectorXd r(rows);
  for (int k = 0; k < rows; ++k) {
    azimuths.push_back(residuals.points[k].context.azimuth_rad);
    r[k] = residuals.points[k].residual_um;
  }
  const std::vector<CandidateDesign> candidates = [&] {
    std::vector<PointContext> contexts;  // a copy only while the columns are made
    contexts.reserve(residuals.points.size());
    for (const ResidualPoint& p : residuals.points) contexts.push_back(p.context);
    return candidate_designs(contexts, options.candidates);
  }();
  for (const CandidateDesign& c : candidates) out.candidate_names.push_back(c.name);

  // 3. Selection.
  out.selection = forward_select(candidates, r, sigma, so);
  const std::vector<int>& selected = out.selection.selected;

  // 4. Joint fit of the selected effects.
  const Eigen::MatrixXd x_selected = joint_columns(candidates, selected);
  const LeastSquaresFit fit = least_squares(x_selected, r);
  const int p = fit.rank;
  const double sigma2_hat = rows - p > 0 ? fit.rss / (rows - p) : kNotAvailable;
  const Eigen::VectorXd r_after = r - fit.fitted;
  std::vector<int> offsets;
  for (std::size_t s = 0, at = 0; s < selected.size(); ++s) {
    offsets.push_back(static_cast<int>(at));
    at += candidates[selected[s]].observable_indices().size();
  }
  for (std::size_t s = 0; s < selected.size(); ++s) {
    const CandidateDesign& c = candidates[selected[s]];
    FittedEffect e;
    e.name = c.name;
    e.step = static_cast<int>(s);
    e.coefficients = coefficients_of(c, fit, offsets[s], sigma2_hat);
    e.parameters = c.name == "probe_lobing"
                       ? lobing_parameters(c, e.coefficients, fit, offsets[s], sigma2_hat)
                       : e.coefficients;
    const SelectionStep& step = out.selection.steps[s];
    e.evidence = step.tests[step.accepted];
    const int q = static_cast<int>(c.observable_indices().size());
    const Eigen::VectorXd contribution =
        x_selected.middleCols(offsets[s], q) * fit.beta.segment(offsets[s], q);
    e.fitted_rms_um = std::sqrt(contribution.squaredNorm() / rows);
    out.effects.push_back(std::move(e));
  }

  // 7. Ambiguity of each selected effect.
  for (std::size_t s = 0; s < selected.size(); ++s) {
    FittedEffect& e = out.effects[s];
    const CandidateDesign& a = candidates[selected[s]];
    std::vector<int> others;
    for (std::size_t o = 0; o < selected.size(); ++o) {
      if (o != s) others.push_back(selected[o]);
    }
    const Eigen::MatrixXd q_others = orthonormal_basis(joint_columns(candidates, others)).q;
    const int q = static_cast<int>(a.observable_indices().size());
    Eigen::VectorXd signal = x_selected.middleCols(offsets[s], q) * fit.beta.segment(offsets[s], q);
    signal -= q_others * (q_others.transpose() * signal);
    const Eigen::MatrixXd q_a = orthonormal_basis(a.observable_columns(), q_others).q;
    const SelectionStep& step = out.selection.steps[s];
    const double a_bic = step.tests[step.accepted].delta_bic;
    for (int b = 0; b < static_cast<int>(candidates.size()); ++b) {
      if (b == selected[s]) continue;
      Ambiguity amb;
      amb.with = candidates[b].name;
      if (std::find(selected.begin(), selected.end(), b) != selected.end()) {
        // Two selected effects: separable only if their joint design is well conditioned.
        amb.condition_number = scaled_condition_number(joint_columns(candidates, {selected[s], b}));
        if (amb.condition_number > options.ambiguity_condition_number) {
          amb.reason = "condition_number";
        }
      } else {
        std::vector<int> joint = others;
        joint.push_back(selected[s]);
        joint.push_back(b);
        amb.condition_number = scaled_condition_number(joint_columns(candidates, joint));
        const Eigen::MatrixXd q_b =
            orthonormal_basis(candidates[b].observable_columns(), q_others).q;
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
      if (amb.reason.empty()) continue;
      amb.separate_by = separating_measurement(a.name, amb.with);
      e.ambiguous.push_back(std::move(amb));
    }
  }

  // 4b. The point-law stage: a fitted noise or step quantisation (point_law_stage.h).
  out.point_law = point_law_stage(r, x_selected, residuals.points, noise,
                                  point_law_options(options, out.null_replicates));
  const PointLawStage& stage = out.point_law;
  const ResidualLaw law_before = floor_law(noise);
  ResidualLaw law_after = law_before;
  Eigen::MatrixXd x_after = x_selected;
  int p_after = p;
  double mean_after = 0.0;  // the fitted law's mean (the shift a tied step explains)
  Eigen::VectorXd r_after_c = r_after;
  if (stage.chosen > 0) {
    const PointLawHypothesis& h = stage.best();
    x_after.resize(rows, static_cast<int>(h.columns.size()) + (h.constant_added ? 1 : 0));
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

  // 5. Gap before / after and held-out check.
  out.residual_before_um = to_vector(r);
  out.residual_after_um = to_vector(r_after_c);
  out.gap_before = gap_statistics(r, rows, law_before);
  out.gap_after = gap_statistics(r_after_c, rows - p_after, law_after);
  if (out.effects.empty()) {
    out.held_out_rms_um = out.gap_before.rms_um;
  } else {
    double ss = 0.0;
    // Fit on the odd teeth (half 0) or the even ones (half 1), evaluate on the other half.
    for (int half = 0; half < 2; ++half) {
      std::vector<int> train, test;
      for (int k = 0; k < rows; ++k) {
        (residuals.points[k].tooth % 2 == (half == 0 ? 1 : 0) ? train : test).push_back(k);
      }
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
    }
    out.held_out_rms_um = std::sqrt(ss / rows);
  }

  // 5–6. Null simulation of the gap statistics and the spectrum.
  const HarmonicSpectrum spectrum(azimuths, options.spectrum_max_order);
  out.spectrum_before_um = spectrum.amplitudes(r);
  out.spectrum_after_um = spectrum.amplitudes(r_after_c);
  const Eigen::MatrixXd q_after = orthonormal_basis(x_after).q;
  const bool reestimate =
      noise.source == "residual_second_differences" || noise.source == "residual_mad";
  const std::vector<std::array<int, 3>> triplets =
      reestimate ? scan_triplets(residuals.points) : std::vector<std::array<int, 3>>{};
  std::vector<double> chi2_before, chi2_after, ks_before, ks_after;
  const int orders = options.spectrum_max_order + 1;
  std::vector<std::vector<double>> amp_before(orders), amp_after(orders);
  Eigen::VectorXd eps(rows), eps_law_after(rows);
  // With no spread at all (σ = 0) the null is simulated at unit σ and the bands scaled to 0.
  const bool unit = !(law_before.variance_um2() > 0.0);
  ResidualLaw sim_before = law_before, sim_after = law_after;
  if (unit) sim_before = sim_after = ResidualLaw{1.0, 0.0, 0.0};
  const double band_scale = unit ? 0.0 : 1.0;
  for (int k = 0; k < out.null_replicates; ++k) {
    RandomStream rng(so.seed, static_cast<std::uint32_t>(k), kDiagnoseNullStream, kGapNullSubIndex);
    for (int i = 0; i < rows; ++i) eps[i] = sim_before.draw(rng);
    ResidualLaw l_before = sim_before, l_after = sim_after;
    if (reestimate) {
      const std::vector<double> e = to_vector(eps);
      const double estimate =
          noise.source == "residual_mad" ? mad_sigma(e) : robust_noise_sigma(triplets, e);
      // As the data's floor: never below the numerical floor.
      l_before.sigma_um = l_after.sigma_um = std::max(estimate, noise.numerical_um);
    }
    if (stage.chosen > 0) {  // the fitted law: its own draws
      RandomStream rng_after(so.seed, static_cast<std::uint32_t>(k), kDiagnoseNullStream,
                             kGapNullSubIndex + 1);
      for (int i = 0; i < rows; ++i) eps_law_after[i] = sim_after.draw(rng_after);
    } else {
      eps_law_after = eps;
    }
    const Eigen::VectorXd eps_after =
        eps_law_after - q_after * (q_after.transpose() * eps_law_after);
    const GapStatistics gb = gap_statistics(eps, rows, l_before);
    const GapStatistics ga = gap_statistics(eps_after, rows - p_after, l_after);
    chi2_before.push_back(gb.chi2_dof);
    chi2_after.push_back(ga.chi2_dof);
    ks_before.push_back(gb.ks);
    ks_after.push_back(ga.ks);
    const std::vector<double> sb = spectrum.amplitudes(eps), sa = spectrum.amplitudes(eps_after);
    for (int o = 0; o < orders; ++o) {
      amp_before[o].push_back(sb[o] * band_scale);
      amp_after[o].push_back(sa[o] * band_scale);
    }
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
    y_after -= q_after * (q_after.transpose() * y_after);
    const std::vector<double> before = to_vector(r), after = to_vector(r_after_c);
    const std::vector<double> yb = to_vector(y_before), ya = to_vector(y_after);
    int sub = kClusterSubIndex + 1;
    for (auto [g, x, y] :
         {std::tuple{&out.gap_before, &before, &yb}, std::tuple{&out.gap_after, &after, &ya}}) {
      const PermutationTest test =
          cluster_swap_energy_test(*x, *y, flank, out.null_replicates, so.seed, sub++);
      g->energy_um = test.statistic;
      g->energy_p = test.p_value;
      const BootstrapInterval ci =
          cluster_bootstrap_rms(*x, tooth, kBootstrapReplicates, so.seed, sub++);
      g->rms_lo_um = ci.lo;
      g->rms_hi_um = ci.hi;
    }
  }

  // 8. The verdict.
  const double practical = so.min_effect_rms_fraction * sigma;
  // At the numerical floor the floor is a bound on exactness, not a law of the residuals: only
  // residuals beyond it (χ²) make a gap, not their shape (KS).
  const bool shape_test = !noise.at_numerical_floor;
  auto gap_rejects = [&](const GapStatistics& g) {
    return (g.chi2_p < so.alpha && g.excess_rms_um >= practical) ||
           (shape_test && g.ks_p < so.alpha);
  };
  out.gap_detected = !selected.empty() || stage.chosen > 0 || gap_rejects(out.gap_before);
  out.unexplained_structure = gap_rejects(out.gap_after);
  const double v0 = law_before.variance_um2();
  const double excess = r.squaredNorm() - rows * v0;
  const double explained = stage.chosen > 0 ? r.squaredNorm() - r_after_c.squaredNorm() +
                                                  rows * (law_after.variance_um2() - v0)
                                            : r.squaredNorm() - fit.rss;
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
  if (stage.chosen == 0 && noise.source == "model" && noise.robust_um > 0.0 &&
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
  if (!out.gap_detected) {
    out.named_effect = "none";
  } else if (!out.effects.empty() && out.explained_fraction >= options.min_explained_fraction) {
    out.named_effect = out.effects.front().name;
    for (const Ambiguity& a : out.effects.front().ambiguous) out.ambiguous_with.push_back(a.with);
  } else {
    out.named_effect = "unexplained";
  }
  return out;
}

}  // namespace gearmc
