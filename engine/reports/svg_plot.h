// Plots as standalone SVG text, with no dependency beyond the standard library: the δRcomp
// histogram of the `run` report (P1's Fig. 5, docs/sources.md) with an optional fitted-density
// overlay and labelled vertical markers (quantiles, P1's claim), a generic XY line/scatter/stem
// plot with optional shaded bands, and a polar scatter plot (value against approach azimuth) for
// the diagnosis report. All three share one look: white background, a header with the title and one
// legend row (outside the plot area, so it never hides data), axes with "nice" ticks (Heckbert,
// "Nice numbers for graph labels", Graphics Gems, 1990), light grid, the colour-blind-safe
// Okabe-Ito palette (Okabe & Ito 2008). Every text is XML-escaped. The output has no XML
// declaration and no id attributes, so several plots can be inlined into one HTML page. Coordinates
// are in data units (µm for deviations, radians for polar angles); sizes in px.
#pragma once

#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "engine/statistics/histogram.h"

namespace gearmc {

// The text with & < > " ' replaced by their XML entities (valid in HTML too).
std::string escape_xml(std::string_view text);

// A vertical line at x (data units) across the plot area, labelled near its top,
// e.g. {3.1, "p99.73 = 3.1 µm"} or {4.0, "P1 claim 4 µm"}.
struct MarkerLine {
  double x = 0.0;
  std::string label;
  std::string colour;  // CSS colour; empty: the next palette colour
  bool dashed = true;
};

struct HistogramPlotOptions {
  std::string title;
  std::string x_label = "δRcomp, µm";
  std::string y_label = "count";
  std::string bars_label;  // legend entry for the bars; empty: none
  // Optional overlay: a probability density f (1/µm) drawn as the expected count per bar,
  // f(x) n w (n = histogram.total(), w = the histogram's bin width), with a legend entry.
  std::function<double(double)> overlay_pdf;
  std::string overlay_label = "fitted density";
  std::vector<MarkerLine> markers;
  // The x range shown (µm). Default: the histogram's lo to the upper edge of its last occupied
  // bin, widened to include the markers, rounded out to ticks.
  std::optional<double> x_min, x_max;
  // The top of the count axis (e.g. the same for the left and right flanks' plots); default:
  // the tallest shown bar or overlay value. Rounded up to a tick (with log_count: a power of 10).
  std::optional<double> y_max;
  // A log10 count axis (ticks 1, 10, 100, …, from a count of 0.5 so a single count shows), so a
  // tail of a few counts is as visible as the peak; empty bins are not drawn.
  bool log_count = false;
  int width_px = 640, height_px = 400;
};

// Bar chart of `histogram` (usually a display histogram, Histogram::rebin): one bar per bin in
// the shown range, bar height proportional to the count (y axis from 0), each bar with a
// <title> tooltip "[lo, hi) µm: count". Under/overflow counts are noted in the header when
// non-zero.
std::string histogram_svg(const Histogram& histogram, const HistogramPlotOptions& options);

// Horizontal bars, one per label, from 0 to value (values >= 0, e.g. shares of a variance in
// %), each labelled with its value; bars in the order given, top to bottom.
struct BarChartOptions {
  std::string title, x_label;
  int decimals = 1;  // of the value labels
  int width_px = 640;
};
std::string bar_chart_svg(const std::vector<std::string>& labels, const std::vector<double>& values,
                          const BarChartOptions& options);

// kStems: a stem plot (e.g. a spectrum: one amplitude per harmonic order), each point a vertical
// line from y = 0 (or the nearer edge of the y range) to y with a dot at y; no line joins points.
enum class SeriesStyle { kLine, kPoints, kLineAndPoints, kStems };

// One data series; non-finite points are skipped (a line is broken there).
struct Series {
  std::string label;  // legend entry; empty: none
  std::vector<double> x, y;
  SeriesStyle style = SeriesStyle::kLine;
  std::string colour;  // CSS colour; empty: the next palette colour
};

// A vertical whisker with caps from y = lower to upper at x (e.g. a confidence band), drawn over
// the series; inside the default y range. Non-finite ends: not drawn.
struct ErrorBar {
  double x = 0.0, lower = 0.0, upper = 0.0;
  std::string colour;        // CSS colour; empty: grey
  double x_offset_px = 0.0;  // drawn this far right of x (bars of several lines at one x)
};

// Large pale discs under the series at (x, y) with a legend entry, marking points (e.g. a
// verdict: meets, misses).
struct PointHalos {
  std::string label, colour;
  std::vector<double> x, y;
};

// A labelled horizontal line across the plot area (e.g. a limit), dashed, its label at the right
// end above the line; inside the default y range.
struct HorizontalLine {
  double y = 0.0;
  std::string label;
  std::string colour = "#c0392b";
};

// A shaded horizontal band lo ≤ y ≤ hi (data units) across the plot area, under the data, with
// a legend entry, e.g. the range a bin mean of pure noise stays within (±2σ/√n).
struct HorizontalBand {
  double lo = 0.0, hi = 0.0;
  std::string label;   // legend entry; empty: none
  std::string colour;  // CSS colour, drawn at 20 % opacity; empty: grey
};

struct XYPlotOptions {
  std::string title, x_label, y_label;
  std::vector<MarkerLine> markers;          // vertical lines at x
  std::vector<double> horizontal_lines;     // thin reference lines at y (e.g. 0)
  std::vector<HorizontalBand> bands;        // shaded y ranges, inside the default range
  std::vector<HorizontalLine> limit_lines;  // labelled dashed lines at y
  std::vector<ErrorBar> error_bars;
  std::vector<PointHalos> halos;
  std::optional<double> x_min, x_max, y_min, y_max;  // default: the data (and lines), rounded out
  bool y_from_zero = false;                          // include y = 0 in the default range
  int width_px = 640, height_px = 400;
};

std::string xy_plot_svg(const std::vector<Series>& series, const XYPlotOptions& options);

// Points at (angle, radius): angle in radians, counter-clockwise from +X (the approach azimuth
// φ of docs/formats.md), radius in data units.
struct PolarSeries {
  std::string label;
  std::vector<double> angle_rad, radius;
  SeriesStyle style = SeriesStyle::kPoints;
  std::string colour;
};

struct PolarPlotOptions {
  std::string title;
  std::string radius_label;  // e.g. "pre-travel, µm", written under the plot
  // Radius at the centre and at the outer ring. Default: r_min = 0 if every radius is >= 0,
  // otherwise the data minimum rounded down to a tick (so signed residuals can be shown);
  // r_max = the data maximum rounded up. Radii below r_min are drawn at the centre.
  std::optional<double> r_min, r_max;
  int size_px = 480;  // the plot is square
};

std::string polar_plot_svg(const std::vector<PolarSeries>& series, const PolarPlotOptions& options);

}  // namespace gearmc
