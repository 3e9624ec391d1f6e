// The profile/helix inspection sheets (engine/reports/inspection_charts.h), read back from the SVG
// they write — well-formed, and every drawn thing where the chart's definition puts it:
//  * the deviation scale: the smallest 1-2-2.5-5 step that holds the traces and the template
//    (hand cases);
//  * measured points: their position along the trace maps linearly onto the A–E marks, their
//    deviation onto the grid (division spacing = the scale), about the trace's centre;
//  * the template: a trace whose extremes span exactly T touches both corridor lines, and a
//    mean line whose |f_H| is exactly f_HT ends on the fan's lines;
//  * values: printed with one decimal, red and bold beyond the tolerance only, with their class;
//  * the cumulative pitch F_pk = u_k − u_1 of ISO 1328-1 §3.2 from the single pitches, against
//    evaluate_pitch on arc positions drawn at random (F_p = max − min).
#include "engine/reports/inspection_charts.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <map>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include "engine/evaluation/gear_parameters.h"
#include "engine/reports/html_report.h"
#include "tests/support/markup_checker.h"

namespace gearmc {
namespace {
using namespace testing_markup;

double attribute(const Element& e, const std::string& name) {
  return std::stod(e.attributes.at(name));
}

// A profile-like trace of tooth `tooth`: x = 20, 21, … 40 mm (A 22, E 38), deviation f(x).
template <class F>
InspectionTrace trace(int tooth, F f, int points = 21) {
  InspectionTrace t;
  t.tooth = tooth;
  for (int i = 0; i < points; ++i) {
    const double x = 20.0 + 20.0 * i / (points - 1);
    t.x_mm.push_back(x);
    t.measured_um.push_back(f(x));
  }
  t.range_start_mm = 22.0;
  t.range_end_mm = 38.0;
  return t;
}

TEST(InspectionCharts, TheScaleIsTheSmallestStepThatHoldsTracesAndTemplate) {
  InspectionSheet sheet;
  // Values −1 … 3 within A–E (centre 1); outside it −1.5 (x = 20) and 3.5 (x = 40): reach 2.5
  // → 2 µm divisions (1 µm holds only ±2).
  sheet.sides[0].traces.push_back(trace(1, [](double x) { return -1.0 + 4.0 * (x - 22) / 16; }));
  EXPECT_DOUBLE_EQ(inspection_division_um(sheet), 2.0);
  // Outside A–E clamped to −1 … 3: reach 2 → 1 µm divisions.
  for (double& v : sheet.sides[0].traces[0].measured_um) v = std::clamp(v, -1.0, 3.0);
  EXPECT_DOUBLE_EQ(inspection_division_um(sheet), 1.0);
  // A total tolerance of 10 µm: corridor ±5 → 2.5 µm divisions (not 5: 2.5 is a step).
  sheet.total_tolerance_um = 10.0;
  EXPECT_DOUBLE_EQ(inspection_division_um(sheet), 2.5);
  // 10.2 µm: ±5.1 → 5 µm.
  sheet.total_tolerance_um = 10.2;
  EXPECT_DOUBLE_EQ(inspection_division_um(sheet), 5.0);
  // A slope tolerance's fan about a mean line whose middle is 1 µm off the centre: 1 + 8/2 = 5.
  sheet.total_tolerance_um.reset();
  sheet.slope_tolerance_um = 8.0;
  sheet.sides[0].traces[0].mean_intercept_um = 0.0;  // middle at 2, the centre at 1
  sheet.sides[0].traces[0].mean_slope_um_per_mm = 4.0 / 16.0;
  EXPECT_DOUBLE_EQ(inspection_division_um(sheet), 2.5);
  // Sub-micrometre traces: 0.1-µm steps.
  InspectionSheet fine;
  fine.sides[1].traces.push_back(trace(2, [](double x) { return 0.15 * std::sin(x); }));
  // By hand: the centre of the extremes in A–E, the largest distance from it over the trace.
  double lo = INFINITY, hi = -INFINITY, reach = 0.0;
  const InspectionTrace& f = fine.sides[1].traces[0];
  for (std::size_t i = 0; i < f.x_mm.size(); ++i) {
    if (f.x_mm[i] >= 22.0 && f.x_mm[i] <= 38.0) {
      lo = std::min(lo, f.measured_um[i]), hi = std::max(hi, f.measured_um[i]);
    }
  }
  for (double v : f.measured_um) reach = std::max(reach, std::abs(v - 0.5 * (lo + hi)));
  const std::vector<double> steps = {0.05, 0.1, 0.2, 0.25, 0.5};
  double expected = NAN;
  for (double step : steps) {
    if (2.0 * step >= reach) {
      expected = step;
      break;
    }
  }
  EXPECT_DOUBLE_EQ(inspection_division_um(fine), expected) << reach;
}

struct Drawn {
  std::vector<Element> circles, lines, texts;
};

Drawn draw(const InspectionSheet& sheet) {
  const std::string svg = inspection_sheet_svg(sheet);
  Drawn d;
  for (const Element& e : parse_ok(svg)) {
    if (e.name == "circle") d.circles.push_back(e);
    if (e.name == "line") d.lines.push_back(e);
    if (e.name == "text") {
      // The text up to the next tag, without the newline after </text>, with &gt; decoded.
      Element t = e;
      while (!t.text.empty() && std::isspace(static_cast<unsigned char>(t.text.back()))) {
        t.text.pop_back();
      }
      for (std::size_t at; (at = t.text.find("&gt;")) != std::string::npos;) {
        t.text.replace(at, 4, ">");
      }
      d.texts.push_back(t);
    }
  }
  return d;
}

bool vertical(const Element& l) { return attribute(l, "x1") == attribute(l, "x2"); }

TEST(InspectionCharts, PointsLandOnTheTraceAxesAndTheTemplateBoundsTheTolerance) {
  // Tooth 5: a trace whose extremes in A–E span exactly 6 µm (−2 … 4, centre 1) and whose mean
  // line rises by exactly 4 µm from A to E; total tolerance 6, slope tolerance 4.
  const auto f = [](double x) {
    return -2.0 + 6.0 * std::pow((std::clamp(x, 22.0, 38.0) - 22.0) / 16.0, 2.0);
  };
  InspectionSheet sheet;
  sheet.total_tolerance_um = 6.0;
  sheet.slope_tolerance_um = 4.0;
  InspectionTrace t = trace(5, f);
  t.mean_intercept_um = -1.0;
  t.mean_slope_um_per_mm = 4.0 / 16.0;
  sheet.sides[0].traces.push_back(t);
  // Reach 3 (the corridor, the trace, the fan about the mean line's middle 1): 2 µm divisions.
  const double division = inspection_division_um(sheet);
  EXPECT_DOUBLE_EQ(division, 2.0);
  const Drawn d = draw(sheet);

  // The panel's centre line (the design line) and its grid: vertical lines over the full panel.
  double centre = NAN;
  std::vector<double> grid;
  for (const Element& l : d.lines) {
    if (!vertical(l)) continue;
    const std::string stroke = l.attributes.at("stroke");
    if (stroke == "#b0b0b0") centre = attribute(l, "x1");
    if (stroke == "#b0b0b0" || stroke == "#e4e4e4") grid.push_back(attribute(l, "x1"));
  }
  ASSERT_TRUE(std::isfinite(centre));
  ASSERT_EQ(grid.size(), 5u);  // −2 … +2 divisions of the one panel with a trace
  std::sort(grid.begin(), grid.end());
  const double px_per_division = grid[1] - grid[0];
  // A and E: the dashed horizontal lines across the panel.
  std::vector<double> marks;
  for (const Element& l : d.lines) {
    if (!vertical(l) && l.attributes.count("stroke-dasharray") &&
        l.attributes.at("stroke") == "#888888") {
      marks.push_back(attribute(l, "y1"));
    }
  }
  ASSERT_EQ(marks.size(), 2u);
  const double yA = marks[0], yE = marks[1];
  EXPECT_GT(yA, yE);  // A (root) below E (tip)

  ASSERT_EQ(d.circles.size(), t.x_mm.size());
  for (std::size_t i = 0; i < t.x_mm.size(); ++i) {
    const double cx = attribute(d.circles[i], "cx"), cy = attribute(d.circles[i], "cy");
    // Along the trace: linear in x with A and E at their marks (px written with 2 decimals).
    EXPECT_NEAR(cy, yA + (yE - yA) * (t.x_mm[i] - 22.0) / 16.0, 0.02) << i;
    // Across: (d − centre of the extremes) at the scale of the grid.
    EXPECT_NEAR(cx, centre + (t.measured_um[i] - 1.0) / division * px_per_division, 0.02) << i;
  }

  // The corridor (solid, template colour, vertical, from A to E) at centre ± T/2: the trace's
  // extremes −2 (x = 22) and 4 (x = 38) lie on it.
  std::vector<double> corridor;
  for (const Element& l : d.lines) {
    if (vertical(l) && l.attributes.at("stroke") == "#009E73")
      corridor.push_back(attribute(l, "x1"));
  }
  ASSERT_EQ(corridor.size(), 2u);
  std::sort(corridor.begin(), corridor.end());
  EXPECT_NEAR(corridor[0], attribute(d.circles[2], "cx"), 0.02);   // x = 22, d = −2
  EXPECT_NEAR(corridor[1], attribute(d.circles[18], "cx"), 0.02);  // x = 38, d = 4
  // The mean line rises by f_HT exactly: it is one of the fan's two dashed lines.
  std::vector<const Element*> mean, fan;
  for (const Element& l : d.lines) {
    // (not the legend's swatch: that one is horizontal)
    if (l.attributes.at("stroke") == "#D55E00" && attribute(l, "y1") != attribute(l, "y2")) {
      mean.push_back(&l);
    }
    if (!vertical(l) && l.attributes.at("stroke") == "#009E73" &&
        l.attributes.count("stroke-dasharray")) {
      fan.push_back(&l);
    }
  }
  ASSERT_EQ(mean.size(), 1u);
  ASSERT_EQ(fan.size(), 2u);
  const auto same = [](const Element& a, const Element& b) {
    for (const char* k : {"x1", "y1", "x2", "y2"}) {
      if (std::abs(attribute(a, k) - attribute(b, k)) > 0.011) return false;
    }
    return true;
  };
  EXPECT_TRUE(same(*mean[0], *fan[0]) || same(*mean[0], *fan[1]));
  // The mean line's ends: −1 µm at A, 3 µm at E.
  EXPECT_NEAR(attribute(*mean[0], "x1"), centre + (-1.0 - 1.0) / division * px_per_division, 0.02);
  EXPECT_NEAR(attribute(*mean[0], "x2"), centre + (3.0 - 1.0) / division * px_per_division, 0.02);
  EXPECT_NEAR(attribute(*mean[0], "y1"), yA, 0.01);
  EXPECT_NEAR(attribute(*mean[0], "y2"), yE, 0.01);
}

TEST(InspectionCharts, AnInternalGearsProfileKeepsItsTipAtTheTop) {
  // An internal gear's evaluation range runs from the root (larger L) to the tip (smaller L):
  // drawn with positions downwards, A (root) is below E (tip), the smaller L higher up.
  InspectionSheet sheet;
  InspectionTrace t = trace(1, [](double) { return 0.0; });
  std::swap(t.range_start_mm, t.range_end_mm);  // A at L = 38, E at L = 22
  sheet.sides[0].traces.push_back(t);
  for (const bool downwards : {false, true}) {
    sheet.positions_downwards = downwards;
    const Drawn d = draw(sheet);
    std::vector<double> marks;
    for (const Element& l : d.lines) {
      if (!vertical(l) && l.attributes.count("stroke-dasharray") &&
          l.attributes.at("stroke") == "#888888") {
        marks.push_back(attribute(l, "y1"));  // A first, then E
      }
    }
    ASSERT_EQ(marks.size(), 2u);
    EXPECT_EQ(marks[0] > marks[1], downwards);  // (svg y grows downwards)
    // The first point (L = 20, the tip side) is the highest point exactly when downwards.
    EXPECT_EQ(attribute(d.circles.front(), "cy") < attribute(d.circles.back(), "cy"), downwards);
  }
}

TEST(InspectionCharts, ValuesBeyondTheirToleranceAreMarkedAndClassesPrinted) {
  InspectionSheet sheet;
  sheet.sides[1].traces.push_back(trace(3, [](double) { return 0.0; }));
  sheet.sides[1].traces.push_back(trace(9, [](double) { return 0.0; }));
  InspectionValueRow total{"Fα", 10.0, false, 1.34, {9.96, 10.04}, {5, 6}};
  InspectionValueRow slope{"fHα", 6.5, true, 0.8, {-6.6, 6.5}, {std::nullopt, 5}};
  sheet.sides[1].rows = {total, slope};
  const Drawn d = draw(sheet);
  std::map<std::string, const Element*> by_text;
  for (const Element& t : d.texts) by_text[t.text] = &t;
  const auto red = [&](const std::string& text) {
    return by_text.at(text)->attributes.count("fill") &&
           by_text.at(text)->attributes.at("fill") == "#C00000";
  };
  // 10.04 > 10 is printed 10.0 but marked; 9.96 is 10.0 too and not marked: the mark is the
  // comparison of the value, not of its print.
  std::size_t marked_ten = 0, plain_ten = 0;
  for (const Element& t : d.texts) {
    if (t.text != "10.0") continue;
    const bool r = t.attributes.count("fill") && t.attributes.at("fill") == "#C00000";
    (r ? marked_ten : plain_ten) += 1;
  }
  EXPECT_EQ(marked_ten, 1u);
  EXPECT_EQ(plain_ten, 1u);  // (the T 10.0 of the label column is "T 10.0  U 1.3")
  EXPECT_TRUE(red("-6.6"));  // |−6.6| > ±6.5
  EXPECT_FALSE(red("6.5"));  // at the limit: conforms
  EXPECT_TRUE(by_text.count("T 10.0  U 1.3"));
  EXPECT_TRUE(by_text.count("T ±6.5  U 0.8"));
  EXPECT_TRUE(by_text.count("Q5"));
  EXPECT_TRUE(by_text.count("Q6"));
  EXPECT_TRUE(by_text.count("Q>11"));
  EXPECT_TRUE(by_text.count("3") && by_text.count("9"));  // the teeth above their traces
}

TEST(InspectionCharts, CumulativePitchIsTheArcPositionFromToothOne) {
  // evaluate_pitch (ISO 1328-1 §3.2) on arc positions drawn at random; the chart's F_pk from its
  // f_pt,k must be u_k − u_1, and max − min of them F_p. Seed 11.
  std::mt19937_64 rng(11);
  std::normal_distribution<double> noise(0.0, 3.0);
  for (int z : {5, 24, 73}) {
    std::vector<double> u(z);
    for (double& v : u) v = noise(rng);
    const PitchResult r = evaluate_pitch(u);
    const std::vector<double> F = cumulative_pitch_um(r.single_um);
    ASSERT_EQ(F.size(), u.size());
    double lo = INFINITY, hi = -INFINITY;
    for (int k = 0; k < z; ++k) {
      EXPECT_NEAR(F[k], u[k] - u[0], 1e-12) << z << " " << k;
      lo = std::min(lo, F[k]), hi = std::max(hi, F[k]);
    }
    EXPECT_NEAR(hi - lo, r.cumulative_um, 1e-12);
  }
}

TEST(HtmlReport, VerdictAndSheetBlocks) {
  HtmlReport page("t");
  page.verdict("Capable <for> 2 of 3", {"F_α: Q_MP 28 % ≤ 30 %", "a & b"}, HtmlReport::Tone::kBad);
  page.sheet("<svg xmlns=\"http://www.w3.org/2000/svg\"/>", "sheet & caption");
  const std::string html = page.html();
  parse_ok(html, true);
  EXPECT_NE(html.find("<div class=\"verdict bad\">"), std::string::npos);
  EXPECT_NE(html.find("Capable &lt;for&gt; 2 of 3"), std::string::npos);
  EXPECT_NE(html.find("<li>a &amp; b</li>"), std::string::npos);
  EXPECT_NE(html.find("<figure class=\"sheet\">"), std::string::npos);
  // The print stylesheet: A4 pages, every sheet on a page of its own.
  EXPECT_NE(html.find("@page { size: A4"), std::string::npos);
  EXPECT_NE(html.find("figure.sheet { break-before: page"), std::string::npos);
}

}  // namespace
}  // namespace gearmc
