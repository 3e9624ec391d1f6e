// `gearmc simulate` (see simulate_command.h).
#include "engine/cli/simulate_command.h"

#include "engine/cli/plan_program.h"

#include <filesystem>
#include <fstream>
#include <stdexcept>

#include "core/input_error.h"
#include "core/output_files.h"
#include "core/provenance.h"
#include "engine/effects/measurement_effect.h"
#include "engine/run/simulate.h"

namespace gearmc {

int simulate_command(const SimulateCommandOptions& o, std::ostream& out, std::ostream& err) {
  Scenario scenario =
      o.scenario_path.empty() ? reference_scenario() : load_scenario_file(o.scenario_path);
  apply_overrides(o.overrides, scenario);
  if (!o.plan_path.empty()) apply_plan_program(o.plan_path, scenario);
  for (const std::string& w : scenario.warnings) err << "gearmc: warning: " << w << "\n";
  check_output_file(o.out, "--out");
  SimulateOptions options;
  options.gears = o.gears;
  options.master = o.master;
  options.reference_deviations = o.reference_deviations;
  // The rows go to disk as each gear is measured (memory: one gear's points, for any --gears),
  // into "<file>.partial", renamed to the file only when every gear is written.
  const std::filesystem::path file(o.out);
  OutputFiles files(file.has_parent_path() ? file.parent_path() : std::filesystem::path("."));
  std::ofstream stream = files.open(file.filename().string());
  Readings header;
  header.stylus_radius_mm = scenario.stylus_radius_mm;
  header.has_ref_dev = options.reference_deviations;
  header.comments.push_back(
      "made by " +
      provenance_line(make_provenance(o.command_line, scenario.source_path, scenario.source_text)));
  write_readings_header(stream, header);
  SimulatedReadings simulated = simulate_readings(scenario, options, [&](const ReadingRow& row) {
    write_reading_row(stream, row, header.has_ref_dev);
  });
  stream.close();
  if (!stream) {
    throw std::runtime_error("cannot write " + o.out + " (disk full?)");
  }
  files.commit();
  out << "gearmc simulate: " << scenario.name << ", " << o.gears
      << (o.gears == 1 ? " gear" : " gears") << (o.master ? " (nominal master)" : "") << ", "
      << scenario.effects->size() << (scenario.effects->size() == 1 ? " effect" : " effects");
  for (std::size_t e = 0; e < scenario.effects->size(); ++e) {
    out << (e ? ", " : " (") << scenario.effects->effect(e).name()
        << (e + 1 == scenario.effects->size() ? ")" : "");
  }
  out << ": " << simulated.rows << " readings -> " << o.out << "\n";
  if (simulated.skipped > 0) {
    out << "  " << simulated.skipped
        << " planned points not measurable (first: " << simulated.first_skip_reason << ")\n";
  }
  return 0;
}

}  // namespace gearmc
