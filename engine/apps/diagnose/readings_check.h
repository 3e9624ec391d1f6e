// What `gearmc diagnose` refuses as bad input beyond the readings file's own syntax (which the
// readings reader checks): rows that cannot belong to the model's gear and probing plan, and
// rows whose residual is not a number the diagnosis can compute with. Each refusal is one
// InputError naming the readings file, the CSV line and the column of the field, the value and
// the allowed range (exit code 2), so no diagnosis is made on them.
//  * check_readings_against_model: tooth in 1 … z (the model gear's number of teeth), grid
//    indices i in 0 … N − 1 and j in 0 … M − 1 (the model's probing grid, N points along the
//    profile and M sections across the face), gear index ≤ kMaxGearIndex, and the header's
//    stylus radius in (0, kMaxStylusRadiusMm] (a larger ball cannot probe a gear tooth space;
//    the bound keeps the model's contact computations finite), and the nominal point p on the
//    gear: √(px² + py²) ≤ tip radius + one module, −m ≤ pz ≤ b + m (face width b). A point far
//    off the gear would enter the effects' columns (scale, squareness: c·n) with a lever of its
//    distance and make every fitted number meaningless. The header's stylus radius must be the
//    model's (stylus.radius_mm). Every nominal point must lie on the model gear's nominal flank
//    of its tooth and side (at its own radius and height) within what the model's tolerances
//    let the flank deviate (F_r + profile and helix total + thickness allowance and tolerance,
//    at least 10 µm), with its normal within 1° of the flank's: readings of another gear are
//    refused with the gear their points fit (base diameter, z and m from the line of action of
//    each point and the start angles of the measured teeth).
//  * check_residuals: every measured deviation, prediction and residual finite, and the
//    measured deviation along n within ±kMaxDeviationUm (1 km): a reading farther than that
//    from its nominal point is not a reading of a gear flank, and keeping |r| ≤ 10⁹ µm keeps
//    every sum of squares of the diagnosis finite (10⁶ readings × (10⁹ µm)² / (10⁻⁶ µm)² ≪
//    10³⁰⁸).
// Lines are found by reading the file again (only when a row is refused): a data row is a
// non-empty line not starting with '#' after the column line, as the reader counts them. With
// no readable file (readings built in memory) the location is "<readings>" and the row number.
#pragma once

#include <string>

#include "engine/apps/diagnose/prediction.h"
#include "engine/readings/readings_csv.h"
#include "engine/scenario/scenario.h"

namespace gearmc {

inline constexpr double kMaxDeviationUm = 1e9;
inline constexpr double kMaxStylusRadiusMm = 100.0;
// The largest gear index a readings row may carry (a batch of a million gears).
inline constexpr int kMaxGearIndex = 999999;

// How far (mm) a reading's nominal point may lie from the model's nominal flank (and a
// label-free point from the flank it is matched to, point_matching.h): what the model's
// tolerances let the real flank deviate (runout, profile and helix total, thickness allowance
// and tolerance, when the tolerance set has them), at least 10 µm.
double nominal_point_allowance_mm(const Scenario& model, const InvoluteGear& gear);

void check_readings_against_model(const Scenario& model, const Readings& readings,
                                  const std::string& readings_path);

// `residuals.points[k]` belongs to `readings.rows[k]`.
void check_residuals(const Residuals& residuals, const Readings& readings,
                     const std::string& readings_path);

}  // namespace gearmc
