// Scenario files: the YAML text is read section by section (gear, tolerances, deviations) into
// the typed, validated Scenario struct (docs/architecture.md, principle 5), so that constructors
// downstream only ever see good values. Unknown keys, wrong types, out-of-range values, missing
// required keys, YAML syntax errors and unreadable files all become one InputError naming
// file:line:column, the dotted key, the value and what was expected (principle 4).
// The schema is documented with each section reader below.
#include "engine/scenario/scenario.h"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <optional>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "engine/effects/effect_config.h"
#include "engine/effects/measurement_effect.h"
#include "engine/io/input_error.h"
#include "engine/io/input_file.h"
#include "engine/io/parameter_ranges.h"
#include "engine/io/scenario_keys.h"
#include "engine/io/yaml_reader.h"
#include "engine/probing/mesh_probe.h"
#include "engine/scenario/claims.h"
#include "gears/deviations.h"
#include "gears/normal_expression.h"

namespace gearmc {
namespace {

// gear: the spur gear (ISO 21771 quantities; lengths in mm, angle in degrees, rack in modules).
//   teeth (required, 5..1000), module_mm (required, > 0), pressure_angle_deg (0 < α < 45,
//   default 20), profile_shift ([-1.5, 3], default 0), face_width_mm (required, > 0),
//   tip_diameter_mm, root_diameter_mm (> 0, optional overrides),
//   basic_rack: {addendum > 0, dedendum > 0, root_radius >= 0} (defaults: ISO 53 profile A).
// The parameters together must make a gear (validate_gear_parameters); if not, the error is
// placed at the `gear` key.
GearParameters read_gear(const YamlMap& gear, InputWarnings* warnings) {
  const RangeTable& r = gear_ranges();
  GearParameters p;
  const auto required = [&](const std::string& key) {
    const ParameterRange& range = r.at("gear." + key);
    return gear.require(key, describe_range(range));
  };
  p.teeth = static_cast<int>(read_ranged_int(required("teeth"), r.at("gear.teeth"), warnings));
  p.module_mm = read_ranged(required("module_mm"), r.at("gear.module_mm"), warnings);
  p.pressure_angle_deg =
      get_ranged(gear, "pressure_angle_deg", r.at("gear.pressure_angle_deg"), warnings)
          .value_or(number_default("gear.pressure_angle_deg"));
  p.profile_shift = get_ranged(gear, "profile_shift", r.at("gear.profile_shift"), warnings)
                        .value_or(number_default("gear.profile_shift"));
  p.face_width_mm = read_ranged(required("face_width_mm"), r.at("gear.face_width_mm"), warnings);
  p.tip_diameter_mm = get_ranged(gear, "tip_diameter_mm", r.at("gear.tip_diameter_mm"), warnings);
  p.root_diameter_mm =
      get_ranged(gear, "root_diameter_mm", r.at("gear.root_diameter_mm"), warnings);
  p.rack.addendum = number_default("gear.basic_rack.addendum");
  p.rack.dedendum = number_default("gear.basic_rack.dedendum");
  p.rack.root_radius = number_default("gear.basic_rack.root_radius");
  if (const auto rack = gear.get_map("basic_rack", child_keys("gear.basic_rack"))) {
    p.rack.addendum = get_ranged(*rack, "addendum", r.at("gear.basic_rack.addendum"), warnings)
                          .value_or(p.rack.addendum);
    p.rack.dedendum = get_ranged(*rack, "dedendum", r.at("gear.basic_rack.dedendum"), warnings)
                          .value_or(p.rack.dedendum);
    p.rack.root_radius =
        get_ranged(*rack, "root_radius", r.at("gear.basic_rack.root_radius"), warnings)
            .value_or(p.rack.root_radius);
  }
  const std::string why = validate_gear_parameters(p);
  if (!why.empty()) {
    throw InputError(gear.location(), gear.path(), "", "parameters that make a gear, but " + why);
  }
  return p;
}

// Strict decimal integer in [min, max] (no sign, no leading zeros beyond "0"); nullopt if not.
std::optional<int> grade_number(const std::string& text, int min, int max) {
  if (text.empty() || text.size() > 2 || (text.size() > 1 && text[0] == '0')) return std::nullopt;
  int value = 0;
  for (const char c : text) {
    if (c < '0' || c > '9') return std::nullopt;
    value = 10 * value + (c - '0');
  }
  if (value < min || value > max) return std::nullopt;
  return value;
}

// The grade in the form the standard uses: GOST 1643-81 "K-S-C" (kinematic, smoothness and
// contact grades, each 1..12) or one grade 1..12 for all three; ISO 1328-1:2013 the flank
// tolerance class 1..11. Written as text or as an integer.
std::string read_grade(const YamlValue& value, ToleranceStandard standard) {
  const bool gost = standard == ToleranceStandard::kGost1643_81;
  const std::string expected =
      gost ? "a GOST 1643-81 accuracy grade: 'K-S-C' (kinematic-smoothness-contact grades, each "
             "from 1 to 12, e.g. \"6-5-5\") or one grade from 1 to 12"
           : "an ISO 1328-1:2013 flank tolerance class, an integer from 1 to 11";
  if (!value.is_scalar()) throw value.error(expected);
  const std::string text = value.node().Scalar();
  if (!gost) {
    if (!grade_number(text, 1, 11)) throw value.error(expected);
    return text;
  }
  std::vector<std::string> parts;
  std::size_t start = 0;
  while (true) {
    const std::size_t dash = text.find('-', start);
    parts.push_back(text.substr(start, dash - start));
    if (dash == std::string::npos) break;
    start = dash + 1;
  }
  if (parts.size() != 1 && parts.size() != 3) throw value.error(expected);
  for (const std::string& part : parts) {
    if (!grade_number(part, 1, 12)) throw value.error(expected);
  }
  return text;
}

std::vector<std::string> tolerance_symbols(ToleranceStandard standard) {
  std::vector<std::string> symbols;
  for (const ToleranceKind kind : all_tolerance_kinds()) {
    if (const auto symbol = tolerance_symbol(kind, standard)) symbols.push_back(*symbol);
  }
  return symbols;
}

// overrides_um: {symbol: µm}. The symbols are the chosen standard's (tolerance_symbol); E_Hs is
// the magnitude of the least rack shift (>= 0), every other value a tolerance (> 0).
std::map<ToleranceKind, double> read_overrides(const YamlMap& overrides, ToleranceStandard standard,
                                               InputWarnings* warnings) {
  const ToleranceStandard other = standard == ToleranceStandard::kGost1643_81
                                      ? ToleranceStandard::kIso1328_1_2013
                                      : ToleranceStandard::kGost1643_81;
  std::map<ToleranceKind, double> values;
  for (const YamlMap::Entry& entry : overrides.entries()) {
    const std::optional<ToleranceKind> kind = tolerance_kind_from_symbol(entry.key, standard);
    if (!kind) {
      const std::vector<std::string> symbols = tolerance_symbols(standard);
      std::string expected = "a tolerance symbol of " + standard_name(standard) + " (";
      for (std::size_t i = 0; i < symbols.size(); ++i) expected += (i ? ", " : "") + symbols[i];
      expected += ")";
      if (tolerance_kind_from_symbol(entry.key, other)) {
        expected += "; '" + entry.key + "' is a symbol of " + standard_name(other);
      }
      throw InputError(entry.value.key_location(), entry.value.path(), entry.key, expected,
                       did_you_mean(entry.key, symbols));
    }
    const bool shift = *kind == ToleranceKind::kThicknessUpper;
    const ParameterRange& range = tolerance_ranges().at(
        shift ? "tolerances.overrides_um.E_Hs" : "tolerances.overrides_um.tolerance");
    values[*kind] = read_ranged(entry.value, range, warnings);
  }
  return values;
}

// tolerances: standard (gost_1643_81 | iso_1328_1_2013, default gost_1643_81), grade (see
// read_grade; default "6-5-5" for GOST, required for ISO), overrides_um (see read_overrides).
ToleranceSpec read_tolerances(const YamlMap& tolerances, InputWarnings* warnings) {
  ToleranceSpec spec;
  const std::string standard = tolerances.get_choice("standard", key_choices("tolerances.standard"))
                                   .value_or(choice_default("tolerances.standard"));
  spec.standard = standard == standard_name(ToleranceStandard::kGost1643_81)
                      ? ToleranceStandard::kGost1643_81
                      : ToleranceStandard::kIso1328_1_2013;
  if (const auto grade = tolerances.find("grade")) {
    spec.grade = read_grade(*grade, spec.standard);
  } else if (spec.standard == ToleranceStandard::kIso1328_1_2013) {
    throw tolerances.missing("grade",
                             "an ISO 1328-1:2013 flank tolerance class, an integer from 1 to 11");
  }
  if (const auto overrides = tolerances.find("overrides_um")) {
    spec.overrides_um = read_overrides(overrides->as_open_map(), spec.standard, warnings);
  }
  return spec;
}

// {distribution: uniform | normal | at_tolerance, k: > 0}, each key falling back to `base`.
DeviationDistribution read_law(const YamlMap& map, DeviationDistribution base,
                               InputWarnings* warnings) {
  if (const auto law = map.get_choice("distribution", key_choices("deviations.distribution"))) {
    base.law = *law == "normal"         ? DeviationDistribution::Law::kNormal
               : *law == "at_tolerance" ? DeviationDistribution::Law::kAtTolerance
                                        : DeviationDistribution::Law::kUniform;
  }
  base.k = get_ranged(map, "k", deviation_ranges().at("deviations.k"), warnings).value_or(base.k);
  return base;
}

// deviations: random (bool, default true); distribution and k: the default law of every group;
// eccentricity, pitch, thickness: {distribution, k}; profile, helix: {distribution, k,
// control_points 4..64} (the law applies to both slope and form of the group); normal_um: a
// muParser expression in L, z, tooth, side (µm), checked where it is compiled.
DeviationModel read_deviations(const YamlMap& deviations, std::string* normal_expression_um,
                               InputWarnings* warnings) {
  DeviationModel model;
  model.random = deviations.get_bool("random").value_or(boolean_default("deviations.random"));
  DeviationDistribution defaults;  // the table's law and k, unless the section gives them
  const std::string default_law = choice_default("deviations.distribution");
  defaults.law = default_law == "normal"         ? DeviationDistribution::Law::kNormal
                 : default_law == "at_tolerance" ? DeviationDistribution::Law::kAtTolerance
                                                 : DeviationDistribution::Law::kUniform;
  defaults.k = number_default("deviations.k");
  const DeviationDistribution base = read_law(deviations, defaults, warnings);
  model.eccentricity = model.pitch = model.thickness = model.profile_slope = model.profile_form =
      model.helix_slope = model.helix_form = base;

  const std::vector<std::pair<std::string, DeviationDistribution*>> simple_groups = {
      {"eccentricity", &model.eccentricity},
      {"pitch", &model.pitch},
      {"thickness", &model.thickness}};
  for (const auto& [key, law] : simple_groups) {
    if (const auto group = deviations.get_map(key, child_keys("deviations." + key))) {
      *law = read_law(*group, base, warnings);
    }
  }

  const ParameterRange& points = deviation_ranges().at("deviations.control_points");
  model.profile_form_control_points =
      static_cast<int>(number_default("deviations.profile.control_points"));
  model.helix_form_control_points =
      static_cast<int>(number_default("deviations.helix.control_points"));
  if (const auto profile = deviations.get_map("profile", child_keys("deviations.profile"))) {
    model.profile_slope = model.profile_form = read_law(*profile, base, warnings);
    model.profile_form_control_points =
        static_cast<int>(get_ranged_int(*profile, "control_points", points, warnings)
                             .value_or(model.profile_form_control_points));
  }
  if (const auto helix = deviations.get_map("helix", child_keys("deviations.helix"))) {
    model.helix_slope = model.helix_form = read_law(*helix, base, warnings);
    model.helix_form_control_points =
        static_cast<int>(get_ranged_int(*helix, "control_points", points, warnings)
                             .value_or(model.helix_form_control_points));
  }

  if (const auto expression = deviations.find("normal_um")) {
    const std::string expected =
        "a muParser expression of L, z, tooth, side giving µm, e.g. \"2*sin(2*_pi*L/5)\"";
    if (!expression->is_scalar()) throw expression->error(expected);
    const std::string text = expression->node().Scalar();
    if (text.find_first_not_of(" \t\r\n") == std::string::npos) throw expression->error(expected);
    try {
      const NormalExpression compiled(text);  // compile now: errors point into the file
    } catch (const ExpressionError& e) {
      throw expression->error(expected + " (muParser: " + shown_input(e.what(), 2 * kShownChars) +
                              " at character " + std::to_string(e.position() + 1) + ")");
    }
    *normal_expression_um = text;
  }
  return model;
}

// The scenario's name: results go to results/<name>/, so it must be one plain path component.
std::string read_name(const YamlValue& value) {
  const std::string expected = "a non-empty name without '/' or '\\' (it names the results folder)";
  const std::string name = value.as_string();
  if (name.empty() || name == "." || name == ".." ||
      name.find_first_of("/\\") != std::string::npos) {
    throw value.error(expected);
  }
  return name;
}

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
    if (at.roll_length_mm >= gear.form_roll_length_mm() &&
        at.roll_length_mm <= gear.tip_roll_length_mm() && at.z_mm >= 0.0 &&
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

// Where a tolerance problem is best shown: the override of `kind` when the scenario gives one,
// else the grade, else the tolerances section, else the gear (a default GOST grade).
InputLocation tolerance_place(const YamlMap& gear, const std::optional<YamlMap>& tolerances,
                              std::optional<ToleranceKind> kind, std::string* key) {
  if (tolerances) {
    if (kind) {
      if (const auto overrides = tolerances->find("overrides_um")) {
        const YamlMap map = overrides->as_open_map();
        for (const YamlMap::Entry& entry : map.entries()) {
          if (tolerance_kind_from_symbol(entry.key, ToleranceStandard::kGost1643_81) == kind ||
              tolerance_kind_from_symbol(entry.key, ToleranceStandard::kIso1328_1_2013) == kind) {
            *key = entry.value.path();
            return entry.value.location();
          }
        }
      }
    }
    if (const auto grade = tolerances->find("grade")) {
      *key = grade->path();
      return grade->location();
    }
    *key = tolerances->path();
    return tolerances->location();
  }
  *key = gear.path();
  return gear.location();
}

// Gears drawn by the runout check (see check_tolerances).
constexpr int kRunoutCheckGears = 8;

// Resolves the scenario's tolerances for its gear (as every command does later) and checks
// that the runout tolerance F_r can hold what the profile and helix tolerances alone produce:
// the gear sampler shrinks pitch deviations to fit F_r but not profile and helix shapes, so a
// gear whose shapes alone break F_r stops a run. The check draws the run's first
// kRunoutCheckGears gears (the scenario's seed and laws) and rejects F_r when one of them does
// not fit; when gears with every profile and helix deviation at its tolerance (the largest any
// law draws) do not fit, it warns that a longer run may meet such a gear.
void check_tolerances(Scenario& scenario, const YamlMap& gear_map,
                      const std::optional<YamlMap>& tolerances) {
  const InvoluteGear gear(scenario.gear);
  ToleranceSet set;
  std::string key;
  try {
    set = resolve_tolerances(scenario.tolerances, gear);
  } catch (const ToleranceError& e) {
    const InputLocation where = tolerance_place(gear_map, tolerances, std::nullopt, &key);
    throw InputError(where, key + ": " + e.what());
  }
  if (!set.get_um(ToleranceKind::kRunout) || !scenario.deviations.random) return;
  const GearSampler sampler(gear, set, scenario.deviations, scenario.seed);
  for (int k = 0; k < kRunoutCheckGears; ++k) {
    try {
      sampler.draw(k);
    } catch (const ToleranceError& e) {
      const InputLocation where =
          tolerance_place(gear_map, tolerances, ToleranceKind::kRunout, &key);
      throw InputError(where, key + ": " + e.what() + " (gear " + std::to_string(k) +
                                  " of the run; every command rejects this scenario)");
    }
  }
  DeviationModel worst = scenario.deviations;
  for (DeviationDistribution* law :
       {&worst.profile_slope, &worst.profile_form, &worst.helix_slope, &worst.helix_form}) {
    law->law = DeviationDistribution::Law::kAtTolerance;
  }
  const GearSampler worst_sampler(gear, set, worst, scenario.seed);
  for (int k = 0; k < kRunoutCheckGears; ++k) {
    try {
      worst_sampler.draw(k);
    } catch (const ToleranceError& e) {
      const InputLocation where =
          tolerance_place(gear_map, tolerances, ToleranceKind::kRunout, &key);
      scenario.warnings.push_back(
          InputError(where, key +
                                ": F_r leaves little room: with profile and helix deviations "
                                "at their tolerances, " +
                                e.what() + "; a run may stop at such a gear")
              .what());
      break;
    }
  }
}

}  // namespace

Scenario::Scenario() : effects(std::make_shared<const EffectChain>()) {}

Scenario parse_scenario(const std::string& yaml_text, const std::string& source_name) {
  // Every user string may end up in JSON outputs and reports: the whole text must be UTF-8.
  require_utf8(yaml_text, source_name, "scenario file");
  const YamlValue root = parse_yaml_document(yaml_text, source_name);
  const std::string expected_top =
      "a map of scenario keys (name, seed, gear, tolerances, deviations, probing, stylus, run, "
      "surfaces, effects, claims, evaluation)";
  if (root.is_null()) {
    throw InputError(root.location(), "", "", expected_top + ", but the scenario is empty");
  }
  if (!root.is_map()) throw root.error(expected_top);
  const YamlMap top = root.as_map(child_keys(""));

  Scenario scenario;
  scenario.source_path = source_name;
  scenario.source_text = yaml_text;
  if (const auto name = top.find("name")) {
    scenario.name = read_name(*name);
  } else {
    scenario.name = std::filesystem::path(source_name).stem().string();
    if (scenario.name.empty()) scenario.name = "scenario";
  }
  scenario.seed =
      top.get_uint64("seed").value_or(static_cast<std::uint64_t>(number_default("seed")));
  InputWarnings* warnings = &scenario.warnings;
  const YamlMap gear_map = top.require_map("gear", child_keys("gear"));
  scenario.gear = read_gear(gear_map, warnings);
  const std::optional<YamlMap> tolerances = top.get_map("tolerances", child_keys("tolerances"));
  if (tolerances) scenario.tolerances = read_tolerances(*tolerances, warnings);
  if (const auto deviations = top.get_map("deviations", child_keys("deviations"))) {
    scenario.deviations = read_deviations(*deviations, &scenario.normal_expression_um, warnings);
  }
  // The tolerances are resolved here, so that every command (geometry, run, simulate, …)
  // accepts or rejects the same scenario, with the place of the cause.
  check_tolerances(scenario, gear_map, tolerances);
  const std::optional<YamlMap> probing = top.get_map("probing", child_keys("probing"));
  scenario.probing =
      probing ? read_probing(*probing, scenario.gear.teeth, warnings) : probing_defaults();
  {
    const ProbingPlanSpec& plan = scenario.probing;
    const double teeth =
        plan.teeth.empty() ? scenario.gear.teeth : static_cast<double>(plan.teeth.size());
    const double points = static_cast<double>(plan.grid.points_along_profile) *
                          plan.grid.sections_across_face * teeth *
                          ((plan.left ? 1 : 0) + (plan.right ? 1 : 0));
    const InputLocation where = probing ? probing->location() : top.location();
    check_ranged(points, probing_ranges().at("probing.points_per_gear"), where,
                 std::to_string(static_cast<long long>(points)), warnings);
  }
  scenario.stylus_radius_mm = number_default("stylus.radius_mm");
  scenario.gears = static_cast<int>(number_default("run.gears"));
  if (const auto stylus = top.get_map("stylus", child_keys("stylus"))) {
    scenario.stylus_radius_mm =
        get_ranged(*stylus, "radius_mm", probing_ranges().at("stylus.radius_mm"), warnings)
            .value_or(scenario.stylus_radius_mm);
  }
  if (const auto run = top.get_map("run", child_keys("run"))) {
    scenario.gears =
        static_cast<int>(get_ranged_int(*run, "gears", probing_ranges().at("run.gears"), warnings)
                             .value_or(scenario.gears));
  }
  if (const auto surfaces = top.find("surfaces")) {
    scenario.surfaces = read_surfaces(*surfaces, scenario.gear, scenario.probing, source_name);
  }
  if (const auto effects = top.find("effects")) {
    scenario.effects = std::make_shared<const EffectChain>(parse_effects(*effects, warnings));
  }
  if (const auto claims = top.find("claims")) {
    scenario.claims = read_claims(*claims, !scenario.effects->empty(), warnings);
  }
  if (const auto evaluation = top.find("evaluation")) {
    scenario.evaluation = read_evaluation(*evaluation, scenario.gear.face_width_mm, warnings);
    check_evaluation(*evaluation, *scenario.evaluation, scenario.probing, scenario.gear.teeth,
                     !scenario.surfaces.empty());
  }
  // A claim on a gear parameter needs that parameter in `evaluation:`.
  const auto joined = [](const std::vector<std::string>& v) {
    std::string out;
    for (const std::string& x : v) out += (out.empty() ? "" : ", ") + x;
    return out;
  };
  for (const ClaimSpec& c : scenario.claims) {
    if (c.quantity != ClaimQuantity::kParameterError) continue;
    const std::vector<std::string>* evaluated =
        scenario.evaluation ? &scenario.evaluation->parameters : nullptr;
    if (!evaluated ||
        std::find(evaluated->begin(), evaluated->end(), c.parameter) == evaluated->end()) {
      throw InputError(c.quantity_where, "claims.quantity", c.quantity_text,
                       "a gear parameter the scenario's `evaluation:` evaluates (" +
                           (evaluated ? "it evaluates: " + joined(*evaluated)
                                      : std::string("add evaluation: {parameters: all}")) +
                           ")");
    }
  }
  return scenario;
}

Scenario load_scenario_file(const std::string& path) {
  return parse_scenario(read_input_file(path, "scenario file", kMaxScenarioBytes), path);
}

ToleranceSet resolve_scenario_tolerances(const Scenario& scenario, const InvoluteGear& gear) {
  try {
    return resolve_tolerances(scenario.tolerances, gear);
  } catch (const ToleranceError& e) {
    throw InputError({scenario.source_path, 0, 0},
                     scenario.source_path + ": tolerances: " + e.what());
  }
}

}  // namespace gearmc
