// Measured points without labels, matched to the model's gear: each point of a label-free point
// table (point_table.h: only the measured coordinates, compensated surface points E or stylus
// centres O) is assigned the flank it was measured on and its foot there, by projection onto
// the gear's nominal flanks (the involute helicoids of gears/involute_gear.h, without design
// modifications, as every reading's nominal point):
//   * the candidates: the point turned back to the section z = 0 (a helical gear's section turns
//     by z helix_turn_per_mm), the teeth next to its polar angle (the nearest tooth centre and
//     its neighbours; a tooth hint narrows them to one, a flank hint to one side, a nominal point
//     hint to the flank it lies on), both flanks;
//     the transverse closed form (InvoluteGear::transverse_position) picks the nearest;
//   * the foot: the flank point P(L, z) nearest to the measured point, by Gauss–Newton on
//     (L, z) from the transverse foot (exact in one step on a spur gear), to 1e-10 mm;
//   * the reading: p = P, n its outward unit normal, c = E + R n (surface points) or O (stylus
//     centres), so e = ((c − p)·n − R)·1000 µm = the deviation along n; the match distance is |e|.
// A point is refused (counted, its line named in a warning) when it has no foot on the flank's
// active part (roll length outside [L_min, L_max], height outside [0, b], inside the base
// circle), when its deviation exceeds `allowance_mm` (what the model's tolerances let a flank
// deviate), or when its normal hint is more than 5° off the matched normal. More than a tenth
// of the points refused is an InputError at the first one (these points are not of this gear).
// Grid labels for the diagnosis: per gear, tooth and flank, the points whose heights agree to
// 1 µm form one section (j counts the sections by height) and i counts a section's points by
// roll length — a profile scan is one section, a helix trace one section per point.
// Frames and units: the gear frame of docs/scenarios.md, mm.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "engine/plan/probing_grid.h"
#include "engine/readings/dmis_results.h"
#include "engine/readings/point_table.h"
#include "engine/readings/readings_csv.h"
#include "gears/involute_gear.h"

namespace gearmc {

// One point's match: the flank, the foot's parameters and point, the signed distance along
// the flank's outward normal (mm, of the measured point: E's deviation, or O's R + deviation).
struct FlankMatch {
  int tooth = 0;
  FlankSide side = FlankSide::kLeft;
  double roll_length_mm = 0.0, z_mm = 0.0;
  FlankPoint foot;
  double signed_distance_mm = 0.0;
  bool found = false;  // false: the point lies inside the base circle (no involute through it)
};

// The nearest flank point of the measured point M (mm, gear frame) among the candidate flanks.
FlankMatch match_to_flank(const InvoluteGear& gear, const Eigen::Vector3d& M,
                          std::optional<int> tooth_hint = std::nullopt,
                          std::optional<FlankSide> side_hint = std::nullopt);

// Grid labels of matched points (see the file comment): for each point its (i, j) from its flank
// (gear, tooth, side) and its foot (roll length, z in mm).
struct FlankOfPoint {
  int gear, tooth;
  FlankSide side;
};
std::vector<std::pair<int, int>> section_labels(const std::vector<FlankOfPoint>& flank_of,
                                                const std::vector<std::pair<double, double>>& feet);

// A user's DMIS program as the probing plan (`--plan`): each planned point (its F(…)=FEAT/POINT
// nominal) matched to its flank, in program order. Each must lie on the active flank of the
// scenario's gear within 1 µm and its vector along the flank's outward normal within 1°; else an
// InputError at its statement (file:line:column) saying what it is off by.
std::vector<ExplicitPlanPoint> plan_from_dmis(const InvoluteGear& gear,
                                              const std::vector<DmisPlanFeature>& features,
                                              const std::string& source);

// Why a table's points fit no flank of `gear`, for its refusal: where they lie (radii from the z
// axis, z range) against the gear's flanks, and the systematic cause when one explains them — a
// unit (scaled by 25.4, 1/25.4, 1e-3 or 1e3 their median radius lies on the flanks), a z datum
// other than the lower face, or the part turned about its axis (the rotation within one pitch,
// searched to half the allowance over up to 200 sampled points, that fits 90 % of them).
std::string describe_misfit(const InvoluteGear& gear, const UnlabelledPoints& table,
                            double allowance_mm);

// What the matching did, for diagnosis.json's `matching` block.
struct MatchingSummary {
  std::size_t points = 0;                               // in the table
  std::size_t refused = 0;                              // not matched (see the file comment)
  double max_distance_um = 0.0, rms_distance_um = 0.0;  // over the matched points
};

// The table's points as readings labelled by matching; refused points are left out, each named
// in `readings.warnings` (the first 10, then a count).
Readings match_unlabelled_points(const InvoluteGear& gear, const UnlabelledPoints& table,
                                 double allowance_mm, MatchingSummary* summary);

}  // namespace gearmc
