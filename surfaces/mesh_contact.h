// First contact of a spherical stylus tip with a triangle-mesh surface (a meshed or scanned
// flank, or a whole gear), exact for the piecewise-planar surface, found through a CGAL AABB
// tree over the triangles; and a CGAL validity check of a mesh (closed, valid, volume).
// The tip centre moves along a line O(t) = p + t n coming from large t; the first contact is
// the largest t at which the sphere of radius R touches a triangle. For one triangle T the set
// {t : dist(O(t), T) <= R} is an interval (the line meets the convex Minkowski sum T + ball), so
// its last point is the largest t among the exits of the line from the slab prism over T's
// interior (|distance to T's plane| <= R above T), from the three edge cylinders, and from the
// three vertex balls; the mesh's first contact is the largest of these over all triangles.
// The AABB tree only prunes: a tree node is visited when the line's part above the best t found
// so far meets the node's box grown by R. CGAL stays inside mesh_contact.cpp (pimpl).
// Lengths in mm; points in the frame of the mesh (the datum frame for gearmc's meshes).
#pragma once

#include <Eigen/Core>
#include <memory>
#include <optional>

#include "surfaces/flank_mesh.h"

namespace gearmc {

struct MeshContactResult {
  bool found = false;  // a contact with t in [t_min, t_max]
  // The sphere at t_max already touches the mesh (found is then false; t, contact, centre and
  // face describe the highest contact that was seen): the caller's window is wrong, or
  // something (a neighbouring tooth) is in the way.
  bool touching_at_t_max = false;
  double t = 0.0;  // first-contact parameter along n, mm
  // C: the point of the mesh the sphere touches, mm.
  Eigen::Vector3d contact = Eigen::Vector3d::Zero();
  // O = p + t n, mm; |C - O| = R.
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  // Index of the touched triangle in the mesh (OpenMesh face idx; GearMesh::faces labels it).
  int face = -1;
  // X = O - R nu(X), nu the barycentric interpolation of the mesh's angle-weighted vertex normals
  // (Thuermer & Wuethrich 1998) on the touched triangle, turned towards O, evaluated where X lies
  // (a short fixed-point iteration from the facet point C). Not a point of the mesh: an estimate
  // of the contact with the smooth surface the mesh samples. On a piecewise-planar mesh C
  // follows the facet normals and converges only as O(h) to the smooth surface's contact
  // (C - O = -R m_facet); this estimate converges as O(h^2) on regular meshes of surfaces with
  // continuous curvature, like O (measured in tests/surfaces/mesh_contact_test.cpp), and as O(h)
  // (with a small constant) where the curvature jumps. Use it for delta_Rcomp on meshed smooth
  // flanks.
  Eigen::Vector3d smoothed_contact = Eigen::Vector3d::Zero();
};

class MeshFlankContact {
 public:
  // Builds the AABB tree over every triangle of `mesh` (copied: the object is independent of
  // the argument's lifetime). Faces must be triangles (TriangleMesh guarantees it).
  explicit MeshFlankContact(const TriangleMesh& mesh);
  ~MeshFlankContact();
  MeshFlankContact(MeshFlankContact&&) noexcept;
  MeshFlankContact& operator=(MeshFlankContact&&) noexcept;
  MeshFlankContact(const MeshFlankContact&) = delete;
  MeshFlankContact& operator=(const MeshFlankContact&) = delete;

  // First contact of the sphere of radius R (mm) whose centre moves along O(t) = p + t n from
  // t_max down to t_min (p in mm, n unit; it is normalised here, t is measured along it).
  // Contacts outside [t_min, t_max] are not searched, except that a sphere already touching
  // the mesh at t_max is reported (touching_at_t_max). const and thread-safe.
  MeshContactResult first_contact(const Eigen::Vector3d& p, const Eigen::Vector3d& n, double R,
                                  double t_min, double t_max) const;

  // The same answer by testing every triangle (no tree): the reference for tests and the
  // benchmark's baseline. O(number of triangles).
  MeshContactResult first_contact_linear_scan(const Eigen::Vector3d& p, const Eigen::Vector3d& n,
                                              double R, double t_min, double t_max) const;

  int triangle_count() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// Last contact parameter of a sphere of radius R moving along p + t n (n unit) with the single
// triangle (a, b, c): the largest t with dist(p + t n, triangle) <= R, or nothing when the line
// never comes that close. Exposed for tests.
std::optional<double> sphere_triangle_last_contact(const Eigen::Vector3d& a,
                                                   const Eigen::Vector3d& b,
                                                   const Eigen::Vector3d& c,
                                                   const Eigen::Vector3d& p,
                                                   const Eigen::Vector3d& n, double R);

// CGAL's view of a mesh (CGAL::is_valid_polygon_mesh, CGAL::is_closed,
// Polygon_mesh_processing::volume / area / is_outward_oriented / does_self_intersect).
struct MeshCheck {
  bool valid = false;              // a valid halfedge polygon mesh
  bool triangles = false;          // every face a triangle
  bool closed = false;             // no border edge
  bool outward_oriented = false;   // closed meshes only
  bool self_intersecting = false;  // checked when check_self_intersection is set
  double area_mm2 = 0.0;
  double volume_mm3 = 0.0;  // signed enclosed volume (> 0: outward), closed meshes only, else 0
};
MeshCheck check_mesh(const TriangleMesh& mesh, bool check_self_intersection = false);

}  // namespace gearmc
