// The per-point measurement pipeline (see gear_measurement.h).
#include "engine/measurement/gear_measurement.h"

#include <cmath>
#include <stdexcept>

#include "engine/contact/contact_certificate.h"
#include "engine/contact/mesh_probe.h"
#include "surfaces/analytic_flank.h"

namespace gearmc {

PointContext point_context(const Eigen::Vector3d& p, const Eigen::Vector3d& n,
                           const Eigen::Vector3d& contact_normal, int order, int sequence_length,
                           int tooth, FlankSide side, double stylus_radius_mm) {
  PointContext context;
  context.p = p;
  context.n = n;
  context.contact_normal = contact_normal;
  context.azimuth_rad = std::atan2(-n.y(), -n.x());
  context.order = order;
  context.sequence_length = sequence_length;
  context.tooth = tooth;
  context.side = side;
  context.stylus_radius_mm = stylus_radius_mm;
  return context;
}

GearMeasurement::GearMeasurement(const MeasurementModel& model, int k, EffectMode effects)
    : model_(model), k_(k), mode_(effects), perturbed_(model.draw_gear(k)) {
  if (mode_ == EffectMode::kDrawn && !model_.effects().empty()) {
    effect_values_ = model_.effects().draw(model_.scenario().seed, k);
  }
}

void GearMeasurement::measure_flank(
    const PlanFlank& flank, const std::function<void(const PointMeasurement&)>& visit) const {
  const InvoluteGear& gear = model_.gear();
  const double R = model_.stylus_radius_mm();
  const EffectChain& effects = model_.effects();
  const bool with_effects = mode_ == EffectMode::kDrawn && !effects.empty();
  std::vector<double> contributions(with_effects ? effects.size() : 0);
  const AnalyticFlank surface(gear, flank.tooth, flank.side,
                              perturbed_.flank(flank.tooth, flank.side), perturbed_.eccentricity_mm,
                              model_.expression());
  // Stage 1 of the contact certificate for the whole flank at once (contact_certificate.h).
  const FlankCurvatureBound bound =
      flank.mesh ? FlankCurvatureBound{}
                 : flank_curvature_bound(surface, R, model_.extent().roll_length_min,
                                         model_.extent().roll_length_max);
  PointMeasurement m;
  for (const PlanPoint& q : flank.points) {
    const FlankPoint& fp = q.nominal;
    m.plan = &q;
    m.contact = flank.mesh
                    ? flank.mesh->probe(fp.point, fp.normal, R)
                    : solve_contact(surface, model_.extent(), fp.point, fp.normal, R,
                                    q.roll_length_mm, q.z_mm, planned_base_angle(fp), &bound);
    ContactResult& r = m.contact;
    // The real stylus path is the nominal one moved along n by |t - R| (t = (O - p)·n); the
    // clearances are 1-Lipschitz in the path's position, so a path whose nominal clearance
    // exceeds that shift (plus 1 µm) cannot collide: the exact check is skipped.
    if (r.status == ContactResult::Status::kOk &&
        q.clearance_mm - std::abs((r.centre - fp.point).dot(fp.normal) - R) < 1e-3) {
      check_tooth_space(gear, flank.tooth, flank.side, fp.normal, model_.stylus_shape(),
                        kProbeApproachMm, &r);
    }
    m.contributions = {};
    if (r.status == ContactResult::Status::kOk) {
      m.recorded_centre = r.centre;
      m.total_error_um = r.normal_error_um;
      if (with_effects) {
        m.context = point_context(fp.point, fp.normal, (r.centre - r.contact).normalized(), q.order,
                                  model_.sequence_length(), flank.tooth, flank.side, R);
        m.context.base_radius_mm = 0.5 * gear.base_diameter_mm();
        m.context.teeth = gear.teeth();
        RandomStream rng = point_effect_stream(model_.scenario().seed, k_, q.order);
        m.recorded_centre = effects.apply(m.context, effect_values_, r.centre, rng, contributions);
        for (double c : contributions) m.total_error_um += c;
        m.contributions = contributions;
      }
    }
    visit(m);
  }
}

void GearMeasurement::measure(const std::function<void(const PointMeasurement&)>& visit) const {
  for (const PlanFlank& flank : model_.flanks()) measure_flank(flank, visit);
}

double GearMeasurement::surface_deviation_um(const PlanPoint& point) const {
  for (const FlankMeshSurface& surface : model_.scenario().surfaces) {
    if (surface.tooth == point.tooth && surface.side == point.side) {
      throw std::logic_error("surface_deviation_um: a mesh flank's deviation is not known");
    }
  }
  const AnalyticFlank surface(model_.gear(), point.tooth, point.side,
                              perturbed_.flank(point.tooth, point.side), perturbed_.eccentricity_mm,
                              model_.expression());
  return 1000.0 * (surface.point(point.roll_length_mm, point.z_mm) - point.nominal.point)
                      .dot(point.nominal.normal);
}

}  // namespace gearmc
