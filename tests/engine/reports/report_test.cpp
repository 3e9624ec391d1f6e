// Report building blocks: SVG plots and the HTML page.
//  * every SVG and the HTML page are well-formed (a small checker below: balanced tags, quoted
//    attributes, only known entities; HTML void elements allowed on the page);
//  * histogram bars: one per non-empty bin, height / count the same for every bar; the fitted
//    density overlay scaled to counts meets the bars where the bars are the expected counts;
//    marker lines and labels; the x range grows to a marker beyond the data;
//  * polar plot: points land at the pixel computed by hand from the documented layout;
//  * HTML: escaping of < & " ', structure, atomic writes (no FILE.tmp left, failures leave the
//    old file).
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <numbers>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "core/output_files.h"
#include "engine/reports/html_report.h"
#include "engine/reports/svg_plot.h"
#include "engine/statistics/histogram.h"
#include "tests/support/markup_checker.h"

namespace gearmc {
namespace {
using namespace testing_markup;

TEST(MarkupChecker, CatchesBrokenMarkup) {
  // The checker itself must be able to fail.
  EXPECT_EQ(check_markup("<svg><g></g></svg>", false, nullptr), "");
  EXPECT_NE(check_markup("<svg><g></svg>", false, nullptr), "");
  EXPECT_NE(check_markup("<svg><text>a < b</text></svg>", false, nullptr), "");
  EXPECT_NE(check_markup("<svg><text>a & b</text></svg>", false, nullptr), "");
  EXPECT_NE(check_markup("<svg width=3/>", false, nullptr), "");
  EXPECT_NE(check_markup("<svg/><svg/>", false, nullptr), "");
}

// --- SVG ----------------------------------------------------------------------------------------

TEST(SvgPlot, EscapeXml) {
  EXPECT_EQ(escape_xml(R"(a<b & "c" 'd'>)"), "a&lt;b &amp; &quot;c&quot; &#39;d&#39;&gt;");
  EXPECT_EQ(escape_xml("δRcomp, µm"), "δRcomp, µm");  // UTF-8 passes through
}

// A display histogram, 0.2 µm bins from 0, with the given counts.
Histogram display_histogram(const std::vector<std::uint64_t>& counts) {
  Histogram h(0.0, 0.2, 25);  // 0-5 µm
  for (std::size_t i = 0; i < counts.size(); ++i) {
    for (std::uint64_t c = 0; c < counts[i]; ++c) h.add(h.centre(i));
  }
  return h;
}

TEST(SvgPlot, HistogramBarsAreProportionalToCounts) {
  const std::vector<std::uint64_t> counts = {0, 3, 40, 180, 320, 250, 120, 60, 20, 5, 0, 1};
  const Histogram h = display_histogram(counts);
  HistogramPlotOptions options;
  options.title = "Right flanks <per-flank max> & more";
  options.bars_label = "gearmc, 1200 flanks";
  options.markers = {{3.1, "p99.73 = 3.1 µm", "", true}, {4.0, "P1 claim 4 µm", "#000000", false}};
  const std::string svg = histogram_svg(h, options);
  const std::vector<Element> elements = parse_ok(svg);
  ASSERT_FALSE(elements.empty());
  EXPECT_EQ(elements[0].name, "svg");
  EXPECT_EQ(elements[0].attributes.at("xmlns"), "http://www.w3.org/2000/svg");

  // One bar per non-empty bin, height / count constant (heights are written with 0.01 px).
  std::vector<std::pair<double, double>> bars;  // (height, count)
  for (std::size_t e = 0; e < elements.size(); ++e) {
    if (elements[e].name != "rect" || elements[e].attributes.count("class") == 0) continue;
    EXPECT_EQ(elements[e].attributes.at("class"), "bar");
    ASSERT_LT(e + 1, elements.size());
    ASSERT_EQ(elements[e + 1].name, "title");  // the tooltip "[lo, hi) µm: count"
    const std::string& tip = elements[e + 1].text;
    bars.emplace_back(std::stod(elements[e].attributes.at("height")),
                      std::stod(tip.substr(tip.rfind(' ') + 1)));
  }
  std::size_t non_empty = 0;
  for (auto c : counts) non_empty += c > 0;
  ASSERT_EQ(bars.size(), non_empty);
  // The scale from the tallest bar (320 counts); heights are rounded to 0.01 px, so each bar
  // agrees to 0.005 px plus the scale's share of the rounding, 0.005 count / 320.
  const double px_per_count = bars[3].first / bars[3].second;
  ASSERT_EQ(bars[3].second, 320.0);
  for (const auto& [height, count] : bars) EXPECT_NEAR(height, px_per_count * count, 0.0101);
  // The y axis is rounded up to a tick by Heckbert's rule: range nice(320) = 500, step
  // nice(500 / 5) = 100, top 400. The plot is 400 - 56 - 50 = 294 px high (layout in
  // svg_plot.cpp), so 320 counts are 294 * 320 / 400 = 235.2 px.
  EXPECT_NEAR(bars[3].first, 235.2, 0.005);
  EXPECT_NE(svg.find(">400</text>"), std::string::npos);

  // Labels: escaped title, axis labels, legend entry, marker labels, and an x axis that reaches
  // the 4 µm marker though the data stop at 2.4 µm.
  EXPECT_NE(svg.find("Right flanks &lt;per-flank max&gt; &amp; more"), std::string::npos);
  EXPECT_NE(svg.find(">δRcomp, µm</text>"), std::string::npos);
  EXPECT_NE(svg.find(">count</text>"), std::string::npos);
  EXPECT_NE(svg.find(">gearmc, 1200 flanks</text>"), std::string::npos);
  EXPECT_NE(svg.find(">p99.73 = 3.1 µm</text>"), std::string::npos);
  EXPECT_NE(svg.find(">P1 claim 4 µm</text>"), std::string::npos);
  EXPECT_NE(svg.find(">4</text>"), std::string::npos);         // x ticks 0, 1, ..., 4 (step 1)
  EXPECT_EQ(count_text(svg, "stroke-dasharray"), 1u);          // only the first marker is dashed
  EXPECT_EQ(svg.find("outside the bins"), std::string::npos);  // nothing under/overflowed
}

TEST(SvgPlot, LogCountBarsAreProportionalToTheLogOfTheirCountAboveHalfACount) {
  // log_count: the axis runs from log10(0.5) to the next power of ten above the tallest bar
  // (320 → 10³), ticks at 1, 10, 100, 1000; a bar of count c is log10(c / 0.5) / log10(2000)
  // of the 294 px plot area high (layout in svg_plot.cpp): c = 1 → 26.81 px, c = 320 →
  // 249.51 px. Empty bins draw nothing.
  const std::vector<std::uint64_t> counts = {0, 3, 40, 180, 320, 250, 120, 60, 20, 5, 0, 1};
  HistogramPlotOptions options;
  options.log_count = true;
  options.y_label = "count (log scale)";
  const std::string svg = histogram_svg(display_histogram(counts), options);
  const std::vector<Element> elements = parse_ok(svg);
  std::vector<std::pair<double, double>> bars;  // (height, count)
  for (std::size_t e = 0; e + 1 < elements.size(); ++e) {
    if (elements[e].name != "rect" || elements[e].attributes.count("class") == 0) continue;
    const std::string& tip = elements[e + 1].text;
    bars.emplace_back(std::stod(elements[e].attributes.at("height")),
                      std::stod(tip.substr(tip.rfind(' ') + 1)));
  }
  ASSERT_EQ(bars.size(), 10u);
  for (const auto& [height, count] : bars) {
    EXPECT_NEAR(height, 294.0 * std::log10(count / 0.5) / std::log10(2000.0), 0.006) << count;
  }
  for (const char* tick : {">1</text>", ">10</text>", ">100</text>", ">1000</text>"}) {
    EXPECT_NE(svg.find(tick), std::string::npos) << tick;
  }
  EXPECT_EQ(svg.find(">10000</text>"), std::string::npos);
  EXPECT_NE(svg.find(">count (log scale)</text>"), std::string::npos);
}

TEST(SvgPlot, SharedCountAxis) {
  // With y_max = 900 the axis top is the tick above 900 (Heckbert: range nice(900) = 1000, step
  // 200, top 1000), whatever the tallest bar: left and right plots get the same scale.
  const Histogram h = display_histogram({0, 3, 40, 180, 320, 250, 120, 60, 20, 5, 0, 1});
  HistogramPlotOptions options;
  options.y_max = 900.0;
  const std::string svg = histogram_svg(h, options);
  parse_ok(svg);
  EXPECT_NE(svg.find(">1000</text>"), std::string::npos);
  // The tallest bar, 320 counts, in the 294 px plot area: 294 * 320 / 1000 = 94.08 px (it would
  // be 235.2 px with the default top 400).
  double tallest = 0.0;
  for (const Element& e : parse_ok(svg)) {
    if (e.name == "rect" && e.attributes.count("class")) {
      tallest = std::max(tallest, std::stod(e.attributes.at("height")));
    }
  }
  EXPECT_NEAR(tallest, 94.08, 0.005);
}

TEST(SvgPlot, BarChartLengthsAreProportionalToValues) {
  const std::vector<std::string> labels = {"noise", "drift <x>", "scale"};
  const std::vector<double> values = {44.2, 14.5, 1.1};
  BarChartOptions options;
  options.title = "Error budget";
  const std::string svg = bar_chart_svg(labels, values, options);
  const std::vector<Element> elements = parse_ok(svg);
  std::vector<double> widths;
  for (const Element& e : elements) {
    if (e.name == "rect" && e.attributes.count("class")) {
      widths.push_back(std::stod(e.attributes.at("width")));
    }
  }
  ASSERT_EQ(widths.size(), 3u);
  // px per unit from the longest bar; widths are written to 0.01 px.
  for (std::size_t i = 0; i < 3; ++i) {
    EXPECT_NEAR(widths[i], widths[0] / values[0] * values[i], 0.011) << labels[i];
  }
  EXPECT_NE(svg.find(">drift &lt;x&gt;</text>"), std::string::npos);
  EXPECT_NE(svg.find(">44.2</text>"), std::string::npos);
}

TEST(SvgPlot, OverlayIsTheDensityScaledToCounts) {
  // Bars = expected counts n P(bin) of a normal law (mu 2, sigma 0.5, n 10 000, w 0.2), rounded;
  // the overlay f(x) n w must pass through the top of the fullest bar at its centre, to within
  // the midpoint-rule error (w^2 / 24 f'' / f = 0.0067 relative at the mode) and rounding.
  const double mu = 2.0, sigma = 0.5, n = 10000.0, w = 0.2;
  auto pdf = [&](double x) {
    return std::exp(-0.5 * (x - mu) * (x - mu) / (sigma * sigma)) /
           (sigma * std::sqrt(2 * std::numbers::pi));
  };
  auto cdf = [&](double x) { return 0.5 * std::erfc(-(x - mu) / (sigma * std::sqrt(2.0))); };
  std::vector<std::uint64_t> counts;
  for (int i = 0; i < 25; ++i) {
    counts.push_back(static_cast<std::uint64_t>(std::llround(n * (cdf((i + 1) * w) - cdf(i * w)))));
  }
  Histogram h = display_histogram(counts);
  // Pad with underflow/overflow so that total() is exactly n (the overlay scales by total()).
  while (static_cast<double>(h.total()) < n) h.add(100.0);
  HistogramPlotOptions options;
  options.overlay_pdf = pdf;
  options.overlay_label = "normal fit";
  const std::string svg = histogram_svg(h, options);
  const std::vector<Element> elements = parse_ok(svg);
  EXPECT_NE(svg.find(">normal fit</text>"), std::string::npos);
  EXPECT_NE(svg.find("outside the bins: 0 below"), std::string::npos);

  // The fullest bar is [1.8, 2.0) or [2.0, 2.2) (equal by symmetry: the lower one, first drawn).
  double bar_top = 1e9, bar_mid = 0;
  std::vector<std::pair<double, double>> curve;
  for (const Element& e : elements) {
    if (e.name == "rect" && e.attributes.count("class")) {
      const double y = std::stod(e.attributes.at("y"));
      if (y < bar_top - 1e-9) {
        bar_top = y;
        bar_mid = std::stod(e.attributes.at("x")) + std::stod(e.attributes.at("width")) / 2;
      }
    }
    if (e.name == "polyline") {
      std::istringstream points(e.attributes.at("points"));
      std::string pair;
      while (points >> pair) {
        curve.emplace_back(std::stod(pair.substr(0, pair.find(','))),
                           std::stod(pair.substr(pair.find(',') + 1)));
      }
    }
  }
  ASSERT_FALSE(curve.empty());
  double curve_y = 0, best = 1e9;
  for (const auto& [x, y] : curve) {
    if (std::abs(x - bar_mid) < best) best = std::abs(x - bar_mid), curve_y = y;
  }
  const double bottom = 400 - 50;  // plot bottom in px (layout in svg_plot.cpp)
  EXPECT_LT(best, 1.5);            // the curve is sampled every ~1.3 px
  EXPECT_NEAR((bottom - curve_y) / (bottom - bar_top), 1.0, 0.012);
}

TEST(SvgPlot, XYPlot) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  Series line{"model", {0, 1, 2, 3, 4, 5}, {0.0, 0.5, nan, 1.5, 2.0, 2.5}, SeriesStyle::kLine, ""};
  Series points{"measured & fitted",
                {0.5, 1.5, 2.5, 3.5},
                {0.2, -0.4, 1.1, nan},
                SeriesStyle::kPoints,
                "#123456"};
  XYPlotOptions options;
  options.title = "Residuals vs order";
  options.x_label = "probing order";
  options.y_label = "residual, µm";
  options.horizontal_lines = {0.0};
  options.markers = {{2.0, "drift starts", "", true}};
  const std::string svg = xy_plot_svg({line, points}, options);
  const std::vector<Element> elements = parse_ok(svg);
  std::size_t polylines = 0, circles = 0;
  for (const Element& e : elements) {
    polylines += e.name == "polyline";
    if (e.name == "circle") {
      ++circles;
      EXPECT_EQ(e.attributes.at("fill"), "#123456");
    }
  }
  EXPECT_EQ(polylines, 2u);  // the line is broken at its NaN
  EXPECT_EQ(circles, 3u);    // the point with y = NaN is skipped
  for (const char* label :
       {">Residuals vs order</text>", ">probing order</text>", ">residual, µm</text>",
        ">model</text>", ">measured &amp; fitted</text>", ">drift starts</text>"}) {
    EXPECT_NE(svg.find(label), std::string::npos) << label;
  }
  // Empty input still gives a well-formed plot.
  parse_ok(xy_plot_svg({}, XYPlotOptions{}));
}

TEST(SvgPlot, StemsRunFromZeroToTheValueWithADot) {
  // Layout (svg_plot.cpp make_frame): plot area x 70 … 616, y 56 … 350 px for 640 × 400. With
  // x in [0, 4] and y in [−1, 2]: x → 70 + x/4·546, y → 350 − (y + 1)/3·294, so y = 0 is at
  // 252 px, y = 1 at 154, y = −0.5 at 301, y = 2 at 56; x = 1, 2, 3 at 206.5, 343, 479.5.
  Series stems{"spectrum", {1, 2, 3}, {1.0, -0.5, 2.0}, SeriesStyle::kStems, "#123456"};
  XYPlotOptions options;
  options.x_min = 0.0, options.x_max = 4.0, options.y_min = -1.0, options.y_max = 2.0;
  const std::string svg = xy_plot_svg({stems}, options);
  const std::vector<Element> elements = parse_ok(svg);
  std::vector<std::vector<double>> lines, dots;
  for (const Element& e : elements) {
    if (e.name == "polyline") {
      EXPECT_NE(e.attributes.at("stroke"), "#123456");  // stems are not joined
    }
    if (e.name == "line" && e.attributes.at("stroke") == "#123456" &&
        e.attributes.at("x1") == e.attributes.at("x2")) {  // vertical: a stem (the legend's
                                                           // swatch is horizontal)
      lines.push_back({std::stod(e.attributes.at("x1")), std::stod(e.attributes.at("y1")),
                       std::stod(e.attributes.at("y2"))});
    }
    if (e.name == "circle" && e.attributes.at("fill") == "#123456") {
      dots.push_back({std::stod(e.attributes.at("cx")), std::stod(e.attributes.at("cy"))});
    }
  }
  const std::vector<std::vector<double>> expected_lines = {
      {206.5, 252, 154}, {343, 252, 301}, {479.5, 252, 56}};
  const std::vector<std::vector<double>> expected_dots = {{206.5, 154}, {343, 301}, {479.5, 56}};
  EXPECT_EQ(lines, expected_lines);
  EXPECT_EQ(dots, expected_dots);
  EXPECT_NE(svg.find(">spectrum</text>"), std::string::npos);  // legend entry
}

TEST(SvgPlot, BandIsShadedUnderTheDataAndWidensTheDefaultRange) {
  // Data y in [0, 0.1] and a band [−0.25, 0.75]: the default y range covers the band, rounded
  // out to Heckbert's ticks: range 1 → step 0.2 → [−0.4, 0.8]. y → 350 − (y + 0.4)/1.2·294 px,
  // so the band's top 0.75 is at 68.25 px and its height 1.0/1.2·294 = 245 px; it spans the
  // plot area's width 70 … 616 px.
  Series data{"mean", {0, 1}, {0.0, 0.1}, SeriesStyle::kLine, "#123456"};
  XYPlotOptions options;
  options.bands = {{-0.25, 0.75, "noise band ±2σ/√n", "#abcdef"}};
  const std::string svg = xy_plot_svg({data}, options);
  const std::vector<Element> elements = parse_ok(svg);
  std::size_t band_index = 0, data_index = 0, bands = 0;
  for (std::size_t i = 0; i < elements.size(); ++i) {
    const Element& e = elements[i];
    if (e.name == "rect" && e.attributes.count("class") && e.attributes.at("class") == "band") {
      ++bands;
      band_index = i;
      EXPECT_EQ(e.attributes.at("fill"), "#abcdef");
      EXPECT_EQ(e.attributes.at("fill-opacity"), "0.20");
      EXPECT_DOUBLE_EQ(std::stod(e.attributes.at("x")), 70.0);
      EXPECT_DOUBLE_EQ(std::stod(e.attributes.at("width")), 546.0);
      EXPECT_DOUBLE_EQ(std::stod(e.attributes.at("y")), 68.25);
      EXPECT_DOUBLE_EQ(std::stod(e.attributes.at("height")), 245.0);
    }
    if (e.name == "polyline" && e.attributes.at("stroke") == "#123456") data_index = i;
  }
  EXPECT_EQ(bands, 1u);
  EXPECT_LT(band_index, data_index);  // drawn first: under the data
  EXPECT_NE(svg.find(">noise band ±2σ/√n</text>"), std::string::npos);  // legend entry
}

TEST(SvgPlot, PolarPointsLandWhereTheLayoutSays) {
  // Layout (svg_plot.cpp): size 480 -> centre (240, 240 + 32), outer radius 240 - 44 = 196 px;
  // r maps linearly from r_min (centre) to r_max (outer ring); angles counter-clockwise from +X,
  // SVG's y axis points down.
  PolarSeries s{"pre-travel",
                {0.0, std::numbers::pi / 2, std::numbers::pi},
                {2.0, 1.0, 0.5},
                SeriesStyle::kPoints,
                ""};
  PolarPlotOptions options;
  options.title = "Pre-travel vs azimuth";
  options.radius_label = "µm";
  options.r_min = 0.0;
  options.r_max = 2.0;
  const std::string svg = polar_plot_svg({s}, options);
  const std::vector<Element> elements = parse_ok(svg);
  std::vector<std::pair<double, double>> centres;
  for (const Element& e : elements) {
    if (e.name == "circle") {
      centres.emplace_back(std::stod(e.attributes.at("cx")), std::stod(e.attributes.at("cy")));
    }
  }
  ASSERT_EQ(centres.size(), 3u);
  EXPECT_NEAR(centres[0].first, 240 + 196, 0.01);
  EXPECT_NEAR(centres[0].second, 272, 0.01);
  EXPECT_NEAR(centres[1].first, 240, 0.01);
  EXPECT_NEAR(centres[1].second, 272 - 98, 0.01);
  EXPECT_NEAR(centres[2].first, 240 - 49, 0.01);
  EXPECT_NEAR(centres[2].second, 272, 0.01);
  for (const char* label :
       {">90°</text>", ">330°</text>", ">pre-travel</text>", ">Pre-travel vs azimuth</text>"}) {
    EXPECT_NE(svg.find(label), std::string::npos) << label;
  }
  // Signed residuals: the default r_min goes below zero and the zero ring is drawn darker.
  PolarSeries signed_series{
      "", {0.0, 1.0, 2.0}, {-0.7, 0.2, 0.75}, SeriesStyle::kLineAndPoints, ""};
  const std::string residuals = polar_plot_svg({signed_series}, PolarPlotOptions{});
  parse_ok(residuals);
  EXPECT_NE(residuals.find("stroke=\"#777777\""), std::string::npos);
}

// --- HTML ---------------------------------------------------------------------------------------

HtmlReport sample_report() {
  HtmlReport report("δRcomp <run> & \"P1\"");
  report.paragraph("a < b & c \"quoted\" 'single'");
  HtmlTable table;
  table.caption = "Per-flank δRcomp, µm";
  table.header = {"flank", "E", "σ", "min", "max"};
  table.rows = {{{"left (P1)", "1.6", "0.6", "0.7", "3.4"}, true},
                {{"left <gearmc>", "1.55", "0.58", "0.71", "3.3"}, false}};
  report.heading("Statistics").table(table);
  report.figure(histogram_svg(display_histogram({1, 2, 3}), {}), "Fig. 1 <left> flanks");
  report.preformatted("name: p1 # <reference> & more\nteeth: 24\n", "scenario.yaml");
  return report;
}

TEST(HtmlReport, EscapesEveryText) {
  const std::string html = sample_report().html();
  EXPECT_NE(html.find("<title>δRcomp &lt;run&gt; &amp; &quot;P1&quot;</title>"), std::string::npos);
  EXPECT_NE(html.find("<h1>δRcomp &lt;run&gt; &amp; &quot;P1&quot;</h1>"), std::string::npos);
  EXPECT_NE(html.find("<p>a &lt; b &amp; c &quot;quoted&quot; &#39;single&#39;</p>"),
            std::string::npos);
  EXPECT_NE(html.find("<td>left &lt;gearmc&gt;</td>"), std::string::npos);
  EXPECT_NE(html.find("<figcaption>Fig. 1 &lt;left&gt; flanks</figcaption>"), std::string::npos);
  EXPECT_NE(html.find("<pre>name: p1 # &lt;reference&gt; &amp; more\nteeth: 24\n</pre>"),
            std::string::npos);
  EXPECT_EQ(html.find("<run>"), std::string::npos);
  EXPECT_EQ(html.find("<gearmc>"), std::string::npos);
}

TEST(HtmlReport, FigureRowsHoldTheirFigures) {
  HtmlReport report("rows");
  report.figure_row({{"<svg xmlns=\"http://www.w3.org/2000/svg\"></svg>", "left"},
                     {"<svg xmlns=\"http://www.w3.org/2000/svg\"></svg>", "right"}});
  const std::string html = report.html();
  parse_ok(html, true);
  const std::size_t row = html.find("<div class=\"figure-row\">");
  ASSERT_NE(row, std::string::npos);
  EXPECT_EQ(count_text(html.substr(row), "<figure>"), 2u);
  EXPECT_NE(html.find("@media print"), std::string::npos);  // a print stylesheet
}

TEST(HtmlReport, StructureIsSelfContained) {
  const std::string html = sample_report().html();
  EXPECT_EQ(html.rfind("<!DOCTYPE html>\n", 0), 0u);
  const std::vector<Element> elements = parse_ok(html, /*html=*/true);
  ASSERT_FALSE(elements.empty());
  EXPECT_EQ(elements[0].name, "html");
  std::vector<std::string> order;
  for (const Element& e : elements) {
    if (e.name == "h2" || e.name == "table" || e.name == "figure" || e.name == "pre" ||
        e.name == "p" || e.name == "svg") {
      order.push_back(e.name);
    }
  }
  EXPECT_EQ(order, (std::vector<std::string>{"p", "h2", "table", "figure", "svg", "pre"}));
  EXPECT_NE(html.find("<meta charset=\"utf-8\">"), std::string::npos);
  EXPECT_NE(html.find("<style>"), std::string::npos);
  // A table scrolls sideways in its own box (not the page) on a narrow window, its caption
  // above the box so it wraps at the window's width.
  EXPECT_NE(html.find("<div class=\"table-caption\">Per-flank δRcomp, µm</div>\n"
                      "<div class=\"table-scroll\">\n<table>"),
            std::string::npos);
  EXPECT_NE(html.find(".table-scroll { overflow-x: auto; }"), std::string::npos);
  EXPECT_EQ(count_text(html, "<tr class=\"highlight\">"), 1u);
  EXPECT_EQ(count_text(html, "<th>"), 5u);
  // Nothing is fetched from elsewhere.
  for (const char* external : {"<script", "<link", "src=", "url(", "@import"}) {
    EXPECT_EQ(html.find(external), std::string::npos) << external;
  }
}

TEST(HtmlReport, ContentsLinkEveryLaterHeadingToItsId) {
  HtmlReport report("contents");
  report.heading("Before the contents");  // not listed, no id
  report.contents("On this page");
  report.heading("Gap before & after").paragraph("text");
  report.heading("Spectrum", 3);
  report.heading("Order, tooth", 3);
  report.heading("Gap before & after");  // the same text again: its own id
  report.heading("Detail", 4);           // level 4: not listed
  const std::string html = report.html();
  const std::vector<Element> elements = parse_ok(html, /*html=*/true);
  std::vector<std::string> links, ids;
  int nested_lists = 0;
  for (const Element& e : elements) {
    if (e.name == "a") links.push_back(e.attributes.at("href"));
    if (e.attributes.count("id")) ids.push_back("#" + e.attributes.at("id"));
    if (e.name == "ol") ++nested_lists;
  }
  // Slugs: ASCII letters and digits, lower case, other runs one '-'; a repeat gets "-2".
  EXPECT_EQ(links, (std::vector<std::string>{"#gap-before-after", "#spectrum", "#order-tooth",
                                             "#gap-before-after-2"}));
  // Every link has its target; the level-4 heading has an id but is not listed.
  links.push_back("#detail");
  EXPECT_EQ(ids, links);
  EXPECT_EQ(nested_lists, 2);  // the list and the level-3 headings under the first entry
  EXPECT_LT(html.find("<nav class=\"contents\">"), html.find("id=\"gap-before-after\""));
  EXPECT_GT(html.find("<nav class=\"contents\">"), html.find("Before the contents"));
  EXPECT_NE(html.find("On this page"), std::string::npos);
  // Without contents(), headings are plain.
  EXPECT_EQ(sample_report().html().find(" id="), std::string::npos);
}

// A new empty directory under the system's temporary directory, unique per process.
std::filesystem::path fresh_directory(const std::string& name) {
  const auto dir = std::filesystem::temp_directory_path() /
                   ("gearmc_report_test_" + name + "_" + std::to_string(::getpid()));
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

std::string read_file(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

TEST(HtmlReport, WritesAtomically) {
  const auto dir = fresh_directory("atomic");
  const auto file = dir / "report.html";
  const HtmlReport report = sample_report();
  report.write(file);
  EXPECT_EQ(read_file(file), report.html());
  EXPECT_FALSE(std::filesystem::exists(dir / "report.html.tmp"));
  // Overwriting replaces the content.
  write_file_atomically(file, "second");
  EXPECT_EQ(read_file(file), "second");
  EXPECT_FALSE(std::filesystem::exists(dir / "report.html.tmp"));
  // A missing directory: an error naming the file, nothing created.
  EXPECT_THROW(write_file_atomically(dir / "missing" / "r.html", "x"), std::runtime_error);
  EXPECT_FALSE(std::filesystem::exists(dir / "missing"));
  // The rename fails (the target is a non-empty directory): the temporary is removed and the
  // target is untouched.
  std::filesystem::create_directories(dir / "busy" / "inside");
  EXPECT_THROW(write_file_atomically(dir / "busy", "x"), std::runtime_error);
  EXPECT_FALSE(std::filesystem::exists(dir / "busy.tmp"));
  EXPECT_TRUE(std::filesystem::is_directory(dir / "busy" / "inside"));
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace gearmc
