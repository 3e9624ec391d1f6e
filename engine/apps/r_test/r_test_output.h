// The presentations of an R-Test evaluation (r_test_evaluation.h): the `r_test` section of
// uncertainty.json, the terminal text of `gearmc uncertainty` and report.html (instrument sketch
// seen from above, calibration residuals, the budget per input, the predictions against the
// verification errors). Numbers are shown in µm (the evaluation works in mm).
#pragma once

#include <nlohmann/json.hpp>
#include <ostream>
#include <string>

#include "core/provenance.h"
#include "engine/apps/r_test/r_test_evaluation.h"
#include "engine/apps/uncertainty/model.h"

namespace gearmc::rtest {

// uncertainty.json for an r_test model: model, source, seed, coverage_probability, trials,
// inputs, and "r_test" (docs/formats.md).
nlohmann::ordered_json r_test_json(const uncertainty::UncertaintyModel& model, const RTestModel& m,
                                   const RTestResult& r, const RTestRunOptions& o,
                                   const Provenance& provenance);

void print_r_test(std::ostream& out, const RTestModel& m, const RTestResult& r);

std::string r_test_report_html(const uncertainty::UncertaintyModel& model, const RTestModel& m,
                               const RTestResult& r, const Provenance& provenance);

}  // namespace gearmc::rtest
