// The R-Test model of a `builtin: {model: r_test, …}` model file: its settings (instrument
// geometry, calibration and verification plan, the numbers of P3's sensitivity method) read from
// the builtin keys, and the six Type-B input classes of P3's budget read from the model's inputs
// (sensor linearity, repeatability and resolution, tip form, ball form, machine positioning),
// each with its law and its degrees of freedom. Also the simulation of one calibration and one
// measurement with errors drawn from those laws, on counter-based streams.
//
// Units: mm (lengths and the input laws), rad. Frame: instrument.h.
#pragma once

#include <array>
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "core/random_stream.h"
#include "engine/apps/r_test/instrument.h"
#include "engine/apps/uncertainty/laws.h"

namespace gearmc::uncertainty {
struct UncertaintyModel;
}

namespace gearmc::rtest {

// The input classes, in this order everywhere (budgets, JSON, report).
enum InputClass { kLinearity, kRepeatability, kResolution, kTipForm, kBallForm, kPositioning };
inline constexpr int kClasses = 6;
// Their names in the model file's `inputs:`.
const std::array<std::string, kClasses>& input_class_names();

// The keys of `builtin:` besides `model`, with their defaults (docs/r-test.md).
struct RTestSettings {
  double ball_radius = 15.0;      // ball_radius_mm
  double tip_radius = 2.5;        // tip_radius_mm
  double base_radius = 40.0;      // base_radius_mm: λ
  double calibration_step = 0.3;  // calibration_step_mm: P_j = O ± s e_x, ± s e_y, ± s e_z
  Vector3d measured_offset{0.2, -0.15, 0.1};  // measured_{x,y,z}_mm: P_m − O
  double mounting_error = 0.05;     // mounting_error_mm: true C_i1 − nominal, each coordinate
  int positions = 100;              // verification_positions
  int repetitions = 1000;           // verification_repetitions
  double verification_range = 0.4;  // verification_range_mm: |u_i·(P − O)| ≤ this
  double varied_delta = 0.01;       // varied_delta_mm: δ of the varied-parameter method
  double varied_step = 0.001;       // varied_step_mm: e
  bool form_per_sensor = true;      // form_error_per_sensor: 1 or 0
};

// Checks the input names (exactly the six classes, any order) and the builtin keys; throws
// std::invalid_argument with one sentence naming the offending key or input.
RTestSettings parse_r_test_settings(const std::vector<std::string>& inputs,
                                    const std::map<std::string, double>& parameters);
std::vector<std::string> r_test_keys();

struct InputLaw {
  uncertainty::Law law;
  double u = 0.0;    // standard uncertainty for the GUM
  double dof = 0.0;  // its degrees of freedom (the model file's dof:, +inf when absent)
  std::string text;  // as written
};

// Everything fixed for one evaluation: settings, geometry, laws, the true instrument of the
// simulation and the plan.
struct RTestModel {
  RTestSettings settings;
  Geometry geometry;
  std::array<InputLaw, kClasses> laws;
  Triple true_base;  // the simulated instrument: nominal C_i1 + a fixed mounting deviation
  std::array<Vector3d, kCalibrationPoints> calibration_points;
  Vector3d measured;  // P_m
  std::uint64_t seed = 1;
  double coverage_probability = 0.95;
  // u of the indication of one reading: √(u_lin² + u_rep² + u_res²).
  double indication_u() const;
};

// Builds the model of an UncertaintyModel whose builtin is r_test (the model file was checked
// when read, so this does not throw on user input). The mounting deviation is drawn from
// uniform(−mounting, +mounting) on the stream (seed, 0, TrialPurpose::kRTestMounting).
RTestModel make_r_test_model(const uncertainty::UncertaintyModel& model);

// The form errors (tip + ball, mm) of one realisation: per sensor, for its 6 calibration
// readings and its measuring reading (one value per sensor when form_per_sensor).
struct FormErrors {
  std::array<std::array<double, kCalibrationPoints + 1>, kSensors> rho{};
};
FormErrors draw_form_errors(const RTestModel& m, TrialStream& s);
double draw_indication(const RTestModel& m, TrialStream& s);

// One simulated calibration: the ball driven to P_j + positioning error, readings of the true
// instrument with form and indication errors, fitted with the commanded P_j and the nominal
// R + r from the nominal base points.
struct Calibration {
  std::array<SensorData, kSensors> data;
  std::array<SensorFit, kSensors> fit;
  Triple base;  // the fitted C_i1
  bool ok = true;
};
Calibration simulate_calibration(const RTestModel& m, const FormErrors& form, TrialStream& s);

// The readings of the true instrument with the ball at `ball` (form errors of the measuring
// readings, fresh indication errors) and the centre the calibrated instrument makes of them.
struct Measurement {
  Vector3d readings = Vector3d::Zero();
  BallCentre centre;
};
Measurement simulate_measurement(const RTestModel& m, const Triple& calibrated_base,
                                 const FormErrors& form, const Vector3d& ball, TrialStream& s);

// Uniform positions for the verification: u_i·(P − O) uniform in ±verification_range (the
// sensor displacements from mid-stroke), position k from the stream (seed, k,
// TrialPurpose::kRTestPositions).
std::vector<Vector3d> verification_positions(const RTestModel& m);

}  // namespace gearmc::rtest
