// Tests of `gearmc simulate` (engine/run/simulate): on a nominal master gear the readings are
// exactly what the effects say (no effect: zero deviation; lobing: −p(φ); drift: linear in
// the order), the probing order follows the scenario, readings are reproducible, and the CLI
// writes a file the readings reader accepts.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <sstream>

#include "engine/effects/effect_config.h"
#include "engine/run/monte_carlo.h"
#include "engine/run/simulate.h"
#include "tests/support/run_gearmc.h"
#include "tests/support/temp_paths.h"

using ::gearmc::testing_support::fresh_temp_path;

namespace gearmc {
namespace {

Scenario with_effects(const std::string& effects_yaml) {
  Scenario s = reference_scenario();
  s.effects = std::make_shared<const EffectChain>(
      parse_effects(parse_yaml_document(effects_yaml, "effects.yaml")));
  return s;
}

SimulateOptions master() {
  SimulateOptions o;
  o.master = true;
  return o;
}

TEST(Simulate, NominalMasterWithoutEffectsReadsZeroDeviation) {
  // Nominal flank, exact contact: the stylus centre is p + R n, so e = 0 up to the contact
  // solver's tolerance (< 1 nm in C; 1e-6 µm asserted as in tests/engine/contact/contact_test.cpp).
  const SimulatedReadings r = simulate_readings(reference_scenario(), master());
  ASSERT_EQ(r.readings.rows.size(), 2400u);  // 24 teeth x 2 flanks x 10 x 5
  EXPECT_EQ(r.skipped, 0);
  for (const ReadingRow& row : r.readings.rows) {
    EXPECT_NEAR(measured_deviation_um(row, 0.5), 0.0, 1e-6);
  }
}

TEST(Simulate, LobingReadsMinusThePretravelAtTheApproachAzimuth) {
  const SimulatedReadings r = simulate_readings(with_effects(R"(
probe_lobing:
  pretravel_um: 1.0
  harmonics: [{order: 3, amplitude_um: 1.5, phase_deg: 30}]
)"),
                                                master());
  for (const ReadingRow& row : r.readings.rows) {
    const double phi = std::atan2(-row.n.y(), -row.n.x());
    const double p = 1.0 + 1.5 * std::cos(3.0 * (phi - std::numbers::pi / 6.0));
    EXPECT_NEAR(measured_deviation_um(row, 0.5), -p, 1e-6);
  }
}

TEST(Simulate, DriftFollowsTheProbingOrderAndOrderIsTheScenarios) {
  for (const char* order : {"tooth_by_tooth", "side_by_side"}) {
    Scenario s = with_effects("drift: {x_um: 2}\n");
    s.probing.order = std::string(order) == "tooth_by_tooth" ? ProbingOrder::kToothByTooth
                                                             : ProbingOrder::kSideBySide;
    const SimulatedReadings r = simulate_readings(s, master());
    const auto& rows = r.readings.rows;
    ASSERT_EQ(rows.size(), 2400u);
    // tooth_by_tooth: point 50 is tooth 1's first R point; side_by_side: tooth 2's first L one.
    if (s.probing.order == ProbingOrder::kToothByTooth) {
      EXPECT_EQ(rows[50].tooth, 1);
      EXPECT_EQ(rows[50].side, FlankSide::kRight);
    } else {
      EXPECT_EQ(rows[50].tooth, 2);
      EXPECT_EQ(rows[50].side, FlankSide::kLeft);
    }
    for (const ReadingRow& row : rows) {
      EXPECT_EQ(row.order, &row - rows.data());
      EXPECT_NEAR(measured_deviation_um(row, 0.5), 2.0 * row.order / 2399.0 * row.n.x(), 1e-6);
    }
  }
}

TEST(Simulate, ReferenceDeviationsExplainTheReadingsOfARandomGear) {
  // A perturbed gear with no effects: the reading minus the surface's own deviation at p is the
  // radius-compensation error along n, bounded by δRcomp (P1-size: well under 10 µm), while
  // the deviations themselves include the thickness (rack shift, −110 … −210 µm · sin α).
  SimulateOptions o;
  o.reference_deviations = true;
  const SimulatedReadings r = simulate_readings(reference_scenario(), o);
  double largest_ref = 0.0;
  for (const ReadingRow& row : r.readings.rows) {
    ASSERT_TRUE(row.ref_dev_um);
    EXPECT_LT(std::abs(measured_deviation_um(row, 0.5)), 10.0);
    largest_ref = std::max(largest_ref, std::abs(*row.ref_dev_um));
  }
  EXPECT_GT(largest_ref, 30.0);
}

TEST(RunWithEffects, TotalErrorAndBudgetAddUpAndAreThreadIndependent) {
  // A stylus-radius error of 0.5 µm shifts every reading by −0.5 µm (effects.h), noise adds
  // σ 0.3 µm: the total error's mean is the δRcomp normal error's mean − 0.5, the budget holds
  // one line per source, and one thread gives the same numbers as two.
  const Scenario s = with_effects("stylus_radius: {error_um: 0.5}\nnoise: {sigma_um: 0.3}\n");
  const MonteCarloRun run(s);
  RunOptions options;
  options.end_gear = 4;
  options.threads = 1;
  const RunResults one = run.run(options);
  options.threads = 2;
  const RunResults two = run.run(options);
  ASSERT_EQ(one.effects.contribution.size(), 2u);
  EXPECT_NEAR(one.effects.contribution[0].mean(), -0.5, 1e-12);  // stylus_radius
  EXPECT_NEAR(one.effects.contribution[1].stddev(), 0.3, 0.01);  // noise, 9600 points
  const double total_mean =
      0.5 * (one.effects.total_signed[0].mean() + one.effects.total_signed[1].mean());
  EXPECT_NEAR(total_mean,
              one.effects.radius_compensation.mean() - 0.5 + one.effects.contribution[1].mean(),
              1e-9);
  for (int side = 0; side < 2; ++side) {
    EXPECT_EQ(one.effects.total_signed[side].mean(), two.effects.total_signed[side].mean());
    EXPECT_EQ(one.effects.total_signed[side].max(), two.effects.total_signed[side].max());
    EXPECT_TRUE(one.total_abs[side].histogram == two.total_abs[side].histogram);
  }
}

TEST(SimulateCli, WritesReproducibleReadingsTheReaderAccepts) {
  namespace fs = std::filesystem;
  const fs::path dir = fresh_temp_path("simulate_cli");
  fs::create_directories(dir);
  const fs::path scenario = dir / "lobing.yaml";
  {
    std::ifstream in(fs::path(GEARMC_SOURCE_DIR) / "scenarios" / "p1_reference.yaml");
    std::stringstream text;
    text << in.rdbuf();
    std::ofstream(scenario) << text.str()
                            << "effects:\n  probe_lobing:\n    harmonics: [{order: 6, "
                               "amplitude_um: 0.75}]\n  noise: {sigma_um: 0.3}\n";
  }
  std::string texts[2];
  for (int run = 0; run < 2; ++run) {
    const fs::path out = dir / ("r" + std::to_string(run) + ".csv");
    const auto result = testing_support::run_gearmc("simulate " + scenario.string() +
                                                    " --gears 2 --out " + out.string());
    ASSERT_EQ(result.exit_code, 0) << result.err;
    EXPECT_NE(result.out.find("4800 readings"), std::string::npos) << result.out;
    const Readings readings = read_readings(out.string());
    EXPECT_EQ(readings.rows.size(), 4800u);
    std::ifstream in(out);
    std::stringstream s;
    s << in.rdbuf();
    texts[run] = s.str();
  }
  // Identical but for the line that says when and by which command line each was made.
  for (std::string& t : texts) {
    const std::size_t made = t.find("# made by gearmc 0.1.0");
    ASSERT_NE(made, std::string::npos);
    t.erase(made, t.find('\n', made) + 1 - made);
  }
  EXPECT_EQ(texts[0], texts[1]);
  // The file streamed gear by gear is the text of the rows made in memory (format_readings).
  {
    SimulateOptions o;
    o.gears = 2;
    Readings whole = simulate_readings(load_scenario_file(scenario.string()), o).readings;
    std::string streamed = texts[0];
    EXPECT_EQ(streamed, format_readings(whole));
  }
  // A file beyond what diagnose reads is refused before any work: P1's plan has 2400 points, a
  // row at most 323 bytes, so 2^30 / (2400 × 323) = 1385.2 → at most 1385 gears.
  const auto big = testing_support::run_gearmc(
      "simulate " + scenario.string() + " --gears 100000 --out " + (dir / "big.csv").string());
  EXPECT_EQ(big.exit_code, 2) << big.err;
  EXPECT_NE(big.err.find("--gears: got '100000', expected at most 1385 gears of this plan (2400 "
                         "points each"),
            std::string::npos)
      << big.err;
  EXPECT_FALSE(fs::exists(dir / "big.csv"));
  EXPECT_FALSE(fs::exists(dir / "big.csv.partial"));
  const auto bad = testing_support::run_gearmc("simulate " + (dir / "missing.yaml").string() +
                                               " --out " + (dir / "x.csv").string());
  EXPECT_EQ(bad.exit_code, 2);
  EXPECT_FALSE(fs::exists(dir / "x.csv"));
  fs::remove_all(dir);
}

}  // namespace
}  // namespace gearmc
