// Interrupt flag, its guard and the created-folder clean-up (see interrupt_guard.h).
#include "engine/cli/interrupt_guard.h"

#include <csignal>

#include "core/output_files.h"

namespace gearmc {
namespace {

std::atomic<bool> g_interrupted{false};
extern "C" void on_interrupt(int) { g_interrupted.store(true); }

}  // namespace

std::atomic<bool>& interrupted_flag() { return g_interrupted; }

InterruptGuard::InterruptGuard() {
  g_interrupted.store(false);
  old_int_ = std::signal(SIGINT, on_interrupt);
  old_term_ = std::signal(SIGTERM, on_interrupt);
}

InterruptGuard::~InterruptGuard() {
  std::signal(SIGINT, old_int_);
  std::signal(SIGTERM, old_term_);
}

CreatedFolder::~CreatedFolder() {
  if (created) remove_if_empty(dir);
}

}  // namespace gearmc
