// `gearmc simulate`: readings of the scenario's gears with its effects (see simulate.h).
#include "engine/run/simulate.h"

#include <algorithm>
#include <string>
#include <vector>

#include "core/input_error.h"
#include "core/input_file.h"
#include "engine/effects/measurement_effect.h"
#include "engine/measurement/gear_measurement.h"
#include "engine/scenario/scenario.h"

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

SimulatedReadings simulate_readings(const Scenario& input, const SimulateOptions& options,
                                    const std::function<void(const ReadingRow&)>& each_row) {
  Scenario scenario = input;
  if (options.master) scenario.deviations.random = false;
  if (options.reference_deviations && !scenario.surfaces.empty()) {
    throw InputError({scenario.source_path, 0, 0},
                     "--reference-deviations: the scenario replaces flanks by meshes "
                     "(`surfaces:`), whose deviations at the nominal points are not known");
  }
  const MeasurementModel model(scenario);
  const std::vector<const PlanPoint*>& sequence = model.sequence();
  const double bytes = static_cast<double>(options.gears) * static_cast<double>(sequence.size()) *
                       static_cast<double>(kMaxReadingsRowBytes);
  if (bytes > static_cast<double>(kMaxReadingsBytes)) {
    const std::uint64_t fit =
        kMaxReadingsBytes / (std::max<std::size_t>(sequence.size(), 1) * kMaxReadingsRowBytes);
    throw InputError({}, "--gears", std::to_string(options.gears),
                     "at most " + std::to_string(fit) + " gears of this plan (" +
                         std::to_string(sequence.size()) + " points each, up to " +
                         std::to_string(kMaxReadingsRowBytes) + " bytes a row): the file would " +
                         "reach " + std::to_string(static_cast<std::uint64_t>(bytes / 1048576.0)) +
                         " MiB, more than the 1024 MiB of the largest readings file diagnose "
                         "reads");
  }

  SimulatedReadings out;
  out.readings.stylus_radius_mm = scenario.stylus_radius_mm;
  out.readings.has_ref_dev = options.reference_deviations;
  int order = 0;
  std::vector<PointMeasurement> measured(sequence.size());
  for (int k = 0; k < options.gears; ++k) {
    // The gear's points as the pipeline measures them (flank by flank), then written in the
    // scenario's probing order (PlanPoint::order).
    const GearMeasurement measurement(model, k, EffectMode::kDrawn);
    measurement.measure([&](const PointMeasurement& m) {
      measured[static_cast<std::size_t>(m.plan->order)] = m;
      measured[static_cast<std::size_t>(m.plan->order)].contributions = {};
    });
    for (const PointMeasurement& m : measured) {
      const PlanPoint& q = *m.plan;
      const int this_order = order++;
      if (!m.valid()) {
        if (out.skipped++ == 0) {
          out.first_skip_reason = std::string(status_reason(m.contact)) +
                                  (m.contact.failure != ContactFailure::kNone
                                       ? " (" + std::string(spelling(m.contact.failure)) + ")"
                                       : std::string()) +
                                  " at gear " + std::to_string(k) + ", tooth " +
                                  std::to_string(q.tooth) +
                                  (q.side == FlankSide::kRight ? " R" : " L") + ", point (" +
                                  std::to_string(q.i) + ", " + std::to_string(q.j) + ")";
        }
        continue;
      }
      ReadingRow row;
      row.key() = point_key(k, q);
      row.order = this_order;
      row.p = q.nominal.point;
      row.n = q.nominal.normal;
      row.c = m.recorded_centre;
      if (options.reference_deviations) row.ref_dev_um = measurement.surface_deviation_um(q);
      ++out.rows;
      if (each_row) {
        each_row(row);
      } else {
        out.readings.rows.push_back(row);
      }
    }
  }
  return out;
}

}  // namespace gearmc
