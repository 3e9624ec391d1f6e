// sweep.csv, sweep.json and report.html of `gearmc sweep` (sweep_report.h).
#include "engine/apps/sweep/sweep_report.h"

#include <array>
#include <charconv>
#include <cmath>
#include <optional>
#include <sstream>

#include "core/number_text.h"
#include "engine/reports/html_report.h"
#include "engine/reports/parameter_report.h"
#include "engine/reports/svg_canvas.h"
#include "engine/reports/svg_plot.h"

namespace gearmc {
namespace {

const char* const kSides[3] = {"left", "right", "both"};

// The value as a number when the whole text is one (e.g. "0.5"), else nullopt.
std::optional<double> number_of(const std::string& text) {
  double v = 0.0;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
  if (ec != std::errc() || end != text.data() + text.size() || !std::isfinite(v)) return {};
  return v;
}

std::string csv_field(const std::string& text) {
  if (text.find_first_of(",\"\n") == std::string::npos) return text;
  std::string quoted = "\"";
  for (char c : text) quoted += c == '"' ? std::string("\"\"") : std::string(1, c);
  return quoted + "\"";
}

}  // namespace

std::array<SweepValue, 3> sweep_parameter_values(const SweepStatistic& stat,
                                                 const MonteCarloRun& mc, const RunResults& r) {
  std::array<SweepValue, 3> v;
  const std::optional<ParameterPresentation> p = present_parameters(mc, r);
  const ParameterSummary* summary = nullptr;
  if (p) {
    for (const ParameterSummary& s : p->parameters) {
      if (parameter_symbol(s.parameter) == stat.parameter) summary = &s;
    }
  }
  if (!summary) {
    for (SweepValue& x : v) x.note = "not evaluated at this point (see the run's notes)";
    return v;
  }
  const std::string& st = stat.statistic;
  if (!stat.ratio()) {
    const auto of = [&](const ParameterSideSummary& side) {
      return st == "bias" ? side.bias_um : st == "u" ? side.u_um : side.U95_um;
    };
    for (const ParameterSideSummary& side : summary->sides) {
      const int k = side.side == "left" ? 0 : side.side == "right" ? 1 : 2;
      if (k < 2) {
        v[k].value = of(side);
        // both: the larger |value| of the two sides (U/T takes the larger U).
        if (!v[2].value || std::abs(of(side)) > std::abs(*v[2].value)) v[2].value = of(side);
      } else {
        v[2].value = of(side);
        v[0].note = v[1].note = "an item of " + stat.parameter + " takes both flanks";
      }
    }
    return v;
  }
  v[0].note = v[1].note = "a statistic of the parameter as a whole (both)";
  const ParameterConformity& c = summary->conformity;
  if (!c.tolerance_um) {
    v[2].note = "no tolerance for " + stat.parameter + " in the scenario's set";
    return v;
  }
  v[2].value = st == "U_over_T"       ? c.u_over_t
               : st == "Q_MP"         ? c.capability_ratio
               : st == "false_accept" ? c.chosen().false_accept_rate()
                                      : c.chosen().false_reject_rate();
  return v;
}

namespace {

// What the "both" column is, in words: both flanks (δRcomp), the larger side (a parameter's bias,
// u, U) or the parameter as a whole (its ratios and rates).
std::string both_words(const SweepStatistic& s) {
  return s.parameter.empty() ? "both flanks" : s.ratio() ? "the parameter" : "the larger side";
}

}  // namespace

std::vector<std::array<SweepValue, 3>> sweep_values(const SweepOutcome& s) {
  if (!s.values.empty()) return s.values;
  std::vector<std::array<SweepValue, 3>> values;
  for (std::size_t i = 0; i < s.results.size(); ++i) {
    const RunResults& r = s.results[i];
    if (!s.statistic.parameter.empty()) {
      values.push_back(sweep_parameter_values(s.statistic, MonteCarloRun(s.points[i].scenario), r));
      continue;
    }
    std::array<SweepValue, 3> v;
    for (int side = 0; side < 3; ++side) {
      v[side].value =
          sweep_statistic_value(s.statistic, sweep_quantity(s.statistic, r, side), &v[side].note);
    }
    values.push_back(v);
  }
  return values;
}

std::vector<std::array<SweepBand, 3>> sweep_point_bands(const SweepOutcome& s,
                                                        const std::vector<GearValues>& gears) {
  std::vector<std::array<SweepBand, 3>> bands;
  if (!sweep_statistic_has_band(s.statistic)) return bands;
  for (std::size_t i = 0; i < s.results.size(); ++i) {
    const Scenario& scenario = s.points[i].scenario;
    if (s.statistic.parameter.empty()) {
      bands.push_back(i < gears.size() ? delta_rcomp_bands(s.statistic, gears[i], s.confidence,
                                                           scenario.seed, s.resamples)
                                       : std::array<SweepBand, 3>{});
    } else {
      bands.push_back(parameter_bands(s.statistic, MonteCarloRun(scenario), s.results[i],
                                      s.confidence, scenario.seed, s.resamples));
    }
  }
  return bands;
}

std::vector<SweepVerdict> sweep_verdicts(const SweepOutcome& s) {
  if (!s.limit.any()) return {};
  const auto values = sweep_values(s);
  std::vector<SweepVerdict> verdicts;
  for (std::size_t i = 0; i < values.size(); ++i) {
    const SweepBand band = i < s.bands.size() ? s.bands[i][2] : SweepBand{};
    verdicts.push_back(sweep_verdict(s.limit, s.statistic, values[i][2].value, band));
  }
  return verdicts;
}

namespace {

// "[4.41, 4.93]" or "—" with the band's note.
std::string band_text(const SweepBand& b) {
  if (!b.lower) return "— (" + b.note + ")";
  std::ostringstream text;
  text.precision(4);
  text << "[" << *b.lower << ", " << *b.upper << "]";
  return text.str();
}

std::string percent_text(double confidence) {
  std::ostringstream text;
  text << confidence * 100.0;
  return text.str() + " %";
}

}  // namespace

std::string sweep_csv(const SweepOutcome& s) {
  std::ostringstream csv;
  // The header first (read with any tool's defaults); the provenance is sweep.json's.
  for (const SweepAxis& a : s.axes) csv << csv_field(a.key) << ",";
  csv << "gears,contacts,failed_contacts";
  const std::string unit = *s.statistic.unit() ? "_um" : "";
  for (const char* side : kSides) csv << "," << s.statistic.text << "_" << side << unit;
  const bool bands = !s.bands.empty();
  if (bands) {
    for (const char* side : kSides) {
      for (const char* end : {"lower", "upper"}) {
        csv << "," << s.statistic.text << "_" << side << "_" << end << unit;
      }
    }
  }
  const std::vector<SweepVerdict> verdicts = sweep_verdicts(s);
  if (!verdicts.empty()) csv << ",verdict";
  csv << "\n";
  const auto values = sweep_values(s);
  for (std::size_t i = 0; i < s.points.size(); ++i) {
    for (const std::string& v : s.points[i].values) csv << csv_field(v) << ",";
    const RunResults& r = s.results[i];
    csv << r.gears << "," << r.contacts << "," << r.failed_contacts;
    for (const SweepValue& v : values[i]) {
      csv << "," << (v.value ? shortest_text(*v.value) : std::string());
    }
    if (bands) {
      for (const SweepBand& b : s.bands[i]) {
        csv << "," << (b.lower ? shortest_text(*b.lower) : std::string()) << ","
            << (b.upper ? shortest_text(*b.upper) : std::string());
      }
    }
    if (!verdicts.empty()) csv << "," << sweep_verdict_text(verdicts[i]);
    csv << "\n";
  }
  return csv.str();
}

nlohmann::ordered_json sweep_json(const SweepOutcome& s) {
  nlohmann::ordered_json j;
  j["provenance"] = provenance_json(s.provenance);
  j["scenario"] = s.scenario_name;
  j["source"] = s.source_path;
  j["statistic"] = s.statistic.text;
  nlohmann::ordered_json axes = nlohmann::ordered_json::array();
  for (const SweepAxis& a : s.axes) axes.push_back({{"key", a.key}, {"values", a.values}});
  j["vary"] = axes;
  if (!s.bands.empty()) {
    j["bands"] = {{"confidence", s.confidence},
                  {"method", "cluster bootstrap over gears, percentile"},
                  {"resamples", s.resamples}};
  }
  if (s.limit.any()) {
    nlohmann::ordered_json limit;
    limit["at_most"] =
        s.limit.at_most ? nlohmann::ordered_json(*s.limit.at_most) : nlohmann::ordered_json();
    limit["at_least"] =
        s.limit.at_least ? nlohmann::ordered_json(*s.limit.at_least) : nlohmann::ordered_json();
    j["limit"] = limit;
  }
  const std::vector<SweepVerdict> verdicts = sweep_verdicts(s);
  const auto values = sweep_values(s);
  nlohmann::ordered_json points = nlohmann::ordered_json::array();
  for (std::size_t i = 0; i < s.points.size(); ++i) {
    nlohmann::ordered_json p;
    nlohmann::ordered_json at;
    for (std::size_t a = 0; a < s.axes.size(); ++a) at[s.axes[a].key] = s.points[i].values[a];
    p["values"] = at;
    const RunResults& r = s.results[i];
    p["gears"] = r.gears;
    p["seed"] = s.points[i].scenario.seed;
    p["contacts"] = r.contacts;
    p["failed_contacts"] = r.failed_contacts;
    p["edge_contacts"] = r.edge_contacts;
    p["collisions"] = r.collisions;
    for (int side = 0; side < 3; ++side) {
      const SweepValue& v = values[i][side];
      p[kSides[side] + std::string("_um")] =
          v.value ? nlohmann::ordered_json(*v.value) : nlohmann::ordered_json();
      if (!v.value) p[kSides[side] + std::string("_note")] = v.note;
    }
    if (!s.bands.empty()) {
      for (int side = 0; side < 3; ++side) {
        const SweepBand& b = s.bands[i][side];
        const std::string key = kSides[side] + std::string("_band_um");
        p[key] = b.lower ? nlohmann::ordered_json::array({*b.lower, *b.upper})
                         : nlohmann::ordered_json();
        if (!b.lower) p[kSides[side] + std::string("_band_note")] = b.note;
      }
    }
    if (!verdicts.empty()) p["verdict"] = sweep_verdict_text(verdicts[i]);
    points.push_back(p);
  }
  j["points"] = points;
  j["ranks"] = s.ranks;
  j["threads"] = s.threads;
  j["wall_s"] = s.wall_s;
  return j;
}

std::vector<std::string> sweep_figures(const SweepOutcome& s) {
  const auto values = sweep_values(s);
  const std::vector<SweepVerdict> verdicts = sweep_verdicts(s);
  std::vector<std::string> figures;
  const std::size_t axes = s.axes.size();
  // Index of the point with the value index `at[a]` on every axis a (last axis fastest).
  const auto point_index = [&](const std::vector<std::size_t>& at) {
    std::size_t index = 0;
    for (std::size_t a = 0; a < axes; ++a) index = index * s.axes[a].values.size() + at[a];
    return index;
  };
  for (std::size_t x_axis = 0; x_axis < axes; ++x_axis) {
    const SweepAxis& xa = s.axes[x_axis];
    bool numeric = true;
    for (const std::string& v : xa.values) numeric = numeric && number_of(v).has_value();
    // One line per combination of the other axes' values.
    std::size_t lines = 1;
    for (std::size_t a = 0; a < axes; ++a) {
      if (a != x_axis) lines *= s.axes[a].values.size();
    }
    std::vector<Series> series;
    std::vector<std::vector<ErrorBar>> bars;  // per series: its points' bands
    XYPlotOptions options;
    // With a limit: each point's verdict as a pale disc under it (one set per verdict).
    const char* verdict_colours[3] = {"#a5d6a7", "#ef9a9a", "#d0d0d0"};  // meets, misses, undecided
    if (!verdicts.empty()) {
      for (int m = 0; m < 3; ++m) {
        options.halos.push_back(
            {sweep_verdict_text(static_cast<SweepVerdict>(m)), verdict_colours[m], {}, {}});
      }
    }
    for (std::size_t line = 0; line < lines; ++line) {
      std::vector<std::size_t> at(axes, 0);
      std::size_t rest = line;
      std::string label;
      for (std::size_t a = axes; a-- > 0;) {
        if (a == x_axis) continue;
        at[a] = rest % s.axes[a].values.size();
        rest /= s.axes[a].values.size();
      }
      for (std::size_t a = 0; a < axes; ++a) {
        if (a == x_axis) continue;
        label += (label.empty() ? "" : ", ") + s.axes[a].key + " = " + s.axes[a].values[at[a]];
      }
      Series line_series;
      line_series.label = label;
      line_series.style = SeriesStyle::kLineAndPoints;
      std::vector<ErrorBar> line_bars;
      for (std::size_t k = 0; k < xa.values.size(); ++k) {
        at[x_axis] = k;
        const std::size_t point = point_index(at);
        const SweepValue& v = values[point][2];
        const double x = numeric ? *number_of(xa.values[k]) : static_cast<double>(k);
        line_series.x.push_back(x);
        line_series.y.push_back(v.value ? *v.value : std::nan(""));
        if (!s.bands.empty() && s.bands[point][2].lower) {
          line_bars.push_back({x, *s.bands[point][2].lower, *s.bands[point][2].upper, ""});
        }
        if (!verdicts.empty() && v.value) {
          PointHalos& h = options.halos[static_cast<std::size_t>(verdicts[point])];
          h.x.push_back(x);
          h.y.push_back(*v.value);
        }
      }
      // A line with exactly the values of an earlier one would hide it: one line, both labels.
      bool merged = false;
      for (Series& earlier : series) {
        bool same = earlier.y.size() == line_series.y.size();
        for (std::size_t k = 0; same && k < earlier.y.size(); ++k) {
          same = earlier.y[k] == line_series.y[k] ||
                 (std::isnan(earlier.y[k]) && std::isnan(line_series.y[k]));
        }
        if (same) {
          const std::string tag = " (same values)";
          if (earlier.label.size() >= tag.size() &&
              earlier.label.compare(earlier.label.size() - tag.size(), tag.size(), tag) == 0) {
            earlier.label.resize(earlier.label.size() - tag.size());
          }
          earlier.label += "; " + line_series.label + tag;
          merged = true;
          break;
        }
      }
      if (!merged) {
        series.push_back(std::move(line_series));
        bars.push_back(std::move(line_bars));
      }
    }
    // The bands in their line's colour, side by side when lines share an x.
    for (std::size_t k = 0; k < series.size(); ++k) {
      const double shift =
          series.size() > 1 && !bars[k].empty()
              ? (static_cast<double>(k) - static_cast<double>(series.size() - 1) / 2.0)
              : 0.0;
      for (ErrorBar b : bars[k]) {
        b.colour = svg_canvas::colour_or(series[k].colour, k);
        b.x_offset_px = 5.0 * shift;
        options.error_bars.push_back(b);
      }
    }
    if (!verdicts.empty()) {
      const char* unit = s.statistic.unit();
      const std::string u = *unit ? std::string(" ") + unit : std::string();
      if (s.limit.at_most) {
        options.limit_lines.push_back(
            {*s.limit.at_most, "at most " + shortest_text(*s.limit.at_most) + u});
      }
      if (s.limit.at_least) {
        options.limit_lines.push_back(
            {*s.limit.at_least, "at least " + shortest_text(*s.limit.at_least) + u});
      }
    }
    options.title = s.statistic.text + " (" + both_words(s.statistic) + ") against " + xa.key;
    options.x_label = numeric ? xa.key : xa.key + " (index of its values)";
    options.y_label = s.statistic.text + (*s.statistic.unit() ? ", µm" : "");
    options.y_from_zero = true;
    options.width_px = 760;
    options.height_px = 460;
    figures.push_back(xy_plot_svg(series, options));
  }
  return figures;
}

std::string sweep_report_html(const SweepOutcome& s, const std::vector<std::string>& figures) {
  HtmlReport report("gearmc sweep: " + s.scenario_name);
  std::string grid;
  for (const SweepAxis& a : s.axes) {
    grid += (grid.empty() ? "" : " × ") + a.key + " ∈ {";
    for (std::size_t k = 0; k < a.values.size(); ++k) grid += (k ? ", " : "") + a.values[k];
    grid += "}";
  }
  {  // The opening box: where on the grid the statistic (both flanks) is lowest and highest.
    const auto values = sweep_values(s);
    std::optional<std::size_t> lo, hi;
    std::size_t without = 0;
    for (std::size_t i = 0; i < values.size(); ++i) {
      const std::optional<double>& v = values[i].back().value;  // both flanks
      if (!v) {
        ++without;
        continue;
      }
      if (!lo || *v < *values[*lo].back().value) lo = i;
      if (!hi || *v > *values[*hi].back().value) hi = i;
    }
    const std::string unit = *s.statistic.unit() ? " µm" : "";
    const auto where = [&](std::size_t i) {
      std::ostringstream text;
      text.precision(4);
      text << *values[i].back().value << unit << " at ";
      for (std::size_t a = 0; a < s.axes.size(); ++a) {
        text << (a ? ", " : "") << s.axes[a].key << " = " << s.points[i].values[a];
      }
      return text.str();
    };
    std::vector<std::string> lines;
    if (lo) {
      lines.push_back("lowest: " + where(*lo));
      lines.push_back("highest: " + where(*hi));
    }
    if (without > 0) {
      lines.push_back(std::to_string(without) + " grid point(s) without a value (see the table)");
    }
    const std::vector<SweepVerdict> verdicts = sweep_verdicts(s);
    int count[3] = {0, 0, 0};
    if (!verdicts.empty()) {
      for (SweepVerdict v : verdicts) ++count[static_cast<int>(v)];
      lines.insert(lines.begin(),
                   "limit " + s.limit.text(s.statistic.unit()) + ": " + std::to_string(count[0]) +
                       " meet (the whole " + percent_text(s.confidence) + " band within), " +
                       std::to_string(count[1]) + " miss (the whole band beyond), " +
                       std::to_string(count[2]) + " undecided (more gears would decide)");
    }
    report.verdict(s.statistic.text + " of " + both_words(s.statistic) + " over " +
                       std::to_string(s.points.size()) + " grid points" +
                       (lo ? "" : ": no grid point has a value"),
                   lines,
                   verdicts.empty() ? HtmlReport::Tone::kNeutral
                   : count[1] > 0   ? HtmlReport::Tone::kBad
                   : count[2] == 0  ? HtmlReport::Tone::kGood
                                    : HtmlReport::Tone::kNeutral);
  }
  report.paragraph("Scenario " + s.source_path + ", grid " + grid + ": " +
                   std::to_string(s.points.size()) + " runs of " + sweep_runs_text(s.points) +
                   ". Statistic: " + s.statistic.text + (*s.statistic.unit() ? " in µm" : "") +
                   (s.statistic.parameter.empty()
                        ? std::string(", of the left flanks, the right flanks and both together.")
                    : s.statistic.ratio()
                        ? std::string(", of the parameter as a whole (the run report's).")
                        : std::string(", of the left and right flanks' items and the larger "
                                      "side (the run report's per side).")));
  if (!s.bands.empty()) {
    report.paragraph(
        "The whiskers are " + percent_text(s.confidence) +
        " confidence bands of the statistic: where it lies for infinitely many gears, from " +
        std::to_string(s.resamples) +
        " bootstrap resamples of the point's gears (whole gears drawn with replacement, as the "
        "gear is the unit of independence; the band is the resamples' central " +
        percent_text(s.confidence) +
        " range). The points share their perturbed gears (same seed), so two points' "
        "difference is known better than their bands suggest.");
  }
  for (std::size_t a = 0; a < figures.size(); ++a) {
    report.figure(figures[a],
                  s.statistic.text + " of " + both_words(s.statistic) + " against " +
                      s.axes[a].key +
                      (s.axes.size() > 1 ? "; one line per level of the other key(s)" : ""));
  }
  HtmlTable table;
  table.caption = "Every grid point";
  for (const SweepAxis& a : s.axes) table.header.push_back(a.key);
  const std::string unit = *s.statistic.unit() ? ", µm" : "";
  for (const std::string h : {"gears", "contacts", "failed"}) table.header.push_back(h);
  for (const std::string side : {"left", "right", "both"}) table.header.push_back(side + unit);
  if (!s.bands.empty()) {
    table.header.push_back("both: " + percent_text(s.confidence) + " band" + unit);
  }
  const std::vector<SweepVerdict> verdicts = sweep_verdicts(s);
  if (!verdicts.empty()) table.header.push_back("limit " + s.limit.text(s.statistic.unit()));
  const auto values = sweep_values(s);
  for (std::size_t i = 0; i < s.points.size(); ++i) {
    HtmlTable::Row row;
    row.cells = s.points[i].values;
    const RunResults& r = s.results[i];
    row.cells.push_back(std::to_string(r.gears));
    row.cells.push_back(std::to_string(r.contacts));
    row.cells.push_back(std::to_string(r.failed_contacts));
    for (const SweepValue& v : values[i]) {
      std::ostringstream text;
      if (v.value) {
        text.precision(4);
        text << *v.value;
      } else {
        text << "— (" << v.note << ")";
      }
      row.cells.push_back(text.str());
    }
    if (!s.bands.empty()) row.cells.push_back(band_text(s.bands[i][2]));
    if (!verdicts.empty()) row.cells.push_back(sweep_verdict_text(verdicts[i]));
    table.rows.push_back(row);
  }
  report.table(table);
  report.paragraph("Made by " + provenance_line(s.provenance) + ".");
  return report.html();
}

}  // namespace gearmc
