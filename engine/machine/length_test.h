// The ISO 10360-2 length test of a kinematic machine (kinematic_machine.h): calibrated lengths
// measured in seven positions of the measuring volume — the four space diagonals and the three
// directions parallel to the axes, through the centre of the travel (ISO 10360-2:2009 §6.3,
// Table 1: the four space diagonals are required, the other three positions are the user's
// choice; axis-parallel ones are the usual default) — five lengths each, the longest at 85 % of
// the line's length inside the travel (the standard asks for at least 66 % of the longest space
// diagonal), each measured bidirectionally: the stylus centre touches the gauge's two end faces
// from outside, at A − R û and B + R û (û the gauge's direction, R the ball radius). The
// kinematic error of the measured length is E = (e(B + R û) − e(A − R û))·û (µm, first order: an
// error across the gauge changes its length by its square). Probing and noise are not part of it.
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "engine/machine/kinematic_machine.h"

namespace gearmc {

struct LengthTestPosition {
  std::string name;           // "diagonal_ppp", … "x", "y", "z"
  Eigen::Vector3d direction;  // unit
  double line_mm = 0.0;       // the length of the line through the centre inside the travel
};

struct LengthTestOptions {
  Eigen::Vector3d stylus_mm = Eigen::Vector3d(0.0, 0.0, -150.0);  // from the ram to the ball
  double ball_radius_mm = 1.5;
  std::vector<double> fractions = {0.1, 0.25, 0.45, 0.65, 0.85};  // of line_mm
};

struct LengthError {
  int position = 0;  // index into the positions
  double length_mm = 0.0;
  double error_um = 0.0;
};

// The kinematic error (µm) of one gauge of `length_mm` along the unit `direction`, centred where
// the ram stands at the reference point, touched bidirectionally (the file comment's E).
double kinematic_length_error_um(const KinematicMachine& machine, const Eigen::Vector3d& direction,
                                 double length_mm, const LengthTestOptions& options = {});

// The seven positions for a machine with travel `travel_mm` (centred on the reference point).
std::vector<LengthTestPosition> length_test_positions(const Eigen::Vector3d& travel_mm);

// The kinematic length errors of `machine` in the seven positions, five lengths each (35).
std::vector<LengthError> length_test(const KinematicMachine& machine,
                                     const LengthTestOptions& options = {});

}  // namespace gearmc
