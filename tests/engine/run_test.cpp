// The Monte-Carlo run: bit-identical statistics for any thread count, --only-gear reproduces a
// gear of the full run, points.csv rows satisfy |C - O| = R and the reported delta, and the
// output folder holds complete files only.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <sys/wait.h>
#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "engine/mc/monte_carlo.h"
#include "tests/support/run_compare.h"
#include "tests/support/run_gearmc.h"

namespace gearmc {
namespace {

Scenario small_reference(int gears) {
  Scenario s = reference_scenario();
  s.gears = gears;
  return s;
}

TEST(MonteCarlo, StatisticsAreBitIdenticalForAnyThreadCount) {
  const MonteCarloRun mc(small_reference(12));
  RunOptions one;
  one.gears = 12;
  one.threads = 1;
  RunOptions all = one;
  all.threads = 0;
  const RunResults a = mc.run(one), b = mc.run(all);
  testing_support::expect_identical_statistics(a, b);
  EXPECT_EQ(a.contacts, 12u * 24 * 2 * 50);
  EXPECT_EQ(a.failed_contacts, 0u);
}

TEST(MonteCarlo, OnlyGearReproducesThatGearOfTheFullRun) {
  const MonteCarloRun mc(small_reference(6));
  std::vector<GearOutcome> full;
  RunOptions options;
  options.gears = 6;
  options.on_gear = [&](const GearOutcome& g) { full.push_back(g); };
  mc.run(options);
  ASSERT_EQ(full.size(), 6u);
  RunOptions alone = options;
  alone.only_gear = 4;
  std::vector<GearOutcome> single;
  alone.on_gear = [&](const GearOutcome& g) { single.push_back(g); };
  mc.run(alone);
  ASSERT_EQ(single.size(), 1u);
  EXPECT_EQ(single[0].gear, 4);
  EXPECT_EQ(single[0].point_delta[0], full[4].point_delta[0]);
  EXPECT_EQ(single[0].point_delta[1], full[4].point_delta[1]);
}

using Result = testing_support::CommandResult;

Result run_cli(const std::string& args) { return testing_support::run_gearmc(args); }

TEST(RunCommand, WritesSummaryHistogramsAndConsistentPoints) {
  namespace fs = std::filesystem;
  const fs::path dir = fs::path(testing::TempDir()) / "gearmc_run_points";
  fs::remove_all(dir);
  const Result r = run_cli("run --gears 2 --points --quiet --out " + dir.string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("flank max L"), std::string::npos);
  const auto summary = nlohmann::json::parse(std::ifstream(dir / "summary.json"));
  EXPECT_EQ(summary["gears"], 2);
  EXPECT_EQ(summary["contacts"], 2 * 24 * 2 * 50);
  EXPECT_EQ(summary["delta_rcomp_um"]["flank_max"]["left"]["n"], 2 * 24);
  EXPECT_TRUE(fs::exists(dir / "histograms.csv"));
  // Pictures and the report (P1 Fig. 5 style histograms, left and right).
  for (const char* svg :
       {"flank_max_left.svg", "flank_max_right.svg", "point_left.svg", "point_right.svg"}) {
    std::ifstream f(dir / svg);
    const std::string text((std::istreambuf_iterator<char>(f)), {});
    EXPECT_NE(text.find("<svg"), std::string::npos) << svg;
    EXPECT_NE(text.find("p99.73"), std::string::npos) << svg;
  }
  std::ifstream report_file(dir / "report.html");
  const std::string report((std::istreambuf_iterator<char>(report_file)), {});
  EXPECT_NE(report.find("P1 Table 2, left"), std::string::npos);  // P1's set-up: comparison
  EXPECT_NE(report.find("does not exceed 4"), std::string::npos);
  EXPECT_NE(report.find("name: p1_reference"), std::string::npos);  // the scenario itself
  EXPECT_EQ(summary["flank_max_best_law"]["left"]["law"].is_string(), true);
  for (const auto& entry : fs::directory_iterator(dir)) {
    EXPECT_EQ(entry.path().string().find(".partial"), std::string::npos) << entry.path();
  }
  // points.csv: |C - O| = R (0.5 mm), delta = |C - E| with E = O - R n, normal_err = (E - C).n
  std::ifstream points(dir / "points.csv");
  std::string line;
  std::getline(points, line);
  EXPECT_EQ(line.rfind("gear,tooth,flank,i,j,px,py,pz,nx,ny,nz,cx,cy,cz,ox,oy,oz,ex,ey,ez,delta_um,"
                       "normal_err_um",
                       0),
            0u);
  int rows = 0;
  while (std::getline(points, line)) {
    std::stringstream ss(line);
    std::string cell;
    std::vector<std::string> cells;
    while (std::getline(ss, cell, ',')) cells.push_back(cell);
    ASSERT_EQ(cells.size(), 23u);
    ASSERT_EQ(cells[22], "ok");
    auto vec = [&](int k) {
      return Eigen::Vector3d(std::stod(cells[k]), std::stod(cells[k + 1]), std::stod(cells[k + 2]));
    };
    const Eigen::Vector3d n = vec(8), c = vec(11), o = vec(14), e = vec(17);
    EXPECT_NEAR((c - o).norm(), 0.5, 1e-9);
    EXPECT_NEAR((e - (o - 0.5 * n)).norm(), 0.0, 1e-12);
    EXPECT_NEAR(std::stod(cells[20]), 1e3 * (c - e).norm(), 1e-9);
    EXPECT_NEAR(std::stod(cells[21]), 1e3 * (e - c).dot(n), 1e-9);
    ++rows;
  }
  EXPECT_EQ(rows, 2 * 24 * 2 * 50);
}

TEST(RunCommand, BadOptionsExitWithTwo) {
  EXPECT_EQ(run_cli("run --gears 0").exit_code, 2);
  EXPECT_EQ(run_cli("run --only-gear 60 --gears 5 --out " + testing::TempDir() + "x").exit_code, 2);
  EXPECT_EQ(run_cli("run /nonexistent.yaml").exit_code, 2);
}

}  // namespace
}  // namespace gearmc
