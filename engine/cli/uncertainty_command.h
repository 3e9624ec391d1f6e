// `gearmc uncertainty MODEL.yaml`: GUM (JCGM 100) and adaptive Monte Carlo (JCGM 101) side by
// side for a measurement model file (docs/uncertainty.md); writes uncertainty.json and
// report.html into the output folder, all or nothing, and prints the comparison table.
#pragma once

#include <cstdint>
#include <optional>
#include <ostream>
#include <string>

namespace gearmc {

struct UncertaintyCommandOptions {
  std::string model_path;
  std::string out_dir;  // default results/<model name>
  std::string trials;   // "" (the model's setting), "adaptive" or a number
  std::optional<std::uint64_t> seed;
  int threads = 0;
  bool quiet = false;
  std::string command_line;
};

// Exit code 0; throws InputError for bad input (the caller prints it, exit 2); 130 when
// interrupted (nothing written).
int uncertainty_command(const UncertaintyCommandOptions& options, std::ostream& out,
                        std::ostream& err);

}  // namespace gearmc
