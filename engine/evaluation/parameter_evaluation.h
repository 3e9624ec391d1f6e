// The ISO 1328-1 parameters of every simulated measurement and of the real gear it measured
// (docs/parameters.md). Per probed flank one profile trace (at mid face) and one helix trace (at
// mid profile), either the probing grid's own section and column or a dedicated denser scan
// probed through the same measurement pipeline (contact, effects); with a user's program as the
// plan (`--plan`), per flank the program's own traces: the transverse section with the most
// points in the profile range and the roll length with the most points in the helix range (ties:
// the nearest to mid face, mid profile), at least 3 points each. Each parameter gets three
// values: `measured` from the reported points (every enabled effect), `true_points` — the same
// evaluation of the real surface at the same nominal points (so measured − true_points is the
// measurement error alone) — and `true_dense`, from a dense trace of the real surface (the gear's
// actual parameter; true_points − true_dense is the sampling error of a sparse trace). Pitch from
// the profile traces at the reference circle; runout from a ball in every tooth space touching
// the profile traces at mid profile; the size deviations from the profile traces where the gauges
// touch: E_sn on the reference circle, E_Wk where the jaws of the span over k teeth touch its
// two outer flanks, E_MdK where the ball of diameter D_M touches (gears/size_dimensions.h), all
// in the profile traces' transverse section. Deviations µm in the transverse plane (ISO 1328-1;
// along the nominal outward normal on a spur gear, that normal's component ÷ cos(beta_b) on a
// helical one), lengths mm.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "engine/evaluation/gear_parameters.h"
#include "engine/measurement/gear_measurement.h"
#include "engine/scenario/evaluation_spec.h"

namespace gearmc {

// One value of a parameter, µm (NaN: not evaluated, e.g. too few valid points in a trace).
struct ParameterValue {
  double measured = 0.0, true_points = 0.0, true_dense = 0.0;
  // The measured value with one measurement effect alone (besides δRcomp), per effect of the
  // chain, then with δRcomp alone (no effect): the error budget. Empty without effects.
  std::vector<double> budget;
};

// One flank's traces as evaluated (for the gear-software charts).
struct FlankTrace {
  int tooth = 1;
  FlankSide side = FlankSide::kLeft;
  std::vector<double> x_mm, measured_um, true_um;  // sampled trace (NaN where no value)
  std::vector<double> dense_x_mm, dense_um;        // the real surface's dense trace
  double range_start_mm = 0.0, range_end_mm = 0.0;
  TraceResult measured_line;  // mean line of the measured trace (samples 0: none)
  TraceResult true_line;      // the same of the real surface's dense trace
};
struct GearTraces {
  std::vector<FlankTrace> profile, helix;  // in plan order
  // Pitch and runout per tooth (1 … z; empty when not evaluated): measured and true (dense).
  std::vector<double> pitch_measured[2], pitch_true[2];  // f_pt,k, [0] L, [1] R
  std::vector<double> ball_measured, ball_true;          // radial ball positions, µm
};

// What one gear gave: per parameter and side ([0] L, [1] R; F_r: one per gear in [0]) the values
// of its items — profile/helix parameters one per probed flank (plan order), f_pt one per tooth,
// F_p one per gear and side.
struct GearParameterValues {
  std::array<std::array<std::vector<ParameterValue>, 2>, kGearParameterCount> values;
  GearTraces traces;
};

// A run's parameter values, appended gear by gear in gear order (they are kept, not streamed:
// the coverage intervals and the decision rates need every item; 24 + 8 × (effects + 1) bytes
// per item and parameter), and the traces of the first gear for the charts.
struct ParameterSamples {
  std::array<std::array<std::vector<ParameterValue>, 2>, kGearParameterCount> values;
  std::optional<int> chart_gear;
  GearTraces chart;
  void append(int gear, GearParameterValues&& g);
};

// Built once per run from the model and the scenario's `evaluation:`; evaluate() is thread-safe.
class ParameterEvaluator {
 public:
  ParameterEvaluator(const MeasurementModel& model, const EvaluationSpec& spec);
  ~ParameterEvaluator();

  const EvaluationSpec& spec() const { return spec_; }
  // The parameters evaluated (the spec's, less those the plan does not allow with `all`).
  const std::vector<GearParameter>& parameters() const { return parameters_; }
  bool evaluates(GearParameter p) const;
  // Why a parameter of `all` was left out (e.g. "f_pt, F_p, F_r: not every tooth is probed").
  const std::vector<std::string>& notes() const { return notes_; }
  // Whether the traces are a user's program's own (see the file comment).
  bool program_traces() const { return program_; }
  // The evaluation ranges used, mm.
  double profile_start_mm() const { return profile_start_; }
  double profile_end_mm() const { return profile_end_; }
  double helix_start_mm() const { return helix_start_; }
  double helix_end_mm() const { return helix_end_; }
  int effect_count() const;  // effects in the chain (budget columns: these + δRcomp alone)
  // The gauges of the size deviations (nullopt when E_Wk / E_MdK are not evaluated): span k and
  // where its jaws touch (roll length, mm); ball diameter D_M and where it touches (mm).
  std::optional<int> span_teeth() const { return span_k_; }
  double span_contact_mm() const { return span_L_; }
  std::optional<double> ball_diameter_mm() const { return size_ball_D_; }
  double ball_contact_mm() const { return size_ball_L_; }

  // Collects the grid's measurements of one gear, then evaluates.
  class Gear {
   public:
    Gear(const ParameterEvaluator& evaluator, const GearMeasurement& measurement);
    // The grid point `m` of flank `flank_index` (MeasurementModel::flanks() order).
    void record(int flank_index, const PointMeasurement& m);
    // Probes the dedicated scans (if any) and evaluates every parameter; the traces for the
    // charts only with `keep_traces`.
    GearParameterValues finish(bool keep_traces);

   private:
    const ParameterEvaluator& e_;
    const GearMeasurement& measurement_;
    struct PointRecord {
      bool recorded = false, valid = false;
      double measured_um = 0.0;           // the reported point's deviation ((c − p)·n − R)
      double base_um = 0.0;               // the contact's deviation plus δRcomp, without effects
      std::vector<double> contributions;  // each effect's change of the reading, µm
    };
    std::vector<std::vector<PointRecord>> grid_;  // per flank, per grid point
    // A measured point's deviations in the transverse plane (µm): the reading's, the contact's
    // plus δRcomp, and each effect's change, from their components along the nominal normal.
    void fill(PointRecord& r, const PointMeasurement& m) const;
  };

 private:
  friend class Gear;
  struct Trace;  // the points of one trace on one flank
  const MeasurementModel& model_;
  EvaluationSpec spec_;
  std::vector<GearParameter> parameters_;
  std::vector<std::string> notes_;
  double profile_start_ = 0, profile_end_ = 0, helix_start_ = 0, helix_end_ = 0;
  double profile_sign_ = 1;              // roll sign: a profile trace's abscissa is sigma L
  double profile_z_ = 0, helix_L_ = 0;   // where the middle traces run (pitch, sizes, runout)
  double reference_L_ = 0, ball_L_ = 0;  // pitch circle and ball contacts (roll lengths)
  double transverse_per_normal_ = 1;     // 1 / cos(beta_b): normal to transverse deviation
  // The grid's sections and columns of the traces (EvaluationSpec::profile_sections,
  // helix_sections), and which of them is the middle one (charts, pitch, runout, sizes).
  std::vector<int> grid_sections_, grid_columns_;
  int middle_profile_ = 0, middle_helix_ = 0;
  bool program_ = false;  // the plan is a user's program (MeasurementModel's explicit points)
  // Per flank (MeasurementModel::flanks() order) and plan point: kInProfile | kInHelix when the
  // point belongs to the flank's profile or helix trace (the grid's section and column, or the
  // program's traces); and where the flank's traces run (z of its profile trace, L of its helix
  // trace, mm).
  static constexpr unsigned char kInProfile = 1, kInHelix = 2;
  std::vector<std::vector<unsigned char>> trace_member_;
  // Per flank and plan point (and per scan flank and scan point): the index of the profile and
  // of the helix trace it belongs to, −1 for none.
  std::vector<std::vector<int>> profile_trace_, helix_trace_, scan_trace_;
  // Per flank and trace: z of its profile traces, L of its helix traces (mm; NaN: a program
  // without that trace on the flank).
  std::vector<std::vector<double>> flank_profile_z_, flank_helix_L_;
  void choose_program_traces(std::size_t flank_index);
  std::vector<PlanFlank> scans_;  // dedicated scans per probed flank (empty: the grid)
  std::vector<BallContact> balls_;
  std::optional<int> span_k_;
  std::optional<double> size_ball_D_;
  double span_L_ = 0, size_ball_L_ = 0;
  std::vector<BallContact> size_balls_;  // the E_MdK ball's contacts, space by space
};

}  // namespace gearmc
