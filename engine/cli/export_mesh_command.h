// `gearmc export-mesh SCENARIO --gear K --out FILE.{stl,ply,obj,off}` (docs/formats.md): writes
// perturbed gear K of the scenario (the same gear `gearmc run --only-gear K` probes) as a
// closed triangle mesh, in the datum frame, mm, for MeshLab or ParaView.
#pragma once

#include <cstdint>
#include <iosfwd>
#include <string>

namespace gearmc {

// The largest mesh written: 20 000 vertices per section and 2 000 000 in all (about 4 million
// triangles: a 200 MB binary STL, about 1 GB in memory). The time is linear in both.
inline constexpr std::uint64_t kMaxMeshSectionVertices = 20000;
inline constexpr std::uint64_t kMaxMeshVertices = 2000000;

struct ExportMeshOptions {
  std::string scenario_path;  // empty: the built-in reference scenario
  int gear = 0;               // 0-based gear index
  std::string out;            // file; the extension picks the format
  int profile_samples = 25, face_samples = 40;
};

// Throws InputError for bad input (unknown extension, unwritable file, bad gear index, a mesh
// beyond the bounds above).
int export_mesh_command(const ExportMeshOptions& options, std::ostream& out, std::ostream& err);

}  // namespace gearmc
