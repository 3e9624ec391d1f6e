// Clearance moves of the DMIS program (engine/plan/dmis_plan.h): the path of the stylus between
// the touches of the probing plan, so that no move runs the ball or the shaft into the gear.
// Every touch starts and ends at its pre-position q = p + (R + a) n (ball centre, a the approach
// distance: SNSET/APPRCH and SNSET/RETRCT are both a, so the CMM's touch runs from q along −n to
// the flank and back to q). Between two touches of one trace (one flank, one section j, along
// the profile) the stylus moves straight from pre-position to pre-position when that segment
// keeps the ball at least a/2 off both flanks of the tooth space and the root circle (and the
// shaft, when there is one, r_s + a/2 off them), checked every 0.05 mm along the segment with
// the closed-form transverse distances of gears/involute_gear.h (InvoluteGear::
// transverse_position, times cos β_b for the normal distance of a helicoid). Otherwise, and
// always between flanks, teeth or sections, the stylus leaves the tooth space and comes back
// from above:
//   spur gear: straight up along +Z from q to the clearance height z = b + h (the tooth space
//     is a prism, so what is clear at q is clear above it), across at that height, down above
//     the next pre-position;
//   helical gear: the tooth space turns with z, so first radially out of the space in q's
//     section (away from the axis beyond the tip circle, r = r_a + R + c; on a ring gear towards
//     the axis, r = r_a − R − c; c = max(a, 1 mm)): in a transverse section the distance to both
//     flanks of the space, r_b (±(φ − φ_flank) − inv α + inv α_r), grows monotonically along the
//     radius out of the space, so the ball and an axial shaft (which lies in the sections above
//     the ball at the same x, y) stay clear; a radial shaft slides along itself. Then up to the
//     clearance height outside the tip circle, across, down outside the tip circle of the next
//     section and radially in to the next pre-position.
// The clearance height h is at least 2R + 5 mm above the upper face (z = b). A radial shaft
// cannot stay one fixed direction over the whole gear: each trace gets its own indexed sensor
// orientation (the horizontal radial direction through the trace's middle pre-position), selected
// at the clearance height. Lengths mm, gear frame (axis +Z, z = 0 lower face, tooth 1 on +X).
#pragma once

#include <Eigen/Core>
#include <vector>

#include "engine/plan/probing_grid.h"
#include "gears/involute_gear.h"

namespace gearmc {

// The stylus as the move planner sees it (the plan layer's copy of the scenario's stylus; the
// collision model of the contact layer, engine/contact/tooth_space.h, is the same shape).
enum class PlanShaftAxis {
  kNone,    // no shaft given: only the ball is kept clear
  kAxial,   // parallel to the gear axis, up from the ball (the probe comes from above)
  kRadial,  // horizontal, radially out of the tooth space (into a ring gear's, from the axis)
};

struct PlanStylus {
  double ball_radius_mm = 0.5;   // R
  double shaft_radius_mm = 0.0;  // r_s (0 with kNone)
  PlanShaftAxis shaft = PlanShaftAxis::kNone;
};

// One sensor orientation: the shaft direction u (unit, from the ball centre towards the probe
// head; +Z for an axial stylus or a ball alone).
struct SensorOrientation {
  Eigen::Vector3d shaft_direction = Eigen::Vector3d::UnitZ();
};

// The moves before one touch: `lift` leaves the previous touch's pre-position and ends at the
// clearance height (empty for a direct move within a trace, and for the first touch), then the
// sensor `sensor` is selected (when `select_sensor`), then `descent` ends at the touch's
// pre-position (ball-centre positions, the program's GOTO targets).
struct TouchMoves {
  std::vector<Eigen::Vector3d> lift, descent;
  bool select_sensor = false;
  int sensor = 0;
  Eigen::Vector3d pre_position;  // q = p + (R + a) n
};

struct ClearancePlan {
  double clearance_height_mm = 0.0;  // z of the ball centre above the gear: b + h
  double stylus_length_mm = 0.0;     // from the ball centre to the head the moves need
  std::vector<SensorOrientation> sensors;
  std::vector<TouchMoves> touches;          // one per planned point, in probing order
  std::vector<Eigen::Vector3d> final_lift;  // after the last touch, up to the clearance height
  int direct_moves = 0, lifted_moves = 0;   // how the touches were reached (the first is lifted)
};

// The clearance height above the upper face the planner uses, h = max(clearance_mm, 2R + 5 mm).
double clearance_above_face_mm(const PlanStylus& stylus, double clearance_mm);

// The moves for `sequence` (probing order) on `gear` with approach (and retract) distance
// `approach_mm`. Throws InputError when the stylus cannot leave the space (a ring gear whose
// tip circle is too small for the ball, r_a − R − c ≤ 0).
ClearancePlan plan_clearance_moves(const InvoluteGear& gear,
                                   const std::vector<PlannedPoint>& sequence,
                                   const PlanStylus& stylus, double approach_mm,
                                   double clearance_mm = 0.0);

// The smallest margin (mm) between the stylus at ball centre `centre` (shaft along `shaft`, of
// length `shaft_length_mm`) and the nominal gear, as the planner sees it: the ball's and shaft's
// normal distance to both flanks of the tooth space the point lies in (its section, extended
// involutes) and to the root circle, minus R (ball) or r_s (shaft); +infinity above or below the
// gear and beyond the tip circle. Negative: the stylus is in the material.
double stylus_margin_mm(const InvoluteGear& gear, const PlanStylus& stylus,
                        const Eigen::Vector3d& centre, const Eigen::Vector3d& shaft,
                        double shaft_length_mm);

}  // namespace gearmc
