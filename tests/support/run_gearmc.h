// Runs the gearmc executable as a user would (GEARMC_BINARY, set by tests/CMakeLists.txt) and
// returns its exit code, standard output and standard error; a sanitizer report on its standard
// error fails the calling test.
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
                               std::to_string(::getpid()) + "_" + std::to_string(calls++) + ".txt";
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
  // A sanitizer report from the child (scripts/test --sanitize builds gearmc with ASan, LSan and
  // UBSan) fails the calling test even when that test expects a non-zero exit code.
  if (err.find("ERROR: AddressSanitizer") != std::string::npos ||
      err.find("ERROR: LeakSanitizer") != std::string::npos ||
      err.find("SUMMARY: UndefinedBehaviorSanitizer") != std::string::npos) {
    ADD_FAILURE() << "sanitizer report from `gearmc " << args << "`:\n" << err;
  }
  // Killed by a signal (a crash, an abort): report it as a shell does, 128 + signal number, never
  // as the 0 that WEXITSTATUS would give.
  if (status == -1) return {-1, out, err};
  if (WIFSIGNALED(status)) return {128 + WTERMSIG(status), out, err};
  return {WEXITSTATUS(status), out, err};
}

}  // namespace gearmc::testing_support
