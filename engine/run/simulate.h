// Simulated CMM readings (`gearmc simulate`, docs/formats.md): the scenario's gears — or a nominal
// master gear — probed along the scenario's plan in its probing order, each point's stylus
// centre at the exact contact moved by the scenario's measurement effects (the "truth" model),
// written as the readings CSV. Gear k is the same gear as `gearmc run --only-gear k`, and the
// effects' random parts come from streams keyed by (seed, gear, point order), so the readings
// are reproducible for any thread count.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <optional>

#include "engine/readings/readings_csv.h"
#include "engine/scenario/scenario.h"

namespace gearmc {

struct SimulateOptions {
  int gears = 1;        // gears 0 .. gears-1, one after the other
  bool master = false;  // a nominal gear (no random deviations)
  // Write ref_dev_um: the real surface's normal deviation at each nominal point (what a
  // calibrated artefact's certificate gives), so that readings show the measurement error.
  bool reference_deviations = false;
};

// The longest text of one readings row: 6 integers and 9 (10 with ref_dev_um) shortest
// round-trip doubles of at most 24 characters, commas and the line end.
inline constexpr std::size_t kMaxReadingsRowBytes = 6 * 11 + 10 * 24 + 16 + 1;

struct SimulatedReadings {
  Readings readings;     // the rows too, unless they were handed to a row sink
  std::size_t rows = 0;  // rows made (kept or handed on)
  // Planned points not written because the stylus could not measure them (edge, collision,
  // no convergence), with the reason of the first one.
  int skipped = 0;
  std::string first_skip_reason;
};

// Points are ordered gear by gear, each gear in the scenario's probing order; the `order`
// column runs over the whole file. Each gear is one measurement: the effects see the point's
// position in that gear's sequence (drift runs over one gear, as in `gearmc run`), and gear k's
// readings equal the run's for gear k.
// The file is bounded before any work: gears × planned points × kMaxReadingsRowBytes must not
// exceed kMaxReadingsBytes, the largest readings file `diagnose` reads (else InputError naming
// --gears, the most gears that fit and the size).
// With `each_row`, every row is handed to it as it is made (gear by gear, in file order) and
// not kept: memory then holds one gear's points whatever the number of gears.
SimulatedReadings simulate_readings(const Scenario& scenario, const SimulateOptions& options,
                                    const std::function<void(const ReadingRow&)>& each_row = {});

}  // namespace gearmc
