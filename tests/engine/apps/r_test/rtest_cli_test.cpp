// `gearmc uncertainty` on an r_test model file, run as a user runs it: bad keys of the builtin
// model and bad input classes give exit code 2 and one message with file:line:column (and a "did
// you mean" where one fits), writing nothing; a small good model file writes uncertainty.json
// with its r_test section and report.html, and prints every route and the verification.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <nlohmann/json.hpp>
#include <string>

#include "tests/support/run_gearmc.h"
#include "tests/support/temp_paths.h"

namespace gearmc {
namespace {

namespace fs = std::filesystem;
using testing_support::run_gearmc;

std::string temp_path(const std::string& tag) {
  return testing_support::fresh_temp_path("rtest_" + tag).string();
}

const char* kGood = R"M(name: rt_small
inputs:
  linearity:     {uniform: [-0.0025, 0.0025], dof: 50}
  repeatability: {uniform: [-0.0005, 0.0005], dof: 50}
  resolution:    {uniform: [-0.00005, 0.00005], dof: 50}
  tip_form:      {uniform: [-0.0005, 0.0005], dof: 50}
  ball_form:     {uniform: [-0.0003, 0.0003], dof: 50}
  positioning:   {uniform: [-0.0001, 0.0001], dof: 50}
builtin:
  model: r_test
  base_radius_mm: 40
  verification_positions: 10
  verification_repetitions: 50
settings: {trials: 5000, seed: 3}
)M";

std::string replace(std::string s, const std::string& from, const std::string& to) {
  const auto at = s.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  return s.replace(at, from.size(), to);
}

TEST(RTestCli, BadKeysAndInputsExit2WithOneMessage) {
  const std::string g = kGood;
  struct Case {
    const char* tag;
    std::string text, where, message;
  } cases[] = {
      {"unknown_key", replace(g, "base_radius_mm: 40", "base_radius: 40"),
       ":11:3:", "did you mean 'base_radius_mm'"},
      {"range", replace(g, "base_radius_mm: 40", "base_radius_mm: 4000"), ":11:19:", "in [5, 500]"},
      {"integer", replace(g, "verification_positions: 10", "verification_positions: 10.5"),
       ":12:27:", "an integer"},
      {"not_number", replace(g, "base_radius_mm: 40", "base_radius_mm: forty"),
       ":11:19:", "number"},
      {"input", replace(g, "tip_form:", "tip_from:"), ":6:18:", "did you mean 'tip_form'"},
      {"missing_input", replace(g, "  positioning:   {uniform: [-0.0001, 0.0001], dof: 50}\n", ""),
       ":9:3:", "'positioning' is missing"},
  };
  for (const Case& c : cases) {
    const std::string model = temp_path(c.tag) + ".yaml";
    std::ofstream(model) << c.text;
    const std::string out = temp_path(std::string(c.tag) + "_out");
    const auto r = run_gearmc("uncertainty " + model + " --out " + out);
    EXPECT_EQ(r.exit_code, 2) << c.tag << ": " << r.err;
    EXPECT_NE(r.err.find(model + c.where), std::string::npos) << c.tag << ": " << r.err;
    EXPECT_NE(r.err.find(c.message), std::string::npos) << c.tag << ": " << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << c.tag << ": " << r.err;
    EXPECT_FALSE(fs::exists(out)) << c.tag;
    fs::remove(model);
  }
}

// Input laws far wider than an R-Test's errors: a linearity error of ±100 mm on 2.5 mm tips and a
// 15 mm ball leaves no calibration that fits (P3's errors are a few µm). That was exit 0 with
// `nan` tables and null U; now one message (exit 2) naming the failed fit, and nothing written.
// Moderately wide laws (±0.05 mm, 20 times P3's linearity) still converge and are accepted.
TEST(RTestCli, LawsTooWideForTheCalibrationAreRefused) {
  const std::string model = temp_path("wide") + ".yaml";
  std::ofstream(model) << replace(kGood, "linearity:     {uniform: [-0.0025, 0.0025], dof: 50}",
                                  "linearity:     {uniform: [-100, 100], dof: 50}");
  const std::string out = temp_path("wide_out");
  const auto r = run_gearmc("uncertainty " + model + " --out " + out + " --quiet");
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find(model + ": the observed calibration fit does not converge"),
            std::string::npos)
      << r.err;
  EXPECT_NE(r.err.find("too wide for the R-Test model"), std::string::npos) << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  EXPECT_FALSE(fs::exists(out));

  std::ofstream(model) << replace(kGood, "linearity:     {uniform: [-0.0025, 0.0025], dof: 50}",
                                  "linearity:     {uniform: [-0.05, 0.05], dof: 50}");
  const auto ok = run_gearmc("uncertainty " + model + " --out " + out + " --quiet");
  EXPECT_EQ(ok.exit_code, 0) << ok.err;
  const auto j = nlohmann::json::parse(std::ifstream(out + "/uncertainty.json"));
  EXPECT_GT(j.at("r_test").at("predictions").at("full_mcm").at("x").at("U_um").get<double>(), 0);
}

TEST(RTestCli, SmallRunWritesTheRTestSection) {
  const std::string model = temp_path("good") + ".yaml";
  std::ofstream(model) << kGood;
  const std::string out = temp_path("good_out");
  const auto r = run_gearmc("uncertainty " + model + " --out " + out + " --quiet");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  for (const char* s : {"P3's GUM of the base points", "GUM, P3's route", "GUM+MCM, P3's route",
                        "GUM, whole chain", "full MCM", "verification: actual 95 % |error|"}) {
    EXPECT_NE(r.out.find(s), std::string::npos) << s << "\n" << r.out;
  }
  const auto j = nlohmann::json::parse(std::ifstream(out + "/uncertainty.json"));
  const auto& rt = j.at("r_test");
  EXPECT_EQ(rt.at("calibration").at("sensors").size(), 3u);
  for (const char* id : {"gum_p3", "gum_mcm_p3", "gum_p3_readings", "gum_mcm_p3_readings",
                         "gum_chain", "full_mcm"}) {
    EXPECT_GT(rt.at("predictions").at(id).at("x").at("U_um").get<double>(), 0.0) << id;
  }
  EXPECT_EQ(rt.at("predictions").at("full_mcm").at("trials").get<int>(), 5000);
  EXPECT_EQ(rt.at("verification").at("measurements").get<int>(), 550);  // 50 x (10 + P_m)
  EXPECT_EQ(rt.at("verification").at("failed").get<int>(), 0);
  EXPECT_TRUE(fs::exists(out + "/report.html"));
  {  // The report opens with the verdict box: how many routes' U cover the actual 95 % error.
    std::ifstream in(out + "/report.html");
    const std::string html((std::istreambuf_iterator<char>(in)), {});
    const auto& actual = rt.at("verification").at("actual_U_um");
    int covering = 0, routes = 0;
    for (const auto& [id, p] : rt.at("predictions").items()) {
      bool all = true;
      for (int k = 0; k < 3; ++k) {
        all = all &&
              p.at(std::string(1, "xyz"[k])).at("U_um").get<double>() >= actual[k].get<double>();
      }
      covering += all;
      ++routes;
    }
    const std::size_t box = html.find("<div class=\"verdict\">");
    ASSERT_NE(box, std::string::npos);
    EXPECT_LT(box, html.find("P3&#39;s contact R-Test"));
    EXPECT_NE(html.find(std::to_string(covering) + " of " + std::to_string(routes) +
                            " routes give a U at P_m that covers",
                        box),
              std::string::npos)
        << html.substr(box, 300);
  }
  EXPECT_EQ(j.at("seed").get<int>(), 3);
  // --seed overrides settings.seed (another calibration draw: other fitted base points).
  const std::string out2 = temp_path("good_out_seed");
  const auto r2 = run_gearmc("uncertainty " + model + " --out " + out2 + " --quiet --seed 4");
  ASSERT_EQ(r2.exit_code, 0) << r2.err;
  const auto j2 = nlohmann::json::parse(std::ifstream(out2 + "/uncertainty.json"));
  EXPECT_EQ(j2.at("seed").get<int>(), 4);
  EXPECT_NE(j2.at("r_test").at("calibration").at("sensors")[0].at("fitted_base_mm"),
            rt.at("calibration").at("sensors")[0].at("fitted_base_mm"));
}

}  // namespace
}  // namespace gearmc
