// The stylus in the tooth space: whether ball and shaft, on their way to a contact, stay clear
// of the rest of the tooth space (the facing flank of the neighbouring tooth, the root circle,
// and for the shaft also the probed flank itself, which a helical flank's twist carries across
// the shaft above the ball). Nominal geometry (deviations are microns; the clearances are about
// the stylus's size). Datum frame, mm.
#pragma once

#include "engine/contact/contact.h"
#include "gears/involute_gear.h"

#include <Eigen/Core>
#include <cstdint>

namespace gearmc {

// Where the stylus shaft (the stem) points from the ball.
enum class ShaftAxis : std::uint8_t {
  kZ,       // parallel to the gear axis, up past the top face z = b (the gear stands on its
            // lower face, the probe comes from above)
  kRadial,  // horizontal, along the radius through the ball centre: out of an external gear's
            // tooth space, into a ring gear's towards the axis
};

// The stylus's shape as far as collisions go: the ball radius R, the radius of the shaft (a
// cylinder about its axis) and the axis. shaft_radius_mm 0: the shaft is not modelled
// (`stylus.shaft_diameter_mm` absent).
struct StylusShape {
  double radius_mm = 0.5;
  double shaft_radius_mm = 0.0;
  ShaftAxis shaft_axis = ShaftAxis::kZ;
};

// Whether the stylus, on its way from `approach_mm` outside the planned point to the contact
// centre O (both along n), stays clear of the rest of the tooth space of the flank `tooth`,
// `side`: the ball of the facing flank of the neighbouring tooth (and its tip corner) and of the
// root circle; the shaft of both flanks and the root. Sets status kCollision and the reason
// (neighbour_flank, root, shaft, in this order) when it does not.
void check_tooth_space(const InvoluteGear& gear, int tooth, FlankSide side,
                       const Eigen::Vector3d& n, const StylusShape& stylus, double approach_mm,
                       ContactResult* result);

// The clearances check_tooth_space tests (mm; negative = an overlap), the smallest over the
// stations of the approach from centre + approach_mm n to `centre`:
// - facing_flank_mm: the ball's distance to the facing flank minus R (of a helical gear a lower
//   bound, see the .cpp);
// - root_mm: the ball's distance from the root circle (outside it; inside an internal gear's);
// - shaft_mm: the shaft's smallest distance to the probed flank, the facing flank and the root
//   circle over its length, a lower bound within 0.1 µm of it where it is below 0.1 mm (+inf
//   when the shaft is not modelled).
struct ToothSpaceClearance {
  double facing_flank_mm, root_mm, shaft_mm;
  double smallest() const;
};
ToothSpaceClearance tooth_space_clearance(const InvoluteGear& gear, int tooth, FlankSide side,
                                          const Eigen::Vector3d& centre, const Eigen::Vector3d& n,
                                          const StylusShape& stylus, double approach_mm);

// The shaft's clearance alone for a ball centre `centre` (mm, as shaft_mm above): exposed for
// independent checks.
double shaft_clearance(const InvoluteGear& gear, int tooth, FlankSide side,
                       const Eigen::Vector3d& centre, const StylusShape& stylus);

}  // namespace gearmc
