// report.html and the terminal summary of `gearmc diagnose` (docs/diagnosis.md): a page a
// metrologist can read in a minute. It opens with the verdict — what disagreed (the residual
// RMS against the noise floor and the gap tests), where (the effect's own pattern and the axis
// along which the residuals' bin means vary most beyond noise: approach azimuth, measurement
// order, tooth, roll length, face position), which effect, how big (parameters ± standard
// error) and the gap before → after with the held-out RMS — or "no gap", or "unexplained
// structure remains". Then the evidence: residuals before and after against approach azimuth
// (XY and polar), measurement order, tooth (per flank side), roll length and face position; the
// harmonic spectrum with its 95 % null bands; the gap table; the fitted parameters; the selection
// table of every step; the ambiguities with the measurement that would separate them;
// histograms of the residuals before and after with the noise floor's normal density; notes,
// inputs and fitted.yaml. Everything is computed from the Diagnosis and the residuals' points:
// nothing depends on how the readings were made.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "engine/apps/diagnose/diagnosis.h"
#include "engine/apps/diagnose/fitted_scenario.h"
#include "engine/readings/point_matching.h"
#include "engine/scenario/scenario.h"

namespace gearmc {

struct DiagnosisReportInput {
  const Scenario& model;
  std::string model_path, readings_path;
  const Residuals& residuals;  // the points (same order as the diagnosis's residual vectors)
  const Diagnosis& diagnosis;
  const FittedScenario& fitted;
  // Label-free readings: how their points were matched to the flanks (point_matching.h).
  std::optional<MatchingSummary> matching = std::nullopt;
};

// The verdict paragraph (plain text, the report's first paragraph).
std::string diagnosis_verdict(const DiagnosisReportInput& input);

// The 3 terminal lines before the report path: inputs and noise floor; the verdict with the
// named effect's significant parameters; the gap RMS before → after, held-out and noise floor.
std::vector<std::string> diagnosis_summary_lines(const DiagnosisReportInput& input);

// The whole report.html page.
std::string diagnosis_report_html(const DiagnosisReportInput& input);

}  // namespace gearmc
