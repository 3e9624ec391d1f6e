// uncertainty.json and the terminal text of an R-Test evaluation (r_test_output.h).
#include <cmath>
#include <iomanip>
#include <sstream>

#include "core/constants.h"

#include "engine/apps/r_test/r_test_output.h"

namespace gearmc::rtest {
namespace {

nlohmann::ordered_json num(double v) {
  if (!std::isfinite(v)) return nullptr;
  return v;
}

nlohmann::ordered_json vec(const Vector3d& v, double scale = 1.0) {
  return {num(v[0] * scale), num(v[1] * scale), num(v[2] * scale)};
}

nlohmann::ordered_json axis_json(const AxisResult& a, bool error) {
  nlohmann::ordered_json j;
  j[error ? "mean_error_um" : "estimate_mm"] = error ? a.estimate * kUmPerMm : a.estimate;
  j["u_um"] = a.u * kUmPerMm;
  j["nu_eff"] = num(a.nu_eff);
  j["k"] = a.k;
  j["U_um"] = a.U * kUmPerMm;
  return j;
}

std::string fixed(double v, int d) {
  std::ostringstream s;
  s.setf(std::ios::fixed);
  s.precision(d);
  s << v;
  return s.str();
}

}  // namespace

nlohmann::ordered_json r_test_json(const uncertainty::UncertaintyModel& model, const RTestModel& m,
                                   const RTestResult& r, const RTestRunOptions& o,
                                   const Provenance& provenance) {
  nlohmann::ordered_json j;
  j["model"] = model.name;
  j["source"] = model.source_path;
  j["seed"] = m.seed;
  j["coverage_probability"] = m.coverage_probability;
  j["trials"] = o.trials;
  nlohmann::ordered_json inputs = nlohmann::ordered_json::object();
  for (int c = 0; c < kClasses; ++c) {
    inputs[input_class_names()[c]] = {
        {"law", m.laws[c].text}, {"u_um", m.laws[c].u * kUmPerMm}, {"dof", num(m.laws[c].dof)}};
  }
  j["inputs"] = inputs;
  nlohmann::ordered_json rt;
  const Geometry& g = m.geometry;
  const RTestSettings& s = m.settings;
  rt["instrument"] = {{"ball_radius_mm", g.ball_radius},
                      {"tip_radius_mm", g.tip_radius},
                      {"base_radius_mm", g.base_radius},
                      {"alpha_deg", g.alpha * 180.0 / M_PI},
                      {"centre_mm", vec(g.centre)},
                      {"reading_at_centre_mm", g.reading_at_centre()},
                      {"form_error_per_sensor", s.form_per_sensor}};
  nlohmann::ordered_json cal = nlohmann::ordered_json::array();
  for (int i = 0; i < kSensors; ++i) {
    nlohmann::ordered_json sj;
    sj["axis"] = vec(g.axis[i]);
    sj["nominal_base_mm"] = vec(g.base[i]);
    sj["true_base_mm"] = vec(m.true_base[i]);
    sj["fitted_base_mm"] = vec(r.observed.base[i]);
    sj["converged"] = r.observed.fit[i].ok;
    sj["iterations"] = r.observed.fit[i].iterations;
    nlohmann::ordered_json res = nlohmann::ordered_json::array();
    for (double g_j : r.observed.fit[i].residuals) res.push_back(g_j * kUmPerMm);
    sj["residuals_um"] = res;
    nlohmann::ordered_json coords = nlohmann::ordered_json::object();
    for (int k = 0; k < 3; ++k) {
      const BaseCoordinate& b = r.base[i][k];
      nlohmann::ordered_json bj;
      bj["estimate_mm"] = b.estimate;
      bj["true_mm"] = b.true_value;
      bj["u_um"] = b.u_exact * kUmPerMm;
      bj["u_varied_parameter_um"] = b.u_varied * kUmPerMm;
      bj["nu_eff"] = num(b.nu_eff);
      bj["k"] = b.k;
      bj["U_um"] = b.U * kUmPerMm;
      nlohmann::ordered_json budget = nlohmann::ordered_json::object();
      for (int c = 0; c < kClasses; ++c) budget[input_class_names()[c]] = b.budget[c] * kUmPerMm;
      bj["budget_um"] = budget;
      coords[std::string(1, "xyz"[k])] = bj;
    }
    sj["gum"] = coords;
    cal.push_back(sj);
  }
  rt["calibration"] = {{"points_mm", nlohmann::ordered_json::array()}, {"sensors", cal}};
  for (const Vector3d& P : m.calibration_points) rt["calibration"]["points_mm"].push_back(vec(P));
  rt["sensitivities"] = {{"varied_delta_mm", s.varied_delta},
                         {"varied_step_mm", s.varied_step},
                         {"max_relative_difference_varied_vs_exact", r.sensitivity_max_rel_diff},
                         {"varied_converged", r.varied_ok}};
  rt["measured_position_mm"] = vec(m.measured);
  rt["measured_readings_mm"] = vec(r.measured_readings);
  rt["estimate_mm"] = vec(r.estimate.centre);
  nlohmann::ordered_json preds = nlohmann::ordered_json::object();
  for (const Prediction& p : r.predictions) {
    nlohmann::ordered_json pj;
    pj["label"] = p.label;
    pj["method"] = p.monte_carlo ? "monte_carlo" : "gum";
    if (p.monte_carlo) {
      pj["trials"] = p.trials;
      pj["failed"] = p.failed;
      pj["wall_s"] = p.wall_s;
    }
    for (int k = 0; k < 3; ++k) {
      pj[std::string(1, "xyz"[k])] =
          axis_json(p.axis[k], p.id == "full_mcm" || p.id == "gum_chain");
    }
    if (!p.budget.empty()) {
      nlohmann::ordered_json b = nlohmann::ordered_json::object();
      for (const BudgetItem& item : p.budget) b[item.name] = vec(item.contribution, kUmPerMm);
      pj["budget_um"] = b;
    }
    preds[p.id] = pj;
  }
  rt["predictions"] = preds;
  const Verification& v = r.verification;
  nlohmann::ordered_json vj;
  vj["positions"] = v.positions.size();
  vj["repetitions"] = s.repetitions;
  vj["range_mm"] = s.verification_range;
  vj["measurements"] = v.measurements;
  vj["failed"] = v.failed;
  vj["actual_U_um"] = vec(v.pooled95, kUmPerMm);
  vj["actual_U_at_measured_position_um"] = vec(v.at_measured95, kUmPerMm);
  vj["mean_error_um"] = vec(v.mean, kUmPerMm);
  vj["rms_error_um"] = vec(v.rms, kUmPerMm);
  nlohmann::ordered_json dev = nlohmann::ordered_json::object();
  nlohmann::ordered_json dev_m = nlohmann::ordered_json::object();
  for (const Prediction& p : r.predictions) {
    Vector3d d, dm;
    for (int k = 0; k < 3; ++k) {
      d[k] = 100.0 * (p.axis[k].U / v.pooled95[k] - 1.0);
      dm[k] = 100.0 * (p.axis[k].U / v.at_measured95[k] - 1.0);
    }
    dev[p.id] = vec(d);
    dev_m[p.id] = vec(dm);
  }
  vj["deviation_percent"] = dev;
  vj["deviation_percent_at_measured_position"] = dev_m;
  vj["wall_s"] = v.wall_s;
  rt["verification"] = vj;
  nlohmann::ordered_json w = nlohmann::ordered_json::array();
  for (const std::string& s2 : r.warnings) w.push_back(s2);
  rt["warnings"] = w;
  j["r_test"] = rt;
  j["provenance"] = provenance_json(provenance);
  return j;
}

void print_r_test(std::ostream& out, const RTestModel& m, const RTestResult& r) {
  const Geometry& g = m.geometry;
  out << "R-Test: ball R " << g.ball_radius << " mm, tip r " << g.tip_radius << " mm, lambda "
      << g.base_radius << " mm, alpha " << fixed(g.alpha * 180 / M_PI, 2) << " deg, "
      << kCalibrationPoints << " calibration points at +-" << m.settings.calibration_step
      << " mm, form errors " << (m.settings.form_per_sensor ? "per sensor" : "per reading") << "\n";
  out << "calibration: residual RMS ";
  out << fixed(residual_rms_um(r.observed), 3) << " um, fits "
      << (r.observed.ok ? "converged" : "NOT converged") << "\n\n";
  out << "P3's GUM of the base points C_i1 (um; u by exact / varied-parameter sensitivities, "
         "nu = 50 per Type-B input)\n";
  out << "  coord     fitted-true       u exact  u varied    nu_eff     k        U\n";
  for (int i = 0; i < kSensors; ++i) {
    for (int k = 0; k < 3; ++k) {
      const BaseCoordinate& b = r.base[i][k];
      out << "  C" << i + 1 << "1_"
          << "xyz"[k] << std::setw(16) << fixed((b.estimate - b.true_value) * kUmPerMm, 3)
          << std::setw(14) << fixed(b.u_exact * kUmPerMm, 3) << std::setw(10)
          << fixed(b.u_varied * kUmPerMm, 3) << std::setw(10) << fixed(b.nu_eff, 0) << std::setw(6)
          << fixed(b.k, 3) << std::setw(9) << fixed(b.U * kUmPerMm, 3) << "\n";
    }
  }
  out << "  varied-parameter vs exact sensitivities: largest relative difference "
      << std::setprecision(2) << std::scientific << r.sensitivity_max_rel_diff << std::defaultfloat
      << std::setprecision(6) << "\n\n";
  out << "ball centre at P_m = O + (" << fixed(m.settings.measured_offset.x(), 3) << ", "
      << fixed(m.settings.measured_offset.y(), 3) << ", "
      << fixed(m.settings.measured_offset.z(), 3)
      << ") mm; expanded uncertainty U (p = " << m.coverage_probability << "), um\n";
  const Verification& v = r.verification;
  out << "  route                                                 U_x     U_y     U_z   vs "
         "actual, all positions (x, y, z)\n";
  for (const Prediction& p : r.predictions) {
    std::string label = p.label;
    label.resize(52, ' ');
    out << "  " << label;
    for (int k = 0; k < 3; ++k) out << std::setw(8) << fixed(p.axis[k].U * kUmPerMm, 3);
    out << "   ";
    for (int k = 0; k < 3; ++k) {
      const double d = 100.0 * (p.axis[k].U / v.pooled95[k] - 1.0);
      out << (d >= 0 ? " +" : " ") << fixed(d, 1) << "%";
    }
    out << "\n";
  }
  std::string label = "verification: actual 95 % |error|, all positions";
  label.resize(52, ' ');
  out << "  " << label;
  for (int k = 0; k < 3; ++k) out << std::setw(8) << fixed(v.pooled95[k] * kUmPerMm, 3);
  label = "verification: actual 95 % |error| at P_m";
  label.resize(52, ' ');
  out << "\n  " << label;
  for (int k = 0; k < 3; ++k) out << std::setw(8) << fixed(v.at_measured95[k] * kUmPerMm, 3);
  out << "   ";
  const Prediction& full = r.predictions.back();
  for (int k = 0; k < 3; ++k) {
    const double d = 100.0 * (full.axis[k].U / v.at_measured95[k] - 1.0);
    out << (d >= 0 ? " +" : " ") << fixed(d, 1) << "%";
  }
  out << " (full MCM vs this)";
  out << "\n  (" << v.positions.size() << " random positions x " << m.settings.repetitions
      << " repetitions with fresh calibration and measuring errors, " << v.failed
      << " failed; full MCM " << r.predictions.back().trials << " trials in "
      << fixed(r.predictions.back().wall_s, 2) << " s, verification " << fixed(v.wall_s, 2)
      << " s)\n";
}

}  // namespace gearmc::rtest
