// The shared ground of the `gearmc diagnose` report (diagnosis_report.cpp, the verdict and the
// page; diagnosis_report_sections.cpp, the page's sections): the residuals arranged along each
// axis the report plots (approach azimuth, measurement order, tooth per flank side, roll length,
// face position) as bin means before and after the fit, how far each axis's bin means vary
// beyond the noise floor, the colours that mean the same in every plot, and the number
// formatting of the report's text. Internal to engine/apps/diagnose's report; units µm unless
// named.
#pragma once

#include <cstddef>
#include <numbers>
#include <string>
#include <vector>

#include "core/constants.h"
#include "engine/apps/diagnose/diagnosis_report.h"

namespace gearmc::diagnose_report {

// Okabe-Ito colours, the same meaning in every plot.
inline const char* const kRawColour = "#c8c8c8";
inline const char* const kBefore = "#D55E00";      // vermillion
inline const char* const kAfter = "#0072B2";       // blue
inline const char* const kFitted = "#009E73";      // bluish green
inline const char* const kNullBefore = "#E69F00";  // orange
inline const char* const kNullAfter = "#56B4E9";   // sky blue
// The most marks of one scatter series (report.html stays small at 10⁶ readings).
inline constexpr std::size_t kMaxScatterMarks = 5000;

// v with `decimals` decimals ("–" when not finite; never "-0.000").
std::string fixed(double v, int decimals = 3);
// How the held-out check split the readings (Diagnosis::held_out_split), in words.
std::string held_out_split_text(const std::string& split);
// A value with its standard error at a precision that follows the error (2 significant digits
// of the error, at most 4 decimals, at least 1).
std::string with_error(double value, double error);
// 3 significant digits ("–" when not finite).
std::string general(double v);
// A null-calibrated p-value: the smallest possible value 1/(K + 1) is shown as "p ≤ …".
std::string p_text(double p, int replicates);

// Residual bin means along one axis: key → (mean x, mean before, mean after, count).
struct Bins {
  std::vector<double> x, before, after;
  std::vector<int> count;
};

// How much the bin means vary beyond noise: RMS of (mean − overall mean) weighted by count, and
// the same expected from noise σ alone (σ √((B − 1)/n)), and their χ² ratio
// Σ n_b (m_b − m̄)² / ((B − 1) σ²).
struct AxisStructure {
  std::string axis;  // e.g. "approach azimuth"
  double rms_um = 0.0, noise_rms_um = 0.0, ratio = 0.0;
};

// Everything the verdict, the summary and the plots share.
struct ReportData {
  int n = 0;
  double sigma = 0.0;
  std::vector<double> before, after, fitted_part;
  std::vector<double> azimuth_deg, order, roll_length, z;
  Bins azimuth, by_order, roll, face;
  Bins tooth[2];                    // left, right
  std::vector<AxisStructure> axes;  // sorted by ratio, largest first
  double mean_before = 0.0;
  double first_tenth = 0.0, last_tenth = 0.0;  // mean residual in the first / last tenth of order
};

ReportData report_data(const DiagnosisReportInput& in);

// What every section of the page reads.
struct ReportContext {
  const DiagnosisReportInput& in;
  const Diagnosis& d;
  const ReportData& r;
  int k;            // null replicates
  bool fitted_any;  // an effect was selected and fitted
};

}  // namespace gearmc::diagnose_report
