// The Monte-Carlo run: bit-identical statistics for any thread count, --only-gear reproduces a
// gear of the full run, points.csv rows satisfy |C - O| = R and the reported delta, and the
// output folder holds complete files only; merging a chunk while the next is measured keeps the
// gear order and the callbacks on the calling thread.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <sys/wait.h>
#include <array>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <stdexcept>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "core/provenance.h"
#include "engine/run/monte_carlo.h"
#include "tests/support/run_compare.h"
#include "tests/support/run_gearmc.h"
#include "tests/support/temp_paths.h"

using ::gearmc::testing_support::fresh_temp_path;

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
  one.end_gear = 12;
  one.threads = 1;
  RunOptions all = one;
  all.threads = 2;  // two threads even on a 1-CPU runner (an explicit arena, monte_carlo.cpp)
  const RunResults a = mc.run(one), b = mc.run(all);
  testing_support::expect_identical_statistics(a, b);
  EXPECT_EQ(a.contacts, 12u * 24 * 2 * 50);
  EXPECT_EQ(a.failed_contacts, 0u);
}

// Three chunks (kGearsPerBlock = 256 gears each, the last one partial) of a small plan (tooth 1,
// 3 x 2 points per flank), so chunk i is merged while chunk i + 1 is measured: the statistics
// and the block moments are bit-identical with one and with two threads, every gear reaches
// on_gear once and in gear order, and on_gear and progress run on the calling thread, progress
// once per chunk in order. An exception thrown by on_gear in the middle of the run (while the
// next chunk is being measured) comes out of run() as it was thrown.
TEST(MonteCarlo, ChunkMergeOverlapsMeasuringAndKeepsGearOrder) {
  Scenario scenario = reference_scenario();
  scenario.probing.teeth = {1};
  scenario.probing.grid.points_along_profile = 3;
  scenario.probing.grid.sections_across_face = 2;
  constexpr int kGears = 2 * kGearsPerBlock + 9;
  scenario.gears = kGears;
  const MonteCarloRun mc(scenario);
  const std::thread::id caller = std::this_thread::get_id();
  auto run = [&](int threads, std::vector<int>* order, std::vector<std::pair<int, int>>* progress) {
    RunOptions options;
    options.end_gear = kGears;
    options.threads = threads;
    options.keep_block_moments = true;
    options.on_gear = [&, order](const GearOutcome& g) {
      EXPECT_EQ(std::this_thread::get_id(), caller);
      order->push_back(g.gear);
    };
    options.progress = [&, progress](int done, int total) {
      EXPECT_EQ(std::this_thread::get_id(), caller);
      progress->emplace_back(done, total);
    };
    return mc.run(options);
  };
  std::vector<int> order1, order2;
  std::vector<std::pair<int, int>> progress1, progress2;
  const RunResults a = run(1, &order1, &progress1), b = run(2, &order2, &progress2);
  testing_support::expect_identical_statistics(a, b);
  EXPECT_EQ(a.gears, kGears);
  EXPECT_EQ(a.contacts, static_cast<std::uint64_t>(kGears) * 2 * 3 * 2);
  ASSERT_EQ(a.block_moments.size(), 3u);
  ASSERT_EQ(b.block_moments.size(), 3u);
  for (int k = 0; k < 3; ++k) {
    for (int s = 0; s < 2; ++s) {
      EXPECT_TRUE(a.block_moments[k].point[s] == b.block_moments[k].point[s]) << k;
    }
  }
  std::vector<int> expected(kGears);
  for (int k = 0; k < kGears; ++k) expected[k] = k;
  EXPECT_EQ(order1, expected);
  EXPECT_EQ(order2, expected);
  const std::vector<std::pair<int, int>> chunks = {
      {kGearsPerBlock, kGears}, {2 * kGearsPerBlock, kGears}, {kGears, kGears}};
  EXPECT_EQ(progress1, chunks);
  EXPECT_EQ(progress2, chunks);

  RunOptions failing;
  failing.end_gear = kGears;
  failing.threads = 2;
  failing.on_gear = [](const GearOutcome& g) {
    if (g.gear == 100) throw std::runtime_error("stop at gear 100");
  };
  try {
    mc.run(failing);
    ADD_FAILURE() << "run() returned although on_gear threw";
  } catch (const std::runtime_error& e) {
    EXPECT_STREQ(e.what(), "stop at gear 100");
  }
}

TEST(MonteCarlo, OnlyGearReproducesThatGearOfTheFullRun) {
  const MonteCarloRun mc(small_reference(6));
  std::vector<GearOutcome> full;
  RunOptions options;
  options.end_gear = 6;
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
  const fs::path dir = fresh_temp_path("run_points");
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
  for (const char* svg : {"flank_max_left.svg", "flank_max_right.svg", "point_left.svg",
                          "point_right.svg", "point_log_left.svg", "point_log_right.svg"}) {
    std::ifstream f(dir / svg);
    const std::string text((std::istreambuf_iterator<char>(f)), {});
    EXPECT_NE(text.find("<svg"), std::string::npos) << svg;
    // 4 800 points support a p99.73 marker; 48 per-flank maxima (2 gears) do not (need 371).
    EXPECT_EQ(text.find("p99.73") != std::string::npos, std::string(svg).rfind("point", 0) == 0)
        << svg;
  }
  {  // The per-point tail on a log10 count axis: its ticks are powers of ten, also in report.html.
    std::ifstream f(dir / "point_log_left.svg");
    const std::string text((std::istreambuf_iterator<char>(f)), {});
    EXPECT_NE(text.find(">count (log scale)</text>"), std::string::npos);
    EXPECT_NE(text.find(">1</text>"), std::string::npos);
    EXPECT_NE(text.find(">100</text>"), std::string::npos);
    std::ifstream page(dir / "report.html");
    const std::string html((std::istreambuf_iterator<char>(page)), {});
    EXPECT_NE(html.find("log10 count axis"), std::string::npos);
  }
  const auto& flank_max_left = summary["delta_rcomp_um"]["flank_max"]["left"];
  EXPECT_TRUE(flank_max_left["p99_73"].is_null());
  EXPECT_EQ(flank_max_left["p99_73_note"], "not enough values: n = 48, p99.73 needs at least 371");
  EXPECT_TRUE(summary["delta_rcomp_um"]["point"]["left"]["p99_73"].is_number());
  // Provenance: this build's version, the command line as typed, the built-in scenario's
  // fingerprint (FNV-1a of its text, recomputed here from the file it is compiled from).
  const auto& made = summary["provenance"];
  EXPECT_EQ(made["gearmc"], "0.1.0");
  EXPECT_FALSE(made["git"].get<std::string>().empty());
  EXPECT_NE(made["command"].get<std::string>().find("run --gears 2 --points --quiet --out"),
            std::string::npos);
  EXPECT_EQ(made["created_utc"].get<std::string>().size(), 20u);  // 2026-11-22T20:55:00Z
  {
    std::ifstream f(std::string(GEARMC_SOURCE_DIR) + "/scenarios/p1_reference.yaml");
    const std::string text((std::istreambuf_iterator<char>(f)), {});
    EXPECT_EQ(made["input_hash"], fnv1a64_text(text));
  }
  EXPECT_NE(r.out.find("n<371"), std::string::npos);
  // histograms.csv: long format; the counts of each quantity and side add up to its n.
  {
    std::ifstream csv(dir / "histograms.csv");
    std::string row;
    std::getline(csv, row);  // the header first: pandas, R, spreadsheets read it by default
    EXPECT_EQ(row, "quantity,side,bin_lo_um,bin_hi_um,count");
    std::map<std::string, std::uint64_t> sums;
    while (std::getline(csv, row)) {
      std::vector<std::string> cells;
      std::stringstream ss(row);
      for (std::string cell; std::getline(ss, cell, ',');) cells.push_back(cell);
      ASSERT_EQ(cells.size(), 5u) << row;
      sums[cells[0] + cells[1]] += std::stoull(cells[4]);
    }
    EXPECT_EQ(sums["pointL"], 2u * 24 * 50);
    EXPECT_EQ(sums["flank_maxR"], 2u * 24);
    EXPECT_EQ(sums["flank_meanL"], 2u * 24);
  }
  std::ifstream report_file(dir / "report.html");
  const std::string report((std::istreambuf_iterator<char>(report_file)), {});
  // The page opens with its verdict box (before the introduction): per-flank p99.73 (too few
  // values at 48 flanks per side) and P1's claim.
  const std::size_t box = report.find("<div class=\"verdict\">");
  ASSERT_NE(box, std::string::npos);
  EXPECT_LT(box, report.find("contacts (failed"));
  EXPECT_NE(
      report.find("δRcomp per flank (µm): p99.73 n&lt;371 left, n&lt;371 right; largest", box),
      std::string::npos);
  EXPECT_NE(report.find("P1&#39;s claim", box), std::string::npos);
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
  std::getline(points, line);  // the header first (the provenance is summary.json's)
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

// A scenario file in the test's temp folder.
std::string write_scenario(const std::string& name, const std::string& text) {
  const std::string path = fresh_temp_path(name).string();
  std::ofstream(path) << text;
  return path;
}

// P1's reference scenario text with `extra` appended (top-level keys) and, optionally, one
// piece of text replaced.
std::string reference_with(const std::string& extra, const std::string& from = "",
                           const std::string& to = "") {
  std::ifstream f(std::string(GEARMC_SOURCE_DIR) + "/scenarios/p1_reference.yaml");
  std::stringstream text;
  text << f.rdbuf() << "\n" << extra << "\n";
  std::string yaml = text.str();
  if (!from.empty()) {
    const std::size_t at = yaml.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    if (at != std::string::npos) yaml.replace(at, from.size(), to);
  }
  return yaml;
}

TEST(RunCommand, AllContactsFailingIsAnErrorWithNothingWritten) {
  // A normal_um expression that is NaN everywhere: no contact can give a value. Before, the run
  // printed a table of dashes and exited 0.
  namespace fs = std::filesystem;
  const std::string scenario =
      write_scenario("gearmc_nan_expression.yaml",
                     reference_with("", "deviations:\n", "deviations:\n  normal_um: \"0/0\"\n"));
  const fs::path dir = fresh_temp_path("nan_run");
  fs::remove_all(dir);
  const Result r = run_cli("run " + scenario + " --gears 1 --quiet --out " + dir.string());
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("none of the 2400 contacts gave a value"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir));  // the folder this run created is removed again
}

TEST(RunCommand, UnwritableOutputFolderFailsBeforeTheRun) {
  // /proc refuses new entries even for root; the message names the folder and the reason.
  const Result r = run_cli("run --gears 2 --quiet --out /proc/gearmc_cannot_be_here");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("/proc/gearmc_cannot_be_here: cannot create the output folder"),
            std::string::npos)
      << r.err;
  EXPECT_EQ(r.out.find("contacts"), std::string::npos);  // the run did not start
  const std::string file = write_scenario("gearmc_not_a_folder.txt", "x");
  const Result f = run_cli("run --gears 2 --quiet --out " + file);
  EXPECT_EQ(f.exit_code, 2);
  EXPECT_NE(f.err.find("is not a folder"), std::string::npos) << f.err;
}

TEST(RunCommand, PointsAboveTheSizeLimitNeedForce) {
  namespace fs = std::filesystem;
  const fs::path dir = fresh_temp_path("points_limit");
  fs::remove_all(dir);
  // 100 000 gears x 2 400 points x 330 B = 79 GB > 4 GB: refused up front, nothing created.
  const Result r = run_cli("run --gears 100000 --points --quiet --out " + dir.string());
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("add --force"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir));
}

TEST(RunCommand, InterruptStopsCleanlyWithExit130) {
  // SIGINT one second into a run of 100 000 gears (about two minutes of work): exit 130, one
  // line on stderr, no partial file and no folder left behind.
  namespace fs = std::filesystem;
  const fs::path dir = fresh_temp_path("interrupted");
  fs::remove_all(dir);
  const std::string err_file = fresh_temp_path("interrupted_err.txt").string();
  const std::string cmd = "timeout --preserve-status -s INT 1 " + std::string(GEARMC_BINARY) +
                          " run --gears 100000 --points --force --quiet --out " + dir.string() +
                          " >/dev/null 2>" + err_file;
  const int status = std::system(cmd.c_str());
  EXPECT_EQ(WEXITSTATUS(status), 130);
  std::ifstream e(err_file);
  const std::string err((std::istreambuf_iterator<char>(e)), {});
  EXPECT_NE(err.find("interrupted after"), std::string::npos) << err;
  EXPECT_FALSE(fs::exists(dir));
}

TEST(RunCommand, ManyCollisionsGiveAWarning) {
  // A 3 mm stylus in P1's tooth spaces (module 5.6) collides on part of the grid: the run still
  // reports the other points but says how many gave no value, on stderr and in summary.json.
  namespace fs = std::filesystem;
  const std::string scenario = write_scenario(
      "gearmc_big_stylus.yaml", reference_with("", "radius_mm: 0.5", "radius_mm: 3.0"));
  const fs::path dir = fresh_temp_path("big_stylus");
  fs::remove_all(dir);
  const Result r = run_cli("run " + scenario + " --gears 1 --quiet --out " + dir.string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto summary = nlohmann::json::parse(std::ifstream(dir / "summary.json"));
  const std::uint64_t bad = summary["failed_contacts"].get<std::uint64_t>() +
                            summary["edge_contacts"].get<std::uint64_t>() +
                            summary["collisions"].get<std::uint64_t>();
  ASSERT_GT(100 * bad, summary["contacts"].get<std::uint64_t>()) << "needs > 1 % without value";
  ASSERT_EQ(summary["warnings"].size(), 1u);
  EXPECT_NE(r.err.find("gearmc: warning:"), std::string::npos) << r.err;
}

TEST(RunCommand, TwoScenarioFilesWithOneNameDoNotOverwriteEachOther) {
  // Both files say `name: p1_reference`; the second run into the default results/p1_reference
  // would silently replace the first one's results. It is refused with a hint instead; the
  // same file again (a re-run) is fine.
  namespace fs = std::filesystem;
  const fs::path work = fresh_temp_path("same_name");
  fs::remove_all(work);
  fs::create_directories(work);
  const std::string text = reference_with("");
  std::ofstream(work / "a.yaml") << text;
  std::ofstream(work / "b.yaml") << text;
  const auto run_in_work = [&](const std::string& args) {
    const std::string cmd = "cd " + work.string() + " && " + std::string(GEARMC_BINARY) + " " +
                            args + " --gears 1 --quiet >/dev/null 2>err.txt";
    return WEXITSTATUS(std::system(cmd.c_str()));
  };
  EXPECT_EQ(run_in_work("run a.yaml"), 0);
  EXPECT_EQ(run_in_work("run a.yaml"), 0);
  EXPECT_EQ(run_in_work("run b.yaml"), 2);
  std::ifstream e(work / "err.txt");
  const std::string err((std::istreambuf_iterator<char>(e)), {});
  EXPECT_NE(err.find("holds the results of another scenario file"), std::string::npos) << err;
  EXPECT_NE(err.find("--out DIR"), std::string::npos) << err;
  EXPECT_EQ(run_in_work("run b.yaml --out results/b"), 0);
}

TEST(RunCommand, OneGearReRunGoesBesideTheFullRunNotOverIt) {
  // `run --only-gear K` without --out writes results/<name>/gear_K/: the full run's report and
  // summary stay as they were (byte for byte), and the re-run's summary counts one gear.
  namespace fs = std::filesystem;
  const fs::path work = fresh_temp_path("only_gear");
  fs::remove_all(work);
  fs::create_directories(work);
  std::ofstream(work / "a.yaml") << reference_with("");
  const auto run_in_work = [&](const std::string& args) {
    const std::string cmd = "cd " + work.string() + " && " + std::string(GEARMC_BINARY) + " " +
                            args + " --quiet >/dev/null 2>err.txt";
    return WEXITSTATUS(std::system(cmd.c_str()));
  };
  const auto text_of = [](const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    return std::string((std::istreambuf_iterator<char>(in)), {});
  };
  ASSERT_EQ(run_in_work("run a.yaml --gears 3"), 0);
  const fs::path full = work / "results" / "p1_reference";
  const std::string report = text_of(full / "report.html");
  const std::string summary = text_of(full / "summary.json");
  ASSERT_FALSE(report.empty());
  ASSERT_EQ(run_in_work("run a.yaml --gears 3 --only-gear 1"), 0);
  EXPECT_EQ(text_of(full / "report.html"), report);
  EXPECT_EQ(text_of(full / "summary.json"), summary);
  const std::string one = text_of(full / "gear_1" / "summary.json");
  EXPECT_NE(one.find("\"only_gear\": 1"), std::string::npos) << one;
}

TEST(RunCommand, BadOptionsExitWithTwo) {
  EXPECT_EQ(run_cli("run --gears 0").exit_code, 2);
  EXPECT_EQ(
      run_cli("run --only-gear 60 --gears 5 --out " + fresh_temp_path("x").string()).exit_code, 2);
  EXPECT_EQ(run_cli("run /nonexistent.yaml").exit_code, 2);
}

}  // namespace
}  // namespace gearmc
