// The diagnosis: selection, fit, gap before/after with null calibration, held-out check,
// spectrum, ambiguity and the verdict (see diagnosis.h).
#include "engine/diagnose/diagnosis.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <sstream>

#include "engine/diagnose/linear_model.h"
#include "engine/stats/distribution_fit.h"

namespace gearmc {
namespace {

constexpr double kPi = std::numbers::pi;
// Stream sub-index of the gap's null simulation (the selection steps use 0, 1, 2, …).
constexpr std::uint32_t kGapNullSubIndex = 1000;

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

// Gap statistics of residual vector r (dof = points − fitted parameters) with noise floor σ.
GapStatistics gap_statistics(const Eigen::VectorXd& r, int dof, double sigma) {
  GapStatistics g;
  const double n = static_cast<double>(r.size());
  const double ss = r.squaredNorm();
  g.rms_um = std::sqrt(ss / n);
  g.dof = dof;
  if (dof > 0 && sigma > 0.0) {
    g.chi2_dof = ss / (dof * sigma * sigma);
    g.excess_rms_um = std::sqrt(std::max(0.0, ss / dof - sigma * sigma));
    g.ks = ks_distance_normal(to_vector(r), sigma);
  }
  return g;
}

}  // namespace

Diagnosis diagnose(const Scenario& model, const Readings& readings,
                   const DiagnoseOptions& options) {
  const Residuals residuals = compute_residuals(model, readings, options.prediction);
  NoiseFloor noise = estimate_noise_floor(model, residuals);
  if (options.noise_floor_um) {
    noise.sigma_um = *options.noise_floor_um;
    noise.source = "given";
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

  std::vector<PointContext> contexts;
  std::vector<double> azimuths;
  Eigen::VectorXd r(rows);
  for (int k = 0; k < rows; ++k) {
    contexts.push_back(residuals.points[k].context);
    azimuths.push_back(residuals.points[k].context.azimuth_rad);
    r[k] = residuals.points[k].residual_um;
  }
  const std::vector<CandidateDesign> candidates = candidate_designs(contexts, options.candidates);
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

  // 5. Gap before / after and held-out check.
  out.residual_before_um = to_vector(r);
  out.residual_after_um = to_vector(r_after);
  out.gap_before = gap_statistics(r, rows, sigma);
  out.gap_after = gap_statistics(r_after, rows - p, sigma);
  if (selected.empty()) {
    out.held_out_rms_um = out.gap_before.rms_um;
  } else {
    double ss = 0.0;
    // Fit on the odd teeth (half 0) or the even ones (half 1), evaluate on the other half.
    for (int half = 0; half < 2; ++half) {
      std::vector<int> train, test;
      for (int k = 0; k < rows; ++k) {
        (residuals.points[k].tooth % 2 == (half == 0 ? 1 : 0) ? train : test).push_back(k);
      }
      Eigen::MatrixXd xt(static_cast<int>(train.size()), x_selected.cols());
      Eigen::VectorXd yt(static_cast<int>(train.size()));
      for (std::size_t k = 0; k < train.size(); ++k) {
        xt.row(static_cast<int>(k)) = x_selected.row(train[k]);
        yt[static_cast<int>(k)] = r[train[k]];
      }
      const LeastSquaresFit half_fit = least_squares(xt, yt);
      for (int k : test) {
        const double e = r[k] - x_selected.row(k).dot(half_fit.beta);
        ss += e * e;
      }
    }
    out.held_out_rms_um = std::sqrt(ss / rows);
  }

  // 5–6. Null simulation of the gap statistics and the spectrum.
  const HarmonicSpectrum spectrum(azimuths, options.spectrum_max_order);
  out.spectrum_before_um = spectrum.amplitudes(r);
  out.spectrum_after_um = spectrum.amplitudes(r_after);
  const Eigen::MatrixXd q_selected = orthonormal_basis(x_selected).q;
  const bool reestimate =
      noise.source == "residual_second_differences" || noise.source == "residual_mad";
  std::vector<double> chi2_before, chi2_after, ks_before, ks_after;
  const int orders = options.spectrum_max_order + 1;
  std::vector<std::vector<double>> amp_before(orders), amp_after(orders);
  Eigen::VectorXd eps(rows);
  const double sim_sigma = sigma > 0.0 ? sigma : 1.0;
  for (int k = 0; k < out.null_replicates; ++k) {
    RandomStream rng(so.seed, static_cast<std::uint32_t>(k), kDiagnoseNullStream, kGapNullSubIndex);
    for (int i = 0; i < rows; ++i) eps[i] = sim_sigma * rng.normal();
    double s_k = sim_sigma;
    if (reestimate) {
      const std::vector<double> e = to_vector(eps);
      s_k = noise.source == "residual_mad" ? mad_sigma(e) : robust_noise_sigma(residuals.points, e);
    }
    const Eigen::VectorXd eps_after = eps - q_selected * (q_selected.transpose() * eps);
    const GapStatistics gb = gap_statistics(eps, rows, s_k);
    const GapStatistics ga = gap_statistics(eps_after, rows - p, s_k);
    chi2_before.push_back(gb.chi2_dof);
    chi2_after.push_back(ga.chi2_dof);
    ks_before.push_back(gb.ks);
    ks_after.push_back(ga.ks);
    const std::vector<double> sb = spectrum.amplitudes(eps), sa = spectrum.amplitudes(eps_after);
    for (int o = 0; o < orders; ++o) {
      amp_before[o].push_back(sb[o] * sigma / sim_sigma);
      amp_after[o].push_back(sa[o] * sigma / sim_sigma);
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

  // 8. The verdict.
  const double practical = so.min_effect_rms_fraction * sigma;
  auto gap_rejects = [&](const GapStatistics& g) {
    return (g.chi2_p < so.alpha && g.excess_rms_um >= practical) || g.ks_p < so.alpha;
  };
  out.gap_detected = !selected.empty() || gap_rejects(out.gap_before);
  out.unexplained_structure = gap_rejects(out.gap_after);
  const double excess = r.squaredNorm() - rows * sigma * sigma;
  if (excess > 0.0) {
    out.explained_fraction = std::clamp((r.squaredNorm() - fit.rss) / excess, 0.0, 1.0);
  } else if (!selected.empty()) {
    out.explained_fraction = 1.0;
  }
  if (out.nominal_fallback > 0) {
    out.notes.push_back(std::to_string(out.nominal_fallback) +
                        " points are not in the model's probing plan (or had no valid model "
                        "contact) and were predicted with the nominal contact p + R n");
  }
  if (noise.source == "model" && noise.robust_um > 0.0 &&
      std::abs(noise.robust_um / noise.model_um - 1.0) > 0.2) {
    std::ostringstream text;
    text << "the residuals' own noise (robust estimate " << noise.robust_um
         << " µm) differs by more than 20 % from the model's noise floor " << noise.model_um
         << " µm";
    out.notes.push_back(text.str());
  }
  if (!out.gap_detected) {
    out.named_effect = "none";
  } else if (!selected.empty() && out.explained_fraction >= options.min_explained_fraction) {
    out.named_effect = out.effects.front().name;
    for (const Ambiguity& a : out.effects.front().ambiguous) out.ambiguous_with.push_back(a.with);
  } else {
    out.named_effect = "unexplained";
  }
  return out;
}

}  // namespace gearmc
