// The name of gearmc's triangle mesh (OpenMesh's array-kernel triangle mesh with double-precision
// points and normals, defined in surfaces/flank_mesh.h) without OpenMesh's headers, for headers
// that only hold or pass a mesh by pointer or reference (e.g. a scenario's mesh flanks). Code that
// builds, reads or walks a mesh includes surfaces/flank_mesh.h. Keeping OpenMesh's headers out
// of such headers keeps them in the few translation units that use them.
#pragma once

#include <cstddef>

namespace OpenMesh {
// OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh declares it with the default argument DefaultTraits.
template <class Traits>
class TriMesh_ArrayKernelT;
}  // namespace OpenMesh

namespace gearmc {

struct TriangleMeshTraits;  // surfaces/flank_mesh.h
using TriangleMesh = OpenMesh::TriMesh_ArrayKernelT<TriangleMeshTraits>;

// The number of triangles (faces) of `mesh`, for code that reports a mesh's size without
// OpenMesh's headers.
std::size_t triangle_count(const TriangleMesh& mesh);

}  // namespace gearmc
