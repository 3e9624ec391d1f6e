// The probing and surfaces sections of a scenario (see probing_sections.h). The schema of each
// section is documented with its reader below.
#include "engine/scenario/probing_sections.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <memory>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "engine/contact/mesh_probe.h"
#include "engine/schema/parameter_ranges.h"
#include "engine/schema/scenario_keys.h"

namespace gearmc {
namespace {

ProfileSpacing spacing_of(const std::string& spacing) {
  return spacing == "roll_length"  ? ProfileSpacing::kRollLength
         : spacing == "arc_length" ? ProfileSpacing::kArcLength
                                   : ProfileSpacing::kRadius;
}

void set_flanks(const std::string& flanks, ProbingPlanSpec& plan) {
  plan.left = flanks != "R";
  plan.right = flanks != "L";
}

ProbingOrder order_of(const std::string& order) {
  return order == "tooth_by_tooth" ? ProbingOrder::kToothByTooth : ProbingOrder::kSideBySide;
}

// One `surfaces:` entry's mesh file: read (OpenMesh), every coordinate finite, and at least one
// vertex within kMeshSearchMm of the nominal flank it replaces, over that flank's extent (form
// to tip circle, z 0..b): a mesh of another tooth or flank, in another frame or in other units
// would otherwise only show up as failed contacts. Errors are placed at the `mesh` value.
std::shared_ptr<const TriangleMesh> read_flank_mesh(const YamlValue& value, const std::string& path,
                                                    const InvoluteGear& gear, int tooth,
                                                    FlankSide side) {
  const std::string expected =
      "a triangle mesh file (.stl, .ply, .obj or .off; datum frame, mm; a relative path is taken "
      "from the scenario file's folder)";
  auto mesh = std::make_shared<TriangleMesh>();
  try {
    *mesh = read_mesh_file(path);
  } catch (const MeshIoError& e) {
    throw value.error(expected + ", but " + e.what());
  }
  const std::string flank = std::to_string(tooth) + side_letter(side);
  double nearest = std::numeric_limits<double>::infinity();
  for (const TriangleMesh::VertexHandle v : mesh->vertices()) {
    const TriangleMesh::Point& x = mesh->point(v);
    if (!std::isfinite(x[0]) || !std::isfinite(x[1]) || !std::isfinite(x[2])) {
      throw value.error(expected + ", but vertex " + std::to_string(v.idx()) + " of '" + path +
                        "' has a coordinate that is not a finite number");
    }
    const NominalFlankCoordinates at =
        nominal_flank_coordinates(gear, tooth, side, Eigen::Vector3d(x[0], x[1], x[2]));
    if (at.roll_length_mm >= gear.active_roll_length_min_mm() &&
        at.roll_length_mm <= gear.active_roll_length_max_mm() && at.z_mm >= 0.0 &&
        at.z_mm <= gear.face_width_mm()) {
      nearest = std::min(nearest, std::abs(at.offset_mm));
    }
  }
  if (nearest > kMeshSearchMm) {
    std::ostringstream why;
    why << expected << ", but no vertex of '" << path << "' lies within " << kMeshSearchMm
        << " mm of the nominal flank " << flank << " (";
    if (std::isfinite(nearest)) {
      why << "the nearest over the flank is " << nearest << " mm from it";
    } else {
      why << "none lies over the flank at all";
    }
    why << "): is it another tooth's or flank's mesh, or in another frame or unit?";
    throw value.error(why.str());
  }
  return mesh;
}

}  // namespace

// The plan of a scenario without `probing:` (and the start of one with it): the key table's
// defaults, every tooth.
ProbingPlanSpec probing_defaults() {
  ProbingPlanSpec plan;
  plan.grid.points_along_profile = static_cast<int>(number_default("probing.points_along_profile"));
  plan.grid.sections_across_face = static_cast<int>(number_default("probing.sections_across_face"));
  plan.grid.margin_fraction = number_default("probing.margin_fraction");
  plan.grid.spacing = spacing_of(choice_default("probing.profile_spacing"));
  set_flanks(choice_default("probing.flanks"), plan);
  plan.order = order_of(choice_default("probing.order"));
  return plan;
}

// probing: {points_along_profile, sections_across_face, margin_fraction, profile_spacing,
// teeth: all | [list], flanks: both | L | R, order: tooth_by_tooth | side_by_side}
ProbingPlanSpec read_probing(const YamlMap& probing, int gear_teeth, InputWarnings* warnings) {
  const RangeTable& r = probing_ranges();
  ProbingPlanSpec plan = probing_defaults();
  ProbingGridSpec& grid = plan.grid;
  grid.points_along_profile =
      static_cast<int>(get_ranged_int(probing, "points_along_profile",
                                      r.at("probing.points_along_profile"), warnings)
                           .value_or(grid.points_along_profile));
  grid.sections_across_face =
      static_cast<int>(get_ranged_int(probing, "sections_across_face",
                                      r.at("probing.sections_across_face"), warnings)
                           .value_or(grid.sections_across_face));
  grid.margin_fraction =
      get_ranged(probing, "margin_fraction", r.at("probing.margin_fraction"), warnings)
          .value_or(grid.margin_fraction);
  if (const auto spacing =
          probing.get_choice("profile_spacing", key_choices("probing.profile_spacing"))) {
    grid.spacing = spacing_of(*spacing);
  }
  if (const auto teeth = probing.find("teeth")) {
    const std::string expected =
        "'all' or a list of tooth numbers 1 … " + std::to_string(gear_teeth);
    if (teeth->is_scalar()) {
      if (teeth->as_choice({"all"}) != "all") throw teeth->error(expected);
    } else if (teeth->is_sequence()) {
      for (const YamlValue& t : teeth->as_sequence()) {
        const int tooth = static_cast<int>(t.as_int(1, gear_teeth));
        for (int seen : plan.teeth) {
          if (seen == tooth)
            throw t.error("each tooth once (tooth " + std::to_string(tooth) + " is listed twice)");
        }
        plan.teeth.push_back(tooth);
      }
      if (plan.teeth.empty()) throw teeth->error(expected);
    } else {
      throw teeth->error(expected);
    }
  }
  if (const auto flanks = probing.get_choice("flanks", key_choices("probing.flanks"))) {
    set_flanks(*flanks, plan);
  }
  if (const auto order = probing.get_choice("order", key_choices("probing.order"))) {
    plan.order = order_of(*order);
  }
  return plan;
}

// surfaces: a list of flanks whose real surface is a mesh file, each
//   {tooth: 1..z (required), flank: L | R (required), mesh: file (required),
//    contact: smoothed | facets (default smoothed, see MeshContactPoint)};
// each flank at most once, and only flanks the probing plan probes (a mesh that is never probed
// is a mistake, not a no-op).
std::vector<FlankMeshSurface> read_surfaces(const YamlValue& value, const GearParameters& gear,
                                            const ProbingPlanSpec& plan,
                                            const std::string& source_name) {
  const std::string expected =
      "a list of flank meshes, e.g. [{tooth: 3, flank: R, mesh: flank_3R.stl, contact: smoothed}]";
  if (!value.is_sequence()) throw value.error(expected);
  const InvoluteGear nominal(gear);
  const std::filesystem::path folder = std::filesystem::path(source_name).parent_path();
  std::vector<FlankMeshSurface> surfaces;
  std::vector<int> lines;  // where each entry's tooth is, for the duplicate message
  for (const YamlValue& item : value.as_sequence()) {
    const YamlMap entry = item.as_map(child_keys("surfaces"));
    FlankMeshSurface surface;
    const YamlValue tooth =
        entry.require("tooth", "a tooth number from 1 to " + std::to_string(gear.teeth));
    surface.tooth =
        static_cast<int>(tooth.as_int(scenario_key("surfaces.tooth").integer_min, gear.teeth));
    const YamlValue flank = entry.require("flank", "one of L, R");
    surface.side = flank.as_choice(key_choices("surfaces.flank")) == "R" ? FlankSide::kRight
                                                                         : FlankSide::kLeft;
    const std::string name = std::to_string(surface.tooth) + side_letter(surface.side);
    for (std::size_t k = 0; k < surfaces.size(); ++k) {
      if (surfaces[k].tooth == surface.tooth && surfaces[k].side == surface.side) {
        throw flank.error("each flank once (flank " + name + " is already given at line " +
                          std::to_string(lines[k]) + ")");
      }
    }
    const bool side_probed = surface.side == FlankSide::kRight ? plan.right : plan.left;
    bool tooth_probed = plan.teeth.empty();
    for (int t : plan.teeth) tooth_probed = tooth_probed || t == surface.tooth;
    if (!side_probed || !tooth_probed) {
      throw tooth.error("a flank the probing plan probes (probing.teeth and probing.flanks leave " +
                        name + " out, so its mesh would never be used)");
    }
    const std::string contact = entry.get_choice("contact", key_choices("surfaces.contact"))
                                    .value_or(choice_default("surfaces.contact"));
    surface.contact = contact == "facets" ? MeshContactPoint::kFacets : MeshContactPoint::kSmoothed;
    const YamlValue mesh = entry.require("mesh", "a triangle mesh file (.stl, .ply, .obj or .off)");
    const std::string written = mesh.as_string();
    if (written.empty()) throw mesh.error("a triangle mesh file (.stl, .ply, .obj or .off)");
    const std::filesystem::path file(written);
    surface.mesh_path =
        file.is_absolute() || folder.empty() ? file.string() : (folder / file).string();
    surface.mesh = read_flank_mesh(mesh, surface.mesh_path, nominal, surface.tooth, surface.side);
    surfaces.push_back(std::move(surface));
    lines.push_back(tooth.location().line);
  }
  return surfaces;
}

}  // namespace gearmc
