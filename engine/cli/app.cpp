// The gearmc command line: CLI11 parsing, dispatch, and the exit-code contract of
// interface.md (0 ok, 2 bad input; nothing half-written).
#include "engine/cli/app.h"

#include <CLI/CLI.hpp>

#include <iostream>
#include <string>

#include "engine/cli/geometry_command.h"
#include "engine/scenario/input_error.h"
#include "engine/scenario/scenario.h"

namespace gearmc {
namespace {

Scenario load_or_reference(const std::string& path) {
  return path.empty() ? reference_scenario() : load_scenario_file(path);
}

}  // namespace

int run_cli(int argc, const char* const* argv, std::ostream& out, std::ostream& err) {
  CLI::App app{
      "gearmc — Monte-Carlo prediction of CMM measurement accuracy on involute spur gears"};
  app.require_subcommand(1);
  app.set_version_flag("--version", "gearmc 0.1.0");

  std::string geometry_scenario;
  CLI::App* geometry =
      app.add_subcommand("geometry", "Print the nominal geometry and resolved tolerances as JSON");
  geometry->add_option("SCENARIO", geometry_scenario,
                       "Scenario file (default: the built-in reference, P1's gear)");

  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    out << app.help();
    return 0;
  } catch (const CLI::CallForAllHelp& e) {
    out << app.help("", CLI::AppFormatMode::All);
    return 0;
  } catch (const CLI::CallForVersion& e) {
    out << "gearmc 0.1.0\n";
    return 0;
  } catch (const CLI::ParseError& e) {
    err << "gearmc: " << e.what() << "\n"
        << "Run 'gearmc --help' for the commands.\n";
    return 2;
  }

  try {
    if (geometry->parsed()) {
      write_geometry_json(load_or_reference(geometry_scenario), out);
      return 0;
    }
  } catch (const InputError& e) {
    err << "gearmc: " << e.what() << "\n";
    return 2;
  }
  return 0;
}

}  // namespace gearmc
