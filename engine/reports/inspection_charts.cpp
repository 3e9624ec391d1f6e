// The profile and helix inspection sheets of inspection_charts.h: a fixed layout of 980 px,
// two halves (left and right flanks) of a position axis and up to four vertical trace panels,
// a block of values under them and a footer that says how to read the sheet.
#include "engine/reports/inspection_charts.h"

#include <algorithm>
#include <cmath>

#include "engine/reports/svg_canvas.h"

namespace gearmc {
namespace {
using namespace svg_canvas;

constexpr int kWidth = 980;
constexpr double kHalfWidth = 480.0, kLabelWidth = 110.0, kPanelWidth = 90.0;
constexpr int kPanels = 4;
constexpr double kPlotTop = 96.0, kPlotBottom = 416.0, kRowsTop = 436.0, kRowHeight = 34.0;
constexpr const char* kMeasuredColour = "#0072B2";
constexpr const char* kRealColour = "#999999";
constexpr const char* kMeanColour = "#D55E00";
constexpr const char* kTemplateColour = "#009E73";
constexpr const char* kOutColour = "#C00000";

// Whether x lies in the evaluation range (1 µm slack, as evaluate_trace_over counts samples).
bool in_range(const InspectionTrace& t, double x) {
  return x >= t.range_start_mm - 1e-3 && x <= t.range_end_mm + 1e-3;
}

// The centre of the trace's extremes in the evaluation range (0 without values there): where
// the total tolerance's corridor encloses the trace best.
double trace_centre(const InspectionTrace& t) {
  double lo = INFINITY, hi = -INFINITY;
  for (std::size_t i = 0; i < t.x_mm.size(); ++i) {
    if (!std::isfinite(t.measured_um[i]) || !in_range(t, t.x_mm[i])) continue;
    lo = std::min(lo, t.measured_um[i]);
    hi = std::max(hi, t.measured_um[i]);
  }
  return lo <= hi ? 0.5 * (lo + hi) : 0.0;
}

bool out_of_tolerance(const InspectionValueRow& row, double v) {
  if (!row.tolerance_um || !std::isfinite(v)) return false;
  return row.two_sided ? std::abs(v) > *row.tolerance_um : v > *row.tolerance_um;
}

std::string one_decimal(double v) { return std::isfinite(v) ? fixed(v, 1) : "–"; }

}  // namespace

double inspection_division_um(const InspectionSheet& sheet) {
  double reach = 0.0;
  if (sheet.total_tolerance_um) reach = 0.5 * *sheet.total_tolerance_um;
  for (const InspectionSide& side : sheet.sides) {
    for (const InspectionTrace& t : side.traces) {
      const double c = trace_centre(t);
      if (sheet.slope_tolerance_um && t.mean_intercept_um && t.mean_slope_um_per_mm) {
        const double mid = *t.mean_intercept_um +
                           0.5 * *t.mean_slope_um_per_mm * (t.range_end_mm - t.range_start_mm);
        reach = std::max(reach, std::abs(mid - c) + 0.5 * *sheet.slope_tolerance_um);
      }
      for (double v : t.measured_um) {
        if (std::isfinite(v)) reach = std::max(reach, std::abs(v - c));
      }
      for (double v : t.dense_um) {
        if (std::isfinite(v)) reach = std::max(reach, std::abs(v - c));
      }
    }
  }
  if (!(reach > 0.0) || !std::isfinite(reach)) return 1.0;
  // The smallest 1, 2, 2.5, 5 × 10^k µm with reach ≤ 2 divisions (the panel keeps 5 px beyond).
  const double decade = std::pow(10.0, std::floor(std::log10(reach / 2.0)));
  for (double step : {1.0, 2.0, 2.5, 5.0, 10.0}) {
    if (2.0 * step * decade >= reach) return step * decade;
  }
  return 10.0 * decade;
}

std::vector<double> cumulative_pitch_um(const std::vector<double>& single_pitch_um) {
  std::vector<double> out;
  double sum = 0.0;
  for (double f : single_pitch_um) {
    out.push_back(sum);
    sum += f;
  }
  return out;
}

std::string inspection_sheet_svg(const InspectionSheet& sheet) {
  const double division = inspection_division_um(sheet);
  // The position range shared by every panel, so A and E line up across the sheet.
  double y_lo = INFINITY, y_hi = -INFINITY;
  std::size_t rows = 0;
  for (const InspectionSide& side : sheet.sides) {
    rows = std::max(rows, side.rows.size());
    for (const InspectionTrace& t : side.traces) {
      y_lo = std::min({y_lo, t.range_start_mm, t.range_end_mm});
      y_hi = std::max({y_hi, t.range_start_mm, t.range_end_mm});
      for (double x : t.x_mm) {
        if (std::isfinite(x)) y_lo = std::min(y_lo, x), y_hi = std::max(y_hi, x);
      }
    }
  }
  if (!(y_lo < y_hi)) y_lo = 0.0, y_hi = 1.0;
  const double pad = 0.04 * (y_hi - y_lo);
  y_lo -= pad;
  y_hi += pad;
  const auto to_y = [&](double mm) {
    const double up = (mm - y_lo) / (y_hi - y_lo) * (kPlotBottom - kPlotTop);
    return sheet.positions_downwards ? kPlotTop + up : kPlotBottom - up;
  };
  const double px_per_um = (kPanelWidth / 2.0 - 5.0) / (2.0 * division);
  const int height = static_cast<int>(kRowsTop + kRowHeight * static_cast<double>(rows) + 58.0);

  Svg svg(kWidth, height);
  std::vector<LegendEntry> legend = {{"measured", kMeasuredColour, true},
                                     {"real surface", kRealColour, true},
                                     {"mean line", kMeanColour, true}};
  if (sheet.total_tolerance_um || sheet.slope_tolerance_um) {
    legend.push_back({"tolerance template", kTemplateColour, true});
  }
  draw_header(svg, kWidth, sheet.title, legend,
              "1 division = " + fixed(division, division < 1.0 ? 2 : 1) + " µm");

  const Ticks position_ticks = loose_ticks(y_lo, y_hi, 7);
  for (int s = 0; s < 2; ++s) {
    const InspectionSide& side = sheet.sides[s];
    const double x0 = 10.0 + s * (kHalfWidth + 10.0);
    const double panels_left = x0 + kLabelWidth;
    svg.text(panels_left + kPanels * kPanelWidth / 2.0, 66.0, side.name, "middle",
             " font-size=\"13\" font-weight=\"bold\"");
    // The position axis at the label column's right edge.
    const double axis_x = panels_left - 6.0;
    svg.line(axis_x, kPlotTop, axis_x, kPlotBottom, kAxisColour);
    for (double v : tick_values(position_ticks, y_lo, y_hi)) {
      svg.line(axis_x - 4, to_y(v), axis_x, to_y(v), kAxisColour);
      svg.text(axis_x - 7, to_y(v) + 4, fixed(v, position_ticks.decimals), "end");
    }
    svg.text(x0 + 30.0, (kPlotTop + kPlotBottom) / 2, sheet.position_label, "middle", "", -90.0);
    if (!sheet.top_word.empty()) {
      svg.text(axis_x, kPlotTop - 6.0, sheet.top_word + " ↑", "end", " font-size=\"11\"");
    }
    for (int k = 0; k < kPanels; ++k) {
      const double left = panels_left + k * kPanelWidth;
      const double xc = left + kPanelWidth / 2.0;
      svg.rect(left, kPlotTop, kPanelWidth, kPlotBottom - kPlotTop, "none",
               " stroke=\"#cccccc\" stroke-width=\"1\"");
      if (k >= static_cast<int>(side.traces.size())) continue;
      const InspectionTrace& t = side.traces[k];
      svg.text(xc, kPlotTop - 8.0, std::to_string(t.tooth), "middle",
               " font-size=\"13\" font-weight=\"bold\"");
      for (int g = -2; g <= 2; ++g) {
        const double x = xc + g * division * px_per_um;
        svg.line(x, kPlotTop, x, kPlotBottom, g == 0 ? "#b0b0b0" : kGridColour);
      }
      const double c = trace_centre(t);
      const auto to_x = [&](double um) { return xc + (um - c) * px_per_um; };
      const double ya = to_y(t.range_start_mm), ye = to_y(t.range_end_mm);
      // A and E: the evaluation range's start and end.
      for (const auto& [y, mark] : {std::pair{ya, "A"}, std::pair{ye, "E"}}) {
        svg.line(left, y, left + kPanelWidth, y, "#888888", 1.0, true);
        svg.text(left + 3.0, y - 3.0, mark, "start", " font-size=\"10\" fill=\"#555555\"");
      }
      if (sheet.total_tolerance_um) {
        const double h = 0.5 * *sheet.total_tolerance_um;
        for (double side_x : {to_x(c - h), to_x(c + h)}) {
          svg.line(side_x, ya, side_x, ye, kTemplateColour, 1.5);
          svg.line(side_x - 3, ya, side_x + 3, ya, kTemplateColour, 1.5);
          svg.line(side_x - 3, ye, side_x + 3, ye, kTemplateColour, 1.5);
        }
      }
      if (t.mean_intercept_um && t.mean_slope_um_per_mm) {
        const double length = t.range_end_mm - t.range_start_mm;
        const double start = *t.mean_intercept_um;
        const double end = start + *t.mean_slope_um_per_mm * length;
        if (sheet.slope_tolerance_um) {
          const double mid = 0.5 * (start + end), h = 0.5 * *sheet.slope_tolerance_um;
          svg.line(to_x(mid - h), ya, to_x(mid + h), ye, kTemplateColour, 1.0, true);
          svg.line(to_x(mid + h), ya, to_x(mid - h), ye, kTemplateColour, 1.0, true);
        }
        svg.line(to_x(start), ya, to_x(end), ye, kMeanColour, 1.5);
      }
      std::vector<std::pair<double, double>> real;
      for (std::size_t i = 0; i < t.dense_x_mm.size(); ++i) {
        if (std::isfinite(t.dense_um[i]))
          real.emplace_back(to_x(t.dense_um[i]), to_y(t.dense_x_mm[i]));
      }
      svg.polyline(real, kRealColour, 1.0);
      // The measured trace, broken where a point has no value.
      std::vector<std::pair<double, double>> piece;
      const auto flush = [&] {
        svg.polyline(piece, kMeasuredColour, 1.5);
        piece.clear();
      };
      for (std::size_t i = 0; i < t.x_mm.size(); ++i) {
        if (!std::isfinite(t.measured_um[i])) {
          flush();
          continue;
        }
        piece.emplace_back(to_x(t.measured_um[i]), to_y(t.x_mm[i]));
        svg.circle(piece.back().first, piece.back().second, 1.6, kMeasuredColour);
      }
      flush();
    }
    // The values under the traces: per parameter the symbol, T and U in the label column, and
    // under every trace its value (red beyond the tolerance) and the class it meets.
    for (std::size_t r = 0; r < side.rows.size(); ++r) {
      const InspectionValueRow& row = side.rows[r];
      const double y = kRowsTop + kRowHeight * static_cast<double>(r);
      svg.line(x0, y - 2, panels_left + kPanels * kPanelWidth, y - 2, "#dddddd");
      svg.text(x0, y + 12, row.symbol + ", µm", "start", " font-weight=\"bold\"");
      std::string limits;
      if (row.tolerance_um)
        limits = (row.two_sided ? "T ±" : "T ") + one_decimal(*row.tolerance_um);
      if (row.expanded_uncertainty_um) {
        limits += (limits.empty() ? "U " : "  U ") + one_decimal(*row.expanded_uncertainty_um);
      }
      svg.text(x0, y + 26, limits, "start", " font-size=\"10.5\" fill=\"#555555\"");
      for (std::size_t k = 0; k < row.values_um.size() && k < kPanels; ++k) {
        const double xc = panels_left + (static_cast<double>(k) + 0.5) * kPanelWidth;
        const double v = row.values_um[k];
        svg.text(xc, y + 12, one_decimal(v), "middle",
                 out_of_tolerance(row, v)
                     ? std::string(" fill=\"") + kOutColour + "\" font-weight=\"bold\""
                     : std::string());
        if (k < row.classes.size()) {
          svg.text(xc, y + 26,
                   row.classes[k] ? "Q" + std::to_string(*row.classes[k]) : std::string("Q>11"),
                   "middle", " font-size=\"10.5\" fill=\"#555555\"");
        }
      }
    }
  }
  const double foot = kRowsTop + kRowHeight * static_cast<double>(rows) + 16.0;
  svg.text(10.0, foot,
           "A–E: evaluation range. Centre line of each trace: the design flank; + to the right = "
           "material added (along the outward normal).",
           "start", " font-size=\"11\" fill=\"#555555\"");
  svg.text(10.0, foot + 16.0,
           "Template: the total tolerance as a corridor around the trace's extremes (solid), the "
           "slope tolerance as a fan through the mean line's middle (dashed).",
           "start", " font-size=\"11\" fill=\"#555555\"");
  return svg.finish();
}

}  // namespace gearmc
