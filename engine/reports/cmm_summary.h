// What a run says of its `cmm:` section (docs/cmm.md): summary.json's `cmm` block and the one
// sentence the terminal and report.html show — the data sheet, how many machines were drawn and
// kept, and how close their acceptance tests came to the MPEs.
#pragma once

#include <nlohmann/json.hpp>
#include <string>

namespace gearmc {

struct CmmModel;

// summary.json's `cmm` block.
nlohmann::ordered_json cmm_summary_json(const CmmModel& cmm);

// "CMM from its data sheet: MPE_E = 1.8 + L/300 µm, MPE_P = 1.7 µm (bridge, 700 × 1000 × 600 mm):
// 200 machines kept of 580 drawn (34.5 %); …"
std::string cmm_summary_sentence(const CmmModel& cmm);

}  // namespace gearmc
