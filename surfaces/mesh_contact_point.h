// Which point of a stylus contact with a triangle-mesh flank counts as the true contact point
// (a scenario's `surfaces: contact:` setting, used by engine/contact/mesh_probe.h). Its own small
// header so that a scenario can name it without the mesh and contact headers.
#pragma once

namespace gearmc {

// Which point of a mesh contact is the true contact point C.
enum class MeshContactPoint {
  // O - R nu, nu the interpolated angle-weighted vertex normal at the facet contact: an estimate
  // of the contact with the smooth surface the mesh samples, converging as O(h^2) with the mesh
  // step h (surfaces/mesh_contact.h). For meshes of smooth flanks (CAD, fitted scans): default.
  kSmoothed,
  // The point of the triangles the sphere touches: exact for the piecewise-planar surface, but
  // it follows the facet normals, so on a mesh of a smooth flank it converges only as O(h).
  kFacets,
};

}  // namespace gearmc
