// Readings from a CMM's DMIS output: the results of running the plan `gearmc export-plan` wrote
// (engine/plan/dmis_plan.h). A DMIS output file holds, per measured point, the nominal
// feature F(label)=FEAT/POINT,CART,x,y,z,i,j,k (point and outward normal) and the actual one
// FA(label)=FEAT/POINT,CART,x,y,z,i,j,k: the point the CMM reports, already radius-compensated
// along the nominal normal (E = O − R n, docs/formats.md). The label names tooth, flank and grid
// indices (T001L_I03_J07), so each result becomes one readings row:
//   p, n = the nominal feature's point and normal (n normalised),
//   c = E + R n, the stylus centre the CMM recorded (so e = ((c − p)·n − R)·1000 µm is the
//   reading along n, as for the CSV), with R the stylus radius the points were compensated with,
//   order = the position of the FA record in the file, gear 0 (one measurement per file).
// The program's OUTPUT/F(label) and OUTPUT/FA(label) statements make the CMM write exactly these
// two records per point; the actuals of the operator's set-up features (labels SETUP_…) are
// skipped. Keywords are case-insensitive; `$$` starts a comment; a line ending in `$` continues on
// the next. Other statements are skipped. Bad input — a malformed FEAT/POINT, a number that is not
// finite, a label not of the plan's form, an actual without its nominal, a point measured twice,
// no results, a statement longer than kMaxDmisStatementBytes, a coordinate or a reading beyond
// the readings ranges (engine/schema/parameter_ranges.cpp, as for the CSV) — is one InputError
// with file:line:column (exit 2). Lengths are in the unit of the last UNITS statement before
// them (MM, CM, METER, INCH, FEET; MM when none), converted to mm; another unit is refused.
#pragma once

#include <Eigen/Core>
#include <cstddef>
#include <string>
#include <vector>

#include "engine/readings/readings_csv.h"

namespace gearmc {

// Longest DMIS statement read (continuation lines joined): a FEAT/POINT of 6 numbers is under
// 200 bytes; the longest statements of real programs are a few kB.
inline constexpr std::size_t kMaxDmisStatementBytes = 16384;

// True when `path` names a DMIS file by its extension (.dmo, .dmi, .dms, .dmis; any case).
bool is_dmis_file(const std::string& path);

Readings parse_dmis_results(const std::string& text, const std::string& source_name,
                            double stylus_radius_mm);
Readings read_dmis_results(const std::string& path, double stylus_radius_mm);

// The planned points of a DMIS program (`--plan PROGRAM.dmi`): its nominal features
// F(label)=FEAT/POINT,CART,x,y,z,i,j,k in program order (the operator's set-up features SETUP_…
// left out), lengths in mm, the vector normalised; where each stands (line, label and values
// columns). Statements as above; no planned point is an InputError.
struct DmisPlanFeature {
  std::string label;
  Eigen::Vector3d point, vector;
  int line = 0, label_column = 0, values_column = 0;
};
std::vector<DmisPlanFeature> parse_dmis_plan(const std::string& text, const std::string& source);
std::vector<DmisPlanFeature> read_dmis_plan(const std::string& path);

}  // namespace gearmc
