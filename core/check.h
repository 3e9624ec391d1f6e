// GEARMC_CHECK(condition, message): an invariant check that stays on in every build, Release
// (NDEBUG) included. A broken invariant is a bug in gearmc, not bad input (docs/architecture.md,
// principle 4: bad input is an InputError; a broken invariant stops the program): the check
// prints "<file>:<line>: gearmc internal error: <message> (failed: <condition>)" to stderr and
// ends the process with exit code 4, the code of every internal error (an exception that is not
// an InputError exits with it too, engine/cli/app.cpp). Use it where continuing would compute a
// wrong number; the condition should be cheap.
// In core/ so that every library (core, gears, surfaces, engine) can use it.
#pragma once

#include <cstdio>
#include <cstdlib>

namespace gearmc {

// The exit code of an internal error (a bug, or an I/O failure), for every command; 2 is bad
// input, 1 and 3 are verdicts of `check`.
inline constexpr int kInternalErrorExit = 4;

}  // namespace gearmc

namespace gearmc::detail {

[[noreturn]] inline void check_failed(const char* file, int line, const char* condition,
                                      const char* message) {
  std::fprintf(stderr, "%s:%d: gearmc internal error: %s (failed: %s)\n", file, line, message,
               condition);
  std::fflush(stderr);
  std::_Exit(kInternalErrorExit);
}

}  // namespace gearmc::detail

// `message`: a string literal (or other const char*) saying what should have held.
#define GEARMC_CHECK(condition, message)                                       \
  do {                                                                         \
    if (!(condition)) [[unlikely]] {                                           \
      ::gearmc::detail::check_failed(__FILE__, __LINE__, #condition, message); \
    }                                                                          \
  } while (false)
