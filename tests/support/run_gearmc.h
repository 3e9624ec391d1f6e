// Runs the gearmc executable as a user would (GEARMC_BINARY, set by tests/CMakeLists.txt) and
// returns its exit code, standard output and standard error.
#pragma once

#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <string>

namespace gearmc::testing_support {

struct CommandResult {
  int exit_code;
  std::string out, err;
};

inline CommandResult run_gearmc(const std::string& args) {
  // One file per process and call: ctest runs test processes in parallel.
  static int calls = 0;
  const std::string err_file = ::testing::TempDir() + "gearmc_command_err_" +
                               std::to_string(::getpid()) + "_" + std::to_string(calls++) +
                               ".txt";
  const std::string cmd = std::string(GEARMC_BINARY) + " " + args + " 2>" + err_file;
  FILE* pipe = popen(cmd.c_str(), "r");
  std::string out;
  std::array<char, 4096> buf;
  size_t n;
  while ((n = fread(buf.data(), 1, buf.size(), pipe)) > 0) out.append(buf.data(), n);
  const int status = pclose(pipe);
  std::ifstream e(err_file);
  std::string err((std::istreambuf_iterator<char>(e)), std::istreambuf_iterator<char>());
  std::remove(err_file.c_str());
  return {WEXITSTATUS(status), out, err};
}

}  // namespace gearmc::testing_support
