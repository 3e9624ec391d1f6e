// SVG text for the report's plots (see svg_plot.h), drawn with the primitives of svg_canvas.h.
#include "engine/reports/svg_plot.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numbers>

#include "engine/reports/svg_canvas.h"

namespace gearmc {
namespace {

using namespace svg_canvas;

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
  std::string note;
  if (histogram.underflow() > 0 || histogram.overflow() > 0) {
    note = "outside the bins: " + std::to_string(histogram.underflow()) + " below, " +
           std::to_string(histogram.overflow()) + " above";
  }
  std::vector<LegendEntry> legend;
  if (!options.bars_label.empty()) legend.push_back({options.bars_label, kPalette[0], false});
  if (options.overlay_pdf) legend.push_back({options.overlay_label, kPalette[1], true});
  // A legend of more than one row moves the plot area down.
  const double extra = (legend_rows(options.width_px, legend, note) - 1) * kLegendRowStep;
  Frame f =
      make_frame(options.width_px, options.height_px, x_lo, x_hi, log ? log_floor : 0.0, yt.hi);
  f.top += extra;
  f.bottom += extra;
  const Ticks xt = loose_ticks(x_lo, x_hi);
  Svg svg(options.width_px, options.height_px + static_cast<int>(extra));
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
  for (const ErrorBar& b : options.error_bars) {
    if (std::isfinite(b.lower) && std::isfinite(b.upper)) {
      y_lo = std::min({y_lo, b.lower, b.upper}), y_hi = std::max({y_hi, b.lower, b.upper});
    }
  }
  for (const HorizontalLine& h : options.limit_lines) {
    if (std::isfinite(h.y)) y_lo = std::min(y_lo, h.y), y_hi = std::max(y_hi, h.y);
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
  // The legend first: a legend of more than one row moves the plot area down.
  constexpr double kBandOpacity = 0.2;
  std::vector<LegendEntry> legend;
  for (const HorizontalBand& b : options.bands) {
    if (std::isfinite(b.lo) && std::isfinite(b.hi) && !b.label.empty()) {
      legend.push_back({b.label, b.colour.empty() ? "#777777" : b.colour, false, kBandOpacity});
    }
  }
  for (const PointHalos& h : options.halos) {
    if (!h.label.empty() && !h.x.empty()) legend.push_back({h.label, h.colour, false});
  }
  for (std::size_t k = 0; k < series.size(); ++k) {
    const Series& s = series[k];
    if (!s.label.empty()) {
      legend.push_back({s.label, colour_or(s.colour, k),
                        draws_lines(s.style) || s.style == SeriesStyle::kStems});
    }
  }
  const double extra = (legend_rows(options.width_px, legend) - 1) * kLegendRowStep;
  Frame f = make_frame(options.width_px, options.height_px, options.x_min.value_or(xt0.lo),
                       options.x_max.value_or(xt0.hi), options.y_min.value_or(yt0.lo),
                       options.y_max.value_or(yt0.hi));
  f.top += extra;
  f.bottom += extra;
  const Ticks xt = loose_ticks(f.x_lo, f.x_hi), yt = loose_ticks(f.y_lo, f.y_hi);

  Svg svg(options.width_px, options.height_px + static_cast<int>(extra));
  draw_axes(svg, f, xt, yt, options.x_label, options.y_label);
  for (const HorizontalBand& b : options.bands) {
    if (!std::isfinite(b.lo) || !std::isfinite(b.hi)) continue;
    const double lo = std::clamp(std::min(b.lo, b.hi), f.y_lo, f.y_hi);
    const double hi = std::clamp(std::max(b.lo, b.hi), f.y_lo, f.y_hi);
    const std::string colour = b.colour.empty() ? "#777777" : b.colour;
    svg.rect(f.left, f.to_y(hi), f.right - f.left, f.to_y(lo) - f.to_y(hi), colour,
             " class=\"band\" fill-opacity=\"" + fixed(kBandOpacity, 2) + "\"",
             b.label.empty() ? "" : b.label);
  }
  for (double y : options.horizontal_lines) {
    if (y >= f.y_lo && y <= f.y_hi) svg.line(f.left, f.to_y(y), f.right, f.to_y(y), "#777777");
  }
  for (const PointHalos& h : options.halos) {
    for (std::size_t i = 0; i < std::min(h.x.size(), h.y.size()); ++i) {
      if (std::isfinite(h.x[i]) && std::isfinite(h.y[i]) && h.x[i] >= f.x_lo && h.x[i] <= f.x_hi &&
          h.y[i] >= f.y_lo && h.y[i] <= f.y_hi) {
        svg.circle(f.to_x(h.x[i]), f.to_y(h.y[i]), 8.0, h.colour);
      }
    }
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
  }
  for (const ErrorBar& b : options.error_bars) {
    if (!std::isfinite(b.lower) || !std::isfinite(b.upper) || b.x < f.x_lo || b.x > f.x_hi) {
      continue;
    }
    const std::string colour = b.colour.empty() ? "#555555" : b.colour;
    const double x = f.to_x(b.x) + b.x_offset_px;
    const double y1 = f.to_y(std::clamp(b.lower, f.y_lo, f.y_hi));
    const double y2 = f.to_y(std::clamp(b.upper, f.y_lo, f.y_hi));
    svg.line(x, y1, x, y2, colour, 1.2);
    svg.line(x - 4, y1, x + 4, y1, colour, 1.2);
    svg.line(x - 4, y2, x + 4, y2, colour, 1.2);
  }
  for (const HorizontalLine& h : options.limit_lines) {
    if (!(h.y >= f.y_lo && h.y <= f.y_hi)) continue;
    svg.line(f.left, f.to_y(h.y), f.right, f.to_y(h.y), h.colour, 1.5, true);
    if (!h.label.empty()) {
      svg.text(f.right - 4, f.to_y(h.y) - 5, h.label, "end",
               " fill=\"" + escape_xml(h.colour) + "\"");
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
