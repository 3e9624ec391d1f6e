// `gearmc simulate`: readings of the scenario's gears with its effects (see simulate.h).
#include "engine/mc/simulate.h"

#include <map>
#include <tuple>

#include "engine/effects/measurement_effect.h"
#include "engine/io/input_error.h"
#include "engine/mc/monte_carlo.h"
#include "engine/probing/probing_grid.h"
#include "engine/scenario/scenario.h"
#include "gears/normal_expression.h"
#include "surfaces/analytic_flank.h"

namespace gearmc {
namespace {

const char* status_reason(const ContactResult& r) {
  switch (r.status) {
    case ContactResult::Status::kOk:
      return "";
    case ContactResult::Status::kEdge:
      return "edge contact";
    case ContactResult::Status::kCollision:
      return "collision";
    case ContactResult::Status::kNotConverged:
      return "contact not converged";
    case ContactResult::Status::kUncertified:
      return "contact not certified as the first contact";
  }
  return "";
}

}  // namespace

SimulatedReadings simulate_readings(const Scenario& input, const SimulateOptions& options) {
  Scenario scenario = input;
  if (options.seed) scenario.seed = *options.seed;
  if (options.master) scenario.deviations.random = false;
  if (options.reference_deviations && !scenario.surfaces.empty()) {
    throw InputError({scenario.source_path, 0, 0},
                     "--reference-deviations: the scenario replaces flanks by meshes "
                     "(`surfaces:`), whose deviations at the nominal points are not known");
  }
  const MonteCarloRun run(scenario);
  const InvoluteGear& gear = run.gear();
  const std::vector<PlannedPoint> sequence = probing_sequence(gear, scenario.probing);
  const EffectChain& effects = *scenario.effects;
  // For ref_dev_um: the same perturbed gears as the run draws (same seed, same streams).
  const ToleranceSet tolerances = resolve_scenario_tolerances(scenario, gear);
  const GearSampler sampler(gear, tolerances, scenario.deviations, scenario.seed);
  std::optional<NormalExpression> expression;
  if (!scenario.normal_expression_um.empty()) expression.emplace(scenario.normal_expression_um);

  SimulatedReadings out;
  out.readings.stylus_radius_mm = scenario.stylus_radius_mm;
  out.readings.has_ref_dev = options.reference_deviations;
  const int sequence_length = static_cast<int>(sequence.size());
  int order = 0;
  for (int k = 0; k < options.gears; ++k) {
    const GearOutcome outcome = run.measure_gear(k, true);
    std::map<std::tuple<int, int, int, int>, const ProbedPoint*> by_plan;
    for (const ProbedPoint& q : outcome.points) {
      by_plan[{q.tooth, q.side == FlankSide::kRight ? 1 : 0, q.i, q.j}] = &q;
    }
    const EffectValues values = effects.draw(scenario.seed, k);
    const PerturbedGear perturbed = sampler.draw(k);
    for (std::size_t position = 0; position < sequence.size(); ++position) {
      const PlannedPoint& planned = sequence[position];
      const int this_order = order++;
      const ProbedPoint& q = *by_plan.at(
          {planned.tooth, planned.side == FlankSide::kRight ? 1 : 0, planned.i, planned.j});
      if (q.contact.status != ContactResult::Status::kOk) {
        if (out.skipped++ == 0) {
          out.first_skip_reason =
              std::string(status_reason(q.contact)) +
              (*q.contact.failure != '\0' ? std::string(" (") + q.contact.failure + ")"
                                          : std::string()) +
              " at gear " + std::to_string(k) + ", tooth " + std::to_string(q.tooth) +
              (q.side == FlankSide::kRight ? " R" : " L") + ", point (" + std::to_string(q.i) +
              ", " + std::to_string(q.j) + ")";
        }
        continue;
      }
      PointContext context;
      context.p = q.p;
      context.n = q.n;
      context.contact_normal =
          (q.contact.centre - q.contact.contact).normalized();  // real normal at C
      context.azimuth_rad = std::atan2(-q.n.y(), -q.n.x());
      context.order = static_cast<int>(position);  // within this gear's measurement
      context.sequence_length = sequence_length;
      context.tooth = q.tooth;
      context.side = q.side;
      context.stylus_radius_mm = scenario.stylus_radius_mm;
      RandomStream rng = point_effect_stream(scenario.seed, k, context.order);
      ReadingRow row;
      row.gear = k;
      row.tooth = q.tooth;
      row.side = q.side;
      row.i = q.i;
      row.j = q.j;
      row.order = this_order;
      row.p = q.p;
      row.n = q.n;
      row.c = effects.apply(context, values, q.contact.centre, rng);
      if (options.reference_deviations) {
        const AnalyticFlank flank(gear, q.tooth, q.side, perturbed.flank(q.tooth, q.side),
                                  perturbed.eccentricity_mm, expression ? &*expression : nullptr);
        row.ref_dev_um = 1000.0 * (flank.point(planned.roll_length, planned.z) - q.p).dot(q.n);
      }
      out.readings.rows.push_back(row);
    }
  }
  return out;
}

}  // namespace gearmc
