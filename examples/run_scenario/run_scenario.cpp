// Runs a scenario from C++ with gearmc's public API (docs/api.md) and reads its statistics:
// the same Monte-Carlo batch as `gearmc run SCENARIO --gears N`, without the command line and
// without output files. Usage: run_scenario [SCENARIO.yaml [GEARS]] (default: the built-in P1
// reference scenario and its own gear count). Prints, per side of the teeth, the δRcomp point
// error's count, mean, standard deviation, maximum and 95 % quantile in µm — the numbers that
// summary.json's "delta_rcomp_um" "point" holds for the same run (tests/package checks it).
#include <charconv>
#include <cstdio>
#include <string>
#include <system_error>

#include "core/input_error.h"
#include "engine/run/monte_carlo.h"
#include "engine/scenario/scenario.h"

int main(int argc, char** argv) {
  try {
    // 1. The scenario: read and validated (unknown keys, ranges, tolerances), or the built-in one.
    gearmc::Scenario scenario =
        argc > 1 ? gearmc::load_scenario_file(argv[1]) : gearmc::reference_scenario();
    for (const std::string& warning : scenario.warnings) {
      std::fprintf(stderr, "warning: %s\n", warning.c_str());
    }
    // 2. Overrides are made on the scenario itself: here the number of gears.
    if (argc > 2) {
      const std::string text = argv[2];
      int gears = 0;
      const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), gears);
      if (error != std::errc() || end != text.data() + text.size() || gears < 1) {
        std::fprintf(stderr, "GEARS: got '%s', expected a whole number of gears >= 1\n",
                     text.c_str());
        return 2;
      }
      scenario.gears = gears;
    }

    // 3. The model (gear, tolerances, probing plan, effects) is built once; run() measures gears
    //    0 .. gears-1 in parallel, each from its own random streams, and merges their statistics
    //    in gear order (bit-identical for any thread count).
    const gearmc::MonteCarloRun batch(scenario);
    gearmc::RunOptions options;
    options.threads = 0;  // all cores
    const gearmc::RunResults results = batch.run(options);

    // 4. The statistics: moments and a histogram per quantity and side ([0] left, [1] right).
    std::printf("%s: %d gears, %llu contacts (%llu failed)\n", scenario.name.c_str(), results.gears,
                static_cast<unsigned long long>(results.contacts),
                static_cast<unsigned long long>(results.failed_contacts));
    const char* side_names[2] = {"left", "right"};
    for (int side = 0; side < 2; ++side) {
      const gearmc::ErrorStatistics& point = results.point[side];
      std::printf("point %s n %llu mean %.17g std %.17g max %.17g p95 %.17g\n", side_names[side],
                  static_cast<unsigned long long>(point.moments.count()), point.moments.mean(),
                  point.moments.stddev(), point.moments.max(), point.histogram.quantile(0.95));
    }
    return 0;
  } catch (const gearmc::InputError& e) {
    std::fprintf(stderr, "%s\n", e.what());
    return 2;
  }
}
