// The measurement model: everything a scenario fixes before the first gear is drawn, built once
// and shared read-only by every command that measures (run, simulate, diagnose, export-mesh and
// the commands to come). It holds the nominal gear, the resolved tolerances, the sampler of
// perturbed gears, the probing plan with what does not depend on the gear drawn (each planned
// point's nominal point and outward normal, its place in the probing sequence, the nominal stylus
// path's tooth-space clearance), the mesh flanks that replace analytic ones (`surfaces:`) and the
// measurement effects. Measuring one gear with it is gear_measurement.h (docs/architecture.md,
// "What flows through the engine"). Lengths in mm, gear frame (axis +Z, tooth 1 on +X).
#pragma once

#include <memory>
#include <vector>

#include "engine/contact/tooth_space.h"
#include "engine/plan/probing_grid.h"
#include "engine/scenario/scenario.h"
#include "gears/deviations.h"
#include "gears/involute_gear.h"
#include "gears/point_key.h"
#include "gears/tolerances.h"

namespace gearmc {

class MeshFlankProbe;
class NormalExpression;
struct FlankExtent;

// One planned point of the probing plan, with what does not depend on the gear drawn.
struct PlanPoint : GridPosition {
  double roll_length_mm = 0;  // ISO roll length L of the nominal point
  double z_mm = 0;            // height above the lower face
  FlankPoint nominal;         // nominal point and outward unit normal (gear frame)
  int order = 0;              // position in one gear's probing sequence (0-based)
  double clearance_mm = 0;    // the nominal stylus path's smallest tooth-space clearance
};

// One probed flank of the plan: its points in grid order, index j * N + i.
struct PlanFlank {
  int tooth = 1;
  FlankSide side = FlankSide::kLeft;
  std::vector<PlanPoint> points;
  const MeshFlankProbe* mesh = nullptr;  // the scenario's mesh for this flank, or null
};

class MeasurementModel {
 public:
  // Throws InputError when the scenario's tolerances cannot be resolved for its gear.
  explicit MeasurementModel(const Scenario& scenario);
  ~MeasurementModel();
  MeasurementModel(const MeasurementModel&) = delete;
  MeasurementModel& operator=(const MeasurementModel&) = delete;

  const Scenario& scenario() const { return scenario_; }
  const InvoluteGear& gear() const { return *gear_; }
  const ToleranceSet& tolerances() const { return tolerances_; }
  const EffectChain& effects() const { return *scenario_.effects; }
  double stylus_radius_mm() const { return scenario_.stylus_radius_mm; }
  // Ball and shaft, for the tooth-space collision checks.
  StylusShape stylus_shape() const {
    return {scenario_.stylus_radius_mm, 0.5 * scenario_.stylus_shaft_diameter_mm,
            scenario_.stylus_shaft_axis};
  }

  // The probed flanks in (tooth, side) order: the scenario's teeth (all when none are listed),
  // left before right.
  const std::vector<PlanFlank>& flanks() const { return flanks_; }
  // The plan's points in probing order (the scenario's `order:`); index = PlanPoint::order.
  const std::vector<const PlanPoint*>& sequence() const { return sequence_; }
  int points_per_flank() const;
  int probed_teeth() const;
  int sequence_length() const { return static_cast<int>(sequence_.size()); }
  // Where the real flank exists: form to tip roll length, 0 to b (contact.h).
  const FlankExtent& extent() const { return *extent_; }

  // Gear k (0-based) as drawn from the scenario's streams (seed, k, purpose): the same gear in
  // every command. Thread-safe.
  PerturbedGear draw_gear(int k) const { return sampler_->draw(k); }
  // The scenario's `normal_um` expression compiled for the calling thread (muParser is not
  // thread-safe), or null when the scenario has none.
  const NormalExpression* expression() const;

 private:
  Scenario scenario_;
  std::unique_ptr<InvoluteGear> gear_;
  ToleranceSet tolerances_;
  std::unique_ptr<GearSampler> sampler_;
  std::unique_ptr<FlankExtent> extent_;
  std::vector<PlanFlank> flanks_;
  std::vector<const PlanPoint*> sequence_;
  // The scenario's mesh flanks, built once (AABB trees), read-only across threads.
  std::vector<std::unique_ptr<const MeshFlankProbe>> meshes_;
  struct ThreadExpressions;
  std::unique_ptr<ThreadExpressions> expressions_;
};

}  // namespace gearmc
