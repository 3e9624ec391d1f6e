// Implementation of r_test_model.h.
#include "engine/apps/r_test/r_test_model.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "core/input_error.h"
#include "engine/apps/uncertainty/model.h"
#include "engine/apps/uncertainty/model_function.h"

namespace gearmc::rtest {

const std::array<std::string, kClasses>& input_class_names() {
  static const std::array<std::string, kClasses> names = {
      "linearity", "repeatability", "resolution", "tip_form", "ball_form", "positioning"};
  return names;
}

namespace {

struct Key {
  const char* name;
  double lo, hi;  // allowed closed range
  bool integer;
  const char* what;
};

const std::vector<Key>& keys() {
  static const std::vector<Key> k = {
      {"ball_radius_mm", 1.0, 100.0, false, "the ball radius R in mm"},
      {"tip_radius_mm", 0.1, 20.0, false, "the tip radius r in mm"},
      {"base_radius_mm", 5.0, 500.0, false, "the distance λ of the base points from O' in mm"},
      {"calibration_step_mm", 0.01, 0.5, false, "the calibration step s in mm (within the stroke)"},
      {"measured_x_mm", -0.5, 0.5, false, "P_m − O along x in mm"},
      {"measured_y_mm", -0.5, 0.5, false, "P_m − O along y in mm"},
      {"measured_z_mm", -0.5, 0.5, false, "P_m − O along z in mm"},
      {"mounting_error_mm", 0.0, 1.0, false, "the mounting deviation bound in mm"},
      {"verification_positions", 1, 10000, true, "a number of positions"},
      {"verification_repetitions", 20, 1000000, true, "a number of repetitions"},
      {"verification_range_mm", 0.001, 0.5, false, "a sensor displacement range in mm"},
      {"varied_delta_mm", 1e-6, 0.1, false, "δ of the varied-parameter method in mm"},
      {"varied_step_mm", 1e-7, 0.1, false, "the step e of the varied-parameter method in mm"},
      {"form_error_per_sensor", 0, 1, true, "1 (form errors fixed per sensor) or 0 (per reading)"},
  };
  return k;
}

std::string number(double v) {
  std::string s = std::to_string(v);
  s.erase(s.find_last_not_of('0') + 1);
  if (!s.empty() && s.back() == '.') s.pop_back();
  return s;
}

}  // namespace

std::vector<std::string> r_test_keys() {
  std::vector<std::string> out;
  for (const Key& k : keys()) out.push_back(k.name);
  return out;
}

RTestSettings parse_r_test_settings(const std::vector<std::string>& inputs,
                                    const std::map<std::string, double>& parameters) {
  const auto& classes = input_class_names();
  const std::vector<std::string> class_list(classes.begin(), classes.end());
  std::string all;
  for (const std::string& c : classes) all += (all.empty() ? "" : ", ") + c;
  for (const std::string& in : inputs) {
    if (std::find(classes.begin(), classes.end(), in) == classes.end()) {
      const std::string hint = did_you_mean(in, class_list);
      throw uncertainty::BuiltinParameterError(
          in,
          "an input class of r_test (" + all + ")" +
              (hint.empty() ? "" : "; did you mean '" + hint + "'?"),
          true);
    }
  }
  for (const std::string& c : classes) {
    if (std::find(inputs.begin(), inputs.end(), c) == inputs.end()) {
      throw std::invalid_argument("r_test: the input '" + c + "' is missing (inputs: " + all +
                                  ", each with its law in mm)");
    }
  }
  const std::vector<std::string> names = r_test_keys();
  std::map<std::string, double> v;
  for (const auto& [key, value] : parameters) {
    const auto it =
        std::find_if(keys().begin(), keys().end(), [&](const Key& k) { return key == k.name; });
    if (it == keys().end()) {
      const std::string hint = did_you_mean(key, names);
      std::string list;
      for (const std::string& n : names) list += (list.empty() ? "" : ", ") + n;
      throw uncertainty::BuiltinParameterError(
          key,
          "a key of r_test (" + list + ")" + (hint.empty() ? "" : "; did you mean '" + hint + "'?"),
          true);
    }
    if (!(value >= it->lo && value <= it->hi) || (it->integer && value != std::floor(value))) {
      throw uncertainty::BuiltinParameterError(key,
                                               std::string(it->what) +
                                                   (it->integer ? ", an integer" : "") + " in [" +
                                                   number(it->lo) + ", " + number(it->hi) + "]",
                                               false);
    }
    v[key] = value;
  }
  RTestSettings s;
  auto get = [&](const char* k, double& out) {
    if (v.count(k)) out = v[k];
  };
  get("ball_radius_mm", s.ball_radius);
  get("tip_radius_mm", s.tip_radius);
  get("base_radius_mm", s.base_radius);
  get("calibration_step_mm", s.calibration_step);
  get("measured_x_mm", s.measured_offset.x());
  get("measured_y_mm", s.measured_offset.y());
  get("measured_z_mm", s.measured_offset.z());
  get("mounting_error_mm", s.mounting_error);
  get("verification_range_mm", s.verification_range);
  get("varied_delta_mm", s.varied_delta);
  get("varied_step_mm", s.varied_step);
  if (v.count("verification_positions")) s.positions = int(v["verification_positions"]);
  if (v.count("verification_repetitions")) s.repetitions = int(v["verification_repetitions"]);
  if (v.count("form_error_per_sensor")) s.form_per_sensor = v["form_error_per_sensor"] == 1.0;
  const double ratio = s.varied_delta / s.varied_step;
  if (std::abs(ratio - std::round(ratio)) > 1e-9 * ratio || ratio > 1000) {
    throw std::invalid_argument("r_test: varied_delta_mm / varied_step_mm = " + number(ratio) +
                                ": expected a whole number of steps, at most 1000");
  }
  const Geometry g = make_geometry(s.ball_radius, s.tip_radius, s.base_radius);
  if (g.reading_at_centre() < 1.0) {
    throw std::invalid_argument("r_test key 'base_radius_mm' = " + number(s.base_radius) +
                                ": expected λ/cos α − (R + r) ≥ 1 mm (room for the sensor "
                                "stroke), i.e. base_radius_mm ≥ " +
                                number((s.ball_radius + s.tip_radius + 1.0) * std::cos(g.alpha)));
  }
  for (int i = 0; i < kSensors; ++i) {
    if (std::abs(g.axis[i].dot(s.measured_offset)) > 0.5) {
      throw std::invalid_argument(
          "r_test: the measured position (measured_x_mm, measured_y_mm, measured_z_mm) moves "
          "sensor " +
          std::to_string(i + 1) + " by " + number(g.axis[i].dot(s.measured_offset)) +
          " mm from mid-stroke: expected at most 0.5 mm (the 1 mm stroke)");
    }
  }
  return s;
}

double RTestModel::indication_u() const {
  return std::sqrt(laws[kLinearity].u * laws[kLinearity].u +
                   laws[kRepeatability].u * laws[kRepeatability].u +
                   laws[kResolution].u * laws[kResolution].u);
}

RTestModel make_r_test_model(const uncertainty::UncertaintyModel& model) {
  RTestModel m;
  std::vector<std::string> names;
  std::map<std::string, const uncertainty::ModelInput*> by_name;
  for (const auto& in : model.inputs) {
    names.push_back(in.name);
    by_name[in.name] = &in;
  }
  m.settings = parse_r_test_settings(names, model.builtin_parameters);
  for (int c = 0; c < kClasses; ++c) {
    const uncertainty::ModelInput& in = *by_name.at(input_class_names()[c]);
    m.laws[c].law = in.law;
    m.laws[c].u = in.law.gum_u();
    m.laws[c].dof = in.dof;
    m.laws[c].text = in.law_text;
  }
  m.seed = model.settings.seed;
  m.coverage_probability = model.settings.coverage_probability;
  const RTestSettings& s = m.settings;
  m.geometry = make_geometry(s.ball_radius, s.tip_radius, s.base_radius);
  TrialStream mount(m.seed, 0, TrialPurpose::kRTestMounting);
  for (int i = 0; i < kSensors; ++i) {
    Vector3d d;
    for (int k = 0; k < 3; ++k) d[k] = s.mounting_error * (2.0 * mount.uniform() - 1.0);
    m.true_base[i] = m.geometry.base[i] + d;
  }
  const Vector3d O = m.geometry.centre;
  const double a = s.calibration_step;
  m.calibration_points = {O + Vector3d(a, 0, 0), O - Vector3d(a, 0, 0), O + Vector3d(0, a, 0),
                          O - Vector3d(0, a, 0), O + Vector3d(0, 0, a), O - Vector3d(0, 0, a)};
  m.measured = O + s.measured_offset;
  return m;
}

FormErrors draw_form_errors(const RTestModel& m, TrialStream& s) {
  FormErrors f;
  for (int i = 0; i < kSensors; ++i) {
    if (m.settings.form_per_sensor) {
      const double e = m.laws[kTipForm].law.sample(s) + m.laws[kBallForm].law.sample(s);
      f.rho[i].fill(e);
    } else {
      for (double& e : f.rho[i]) {
        e = m.laws[kTipForm].law.sample(s) + m.laws[kBallForm].law.sample(s);
      }
    }
  }
  return f;
}

double draw_indication(const RTestModel& m, TrialStream& s) {
  return m.laws[kLinearity].law.sample(s) + m.laws[kRepeatability].law.sample(s) +
         m.laws[kResolution].law.sample(s);
}

Calibration simulate_calibration(const RTestModel& m, const FormErrors& form, TrialStream& s) {
  Calibration c;
  const double rho = m.geometry.contact_radius();
  std::array<Vector3d, kCalibrationPoints> actual;
  for (int j = 0; j < kCalibrationPoints; ++j) {
    Vector3d e;
    for (int k = 0; k < 3; ++k) e[k] = m.laws[kPositioning].law.sample(s);
    actual[j] = m.calibration_points[j] + e;
  }
  for (int i = 0; i < kSensors; ++i) {
    SensorData& d = c.data[i];
    for (int j = 0; j < kCalibrationPoints; ++j) {
      d.points[j] = m.calibration_points[j];
      d.rho[j] = rho;
      d.readings[j] =
          reading_for(m.true_base[i], m.geometry.axis[i], actual[j], rho + form.rho[i][j]) +
          draw_indication(m, s);
    }
    c.fit[i] = calibrate_sensor(m.geometry.axis[i], d, m.geometry.base[i]);
    c.base[i] = c.fit[i].base;
    c.ok = c.ok && c.fit[i].ok;
  }
  return c;
}

Measurement simulate_measurement(const RTestModel& m, const Triple& calibrated_base,
                                 const FormErrors& form, const Vector3d& ball, TrialStream& s) {
  Measurement out;
  const double rho = m.geometry.contact_radius();
  for (int i = 0; i < kSensors; ++i) {
    out.readings[i] = reading_for(m.true_base[i], m.geometry.axis[i], ball,
                                  rho + form.rho[i][kCalibrationPoints]) +
                      draw_indication(m, s);
  }
  out.centre =
      solve_ball_centre(calibrated_base, m.geometry.axis, out.readings, Vector3d::Constant(rho));
  return out;
}

std::vector<Vector3d> verification_positions(const RTestModel& m) {
  std::vector<Vector3d> out;
  Matrix3d U;
  for (int i = 0; i < kSensors; ++i) U.row(i) = m.geometry.axis[i].transpose();
  const Matrix3d Uinv = U.inverse();
  for (int k = 0; k < m.settings.positions; ++k) {
    TrialStream s(m.seed, static_cast<std::uint64_t>(k), TrialPurpose::kRTestPositions);
    Vector3d d;
    for (int i = 0; i < kSensors; ++i) d[i] = m.settings.verification_range * (2 * s.uniform() - 1);
    out.push_back(m.geometry.centre + Uinv * d);
  }
  return out;
}

}  // namespace gearmc::rtest
