// Which point of a probing plan a value belongs to, the one key every point type shares: its
// place in the grid of one flank (tooth, flank side, indices i along the profile and j across the
// face) and, once measured, the gear of the run it was measured on. The plan's points are grid
// positions; probed points, readings, residuals and excluded readings are keyed points. Point
// types derive from these, so their fields read p.tooth, p.i, … and a key is copied whole
// (q.key() = p.key()), never field by field.
#pragma once

#include "gears/involute_gear.h"

namespace gearmc {

// A point's place in the probing grid of one gear.
struct GridPosition {
  int tooth = 1;                      // 1 .. z
  FlankSide side = FlankSide::kLeft;  // the flank of the tooth
  int i = 0;                          // along the profile, 0 .. N-1 (rising roll length)
  int j = 0;                          // across the face, 0 .. M-1 (rising z)

  GridPosition& grid_position() { return *this; }
  const GridPosition& grid_position() const { return *this; }
  friend bool operator==(const GridPosition&, const GridPosition&) = default;
};

// A measured point's key: its grid position on gear `gear` of the run (0-based).
struct PointKey : GridPosition {
  int gear = 0;

  PointKey& key() { return *this; }
  const PointKey& key() const { return *this; }
  friend bool operator==(const PointKey&, const PointKey&) = default;
};

// The key of grid position `at` on gear `gear`.
inline PointKey point_key(int gear, const GridPosition& at) {
  PointKey key;
  key.grid_position() = at;
  key.gear = gear;
  return key;
}

}  // namespace gearmc
