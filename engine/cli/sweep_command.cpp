// `gearmc sweep` (sweep_command.h): checks every variant and the output folder before any work,
// runs the grid over the ranks, and rank 0 writes the outputs atomically.
#include "engine/cli/sweep_command.h"
#include "engine/cli/interrupt_guard.h"

#include <tbb/info.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <iomanip>
#include <iostream>

#include "core/input_error.h"
#include "core/output_files.h"
#include "core/provenance.h"
#include "core/ranks.h"
#include "engine/apps/sweep/sweep.h"
#include "engine/apps/sweep/sweep_report.h"

namespace gearmc {

namespace fs = std::filesystem;

int sweep_command(const SweepCommandOptions& o, std::ostream& out, std::ostream& err) {
  const auto start = std::chrono::steady_clock::now();
  const Scenario base = load_scenario_file(o.scenario_path);
  for (const std::string& w : base.warnings) err << "gearmc: warning: " << w << "\n";
  SweepOutcome s;
  s.statistic = parse_sweep_statistic(o.statistic);
  for (const std::string& v : o.vary) {
    s.axes.push_back(parse_vary(v));
    for (std::size_t a = 0; a + 1 < s.axes.size(); ++a) {
      if (s.axes[a].key == s.axes.back().key) {
        throw InputError({}, "--vary", v, "each key varied once ('" + s.axes[a].key + "' twice)");
      }
    }
  }
  s.points = sweep_grid(base.source_text, o.scenario_path, s.axes, o.overrides);
  check_sweep_statistic(s.statistic, s.points);
  s.scenario_name = base.name;
  s.source_path = o.scenario_path;

  const Ranks ranks = Ranks::world();
  CreatedFolder folder;
  ranks.agree([&] {
    if (!ranks.is_root()) return;
    folder.dir =
        o.out_dir.empty() ? fs::path("results") / (base.name + "_sweep") : fs::path(o.out_dir);
    prepare_output_folder(folder.dir, &folder.created);
  });
  out << "gearmc sweep: " << base.name << ", " << s.points.size() << " variants of "
      << sweep_runs_text(s.points, true) << ", statistic " << s.statistic.text << ", "
      << ranks.size() << " rank(s)\n"
      << std::flush;

  const bool show_progress = !o.quiet && isatty(STDERR_FILENO);
  std::function<void(int, int)> progress;
  if (show_progress) {
    progress = [&](int done, int total) {
      err << "\r  variants " << done << "/" << total << "   " << std::flush;
      if (done == total) err << "\n";
    };
  }
  {
    InterruptGuard guard;
    s.results = run_sweep(s.points, o.threads, ranks, progress);
  }
  if (!ranks.is_root()) return 0;
  s.ranks = ranks.size();
  s.threads = o.threads > 0 ? o.threads : tbb::info::default_concurrency();
  s.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  s.provenance = make_provenance(o.command_line, o.scenario_path, base.source_text);
  s.values = sweep_values(s);

  OutputFiles files(folder.dir);
  files.write("sweep.csv", sweep_csv(s));
  files.write("sweep.json", sweep_json(s).dump(2) + "\n");
  const std::vector<std::string> figures = sweep_figures(s);
  files.write("report.html", sweep_report_html(s, figures));
  files.commit();
  folder.created = false;

  const auto values = sweep_values(s);
  for (std::size_t i = 0; i < s.points.size(); ++i) {
    for (std::size_t a = 0; a < s.axes.size(); ++a) {
      out << (a ? "  " : "  ") << s.axes[a].key << "=" << s.points[i].values[a];
    }
    out << "  " << s.statistic.text
        << (s.statistic.parameter.empty() ? " (both flanks)"
            : s.statistic.ratio()         ? ""
                                          : " (larger side)")
        << " = ";
    if (values[i][2].value) {
      out << std::setprecision(4) << *values[i][2].value << std::defaultfloat
          << (*s.statistic.unit() ? " µm" : "") << "\n";
    } else {
      out << "— (" << values[i][2].note << ")\n";
    }
  }
  out << "report: " << (folder.dir / "report.html").string() << "\n";
  return 0;
}

}  // namespace gearmc
