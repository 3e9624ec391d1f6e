// Triangle meshes of real flanks and of whole perturbed gears (OpenMesh), and their files.
// A flank mesh samples the analytic real flank S(L, z) (surfaces/analytic_flank.h) on a regular
// (roll length, z) grid, so its vertices lie exactly on the real surface and the mesh is its
// piecewise-linear interpolant; a gear mesh adds tip lands, simplified roots and the two end
// faces so that the gear is a closed, outward-oriented surface a user can look at in MeshLab or
// ParaView (`gearmc export-mesh`) or probe like a scanned part. Every point is in the datum
// (CMM) frame of docs/formats.md (gear axis +Z, z = 0 on the lower face, tooth 1 on +X, the gear's
// eccentricity included), in mm. Files: STL (binary / ASCII), PLY (binary / ASCII), OBJ, OFF,
// read and written by OpenMesh, written to a temporary name and renamed when complete.
#pragma once

// OpenMesh's IO must be included before the mesh kernel (it registers the readers/writers).
#include <OpenMesh/Core/IO/MeshIO.hh>
#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include "gears/deviations.h"
#include "gears/involute_gear.h"
#include "gears/normal_expression.h"
#include "surfaces/analytic_flank.h"
#include "surfaces/triangle_mesh_fwd.h"

namespace gearmc {

// Double-precision points and normals (OpenMesh's default is float). TriangleMesh, the mesh
// with these traits, is named in surfaces/triangle_mesh_fwd.h.
struct TriangleMeshTraits : public OpenMesh::DefaultTraits {
  typedef OpenMesh::Vec3d Point;
  typedef OpenMesh::Vec3d Normal;
};

// ---------------------------------------------------------------------------------------------
// Meshing

// The part of one flank to mesh: a box in (roll length L, z), mm, sampled on a regular grid of
// roll_length_samples x z_samples points (each >= 2, ends included).
struct FlankMeshSpec {
  double roll_length_min_mm = 0.0, roll_length_max_mm = 0.0;
  double z_min_mm = 0.0, z_max_mm = 0.0;
  int roll_length_samples = 2, z_samples = 2;
};

// The whole usable flank (form circle to tip circle, z = 0 to b) with grid steps of at most
// `roll_length_step_mm` in L and `z_step_mm` in z. (A step dL in roll length is an arc length
// of (L / r_b) dL on the involute.)
FlankMeshSpec whole_flank_spec(const InvoluteGear& gear, double roll_length_step_mm,
                               double z_step_mm);

// Triangulates the real flank over `spec`: vertex v = j * roll_length_samples + i is
// S(L_i, z_j) with L_i, z_j equally spaced over the box (datum frame, mm), two triangles per
// grid cell, every triangle's normal (counter-clockwise vertex order) on the side of the
// outward normal. The cell diagonal runs so that an L flank and an R flank are mirror images
// and the triangles are the ones mesh_gear makes for the same sampling.
TriangleMesh mesh_flank(const AnalyticFlank& flank, const FlankMeshSpec& spec);

// Sampling of a whole-gear mesh: per transverse section, profile_samples points on each flank
// (form circle to tip circle, equal roll-length steps), tip_samples interior points on each tip
// land, root_samples interior points on each root; face_samples sections from z = 0 to z = b.
struct GearMeshSpec {
  int profile_samples = 25;
  int tip_samples = 6;
  int root_samples = 12;
  int face_samples = 40;
};

// What a face of a gear mesh belongs to. tooth is 1..z for flanks and tips; for a root it is
// the tooth whose R flank the root follows (the space between tooth and tooth + 1); 0 on the
// end faces. side is meaningful for flanks only.
struct GearMeshFace {
  // kRim: the outer cylinder of an internal gear's ring (mesh_gear).
  enum class Region : std::uint8_t { kFlank, kTip, kRoot, kEndFace, kRim };
  Region region = Region::kFlank;
  int tooth = 0;
  FlankSide side = FlankSide::kLeft;
};

struct GearMesh {
  TriangleMesh mesh;
  std::vector<GearMeshFace> faces;  // faces[f] describes mesh face f
};

// The whole perturbed gear (every flank of every tooth with its deviations and the gear's
// eccentricity, plus `expression` if not null) as a closed triangle mesh oriented outwards,
// datum frame, mm. Each transverse section is a star-shaped polygon around the (eccentric) gear
// centre: for every tooth, counter-clockwise, the L flank from the form circle up, the tip land
// (polar angle interpolated between the two real flank tips, radius interpolated between their
// radii: the tip circle on a nominal gear), the R flank down, then the root to the next tooth.
// Simplification: the root is NOT the generated trochoid fillet; it is a blend from the flank
// starts on the form circle down to the root circle,
//   r(u) = r_f + (r_start(u) - r_f) |2u - 1|^3,   u in [0, 1] across the space,
// with r_start interpolated between the two flank starts' radii (nominal: r_Ff). The end faces
// z = 0 and z = b are each an annulus from the section to its radial projection on a circle of
// half its smallest radius, and that inner polygon (no vertex in more than a few triangles, so
// the build is linear in M). Vertices: section j (z_j = j b / (face_samples - 1)) holds vertices
// j * M ... j * M + M - 1, then the bottom's and the top's inner rings (M each); triangles:
// 2 (face_samples - 1) M walls and 3 M - 2 per end face.
GearMesh mesh_gear(const InvoluteGear& gear, const PerturbedGear& perturbed,
                   const GearMeshSpec& spec, const NormalExpression* expression = nullptr);

// ---------------------------------------------------------------------------------------------
// Files

// Unreadable or unwritable mesh files, unknown extensions, files without triangles.
class MeshIoError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

enum class MeshFormat { kStl, kPly, kObj, kOff };

// The format named by the file's extension (.stl .ply .obj .off, any case); MeshIoError
// otherwise.
MeshFormat mesh_format_of(const std::string& path);

struct MeshWriteOptions {
  bool binary = true;  // STL and PLY; OBJ and OFF are always written as text
};

// Writes `mesh` to `path` (format from the extension) through OpenMesh: first to a temporary
// file beside it, renamed to `path` when complete, so no half-written file is ever left.
// Precision: OpenMesh 9 stores coordinates as 32-bit floats in every format (its writers and
// readers convert through float), so a written coordinate x carries a rounding error
// <= |x| 2^-24 (<= 4.8 nm at 80 mm); text formats print that float exactly.
void write_mesh_file(const TriangleMesh& mesh, const std::string& path,
                     const MeshWriteOptions& options = {});

// Largest mesh file read: 512 MiB (a binary STL of 10 million triangles; a measured flank of
// 10^6 points is about a tenth of it).
inline constexpr std::uintmax_t kMaxMeshFileBytes = 512ull << 20;

// Reads a triangle mesh (polygons are triangulated; STL vertices are merged). MeshIoError when
// the file is not a regular file of at most kMaxMeshFileBytes, cannot be opened, its extension is
// unknown, OpenMesh cannot parse it, or it holds no triangle.
TriangleMesh read_mesh_file(const std::string& path);

}  // namespace gearmc
