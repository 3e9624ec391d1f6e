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

namespace {

// A gear parameter's statistic at one point (sweep.h): from the run's parameter presentation,
// as the run report states it.
std::array<SweepValue, 3> parameter_values(const SweepStatistic& stat, const Scenario& scenario,
                                           const RunResults& r) {
  std::array<SweepValue, 3> v;
  const MonteCarloRun mc(scenario);
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
      values.push_back(parameter_values(s.statistic, s.points[i].scenario, r));
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

std::string sweep_csv(const SweepOutcome& s) {
  std::ostringstream csv;
  // The header first (read with any tool's defaults); the provenance is sweep.json's.
  for (const SweepAxis& a : s.axes) csv << csv_field(a.key) << ",";
  csv << "gears,contacts,failed_contacts";
  const std::string unit = *s.statistic.unit() ? "_um" : "";
  for (const char* side : kSides) csv << "," << s.statistic.text << "_" << side << unit;
  csv << "\n";
  const auto values = sweep_values(s);
  for (std::size_t i = 0; i < s.points.size(); ++i) {
    for (const std::string& v : s.points[i].values) csv << csv_field(v) << ",";
    const RunResults& r = s.results[i];
    csv << r.gears << "," << r.contacts << "," << r.failed_contacts;
    for (const SweepValue& v : values[i]) {
      csv << "," << (v.value ? shortest_text(*v.value) : std::string());
    }
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
      for (std::size_t k = 0; k < xa.values.size(); ++k) {
        at[x_axis] = k;
        const SweepValue& v = values[point_index(at)][2];
        line_series.x.push_back(numeric ? *number_of(xa.values[k]) : static_cast<double>(k));
        line_series.y.push_back(v.value ? *v.value : std::nan(""));
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
      if (!merged) series.push_back(std::move(line_series));
    }
    XYPlotOptions options;
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
    report.verdict(s.statistic.text + " of " + both_words(s.statistic) + " over " +
                       std::to_string(s.points.size()) + " grid points" +
                       (lo ? "" : ": no grid point has a value"),
                   lines);
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
    table.rows.push_back(row);
  }
  report.table(table);
  report.paragraph("Made by " + provenance_line(s.provenance) + ".");
  return report.html();
}

}  // namespace gearmc
