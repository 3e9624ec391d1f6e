// What `gearmc check` writes and prints, composed from a finished CheckRun: check.json (the
// claims' verdicts, estimates and bounds, the method, the run's size and provenance), the JUnit
// XML of the verdicts (one testcase per claim, a <failure> for "fails" and "undecided", so CI
// servers show claims as tests), report.html (per claim: the statement, the numbers and the
// histogram of the quantity with the limit and the confidence bounds marked) and one terminal
// line per claim. Units: µm, seconds.
#pragma once

#include <nlohmann/json.hpp>
#include <string>

#include "core/provenance.h"
#include "engine/apps/check/sequential_check.h"
#include "engine/scenario/scenario.h"

namespace gearmc {

struct CheckContext {
  const Scenario* scenario = nullptr;
  Provenance provenance;
  int max_gears = kDefaultMaxGears;
  int threads = 0;  // as asked (0: all cores)
  int ranks = 1;    // processes of the MPI job
  // The run report of the gears the claims rest on, relative to check's report (empty: none).
  std::string run_report;
};

// True when every claim holds.
bool all_claims_hold(const CheckRun& run);

// The exit code of `check`: 0 every claim holds, 1 a claim fails, 3 no claim fails but one is
// undecided at the gear budget (docs/check.md, "Exit codes").
int check_exit_code(const CheckRun& run);

// "max δRcomp per flank (both sides) quantile 0.9973 ≤ 4 µm at 95 % confidence".
std::string claim_statement(const ClaimSpec& claim);

nlohmann::ordered_json check_json(const CheckContext& context, const CheckRun& run);
std::string check_junit_xml(const CheckContext& context, const CheckRun& run);
std::string check_report_html(const CheckContext& context, const CheckRun& run);
// "p1_4um  fails  estimate 4.21 µm  bound [4.05, 4.40] µm  (limit ≤ 4 µm)  1024 gears  2.1 s".
std::string claim_terminal_line(const ClaimSpec& claim, const ClaimResult& result,
                                std::size_t name_width);

}  // namespace gearmc
