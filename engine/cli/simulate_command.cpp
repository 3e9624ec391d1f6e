// `gearmc simulate` (see simulate_command.h).
#include "engine/cli/simulate_command.h"

#include <filesystem>

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
  for (const std::string& w : scenario.warnings) err << "gearmc: warning: " << w << "\n";
  check_output_file(o.out, "--out");
  SimulateOptions options;
  options.gears = o.gears;
  options.master = o.master;
  options.reference_deviations = o.reference_deviations;
  SimulatedReadings simulated = simulate_readings(scenario, options);
  simulated.readings.comments.push_back(
      "made by " +
      provenance_line(make_provenance(o.command_line, scenario.source_path, scenario.source_text)));
  write_readings(o.out, simulated.readings);
  out << "gearmc simulate: " << scenario.name << ", " << o.gears
      << (o.gears == 1 ? " gear" : " gears") << (o.master ? " (nominal master)" : "") << ", "
      << scenario.effects->size() << (scenario.effects->size() == 1 ? " effect" : " effects");
  for (std::size_t e = 0; e < scenario.effects->size(); ++e) {
    out << (e ? ", " : " (") << scenario.effects->effect(e).name()
        << (e + 1 == scenario.effects->size() ? ")" : "");
  }
  out << ": " << simulated.readings.rows.size() << " readings -> " << o.out << "\n";
  if (simulated.skipped > 0) {
    out << "  " << simulated.skipped
        << " planned points not measurable (first: " << simulated.first_skip_reason << ")\n";
  }
  return 0;
}

}  // namespace gearmc
