// The thread count of a command (`--threads T`): with T > 0 parallel work runs on exactly T
// oneTBB threads, also above the machine's core count (the global limit allows them, the arena
// asks for them), so a thread-independence check with 2 threads really runs 2 threads on a
// 1-CPU machine; with T = 0 oneTBB's default (all cores). Results never depend on T: the
// parallel code reduces in a fixed order.
#pragma once

#include <tbb/global_control.h>
#include <tbb/task_arena.h>

#include <cstddef>
#include <optional>

namespace gearmc {

class ThreadArena {
 public:
  explicit ThreadArena(int threads) {
    if (threads > 0) {
      limit_.emplace(tbb::global_control::max_allowed_parallelism,
                     static_cast<std::size_t>(threads));
      arena_.emplace(threads);
    }
  }
  // Runs `work` (which may start oneTBB parallel loops) within the thread limit.
  template <typename F>
  void run(F&& work) {
    if (arena_) {
      arena_->execute(work);
    } else {
      work();
    }
  }

 private:
  std::optional<tbb::global_control> limit_;
  std::optional<tbb::task_arena> arena_;
};

}  // namespace gearmc
