// The per-point measurement pipeline, the one every command uses (docs/architecture.md): gear k
// is drawn once from the model's streams; at each planned point the stylus approaches along −n
// and its exact first contact with the real flank is solved (analytic flank: contact.h; a
// scenario mesh: mesh_probe.h), the tooth space is checked for collisions, and the measurement
// effects move the stylus centre the CMM records. `gearmc run` reduces the results into
// statistics, `gearmc simulate` writes them as readings, `gearmc diagnose` predicts readings
// from the contacts with the effects at their nominal values. Lengths in mm, errors in µm, gear
// frame (axis +Z, tooth 1 on +X).
#pragma once

#include <Eigen/Core>
#include <functional>
#include <span>
#include <vector>

#include "engine/contact/contact.h"
#include "engine/effects/measurement_effect.h"
#include "engine/measurement/measurement_model.h"

namespace gearmc {

// How a gear's measurement applies the model's effects.
enum class EffectMode {
  kNone,   // the contact only: recorded centre = true stylus centre at contact
  kDrawn,  // parameters drawn per gear (seed, gear), random parts per point (seed, gear, order)
};

// What one planned point gave.
struct PointMeasurement {
  const PlanPoint* plan = nullptr;
  ContactResult contact;
  // Only when the contact is valid (contact.status == kOk):
  PointContext context;  // as the effects see the point (only when effects were applied)
  Eigen::Vector3d recorded_centre = Eigen::Vector3d::Zero();  // what the CMM records, mm
  std::span<const double> contributions;  // kDrawn: each effect's change of the reading, µm
  // The total point error along n, µm: (E' − C)·n with E' = c − R n the point reported from the
  // recorded centre c (= contact.normal_error_um without effects).
  double total_error_um = 0.0;
  bool valid() const { return contact.status == ContactResult::Status::kOk; }
};

// The effects' view of a planned or measured point: nominal point p, outward normal n, the real
// surface's normal at contact, approach azimuth φ = atan2(−n_y, −n_x), and its place in one
// gear's probing sequence (order 0-based of `sequence_length`).
PointContext point_context(const Eigen::Vector3d& p, const Eigen::Vector3d& n,
                           const Eigen::Vector3d& contact_normal, int order, int sequence_length,
                           int tooth, FlankSide side, double stylus_radius_mm);

// Gear k drawn from the model and measured point by point. One object per gear and thread.
class GearMeasurement {
 public:
  GearMeasurement(const MeasurementModel& model, int k, EffectMode effects);

  int index() const { return k_; }
  const PerturbedGear& perturbed() const { return perturbed_; }
  const MeasurementModel& model() const { return model_; }

  // Measures every point of `flank` in grid order (j * N + i) and calls `visit` with each.
  void measure_flank(const PlanFlank& flank,
                     const std::function<void(const PointMeasurement&)>& visit) const;
  // Every flank of the plan, in MeasurementModel::flanks() order.
  void measure(const std::function<void(const PointMeasurement&)>& visit) const;

  // The real surface's normal deviation at the planned point's nominal (L, z), µm along the
  // nominal outward normal (what a calibrated artefact's certificate gives). Analytic flanks
  // only (a mesh flank's deviation at the nominal point is not known: throws std::logic_error).
  double surface_deviation_um(const PlanPoint& point) const;

 private:
  const MeasurementModel& model_;
  int k_;
  EffectMode mode_;
  PerturbedGear perturbed_;
  EffectValues effect_values_;
};

}  // namespace gearmc
