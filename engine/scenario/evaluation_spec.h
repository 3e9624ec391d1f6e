// The scenario's `evaluation:` section: which ISO 1328-1 gear parameters a run evaluates from
// every simulated measurement, over which evaluation ranges, from which traces, and the decision
// rule of its conformity statements (docs/parameters.md). Absent = no parameter evaluation (the
// run's outputs are those of a scenario without the section). Lengths in mm.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "core/input_error.h"
#include "engine/plan/probing_grid.h"

namespace gearmc {

class YamlValue;
using InputWarnings = std::vector<std::string>;

struct EvaluationSpec {
  // The parameter symbols (F_alpha, f_Halpha, f_falpha, F_beta, f_Hbeta, f_fbeta, f_pt, F_p,
  // F_r), in that order; `all` (the default) lists every one.
  std::vector<std::string> parameters;
  bool all = false;  // `parameters: all` (pitch and runout are left out, with a note, when the
                     // probing plan does not allow them; listed explicitly they are an error)
  // Points of a dedicated profile trace at mid face and helix trace at mid profile on every
  // probed flank (a gear CMM's scan); 0 = evaluate the probing grid's own section / column.
  int profile_points = 0, helix_points = 0;
  // Where the first of them asking for a scan (> 0) was written, with its key and value, for a
  // message that refuses scans (`run --plan`: a user's program does not run them).
  std::optional<InputLocation> scans_at;
  std::string scans_key, scans_value;
  // Points of the dense trace on the real surface that gives a parameter's true value.
  int truth_points = 100;
  // Profile evaluation range L_α: from the form circle over this fraction of the active roll
  // length (ISO 1328-1:2013: about 92–95 %, default 0.95).
  double profile_end_fraction = 0.95;
  // Helix evaluation range L_β: b minus this at each end; nullopt = ISO's min(5 % b, m_n).
  std::optional<double> helix_end_exclusion_mm;
  std::string decision_rule = "simple";  // "simple" | "guard_banded"
};

// Reads `evaluation:` (a map of the keys in the key table under "evaluation") for a gear of face
// width b (the helix end exclusion must leave a range: < b/2). Throws InputError.
EvaluationSpec read_evaluation(const YamlValue& value, double face_width_mm,
                               InputWarnings* warnings);
// The section against the rest of the scenario, InputError at `value` when: a flank is a mesh
// (`surfaces:`: its true deviation at a point is not known, so no true parameter value); f_pt,
// F_p or F_r are listed but not every tooth is probed; F_r is listed but one side is not probed.
void check_evaluation(const YamlValue& value, const EvaluationSpec& spec,
                      const ProbingPlanSpec& plan, int gear_teeth, bool has_mesh_surfaces);

}  // namespace gearmc
