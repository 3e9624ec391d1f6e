// `gearmc export-mesh`: perturbed gear K as a triangle mesh file (see export_mesh_command.h).
#include "engine/cli/export_mesh_command.h"

#include <ostream>

#include "core/input_error.h"
#include "core/output_files.h"
#include "engine/measurement/measurement_model.h"
#include "engine/scenario/scenario.h"
#include "gears/normal_expression.h"
#include "surfaces/flank_mesh.h"

namespace gearmc {

int export_mesh_command(const ExportMeshOptions& o, std::ostream& out, std::ostream& err) {
  const Scenario scenario =
      o.scenario_path.empty() ? reference_scenario() : load_scenario_file(o.scenario_path);
  for (const std::string& w : scenario.warnings) err << "gearmc: warning: " << w << "\n";
  check_output_file(o.out, "--out");
  try {
    (void)mesh_format_of(o.out);
  } catch (const MeshIoError& e) {
    throw InputError({}, "--out", o.out, "a file ending in .stl, .ply, .obj or .off");
  }
  if (o.gear < 0) {
    throw InputError({}, "--gear", std::to_string(o.gear), "a gear index >= 0");
  }
  GearMeshSpec spec;
  spec.profile_samples = o.profile_samples;
  spec.face_samples = o.face_samples;
  // The mesh's size before any work: vertices per section M = z (2 P + tip + root); the whole
  // mesh has (F + 2) M vertices (F sections and each end face's inner ring) and
  // 2 (F - 1) M + 2 (3 M - 2) triangles (surfaces/flank_mesh.h).
  const std::uint64_t per_section =
      static_cast<std::uint64_t>(scenario.gear.teeth) *
      (2 * static_cast<std::uint64_t>(spec.profile_samples) + spec.tip_samples + spec.root_samples);
  const std::uint64_t vertices = (static_cast<std::uint64_t>(spec.face_samples) + 2) * per_section;
  if (per_section > kMaxMeshSectionVertices || vertices > kMaxMeshVertices) {
    throw InputError(
        {}, "--profile-samples, --face-samples",
        std::to_string(spec.profile_samples) + ", " + std::to_string(spec.face_samples),
        "a mesh of at most " + std::to_string(kMaxMeshSectionVertices) +
            " vertices per section and " + std::to_string(kMaxMeshVertices) +
            " in all; these give " + std::to_string(per_section) + " per section (" +
            std::to_string(scenario.gear.teeth) + " teeth × (2 × " +
            std::to_string(spec.profile_samples) + " + " +
            std::to_string(spec.tip_samples + spec.root_samples) + ")) and " +
            std::to_string(vertices) + " in all");
  }
  // Gear K as every command draws it (the measurement model, engine/measurement).
  const MeasurementModel model(scenario);
  const PerturbedGear perturbed = model.draw_gear(o.gear);
  GearMesh mesh;
  try {
    mesh = mesh_gear(model.gear(), perturbed, spec, model.expression());
  } catch (const MeshIoError& e) {
    throw InputError({scenario.source_path, 0, 0},
                     scenario.source_path + ": gear " + std::to_string(o.gear) + ": " + e.what());
  }
  try {
    write_mesh_file(mesh.mesh, o.out);
  } catch (const MeshIoError& e) {
    throw InputError({o.out, 0, 0}, o.out + ": " + e.what());
  }
  out << "gearmc export-mesh: gear " << o.gear << " of " << scenario.name << " ("
      << mesh.mesh.n_vertices() << " vertices, " << mesh.mesh.n_faces() << " triangles, mm, "
      << "datum frame; deviations are microns: exaggerate them in the viewer to see them) -> "
      << o.out << "\n";
  return 0;
}

}  // namespace gearmc
