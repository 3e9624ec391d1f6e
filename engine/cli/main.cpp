// Entry point of the gearmc executable: everything happens in run_cli (engine/cli/app.h). Under
// mpirun every rank runs it; only rank 0 prints (the other ranks' output goes nowhere), so a job
// shows one progress line and one message, and all ranks return the same exit code.
#include <iostream>
#include <sstream>

#include "core/ranks.h"
#include "engine/cli/app.h"

int main(int argc, char** argv) {
  const gearmc::MpiSession mpi(&argc, &argv);
  if (gearmc::Ranks::world().is_root()) return gearmc::run_cli(argc, argv, std::cout, std::cerr);
  std::ostringstream out, err;  // rank > 0: discarded
  return gearmc::run_cli(argc, argv, out, err);
}
