// `gearmc sweep` (sweep_command.h): checks every variant and the output folder before any work,
// runs the grid over the ranks, and rank 0 writes the outputs atomically.
#include "engine/cli/sweep_command.h"
#include "engine/cli/interrupt_guard.h"

#include <tbb/info.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <sstream>

#include "core/input_error.h"
#include "core/number_text.h"
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
  s.confidence = o.confidence;
  s.limit = {o.at_most, o.at_least};
  for (const std::optional<double>* v : {&o.at_most, &o.at_least}) {
    if (*v && !std::isfinite(**v)) {
      throw InputError({}, v == &o.at_most ? "--at-most" : "--at-least", std::to_string(**v),
                       "a finite number");
    }
  }
  if (o.at_most && o.at_least && *o.at_least > *o.at_most) {
    throw InputError({}, "--at-least", shortest_text(*o.at_least),
                     "at most --at-most (" + shortest_text(*o.at_most) + ")");
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
  std::vector<GearValues> gear_values;  // per point (δRcomp statistics), for the bands
  {
    InterruptGuard guard;
    s.results = run_sweep(s.points, o.threads, ranks, progress, &s.statistic, &gear_values);
  }
  if (!ranks.is_root()) return 0;
  s.bands = sweep_point_bands(s, gear_values);
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
  const std::vector<SweepVerdict> verdicts = sweep_verdicts(s);
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
          << (*s.statistic.unit() ? " µm" : "");
      const SweepBand band = s.bands.empty() ? SweepBand{} : s.bands[i][2];
      if (band.lower) {
        out << std::setprecision(4) << "  [" << *band.lower << ", " << *band.upper << "]"
            << std::defaultfloat;
      }
      if (!verdicts.empty()) out << "  " << sweep_verdict_text(verdicts[i]);
      out << "\n";
    } else {
      out << "— (" << values[i][2].note << ")" << (verdicts.empty() ? "" : "  undecided") << "\n";
    }
  }
  bool any_band = false;
  for (const auto& b : s.bands) any_band = any_band || b[2].lower.has_value();
  std::ostringstream bands_words;
  bands_words << o.confidence * 100 << " % bands of " << s.resamples
              << " bootstrap resamples of the gears";
  if (!any_band) {
    bands_words.str(s.bands.empty() ? "no bands: the count is exact, an extreme has none"
                                    : "no bands: " + s.bands[0][2].note);
  }
  if (!verdicts.empty()) {
    int count[3] = {0, 0, 0};
    for (SweepVerdict v : verdicts) ++count[static_cast<int>(v)];
    out << "limit " << s.limit.text(s.statistic.unit()) << ": " << count[0] << " meet, " << count[1]
        << " miss, " << count[2] << " undecided (" << bands_words.str() << ")\n";
  } else if (any_band) {
    out << "[…]: " << bands_words.str() << "\n";
  }
  out << "report: " << (folder.dir / "report.html").string() << "\n";
  return 0;
}

}  // namespace gearmc
