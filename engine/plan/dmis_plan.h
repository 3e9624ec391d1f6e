// The probing plan as a DMIS program (Dimensional Measuring Interface Standard, ANSI/DMIS 105.2
// Part 1, version 5.3), so the plan gearmc simulates runs on a real CMM and its results come back
// to `gearmc diagnose`: one feature per planned point, in the plan's probing order,
//   F(T001L_I00_J00)=FEAT/POINT,CART,x,y,z,i,j,k     nominal point and outward unit normal
//   MEAS/POINT,F(T001L_I00_J00),1                     measure it with one touch
//   PTMEAS/CART,x,y,z,i,j,k                           the touch: target and approach vector
//   ENDMES
// The PTMEAS vector is the nominal outward normal n: as in DMIS, the probe travels along −n
// onto the surface (docs/formats.md "Coordinate conventions": the stylus approaches along −n).
// The labels name tooth (3 digits), flank (L or R), profile index i and face index j
// (2 digits each), so the measured results can be matched to the plan. Coordinates in mm in the
// gear frame (axis +Z, tooth 1 on +X), written with 6 decimals (1 nm); the header sets
// UNITS/MM,ANGDEC and the approach distance SNSET/APPRCH (mm); `$$` lines are comments.
#pragma once

#include <string>
#include <vector>

#include "engine/plan/probing_grid.h"
#include "gears/involute_gear.h"

namespace gearmc {

// The feature label of a planned point, e.g. "T001L_I03_J07".
std::string dmis_point_label(int tooth, FlankSide side, int i, int j);

// The program for `sequence` (the plan in probing order, probing_sequence()). `title` goes into
// DMISMN; `comments` are written as `$$` lines after it (e.g. what made the file).
std::string dmis_program(const std::vector<PlannedPoint>& sequence, const std::string& title,
                         double approach_mm, const std::vector<std::string>& comments);

}  // namespace gearmc
