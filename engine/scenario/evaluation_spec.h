// The scenario's `evaluation:` section: which ISO 1328-1 gear parameters a run evaluates from
// every simulated measurement, over which evaluation ranges, from which traces, and the decision
// rule of its conformity statements (docs/parameters.md). Absent = no parameter evaluation (the
// run's outputs are those of a scenario without the section). Lengths in mm.
#pragma once

#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "core/input_error.h"
#include "engine/plan/probing_grid.h"
#include "gears/involute_gear.h"

namespace gearmc {

class YamlValue;
using InputWarnings = std::vector<std::string>;

struct EvaluationSpec {
  // The parameter symbols (F_alpha, f_Halpha, f_falpha, F_beta, f_Hbeta, f_fbeta, f_pt, F_p,
  // F_r, E_sn, E_Wk, E_MdK), in that order; `all` (the default) lists the nine ISO 1328-1 ones.
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
  // Profile traces per flank at this many heights across the face and helix traces at this many
  // roll lengths across the profile: the centres of equal parts of L_β resp. L_α (1: mid face,
  // mid profile); on the grid its sections / columns spread alike. Every trace is an item.
  int profile_sections = 1, helix_sections = 1;
  // Where the first of them above 1 was written (a user's program has one trace per flank).
  std::optional<InputLocation> sections_at;
  std::string sections_key, sections_value;
  // Points of the dense trace on the real surface that gives a parameter's true value.
  int truth_points = 100;
  // Profile evaluation range L_α: from the form circle over this fraction of the active roll
  // length (ISO 1328-1:2013: about 92–95 %, default 0.95).
  double profile_end_fraction = 0.95;
  // Helix evaluation range L_β: b minus this at each end; nullopt = ISO's min(5 % b, m_n).
  std::optional<double> helix_end_exclusion_mm;
  std::string decision_rule = "simple";  // "simple" | "guard_banded"
  // The span of E_Wk (k teeth) and the ball of E_MdK (diameter D_M, mm); nullopt = the span whose
  // jaws, the ball which, touch nearest mid profile (docs/parameters.md).
  std::optional<int> span_teeth;
  std::optional<double> ball_diameter_mm;
  // Cut-offs λc of the Gaussian profile and helix filters (ISO 16610-21; roll length resp. face
  // position, mm); nullopt = unfiltered traces (engine/evaluation/trace_filter.h).
  std::optional<double> profile_cutoff_mm, helix_cutoff_mm;
  // The drawing's allowances of a size deviation (`size_allowances_um`), µm: symbol (E_sn, E_Wk,
  // E_MdK) → [lower, upper]; a size without them has no conformity decision.
  std::map<std::string, std::pair<double, double>> size_allowances_um;
};

// The profile evaluation range L_α as an interval of roll length [lo, hi] (mm): from the form
// circle over `profile_end_fraction` of the active profile towards the tip (on an internal gear
// the tip has the smaller roll length).
std::pair<double, double> profile_evaluation_roll_lengths(const InvoluteGear& gear,
                                                          const EvaluationSpec& spec);
// The span k of E_Wk and the ball D_M of E_MdK that `spec` asks for or that touch nearest mid
// profile (nullopt: none touches within L_α; an internal gear has no span).
std::optional<int> evaluation_span_teeth(const InvoluteGear& gear, const EvaluationSpec& spec);
std::optional<double> evaluation_ball_diameter_mm(const InvoluteGear& gear,
                                                  const EvaluationSpec& spec);

// Reads `evaluation:` (a map of the keys in the key table under "evaluation") for a gear of face
// width b (the helix end exclusion must leave a range: < b/2). Throws InputError.
EvaluationSpec read_evaluation(const YamlValue& value, double face_width_mm,
                               InputWarnings* warnings);
// The section against the rest of the scenario, InputError at `value` when: a flank is a mesh
// (`surfaces:`: its true deviation at a point is not known, so no true parameter value); f_pt,
// F_p or F_r are listed but not every tooth is probed; F_r or a size deviation is listed but one
// side is not probed; E_Wk on an internal gear; at the key when span_teeth or ball_diameter_mm
// makes the gauge touch outside L_α (with the values that touch within it).
void check_evaluation(const YamlValue& value, const EvaluationSpec& spec,
                      const ProbingPlanSpec& plan, const InvoluteGear& gear,
                      bool has_mesh_surfaces);

}  // namespace gearmc
