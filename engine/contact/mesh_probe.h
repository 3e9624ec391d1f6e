// Probing a flank whose real surface is a triangle mesh (a scanned or CAD flank named in a
// scenario's `surfaces:` section) with the same probing plan and the same ContactResult
// semantics as the analytic solver (contact.h): the stylus centre moves along the nominal
// normal, O(t) = p + t n, from kProbeApproachMm outside the nominal touching position (t = R) to
// kProbeApproachMm beyond it; the first contact with the triangles (surfaces/mesh_contact.h,
// CGAL AABB tree, exact for the piecewise-planar surface) gives O, the true contact point C (the
// facet point or the smoothed estimate, MeshContactPoint), E = O - R n, delta_Rcomp = |C - E|
// and the normal error (E - C).n. What the analytic solver calls an edge contact is here a
// contact on the mesh's border; a sphere that passes the mesh without touching it is a failed
// contact ("no_mesh_contact"), one that already touches the mesh where the approach starts is a
// collision ("touching_at_start"): neither is ever a measured value. Datum frame, mm; errors µm.
#pragma once

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <vector>

#include "engine/contact/contact.h"
#include "gears/involute_gear.h"
#include "surfaces/flank_mesh.h"
#include "surfaces/mesh_contact.h"
#include "surfaces/mesh_contact_point.h"

namespace gearmc {

// Where a point x (datum frame, mm) lies relative to the nominal flank `side` of `tooth`: the
// roll length L and height z of the nominal flank point whose normal passes through x, and the
// signed distance along that normal (+ = outside the material). Closed form in the transverse
// plane (involutes of one base circle are parallel, so the distance along the normal is r_b
// times the polar angle between them): L = r_b (theta_b - s phi + alpha_x),
// offset = r_b (inv(alpha_x) + s phi - theta_b), phi = polar angle of x from the tooth centre,
// alpha_x = acos(r_b / |x|), s = +1 for R, -1 for L. For |x| < r_b alpha_x is taken as 0. On a
// helical gear phi is taken in x's transverse section (turned back by z helix_turn_per_mm): L
// and the offset are then the transverse ones (the distance along the helicoid's normal is the
// offset times cos(beta_b), and the normal's foot lies offset sin(beta_b) away in z).
struct NominalFlankCoordinates {
  double roll_length_mm = 0.0;
  double z_mm = 0.0;
  double offset_mm = 0.0;
};
NominalFlankCoordinates nominal_flank_coordinates(const InvoluteGear& gear, int tooth,
                                                  FlankSide side, const Eigen::Vector3d& x);

// The stylus's search window along n around the nominal touching position t = R (mm): it starts
// this far outside (where check_tooth_space also starts the approach) and gives up this far
// beyond.
inline constexpr double kMeshSearchMm = kProbeApproachMm;

class MeshFlankProbe {
 public:
  // Builds the AABB tree over `mesh` (datum frame, mm; copied) once; `tooth`, `side` name the
  // flank it replaces (ContactResult::roll_length of a contact is the nominal roll length of
  // C on that flank). probe() is then const and thread-safe.
  MeshFlankProbe(const InvoluteGear& gear, int tooth, FlankSide side, const TriangleMesh& mesh,
                 MeshContactPoint point);

  // Probes the planned point p with nominal outward unit normal n (datum frame, mm) with a
  // sphere of radius R (mm), searching t in [R - kMeshSearchMm, R + kMeshSearchMm].
  // Status: kOk (contact, delta_um, normal_error_um filled; |C - O| = R), kEdge (the sphere
  // touches the mesh's border first), kCollision with collision "touching_at_start", or
  // kNotConverged with failure "no_mesh_contact". iterations = 0.
  ContactResult probe(const Eigen::Vector3d& p, const Eigen::Vector3d& n, double R) const;

  MeshContactPoint contact_point() const { return point_; }
  int triangle_count() const { return contact_.triangle_count(); }

 private:
  const InvoluteGear& gear_;
  int tooth_;
  FlankSide side_;
  MeshContactPoint point_;
  MeshFlankContact contact_;
  // The mesh's vertices, each face's corners (vertex indices, in the order MeshFlankContact
  // uses) and which corners (bit k) and edges (bit 3 + k: corner k -> corner k + 1) of each face
  // lie on the mesh's border.
  std::vector<Eigen::Vector3d> vertices_;
  std::vector<std::array<int, 3>> faces_;
  std::vector<std::uint8_t> border_;
};

}  // namespace gearmc
