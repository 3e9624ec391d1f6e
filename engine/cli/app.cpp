// The gearmc command line: CLI11 parsing, dispatch, and the exit-code contract of
// docs/formats.md (0 ok, 2 bad input; nothing half-written).
#include "engine/cli/app.h"

#include <CLI/CLI.hpp>

#include <algorithm>
#include <iostream>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/check.h"
#include "core/input_error.h"
#include "core/provenance.h"
#include "core/ranks.h"
#include "core/version.h"
#include "engine/cli/check_command.h"
#include "engine/cli/diagnose_command.h"
#include "engine/cli/export_mesh_command.h"
#include "engine/cli/export_plan_command.h"
#include "engine/cli/geometry_command.h"
#include "engine/cli/run_command.h"
#include "engine/cli/simulate_command.h"
#include "engine/cli/sweep_command.h"
#include "engine/cli/uncertainty_command.h"
#include "engine/scenario/scenario.h"

namespace gearmc {
namespace {

Scenario load_or_reference(const std::string& path) {
  return path.empty() ? reference_scenario() : load_scenario_file(path);
}

// The subcommand CLI11 was parsing when it stopped (the last one parsed), or null.
const CLI::App* parsed_subcommand(const CLI::App& app) {
  for (const CLI::App* sub : app.get_subcommands({})) {
    if (sub->parsed()) return sub;
  }
  return nullptr;
}

std::string help_command(const CLI::App& app) {
  const CLI::App* sub = parsed_subcommand(app);
  return sub ? "gearmc " + sub->get_name() + " --help" : "gearmc --help";
}

std::string help_of(const CLI::App& app, int, const char* const*) {
  const CLI::App* sub = parsed_subcommand(app);
  return sub ? sub->help() : app.help();
}

// "; did you mean 'X'?" for a mistyped subcommand or option, else "".
std::string suggestion(const CLI::App& app, int argc, const char* const* argv) {
  std::vector<std::string> commands;
  for (const CLI::App* sub : app.get_subcommands({})) commands.push_back(sub->get_name());
  const CLI::App* sub = parsed_subcommand(app);
  if (sub == nullptr) {
    // The first word that is not an option should have been a command.
    for (int i = 1; i < argc; ++i) {
      const std::string word = argv[i];
      if (word.rfind("-", 0) == 0) continue;
      const std::string hint = did_you_mean(word, commands);
      return hint.empty() ? "" : "; did you mean '" + hint + "'?";
    }
    return "";
  }
  std::vector<std::string> options;
  for (const CLI::Option* o : sub->get_options()) {
    for (const std::string& name : o->get_lnames()) options.push_back("--" + name);
  }
  for (int i = 1; i < argc; ++i) {
    std::string word = argv[i];
    if (word.rfind("--", 0) != 0) continue;
    word = word.substr(0, word.find('='));
    if (std::find(options.begin(), options.end(), word) != options.end()) continue;
    const std::string hint = did_you_mean(word, options);
    if (!hint.empty()) return "; did you mean '" + hint + "'?";
  }
  return "";
}

}  // namespace

int run_cli(int argc, const char* const* argv, std::ostream& out, std::ostream& err) {
  CLI::App app{"gearmc — Monte-Carlo prediction of CMM measurement accuracy on involute spur gears",
               "gearmc"};
  app.require_subcommand(0, 1);
  app.set_version_flag("--version", gearmc_version_line());
  app.footer(
      "Examples:\n"
      "  gearmc run                                   P1's reference gear, 50 gears\n"
      "  gearmc run scenarios/p1_iso_class8.yaml --gears 500 --seed 7\n"
      "  gearmc diagnose --model model.yaml --measured readings.csv --out results/diag\n"
      "  gearmc uncertainty scenarios/uncertainty/mass_calibration.yaml   GUM and Monte Carlo\n"
      "  gearmc check scenarios/p1_claims.yaml        decide the scenario's accuracy claims\n"
      "Run 'gearmc COMMAND --help' for a command's options.");
  app.add_subcommand("help", "Print this help");

  std::string geometry_scenario;
  CLI::App* geometry =
      app.add_subcommand("geometry", "Print the nominal geometry and resolved tolerances as JSON");
  geometry->footer("Example:\n  gearmc geometry scenarios/p1_iso_class8.yaml");
  geometry->add_option("SCENARIO", geometry_scenario,
                       "Scenario file (default: the built-in reference, P1's gear)");

  RunCommandOptions run_options;
  CLI::App* run = app.add_subcommand(
      "run", "Monte-Carlo batch: perturbed gears, probing grid, contact, δRcomp statistics");
  run->add_option("SCENARIO", run_options.scenario_path,
                  "Scenario file (default: the built-in reference, P1's gear)");
  run->footer(
      "Example:\n  gearmc run scenarios/p1_iso_class8.yaml --gears 500 --seed 7 --out results/c8");
  run->add_option("--out", run_options.out_dir, "Output folder (default results/<scenario>)");
  run->add_option("--gears", run_options.overrides.gears, "Number of gears (overrides run.gears)")
      ->check(CLI::Range(1, 100000000));
  run->add_option("--seed", run_options.overrides.seed, "Random seed (overrides seed)");
  run->add_option("--threads", run_options.threads, "Worker threads (default: all cores)")
      ->check(CLI::Range(1, 4096));
  run->add_flag("--points", run_options.points, "Also write points.csv, one row per point");
  run->add_option("--plan", run_options.plan_path,
                  "A DMIS program (.dmi) whose FEAT/POINT nominals and vectors are the probing "
                  "plan, instead of the scenario's grid");
  run->add_option("--only-gear", run_options.only_gear,
                  "Re-run gear K (0-based) alone, exactly as in the full run (outputs in "
                  "results/<name>/gear_K unless --out)");
  run->add_flag("--quiet", run_options.quiet, "No progress bar");
  run->add_flag("--force", run_options.force,
                "With --points: write points.csv even when it would exceed 4 GB");

  ExportMeshOptions mesh_options;
  CLI::App* export_mesh = app.add_subcommand(
      "export-mesh", "Write perturbed gear K as a triangle mesh (STL, PLY, OBJ or OFF)");
  export_mesh->footer("Example:\n  gearmc export-mesh --gear 17 --out gear17.stl");
  export_mesh->add_option("SCENARIO", mesh_options.scenario_path,
                          "Scenario file (default: the built-in reference)");
  export_mesh->add_option("--gear", mesh_options.gear, "Gear index K (0-based, as in run)");
  export_mesh->add_option("--out", mesh_options.out, "Output file: .stl, .ply, .obj or .off")
      ->required();
  export_mesh
      ->add_option("--profile-samples", mesh_options.profile_samples,
                   "Points along each flank's profile (default 25)")
      ->check(CLI::Range(2, 2000));
  export_mesh
      ->add_option("--face-samples", mesh_options.face_samples,
                   "Sections across the face width (default 40)")
      ->check(CLI::Range(2, 20000));

  ExportPlanOptions plan_options;
  CLI::App* export_plan = app.add_subcommand(
      "export-plan", "Write the probing plan as a DMIS program (to run it on a real CMM)");
  export_plan->footer(
      "Example:\n  gearmc export-plan scenarios/p1_reference.yaml --format dmis --out plan.dmi");
  export_plan->add_option("SCENARIO", plan_options.scenario_path,
                          "Scenario file (default: the built-in reference)");
  export_plan->add_option("--format", plan_options.format, "Program format: dmis (default)");
  export_plan->add_option("--out", plan_options.out, "Program file to write")->required();

  SimulateCommandOptions simulate_options;
  CLI::App* simulate = app.add_subcommand(
      "simulate", "Simulated CMM readings of the scenario's gears with its effects (readings CSV)");
  simulate->footer(
      "Example:\n  gearmc simulate scenarios/diagnose/lobing_truth.yaml --master --out lobing.csv");
  simulate->add_option("SCENARIO", simulate_options.scenario_path,
                       "Scenario file (default: the built-in reference)");
  simulate->add_option("--out", simulate_options.out, "Readings file to write (.csv)")->required();
  simulate->add_option("--gears", simulate_options.gears, "Gears 0 .. N-1 (default 1)")
      ->check(CLI::Range(1, 100000));
  simulate->add_option("--seed", simulate_options.overrides.seed, "Random seed (overrides seed)");
  simulate->add_option("--plan", simulate_options.plan_path,
                       "A DMIS program (.dmi) whose FEAT/POINT nominals and vectors are the "
                       "probing plan, instead of the scenario's grid");
  simulate->add_flag("--master", simulate_options.master,
                     "Measure a nominal master gear (no random deviations)");
  simulate->add_flag("--reference-deviations", simulate_options.reference_deviations,
                     "Add ref_dev_um: the surface's true normal deviation at each point");

  DiagnoseCommandOptions diagnose_options;
  CLI::App* diagnose = app.add_subcommand(
      "diagnose",
      "Find where model and measurement disagree, name the missing effect, fit it, write the "
      "extended scenario and a report");
  diagnose->footer(
      "Example:\n  gearmc diagnose --model scenarios/diagnose/lobing_model.yaml --measured "
      "lobing.csv --out results/diagnose_lobing");
  diagnose->add_option("--model", diagnose_options.model_path, "Model scenario file")->required();
  diagnose
      ->add_option("--measured", diagnose_options.measured_paths,
                   "Readings CSV, or the DMIS results (.dmo) of export-plan's program, or a "
                   "CMM point table (with --columns); several files: repeated measurements of "
                   "the gear, read together")
      ->required();
  diagnose->add_option("--columns", diagnose_options.columns_path,
                       "Column mapping (YAML) of a CMM point table given as --measured");
  diagnose
      ->add_option("--out", diagnose_options.out_dir,
                   "Output folder for diagnosis.json, fitted.yaml, report.html")
      ->required();
  diagnose->add_option("--seed", diagnose_options.null_seed,
                       "Seed of the null simulations (default 1)");
  diagnose
      ->add_option("--null-replicates", diagnose_options.null_replicates,
                   "Null simulations K (default 200, at least 2/alpha - 1, at most 10000; 0: "
                   "tables instead)")
      ->check(CLI::Range(0, 10000));
  diagnose->add_option("--candidates", diagnose_options.candidates,
                       "Comma-separated library effects the diagnosis may name (default: all)");
  diagnose
      ->add_option("--workpiece", diagnose_options.workpiece,
                   "master (default: nominal or calibrated, every gap is the machine's) or "
                   "production (the gear's own flank deviations are fitted in every model)")
      ->check(CLI::IsMember({"master", "production"}));
  diagnose->add_option(
      "--turned-by", diagnose_options.turned_by,
      "With --workpiece production: every gear/run of the readings is the same gear, turned on "
      "the table by K teeth in each (one K per gear or run, e.g. 0,3: the plan's tooth t holds "
      "the gear's tooth t + K); the part's deviations move with the gear, the machine's stay");
  diagnose->add_flag("--model-gears", diagnose_options.model_gears,
                     "Predict on the model's perturbed gears (same seed) instead of its nominal "
                     "master (only for readings simulated from the same gear model)");

  UncertaintyCommandOptions uncertainty_options;
  CLI::App* uncertainty = app.add_subcommand(
      "uncertainty",
      "GUM (JCGM 100) and adaptive Monte Carlo (JCGM 101) side by side for a measurement model");
  uncertainty->footer(
      "Example:\n  gearmc uncertainty scenarios/uncertainty/mass_calibration.yaml --out "
      "results/mass");
  uncertainty->add_option("MODEL", uncertainty_options.model_path, "Model file (YAML)")->required();
  uncertainty->add_option("--out", uncertainty_options.out_dir,
                          "Output folder (default results/<model name>)");
  uncertainty->add_option("--trials", uncertainty_options.trials,
                          "Monte-Carlo trials M, or 'adaptive' (overrides settings.trials)");
  uncertainty->add_option("--seed", uncertainty_options.seed, "Random seed (overrides seed)");
  uncertainty
      ->add_option("--threads", uncertainty_options.threads, "Worker threads (default: all cores)")
      ->check(CLI::Range(1, 4096));
  uncertainty->add_flag("--quiet", uncertainty_options.quiet, "No progress line");

  SweepCommandOptions sweep_options;
  CLI::App* sweep = app.add_subcommand(
      "sweep", "Grid of scenario variants: the statistic of each run against each varied key");
  sweep->footer(
      "Example:\n  gearmc sweep scenarios/p1_reference.yaml --vary stylus.radius_mm=0.3,0.5,1,1.5 "
      "--vary probing.points_along_profile=5,10,20");
  sweep->add_option("SCENARIO", sweep_options.scenario_path, "Scenario file")->required();
  sweep->add_option("--vary", sweep_options.vary, "KEY=V1,V2,… (repeat for more keys)")
      ->required()
      ->allow_extra_args(false)
      ->take_all();
  sweep->add_option("--statistic", sweep_options.statistic,
                    "delta_rcomp.<point|flank_max|flank_mean>.<n|mean|std|min|max|p95|p99_73> "
                    "(default delta_rcomp.flank_max.p99_73), or parameters.<symbol>.<bias|u|U|"
                    "U_over_T|Q_MP|false_accept|false_reject> with evaluation:");
  sweep
      ->add_option("--confidence", sweep_options.confidence,
                   "Confidence of each point's band (default 0.95)")
      ->check(CLI::Range(0.5, 0.99));
  sweep->add_option("--at-most", sweep_options.at_most,
                    "Limit: each point meets, misses or is undecided against statistic ≤ V");
  sweep->add_option("--at-least", sweep_options.at_least,
                    "Limit: statistic ≥ V (with --at-most: a two-sided limit)");
  sweep->add_option("--out", sweep_options.out_dir,
                    "Output folder (default results/<scenario>_sweep)");
  sweep
      ->add_option("--gears", sweep_options.overrides.gears,
                   "Gears per variant (overrides run.gears)")
      ->check(CLI::Range(1, 100000000));
  sweep->add_option("--seed", sweep_options.overrides.seed, "Random seed (overrides seed)");
  sweep->add_option("--threads", sweep_options.threads, "Worker threads (default: all cores)")
      ->check(CLI::Range(1, 4096));
  sweep->add_flag("--quiet", sweep_options.quiet, "No progress line");

  run_options.command_line = command_line_text(argc, argv);
  sweep_options.command_line = run_options.command_line;

  CheckCommandOptions check_options;
  CLI::App* check = app.add_subcommand(
      "check", "Decide the scenario's accuracy claims (claims:) with confidence bounds");
  check->footer(
      "Example:\n  gearmc check scenarios/p1_claims.yaml --junit results/claims.xml\n"
      "Exit 0: every claim holds; 1: a claim fails; 3: none fails, some undecided at --max-gears;\n"
      "2: bad input; 4: internal error.");
  check->add_option("SCENARIO", check_options.scenario_path, "Scenario file with claims:")
      ->required();
  check->add_option("--out", check_options.out_dir,
                    "Output folder for check.json and report.html (default "
                    "results/<scenario>/check)");
  check
      ->add_option("--max-gears", check_options.max_gears,
                   "Gears at most (default 20000); looks after 256, 512, 1024, …")
      ->check(CLI::Range(1, 100000000));
  check->add_option("--seed", check_options.overrides.seed, "Random seed (overrides seed)");
  check->add_option("--threads", check_options.threads, "Worker threads (default: all cores)")
      ->check(CLI::Range(1, 4096));
  check->add_option("--junit", check_options.junit_path,
                    "Also write the verdicts as JUnit XML (one test case per claim)");
  check->add_flag("--quiet", check_options.quiet, "No progress line");

  check_options.command_line = run_options.command_line;
  uncertainty_options.command_line = run_options.command_line;
  simulate_options.command_line = run_options.command_line;
  plan_options.command_line = run_options.command_line;
  diagnose_options.command_line = run_options.command_line;
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    out << help_of(app, argc, argv);
    return 0;
  } catch (const CLI::CallForAllHelp& e) {
    out << app.help("", CLI::AppFormatMode::All);
    return 0;
  } catch (const CLI::CallForVersion& e) {
    out << gearmc_version_line() << "\n";
    return 0;
  } catch (const CLI::ParseError& e) {
    err << "gearmc: " << e.what() << suggestion(app, argc, argv) << "\n"
        << "Run '" << help_command(app) << "' for the options.\n";
    return 2;
  }
  if (app.get_subcommands().empty() || app.got_subcommand("help")) {
    // The top-level help itself (App::help() would show the `help` subcommand's).
    out << app.get_formatter()->make_help(&app, "gearmc", CLI::AppFormatMode::Normal);
    return 0;
  }

  // Under mpirun, the commands without Monte-Carlo work run on rank 0 alone.
  const bool distributed =
      run->parsed() || uncertainty->parsed() || sweep->parsed() || check->parsed();
  if (!distributed && !Ranks::world().is_root()) return 0;
  try {
    if (geometry->parsed()) {
      const Scenario scenario = load_or_reference(geometry_scenario);
      for (const std::string& w : scenario.warnings) err << "gearmc: warning: " << w << "\n";
      write_geometry_json(scenario, out);
      return 0;
    }
    if (run->parsed()) return run_command(run_options, out, err);
    if (export_mesh->parsed()) return export_mesh_command(mesh_options, out, err);
    if (export_plan->parsed()) return export_plan_command(plan_options, out, err);
    if (simulate->parsed()) return simulate_command(simulate_options, out, err);
    if (diagnose->parsed()) return diagnose_command(diagnose_options, out, err);
    if (uncertainty->parsed()) return uncertainty_command(uncertainty_options, out, err);
    if (sweep->parsed()) return sweep_command(sweep_options, out, err);
    if (check->parsed()) return check_command(check_options, out, err);
  } catch (const InputError& e) {
    err << "gearmc: " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {  // a bug or an I/O failure, not bad input
    err << "gearmc: internal error: " << e.what() << "\n";
    return kInternalErrorExit;
  }
  return 0;
}

}  // namespace gearmc
