// A path for a test's outputs under GoogleTest's temporary folder, unique per process (ctest runs
// test cases of one binary in parallel processes) and removed first, so a test starts clean.
#pragma once

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <string>

namespace gearmc::testing_support {

inline std::filesystem::path fresh_temp_path(const std::string& tag) {
  const std::filesystem::path p = std::filesystem::path(::testing::TempDir()) /
                                  ("gearmc_" + tag + "_" + std::to_string(::getpid()));
  std::filesystem::remove_all(p);
  return p;
}

}  // namespace gearmc::testing_support
