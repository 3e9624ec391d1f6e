// The model's prediction at the measured points, residuals and the noise floor (see
// prediction.h).
#include "engine/apps/diagnose/prediction.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <map>
#include <memory>
#include <tuple>

#include "core/input_error.h"
#include "engine/apps/diagnose/linear_model.h"
#include "engine/measurement/gear_measurement.h"

namespace gearmc {
namespace {

using PlanKey = std::tuple<int, int, int, int>;  // tooth, side (0 L, 1 R), i, j

PlanKey plan_key(int tooth, FlankSide side, int i, int j) {
  return {tooth, side == FlankSide::kRight ? 1 : 0, i, j};
}

// The model's nominal point and contact at a planned point.
struct ContactPrediction {
  Eigen::Vector3d p;
  ContactResult contact;
};

// A row's nominal point must equal the model plan's to this (mm) to use the model's contact.
constexpr double kSamePointMm = 1e-4;

}  // namespace

Residuals compute_residuals(const Scenario& model, const Readings& readings,
                            const PredictionOptions& options) {
  if (readings.rows.empty()) {
    throw InputError({"<readings>", 0, 0}, "the readings have no rows: nothing to diagnose");
  }
  Scenario scenario = model;
  const bool nominal = options.artefact == ArtefactModel::kNominalMaster || readings.has_ref_dev;
  if (nominal) scenario.deviations.random = false;
  if (readings.has_ref_dev) scenario.normal_expression_um.clear();
  // The ball: the model's (check_readings has refused readings compensated with another one).
  const double R = model.stylus_radius_mm;

  Residuals out;
  out.artefact = nominal ? ArtefactModel::kNominalMaster : ArtefactModel::kModelGears;

  // Each gear's place in the measurement: first and last order of its rows.
  std::map<int, std::pair<int, int>> gear_orders;
  for (const ReadingRow& row : readings.rows) {
    auto [it, inserted] = gear_orders.try_emplace(row.gear, row.order, row.order);
    if (!inserted) {
      it->second.first = std::min(it->second.first, row.order);
      it->second.second = std::max(it->second.second, row.order);
    }
  }

  // The model's contacts, per gear (one nominal gear serves every gear of a master): the
  // measurement pipeline without effects (gear_measurement.h).
  const MeasurementModel pipeline(scenario);
  std::map<int, std::map<PlanKey, ContactPrediction>> by_plan;
  auto model_points = [&](int gear) -> const std::map<PlanKey, ContactPrediction>& {
    const int key = nominal ? 0 : gear;
    auto found = by_plan.find(key);
    if (found != by_plan.end()) return found->second;
    auto& index = by_plan[key];
    GearMeasurement(pipeline, key, EffectMode::kNone).measure([&](const PointMeasurement& m) {
      const PlanPoint& q = *m.plan;
      index[plan_key(q.tooth, q.side, q.i, q.j)] = {q.nominal.point, m.contact};
    });
    return index;
  };

  // Rows matched to the gear off the model's plan (point_matching.h: a scan, another program's
  // points): the model's contact at their own nominal points, measured per (gear, tooth, flank)
  // as the plan's flanks are (the flank's mesh when the model has one for it and probes it). One
  // flank's points at a time; what is kept is the centre and contact point (memory at 10^6).
  struct OwnContact {
    Eigen::Vector3d centre, contact;
    enum : std::uint8_t { kNone, kOk, kNoValue } state = kNone;
  };
  std::vector<OwnContact> own;
  if (readings.labels_from_matching && readings.feet.size() == readings.rows.size()) {
    own.resize(readings.rows.size());
    const InvoluteGear& gear = pipeline.gear();
    std::map<std::tuple<int, int, int>, std::vector<std::size_t>> groups;
    for (std::size_t k = 0; k < readings.rows.size(); ++k) {
      const ReadingRow& row = readings.rows[k];
      const auto& plan = model_points(row.gear);
      const auto found = plan.find(plan_key(row.tooth, row.side, row.i, row.j));
      if (found != plan.end() && (found->second.p - row.p).norm() <= kSamePointMm) continue;
      groups[{nominal ? 0 : row.gear, row.tooth, row.side == FlankSide::kRight ? 1 : 0}].push_back(
          k);
    }
    std::map<int, std::unique_ptr<GearMeasurement>> measured;
    for (const auto& [key, members] : groups) {
      const ReadingRow& first = readings.rows[members.front()];
      PlanFlank flank;
      flank.tooth = first.tooth;
      flank.side = first.side;
      for (const PlanFlank& f : pipeline.flanks()) {
        if (f.tooth == flank.tooth && f.side == flank.side) flank.mesh = f.mesh;
      }
      flank.points.reserve(members.size());
      for (const std::size_t k : members) {
        const ReadingRow& row = readings.rows[k];
        PlanPoint& q = flank.points.emplace_back();
        q.grid_position() = GridPosition{row.tooth, row.side, row.i, row.j};
        q.roll_length_mm = readings.feet[k].first;
        q.z_mm = readings.feet[k].second;
        q.nominal = gear.flank_point(row.tooth, row.side, q.roll_length_mm, q.z_mm);
        // The point was measured: its path is taken as clear (no collision check).
        q.clearance_mm = std::numeric_limits<double>::infinity();
      }
      auto& g = measured[std::get<0>(key)];
      if (!g) g = std::make_unique<GearMeasurement>(pipeline, std::get<0>(key), EffectMode::kNone);
      std::size_t next = 0;
      g->measure_flank(flank, [&](const PointMeasurement& m) {
        OwnContact& c = own[members[next++]];
        c.state = m.valid() ? OwnContact::kOk : OwnContact::kNoValue;
        c.centre = m.contact.centre;
        c.contact = m.contact.contact;
      });
    }
  }

  const EffectChain& effects = *scenario.effects;
  const EffectValues values = effects.nominal();
  out.points.reserve(readings.rows.size());
  for (const ReadingRow& row : readings.rows) {
    ResidualPoint point;
    point.key() = row.key();
    point.order = row.order;
    point.line = row.line;
    const auto [first, last] = gear_orders.at(row.gear);
    PointContext& context = point.context;
    context = point_context(row.p, row.n, row.n, row.order - first, last - first + 1, row.tooth,
                            row.side, R);
    context.base_radius_mm = 0.5 * pipeline.gear().base_diameter_mm();
    context.teeth = pipeline.gear().teeth();

    Eigen::Vector3d centre = row.p + R * row.n;  // nominal contact
    const OwnContact* mine =
        own.empty() ? nullptr : &own[static_cast<std::size_t>(&row - readings.rows.data())];
    const ContactResult* planned = nullptr;
    if (!mine || mine->state == OwnContact::kNone) {
      mine = nullptr;
      const auto& plan = model_points(row.gear);
      const auto found = plan.find(plan_key(row.tooth, row.side, row.i, row.j));
      if (found != plan.end() && (found->second.p - row.p).norm() <= kSamePointMm) {
        planned = &found->second.contact;
      }
    }
    if (mine && mine->state == OwnContact::kOk) {
      centre = mine->centre;
      context.contact_normal = (mine->centre - mine->contact).normalized();
    } else if (planned && planned->status == ContactResult::Status::kOk) {
      centre = planned->centre;
      context.contact_normal = (planned->centre - planned->contact).normalized();
    } else {
      point.model_contact = false;
      ++out.nominal_fallback;
    }
    const Eigen::Vector3d recorded = effects.apply_mean(context, values, centre);
    point.predicted_um = reading_um(context, recorded);
    point.measured_um = measured_deviation_um(row, R);
    point.residual_um = point.measured_um - point.predicted_um;
    out.points.push_back(point);
  }
  return out;
}

ProfileScans profile_scans(const std::vector<ResidualPoint>& points) {
  const auto key = [&](int k) {
    const ResidualPoint& p = points[static_cast<std::size_t>(k)];
    return std::make_tuple(p.gear, p.tooth, p.side == FlankSide::kRight ? 1 : 0, p.j, p.i);
  };
  std::vector<int> order(points.size());
  for (std::size_t k = 0; k < order.size(); ++k) order[k] = static_cast<int>(k);
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return key(a) < key(b); });
  ProfileScans out;
  out.points.reserve(order.size());
  for (std::size_t at = 0; at < order.size(); ++at) {
    // Of equal keys (stable: in file order) the last one stands for the position.
    if (at + 1 < order.size() && key(order[at]) == key(order[at + 1])) continue;
    const ResidualPoint& p = points[static_cast<std::size_t>(order[at])];
    const bool new_scan = out.points.empty() || [&] {
      const ResidualPoint& q = points[static_cast<std::size_t>(out.points.back())];
      return q.gear != p.gear || q.tooth != p.tooth || q.side != p.side || q.j != p.j;
    }();
    if (new_scan) out.start.push_back(out.points.size());
    out.points.push_back(order[at]);
  }
  out.start.push_back(out.points.size());
  if (out.points.empty()) out.start.clear();
  return out;
}

std::vector<std::array<int, 3>> scan_triplets(const std::vector<ResidualPoint>& points) {
  const ProfileScans scans = profile_scans(points);
  std::vector<std::array<int, 3>> out;
  const auto i_of = [&](int k) { return points[static_cast<std::size_t>(k)].i; };
  for (std::size_t s = 0; s < scans.count(); ++s) {
    for (std::size_t at = scans.start[s]; at + 2 < scans.start[s + 1]; ++at) {
      const int a = scans.points[at], b = scans.points[at + 1], c = scans.points[at + 2];
      if (i_of(b) == i_of(a) + 1 && i_of(c) == i_of(b) + 1) out.push_back({a, b, c});
    }
  }
  return out;
}

double robust_noise_sigma(const std::vector<std::array<int, 3>>& triplets,
                          const std::vector<double>& residual_um) {
  std::vector<double> d;
  d.reserve(triplets.size());
  for (const auto& t : triplets) {
    d.push_back(residual_um[t[0]] - 2.0 * residual_um[t[1]] + residual_um[t[2]]);
  }
  if (d.empty()) return std::numeric_limits<double>::quiet_NaN();
  return mad_sigma(std::move(d)) / std::sqrt(6.0);
}

double robust_noise_sigma(const std::vector<ResidualPoint>& points,
                          const std::vector<double>& residual_um, int* count) {
  const std::vector<std::array<int, 3>> triplets = scan_triplets(points);
  if (count) *count = static_cast<int>(triplets.size());
  return robust_noise_sigma(triplets, residual_um);
}

std::string_view spelling(NoiseFloorSource source) {
  switch (source) {
    case NoiseFloorSource::kModel:
      return "model";
    case NoiseFloorSource::kResidualSecondDifferences:
      return "residual_second_differences";
    case NoiseFloorSource::kResidualMad:
      return "residual_mad";
    case NoiseFloorSource::kNumericalFloor:
      return "numerical_floor";
    case NoiseFloorSource::kGiven:
      return "given";
  }
  return "?";
}

NoiseFloor estimate_noise_floor(const Scenario& model, const Residuals& residuals) {
  NoiseFloor floor;
  const PointLaw model_law = model.effects->point_law(model.effects->nominal());
  const double variance = model_law.variance_um2();
  floor.model_um = std::sqrt(variance);
  std::vector<double> r;
  r.reserve(residuals.points.size());
  for (const ResidualPoint& p : residuals.points) r.push_back(p.residual_um);
  floor.robust_um = robust_noise_sigma(residuals.points, r, &floor.differences);
  floor.numerical_um = kNumericalFloorUm;
  const int n = static_cast<int>(r.size());
  if (floor.model_um > 0.0) {
    floor.sigma_um = floor.model_um;
    floor.source = NoiseFloorSource::kModel;
    floor.law = model_law;
  } else if (floor.differences >= kMinFloorSamples) {
    floor.sigma_um = floor.robust_um;
    floor.source = NoiseFloorSource::kResidualSecondDifferences;
  } else if (n >= kMinFloorSamples) {
    // Without enough scans of 3 points: the MAD of the residuals themselves (an upper bound).
    floor.sigma_um = mad_sigma(r);
    floor.source = NoiseFloorSource::kResidualMad;
  } else {
    floor.sigma_um = 0.0;
    floor.source = NoiseFloorSource::kNumericalFloor;
    floor.not_enough = "not enough readings: " + std::to_string(n) + ", need ≥ " +
                       std::to_string(kMinFloorSamples) +
                       " (or as many second differences along profile scans) to estimate the "
                       "noise floor of a model without a random part";
  }
  if (!(floor.sigma_um >= floor.numerical_um)) {
    floor.sigma_um = floor.numerical_um;
    floor.at_numerical_floor = true;
  }
  if (floor.source != NoiseFloorSource::kModel)
    floor.law = PointLaw{floor.sigma_um * floor.sigma_um, {}};
  return floor;
}

}  // namespace gearmc
