// Entry point of the gearmc executable: everything happens in run_cli (engine/cli/app.h).
#include <iostream>

#include "engine/cli/app.h"

int main(int argc, char** argv) { return gearmc::run_cli(argc, argv, std::cout, std::cerr); }
