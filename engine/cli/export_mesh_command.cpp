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
  // Gear K as every command draws it (the measurement model, engine/measurement).
  const MeasurementModel model(scenario);
  const PerturbedGear perturbed = model.draw_gear(o.gear);
  GearMeshSpec spec;
  spec.profile_samples = o.profile_samples;
  spec.face_samples = o.face_samples;
  const GearMesh mesh = mesh_gear(model.gear(), perturbed, spec, model.expression());
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
