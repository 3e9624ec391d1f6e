// `gearmc check`: argument checks, the sequential run of the claims, output files and printing
// (see check_command.h); the decision is engine/apps/check (sequential_check.h), what is written is
// composed in engine/apps/check/check_outputs.h.
#include "engine/cli/check_command.h"

#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <sstream>

#include "core/input_error.h"
#include "core/output_files.h"
#include "core/provenance.h"
#include "core/ranks.h"
#include "engine/apps/check/check_outputs.h"
#include "engine/apps/check/sequential_check.h"
#include "engine/cli/interrupt_guard.h"
#include "engine/cli/run_outputs.h"
#include "engine/evaluation/gear_parameters.h"
#include "engine/run/monte_carlo.h"

namespace gearmc {

namespace fs = std::filesystem;

int check_command(const CheckCommandOptions& o, std::ostream& out, std::ostream& err) {
  Scenario scenario = load_scenario_file(o.scenario_path);
  apply_overrides(o.overrides, scenario);
  for (const std::string& w : scenario.warnings) err << "gearmc: warning: " << w << "\n";
  if (scenario.claims.empty()) {
    throw InputError({scenario.source_path, 0, 0},
                     scenario.source_path +
                         ": no claims to check; add a `claims:` list, e.g.\n"
                         "claims:\n"
                         "  - name: flank_max_4um\n"
                         "    quantity: delta_rcomp.flank_max\n"
                         "    statistic: {quantile: 0.9973}\n"
                         "    at_most_um: 4.0\n"
                         "    confidence: 0.95\n"
                         "(docs/check.md)");
  }
  const MonteCarloRun mc(scenario);
  // U/T claims: the tolerance interval's width of their parameter (2T for ±T, T for ≤ T, upper −
  // lower for a size's allowances).
  for (ClaimSpec& c : scenario.claims) {
    if (c.statistic != ClaimStatistic::kUOverT) continue;
    if (scenario.evaluation) {
      const auto& allowances = scenario.evaluation->size_allowances_um;
      if (const auto a = allowances.find(c.parameter); a != allowances.end()) {
        c.tolerance_width_um = a->second.second - a->second.first;
        continue;
      }
    }
    const std::optional<GearParameter> p = parameter_from_symbol(c.parameter);
    const double T = p ? parameter_tolerance_um(mc.tolerances(), *p).value_or(0.0) : 0.0;
    if (!(T > 0.0)) {
      throw InputError(c.statistic_where, "claims.statistic", "U_over_T",
                       "a statistic this claim can have: the scenario's tolerances have no T for " +
                           c.parameter +
                           " (U/T needs it, or evaluation.size_allowances_um for a "
                           "size; statistic U needs none)");
    }
    c.tolerance_width_um = parameter_signed(*p) ? 2.0 * T : T;
  }

  // Fail before the work: the output folder and the JUnit file must be writable now.
  // Only rank 0 of an MPI job writes; the other ranks measure their share of each batch.
  const Ranks ranks = Ranks::world();
  CreatedFolder folder;
  ranks.agree([&] {
    if (!ranks.is_root()) return;
    folder.dir =
        o.out_dir.empty() ? fs::path("results") / scenario.name / "check" : fs::path(o.out_dir);
    prepare_output_folder(folder.dir, &folder.created);
    if (!o.junit_path.empty()) check_output_file(o.junit_path, "--junit");
  });

  out << "gearmc check: " << scenario.name << ", " << scenario.claims.size()
      << (scenario.claims.size() == 1 ? " claim" : " claims") << ", at most " << o.max_gears
      << " gears (looks at " << kFirstLookGears << ", doubling), seed " << scenario.seed << "\n"
      << std::flush;

  CheckOptions options;
  options.max_gears = o.max_gears;
  options.threads = o.threads;
  options.cancel = &interrupted_flag();
  options.ranks = &ranks;
  options.keep_run = true;  // the run report of the gears the claims rest on (run/)
  const bool show_progress = !o.quiet && isatty(STDERR_FILENO);
  if (show_progress) {
    options.on_look = [&](const SequentialCheck& check) {
      int decided = 0;
      for (std::size_t i = 0; i < scenario.claims.size(); ++i) decided += check.decided(i);
      err << "\r  gears " << check.gears() << "/" << check.max_gears() << "  decided " << decided
          << "/" << scenario.claims.size() << "   " << std::flush;
    };
  }
  CheckRun run;
  {
    InterruptGuard guard;
    try {
      run = run_check(mc, scenario.claims, options);
    } catch (const ToleranceError& e) {
      throw InputError({scenario.source_path, 0, 0},
                       scenario.source_path + ": tolerances: " + e.what());
    }
  }
  if (show_progress) err << "\n";
  if (!ranks.is_root()) return run.cancelled ? 130 : 0;
  if (run.cancelled) {
    err << "gearmc: interrupted after " << run.gears << " gears; nothing written\n";
    return 130;
  }
  if (run.contacts > 0 &&
      run.failed_contacts + run.edge_contacts + run.collisions == run.contacts) {
    std::ostringstream msg;
    msg << scenario.source_path << ": none of the " << run.contacts << " contacts"
        << (run.no_values ? " of the first gear" : "") << " gave a value (failed "
        << run.failed_contacts << ", edge " << run.edge_contacts << ", collisions "
        << run.collisions
        << "); check the stylus (radius, shaft) against the tooth space and any normal_um "
           "expression";
    throw InputError({scenario.source_path, 0, 0}, msg.str());
  }

  CheckContext context;
  context.scenario = &scenario;
  context.provenance = make_provenance(o.command_line, scenario.source_path, scenario.source_text);
  context.max_gears = o.max_gears;
  context.threads = o.threads;
  context.ranks = ranks.size();
  context.run_report = "run/report.html";
  OutputFiles files(folder.dir);
  files.write("check.json", check_json(context, run).dump(2) + "\n");
  files.write("report.html", check_report_html(context, run));
  const std::string junit = o.junit_path.empty() ? "" : check_junit_xml(context, run);
  // The run report of the same gears, as `gearmc run --gears N` of the scenario writes it.
  const fs::path run_dir = folder.dir / "run";
  const bool made_run_dir = !fs::exists(run_dir);
  fs::create_directories(run_dir);
  try {
    OutputFiles run_files(run_dir);
    Scenario ran = scenario;
    ran.gears = run.gears;
    write_run_files(run_files, ran, mc, *run.run_results, o.command_line, ranks.size(), o.threads);
    run_files.commit();
  } catch (...) {
    if (made_run_dir) remove_if_empty(run_dir);
    throw;
  }
  files.commit();
  folder.created = false;
  if (!o.junit_path.empty()) write_file_atomically(o.junit_path, junit);

  std::size_t width = 0;
  for (const ClaimSpec& c : scenario.claims) width = std::max(width, c.name.size());
  for (std::size_t i = 0; i < run.results.size(); ++i) {
    out << claim_terminal_line(scenario.claims[i], run.results[i], width) << "\n";
  }
  if (run.failed_contacts + run.edge_contacts + run.collisions > 0) {
    err << "gearmc: warning: " << run.failed_contacts + run.edge_contacts + run.collisions << " of "
        << run.contacts
        << " contacts gave no value (failed, edge or collision); the claims rest on the others\n";
  }
  out << run.gears << " gears in " << std::fixed << std::setprecision(1) << run.wall_s
      << " s; check.json and report.html in " << folder.dir.string()
      << " (the run report of these gears in run/)\n"
      << std::defaultfloat;
  return check_exit_code(run);
}

}  // namespace gearmc
