// Regression tests on the scenarios (the OpenMC pattern, docs/architecture.md principle 7): every
// scenarios/NAME.yaml is run through the gearmc executable with a small fixed number of gears
// and its own seed, and the run's summary.json — without the timing fields — is compared with
// the stored reference scenarios/NAME.ref.json.
//
// Comparison (reference_compare.h): counts (gears, contacts, collisions, n, ...) and strings
// exactly; real numbers to a relative 1e-9 (the run is otherwise bit-reproducible: tests/engine/
// run_test.cpp checks 1 thread against all threads exactly). The references of `simulate` and
// `diagnose` are in command_regression_test.cpp.
//
// Regenerating the references after an intended change of results:
//   scripts/update-references        (runs this test binary with --update)
// and say in the commit message why the results changed.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "tests/regression/reference_compare.h"
#include "tests/support/run_gearmc.h"
#include "tests/support/temp_paths.h"

using ::gearmc::testing_support::fresh_temp_path;

namespace gearmc {
namespace {

namespace fs = std::filesystem;
using nlohmann::ordered_json;
using testing_support::run_gearmc;

constexpr int kGears = 3;  // small: the whole suite stays within a few seconds

std::vector<std::string> scenario_stems() {
  std::vector<std::string> stems;
  for (const auto& entry : fs::directory_iterator(fs::path(GEARMC_SOURCE_DIR) / "scenarios")) {
    if (entry.path().extension() == ".yaml") stems.push_back(entry.path().stem().string());
  }
  std::sort(stems.begin(), stems.end());
  return stems;
}

// summary.json without what changes from run to run (timing, provenance: date, command, build
// commit) or from machine to machine (paths).
ordered_json regression_view(ordered_json summary) {
  // ranks and threads: the shape of the job, the only other fields that may differ (every other
  // byte is the same for any number of ranks and threads, tests/mpi/mpi_identity.sh).
  for (const char* key : {"wall_s", "contacts_per_s", "source", "provenance", "ranks", "threads"}) {
    summary.erase(key);
  }
  return summary;
}

class ScenarioRegression : public ::testing::TestWithParam<std::string> {};

TEST_P(ScenarioRegression, MatchesStoredReference) {
  const std::string stem = GetParam();
  const fs::path scenarios = fs::path(GEARMC_SOURCE_DIR) / "scenarios";
  const fs::path reference_path = scenarios / (stem + ".ref.json");
  const fs::path out = fresh_temp_path("regression_" + stem);
  fs::remove_all(out);
  const auto result = run_gearmc("run " + (scenarios / (stem + ".yaml")).string() + " --gears " +
                                 std::to_string(kGears) + " --quiet --out " + out.string());
  ASSERT_EQ(result.exit_code, 0) << result.err;
  std::ifstream summary_file(out / "summary.json");
  ASSERT_TRUE(summary_file) << "no summary.json in " << out;
  const ordered_json actual = regression_view(ordered_json::parse(summary_file));
  fs::remove_all(out);

  if (regression::update_mode()) {
    ordered_json reference;
    reference["_about"] =
        "Regression reference of scenarios/" + stem + ".yaml: summary.json of `gearmc run " +
        "scenarios/" + stem + ".yaml --gears " + std::to_string(kGears) +
        "` without timing fields. Written by scripts/update-references; compared by "
        "tests/regression/regression_test.cpp.";
    for (const auto& [key, value] : actual.items()) reference[key] = value;
    std::ofstream(reference_path) << reference.dump(2) << "\n";
    GTEST_SKIP() << "reference written: " << reference_path;
  }

  std::ifstream reference_file(reference_path);
  ASSERT_TRUE(reference_file) << "no stored reference " << reference_path
                              << "; create it with scripts/update-references";
  const std::string report =
      regression::differences_from(ordered_json::parse(reference_file), actual);
  EXPECT_TRUE(report.empty())
      << "scenario " << stem << " differs from " << reference_path << ":\n"
      << report
      << "If the change is intended, run scripts/update-references and give the reason in the "
         "commit message.";
}

INSTANTIATE_TEST_SUITE_P(Scenarios, ScenarioRegression, ::testing::ValuesIn(scenario_stems()),
                         [](const ::testing::TestParamInfo<std::string>& param_info) {
                           return param_info.param;
                         });

}  // namespace
}  // namespace gearmc

int main(int argc, char** argv) {
  std::vector<char*> args;
  for (int i = 0; i < argc; ++i) {
    if (std::strcmp(argv[i], "--update") == 0) {
      gearmc::regression::update_mode() = true;
    } else {
      args.push_back(argv[i]);
    }
  }
  // InitGoogleTest removes the flags it recognises by shifting the array down to and including
  // argv[argc], which the C and C++ standards require to be a null pointer: keep that terminator
  // (without it every --gtest_* flag read one element past the end of `args`).
  int count = static_cast<int>(args.size());
  args.push_back(nullptr);
  ::testing::InitGoogleTest(&count, args.data());
  return RUN_ALL_TESTS();
}
