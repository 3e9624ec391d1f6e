// Prints docs/scenario-keys.md: every scenario key with its type, default and allowed values,
// and the units and ranges of every number, generated from the readers' own key and range
// tables (scripts/update-docs writes it; tests/docs/docs_test.cpp checks that the committed
// page equals this output).
#include <iostream>

#include "engine/schema/parameter_ranges.h"
#include "engine/schema/scenario_keys.h"

int main() {
  std::cout << gearmc::scenario_keys_markdown();
  return 0;
}
