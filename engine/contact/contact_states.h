// Why a stylus contact has no value: the kinds of collision and of failure a ContactResult or a
// contact certificate carries, with their spellings in points.csv, the terminal and messages in
// one table each (docs/formats.md "points.csv"). States are enums in the code; only these
// functions turn them into text.
#pragma once

#include <cstdint>
#include <string_view>

namespace gearmc {

// What the sphere meets before the planned flank point (ContactResult::Status::kCollision).
enum class CollisionKind : std::uint8_t {
  kNone,
  kNeighbourFlank,   // the facing flank of the tooth space
  kRoot,             // the root circle
  kTouchingAtStart,  // a mesh flank already touches the sphere where the approach starts
  kShaft,            // the stylus shaft meets a flank or the root above the ball
};

// Why a contact failed (kNotConverged) or is not proven the first contact (kUncertified).
enum class ContactFailure : std::uint8_t {
  kNone,                 // the Newton iteration's own failure, or no failure
  kNoMeshContact,        // the sphere passed a mesh flank without touching it
  kRestartCap,           // the certificate found higher points more often than allowed
  kNormalNotTransverse,  // certificate: the approach is not transverse to the flank
  kFootprintNotBounded,  // certificate: the footprint cannot be bounded
  kNotConcaveAtContact,  // certificate: the field's curvature at the contact reaches 1/R
  kUnprovenRegion,       // certificate: a cell's bound exceeds the tolerance after refinement
};

// The spellings ("" for kNone).
constexpr std::string_view spelling(CollisionKind kind) {
  switch (kind) {
    case CollisionKind::kNone:
      return "";
    case CollisionKind::kNeighbourFlank:
      return "neighbour_flank";
    case CollisionKind::kRoot:
      return "root";
    case CollisionKind::kTouchingAtStart:
      return "touching_at_start";
    case CollisionKind::kShaft:
      return "shaft";
  }
  return "?";
}

constexpr std::string_view spelling(ContactFailure failure) {
  switch (failure) {
    case ContactFailure::kNone:
      return "";
    case ContactFailure::kNoMeshContact:
      return "no_mesh_contact";
    case ContactFailure::kRestartCap:
      return "restart_cap";
    case ContactFailure::kNormalNotTransverse:
      return "normal_not_transverse";
    case ContactFailure::kFootprintNotBounded:
      return "footprint_not_bounded";
    case ContactFailure::kNotConcaveAtContact:
      return "not_concave_at_contact";
    case ContactFailure::kUnprovenRegion:
      return "unproven_region";
  }
  return "?";
}

}  // namespace gearmc
