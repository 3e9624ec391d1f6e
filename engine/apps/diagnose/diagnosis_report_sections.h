// The sections of the `gearmc diagnose` report after its verdict (docs/diagnosis.md: read it top
// down), each appended to the page in this order by diagnosis_report_html: where the residuals
// disagree (approach azimuth, spectrum, order, tooth, position), the gap, the spread of single
// readings, the fitted effects, the selection, the ambiguities, the residual histograms, notes,
// inputs and fitted.yaml. Internal to engine/apps/diagnose's report.
#pragma once

#include "engine/apps/diagnose/diagnosis_report_data.h"
#include "engine/reports/html_report.h"

namespace gearmc::diagnose_report {

// Where: the residuals against the approach azimuth — every reading (a bounded sample
// beyond kMaxScatterMarks, always with the extremes) with the 5° means before and after and the
// fitted effect, and a polar view of the 10° means.
void azimuth_section(HtmlReport& report, const ReportContext& ctx);

// The harmonic spectrum of the residuals against the approach azimuth with its 95 % null
// bands.
void spectrum_section(HtmlReport& report, const ReportContext& ctx);

// The residuals against measurement order, tooth (per flank side), roll length and face
// position, and the table of how far each axis's bin means exceed noise.
void position_section(HtmlReport& report, const ReportContext& ctx);

// The gap before and after the fit: RMS, held-out RMS, noise floor, χ², KS, bootstrap
// interval and energy test, and where the noise floor comes from.
void gap_section(HtmlReport& report, const ReportContext& ctx);

// A production gear's own flank deviations (part_model.h): per side, the machine effects they
// hide on this set-up, and per flank (diagnosis_report_part.cpp). Nothing for a master.
void part_section(HtmlReport& report, const ReportContext& ctx);

// The spread of single readings: the point-law stage's white-variance test and laws.
void point_law_section(HtmlReport& report, const ReportContext& ctx);

// The fitted parameters of the selected effects with their standard errors.
void fitted_effects_section(HtmlReport& report, const ReportContext& ctx);

// The forward selection, one table per step.
void selection_section(HtmlReport& report, const ReportContext& ctx);

// The ambiguities of each selected effect with the measurement that would separate them.
void ambiguity_section(HtmlReport& report, const ReportContext& ctx);

// Histograms of the residuals before and after against the law of a reading.
void histograms_section(HtmlReport& report, const ReportContext& ctx);

// The notes, the inputs and fitted.yaml.
void notes_and_inputs_section(HtmlReport& report, const ReportContext& ctx);

}  // namespace gearmc::diagnose_report
