// Prints docs/scenario-keys.md: the reference of every ranged number, generated from the
// readers' own range tables (scripts/update-docs writes it; tests/engine/docs_test.cpp checks
// that the committed page equals this output).
#include <iostream>

#include "engine/io/parameter_ranges.h"

int main() {
  std::cout << gearmc::range_reference_markdown();
  return 0;
}
