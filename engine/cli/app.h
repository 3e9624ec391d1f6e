// The gearmc command line (docs/formats.md, "Subcommands"): parses the arguments with CLI11 and
// dispatches to the commands. Bad input of any kind ends with one message on stderr and exit
// code 2; run_cli never throws.
#pragma once

#include <iosfwd>

namespace gearmc {

int run_cli(int argc, const char* const* argv, std::ostream& out, std::ostream& err);

}  // namespace gearmc
