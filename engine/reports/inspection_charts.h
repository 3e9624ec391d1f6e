// Inspection charts in the conventions of gear-measuring instruments (the profile and helix
// sheets of gear-measuring software's protocols, e.g. Stein Software's GEARPAK: up to four teeth
// per page, the design line straight and vertical, left flank's chart beside the right's, the
// values and the class under each chart, red beyond tolerance): each flank's trace
// drawn vertically — roll length (profile, tip at the top) or face position (helix) upwards, the
// deviation magnified sideways at one scale for the whole sheet — left flanks on the left half,
// right flanks on the right, several teeth side by side; in every trace the evaluation range
// between its A (start) and E (end) marks, the measured trace and points, the real surface, the
// least-squares mean line and the tolerance template built from the scenario's tolerances
// (not a K-chart of AGMA 2000 / DIN 3961, which narrows the band inside the range); under every trace its values (F, f_H, f_f) with the tolerance, the run's U and
// the ISO 1328-1 class the value meets. Self-contained SVG text, like svg_plot.h. Deviations in
// µm along the design flank's normal (deviations from the design: the design line is straight
// and vertical), positions in mm.
#pragma once

#include <optional>
#include <string>
#include <vector>

namespace gearmc {

// One flank's trace as the chart draws it.
struct InspectionTrace {
  int tooth = 1;
  std::vector<double> x_mm, measured_um;            // sampled trace, ascending x (NaN: no value)
  std::vector<double> dense_x_mm, dense_um;         // the real surface (may be empty)
  double range_start_mm = 0.0, range_end_mm = 0.0;  // the evaluation range, A and E
  // The measured trace's mean line d = intercept + slope · (x − range_start); none when absent.
  std::optional<double> mean_intercept_um, mean_slope_um_per_mm;
};

// One parameter's row of values under the traces of one side.
struct InspectionValueRow {
  std::string symbol;                  // as printed, e.g. "Fα"
  std::optional<double> tolerance_um;  // T (±T when two_sided); none: no tolerance
  bool two_sided = false;
  std::optional<double> expanded_uncertainty_um;  // the run's U of this parameter and side
  std::vector<double> values_um;                  // one per trace (NaN: not evaluated)
  std::vector<std::optional<int>> classes;  // ISO 1328-1 class met, one per trace (empty: none)
};

struct InspectionSide {
  std::string name;  // "left flanks", "right flanks"
  std::vector<InspectionTrace> traces;
  std::vector<InspectionValueRow> rows;
};

struct InspectionSheet {
  std::string title;
  std::string position_label;  // e.g. "roll length L, mm"
  std::string top_word;        // e.g. "tip" (written above the position axis)
  // Positions grow downwards: an internal gear's profile, whose tip has the smaller roll length,
  // keeps its tip at the top (and A, at the root, at the bottom) like an external one's.
  bool positions_downwards = false;
  // The tolerance template: the total tolerance as a corridor of its width parallel
  // to the design line, placed where it encloses the trace best (centred on the trace's extremes
  // in the evaluation range, so the trace fits it exactly when F ≤ T); the slope tolerance as a
  // fan through the mean line's middle (the mean line lies inside it exactly when |f_H| ≤ f_HT).
  std::optional<double> total_tolerance_um, slope_tolerance_um;
  InspectionSide sides[2];  // [0] left flanks, [1] right flanks
};

// The deviation scale of a sheet: µm per grid division, the smallest of 1, 2, 2.5, 5 × 10^k
// with which every trace (centred on its own extremes in the evaluation range), the total
// tolerance's corridor and the slope tolerance's fan fit in ±2 divisions.
double inspection_division_um(const InspectionSheet& sheet);

// The cumulative pitch deviations F_pk = u_k − u_1 = f_pt,1 + … + f_pt,k−1 (ISO 1328-1:2013
// §3.2; F_p1 = 0) of the single pitch deviations f_pt,k (k = 1 … z, µm), as the F_p chart draws
// them; NaN after a NaN.
std::vector<double> cumulative_pitch_um(const std::vector<double>& single_pitch_um);

// The sheet as SVG (width 980 px): up to 4 traces per side.
std::string inspection_sheet_svg(const InspectionSheet& sheet);

}  // namespace gearmc
