// Contact solves per second (issue 3 speed goals), single thread:
//  * BM_AnalyticContact: the Newton solver on random-field flanks of P1's reference scenario
//    (8/6 control values, P1's tolerances), P1's 10 x 5 grid on every flank of a gear;
//  * BM_GearDraw: drawing one perturbed gear (the sampler's share of a Monte-Carlo run);
//  * BM_ReferenceRun: the whole reference scenario (50 gears x 2400 points), all threads.
// Run: build/tests/bench/contact_bench --benchmark_repetitions=5
// --benchmark_report_aggregates_only=true
#include <benchmark/benchmark.h>

#include "engine/cli/geometry_command.h"
#include "engine/mc/monte_carlo.h"
#include "engine/probing/contact.h"

namespace gearmc {
namespace {

struct Fixture {
  Scenario scenario = reference_scenario();
  InvoluteGear gear{scenario.gear};
  ToleranceSet tolerances = resolve_scenario_tolerances(scenario, gear);
  GearSampler sampler{gear, tolerances, scenario.deviations, scenario.seed};
};

void BM_AnalyticContact(benchmark::State& state) {
  Fixture f;
  const PerturbedGear g = f.sampler.draw(3);
  const ProbingGridCoordinates grid = probing_grid_coordinates(f.gear, f.scenario.probing.grid);
  const FlankExtent extent{f.gear.form_roll_length_mm(), f.gear.tip_roll_length_mm(), 0.0,
                           f.gear.face_width_mm()};
  std::int64_t solves = 0;
  double sink = 0.0;
  for (auto _ : state) {
    for (int tooth = 1; tooth <= f.gear.teeth(); ++tooth) {
      for (FlankSide side : {FlankSide::kLeft, FlankSide::kRight}) {
        const AnalyticFlank flank(f.gear, tooth, side, g.flank(tooth, side), g.eccentricity_mm);
        for (double z : grid.heights) {
          for (double L : grid.roll_lengths) {
            const FlankPoint fp = f.gear.flank_point(tooth, side, L, z);
            const ContactResult r = solve_contact(flank, extent, fp.point, fp.normal, 0.5, L, z);
            sink += r.delta_um;
            ++solves;
          }
        }
      }
    }
  }
  benchmark::DoNotOptimize(sink);
  state.counters["solves_per_s"] =
      benchmark::Counter(static_cast<double>(solves), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_AnalyticContact)->Unit(benchmark::kMillisecond);

void BM_GearDraw(benchmark::State& state) {
  Fixture f;
  int k = 0;
  for (auto _ : state) benchmark::DoNotOptimize(f.sampler.draw(k++));
}
BENCHMARK(BM_GearDraw)->Unit(benchmark::kMillisecond);

void BM_ReferenceRun(benchmark::State& state) {
  const Scenario scenario = reference_scenario();
  const MonteCarloRun mc(scenario);
  RunOptions options;
  options.gears = scenario.gears;
  std::int64_t contacts = 0;
  for (auto _ : state) {
    const RunResults r = mc.run(options);
    contacts += static_cast<std::int64_t>(r.contacts);
  }
  state.counters["contacts_per_s"] =
      benchmark::Counter(static_cast<double>(contacts), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_ReferenceRun)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
}  // namespace gearmc

BENCHMARK_MAIN();
