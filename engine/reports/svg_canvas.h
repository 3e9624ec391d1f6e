// The drawing primitives the plots of svg_plot.cpp share: the colour-blind-safe Okabe-Ito
// palette (Okabe & Ito 2008), number formatting, "nice" axis ticks (Heckbert, "Nice numbers for
// graph labels", Graphics Gems, 1990), a minimal SVG writer that escapes every text, the
// Cartesian frame (plot area and data range, data → px), the axes with grid and labels, the
// labelled vertical markers and the header with title and one legend row. Internal to
// engine/reports: only svg_plot.cpp includes it. Coordinates in px unless named data units.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "engine/reports/svg_plot.h"

namespace gearmc::svg_canvas {

// Okabe & Ito (2008), "Color universal design": distinguishable with any colour vision.
inline constexpr const char* kPalette[] = {"#0072B2", "#D55E00", "#009E73", "#CC79A7",
                                           "#E69F00", "#56B4E9", "#000000", "#F0E442"};
inline constexpr std::size_t kPaletteSize = sizeof kPalette / sizeof kPalette[0];
inline constexpr const char* kGridColour = "#e4e4e4";
inline constexpr const char* kAxisColour = "#333333";

inline std::string colour_or(const std::string& colour, std::size_t palette_index) {
  return colour.empty() ? kPalette[palette_index % kPaletteSize] : colour;
}

// A number with a fixed count of decimals; "-0" is written as "0".
inline std::string fixed(double v, int decimals) {
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, "%.*f", decimals, v);
  std::string s = buffer;
  if (s.find_first_not_of("-0.") == std::string::npos && s.front() == '-') s.erase(0, 1);
  return s;
}

// Pixel coordinates: two decimals are far below what a screen resolves.
inline std::string px(double v) { return fixed(v, 2); }

// --- Nice ticks (Heckbert 1990)
// -------------------------------------------------------------------

inline double nice_number(double x, bool round) {
  const double exponent = std::floor(std::log10(x));
  const double fraction = x / std::pow(10.0, exponent);
  double nice;
  if (round) {
    nice = fraction < 1.5 ? 1 : fraction < 3 ? 2 : fraction < 7 ? 5 : 10;
  } else {
    nice = fraction <= 1 ? 1 : fraction <= 2 ? 2 : fraction <= 5 ? 5 : 10;
  }
  return nice * std::pow(10.0, exponent);
}

struct Ticks {
  double lo, hi, step;
  int decimals;  // enough to tell the ticks apart
};

// Heckbert's "loose labelling": the axis [lo, hi] extended to multiples of a 1-2-5 step.
// An empty or degenerate range is widened first.
inline Ticks loose_ticks(double lo, double hi, int target_ticks = 6) {
  if (!std::isfinite(lo) || !std::isfinite(hi)) lo = 0, hi = 1;
  if (hi < lo) std::swap(lo, hi);
  if (hi - lo <= 1e-12 * std::max(std::abs(lo), std::abs(hi))) {
    const double pad = lo == 0.0 ? 1.0 : 0.1 * std::abs(lo);
    lo -= pad;
    hi += pad;
  }
  const double range = nice_number(hi - lo, false);
  const double step = nice_number(range / (target_ticks - 1), true);
  Ticks t;
  t.step = step;
  t.lo = std::floor(lo / step + 1e-9) * step;
  t.hi = std::ceil(hi / step - 1e-9) * step;
  t.decimals = std::max(0, static_cast<int>(-std::floor(std::log10(step) + 1e-9)));
  return t;
}

// The tick values of `t` that lie within [lo, hi] (an axis that may be narrower than t).
inline std::vector<double> tick_values(const Ticks& t, double lo, double hi) {
  std::vector<double> values;
  const double first = std::ceil(lo / t.step - 1e-9);
  for (double k = first;; k += 1.0) {
    double v = k * t.step;
    if (v > hi + 1e-9 * t.step) break;
    if (std::abs(v) < 1e-9 * t.step) v = 0.0;
    values.push_back(v);
    if (values.size() > 100) break;  // guard against a pathological explicit range
  }
  return values;
}

// --- A minimal SVG writer -----------------------------------------------------------------------

class Svg {
 public:
  Svg(int width, int height) {
    out_ = "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" + std::to_string(width) +
           "\" height=\"" + std::to_string(height) + "\" viewBox=\"0 0 " + std::to_string(width) +
           ' ' + std::to_string(height) +
           "\" font-family=\"Helvetica, Arial, sans-serif\" font-size=\"12\">\n";
    out_ += "<rect x=\"0\" y=\"0\" width=\"" + std::to_string(width) + "\" height=\"" +
            std::to_string(height) + "\" fill=\"#ffffff\"/>\n";
  }
  void line(double x1, double y1, double x2, double y2, const std::string& stroke,
            double stroke_width = 1.0, bool dashed = false) {
    out_ += "<line x1=\"" + px(x1) + "\" y1=\"" + px(y1) + "\" x2=\"" + px(x2) + "\" y2=\"" +
            px(y2) + "\" stroke=\"" + escape_xml(stroke) + "\" stroke-width=\"" + px(stroke_width) +
            '"' + (dashed ? " stroke-dasharray=\"6 4\"" : "") + "/>\n";
  }
  void rect(double x, double y, double w, double h, const std::string& fill,
            const std::string& extra = "", const std::string& tooltip = "") {
    out_ += "<rect" + extra + " x=\"" + px(x) + "\" y=\"" + px(y) + "\" width=\"" + px(w) +
            "\" height=\"" + px(h) + "\" fill=\"" + escape_xml(fill) + '"';
    if (tooltip.empty()) {
      out_ += "/>\n";
    } else {
      out_ += "><title>" + escape_xml(tooltip) + "</title></rect>\n";
    }
  }
  void circle(double x, double y, double r, const std::string& fill) {
    out_ += "<circle cx=\"" + px(x) + "\" cy=\"" + px(y) + "\" r=\"" + px(r) + "\" fill=\"" +
            escape_xml(fill) + "\" fill-opacity=\"0.75\"/>\n";
  }
  void polyline(const std::vector<std::pair<double, double>>& points, const std::string& stroke,
                double stroke_width = 1.5) {
    if (points.size() < 2) return;
    out_ += "<polyline fill=\"none\" stroke=\"" + escape_xml(stroke) + "\" stroke-width=\"" +
            px(stroke_width) + "\" stroke-linejoin=\"round\" points=\"";
    for (std::size_t i = 0; i < points.size(); ++i) {
      if (i > 0) out_ += ' ';
      out_ += px(points[i].first) + ',' + px(points[i].second);
    }
    out_ += "\"/>\n";
  }
  // anchor: "start", "middle" or "end"; rotate: degrees about (x, y).
  void text(double x, double y, std::string_view content, const std::string& anchor = "start",
            const std::string& extra = "", double rotate = 0.0) {
    out_ += "<text x=\"" + px(x) + "\" y=\"" + px(y) + "\" text-anchor=\"" + anchor + '"';
    if (rotate != 0.0) {
      out_ += " transform=\"rotate(" + px(rotate) + ' ' + px(x) + ' ' + px(y) + ")\"";
    }
    out_ += extra + '>' + escape_xml(content) + "</text>\n";
  }
  std::string finish() { return out_ + "</svg>\n"; }

 private:
  std::string out_;
};

// --- The Cartesian frame shared by the histogram and the XY plot --------------------------------

struct Frame {
  double left, top, right, bottom;  // the plot area, px
  double x_lo, x_hi, y_lo, y_hi;    // data range
  double to_x(double x) const { return left + (x - x_lo) / (x_hi - x_lo) * (right - left); }
  double to_y(double y) const { return bottom - (y - y_lo) / (y_hi - y_lo) * (bottom - top); }
};

inline Frame make_frame(int width, int height, double x_lo, double x_hi, double y_lo, double y_hi) {
  return {70.0, 56.0, width - 24.0, height - 50.0, x_lo, x_hi, y_lo, y_hi};
}

// A power of ten 10^k as a tick label: "1", "10", …, "100000", then "10^6" written 1e6.
inline std::string power_of_ten(double k) {
  const int e = static_cast<int>(std::lround(k));
  if (e >= 0 && e <= 5) return fixed(std::pow(10.0, e), 0);
  return "1e" + std::to_string(e);
}

// y_log: the y data are log10 values, labelled as the powers of ten.
inline void draw_axes(Svg& svg, const Frame& f, const Ticks& xt, const Ticks& yt,
                      const std::string& x_label, const std::string& y_label, bool y_log = false) {
  for (double v : tick_values(yt, f.y_lo, f.y_hi)) {
    const double y = f.to_y(v);
    svg.line(f.left, y, f.right, y, kGridColour);
    svg.line(f.left - 5, y, f.left, y, kAxisColour);
    svg.text(f.left - 8, y + 4, y_log ? power_of_ten(v) : fixed(v, yt.decimals), "end");
  }
  for (double v : tick_values(xt, f.x_lo, f.x_hi)) {
    const double x = f.to_x(v);
    svg.line(x, f.top, x, f.bottom, kGridColour);
    svg.line(x, f.bottom, x, f.bottom + 5, kAxisColour);
    svg.text(x, f.bottom + 18, fixed(v, xt.decimals), "middle");
  }
  svg.line(f.left, f.bottom, f.right, f.bottom, kAxisColour);
  svg.line(f.left, f.top, f.left, f.bottom, kAxisColour);
  if (!x_label.empty()) svg.text((f.left + f.right) / 2, f.bottom + 38, x_label, "middle");
  if (!y_label.empty()) svg.text(18, (f.top + f.bottom) / 2, y_label, "middle", "", -90.0);
}

inline void draw_markers(Svg& svg, const Frame& f, const std::vector<MarkerLine>& markers,
                         std::size_t first_colour) {
  for (std::size_t k = 0; k < markers.size(); ++k) {
    const MarkerLine& m = markers[k];
    if (!(m.x >= f.x_lo && m.x <= f.x_hi)) continue;
    const std::string colour = colour_or(m.colour, first_colour + k);
    const double x = f.to_x(m.x);
    svg.line(x, f.top, x, f.bottom, colour, 1.5, m.dashed);
    if (m.label.empty()) continue;
    // Labels stack downwards from the top; on the right half they sit left of their line.
    const bool right_half = x > (f.left + f.right) / 2;
    svg.text(right_half ? x - 4 : x + 4, f.top + 14.0 + 15.0 * static_cast<double>(k), m.label,
             right_half ? "end" : "start",
             " fill=\"" + escape_xml(colour) +
                 "\" stroke=\"#ffffff\" stroke-width=\"3\" paint-order=\"stroke\"");
  }
}

struct LegendEntry {
  std::string label, colour;
  bool is_line;          // a line swatch, otherwise a filled square
  double opacity = 1.0;  // of the square
};

// Approximate rendered width (px) of 12 px sans-serif text: 6.5 px per character (UTF-8
// continuation bytes not counted).
inline double text_width(std::string_view text) {
  double characters = 0;
  for (char c : text) characters += (static_cast<unsigned char>(c) & 0xC0) != 0x80;
  return 6.5 * characters;
}

// The header above the plot area: the title (y = 22) and one centred row (y = 42) with the
// legend entries followed by a grey note. Kept out of the plot area so it never hides data.
// The legend's rows: entries in order, a new row when the next would pass the right edge.
constexpr double kLegendSwatch = 22.0, kLegendGap = 18.0, kLegendRow = 42.0, kLegendRowStep = 18.0;
inline double legend_entry_width(const LegendEntry& e) {
  return kLegendSwatch + text_width(e.label) + kLegendGap;
}
inline int legend_rows(int width, const std::vector<LegendEntry>& legend,
                       const std::string& note = "") {
  int rows = 1;
  double x = 4.0;
  for (const LegendEntry& e : legend) {
    if (x > 4.0 && x + legend_entry_width(e) > width - 4.0) ++rows, x = 4.0;
    x += legend_entry_width(e);
  }
  if (!note.empty() && x > 4.0 && x + text_width(note) > width - 4.0) ++rows;
  return rows;
}

// The title and the legend under it: one centred row when it fits, else rows from the left
// (legend_rows of them, kLegendRowStep apart; the caller leaves room for the extra rows).
inline void draw_header(Svg& svg, int width, const std::string& title,
                        const std::vector<LegendEntry>& legend, const std::string& note = "") {
  if (!title.empty()) {
    svg.text(width / 2.0, 22.0, title, "middle", " font-size=\"15\" font-weight=\"bold\"");
  }
  double total = note.empty() ? 0.0 : text_width(note);
  for (const LegendEntry& e : legend) total += legend_entry_width(e);
  const bool one_row = legend_rows(width, legend, note) == 1;
  double x = one_row ? std::max(4.0, (width - total) / 2.0) : 4.0;
  double row = kLegendRow;
  for (const LegendEntry& e : legend) {
    if (!one_row && x > 4.0 && x + legend_entry_width(e) > width - 4.0) {
      x = 4.0;
      row += kLegendRowStep;
    }
    if (e.is_line) {
      svg.line(x, row - 4, x + 16, row - 4, e.colour, 2.0);
    } else if (e.opacity < 1.0) {
      svg.rect(x + 2, row - 10, 12, 12, e.colour, " fill-opacity=\"" + fixed(e.opacity, 2) + "\"");
    } else {
      svg.rect(x + 2, row - 10, 12, 12, e.colour);
    }
    svg.text(x + kLegendSwatch, row, e.label);
    x += legend_entry_width(e);
  }
  if (!note.empty()) {
    if (!one_row && x > 4.0 && x + text_width(note) > width - 4.0) x = 4.0, row += kLegendRowStep;
    svg.text(x, row, note, "start", " fill=\"#555555\"");
  }
}

}  // namespace gearmc::svg_canvas
