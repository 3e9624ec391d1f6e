// fitted.yaml of `gearmc diagnose` (docs/formats.md): the model scenario with the effect(s) the
// diagnosis named added to its `effects:` section, or updated there, with their fitted physical
// parameters — so that the model now predicts what was measured, and a second `diagnose` with
// fitted.yaml as the model finds no further gap.
//
// How the parameters are written. The diagnosis fits first-order increments about the model's own
// values of each effect (diagnosis.h, candidates.h); here they are added to those values:
//  * a number becomes number + increment; a law keeps its shape and moves by the increment
//    ({uniform: [lo + Δ, hi + Δ]}, {normal: [mean + Δ, sd]});
//  * probe_lobing: pretravel_um as above; each fitted order k is the vector sum of the model's
//    harmonic (a cos kφ_k, a sin kφ_k) at its nominal values and the fitted increment
//    (cos_k_um, sin_k_um), written as `harmonics: [{order, amplitude_um, phase_deg}]` with the
//    phase in [0, 360°/k); orders the fit does not touch keep their text; a model lobing given by
//    `from_probe_model` is replaced by its explicit p0 and harmonics (the probe model's values);
//  * thermal_expansion: the candidate's column is the steel CTE 11.5 ppm/K, so the increment of
//    workpiece_delta_t_k is scaled by 11.5 / the model's workpiece CTE (a model CTE of 0 is set
//    to 11.5, its ΔT then had no effect);
//  * parameters the probing plan cannot observe (no estimate) are left out / left as they were;
//    a parameter that must be ≥ 0 (step_um) is clamped at 0, with a note.
// Effects are added only when the diagnosis names a library effect; for "none" and "unexplained"
// fitted.yaml is the model unchanged (with a header saying so). Everything else in the model is
// kept (keys, order, quoting, flow or block style; the model's comments are not carried over —
// yaml-cpp does not keep them); relative `surfaces:` mesh paths are made absolute so the file
// loads from any folder. The text starts with a comment naming gearmc diagnose, the model and the
// readings.
#pragma once

#include <string>
#include <vector>

#include "engine/apps/diagnose/diagnosis.h"
#include "engine/scenario/scenario.h"

namespace gearmc {

struct FittedScenario {
  std::string yaml;                  // the text of fitted.yaml
  std::vector<std::string> updated;  // effects added or updated, in the diagnosis's order
  // Remarks for the reader (also in the header comment): ambiguities, clamped values, a model
  // lobing with a qualification strategy, effects not added.
  std::vector<std::string> notes;
};

// `model_path` and `readings_path` are named in the header comment. Throws std::runtime_error if
// the model's text cannot be re-read as YAML (it was read once, so this is a bug).
FittedScenario fitted_scenario(const Scenario& model, const Diagnosis& diagnosis,
                               const std::string& model_path, const std::string& readings_path);

// A number as fitted.yaml writes it: fixed notation, at most 6 decimals, trailing zeros removed
// ("0.748123", "30", "-2.5"); never "-0".
std::string format_fitted_number(double value);

}  // namespace gearmc
