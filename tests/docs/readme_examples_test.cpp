// The README's examples run as written: the diagnose example's truth and model scenarios ship in
// scenarios/diagnose/, and diagnosing readings simulated from the truth names the hidden effect
// (6-lobed pre-travel of 0.75 µm) with its amplitude within 3 standard errors of the truth.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "tests/support/run_gearmc.h"
#include "tests/support/temp_paths.h"

using ::gearmc::testing_support::fresh_temp_path;

namespace gearmc {
namespace {

namespace fs = std::filesystem;
using testing_support::run_gearmc;

TEST(ReadmeExamples, DiagnoseFindsTheLobingOfTheShippedTruth) {
  const std::string scenarios = std::string(GEARMC_SOURCE_DIR) + "/scenarios/diagnose/";
  const fs::path dir = fresh_temp_path("readme_diagnose");
  fs::remove_all(dir);
  fs::create_directories(dir);
  const std::string readings = (dir / "lobing.csv").string();
  const auto simulated =
      run_gearmc("simulate " + scenarios + "lobing_truth.yaml --master --out " + readings);
  ASSERT_EQ(simulated.exit_code, 0) << simulated.err;
  const auto diagnosed = run_gearmc("diagnose --model " + scenarios + "lobing_model.yaml " +
                                    "--measured " + readings + " --out " + (dir / "out").string());
  ASSERT_EQ(diagnosed.exit_code, 0) << diagnosed.err;
  const auto j = nlohmann::json::parse(std::ifstream(dir / "out" / "diagnosis.json"));
  EXPECT_EQ(j["named_effect"], "probe_lobing");
  EXPECT_TRUE(j["gap_detected"].get<bool>());
  // The truth (lobing_truth.yaml): amplitude 0.75 µm of the 6th harmonic.
  const auto& effect = j["effects"][0];
  const double amplitude = effect["parameters"]["amplitude_6_um"].get<double>();
  const double se = effect["std_errors"]["amplitude_6_um"].get<double>();
  EXPECT_NEAR(amplitude, 0.75, 3.0 * se);
}

TEST(ReadmeExamples, TheUncertaintyExamplePrintsWhatTheReadmeShows) {
  // The README's `gearmc uncertainty` block, run as written (with --out into a temporary
  // folder): every printed line of the README's block except the timing and report lines must
  // be in the command's output (the run is deterministic: seed 1, 10^6 trials). The numbers
  // themselves are checked against JCGM 101 §9.3 in uncertainty_mcm_test.cpp and
  // uncertainty_gum_test.cpp.
  std::ifstream readme(std::string(GEARMC_SOURCE_DIR) + "/README.md");
  std::vector<std::string> expected;
  bool inside = false;
  for (std::string line; std::getline(readme, line);) {
    if (line.rfind("$ build/gearmc uncertainty scenarios/uncertainty/mass_calibration.yaml", 0) ==
        0) {
      inside = true;
      continue;
    }
    if (inside && line.rfind("```", 0) == 0) break;
    if (inside && !line.empty() && line.rfind("MCM: ", 0) != 0 && line.rfind("report: ", 0) != 0) {
      expected.push_back(line);
    }
  }
  ASSERT_GE(expected.size(), 8u) << "the README's uncertainty block was not found";
  const fs::path dir = fresh_temp_path("readme_uncertainty");
  fs::remove_all(dir);
  const auto r = run_gearmc("uncertainty " + std::string(GEARMC_SOURCE_DIR) +
                            "/scenarios/uncertainty/mass_calibration.yaml --out " + dir.string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string printed = r.out + r.err;  // the README shows the warnings too
  for (const std::string& line : expected) {
    EXPECT_NE(printed.find(line), std::string::npos) << "README line not printed: " << line << "\n"
                                                     << printed;
  }
}

}  // namespace
}  // namespace gearmc
