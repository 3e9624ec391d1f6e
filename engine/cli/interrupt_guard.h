// What the long-running commands (run, uncertainty) share to stop cleanly: a flag set by SIGINT or
// SIGTERM while a guard is alive, which the Monte-Carlo loops poll to stop within a moment
// (exit 130, nothing left behind), and an output folder removed on the way out if the command
// created it and left it empty. Internal to engine/cli.
#pragma once

#include <atomic>
#include <filesystem>

namespace gearmc {

// Set by SIGINT/SIGTERM while an InterruptGuard lives (a signal handler can only touch a
// lock-free atomic with static storage).
std::atomic<bool>& interrupted_flag();

// Installs the handler for SIGINT and SIGTERM for its lifetime (clearing the flag), then
// restores the old handlers.
class InterruptGuard {
 public:
  InterruptGuard();
  ~InterruptGuard();
  InterruptGuard(const InterruptGuard&) = delete;
  InterruptGuard& operator=(const InterruptGuard&) = delete;

 private:
  void (*old_int_)(int);
  void (*old_term_)(int);
};

// Removes `dir` on destruction if `created` and it is empty.
struct CreatedFolder {
  std::filesystem::path dir;
  bool created = false;
  ~CreatedFolder();
};

}  // namespace gearmc
