// diagnosis.json (docs/formats.md, `diagnose` outputs): the Diagnosis as JSON. The keys
// docs/formats.md requires — gap_detected, named_effect, ambiguous_with, effects[{name, parameters,
// std_errors, evidence}], gap_before {rms_um, ks}, gap_after {rms_um, ks}, noise_floor_um — come
// first; the rest (selection table, spectrum, noise-floor provenance, held-out RMS, explained
// fraction) is there for the report and for a reader who wants to check the decision. "status"
// comes first: "tested", or "not_enough_readings" (then "status_reason" says how many readings
// there are and how many are needed, and gap_detected is false with named_effect "not_tested"). The
// file holds no null and no NaN: a number that could not be computed (not available, e.g. a p-value
// without a test, or infinite, e.g. the condition number of exactly dependent columns) is left out
// of its object and its key listed in that object's "not_computed" array; an array with such a
// value is left out whole. "accepted" of a selection step and point_law.chosen are "none" when
// nothing was. Units: µm unless a key's name says otherwise. effects[].parameters are the physical
// parameters (probe_lobing: pretravel_um, amplitude_<k>_um, phase_<k>_deg per order; a parameter
// the plan cannot observe is listed in not_computed and in evidence.not_observable);
// evidence.coefficients are the linear coefficients that were fitted.
#pragma once

#include <string>

#include "engine/apps/diagnose/diagnosis.h"

namespace gearmc {

// The JSON text (2-space indent, keys in a fixed order, so the same Diagnosis gives the same
// bytes).
std::string diagnosis_json(const Diagnosis& diagnosis);

// Writes diagnosis_json to `path` atomically (write_file_atomically: `path`.tmp, then rename);
// throws std::runtime_error on I/O errors.
void write_diagnosis_json(const std::string& path, const Diagnosis& diagnosis);

}  // namespace gearmc
