// Implementation of r_test_evaluation.h. GUM: JCGM 100:2008 (law of propagation 5.1.2,
// Welch–Satterthwaite G.4.1, k from Student's t G.3); Monte Carlo: JCGM 101:2008 (§7.6 estimate
// and u, §7.7 probabilistically symmetric interval).
#include "engine/apps/r_test/r_test_evaluation.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <iomanip>
#include <limits>
#include <optional>
#include <sstream>
#include <string>

#include "core/constants.h"
#include "core/thread_arena.h"
#include "engine/apps/uncertainty/gum.h"
#include "engine/apps/uncertainty/mcm.h"

namespace gearmc::rtest {
namespace {

// Runs body(t) for t in [0, n) in parallel chunks; stops early (returns false) when cancelled.
template <typename Body>
bool parallel_trials(std::uint64_t n, const std::atomic<bool>* cancel, Body body) {
  constexpr std::uint64_t kChunk = 1 << 16;
  for (std::uint64_t first = 0; first < n; first += kChunk) {
    if (cancel && cancel->load()) return false;
    const std::uint64_t last = std::min(n, first + kChunk);
    tbb::parallel_for(tbb::blocked_range<std::uint64_t>(first, last, 256),
                      [&](const tbb::blocked_range<std::uint64_t>& r) {
                        for (std::uint64_t t = r.begin(); t != r.end(); ++t) body(t);
                      });
  }
  return true;
}

// Monte-Carlo statistics of one axis from its values (NaN = failed trial, left out).
AxisResult mc_axis(std::vector<double> v, double p) {
  v.erase(std::remove_if(v.begin(), v.end(), [](double x) { return !std::isfinite(x); }), v.end());
  AxisResult a;
  // Too few values left for a coverage interval (most trials failed: the run is refused by
  // r_test_refusal, kMaxFailedShare): no statistics, rather than an interval read past the end.
  if (v.size() < 2 || uncertainty::coverage_count(v.size(), p) >= v.size()) return a;
  double mean = 0.0;
  for (double x : v) mean += x;
  mean /= static_cast<double>(v.size());
  double ss = 0.0;
  for (double x : v) ss += (x - mean) * (x - mean);
  a.estimate = mean;
  a.u = std::sqrt(ss / static_cast<double>(v.size() - 1));
  uncertainty::sort_values(v);
  const uncertainty::Interval I = uncertainty::symmetric_interval(v, p);
  a.lo = I.lo;
  a.hi = I.hi;
  a.U = 0.5 * (I.hi - I.lo);
  a.k = a.u > 0 ? a.U / a.u : 0.0;
  return a;
}

// Per-class root-sum-square of contributions.
struct ClassSum {
  std::array<Vector3d, kClasses> sq;
  ClassSum() { sq.fill(Vector3d::Zero()); }
  void add(int c, const Vector3d& contribution) { sq[c] += contribution.cwiseAbs2(); }
};

Prediction gum_prediction(const std::string& id, const std::string& label,
                          const std::vector<Vector3d>& contributions,
                          const std::vector<double>& dof, const Vector3d& estimate, double p) {
  Prediction pr;
  pr.id = id;
  pr.label = label;
  for (int k = 0; k < 3; ++k) {
    pr.axis[k] = combine(contributions, dof, k, p);
    pr.axis[k].estimate = estimate[k];
    pr.axis[k].lo = estimate[k] - pr.axis[k].U;
    pr.axis[k].hi = estimate[k] + pr.axis[k].U;
  }
  return pr;
}

// The inputs of one sensor's calibration as data directions, with their class.
struct CalInput {
  int cls;
  DataDirection dir;
  std::string name;
};

std::vector<CalInput> calibration_inputs(const RTestModel& m) {
  std::vector<CalInput> in;
  static const char* axes = "xyz";
  for (int j = 0; j < kCalibrationPoints; ++j) {
    DataDirection d;
    d.reading[j] = 1.0;
    for (int c : {kLinearity, kRepeatability, kResolution}) {
      in.push_back({c, d, "l_" + std::to_string(j + 1)});
    }
  }
  for (int c : {kTipForm, kBallForm}) {
    if (m.settings.form_per_sensor) {
      DataDirection d;
      d.rho.fill(1.0);
      in.push_back({c, d, "rho"});
    } else {
      for (int j = 0; j < kCalibrationPoints; ++j) {
        DataDirection d;
        d.rho[j] = 1.0;
        in.push_back({c, d, "rho_" + std::to_string(j + 1)});
      }
    }
  }
  for (int j = 0; j < kCalibrationPoints; ++j) {
    for (int k = 0; k < 3; ++k) {
      DataDirection d;
      d.point[j][k] = 1.0;
      in.push_back({kPositioning, d, std::string("P_") + std::to_string(j + 1) + axes[k]});
    }
  }
  return in;
}

}  // namespace

AxisResult combine(const std::vector<Vector3d>& contributions, const std::vector<double>& dof,
                   int coordinate, double p) {
  AxisResult a;
  std::vector<double> c;
  double var = 0.0;
  for (const Vector3d& v : contributions) {
    c.push_back(std::abs(v[coordinate]));
    var += v[coordinate] * v[coordinate];
  }
  a.u = std::sqrt(var);
  a.nu_eff = uncertainty::welch_satterthwaite(a.u, c, dof);
  a.k = uncertainty::coverage_factor(p, a.nu_eff);
  a.U = a.k * a.u;
  return a;
}

bool full_mcm_trial(const RTestModel& m, std::uint64_t trial, Vector3d& error) {
  TrialStream s(m.seed, trial, TrialPurpose::kRTestFullMcm);
  const FormErrors form = draw_form_errors(m, s);
  const Calibration cal = simulate_calibration(m, form, s);
  const Measurement meas = simulate_measurement(m, cal.base, form, m.measured, s);
  error = meas.centre.centre - m.measured;
  return cal.ok && meas.centre.ok;
}

Prediction whole_chain_gum(const RTestModel& m, const Calibration& cal, const Vector3d& ball) {
  const Geometry& g = m.geometry;
  const double rho = g.contact_radius();
  Vector3d l;
  for (int i = 0; i < kSensors; ++i) l[i] = reading_for(cal.base[i], g.axis[i], ball, rho);
  const BallCentreDerivatives B = ball_centre_derivatives(cal.base, g.axis, l, ball);
  std::vector<Vector3d> contrib;
  std::vector<double> dof;
  ClassSum sums;
  auto add = [&](int c, const Vector3d& sens) {
    const Vector3d v = sens * m.laws[c].u;
    contrib.push_back(v);
    dof.push_back(m.laws[c].dof);
    sums.add(c, v);
  };
  std::array<SensorFitDerivatives, kSensors> D;
  for (int i = 0; i < kSensors; ++i) {
    D[i] = sensor_fit_derivatives(g.axis[i], cal.data[i], cal.base[i]);
  }
  for (int i = 0; i < kSensors; ++i) {
    // Indication of the calibration readings: the fit datum l_j carries +η.
    for (int j = 0; j < kCalibrationPoints; ++j) {
      const Vector3d s = B.d_base[i] * D[i].d_reading.col(j);
      for (int c : {kLinearity, kRepeatability, kResolution}) add(c, s);
    }
    // Form: the true R + r is ρ + φ, the fit and the solve use ρ: both data are off by −φ.
    for (int c : {kTipForm, kBallForm}) {
      if (m.settings.form_per_sensor) {
        Vector3d dC = Vector3d::Zero();
        for (int j = 0; j < kCalibrationPoints; ++j) dC -= D[i].d_rho.col(j);
        add(c, B.d_base[i] * dC - B.d_rho.col(i));
      } else {
        for (int j = 0; j < kCalibrationPoints; ++j) {
          add(c, -(B.d_base[i] * D[i].d_rho.col(j)));
        }
        add(c, -B.d_rho.col(i));
      }
    }
    // Indication of the measuring reading.
    for (int c : {kLinearity, kRepeatability, kResolution}) add(c, B.d_reading.col(i));
  }
  // Positioning: the ball stood at P_j + ε, the fits use P_j (all three sensors at once).
  for (int j = 0; j < kCalibrationPoints; ++j) {
    for (int k = 0; k < 3; ++k) {
      Vector3d s = Vector3d::Zero();
      for (int i = 0; i < kSensors; ++i) s -= B.d_base[i] * D[i].d_point[j].col(k);
      add(kPositioning, s);
    }
  }
  Prediction pr = gum_prediction("gum_chain", "GUM, whole chain (correlations kept)", contrib, dof,
                                 Vector3d::Zero(), m.coverage_probability);
  for (int c = 0; c < kClasses; ++c) {
    pr.budget.push_back({input_class_names()[c], sums.sq[c].cwiseSqrt()});
  }
  return pr;
}

namespace {

// P3's GUM of the ball centre from independent C_i1, r, R (and the measuring readings when
// `readings`), at ball position `ball` with the fitted instrument's noise-free readings.
Prediction p3_gum(const RTestModel& m, const RTestResult& r, const Vector3d& ball, bool readings) {
  const Geometry& g = m.geometry;
  const double rho = g.contact_radius();
  Vector3d l;
  for (int i = 0; i < kSensors; ++i) {
    l[i] = reading_for(r.observed.base[i], g.axis[i], ball, rho);
  }
  const BallCentreDerivatives B = ball_centre_derivatives(r.observed.base, g.axis, l, ball);
  std::vector<Vector3d> contrib;
  std::vector<double> dof;
  std::vector<BudgetItem> budget;
  static const char* axes = "xyz";
  for (int i = 0; i < kSensors; ++i) {
    for (int k = 0; k < 3; ++k) {
      const BaseCoordinate& b = r.base[i][k];
      const Vector3d v = B.d_base[i].col(k) * b.u_exact;
      contrib.push_back(v);
      dof.push_back(b.nu_eff);
      budget.push_back({"C" + std::to_string(i + 1) + "1_" + axes[k], v.cwiseAbs()});
    }
  }
  const Vector3d d_rho = B.d_rho.rowwise().sum();  // ρ_i = R + r for every sensor
  for (int c : {kTipForm, kBallForm}) {
    const Vector3d v = d_rho * m.laws[c].u;
    contrib.push_back(v);
    dof.push_back(m.laws[c].dof);
    budget.push_back({c == kTipForm ? "r" : "R", v.cwiseAbs()});
  }
  if (readings) {
    Vector3d sq = Vector3d::Zero();
    for (int i = 0; i < kSensors; ++i) {
      for (int c : {kLinearity, kRepeatability, kResolution}) {
        const Vector3d v = B.d_reading.col(i) * m.laws[c].u;
        contrib.push_back(v);
        dof.push_back(m.laws[c].dof);
        sq += v.cwiseAbs2();
      }
    }
    budget.push_back({"l_1..3 (measuring readings)", sq.cwiseSqrt()});
  }
  Prediction pr = gum_prediction(readings ? "gum_p3_readings" : "gum_p3",
                                 readings ? "GUM, P3's inputs + measuring readings"
                                          : "GUM, P3's route (C_i1 independent, r, R)",
                                 contrib, dof, r.estimate.centre, m.coverage_probability);
  pr.budget = budget;
  return pr;
}

Prediction p3_gum_mcm(const RTestModel& m, const RTestResult& r, bool readings,
                      const RTestRunOptions& o, bool& cancelled) {
  const auto start = std::chrono::steady_clock::now();
  const Geometry& g = m.geometry;
  const std::uint64_t M = o.trials;
  std::array<std::vector<double>, 3> values;
  for (auto& v : values) v.assign(M, kNaN);
  std::atomic<std::uint64_t> failed{0};
  const TrialPurpose purpose =
      readings ? TrialPurpose::kRTestGumMcmReadings : TrialPurpose::kRTestGumMcm;
  const bool done = parallel_trials(M, o.cancel, [&](std::uint64_t t) {
    TrialStream s(m.seed, t, purpose);
    Triple C;
    for (int i = 0; i < kSensors; ++i) {
      for (int k = 0; k < 3; ++k)
        C[i][k] = r.base[i][k].estimate + r.base[i][k].u_exact * s.normal();
    }
    const double tip = g.tip_radius + m.laws[kTipForm].u * s.normal();
    const double ball = g.ball_radius + m.laws[kBallForm].u * s.normal();
    Vector3d l = r.measured_readings;
    if (readings) {
      for (int i = 0; i < kSensors; ++i) l[i] += draw_indication(m, s);
    }
    const BallCentre P = solve_ball_centre(C, g.axis, l, Vector3d::Constant(tip + ball));
    if (!P.ok) {
      ++failed;
      return;
    }
    for (int k = 0; k < 3; ++k) values[k][t] = P.centre[k];
  });
  cancelled = cancelled || !done;
  Prediction pr;
  pr.id = readings ? "gum_mcm_p3_readings" : "gum_mcm_p3";
  pr.label = readings ? "GUM+MCM, P3's inputs + measuring readings"
                      : "GUM+MCM, P3's route (C_i1 ~ N independent, r, R)";
  pr.monte_carlo = true;
  pr.trials = M;
  pr.failed = failed;
  for (int k = 0; k < 3; ++k) pr.axis[k] = mc_axis(std::move(values[k]), m.coverage_probability);
  pr.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return pr;
}

Prediction full_mcm(const RTestModel& m, const RTestRunOptions& o, bool& cancelled) {
  const auto start = std::chrono::steady_clock::now();
  const std::uint64_t M = o.trials;
  std::array<std::vector<double>, 3> values;
  for (auto& v : values) v.assign(M, kNaN);
  std::atomic<std::uint64_t> failed{0};
  const bool done = parallel_trials(M, o.cancel, [&](std::uint64_t t) {
    Vector3d e;
    if (!full_mcm_trial(m, t, e)) {
      ++failed;
      return;
    }
    for (int k = 0; k < 3; ++k) values[k][t] = e[k];
  });
  cancelled = cancelled || !done;
  Prediction pr;
  pr.id = "full_mcm";
  pr.label = "full MCM (calibration inside the loop)";
  pr.monte_carlo = true;
  pr.trials = M;
  pr.failed = failed;
  for (int k = 0; k < 3; ++k) pr.axis[k] = mc_axis(std::move(values[k]), m.coverage_probability);
  pr.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return pr;
}

Verification verify(const RTestModel& m, const RTestResult& r, const RTestRunOptions& o,
                    bool& cancelled) {
  const auto start = std::chrono::steady_clock::now();
  Verification v;
  v.positions = verification_positions(m);
  const std::size_t np = v.positions.size();
  const std::size_t K = static_cast<std::size_t>(m.settings.repetitions);
  // errors[axis][rep * np + position]
  std::array<std::vector<double>, 3> errors;
  for (auto& e : errors) e.assign(K * np, kNaN);
  std::array<std::vector<double>, 3> at_measured;
  for (auto& e : at_measured) e.assign(K, kNaN);
  std::atomic<std::uint64_t> failed{0};
  const bool done = parallel_trials(K, o.cancel, [&](std::uint64_t rep) {
    TrialStream s(m.seed, rep, TrialPurpose::kRTestVerification);
    const FormErrors form = draw_form_errors(m, s);
    const Calibration cal = simulate_calibration(m, form, s);
    // The positions, then P_m (index np).
    for (std::size_t p = 0; p <= np; ++p) {
      const Vector3d commanded = p < np ? v.positions[p] : m.measured;
      Vector3d eps;
      for (int k = 0; k < 3; ++k) eps[k] = m.laws[kPositioning].law.sample(s);
      const Measurement meas = simulate_measurement(m, cal.base, form, commanded + eps, s);
      if (!cal.ok || !meas.centre.ok) {
        ++failed;
        continue;
      }
      // Against the commanded position, as on the machine.
      const Vector3d e = meas.centre.centre - commanded;
      for (int k = 0; k < 3; ++k) {
        if (p < np) {
          errors[k][rep * np + p] = e[k];
        } else {
          at_measured[k][rep] = e[k];
        }
      }
    }
  });
  cancelled = cancelled || !done;
  v.measurements = K * (np + 1);
  v.failed = failed;
  const double p = m.coverage_probability;
  for (std::size_t q = 0; q < np; ++q) {
    Vector3d a;
    for (int k = 0; k < 3; ++k) {
      std::vector<double> col(K);
      for (std::size_t rep = 0; rep < K; ++rep) col[rep] = errors[k][rep * np + q];
      a[k] = abs_quantile(std::move(col), p);
    }
    v.actual95.push_back(a);
    Prediction chain = whole_chain_gum(m, r.observed, v.positions[q]);
    Prediction p3 = p3_gum(m, r, v.positions[q], true);
    v.gum_chain_U.push_back(Vector3d(chain.axis[0].U, chain.axis[1].U, chain.axis[2].U));
    v.gum_p3_U.push_back(Vector3d(p3.axis[0].U, p3.axis[1].U, p3.axis[2].U));
  }
  for (int k = 0; k < 3; ++k) {
    double sum = 0.0, sq = 0.0;
    std::size_t n = 0;
    for (double e : errors[k]) {
      if (!std::isfinite(e)) continue;
      sum += e;
      sq += e * e;
      ++n;
    }
    v.mean[k] = n ? sum / double(n) : kNaN;
    v.rms[k] = n ? std::sqrt(sq / double(n)) : kNaN;
    v.pooled95[k] = abs_quantile(std::move(errors[k]), p);
    v.at_measured95[k] = abs_quantile(std::move(at_measured[k]), p);
  }
  v.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return v;
}

}  // namespace

RTestResult evaluate_r_test(const RTestModel& m, const RTestRunOptions& o) {
  RTestResult r;
  ThreadArena arena(o.threads);
  const Geometry& g = m.geometry;
  const double p = m.coverage_probability;

  // 1. The observed calibration and the observed readings at P_m.
  {
    TrialStream s(m.seed, 0, TrialPurpose::kRTestObserved);
    const FormErrors form = draw_form_errors(m, s);
    r.observed = simulate_calibration(m, form, s);
    const Measurement meas = simulate_measurement(m, r.observed.base, form, m.measured, s);
    r.measured_readings = meas.readings;
    r.estimate = meas.centre;
    if (!r.observed.ok) r.warnings.push_back("the observed calibration fit did not converge");
    if (!r.estimate.ok) r.warnings.push_back("the ball centre at P_m did not converge");
  }

  // 2. P3's GUM of the base points: sensitivities exact and varied-parameter.
  const std::vector<CalInput> inputs = calibration_inputs(m);
  for (int i = 0; i < kSensors; ++i) {
    const SensorData& data = r.observed.data[i];
    const Vector3d& C = r.observed.base[i];
    const SensorFitDerivatives D = sensor_fit_derivatives(g.axis[i], data, C);
    std::vector<Vector3d> exact, varied;
    std::vector<double> dof;
    ClassSum sums;
    VariedSensitivity last;
    for (std::size_t n = 0; n < inputs.size(); ++n) {
      const CalInput& in = inputs[n];
      const Vector3d se = directional_derivative(D, in.dir);
      // The indication classes of one reading (and tip and ball form) share one direction in
      // the data: it is varied once.
      if (n == 0 || in.name != inputs[n - 1].name) {
        last = varied_parameter_sensitivity(g.axis[i], data, C, in.dir, m.settings.varied_delta,
                                            m.settings.varied_step);
        r.varied_ok = r.varied_ok && last.ok;
        const double scale = std::max(se.norm(), 1e-300);
        r.sensitivity_max_rel_diff =
            std::max(r.sensitivity_max_rel_diff, (last.value - se).norm() / scale);
      }
      const double u = m.laws[in.cls].u;
      exact.push_back(se * u);
      varied.push_back(last.value * u);
      dof.push_back(m.laws[in.cls].dof);
      sums.add(in.cls, se * u);
    }
    for (int k = 0; k < 3; ++k) {
      BaseCoordinate& b = r.base[i][k];
      b.true_value = m.true_base[i][k];
      b.estimate = C[k];
      const AxisResult e = combine(exact, dof, k, p);
      b.u_exact = e.u;
      b.nu_eff = e.nu_eff;
      b.k = e.k;
      b.U = e.U;
      b.u_varied = combine(varied, dof, k, p).u;
      for (int c = 0; c < kClasses; ++c) b.budget[c] = std::sqrt(sums.sq[c][k]);
    }
  }
  if (!r.varied_ok) {
    r.warnings.push_back("a refit of the varied-parameter method did not converge");
  }

  arena.run([&] {
    // P3's routes at P_m.
    r.predictions.push_back(p3_gum(m, r, m.measured, false));
    r.predictions.push_back(p3_gum_mcm(m, r, false, o, r.cancelled));
    r.predictions.push_back(p3_gum(m, r, m.measured, true));
    r.predictions.push_back(p3_gum_mcm(m, r, true, o, r.cancelled));
    // The whole chain and the full MCM.
    r.predictions.push_back(whole_chain_gum(m, r.observed, m.measured));
    r.predictions.push_back(full_mcm(m, o, r.cancelled));
    r.verification = verify(m, r, o, r.cancelled);
  });
  for (const Prediction& pr : r.predictions) {
    if (pr.failed > 0) {
      r.warnings.push_back(pr.label + ": " + std::to_string(pr.failed) + " of " +
                           std::to_string(pr.trials) + " trials failed (left out)");
    }
  }
  if (r.verification.failed > 0) {
    r.warnings.push_back("verification: " + std::to_string(r.verification.failed) + " of " +
                         std::to_string(r.verification.measurements) +
                         " measurements failed (left out)");
  }
  return r;
}

double residual_rms_um(const Calibration& c) {
  double ss = 0.0;
  int n = 0;
  for (const SensorFit& f : c.fit) {
    for (double g_j : f.residuals) {
      ss += g_j * g_j;
      ++n;
    }
  }
  return n > 0 ? std::sqrt(ss / n) * kUmPerMm : kNaN;
}

std::string r_test_refusal(const RTestResult& r) {
  if (!r.observed.ok) {
    std::ostringstream rms;
    rms << std::setprecision(4) << residual_rms_um(r.observed);
    return "the observed calibration fit does not converge (residual RMS " + rms.str() + " µm)";
  }
  if (!r.estimate.ok) return "the ball centre at P_m does not converge";
  const auto too_many = [](std::uint64_t failed, std::uint64_t all) {
    return all > 0 && static_cast<double>(failed) > kMaxFailedShare * static_cast<double>(all);
  };
  for (const Prediction& pr : r.predictions) {
    if (too_many(pr.failed, pr.trials)) {
      return pr.label + ": " + std::to_string(pr.failed) + " of " + std::to_string(pr.trials) +
             " trials failed (more than 1 %)";
    }
  }
  if (too_many(r.verification.failed, r.verification.measurements)) {
    return "verification: " + std::to_string(r.verification.failed) + " of " +
           std::to_string(r.verification.measurements) + " measurements failed (more than 1 %)";
  }
  return "";
}

double abs_quantile(std::vector<double> v, double p) {
  for (double& x : v) x = std::abs(x);
  v.erase(std::remove_if(v.begin(), v.end(), [](double x) { return !std::isfinite(x); }), v.end());
  if (v.empty()) return kNaN;
  const std::size_t r = std::min<std::size_t>(
      v.size() - 1, static_cast<std::size_t>(std::ceil(p * static_cast<double>(v.size()))) - 1);
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(r), v.end());
  return v[r];
}

}  // namespace gearmc::rtest
