// `gearmc export-mesh SCENARIO --gear K --out FILE.{stl,ply,obj,off}` (docs/formats.md): writes
// perturbed gear K of the scenario (the same gear `gearmc run --only-gear K` probes) as a
// closed triangle mesh, in the datum frame, mm, for MeshLab or ParaView.
#pragma once

#include <iosfwd>
#include <string>

namespace gearmc {

struct ExportMeshOptions {
  std::string scenario_path;  // empty: the built-in reference scenario
  int gear = 0;               // 0-based gear index
  std::string out;            // file; the extension picks the format
  int profile_samples = 25, face_samples = 40;
};

// Throws InputError for bad input (unknown extension, unwritable file, bad gear index).
int export_mesh_command(const ExportMeshOptions& options, std::ostream& out, std::ostream& err);

}  // namespace gearmc
