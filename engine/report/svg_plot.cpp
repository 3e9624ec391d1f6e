// SVG text for the report's plots: a small writer, Heckbert's nice ticks, and the three plot
// kinds (see svg_plot.h).
#include "engine/report/svg_plot.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numbers>

namespace gearmc {
namespace {

// Okabe & Ito (2008), "Color universal design": distinguishable with any colour vision.
constexpr const char* kPalette[] = {"#0072B2", "#D55E00", "#009E73", "#CC79A7",
                                    "#E69F00", "#56B4E9", "#000000", "#F0E442"};
constexpr std::size_t kPaletteSize = sizeof kPalette / sizeof kPalette[0];
constexpr const char* kGridColour = "#e4e4e4";
constexpr const char* kAxisColour = "#333333";

std::string colour_or(const std::string& colour, std::size_t palette_index) {
  return colour.empty() ? kPalette[palette_index % kPaletteSize] : colour;
}

// A number with a fixed count of decimals; "-0" is written as "0".
std::string fixed(double v, int decimals) {
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, "%.*f", decimals, v);
  std::string s = buffer;
  if (s.find_first_not_of("-0.") == std::string::npos && s.front() == '-') s.erase(0, 1);
  return s;
}

// Pixel coordinates: two decimals are far below what a screen resolves.
std::string px(double v) { return fixed(v, 2); }

// --- Nice ticks (Heckbert 1990)
// -------------------------------------------------------------------

double nice_number(double x, bool round) {
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
Ticks loose_ticks(double lo, double hi, int target_ticks = 6) {
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
std::vector<double> tick_values(const Ticks& t, double lo, double hi) {
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

Frame make_frame(int width, int height, double x_lo, double x_hi, double y_lo, double y_hi) {
  return {70.0, 56.0, width - 24.0, height - 50.0, x_lo, x_hi, y_lo, y_hi};
}

// A power of ten 10^k as a tick label: "1", "10", …, "100000", then "10^6" written 1e6.
std::string power_of_ten(double k) {
  const int e = static_cast<int>(std::lround(k));
  if (e >= 0 && e <= 5) return fixed(std::pow(10.0, e), 0);
  return "1e" + std::to_string(e);
}

// y_log: the y data are log10 values, labelled as the powers of ten.
void draw_axes(Svg& svg, const Frame& f, const Ticks& xt, const Ticks& yt,
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

void draw_markers(Svg& svg, const Frame& f, const std::vector<MarkerLine>& markers,
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
double text_width(std::string_view text) {
  double characters = 0;
  for (char c : text) characters += (static_cast<unsigned char>(c) & 0xC0) != 0x80;
  return 6.5 * characters;
}

// The header above the plot area: the title (y = 22) and one centred row (y = 42) with the
// legend entries followed by a grey note. Kept out of the plot area so it never hides data.
void draw_header(Svg& svg, int width, const std::string& title,
                 const std::vector<LegendEntry>& legend, const std::string& note = "") {
  if (!title.empty()) {
    svg.text(width / 2.0, 22.0, title, "middle", " font-size=\"15\" font-weight=\"bold\"");
  }
  constexpr double kSwatch = 22.0, kGap = 18.0, kRow = 42.0;
  double total = note.empty() ? 0.0 : text_width(note);
  for (const LegendEntry& e : legend) total += kSwatch + text_width(e.label) + kGap;
  double x = std::max(4.0, (width - total) / 2.0);
  for (const LegendEntry& e : legend) {
    if (e.is_line) {
      svg.line(x, kRow - 4, x + 16, kRow - 4, e.colour, 2.0);
    } else if (e.opacity < 1.0) {
      svg.rect(x + 2, kRow - 10, 12, 12, e.colour, " fill-opacity=\"" + fixed(e.opacity, 2) + "\"");
    } else {
      svg.rect(x + 2, kRow - 10, 12, 12, e.colour);
    }
    svg.text(x + kSwatch, kRow, e.label);
    x += kSwatch + text_width(e.label) + kGap;
  }
  if (!note.empty()) svg.text(x, kRow, note, "start", " fill=\"#555555\"");
}

bool draws_lines(SeriesStyle s) {
  return s == SeriesStyle::kLine || s == SeriesStyle::kLineAndPoints;
}
bool draws_points(SeriesStyle s) { return s != SeriesStyle::kLine; }

}  // namespace

std::string escape_xml(std::string_view text) {
  std::string out;
  out.reserve(text.size());
  for (char c : text) {
    switch (c) {
      case '&':
        out += "&amp;";
        break;
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '"':
        out += "&quot;";
        break;
      case '\'':
        out += "&#39;";
        break;
      default:
        out += c;
    }
  }
  return out;
}

std::string histogram_svg(const Histogram& histogram, const HistogramPlotOptions& options) {
  // The x range: lo to the last occupied bin, widened to the markers, rounded out to ticks.
  std::size_t last = 0;
  bool any = false;
  for (std::size_t i = 0; i < histogram.bin_count(); ++i) {
    if (histogram.count(i) > 0) last = i, any = true;
  }
  double x_lo = histogram.lo();
  double x_hi = any ? histogram.edge(last + 1) : histogram.hi();
  for (const MarkerLine& m : options.markers) {
    if (std::isfinite(m.x)) x_lo = std::min(x_lo, m.x), x_hi = std::max(x_hi, m.x);
  }
  const Ticks xt0 = loose_ticks(options.x_min.value_or(x_lo), options.x_max.value_or(x_hi));
  x_lo = options.x_min.value_or(xt0.lo);
  x_hi = options.x_max.value_or(xt0.hi);

  // The y range: the tallest shown bar or overlay value, rounded up to a tick.
  double y_top = 0.0;
  for (std::size_t i = 0; i < histogram.bin_count(); ++i) {
    if (histogram.edge(i + 1) > x_lo && histogram.edge(i) < x_hi) {
      y_top = std::max(y_top, static_cast<double>(histogram.count(i)));
    }
  }
  std::vector<std::pair<double, double>> overlay;  // (x, expected count)
  if (options.overlay_pdf) {
    const double scale = static_cast<double>(histogram.total()) * histogram.width();
    constexpr int kSamples = 400;
    for (int i = 0; i <= kSamples; ++i) {
      const double x = x_lo + (x_hi - x_lo) * i / kSamples;
      const double y = options.overlay_pdf(x) * scale;
      if (std::isfinite(y)) {
        overlay.emplace_back(x, y);
        y_top = std::max(y_top, y);
      }
    }
  }
  if (options.y_max && *options.y_max > 0.0) y_top = *options.y_max;
  // The count axis: linear from 0, or log10 from a count of 0.5 up to the next power of ten with
  // a tick at every power of ten.
  const bool log = options.log_count;
  const double log_floor = std::log10(0.5);
  const Ticks yt =
      log ? Ticks{0.0, std::max(1.0, std::ceil(std::log10(std::max(y_top, 1.0)) - 1e-9)), 1.0, 0}
          : loose_ticks(0.0, y_top > 0 ? y_top : 1.0, 6);
  const auto to_axis = [&](double count) { return log ? std::log10(count) : count; };
  const Frame f =
      make_frame(options.width_px, options.height_px, x_lo, x_hi, log ? log_floor : 0.0, yt.hi);
  const Ticks xt = loose_ticks(x_lo, x_hi);

  std::string note;
  if (histogram.underflow() > 0 || histogram.overflow() > 0) {
    note = "outside the bins: " + std::to_string(histogram.underflow()) + " below, " +
           std::to_string(histogram.overflow()) + " above";
  }
  Svg svg(options.width_px, options.height_px);
  draw_axes(svg, f, xt, yt, options.x_label, options.y_label, log);

  const int decimals = std::max(0, static_cast<int>(-std::floor(std::log10(histogram.width()))));
  for (std::size_t i = 0; i < histogram.bin_count(); ++i) {
    const std::uint64_t count = histogram.count(i);
    const double lo = std::max(histogram.edge(i), x_lo), hi = std::min(histogram.edge(i + 1), x_hi);
    if (count == 0 || !(hi > lo)) continue;
    const double top = f.to_y(std::min(to_axis(static_cast<double>(count)), yt.hi));
    svg.rect(f.to_x(lo), top, f.to_x(hi) - f.to_x(lo), f.bottom - top, kPalette[0],
             " class=\"bar\" fill-opacity=\"0.8\" stroke=\"#ffffff\" stroke-width=\"0.5\"",
             "[" + fixed(histogram.edge(i), decimals + 1) + ", " +
                 fixed(histogram.edge(i + 1), decimals + 1) + ") µm: " + std::to_string(count));
  }
  if (!overlay.empty()) {
    std::vector<std::pair<double, double>> points;
    for (const auto& [x, y] : overlay) {
      if (log && !(y >= 0.5)) {  // below the log axis: break the line there
        svg.polyline(points, kPalette[1], 2.0);
        points.clear();
        continue;
      }
      points.emplace_back(f.to_x(x), f.to_y(std::min(to_axis(y), yt.hi)));
    }
    svg.polyline(points, kPalette[1], 2.0);
  }
  draw_markers(svg, f, options.markers, 2);

  std::vector<LegendEntry> legend;
  if (!options.bars_label.empty()) legend.push_back({options.bars_label, kPalette[0], false});
  if (options.overlay_pdf) legend.push_back({options.overlay_label, kPalette[1], true});
  draw_header(svg, options.width_px, options.title, legend, note);
  return svg.finish();
}

std::string bar_chart_svg(const std::vector<std::string>& labels, const std::vector<double>& values,
                          const BarChartOptions& options) {
  constexpr double kRowHeight = 26.0, kTop = 44.0;
  const std::size_t n = std::min(labels.size(), values.size());
  double label_width = 0.0, top = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    label_width = std::max(label_width, text_width(labels[i]));
    if (std::isfinite(values[i])) top = std::max(top, values[i]);
  }
  const int height = static_cast<int>(kTop + kRowHeight * static_cast<double>(n) + 50.0);
  const Ticks xt = loose_ticks(0.0, top > 0 ? top : 1.0, 6);
  Frame f{label_width + 16.0, kTop, options.width_px - 40.0, height - 50.0, 0.0, xt.hi, 0.0, 1.0};
  Svg svg(options.width_px, height);
  for (double v : tick_values(xt, f.x_lo, f.x_hi)) {
    const double x = f.to_x(v);
    svg.line(x, f.top, x, f.bottom, kGridColour);
    svg.text(x, f.bottom + 18, fixed(v, xt.decimals), "middle");
  }
  svg.line(f.left, f.bottom, f.right, f.bottom, kAxisColour);
  svg.line(f.left, f.top, f.left, f.bottom, kAxisColour);
  if (!options.x_label.empty()) {
    svg.text((f.left + f.right) / 2, f.bottom + 38, options.x_label, "middle");
  }
  for (std::size_t i = 0; i < n; ++i) {
    const double y = kTop + kRowHeight * static_cast<double>(i);
    svg.text(f.left - 8, y + kRowHeight / 2 + 4, labels[i], "end");
    const double v = std::isfinite(values[i]) ? std::max(values[i], 0.0) : 0.0;
    const double w = f.to_x(v) - f.left;
    svg.rect(f.left, y + 4, w, kRowHeight - 8, kPalette[0], " class=\"bar\"",
             labels[i] + ": " + fixed(values[i], options.decimals));
    svg.text(f.left + w + 4, y + kRowHeight / 2 + 4, fixed(values[i], options.decimals));
  }
  draw_header(svg, options.width_px, options.title, {});
  return svg.finish();
}

std::string xy_plot_svg(const std::vector<Series>& series, const XYPlotOptions& options) {
  constexpr double kInf = std::numeric_limits<double>::infinity();
  double x_lo = kInf, x_hi = -kInf, y_lo = kInf, y_hi = -kInf;
  for (const Series& s : series) {
    for (std::size_t i = 0; i < std::min(s.x.size(), s.y.size()); ++i) {
      if (!std::isfinite(s.x[i]) || !std::isfinite(s.y[i])) continue;
      x_lo = std::min(x_lo, s.x[i]), x_hi = std::max(x_hi, s.x[i]);
      y_lo = std::min(y_lo, s.y[i]), y_hi = std::max(y_hi, s.y[i]);
    }
  }
  for (const MarkerLine& m : options.markers) {
    if (std::isfinite(m.x)) x_lo = std::min(x_lo, m.x), x_hi = std::max(x_hi, m.x);
  }
  for (double y : options.horizontal_lines) {
    if (std::isfinite(y)) y_lo = std::min(y_lo, y), y_hi = std::max(y_hi, y);
  }
  for (const HorizontalBand& b : options.bands) {
    if (std::isfinite(b.lo) && std::isfinite(b.hi)) {
      y_lo = std::min(y_lo, std::min(b.lo, b.hi)), y_hi = std::max(y_hi, std::max(b.lo, b.hi));
    }
  }
  bool stems = false;
  for (const Series& s : series) stems = stems || s.style == SeriesStyle::kStems;
  if (options.y_from_zero || stems) y_lo = std::min(y_lo, 0.0), y_hi = std::max(y_hi, 0.0);
  if (x_lo > x_hi) x_lo = 0, x_hi = 1;  // no data
  if (y_lo > y_hi) y_lo = 0, y_hi = 1;
  const Ticks xt0 = loose_ticks(options.x_min.value_or(x_lo), options.x_max.value_or(x_hi));
  const Ticks yt0 = loose_ticks(options.y_min.value_or(y_lo), options.y_max.value_or(y_hi));
  const Frame f = make_frame(options.width_px, options.height_px, options.x_min.value_or(xt0.lo),
                             options.x_max.value_or(xt0.hi), options.y_min.value_or(yt0.lo),
                             options.y_max.value_or(yt0.hi));
  const Ticks xt = loose_ticks(f.x_lo, f.x_hi), yt = loose_ticks(f.y_lo, f.y_hi);

  Svg svg(options.width_px, options.height_px);
  draw_axes(svg, f, xt, yt, options.x_label, options.y_label);
  std::vector<LegendEntry> legend;
  constexpr double kBandOpacity = 0.2;
  for (const HorizontalBand& b : options.bands) {
    if (!std::isfinite(b.lo) || !std::isfinite(b.hi)) continue;
    const double lo = std::clamp(std::min(b.lo, b.hi), f.y_lo, f.y_hi);
    const double hi = std::clamp(std::max(b.lo, b.hi), f.y_lo, f.y_hi);
    const std::string colour = b.colour.empty() ? "#777777" : b.colour;
    svg.rect(f.left, f.to_y(hi), f.right - f.left, f.to_y(lo) - f.to_y(hi), colour,
             " class=\"band\" fill-opacity=\"" + fixed(kBandOpacity, 2) + "\"",
             b.label.empty() ? "" : b.label);
    if (!b.label.empty()) legend.push_back({b.label, colour, false, kBandOpacity});
  }
  for (double y : options.horizontal_lines) {
    if (y >= f.y_lo && y <= f.y_hi) svg.line(f.left, f.to_y(y), f.right, f.to_y(y), "#777777");
  }
  for (std::size_t k = 0; k < series.size(); ++k) {
    const Series& s = series[k];
    const std::string colour = colour_or(s.colour, k);
    const std::size_t n = std::min(s.x.size(), s.y.size());
    auto inside = [&](std::size_t i) {
      return std::isfinite(s.x[i]) && std::isfinite(s.y[i]) && s.x[i] >= f.x_lo &&
             s.x[i] <= f.x_hi && s.y[i] >= f.y_lo && s.y[i] <= f.y_hi;
    };
    if (draws_lines(s.style)) {
      // Lines are broken at non-finite points; points outside the range are clamped to it.
      std::vector<std::pair<double, double>> run;
      for (std::size_t i = 0; i <= n; ++i) {
        if (i == n || !std::isfinite(s.x[i]) || !std::isfinite(s.y[i])) {
          svg.polyline(run, colour);
          run.clear();
          continue;
        }
        run.emplace_back(f.to_x(std::clamp(s.x[i], f.x_lo, f.x_hi)),
                         f.to_y(std::clamp(s.y[i], f.y_lo, f.y_hi)));
      }
    }
    if (s.style == SeriesStyle::kStems) {
      // From y = 0 (the nearer edge when 0 is outside the range) to the value.
      const double base = f.to_y(std::clamp(0.0, f.y_lo, f.y_hi));
      for (std::size_t i = 0; i < n; ++i) {
        if (!inside(i)) continue;
        svg.line(f.to_x(s.x[i]), base, f.to_x(s.x[i]), f.to_y(s.y[i]), colour, 1.5);
      }
    }
    if (draws_points(s.style)) {
      const double radius = s.style == SeriesStyle::kStems ? 3.0 : 2.5;
      for (std::size_t i = 0; i < n; ++i) {
        if (inside(i)) svg.circle(f.to_x(s.x[i]), f.to_y(s.y[i]), radius, colour);
      }
    }
    if (!s.label.empty()) {
      legend.push_back({s.label, colour, draws_lines(s.style) || s.style == SeriesStyle::kStems});
    }
  }
  draw_markers(svg, f, options.markers, series.size());
  draw_header(svg, options.width_px, options.title, legend);
  return svg.finish();
}

std::string polar_plot_svg(const std::vector<PolarSeries>& series,
                           const PolarPlotOptions& options) {
  constexpr double kInf = std::numeric_limits<double>::infinity();
  double data_lo = kInf, data_hi = -kInf;
  for (const PolarSeries& s : series) {
    for (std::size_t i = 0; i < std::min(s.angle_rad.size(), s.radius.size()); ++i) {
      if (!std::isfinite(s.angle_rad[i]) || !std::isfinite(s.radius[i])) continue;
      data_lo = std::min(data_lo, s.radius[i]), data_hi = std::max(data_hi, s.radius[i]);
    }
  }
  if (data_lo > data_hi) data_lo = 0, data_hi = 1;  // no data
  const Ticks t0 = loose_ticks(options.r_min.value_or(std::min(data_lo, 0.0)),
                               options.r_max.value_or(data_hi), 5);
  const double r_lo = options.r_min.value_or(t0.lo), r_hi = options.r_max.value_or(t0.hi);
  const Ticks t = loose_ticks(r_lo, r_hi, 5);

  const int size = options.size_px;
  // Layout: header (title, legend) above; angle labels 16 px outside the outer ring.
  const int height = size + 40;
  const double cx = size / 2.0, cy = size / 2.0 + 32.0, radius = size / 2.0 - 44.0;
  auto to_px = [&](double r) { return std::clamp((r - r_lo) / (r_hi - r_lo), 0.0, 1.0) * radius; };
  auto point = [&](double angle, double r) {
    const double rp = to_px(r);
    return std::pair<double, double>{cx + rp * std::cos(angle), cy - rp * std::sin(angle)};
  };

  Svg svg(size, height);
  for (double v : tick_values(t, r_lo, r_hi)) {  // rings with their radius labels
    const double rp = to_px(v);
    if (rp <= 0.0) continue;
    std::vector<std::pair<double, double>> ring;
    for (int i = 0; i <= 120; ++i) ring.push_back(point(2.0 * std::numbers::pi * i / 120, v));
    const bool zero_ring = v == 0.0 && r_lo < 0.0;
    svg.polyline(ring, zero_ring ? "#777777" : kGridColour, zero_ring ? 1.5 : 1.0);
    // Ring labels along the 15° direction, between the 0° and 30° spokes.
    const double a = std::numbers::pi / 12;
    svg.text(cx + rp * std::cos(a) + 3, cy - rp * std::sin(a) - 3, fixed(v, t.decimals), "start",
             " fill=\"#555555\"");
  }
  for (int deg = 0; deg < 360; deg += 30) {  // spokes every 30° with labels
    const double a = deg * std::numbers::pi / 180.0;
    svg.line(cx, cy, cx + radius * std::cos(a), cy - radius * std::sin(a), kGridColour);
    svg.text(cx + (radius + 16) * std::cos(a), cy - (radius + 16) * std::sin(a) + 4,
             std::to_string(deg) + "°", "middle");
  }
  std::vector<LegendEntry> legend;
  for (std::size_t k = 0; k < series.size(); ++k) {
    const PolarSeries& s = series[k];
    const std::string colour = colour_or(s.colour, k);
    const std::size_t n = std::min(s.angle_rad.size(), s.radius.size());
    std::vector<std::pair<double, double>> run;
    for (std::size_t i = 0; i <= n; ++i) {
      const bool valid = i < n && std::isfinite(s.angle_rad[i]) && std::isfinite(s.radius[i]);
      if (!valid) {
        if (draws_lines(s.style)) svg.polyline(run, colour);
        run.clear();
        continue;
      }
      const auto [x, y] = point(s.angle_rad[i], s.radius[i]);
      run.emplace_back(x, y);
      if (draws_points(s.style)) svg.circle(x, y, 2.5, colour);
    }
    if (!s.label.empty()) legend.push_back({s.label, colour, draws_lines(s.style)});
  }
  if (!options.radius_label.empty()) {
    svg.text(cx, height - 8.0, "radius: " + options.radius_label, "middle");
  }
  draw_header(svg, size, options.title, legend);
  return svg.finish();
}

}  // namespace gearmc
