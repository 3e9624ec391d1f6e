// A path for a test's outputs under GoogleTest's temporary folder, unique per process (ctest runs
// test cases of one binary in parallel processes) and removed first, so a test starts clean. The
// process id comes first, so a tag's extension (`plan.dmi`, `gear.stl`) stays the file's.
#pragma once

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <string>

namespace gearmc::testing_support {

inline std::filesystem::path fresh_temp_path(const std::string& tag) {
  const std::filesystem::path p = std::filesystem::path(::testing::TempDir()) /
                                  ("gearmc_" + std::to_string(::getpid()) + "_" + tag);
  std::filesystem::remove_all(p);
  return p;
}

}  // namespace gearmc::testing_support
