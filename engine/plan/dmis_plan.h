// The probing plan as a DMIS program (Dimensional Measuring Interface Standard, ANSI/DMIS 105.2
// Part 1, version 5.3), so the plan gearmc simulates runs on a real CMM and its results come back
// to `gearmc diagnose`. The program, in order:
//   DMISMN, `$$` comments (what made it, the gear, the stylus), UNITS/MM,ANGDEC;
//   the stylus: S(label)=SNSDEF/PROBE,INDEX,POL,A,B,0,0,1,length,diameter (ball diameter 2R,
//     A = tilt of the stylus from the vertical, B = its turn about +Z from +X, so the direction
//     from the ball to the head is (sin A cos B, sin A sin B, cos A); the shaft's diameter in a
//     comment), SNSLCT, SNSET/APPRCH, SNSET/RETRCT (both the approach distance a) and
//     SNSET/SEARCH;
//   the operator's set-up step (MODE/MAN): the gear axis (the tip cylinder), the lower face
//     (z = 0) and tooth 1 (the midpoint of its two flanks on the reference circle) measured by
//     hand, DATDEF DAT(A), DAT(B), DAT(C), DATSET (axis = Z and the X, Y origin, face = Z origin,
//     tooth 1 on +X) and on a helical gear a ROTATE back to the section z = 0: gearmc's frame is
//     that datum frame;
//   MODE/AUTO,PROG,MAN and per planned point, in the plan's probing order, the clearance moves
//     (GOTO ball-centre positions, engine/plan/clearance_moves.h; SNSLCT where a radial stylus
//     changes its orientation) and
//       F(T001L_I00_J00)=FEAT/POINT,CART,x,y,z,i,j,k     nominal point and outward unit normal
//       MEAS/POINT,F(T001L_I00_J00),1                     measure it with one touch
//       PTMEAS/CART,x,y,z,i,j,k                           the touch: target and approach vector
//       ENDMES
//       OUTPUT/F(T001L_I00_J00)                           nominal and actual into the results,
//       OUTPUT/FA(T001L_I00_J00)                          which `gearmc diagnose` reads back
//   and the final lift and ENDFIL.
// The PTMEAS vector is the nominal outward normal n: as in DMIS, the probe travels along −n
// onto the surface (docs/formats.md "Coordinate conventions": the stylus approaches along −n).
// The labels name tooth (3 digits), flank (L or R), profile index i and face index j
// (2 digits each), so the measured results can be matched to the plan; the set-up step's
// features are named SETUP_… (the results reader skips them). Coordinates in mm in the gear
// frame (axis +Z, tooth 1 on +X), written with 6 decimals (1 nm).
#pragma once

#include <string>
#include <vector>

#include "engine/plan/clearance_moves.h"
#include "engine/plan/probing_grid.h"
#include "gears/involute_gear.h"

namespace gearmc {

// Label prefix of the operator's set-up features (not results of the plan).
inline constexpr char kDmisSetupPrefix[] = "SETUP_";

// The feature label of a planned point, e.g. "T001L_I03_J07".
std::string dmis_point_label(int tooth, FlankSide side, int i, int j);

struct DmisProgramOptions {
  std::string title;                  // goes into DMISMN
  std::vector<std::string> comments;  // `$$` lines after it (e.g. what made the file)
  double approach_mm = 1.0;           // a: SNSET/APPRCH and RETRCT, and the pre-positions
  PlanStylus stylus;                  // ball radius R, shaft
  double clearance_mm = 0.0;          // above the upper face (at least 2R + 5 mm)
};

// The program for `sequence` (the plan in probing order, probing_sequence()) on `gear`.
std::string dmis_program(const InvoluteGear& gear, const std::vector<PlannedPoint>& sequence,
                         const DmisProgramOptions& options);

}  // namespace gearmc
