// The run's output files (run_outputs.h).
#include "engine/cli/run_outputs.h"

#include <tbb/info.h>

#include <functional>
#include <nlohmann/json.hpp>

#include "core/provenance.h"
#include "engine/reports/html_report.h"

namespace gearmc {

RunOutputs write_run_files(OutputFiles& files, const Scenario& scenario, const MonteCarloRun& mc,
                           const RunResults& r, const std::string& command_line, int ranks,
                           int threads, std::optional<int> only_gear) {
  RunOutputs o{
      present_run(r, make_provenance(command_line, scenario.source_path, scenario.source_text)),
      present_parameters(mc, r)};
  const RunPresentation& view = o.view;
  const std::optional<ParameterPresentation>& parameters = o.parameters;
  // Gear parameters (scenario `evaluation:`): their summary keys, figures and report section.
  nlohmann::ordered_json summary = run_summary_json(scenario, mc, r, view, only_gear);
  if (parameters) add_parameter_json(summary, mc, *parameters);
  // The job's shape: with the wall times, the only fields that differ between runs of any number
  // of ranks and threads.
  summary["ranks"] = ranks;
  summary["threads"] = threads > 0 ? threads : tbb::info::default_concurrency();
  files.write("summary.json", summary.dump(2) + "\n");
  files.write("histograms.csv", run_histograms_csv(r, view));
  const std::vector<RunFigure> figures = run_figures(scenario, r, view);
  for (const RunFigure& f : figures) files.write(f.file, f.svg);
  std::vector<RunFigure> parameter_charts;
  if (parameters) parameter_charts = parameter_figures(mc, r, *parameters);
  for (const RunFigure& f : parameter_charts) files.write(f.file, f.svg);
  std::function<void(HtmlReport&)> parameter_section, opening;
  if (parameters) {
    parameter_section = [&](HtmlReport& report) {
      add_parameter_section(report, mc, *parameters, parameter_charts);
    };
    opening = [&](HtmlReport& report) {
      const ParameterVerdict v = parameter_verdict(*parameters);
      report.verdict(v.headline, v.lines,
                     v.assessed == 0           ? HtmlReport::Tone::kNeutral
                     : v.capable == v.assessed ? HtmlReport::Tone::kGood
                                               : HtmlReport::Tone::kBad);
    };
  }
  files.write("report.html",
              run_report_html(scenario, r, view, figures, parameter_section, opening));
  return o;
}

}  // namespace gearmc
