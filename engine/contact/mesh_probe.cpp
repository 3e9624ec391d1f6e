// Probing a mesh flank with the analytic solver's plan and result semantics (see mesh_probe.h):
// the sphere sweep itself is MeshFlankContact's (surfaces/mesh_contact.h); this file maps its
// answer onto ContactResult and finds contacts on the mesh's border (a border edge or vertex
// of the touched triangle, from OpenMesh's halfedge topology), which are edge contacts.
#include "engine/contact/mesh_probe.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace gearmc {
namespace {

// A barycentric coordinate this small puts the contact on the opposite edge (the facet point is
// computed on the edge itself when the closest feature is an edge, so its coordinate is ~1e-16).
constexpr double kOnFeature = 1e-9;

// Barycentric coordinates of x (a point of the triangle's plane) in the triangle (a, b, c).
Eigen::Vector3d barycentric(const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                            const Eigen::Vector3d& c, const Eigen::Vector3d& x) {
  const Eigen::Vector3d v0 = b - a, v1 = c - a, v2 = x - a;
  const double d00 = v0.dot(v0), d01 = v0.dot(v1), d11 = v1.dot(v1);
  const double d20 = v2.dot(v0), d21 = v2.dot(v1);
  const double det = d00 * d11 - d01 * d01;
  if (!(det > 0.0)) return {0.0, 0.0, 0.0};  // a needle: treated as on every feature
  const double b1 = (d11 * d20 - d01 * d21) / det, b2 = (d00 * d21 - d01 * d20) / det;
  return {1.0 - b1 - b2, b1, b2};
}

}  // namespace

NominalFlankCoordinates nominal_flank_coordinates(const InvoluteGear& gear, int tooth,
                                                  FlankSide side, const Eigen::Vector3d& x) {
  // In the transverse section z, turned back by the helix (0 on a spur gear).
  const TransversePosition at =
      gear.transverse_position(tooth, side, x.head<2>(), x.z() * gear.helix_turn_per_mm());
  NominalFlankCoordinates c;
  c.roll_length_mm = at.foot_roll_length_mm;
  c.z_mm = x.z();
  c.offset_mm = at.distance_mm;
  return c;
}

MeshFlankProbe::MeshFlankProbe(const InvoluteGear& gear, int tooth, FlankSide side,
                               const TriangleMesh& mesh, MeshContactPoint point)
    : gear_(gear), tooth_(tooth), side_(side), point_(point), contact_(mesh) {
  vertices_.reserve(mesh.n_vertices());
  for (const TriangleMesh::VertexHandle v : mesh.vertices()) {
    const TriangleMesh::Point& x = mesh.point(v);
    vertices_.emplace_back(x[0], x[1], x[2]);
  }
  faces_.resize(mesh.n_faces());
  border_.assign(mesh.n_faces(), 0);
  for (const TriangleMesh::FaceHandle f : mesh.faces()) {
    // The corners in fv_range order: the order MeshFlankContact reads them in.
    std::array<TriangleMesh::VertexHandle, 3> v;
    int k = 0;
    for (const TriangleMesh::VertexHandle h : mesh.fv_range(f)) {
      if (k < 3) v[k] = h;
      ++k;
    }
    std::uint8_t flags = 0;
    for (k = 0; k < 3; ++k) {
      faces_[f.idx()][k] = v[k].idx();
      if (mesh.is_boundary(v[k])) flags |= 1u << k;
      const TriangleMesh::HalfedgeHandle h = mesh.find_halfedge(v[k], v[(k + 1) % 3]);
      if (!h.is_valid() || mesh.is_boundary(mesh.edge_handle(h))) flags |= 1u << (3 + k);
    }
    border_[f.idx()] = flags;
  }
}

ContactResult MeshFlankProbe::probe(const Eigen::Vector3d& p, const Eigen::Vector3d& n,
                                    double R) const {
  ContactResult result;
  result.iterations = 0;
  const MeshContactResult m = contact_.first_contact(p, n, R, R - kMeshSearchMm, R + kMeshSearchMm);
  if (m.touching_at_t_max) {
    result.status = ContactResult::Status::kCollision;
    result.collision = CollisionKind::kTouchingAtStart;
    return result;
  }
  if (!m.found) {
    result.status = ContactResult::Status::kNotConverged;
    result.failure = ContactFailure::kNoMeshContact;
    return result;
  }
  // On the border: a corner or an edge of the touched triangle that the mesh ends at.
  const std::array<int, 3>& f = faces_[m.face];
  const Eigen::Vector3d w =
      barycentric(vertices_[f[0]], vertices_[f[1]], vertices_[f[2]], m.contact);
  const std::uint8_t flags = border_[m.face];
  bool on_border = false;
  for (int k = 0; k < 3; ++k) {
    const bool at_corner = w[(k + 1) % 3] <= kOnFeature && w[(k + 2) % 3] <= kOnFeature;
    const bool on_edge = w[(k + 2) % 3] <= kOnFeature;  // edge k -> k + 1, opposite corner k + 2
    if ((at_corner && (flags & (1u << k))) || (on_edge && (flags & (1u << (3 + k))))) {
      on_border = true;
    }
  }
  const Eigen::Vector3d C = point_ == MeshContactPoint::kSmoothed ? m.smoothed_contact : m.contact;
  const NominalFlankCoordinates at = nominal_flank_coordinates(gear_, tooth_, side_, C);
  result.roll_length_mm = at.roll_length_mm;
  result.z_mm = at.z_mm;
  if (on_border) {
    result.status = ContactResult::Status::kEdge;
    return result;
  }
  result.status = ContactResult::Status::kOk;
  result.contact = C;
  result.centre = m.centre;
  result.reported = result.centre - R * n;
  result.delta_um = 1e3 * (result.contact - result.reported).norm();
  result.normal_error_um = 1e3 * (result.reported - result.contact).dot(n);
  return result;
}

}  // namespace gearmc
