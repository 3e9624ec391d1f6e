// Probing plan: where on each flank the CMM probes. Per flank an N x M grid, N points along
// the profile (equal steps in roll length) and M sections across the face width, kept a
// margin away from each edge of the flank (P1: N = 10, M = 5, 5 % margins, docs/sources.md).
// The flank extent is the active involute: roll length from the form circle to the tip
// circle, z from 0 to b. Lengths mm.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "gears/involute_gear.h"
#include "gears/point_key.h"

namespace gearmc {

// How the N profile points are spaced between the margins: equal steps in roll length (the
// ISO profile abscissa, default), in arc length along the involute (s = L^2 / (2 r_b)), or in
// radius (r = sqrt(r_b^2 + L^2)).
enum class ProfileSpacing { kRollLength, kArcLength, kRadius };

struct ProbingGridSpec {
  int points_along_profile = 10;  // N
  int sections_across_face = 5;   // M
  double margin_fraction = 0.05;  // of the extent, at each end of both directions
  ProfileSpacing spacing = ProfileSpacing::kRollLength;
};

// Which flanks a run probes.
// The order in which a CMM probes the planned points (drift and other time-dependent effects
// depend on it). Within a flank the grid is always scanned section by section, along the
// profile within a section (plan_flank's order).
enum class ProbingOrder {
  kToothByTooth,  // tooth after tooth (in the plan's tooth order): its L flank, then its R flank
  kSideBySide,    // every tooth's L flank, then every tooth's R flank
};

// One point of a plan given point by point (a user's DMIS program, `--plan`): its flank, grid
// labels (sections and points in them, as engine/readings/point_matching.h counts them) and
// flank parameters (roll length and height, mm).
struct ExplicitPlanPoint : GridPosition {
  double roll_length_mm = 0.0, z_mm = 0.0;
};

struct ProbingPlanSpec {
  ProbingGridSpec grid;
  std::vector<int> teeth;  // 1-based tooth numbers; empty = every tooth
  bool left = true, right = true;
  ProbingOrder order = ProbingOrder::kToothByTooth;
  // A plan point by point, in probing order (`--plan PROGRAM.dmi`); empty: the grid above with
  // teeth, flanks and order.
  std::vector<ExplicitPlanPoint> points;
};

// One planned point: nominal position and outward normal, its grid indices (0-based).
struct PlannedPoint : GridPosition {
  double roll_length_mm = 0.0;    // ISO roll length L of the point
  double z_mm = 0.0;              // height above the lower face
  Eigen::Vector3d point, normal;  // the nominal point (mm) and its outward unit normal
};

// The grid's roll lengths and heights (shared by every flank of the gear).
struct ProbingGridCoordinates {
  std::vector<double> roll_lengths, heights;
};
ProbingGridCoordinates probing_grid_coordinates(const InvoluteGear& gear,
                                                const ProbingGridSpec& spec);

// The planned points of one flank, profile index fastest.
std::vector<PlannedPoint> plan_flank(const InvoluteGear& gear, const ProbingGridSpec& spec,
                                     int tooth, FlankSide side);

// Every planned point of the plan, in probing order (the position in the vector is the point's
// `order`).
std::vector<PlannedPoint> probing_sequence(const InvoluteGear& gear, const ProbingPlanSpec& plan);

}  // namespace gearmc
