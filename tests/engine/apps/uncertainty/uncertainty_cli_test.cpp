// `gearmc uncertainty` run as a user runs it:
//  * bad model files (unknown law, wrong parameter count, an expression naming an unknown input,
//    a correlation matrix that is not positive definite, sd <= 0, unknown keys, an unknown
//    builtin, too few trials) give exit code 2 and one message with file:line:column, the key
//    and a "did you mean" where one fits, and write nothing (the --out folder is not created);
//  * uncertainty.json has the documented keys, and is byte-identical for 1 and 2 threads apart
//    from "threads", "wall_s" and the provenance (command line, time) — fixed M and adaptive.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <nlohmann/json.hpp>
#include <string>

#include "engine/apps/uncertainty/evaluation.h"
#include "tests/support/run_gearmc.h"
#include "tests/support/temp_paths.h"

namespace gearmc {
namespace {

namespace fs = std::filesystem;
using testing_support::run_gearmc;

std::string temp_dir(const std::string& tag) {
  return testing_support::fresh_temp_path("unc_" + tag).string();
}

std::string write_model(const std::string& tag, const std::string& text) {
  const std::string path = temp_dir(tag) + ".yaml";
  std::ofstream(path) << text;
  return path;
}

const char* kGood = R"M(name: good
inputs:
  X1: {normal: [0, 1]}
  X2: {uniform: [-1, 1]}
  X3: {normal: [0, 1]}
outputs:
  Y: "X1 + X2*X3"
settings: {trials: 20000, seed: 3}
)M";

struct BadCase {
  const char* tag;
  std::string text;
  std::string where;    // "file:line:col" suffix expected after the file name
  std::string message;  // a part of the message
};

std::string replace(std::string s, const std::string& from, const std::string& to) {
  const auto at = s.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  return s.replace(at, from.size(), to);
}

// Comparisons stay expressions (==, !=, <=, >= are not assignments).
TEST(UncertaintyCli, ComparisonsAreNotAssignments) {
  const std::string model =
      write_model("compare", replace(kGood, "X1 + X2*X3", "(X1 <= 0) + (X2 >= 0) + (X3 != 5)"));
  const std::string out = temp_dir("compare_out");
  const auto r = run_gearmc("uncertainty " + model + " --out " + out + " --quiet");
  EXPECT_EQ(r.exit_code, 0) << r.err;
  fs::remove_all(out);
  fs::remove(model);
}

// An input whose mean is far larger than its u: 1e-3 u is below the resolution of the mean in a
// double (x + h == x), so the step is widened to 2^-26 |x| and said in a warning; Y = X1 + X2 is
// linear, so the widened step is exact and c_X1 = 1 (it was 0: u(y) = 0 was printed). X2's part
// cannot be had in double precision at all — Y = 1e20 moves in steps of 16384 — so the true
// u(y) = √2 (JCGM 100 5.1.2) is not what is printed (1): that is said in a warning, never silent.
TEST(UncertaintyCli, SensitivitiesOfAnInputWithAHugeMeanUseARelativeStep) {
  const std::string model = write_model("huge_mean", R"M(name: huge
inputs:
  X1: {normal: [1e20, 1]}
  X2: {normal: [0, 1]}
outputs:
  Y: "X1 + X2"
settings: {trials: 20000, seed: 3}
)M");
  const std::string out = temp_dir("huge_out");
  const auto r = run_gearmc("uncertainty " + model + " --out " + out + " --quiet");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("warning: the sensitivity to X1 is a central difference over"),
            std::string::npos)
      << r.err;
  const nlohmann::json j = nlohmann::json::parse(std::ifstream(out + "/uncertainty.json"));
  const nlohmann::json& y = j["outputs"]["Y"]["gum"];
  EXPECT_NEAR(y["u"].get<double>(), 1.0, 1e-12) << y.dump();
  EXPECT_EQ(y["sensitivities"]["X1"].get<double>(), 1.0);
  EXPECT_NE(r.err.find("warning: the sensitivity of Y to X2 is lost in the output's resolution: "
                       "Y = 1e+20 moves in steps of 16384"),
            std::string::npos)
      << r.err;
  // The Monte-Carlo draws of X1 are all 1e20 (steps of 16384 at 1e20): said, not hidden.
  EXPECT_NE(r.err.find("warning: input X1: its u (1) is under 1000 steps of a double"),
            std::string::npos)
      << r.err;
  fs::remove_all(out);
  fs::remove(model);
}

// Values near the largest double: their sum overflows although each is finite (the fuzzer's
// `dm: 1e308` once printed an MCM estimate and u of "inf"). The mean of a constant is the
// constant and its u is 0, whatever its size.
TEST(UncertaintyCli, HugeOutputValuesKeepAFiniteMean) {
  const std::string model = write_model("huge_values", replace(kGood, "X1 + X2*X3", "1e308"));
  const std::string out = temp_dir("huge_values_out");
  const auto r = run_gearmc("uncertainty " + model + " --out " + out + " --quiet");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const nlohmann::json j = nlohmann::json::parse(std::ifstream(out + "/uncertainty.json"));
  EXPECT_EQ(j["outputs"]["Y"]["mcm"]["estimate"].get<double>(), 1e308);
  EXPECT_EQ(j["outputs"]["Y"]["mcm"]["u"].get<double>(), 0.0);
  fs::remove_all(out);
  fs::remove(model);
}

// A sensitivity that is not finite while y is: exp(X1) at X1 = 709.78 is 1.79e308, finite, but
// the central difference's step 1e-3 u = 0.01 reaches exp(709.79) = inf (exp overflows beyond
// ln(DBL_MAX) = 709.7827). max(0, NaN) = 0 once turned that into a printed u(y) = 0 and "inf"
// cells in the report (the fuzzer's mass calibration with 1e308/rho_W); it is an error at the
// output, naming the sensitivity and the input estimates, and nothing is written.
TEST(UncertaintyCli, ANonFiniteSensitivityIsAnErrorNotAZeroU) {
  const std::string model = write_model("overflowing", R"M(name: overflowing
inputs:
  X1: {normal: [709.78, 10]}
outputs:
  Y: "exp(X1)"
settings: {trials: 2000, seed: 3}
)M");
  const std::string out = temp_dir("overflowing_out");
  const auto r = run_gearmc("uncertainty " + model + " --out " + out + " --quiet");
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("outputs.Y: got 'dY/dX1 = inf'"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("at the input estimates (X1 = 709.78)"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(out));
  fs::remove(model);
}

TEST(UncertaintyCli, BadModelFilesExit2WithPlaceAndWriteNothing) {
  const std::string g = kGood;
  const BadCase cases[] = {
      {"law", replace(g, "uniform: [-1, 1]", "uniforn: [-1, 1]"),
       ":4:8:", "did you mean 'uniform'"},
      {"count", replace(g, "normal: [0, 1]}\n  X2", "normal: [0]}\n  X2"),
       ":3:16:", "normal [mean, sd]"},
      {"sd", replace(g, "normal: [0, 1]}\n  X2", "normal: [0, -1]}\n  X2"),
       ":3:16:", "sd must be > 0"},
      {"unknown_input", replace(g, "X1 + X2*X3", "X1 + X2*X4"), ":7:6:", "'X4' is none of them"},
      {"non_pd", g + "correlations: [[X1, X3, 0.9], [X1, X3, 0.8]]\n",
       ":9:31:", "each pair of inputs at most once"},
      {"not_pd",
       replace(g, "X2: {uniform: [-1, 1]}", "X2: {normal: [0, 1]}") +
           "correlations: [[X1, X2, 0.9], [X1, X3, 0.9], [X2, X3, -0.9]]\n",
       ":9:15:", "positive definite"},
      {"unreachable_r",
       replace(g, "X2: {uniform: [-1, 1]}", "X2: {exponential: [1]}") +
           "correlations: [[X1, X2, 0.99]]\n",
       ":9:25:", "a correlation these two laws can have"},
      {"top_key", replace(g, "settings:", "setings:"), ":8:1:", "did you mean 'settings'"},
      {"setting_key", replace(g, "trials: 20000", "trails: 20000"),
       ":8:12:", "did you mean 'trials'"},
      {"builtin", replace(g, "outputs:\n  Y: \"X1 + X2*X3\"", "builtin: {model: summ}"),
       ":6:18:", "did you mean 'sum'"},
      // p = 0.95: q = round(0.95 M) must be 1 … M − 1, first true at M = 11 (10: q = 10 = M).
      {"few_trials", replace(g, "trials: 20000", "trials: 10"), ":8:", "at least 11 trials"},
      // muParser reads '=' as an assignment to the input: the output would be the constant 3.
      {"assignment", replace(g, "X1 + X2*X3", "X1=3"),
       ":7:6:", "not an assignment ('=' at character 3"},
      {"add_assignment", replace(g, "X1 + X2*X3", "X1 += 3"), ":7:6:", "not an assignment"},
      // u = 2.9e307 is a double, its square is not: found by the command fuzzer (nan tables).
      {"variance", replace(g, "uniform: [-1, 1]", "uniform: [-1, 1e308]"),
       ":4:", "whose mean and variance a double can hold"},
      // A pole at the input estimates (X1's mean is 0): no GUM linearisation, not a nan table.
      {"pole", replace(g, "X1 + X2*X3", "1/X1"),
       ":7:6:", "outputs.Y: got 'y = inf', expected a model with a finite value"},
      // 4e9 trials x 16 bytes = 64 GB: refused before any work (the memory rule).
      {"memory", replace(g, "trials: 20000", "trials: 4000000000"),
       ":8:", "16 bytes per trial per output"},
      {"later_output", replace(g, "Y: \"X1 + X2*X3\"", "Y: \"Z + 1\"\n  Z: \"X1\""),
       ":7:6:", "outputs may use only outputs listed before them"},
      {"tolerance_output", replace(g, "settings:", "tolerances: {W: {upper: 1}}\nsettings:"),
       ":8:14:", "did you mean 'Y'"},
      {"tolerance_order",
       replace(g, "settings:", "tolerances: {Y: {lower: 2, upper: 1}}\nsettings:"),
       ":8:", "an upper limit above the lower limit"},
  };
  for (const BadCase& c : cases) {
    const std::string model = write_model(c.tag, c.text);
    const std::string out = temp_dir(std::string(c.tag) + "_out");
    const auto r = run_gearmc("uncertainty " + model + " --out " + out);
    EXPECT_EQ(r.exit_code, 2) << c.tag << ": " << r.err;
    EXPECT_NE(r.err.find(model + c.where), std::string::npos) << c.tag << ": " << r.err;
    EXPECT_NE(r.err.find(c.message), std::string::npos) << c.tag << ": " << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << c.tag << ": " << r.err;
    EXPECT_FALSE(fs::exists(out)) << c.tag;
    fs::remove(model);
  }
  const auto r = run_gearmc("uncertainty " + write_model("good", kGood) + " --trials 1e6 --out " +
                            temp_dir("bad_trials"));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("--trials"), std::string::npos) << r.err;
}

TEST(UncertaintyCli, ConformanceProbabilityOfJcgm106Section7) {
  // JCGM 106:2012 §7 (single measured value against two-sided limits): y = 13.6, u = 1.8, limits
  // 12.5 and 16.3. p_c = Φ((16.3 − 13.6)/1.8) − Φ((12.5 − 13.6)/1.8) = Φ(1.5) − Φ(−0.6111)
  // = 0.66263 (independently: Python math.erf, 0.6626297865). The GUM value to 1e-6; the MCM
  // value (10^6 trials, seed 1) within 4 binomial standard errors √(p(1 − p)/M) = 4 × 0.00047.
  using uncertainty::conformance_probability;
  EXPECT_NEAR(conformance_probability(13.6, 1.8, 12.5, 16.3), 0.6626297865, 1e-6);
  // One-sided: only the lower limit, 1 − Φ(−0.6111) = 0.7294369878.
  EXPECT_NEAR(conformance_probability(13.6, 1.8, 12.5, std::nullopt), 0.7294369878, 1e-6);
  const std::string model = write_model("jcgm106", R"M(name: jcgm106
inputs:
  x: {normal: [13.6, 1.8]}
outputs:
  y: "x"
tolerances:
  y: {lower: 12.5, upper: 16.3}
settings: {trials: 1000000, seed: 1}
)M");
  const std::string out = temp_dir("jcgm106_out");
  const auto r = run_gearmc("uncertainty " + model + " --out " + out + " --quiet");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = nlohmann::json::parse(std::ifstream(out + "/uncertainty.json"));
  const auto& c = j["outputs"]["y"]["conformity"];
  EXPECT_EQ(c["lower"].get<double>(), 12.5);
  EXPECT_EQ(c["upper"].get<double>(), 16.3);
  EXPECT_NEAR(c["gum_probability"].get<double>(), 0.6626297865, 1e-6);
  EXPECT_NEAR(c["mcm_probability"].get<double>(), 0.6626297865,
              4.0 * std::sqrt(0.6626 * 0.3374 / 1e6));
}

TEST(UncertaintyCli, OutputsUseEarlierOutputs) {
  const std::string model = write_model(
      "chain", replace(kGood, "Y: \"X1 + X2*X3\"", "Y: \"X1 + X2*X3\"\n  Z: \"2*Y + 1\""));
  const std::string out = temp_dir("chain_out");
  const auto r = run_gearmc("uncertainty " + model + " --quiet --out " + out);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = nlohmann::json::parse(std::ifstream(out + "/uncertainty.json"));
  // Z = 2Y + 1 exactly, trial by trial: its mean and u follow from Y's.
  const auto& y = j["outputs"]["Y"]["mcm"];
  const auto& z = j["outputs"]["Z"]["mcm"];
  EXPECT_NEAR(z["estimate"].get<double>(), 2 * y["estimate"].get<double>() + 1, 1e-12);
  EXPECT_NEAR(z["u"].get<double>(), 2 * y["u"].get<double>(), 1e-12);
  EXPECT_NEAR(j["outputs"]["Z"]["gum"]["sensitivities"]["X1"].get<double>(), 2.0, 1e-8);
  fs::remove_all(out);
  fs::remove(model);
}

TEST(UncertaintyCli, AnOutputWithoutUncertaintyIsReported) {
  // y depends only on a constant: u = 0 on both sides, the GUM trivially validated (δ = 0), and
  // the report is still drawn (a zero-width histogram range once made it an internal error).
  const std::string model = write_model("constant", R"M(name: constant_model
inputs:
  a: {constant: 3}
  b: {normal: [0, 1]}
outputs:
  y: "2*a"
  w: "b + a"
settings: {trials: 1000}
)M");
  const std::string out = temp_dir("constant_out");
  const auto r = run_gearmc("uncertainty " + model + " --quiet --out " + out);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = nlohmann::json::parse(std::ifstream(out + "/uncertainty.json"));
  const auto& y = j["outputs"]["y"];
  EXPECT_EQ(y["gum"]["u"].get<double>(), 0.0);
  EXPECT_EQ(y["mcm"]["u"].get<double>(), 0.0);
  EXPECT_EQ(y["mcm"]["estimate"].get<double>(), 6.0);
  EXPECT_TRUE(y["validation"]["gum_validated"].get<bool>());
  EXPECT_TRUE(fs::exists(out + "/report.html"));
  fs::remove_all(out);
  fs::remove(model);
}

TEST(UncertaintyCli, InterruptStopsCleanlyWithExit130) {
  // SIGINT one second into an adaptive run that cannot stop by its rule soon (4 significant
  // digits of u = 2 need about 10^10 trials): exit 130, no file and no folder left behind.
  const std::string model =
      write_model("endless", replace(replace(kGood, "trials: 20000", "trials: adaptive"), "seed: 3",
                                     "seed: 3, significant_digits: 4"));
  const std::string out = temp_dir("endless_out");
  const std::string err_file = temp_dir("endless_err") + ".txt";
  const std::string cmd = "timeout --preserve-status -s INT 1 " + std::string(GEARMC_BINARY) +
                          " uncertainty " + model + " --quiet --out " + out + " >/dev/null 2>" +
                          err_file;
  const int status = std::system(cmd.c_str());
  EXPECT_EQ(WEXITSTATUS(status), 130);
  std::ifstream e(err_file);
  const std::string err((std::istreambuf_iterator<char>(e)), {});
  EXPECT_NE(err.find("interrupted"), std::string::npos) << err;
  EXPECT_FALSE(fs::exists(out));
  fs::remove(model);
  fs::remove(err_file);
}

nlohmann::json run_json(const std::string& args, const std::string& out) {
  const auto r = run_gearmc("uncertainty " + args + " --quiet --out " + out);
  EXPECT_EQ(r.exit_code, 0) << r.err;
  std::ifstream f(out + "/uncertainty.json");
  nlohmann::json j = nlohmann::json::parse(f);
  EXPECT_TRUE(fs::exists(out + "/report.html"));
  return j;
}

TEST(UncertaintyCli, JsonKeysAndThreadIndependence) {
  const std::string dir = std::string(GEARMC_SOURCE_DIR) + "/scenarios/uncertainty/";
  for (const std::string& args :
       {dir + "mass_calibration.yaml --trials 300000", dir + "additive_rectangular.yaml"}) {
    const std::string a = temp_dir("t1"), b = temp_dir("t2");
    nlohmann::json j1 = run_json(args + " --threads 1", a);
    nlohmann::json j2 = run_json(args + " --threads 2", b);
    EXPECT_EQ(j1["threads"], 1);
    EXPECT_EQ(j2["threads"], 2);
    for (auto* j : {&j1, &j2}) {
      j->erase("threads");
      j->erase("wall_s");
      j->erase("provenance");
    }
    EXPECT_EQ(j1.dump(), j2.dump()) << args;
    const auto& o = j1["outputs"].begin().value();
    for (const char* k :
         {"estimate", "u", "nu_eff", "k", "U", "interval", "sensitivities", "contributions"}) {
      EXPECT_TRUE(o["gum"].contains(k)) << k;
    }
    for (const char* k :
         {"estimate", "u", "interval_symmetric", "interval_shortest", "trials", "adaptive"}) {
      EXPECT_TRUE(o["mcm"].contains(k)) << k;
    }
    EXPECT_TRUE(o["mcm"]["adaptive"].contains("blocks"));
    EXPECT_TRUE(o["mcm"]["adaptive"].contains("delta"));
    for (const char* k : {"delta", "d_low", "d_high", "gum_validated"}) {
      EXPECT_TRUE(o["validation"].contains(k)) << k;
    }
    for (const char* k : {"model", "seed", "coverage_probability"}) {
      EXPECT_TRUE(j1.contains(k)) << k;
    }
    // The report: histogram, CDFs and budget per output, plus the adaptive stop for adaptive
    // runs; the verdict and the model file's text.
    std::ifstream rf(a + "/report.html");
    const std::string report((std::istreambuf_iterator<char>(rf)), {});
    std::size_t svgs = 0;
    for (std::size_t at = report.find("<svg"); at != std::string::npos;
         at = report.find("<svg", at + 1)) {
      ++svgs;
    }
    const bool adaptive = args.find("rectangular") != std::string::npos;
    EXPECT_EQ(svgs, adaptive ? 4u : 3u) << args;
    EXPECT_NE(report.find("JCGM 101 §8 validation"), std::string::npos);
    // The verdict box opens the page and follows the §8 verdict of summary.json.
    const std::size_t box = report.find("<div class=\"verdict");
    ASSERT_NE(box, std::string::npos);
    EXPECT_LT(box, report.find("Results (units of each output)"));
    bool validated = true;  // every output's
    for (const auto& out : j1["outputs"]) {
      validated = validated && out["validation"]["gum_validated"].get<bool>();
    }
    EXPECT_EQ(report.find("<div class=\"headline\">The GUM&#39;s results are validated by", box) !=
                  std::string::npos,
              validated)
        << report.substr(box, 200);
    EXPECT_NE(report.find("Model file"), std::string::npos);
    EXPECT_NE(report.find(j1["model"].get<std::string>()), std::string::npos);
    fs::remove_all(a);
    fs::remove_all(b);
  }
}

}  // namespace
}  // namespace gearmc
