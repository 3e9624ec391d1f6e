// A scenario: everything one gearmc study is made of, read from a YAML file into typed,
// validated values (docs/architecture.md, principle 5). Unknown keys, wrong types and out-of-range
// values are InputErrors with file:line:column. Units: mm, degrees, µm as the key names say.
// Public API (docs/api.md): a stable part of the C++ interface, installed with its includes.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "core/input_error.h"
#include "engine/contact/tooth_space.h"
#include "engine/plan/probing_grid.h"
#include "engine/scenario/claims.h"
#include "engine/scenario/evaluation_spec.h"
#include "gears/deviations.h"
#include "gears/involute_gear.h"
#include "gears/tolerances.h"
#include "surfaces/mesh_contact_point.h"
#include "surfaces/triangle_mesh_fwd.h"

namespace gearmc {

class EffectChain;  // engine/effects/measurement_effect.h
struct CmmModel;    // engine/effects/cmm_effects.h

// A flank whose real surface is a triangle mesh file (`surfaces:`, e.g. a scanned or CAD flank):
// in every gear of a run it is probed instead of the analytic perturbed flank, so that flank's
// random deviations, the gear's eccentricity and `normal_um` do not apply to it. The mesh is in
// the datum frame in mm (the frame `gearmc export-mesh` writes).
struct FlankMeshSurface {
  int tooth = 1;  // 1..z
  FlankSide side = FlankSide::kRight;
  std::string mesh_path;  // as opened: a relative path is taken from the scenario file's folder
  MeshContactPoint contact = MeshContactPoint::kSmoothed;
  // Read and checked (finite coordinates, some vertex within kMeshSearchMm of the nominal flank)
  // when the scenario is parsed; shared, read-only. TriangleMesh is only declared here
  // (surfaces/triangle_mesh_fwd.h): code that walks the mesh includes surfaces/flank_mesh.h.
  std::shared_ptr<const TriangleMesh> mesh;
};

struct Scenario {
  Scenario();        // effects: an empty chain (the chain's type is complete only in scenario.cpp)
  std::string name;  // from `name:`, else the file's stem
  std::string source_path;  // file it was read from ("<built-in>" for the reference)
  std::string source_text;  // the YAML text itself (reports show it)
  std::uint64_t seed = 1;
  GearParameters gear;
  ToleranceSpec tolerances;
  DeviationModel deviations;
  // Deterministic normal deviation, muParser syntax in L, z, tooth, side (µm), added to the
  // random deviations (docs/formats.md, "Deterministic deviations"). Empty = none.
  std::string normal_expression_um;
  ProbingPlanSpec probing;        // `probing:` (P1: N 10, M 5, 5 % margins, all teeth, both)
  double stylus_radius_mm = 0.5;  // `stylus: radius_mm` (P1: 0.5 mm)
  // `stylus: shaft_diameter_mm`: the stem's diameter, 0 = the shaft is not checked for
  // collisions (engine/contact/tooth_space.h).
  double stylus_shaft_diameter_mm = 0.0;
  ShaftAxis stylus_shaft_axis = ShaftAxis::kZ;  // `stylus: shaft_axis` (z: from above)
  int gears = 50;                               // `run: gears` (P1: 50)
  std::vector<FlankMeshSurface> surfaces;       // `surfaces:` (none: every flank is analytic)
  // `effects:` — the measurement effects, in physical order (empty: δRcomp alone), read by the
  // effects module (parse_effects) from the section the scenario hands over. Shared, read-only;
  // never null (a default Scenario holds an empty chain). Code that uses the chain includes
  // engine/effects/measurement_effect.h.
  std::shared_ptr<const EffectChain> effects;
  // `cmm:` — a CMM from its data sheet (docs/cmm.md): the section as read and the machines kept
  // by its acceptance tests; null without the section. Its effects (`cmm_geometry`,
  // `cmm_probing`) are in `effects`, after the section's own.
  std::shared_ptr<const CmmModel> cmm;
  // `claims:` — accuracy claims `gearmc check` decides (claims.h); empty: none. Other commands
  // read and validate them but do not use them.
  std::vector<ClaimSpec> claims;
  // `evaluation:` — the ISO 1328-1 gear parameters evaluated from every simulated measurement
  // (evaluation_spec.h); absent = none.
  std::optional<EvaluationSpec> evaluation;
  // Values that are valid but outside their usual range (parameter_ranges.h), each a whole
  // located message "file:line:col: key: …"; the caller prints them (they are not errors).
  std::vector<std::string> warnings;
};

// Reads and validates a scenario file (a regular file of at most kMaxScenarioBytes, UTF-8),
// including the resolution of its tolerances for its gear. Throws InputError.
Scenario load_scenario_file(const std::string& path);
// Same, from text; `source_name` is used in error messages.
Scenario parse_scenario(const std::string& yaml_text, const std::string& source_name);
// Resolves the scenario's tolerances for its gear; a ToleranceError becomes an InputError
// naming the scenario file and the `tolerances` section. (A loaded scenario has already been
// checked; this is for every command that needs the resolved set.)
ToleranceSet resolve_scenario_tolerances(const Scenario& scenario, const InvoluteGear& gear);

// What a command may override on a scenario (`--seed`, `--gears`). The scenario is the one
// place the seed and the gear count live; apply_overrides is the one place they are overridden,
// so every command means the same by them. (`diagnose --seed` is another seed: its null
// simulations'.)
struct ScenarioOverrides {
  std::optional<std::uint64_t> seed;  // replaces `seed:`
  std::optional<int> gears;           // replaces `run: gears`
};
void apply_overrides(const ScenarioOverrides& overrides, Scenario& scenario);

// The built-in reference scenario: P1's gear (Table 1) with P1's tolerances. Its text is the
// same as scenarios/p1_reference.yaml.
Scenario reference_scenario();

}  // namespace gearmc
