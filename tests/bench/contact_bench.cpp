// Contact solves per second (the goals in docs/performance.md), single thread:
//  * BM_AnalyticContact: the Newton solver on random-field flanks of P1's reference scenario
//    (8/6 control values, P1's tolerances), P1's 10 x 5 grid on every flank of a gear; the
//    planned points (nominal, the same for every gear) computed once outside the timing and
//    each solve given its planned point's base angle and its flank's stage-1 certificate bound
//    (FlankCurvatureBound, once per flank), as a run does; counters: Newton iterations and
//    certificate restarts per solve;
//  * BM_AnalyticContactOneFlank / BM_MeshContact: the same flank (tooth 1 R of gear 3) probed
//    at the same 40 x 20 grid of planned points (5 % margins) by the analytic solver and by
//    the mesh path (mesh_flank of that flank, MeshFlankProbe with the smoothed contact point,
//    as a scenario's `surfaces:` entry probes it), the mesh at the roll-length and z steps
//    given as arguments (µm). The mesh is built once per step pair, outside the timing. Its
//    counters give the accuracy against the analytic solver (which converges to < 1 nm):
//    max |C_s - C|, max |O_mesh - O| and max |delta_mesh - delta| over all 800 points ("all")
//    and over the points off the deviation model's curvature-jump lines ("interior": the
//    B-spline form deviations are continued linearly beyond the ISO evaluation ranges, whose
//    ends P1's 5 % margins hit exactly: z = 3.94 and 74.95 mm, L = 44.32 mm; there the mesh's
//    vertex normals converge only with order 1);
//  * BM_HelicalContact: the same with the gear made helical (beta 15°, right hand);
//  * BM_InternalContact: the same with the gear made an internal one (its teeth 60, its profile
//    shift and diameter overrides dropped, so that the ring has an involute: P1's normal module,
//    face width, grid and tolerances);
//  * BM_GearDraw: drawing one perturbed gear (the sampler's share of a Monte-Carlo run);
//  * BM_ReferenceRun: the whole reference scenario (50 gears x 2400 points), all threads.
// Run: build/tests/bench/contact_bench --benchmark_repetitions=5
// --benchmark_report_aggregates_only=true
#include <benchmark/benchmark.h>

#include <chrono>
#include <cmath>
#include <map>
#include <memory>
#include <utility>
#include <vector>

#include "engine/contact/contact.h"
#include "engine/contact/contact_certificate.h"
#include "engine/contact/mesh_probe.h"
#include "engine/run/monte_carlo.h"
#include "engine/scenario/scenario.h"
#include "surfaces/flank_mesh.h"

namespace gearmc {
namespace {

// P1's reference scenario, its gear made helical when helix_angle_deg > 0 (right hand).
Scenario reference_with_helix(double helix_angle_deg, bool internal = false) {
  Scenario s = reference_scenario();
  if (internal) {
    s.gear.internal = true;
    s.gear.teeth = 60;
    s.gear.profile_shift = 0.0;
    s.gear.tip_diameter_mm.reset();
    s.gear.root_diameter_mm.reset();
  }
  if (helix_angle_deg > 0.0) {
    s.gear.helix_angle_deg = helix_angle_deg;
    s.gear.hand = Hand::kRight;
  }
  return s;
}

struct Fixture {
  explicit Fixture(double helix_angle_deg = 0.0, bool internal = false)
      : scenario(reference_with_helix(helix_angle_deg, internal)) {}
  Scenario scenario;
  InvoluteGear gear{scenario.gear};
  ToleranceSet tolerances = resolve_scenario_tolerances(scenario, gear);
  GearSampler sampler{gear, tolerances, scenario.deviations, scenario.seed};
};

// The body of BM_AnalyticContact and BM_HelicalContact: `helix_angle_deg` 0 is P1's spur gear.
void analytic_contact(benchmark::State& state, double helix_angle_deg, bool internal = false) {
  Fixture f(helix_angle_deg, internal);
  const PerturbedGear g = f.sampler.draw(3);
  const ProbingGridCoordinates grid = probing_grid_coordinates(f.gear, f.scenario.probing.grid);
  const FlankExtent extent{f.gear.active_roll_length_min_mm(), f.gear.active_roll_length_max_mm(),
                           0.0, f.gear.face_width_mm()};
  // The planned points are nominal, the same for every gear: computed once, outside the timing,
  // as a run's probing plan computes them once (engine/measurement/measurement_model.h). Each solve
  // takes the base point's angle from its planned point, as the run does.
  struct Planned {
    FlankPoint fp;
    double L, z;
  };
  std::vector<Planned> planned;
  for (int tooth = 1; tooth <= f.gear.teeth(); ++tooth) {
    for (FlankSide side : {FlankSide::kLeft, FlankSide::kRight}) {
      for (double z : grid.heights) {
        for (double L : grid.roll_lengths) {
          planned.push_back({f.gear.flank_point(tooth, side, L, z), L, z});
        }
      }
    }
  }
  std::int64_t solves = 0, iterations = 0, restarts = 0;
  double sink = 0.0;
  for (auto _ : state) {
    const Planned* next = planned.data();
    for (int tooth = 1; tooth <= f.gear.teeth(); ++tooth) {
      for (FlankSide side : {FlankSide::kLeft, FlankSide::kRight}) {
        const AnalyticFlank flank(f.gear, tooth, side, g.flank(tooth, side), g.eccentricity_mm);
        // The certificate's stage 1 once per flank, as a run computes it (gear_measurement.cpp).
        const FlankCurvatureBound bound =
            flank_curvature_bound(flank, 0.5, extent.roll_length_min, extent.roll_length_max);
        const std::size_t per_flank = grid.heights.size() * grid.roll_lengths.size();
        for (std::size_t k = 0; k < per_flank; ++k, ++next) {
          const ContactResult r =
              solve_contact(flank, extent, next->fp.point, next->fp.normal, 0.5, next->L, next->z,
                            planned_base_angle(next->fp), &bound);
          sink += r.delta_um;
          iterations += r.iterations;
          restarts += r.restarts;
          ++solves;
        }
      }
    }
  }
  benchmark::DoNotOptimize(sink);
  state.counters["solves_per_s"] =
      benchmark::Counter(static_cast<double>(solves), benchmark::Counter::kIsRate);
  state.counters["iterations_per_solve"] =
      static_cast<double>(iterations) / static_cast<double>(solves);
  state.counters["restarts_per_solve"] =
      static_cast<double>(restarts) / static_cast<double>(solves);
}

void BM_AnalyticContact(benchmark::State& state) { analytic_contact(state, 0.0); }
BENCHMARK(BM_AnalyticContact)->Unit(benchmark::kMillisecond);

// The same with P1's gear made helical (beta 15°, right hand; the same normal module, teeth,
// face width, grid and random fields' tolerances): the goal is at least 0.8 x the spur solves
// per second (issue: helical gears). Its certificate's stage 1 is per point
// (helical_exact_bound), not per flank.
void BM_HelicalContact(benchmark::State& state) { analytic_contact(state, 15.0); }
BENCHMARK(BM_HelicalContact)->Unit(benchmark::kMillisecond);

// P1's gear as a ring gear (internal, 60 teeth, x 0): concave flanks, stage 1 per flank.
void BM_InternalContact(benchmark::State& state) { analytic_contact(state, 0.0, true); }
BENCHMARK(BM_InternalContact)->Unit(benchmark::kMillisecond);

// One flank of gear 3 and the 40 x 20 planned points on it, with the analytic answers.
struct OneFlank {
  static constexpr int kTooth = 1;
  static constexpr FlankSide kSide = FlankSide::kRight;
  static constexpr double kR = 0.5;
  Fixture f;
  PerturbedGear g = f.sampler.draw(3);
  AnalyticFlank flank{f.gear, kTooth, kSide, g.flank(kTooth, kSide), g.eccentricity_mm};
  FlankExtent extent{f.gear.form_roll_length_mm(), f.gear.tip_roll_length_mm(), 0.0,
                     f.gear.face_width_mm()};
  std::vector<PlannedPoint> points;
  std::vector<ContactResult> exact;
  std::vector<bool> interior;  // off the deviation field's curvature-jump lines
  OneFlank() {
    ProbingGridSpec grid;
    grid.points_along_profile = 40;
    grid.sections_across_face = 20;
    points = plan_flank(f.gear, grid, kTooth, kSide);
    const EvaluationRanges ranges = f.sampler.ranges();
    for (const PlannedPoint& p : points) {
      exact.push_back(
          solve_contact(flank, extent, p.point, p.normal, kR, p.roll_length_mm, p.z_mm));
      auto near = [](double a, double b) { return std::abs(a - b) < 0.01; };
      interior.push_back(!near(p.z_mm, ranges.helix_start_mm) &&
                         !near(p.z_mm, ranges.helix_end_mm) &&
                         !near(p.roll_length_mm, ranges.profile_start_mm) &&
                         !near(p.roll_length_mm, ranges.profile_end_mm));
    }
  }
};

const OneFlank& one_flank() {
  static const OneFlank instance;
  return instance;
}

void BM_AnalyticContactOneFlank(benchmark::State& state) {
  const OneFlank& c = one_flank();
  std::int64_t solves = 0;
  double sink = 0.0;
  for (auto _ : state) {
    for (const PlannedPoint& p : c.points) {
      const ContactResult r = solve_contact(c.flank, c.extent, p.point, p.normal, OneFlank::kR,
                                            p.roll_length_mm, p.z_mm);
      sink += r.delta_um;
      ++solves;
    }
  }
  benchmark::DoNotOptimize(sink);
  state.counters["solves_per_s"] =
      benchmark::Counter(static_cast<double>(solves), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_AnalyticContactOneFlank)->Unit(benchmark::kMillisecond);

// The mesh of the flank at (roll-length step, z step) in µm, with its build time; built once.
struct MeshCase {
  std::unique_ptr<MeshFlankProbe> probe;
  double build_s = 0.0;
};
const MeshCase& mesh_case(int dL_um, int dz_um) {
  static std::map<std::pair<int, int>, MeshCase> cache;
  MeshCase& m = cache[{dL_um, dz_um}];
  if (!m.probe) {
    const OneFlank& c = one_flank();
    const auto start = std::chrono::steady_clock::now();
    const TriangleMesh mesh =
        mesh_flank(c.flank, whole_flank_spec(c.f.gear, 1e-3 * dL_um, 1e-3 * dz_um));
    m.probe = std::make_unique<MeshFlankProbe>(c.f.gear, OneFlank::kTooth, OneFlank::kSide, mesh,
                                               MeshContactPoint::kSmoothed);
    m.build_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  }
  return m;
}

void BM_MeshContact(benchmark::State& state) {
  const OneFlank& c = one_flank();
  const MeshCase& m = mesh_case(static_cast<int>(state.range(0)), static_cast<int>(state.range(1)));
  std::int64_t solves = 0;
  double sink = 0.0;
  for (auto _ : state) {
    for (const PlannedPoint& p : c.points) {
      const ContactResult r = m.probe->probe(p.point, p.normal, OneFlank::kR);
      sink += r.delta_um;
      ++solves;
    }
  }
  benchmark::DoNotOptimize(sink);
  // Accuracy against the analytic solver, nm.
  double C_all = 0, O_all = 0, d_all = 0, C_in = 0, O_in = 0, d_in = 0;
  int failed = 0;
  for (std::size_t k = 0; k < c.points.size(); ++k) {
    const ContactResult r = m.probe->probe(c.points[k].point, c.points[k].normal, OneFlank::kR);
    if (r.status != ContactResult::Status::kOk) {
      ++failed;
      continue;
    }
    const double dC = 1e6 * (r.contact - c.exact[k].contact).norm();
    const double dO = 1e6 * (r.centre - c.exact[k].centre).norm();
    const double dd = 1e3 * std::abs(r.delta_um - c.exact[k].delta_um);
    C_all = std::max(C_all, dC), O_all = std::max(O_all, dO), d_all = std::max(d_all, dd);
    if (c.interior[k])
      C_in = std::max(C_in, dC), O_in = std::max(O_in, dO), d_in = std::max(d_in, dd);
  }
  state.counters["solves_per_s"] =
      benchmark::Counter(static_cast<double>(solves), benchmark::Counter::kIsRate);
  state.counters["triangles"] = m.probe->triangle_count();
  state.counters["build_s"] = m.build_s;
  state.counters["failed"] = failed;
  state.counters["dC_all_nm"] = C_all;
  state.counters["dO_all_nm"] = O_all;
  state.counters["ddelta_all_nm"] = d_all;
  state.counters["dC_interior_nm"] = C_in;
  state.counters["dO_interior_nm"] = O_in;
  state.counters["ddelta_interior_nm"] = d_in;
}
// (roll-length step, z step) in µm: the test resolution of
// tests/engine/contact/mesh_surface_test.cpp, two finer isotropic ones, and the anisotropic one
// whose interior error reaches 1 nm (the involute's curvature across the profile, up to 1/L,
// dominates the chord error; along z only the helix form bends the flank, so z can be sampled 10
// times more coarsely).
BENCHMARK(BM_MeshContact)
    ->Args({250, 250})
    ->Args({100, 100})
    ->Args({50, 50})
    ->Args({20, 200})
    ->Unit(benchmark::kMillisecond);

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
