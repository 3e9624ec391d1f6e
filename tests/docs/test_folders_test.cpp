// The tests' own hygiene, checked on their sources: ctest runs every test case in a process of
// its own, two at a time, so a test that writes under GoogleTest's shared TempDir() by a fixed
// name races with any other case using the same name (a CI run failed that way: one DMIS case
// removed the folder another was writing plan.dmi into). Every test therefore takes its paths
// from tests/support/temp_paths.h (unique per process) and no test source calls TempDir() itself.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <regex>
#include <string>

#include "tests/support/temp_paths.h"

namespace {

namespace fs = std::filesystem;

TEST(TestFolders, NoTestWritesUnderTheSharedTempFolderByAFixedName) {
  const fs::path root = fs::path(GEARMC_SOURCE_DIR) / "tests";
  const std::regex direct(R"(\bTempDir\(\))");
  int files = 0;
  for (const auto& entry : fs::recursive_directory_iterator(root)) {
    const std::string ext = entry.path().extension().string();
    if (ext != ".cpp" && ext != ".h") continue;
    const std::string rel = fs::relative(entry.path(), root).string();
    // The two helpers that make per-process names, and this file.
    if (rel == "support/temp_paths.h" || rel == "support/run_gearmc.h" ||
        rel == "docs/test_folders_test.cpp")
      continue;
    ++files;
    std::ifstream in(entry.path());
    int line_no = 0;
    for (std::string line; std::getline(in, line);) {
      ++line_no;
      EXPECT_FALSE(std::regex_search(line, direct))
          << "tests/" << rel << ":" << line_no << ": " << line
          << "\n  use testing_support::fresh_temp_path(tag) (unique per process)";
    }
  }
  EXPECT_GT(files, 100);
}

TEST(TestFolders, FreshTempPathsDifferBetweenProcessesAndStartEmpty) {
  // The path carries the process id, so two ctest processes never share it.
  const fs::path p = gearmc::testing_support::fresh_temp_path("hygiene");
  EXPECT_NE(p.filename().string().find(std::to_string(::getpid())), std::string::npos) << p;
  fs::create_directories(p);
  std::ofstream(p / "left_over") << "x";
  const fs::path again = gearmc::testing_support::fresh_temp_path("hygiene");
  EXPECT_EQ(again, p);
  EXPECT_FALSE(fs::exists(again / "left_over"));
}

}  // namespace
