// `gearmc sweep` through the executable: a grid point's statistic is the same number as `gearmc
// run` of that variant written by hand (an independent path: the run command, its summary.json);
// the grid order and the files; and bad keys, values and statistics: one message naming them,
// exit code 2, no output folder.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "tests/support/run_gearmc.h"
#include "tests/support/temp_paths.h"

namespace gearmc {
namespace {

namespace fs = std::filesystem;
using testing_support::run_gearmc;

fs::path temp(const std::string& tag) { return testing_support::fresh_temp_path("sweep_" + tag); }

std::string read(const fs::path& p) {
  std::ifstream in(p);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

const std::string kScenario = std::string(GEARMC_SOURCE_DIR) + "/scenarios/p1_reference.yaml";

TEST(SweepCli, PointEqualsTheRunOfTheVariantWrittenByHand) {
  const fs::path out = temp("point");
  const auto r = run_gearmc("sweep " + kScenario +
                            " --vary stylus.radius_mm=0.5,1 --statistic delta_rcomp.flank_max.mean"
                            " --gears 3 --quiet --out " +
                            out.string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const nlohmann::json sweep = nlohmann::json::parse(read(out / "sweep.json"));
  ASSERT_EQ(sweep["points"].size(), 2u);
  EXPECT_EQ(sweep["points"][1]["values"]["stylus.radius_mm"], "1");
  EXPECT_EQ(sweep["ranks"], 1);
  EXPECT_TRUE(fs::exists(out / "sweep.csv"));
  EXPECT_TRUE(fs::exists(out / "report.html"));
  {  // The opening box: the grid points with the lowest and highest statistic (both flanks).
    const std::string html = read(out / "report.html");
    const auto& points = sweep["points"];
    std::size_t lo = 0, hi = 0;
    for (std::size_t i = 0; i < points.size(); ++i) {
      const double v = points[i]["both_um"].get<double>();
      if (v < points[lo]["both_um"].get<double>()) lo = i;
      if (v > points[hi]["both_um"].get<double>()) hi = i;
    }
    const std::size_t box = html.find("<div class=\"verdict\">");
    ASSERT_NE(box, std::string::npos);
    EXPECT_NE(html.find("lowest: ", box), std::string::npos);
    EXPECT_NE(html.find(" at stylus.radius_mm = " +
                        points[lo]["values"]["stylus.radius_mm"].get<std::string>() +
                        "</li>\n<li>highest: "),
              std::string::npos);
    EXPECT_NE(
        html.find(" at stylus.radius_mm = " +
                  points[hi]["values"]["stylus.radius_mm"].get<std::string>() + "</li>\n</ul>"),
        std::string::npos);
  }

  // The variant radius 1 mm by hand: the scenario text with its one `radius_mm:` line changed.
  std::string text = read(kScenario);
  const std::string from = "radius_mm: 0.5";
  ASSERT_EQ(text.find(from), text.rfind(from));
  text.replace(text.find(from), from.size(), "radius_mm: 1");
  const fs::path variant = temp("variant.yaml");
  std::ofstream(variant) << text;
  const fs::path run_out = temp("run");
  const auto run =
      run_gearmc("run " + variant.string() + " --gears 3 --quiet --out " + run_out.string());
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const nlohmann::json summary = nlohmann::json::parse(read(run_out / "summary.json"));
  const auto& fm = summary["delta_rcomp_um"]["flank_max"];
  EXPECT_EQ(sweep["points"][1]["left_um"].get<double>(), fm["left"]["mean"].get<double>());
  EXPECT_EQ(sweep["points"][1]["right_um"].get<double>(), fm["right"]["mean"].get<double>());
  // Both flanks: the two sides' means weighted by their counts (equal counts here), to rounding.
  const double both = 0.5 * (fm["left"]["mean"].get<double>() + fm["right"]["mean"].get<double>());
  EXPECT_NEAR(sweep["points"][1]["both_um"].get<double>(), both, 1e-12 * both);
  // p99.73 needs 371 values; 3 gears give 72 flank maxima per side: null with a note, not a number.
  const fs::path out2 = temp("null");
  ASSERT_EQ(run_gearmc("sweep " + kScenario +
                       " --vary stylus.radius_mm=0.5 --gears 3 --quiet --out " + out2.string())
                .exit_code,
            0);
  const nlohmann::json s2 = nlohmann::json::parse(read(out2 / "sweep.json"));
  EXPECT_TRUE(s2["points"][0]["left_um"].is_null());
  EXPECT_NE(s2["points"][0]["left_note"].get<std::string>().find("371"), std::string::npos);
  for (const fs::path& p : {out, variant, run_out, out2}) fs::remove_all(p);
}

TEST(SweepCli, AGearParameterStatisticIsTheRunReportsOwn) {
  // U of F_α per side and Q_MP, as `gearmc run` of the variant states them in summary.json (an
  // independent path through the run command); "both" is the larger side's U (U/T takes it).
  const std::string params =
      std::string(GEARMC_SOURCE_DIR) + "/scenarios/p1_reference_parameters.yaml";
  const fs::path out = temp("param"), out_q = temp("param_q");
  const std::string grid = " --vary stylus.radius_mm=1 --gears 5 --quiet --out ";
  ASSERT_EQ(
      run_gearmc("sweep " + params + grid + out.string() + " --statistic parameters.F_alpha.U")
          .exit_code,
      0);
  ASSERT_EQ(
      run_gearmc("sweep " + params + grid + out_q.string() + " --statistic parameters.F_alpha.Q_MP")
          .exit_code,
      0);
  std::string text = read(params);
  const std::string from = "radius_mm: 0.5";
  ASSERT_EQ(text.find(from), text.rfind(from));
  text.replace(text.find(from), from.size(), "radius_mm: 1");
  const fs::path variant = temp("param_variant.yaml"), run_out = temp("param_run");
  std::ofstream(variant) << text;
  ASSERT_EQ(run_gearmc("run " + variant.string() + " --gears 5 --quiet --out " + run_out.string())
                .exit_code,
            0);
  const nlohmann::json summary = nlohmann::json::parse(read(run_out / "summary.json"));
  const auto& fa = summary["parameters"]["F_alpha"];
  const nlohmann::json point = nlohmann::json::parse(read(out / "sweep.json"))["points"][0];
  const double left = fa["left"]["U95_um"].get<double>(),
               right = fa["right"]["U95_um"].get<double>();
  EXPECT_EQ(point["left_um"].get<double>(), left);
  EXPECT_EQ(point["right_um"].get<double>(), right);
  EXPECT_EQ(point["both_um"].get<double>(), std::max(left, right));
  const nlohmann::json q = nlohmann::json::parse(read(out_q / "sweep.json"))["points"][0];
  EXPECT_EQ(q["both_um"].get<double>(), summary["conformity"]["F_alpha"]["Q_MP"].get<double>());
  EXPECT_TRUE(q["left_um"].is_null());
  EXPECT_NE(q["left_note"].get<std::string>().find("as a whole"), std::string::npos);
  // A scenario without the parameter: refused before any run.
  const auto none = run_gearmc("sweep " + kScenario + grid + temp("param_none").string() +
                               " --statistic parameters.F_alpha.U");
  EXPECT_EQ(none.exit_code, 2);
  EXPECT_NE(none.err.find("a parameter every variant evaluates"), std::string::npos) << none.err;
  EXPECT_FALSE(fs::exists(temp("param_none")));
  for (const fs::path& p : {out, out_q, variant, run_out}) fs::remove_all(p);
}

// The count n is a number of values, not µm: the terminal, sweep.csv and the report say so. With
// the gear count varied, each point counts its own gears: n of the point quantity is
// gears × 24 teeth × 2 flanks × 10 × 5 points per flank / 2 per side (P1's plan, both flanks).
TEST(SweepCli, TheCountHasNoUnitAndVariedGearCountsAreSaid) {
  const fs::path out = temp("count");
  const auto r = run_gearmc("sweep " + kScenario +
                            " --vary run.gears=1,2 --statistic delta_rcomp.point.n --quiet --out " +
                            out.string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("2 variants of 1–2 gears"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("run.gears=1  delta_rcomp.point.n (both flanks) = 2400\n"),
            std::string::npos)
      << r.out;
  EXPECT_NE(r.out.find("run.gears=2  delta_rcomp.point.n (both flanks) = 4800\n"),
            std::string::npos)
      << r.out;
  EXPECT_EQ(r.out.find("µm"), std::string::npos) << r.out;
  const std::string csv = read(out / "sweep.csv");
  // The header is the first line (read with the defaults of pandas, R and spreadsheets).
  EXPECT_EQ(csv.rfind("run.gears,gears,contacts,failed_contacts,", 0), 0u) << csv;
  EXPECT_NE(
      csv.find(",delta_rcomp.point.n_left,delta_rcomp.point.n_right,delta_rcomp.point.n_both\n"),
      std::string::npos)
      << csv;
  EXPECT_NE(read(out / "report.html").find("runs of 1–2 gears"), std::string::npos);
  fs::remove_all(out);
}

// A limit: each point's verdict from its band, in the terminal, sweep.csv, sweep.json and the
// report; the band (95 % by default) brackets the point's value; the count has no band.
TEST(SweepCli, ALimitGivesEachPointAVerdictFromItsBand) {
  const fs::path out = temp("limit");
  const auto r = run_gearmc("sweep " + kScenario +
                            " --vary stylus.radius_mm=0.3,1.5 --statistic delta_rcomp.point.p95"
                            " --gears 20 --at-most 2 --quiet --out " +
                            out.string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const nlohmann::json sweep = nlohmann::json::parse(read(out / "sweep.json"));
  EXPECT_EQ(sweep["bands"]["confidence"], 0.95);
  EXPECT_EQ(sweep["bands"]["resamples"], 1000);
  EXPECT_EQ(sweep["limit"]["at_most"], 2.0);
  EXPECT_TRUE(sweep["limit"]["at_least"].is_null());
  const std::string csv = read(out / "sweep.csv");
  int verdicts[3] = {0, 0, 0};
  for (const auto& p : sweep["points"]) {
    ASSERT_TRUE(p["both_band_um"].is_array()) << p.dump();
    const double lo = p["both_band_um"][0], hi = p["both_band_um"][1], v = p["both_um"];
    EXPECT_LT(lo, hi);
    // The estimate is the histogram's (rounded up by at most 2^-12 relative): inside the band.
    EXPECT_LE(lo, v);
    EXPECT_GE(hi * (1.0 + 0x1.0p-12), v);
    const std::string expected = hi <= 2.0 ? "meets" : lo > 2.0 ? "misses" : "undecided";
    EXPECT_EQ(p["verdict"], expected) << p.dump();
    ++verdicts[expected == "meets" ? 0 : expected == "misses" ? 1 : 2];
    EXPECT_NE(csv.find("," + expected + "\n"), std::string::npos) << csv;
  }
  // P1 with a 0.3 mm stylus stays far below 2 µm at p95 and a 1.5 mm one far above it.
  EXPECT_EQ(sweep["points"][0]["verdict"], "meets");
  EXPECT_EQ(sweep["points"][1]["verdict"], "misses");
  EXPECT_NE(r.out.find("limit ≤ 2 µm: " + std::to_string(verdicts[0]) + " meet, " +
                       std::to_string(verdicts[1]) + " miss, " + std::to_string(verdicts[2]) +
                       " undecided (95 % bands of 1000 bootstrap resamples of the gears)"),
            std::string::npos)
      << r.out;
  EXPECT_EQ(csv.rfind("stylus.radius_mm,gears,contacts,failed_contacts,", 0), 0u);
  EXPECT_NE(csv.find(",delta_rcomp.point.p95_both_lower_um,delta_rcomp.point.p95_both_upper_um,"
                     "verdict\n"),
            std::string::npos)
      << csv;
  const std::string html = read(out / "report.html");
  EXPECT_NE(html.find("limit ≤ 2 µm: 1 meet"), std::string::npos);
  EXPECT_NE(html.find("at most 2 µm"), std::string::npos);  // the limit line's label
  // A narrower confidence gives a narrower band of the same resamples.
  const fs::path out80 = temp("limit80");
  ASSERT_EQ(run_gearmc("sweep " + kScenario +
                       " --vary stylus.radius_mm=0.3,1.5 --statistic delta_rcomp.point.p95"
                       " --gears 20 --confidence 0.8 --quiet --out " +
                       out80.string())
                .exit_code,
            0);
  const nlohmann::json s80 = nlohmann::json::parse(read(out80 / "sweep.json"));
  for (int i = 0; i < 2; ++i) {
    const auto& b95 = sweep["points"][i]["both_band_um"];
    const auto& b80 = s80["points"][i]["both_band_um"];
    EXPECT_GT(b80[0].get<double>(), b95[0].get<double>());
    EXPECT_LT(b80[1].get<double>(), b95[1].get<double>());
  }
  EXPECT_FALSE(s80.contains("limit"));
  for (const fs::path& p : {out, out80}) fs::remove_all(p);
}

TEST(SweepCli, BadKeysValuesAndStatisticsAreOneMessageAndNothingWritten) {
  struct Case {
    std::string args, expected;
  };
  const std::vector<Case> cases = {
      {"--vary stylus.radiusmm=0.5", "did you mean"},
      {"--vary stylus.radius_mm=abc", "'abc'"},
      {"--vary stylus.radius_mm=-1", "stylus.radius_mm"},
      {"--vary stylus.radius_mm", "KEY=V1,V2"},
      {"--vary stylus.radius_mm=0.5,0.5", "twice"},
      {"--vary stylus.radius_mm=0.5 --statistic delta_rcomp.flank_max.p99", "--statistic"},
      // Keys the options also set: --gears (and --seed) would override the varied values in
      // every variant, and the header once printed the option's count for all of them.
      {"--vary run.gears=3,4", "--vary: got 'run.gears', expected a key --gears does not override"},
      {"--vary seed=1,2 --seed 5", "--vary: got 'seed', expected a key --seed does not override"},
      {"--vary stylus.radius_mm=0.5 --at-most 1 --at-least 2",
       "--at-least: got '2', expected at most --at-most (1)"},
      {"--vary stylus.radius_mm=0.5 --confidence 1.5", "--confidence"},
      {"--vary stylus.radius_mm=0.5 --at-most abc", "--at-most"},
  };
  for (const Case& c : cases) {
    const fs::path out = temp("bad");
    const auto r = run_gearmc("sweep " + kScenario + " " + c.args + " --gears 2 --quiet --out " +
                              out.string());
    EXPECT_EQ(r.exit_code, 2) << c.args << ": " << r.err;
    EXPECT_NE(r.err.find(c.expected), std::string::npos) << c.args << ": " << r.err;
    std::istringstream lines(r.err);
    int messages = 0;
    for (std::string line; std::getline(lines, line);) messages += line.rfind("gearmc: ", 0) == 0;
    EXPECT_EQ(messages, 1) << c.args << ": " << r.err;
    EXPECT_FALSE(fs::exists(out)) << c.args;
  }
}

}  // namespace
}  // namespace gearmc
