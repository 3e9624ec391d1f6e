// `gearmc diagnose --model SCENARIO --measured READINGS.csv --out DIR [--seed S]
// [--null-replicates K] [--model-gears]` (docs/diagnosis.md): compares the model scenario's
// prediction with measured readings, names the missing effect (engine/apps/diagnose), and writes
// diagnosis.json, fitted.yaml (the model plus the fitted effect) and report.html into DIR — all
// three under temporary names, renamed when all are complete. Bad input (scenario, readings CSV,
// output folder) throws InputError before anything is written (exit 2); whatever the diagnosis
// finds, the exit code is 0.
#pragma once

#include <cstdint>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

namespace gearmc {

struct DiagnoseCommandOptions {
  std::string model_path;  // --model SCENARIO (required)
  // --measured READINGS.csv … (required): one file, or several measurements of the same gear
  // (repeated runs) read together — each file's gears follow the previous file's.
  std::vector<std::string> measured_paths;
  std::string columns_path;  // --columns MAPPING.yaml: --measured is a CMM point table
  std::string out_dir;       // --out DIR (required; created if missing)
  std::optional<std::uint64_t> null_seed;  // --seed: of the null simulations (default 1)
  std::optional<int> null_replicates;      // K (default 200; 0: no null simulation)
  bool model_gears = false;  // predict on the model's perturbed gears, not its nominal master
  // --candidates a,b,…: the library effects the selection may name (default: all of them)
  std::string candidates;
  // --workpiece master|production: a production gear's own flank deviations are part of every
  // model (engine/apps/diagnose/part_model.h)
  std::string workpiece = "master";
  // --turned-by K,K,…: with production, every gear/run of the readings is the same gear, in
  // set-up g turned on the table by K_g teeth (one per gear index, in order)
  std::string turned_by;
  std::string command_line;  // as typed, for the outputs' provenance
};

// Runs the command and prints a 3–5 line summary and the report's path to `out`; returns the
// exit code. Throws InputError for bad input.
int diagnose_command(const DiagnoseCommandOptions& options, std::ostream& out, std::ostream& err);

}  // namespace gearmc
