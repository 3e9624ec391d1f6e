// `gearmc run`: argument checks, the Monte-Carlo batch, output files and printing (see
// run_command.h); what is written and printed is composed in engine/reports (run_report.h,
// run_terminal.h).
#include "engine/cli/run_command.h"

#include "engine/cli/interrupt_guard.h"
#include "engine/cli/plan_program.h"
#include "engine/cli/run_outputs.h"

#include <unistd.h>

#include <atomic>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iomanip>
#include <iostream>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>

#include <tbb/info.h>

#include "core/input_error.h"
#include "core/output_files.h"
#include "core/provenance.h"
#include "core/ranks.h"
#include "engine/reports/html_report.h"
#include "engine/reports/parameter_report.h"
#include "engine/reports/run_report.h"
#include "engine/reports/run_terminal.h"
#include "engine/run/monte_carlo.h"
#include "engine/run/run_partials.h"

namespace gearmc {
namespace {

namespace fs = std::filesystem;

// Measured size of one points.csv row (17 significant digits, 24 fields): 300–330 bytes on P1's
// gear; 330 is used for the estimate.
constexpr double kPointRowBytes = 330.0;
// --points refuses a file larger than this unless --force.
constexpr double kPointsLimitBytes = 4.0e9;

// The default folder results/<name> may hold the results of another scenario file with the same
// `name:`; overwriting them silently would lose them. (An explicit --out is the user's choice.)
void refuse_another_scenarios_folder(const fs::path& dir, const Scenario& scenario) {
  std::ifstream previous(dir / "summary.json");
  if (!previous) return;
  const nlohmann::json summary = nlohmann::json::parse(previous, nullptr, false);
  if (summary.is_discarded() || !summary.contains("source") || !summary["source"].is_string()) {
    return;
  }
  const std::string source = summary["source"].get<std::string>();
  if (source == scenario.source_path) return;
  throw InputError({scenario.source_path, 0, 0},
                   dir.string() + " holds the results of another scenario file with the name '" +
                       scenario.name + "' (" + source + "); give this run its own folder with " +
                       "--out DIR, or remove " + dir.string());
}

}  // namespace

int run_command(const RunCommandOptions& o, std::ostream& out, std::ostream& err) {
  Scenario scenario =
      o.scenario_path.empty() ? reference_scenario() : load_scenario_file(o.scenario_path);
  apply_overrides(o.overrides, scenario);
  if (!o.plan_path.empty()) apply_plan_program(o.plan_path, scenario);
  for (const std::string& w : scenario.warnings) err << "gearmc: warning: " << w << "\n";
  const MonteCarloRun mc(scenario);
  if (o.only_gear && (*o.only_gear < 0 || *o.only_gear >= scenario.gears)) {
    throw InputError({}, "--only-gear", std::to_string(*o.only_gear),
                     "a gear index from 0 to " + std::to_string(scenario.gears - 1));
  }
  const double gears_run = o.only_gear ? 1.0 : static_cast<double>(scenario.gears);
  const double planned_points =
      gears_run * mc.probed_teeth() * mc.points_per_flank() *
      ((scenario.probing.left ? 1 : 0) + (scenario.probing.right ? 1 : 0));
  if (o.points) {
    const double bytes = planned_points * kPointRowBytes;
    if (bytes > kPointsLimitBytes && !o.force) {
      std::ostringstream msg;
      msg << "--points: points.csv would hold " << std::setprecision(3) << planned_points
          << " rows, about " << bytes / 1e9 << " GB; add --force to write it anyway, or run "
          << "fewer gears";
      throw InputError({}, msg.str());
    }
  }

  // Fail before the work: the output folder must be writable now, not after the run. Only rank 0
  // writes (the other ranks of an MPI job only compute their share of the gears).
  const Ranks ranks = Ranks::world();
  CreatedFolder folder;
  std::optional<OutputFiles> files;
  std::ofstream points_file;
  ranks.agree([&] {
    if (!ranks.is_root()) return;
    // One gear re-run (--only-gear K) goes beside the full run's results, not over them.
    folder.dir = !o.out_dir.empty() ? fs::path(o.out_dir)
                 : o.only_gear      ? fs::path("results") / scenario.name /
                                     ("gear_" + std::to_string(*o.only_gear))
                               : fs::path("results") / scenario.name;
    if (o.out_dir.empty()) refuse_another_scenarios_folder(folder.dir, scenario);
    prepare_output_folder(folder.dir, &folder.created);
    files.emplace(folder.dir);
    if (o.points) {
      points_file = files->open("points.csv");
      points_file << std::setprecision(17);
      // The header first (pandas, R and spreadsheets read it with their defaults); what made
      // the file is in summary.json's provenance beside it.
      points_file << points_csv_header();
    }
  });
  const fs::path& dir = folder.dir;

  out << run_header_line(scenario, mc, o.only_gear) << "\n";
  if (o.points) {
    out << "points.csv: " << std::setprecision(3) << planned_points << " rows, about "
        << planned_points * kPointRowBytes / 1e6 << " MB\n"
        << std::defaultfloat;
  }
  out << std::flush;

  RunOptions run;
  run.threads = o.threads;
  run.only_gear = o.only_gear;
  run.record_points = o.points;
  run.cancel = &interrupted_flag();
  GearStream points_rows;
  if (o.points) {
    // Rows are made on the rank that probed the gear and written by rank 0 in gear order.
    points_rows.encode = [](const GearOutcome& g, std::string& bytes) {
      std::ostringstream rows;
      rows << std::setprecision(17);
      for (const ProbedPoint& p : g.points) write_point_row(rows, p);
      bytes += rows.str();
    };
    points_rows.consume = [&](std::string_view bytes) {
      points_file.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    };
  }
  const bool show_progress = !o.quiet && isatty(STDERR_FILENO);
  const auto start = std::chrono::steady_clock::now();
  if (show_progress) {
    run.progress = [&](int done, int total) {
      const double t =
          std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      if (t < 1.0 && done < total) return;
      const double eta = done > 0 ? t * (total - done) / done : 0.0;
      const double rate = done * mc.points_per_flank() * mc.probed_teeth() * 2.0 / t;
      err << "\r  gears " << done << "/" << total << "  contacts/s " << std::scientific
          << std::setprecision(2) << rate << std::defaultfloat << "  ETA " << std::fixed
          << std::setprecision(0) << eta << " s   " << std::defaultfloat << std::flush;
      if (done == total) err << '\n';
    };
  }
  RunResults r;
  {
    InterruptGuard guard;
    r = run_on_ranks(mc, run, ranks, points_rows);
  }
  if (!ranks.is_root()) return r.cancelled ? 130 : 0;
  if (r.cancelled) {
    // The partial files go with `files`, the folder with `folder` (if this run made it).
    err << (show_progress ? "\n" : "") << "gearmc: interrupted after " << r.gears
        << " gears; nothing written\n";
    return 130;
  }
  if (o.points) points_file.close();
  if (r.contacts > 0 && r.failed_contacts + r.edge_contacts + r.collisions == r.contacts) {
    std::ostringstream msg;
    msg << (scenario.source_path.empty() ? "the reference scenario" : scenario.source_path)
        << ": none of the " << r.contacts << " contacts gave a value (failed " << r.failed_contacts
        << ", edge " << r.edge_contacts << ", collisions " << r.collisions
        << "); check the stylus (radius, shaft) against the tooth space and any normal_um "
           "expression "
           "(it must be finite on the whole flank)";
    throw InputError({scenario.source_path, 0, 0}, msg.str());
  }

  const RunOutputs written = write_run_files(*files, scenario, mc, r, o.command_line, ranks.size(),
                                             o.threads, o.only_gear);
  const RunPresentation& view = written.view;
  const std::optional<ParameterPresentation>& parameters = written.parameters;
  files->commit();
  folder.created = false;  // keep it: it holds the results now

  out << run_contacts_line(r) << "\n";
  if (ranks.size() > 1) {
    out << "ranks " << ranks.size() << ": " << r.reduction_bytes
        << " bytes of partial results received by rank 0, waited " << std::setprecision(3)
        << r.gather_s << " s after its own share, merged in " << r.merge_s << " s\n"
        << std::defaultfloat;
  }
  for (const std::string& w : view.warnings) err << "gearmc: warning: " << w << "\n";
  print_run_summary(out, scenario, r, view);
  if (parameters) print_parameter_tables(out, mc, *parameters);
  out << "report: " << dir.string() << "/report.html\n";
  return 0;
}

}  // namespace gearmc
