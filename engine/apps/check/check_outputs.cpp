// check.json, the JUnit XML, report.html and the terminal lines of `gearmc check` (see
// check_outputs.h).
#include "engine/apps/check/check_outputs.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>

#include "engine/reports/html_report.h"
#include "engine/reports/svg_plot.h"

namespace gearmc {
namespace {

std::string fixed(double v, int decimals = 3) {
  if (!std::isfinite(v)) return "—";
  char text[64];
  std::snprintf(text, sizeof text, "%.*f", decimals, v);
  return text;
}

std::string general(double v, int digits = 4) {
  char text[64];
  std::snprintf(text, sizeof text, "%.*g", digits, v);
  return text;
}

nlohmann::ordered_json number_or_null(double v) {
  return std::isfinite(v) ? nlohmann::ordered_json(v) : nlohmann::ordered_json(nullptr);
}

std::string quantity_words(const ClaimSpec& c) {
  std::string q;
  switch (c.quantity) {
    case ClaimQuantity::kDeltaRcompPoint:
      q = "δRcomp per point";
      break;
    case ClaimQuantity::kDeltaRcompFlankMax:
      q = "max δRcomp per flank";
      break;
    case ClaimQuantity::kTotalErrorPoint:
      q = "|total error| per point";
      break;
    case ClaimQuantity::kParameterError:
      q = c.parameter + " error (measured − true) per item";
      break;
  }
  return q + " (" +
         (c.side == ClaimSide::kBoth ? std::string("both sides") : side_text(c.side) + " flanks") +
         ")";
}

// A bound to 3 decimals rounded outward (down for the lower, up for the upper bound), so the
// printed bound is still a bound; a bound at the limit is printed as the limit is.
std::string bound_number(double v, bool upper, double limit) {
  if (!std::isfinite(v)) return "—";
  if (v == limit) return general(limit);
  const double thousandths = upper ? std::ceil(v * 1000.0) : std::floor(v * 1000.0);
  return fixed(thousandths / 1000.0);
}

std::string bound_text(const ClaimSpec& c, const ClaimResult& r) {
  return "[" + bound_number(r.lower_um, false, c.two_sided ? c.lower_limit_um : c.limit_um) + ", " +
         bound_number(r.upper_um, true, c.limit_um) + "]" + claim_unit(c);
}

// What the verdict says in one sentence, for the report and the JUnit failure message.
std::string verdict_sentence(const ClaimSpec& c, const ClaimResult& r) {
  std::string s = std::string(verdict_text(r.verdict)) + " after " + std::to_string(r.gears) +
                  " gears: estimate " + fixed(r.estimate_um) + claim_unit(c) + ", " +
                  "lower and upper confidence bounds " + bound_text(c, r) + " (each one-sided at " +
                  general(100.0 * (1.0 - bound_alpha(c))) + " %; together at least " +
                  general(100.0 * (2.0 * (1.0 - bound_alpha(c)) - 1.0)) + " %)" + ", limit " +
                  limit_text(c);
  if (r.exceedance && r.exceedance_allowed && c.statistic == ClaimStatistic::kQuantile) {
    s += "; probability of a value beyond the limit " + general(*r.exceedance, 3) + " (bounds " +
         general(r.exceedance_lower.value_or(NAN), 3) + " … " +
         general(r.exceedance_upper.value_or(NAN), 3) + "), allowed " +
         general(*r.exceedance_allowed, 4);
  }
  if (!r.note.empty()) s += "; " + r.note;
  return s;
}

}  // namespace

bool all_claims_hold(const CheckRun& run) {
  for (const ClaimResult& r : run.results) {
    if (r.verdict != Verdict::kHolds) return false;
  }
  return !run.results.empty();
}

int check_exit_code(const CheckRun& run) {
  bool undecided = run.results.empty();
  for (const ClaimResult& r : run.results) {
    if (r.verdict == Verdict::kFails) return 1;
    if (r.verdict == Verdict::kUndecided) undecided = true;
  }
  return undecided ? 3 : 0;
}

std::string claim_statement(const ClaimSpec& c) {
  return quantity_words(c) + " " + statistic_text(c) + " " + limit_text(c) + " at " +
         general(100.0 * c.confidence) + " % confidence";
}

nlohmann::ordered_json check_json(const CheckContext& context, const CheckRun& run) {
  const Scenario& scenario = *context.scenario;
  nlohmann::ordered_json j;
  j["command"] = "check";
  j["scenario"] = scenario.name;
  j["source"] = scenario.source_path;
  j["seed"] = scenario.seed;
  j["ranks"] = context.ranks;
  j["threads"] = context.threads;
  j["max_gears"] = context.max_gears;
  j["gears"] = run.gears;
  if (!context.run_report.empty()) j["run_report"] = context.run_report;
  j["looks"] = look_points(context.max_gears);
  j["contacts"] = run.contacts;
  j["failed_contacts"] = run.failed_contacts;
  j["edge_contacts"] = run.edge_contacts;
  j["collisions"] = run.collisions;
  j["wall_s"] = run.wall_s;
  nlohmann::ordered_json claims = nlohmann::ordered_json::array();
  for (std::size_t i = 0; i < run.results.size(); ++i) {
    const ClaimSpec& c = run.trackers[i].claim();
    const ClaimResult& r = run.results[i];
    nlohmann::ordered_json k;
    k["name"] = c.name;
    k["verdict"] = verdict_text(r.verdict);
    const bool ratio = c.statistic == ClaimStatistic::kUOverT;  // no unit: keys without _um
    k[ratio ? "estimate" : "estimate_um"] = number_or_null(r.estimate_um);
    k[ratio ? "bound" : "bound_um"] = {number_or_null(r.lower_um), number_or_null(r.upper_um)};
    k["confidence"] = c.confidence;
    k["gears"] = r.gears;
    k["time_s"] = r.time_s;
    k["quantity"] = c.quantity_text;
    k["side"] = side_text(c.side);
    k["statistic"] = statistic_text(c);
    const std::string unit = ratio ? "" : "_um";
    if (c.two_sided) k["at_least" + unit] = c.lower_limit_um;
    k[(c.at_most ? "at_most" : "at_least") + unit] = c.limit_um;
    if (ratio) k["tolerance_width_um"] = c.tolerance_width_um;
    k["method"] = r.method;
    if (r.resolution_um > 0.0) k["resolution_um"] = r.resolution_um;
    if (r.exceedance) {
      k["exceedance"] = {{"estimate", *r.exceedance},
                         {"bound",
                          {number_or_null(r.exceedance_lower.value_or(NAN)),
                           number_or_null(r.exceedance_upper.value_or(NAN))}},
                         {"allowed", number_or_null(r.exceedance_allowed.value_or(NAN))},
                         {"per", c.statistic == ClaimStatistic::kMax ? "gear" : "value"}};
    }
    if (run.trackers[i].gears_without_values() > 0) {
      k["gears_without_values"] = run.trackers[i].gears_without_values();
    }
    if (!r.note.empty()) k["note"] = r.note;
    claims.push_back(k);
  }
  j["claims"] = claims;
  j["all_hold"] = all_claims_hold(run);
  j["provenance"] = provenance_json(context.provenance);
  return j;
}

std::string check_junit_xml(const CheckContext& context, const CheckRun& run) {
  int failures = 0;
  for (const ClaimResult& r : run.results) failures += r.verdict != Verdict::kHolds;
  const std::string suite = escape_xml(context.scenario->name);
  std::ostringstream x;
  x << "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
    << "<testsuites name=\"gearmc check\" tests=\"" << run.results.size() << "\" failures=\""
    << failures << "\" errors=\"0\" time=\"" << fixed(run.wall_s) << "\">\n"
    << "  <testsuite name=\"" << suite << "\" tests=\"" << run.results.size() << "\" failures=\""
    << failures << "\" errors=\"0\" skipped=\"0\" time=\"" << fixed(run.wall_s) << "\">\n";
  for (std::size_t i = 0; i < run.results.size(); ++i) {
    const ClaimSpec& c = run.trackers[i].claim();
    const ClaimResult& r = run.results[i];
    x << "    <testcase classname=\"gearmc.check." << suite << "\" name=\"" << escape_xml(c.name)
      << "\" time=\"" << fixed(r.time_s) << "\">\n";
    if (r.verdict != Verdict::kHolds) {
      x << "      <failure type=\"" << verdict_text(r.verdict) << "\" message=\""
        << escape_xml(std::string(verdict_text(r.verdict)) + ": " + claim_statement(c)) << "\">"
        << escape_xml(verdict_sentence(c, r)) << "</failure>\n";
    }
    x << "      <system-out>" << escape_xml(claim_statement(c) + ": " + verdict_sentence(c, r))
      << "</system-out>\n"
      << "    </testcase>\n";
  }
  x << "  </testsuite>\n</testsuites>\n";
  return x.str();
}

std::string check_report_html(const CheckContext& context, const CheckRun& run) {
  const Scenario& scenario = *context.scenario;
  HtmlReport report("gearmc check: " + scenario.name);
  {  // The verdict box: every claim's verdict in a line, the count in the headline.
    int fails = 0, undecided = 0;
    std::vector<std::string> lines;
    for (std::size_t i = 0; i < run.results.size(); ++i) {
      const ClaimSpec& c = run.trackers[i].claim();
      const ClaimResult& r = run.results[i];
      fails += r.verdict == Verdict::kFails;
      undecided += r.verdict == Verdict::kUndecided;
      lines.push_back(c.name + " (" + claim_statement(c) + "): " + verdict_text(r.verdict) +
                      ", estimate " + fixed(r.estimate_um) + claim_unit(c) + ", bounds " +
                      bound_text(c, r));
    }
    const std::string counts = std::to_string(run.results.size()) + " claims, " +
                               std::to_string(run.gears) + " gears of at most " +
                               std::to_string(context.max_gears) + ", seed " +
                               std::to_string(scenario.seed) + ", " + fixed(run.wall_s, 1) + " s";
    std::string headline = all_claims_hold(run)
                               ? "Every claim holds (" + counts + ")."
                               : "Not every claim holds: " + std::to_string(fails) + " fail, " +
                                     std::to_string(undecided) + " undecided (" + counts + ").";
    report.verdict(headline, lines,
                   all_claims_hold(run) ? HtmlReport::Tone::kGood
                   : fails > 0          ? HtmlReport::Tone::kBad
                                        : HtmlReport::Tone::kNeutral);
  }
  if (!context.run_report.empty()) {
    report.link_paragraph("The run report of these " + std::to_string(run.gears) +
                              " gears (every statistic, histogram and chart of the run, as "
                              "gearmc run --gears " +
                              std::to_string(run.gears) + " writes it): ",
                          context.run_report, context.run_report);
  }
  report.contents();
  HtmlTable summary;
  summary.header = {"claim", "statement", "verdict", "estimate", "bounds", "gears"};
  for (std::size_t i = 0; i < run.results.size(); ++i) {
    const ClaimSpec& c = run.trackers[i].claim();
    const ClaimResult& r = run.results[i];
    summary.rows.push_back(
        {{c.name, claim_statement(c), verdict_text(r.verdict), fixed(r.estimate_um) + claim_unit(c),
          bound_text(c, r), std::to_string(r.gears)},
         r.verdict != Verdict::kHolds});
  }
  report.heading("Verdicts");
  report.table(summary);
  report.paragraph(
      "A claim holds when its confidence bound is on the right side of the limit, fails when "
      "the bound on the other side is past it, and is undecided otherwise. The gear is the unit "
      "of independence: every bound is computed from one number per gear (for a quantile, the "
      "gear's fraction of values beyond the limit), so values of one gear, which share its "
      "eccentricity and effects, are never counted as independent. The bounds are confidence "
      "sequences, valid at every look (after 256, 512, 1024, … gears), so stopping at the first "
      "decisive look does not raise the error rate.");
  for (std::size_t i = 0; i < run.results.size(); ++i) {
    const ClaimSpec& c = run.trackers[i].claim();
    const ClaimResult& r = run.results[i];
    report.heading(c.name);
    report.paragraph(claim_statement(c) + ": " + verdict_sentence(c, r) + ". Method: " + r.method +
                     (r.resolution_um > 0.0 ? "; the bounds in µm are resolved to one bin of " +
                                                  general(r.resolution_um, 3) + " µm"
                                            : "") +
                     ".");
    const std::optional<Histogram>& pooled = run.trackers[i].pooled();
    if (!pooled || pooled->total() == 0) continue;
    if (c.statistic == ClaimStatistic::kUOverT) continue;  // a ratio: not on the errors' axis
    HistogramPlotOptions plot;
    plot.title = c.name + ": " + quantity_words(c);
    plot.x_label = quantity_words(c) + ", µm";
    plot.bars_label = "values of " + std::to_string(r.gears) + " gears";
    plot.log_count = true;
    // From the smallest value (the grid extends a quarter of the data's span below it).
    plot.x_min = std::min(pooled->min(), c.two_sided ? c.lower_limit_um : c.limit_um);
    plot.markers.push_back(
        {c.limit_um, std::string("limit ") + general(c.limit_um) + " µm", "#D55E00", false});
    if (c.two_sided) {
      plot.markers.push_back({c.lower_limit_um,
                              std::string("limit ") + general(c.lower_limit_um) + " µm", "#D55E00",
                              false});
    }
    if (std::isfinite(r.lower_um)) {
      plot.markers.push_back(
          {r.lower_um,
           "lower bound " +
               bound_number(r.lower_um, false, c.two_sided ? c.lower_limit_um : c.limit_um),
           "#0072B2", true});
    }
    if (std::isfinite(r.upper_um)) {
      plot.markers.push_back({r.upper_um,
                              "upper bound " + bound_number(r.upper_um, true, c.limit_um),
                              "#0072B2", true});
    }
    if (std::isfinite(r.estimate_um)) {
      plot.markers.push_back({r.estimate_um, "estimate " + fixed(r.estimate_um), "#009E73", true});
    }
    report.figure(histogram_svg(pooled->rebin(4), plot),
                  "Histogram of " + quantity_words(c) + " (log count), with the limit, the " +
                      "estimate and the confidence bounds of the claim's statistic." +
                      (c.statistic == ClaimStatistic::kExpandedUncertainty
                           ? " U is a statistic of the whole law, not a value: it is the "
                             "half-width of the interval ±U about zero, which holds about 95 % "
                             "of the errors when their law is near normal."
                           : ""));
  }
  report.heading("Scenario");
  report.preformatted(scenario.source_text, scenario.source_path);
  report.paragraph("Made by " + provenance_line(context.provenance) + ".");
  return report.html();
}

std::string claim_terminal_line(const ClaimSpec& c, const ClaimResult& r, std::size_t name_width) {
  std::string name = c.name;
  if (name.size() < name_width) name += std::string(name_width - name.size(), ' ');
  char verdict[16];
  std::snprintf(verdict, sizeof verdict, "%-9s", verdict_text(r.verdict));
  return name + "  " + verdict + "  " + statistic_text(c) + " estimate " + fixed(r.estimate_um) +
         claim_unit(c) + "  bounds " + bound_text(c, r) + "  (limit " + limit_text(c) + ")  " +
         std::to_string(r.gears) + " gears  " + fixed(r.time_s, 1) + " s";
}

}  // namespace gearmc
