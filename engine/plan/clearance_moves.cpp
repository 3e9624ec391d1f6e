// Clearance moves of the DMIS program (see clearance_moves.h).
#include "engine/plan/clearance_moves.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "core/input_error.h"

namespace gearmc {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kDirectStepMm = 0.05;  // sampling of a direct move between two pre-positions
constexpr double kShaftStepMm = 0.25;   // sampling along the shaft's axis

// Signed normal distance (mm, > 0 outside the material) of the point `x` from the gear, as seen
// in its transverse section (clamped to the faces): the extended involutes of both flanks of the
// tooth space the point's polar angle falls into, the root circle, and the tip circle (beyond it
// a point is at least its radial distance away). A lower bound of the true distance to the
// nominal solid (the solid lies inside the extended flanks), then the faces: above z = b (below
// 0) the point is sqrt(d² + dz²) away from the section's outline when outside it, dz when above
// the material.
double gear_distance_mm(const InvoluteGear& gear, const Eigen::Vector3d& x) {
  const double b = gear.face_width_mm();
  const double r = std::hypot(x.x(), x.y());
  const double r_a = 0.5 * gear.tip_diameter_mm(), r_f = 0.5 * gear.root_diameter_mm();
  const double zc = std::clamp(x.z(), 0.0, b);
  const double turn = zc * gear.helix_turn_per_mm();
  const double tau = gear.angular_pitch_rad();
  double theta0 = std::atan2(x.y(), x.x()) - turn;
  theta0 -= 2.0 * std::numbers::pi * std::floor(theta0 / (2.0 * std::numbers::pi));
  const int z = gear.teeth();
  const int k = std::min(z - 1, static_cast<int>(std::floor(theta0 / tau)));  // 0-based
  const int tooth_before = k + 1, tooth_after = (k + 1) % z + 1;
  const Eigen::Vector2d X(x.x(), x.y());
  const double cos_bb = std::cos(gear.base_helix_angle_rad());
  const double d_r = gear.transverse_position(tooth_before, FlankSide::kRight, X, turn).distance_mm;
  const double d_l = gear.transverse_position(tooth_after, FlankSide::kLeft, X, turn).distance_mm;
  double d = std::min(d_r, d_l) * cos_bb;
  if (gear.internal()) {
    d = std::min(d, r_f - r);
    if (r < r_a) d = std::max(d, r_a - r);
  } else {
    d = std::min(d, r - r_f);
    if (r > r_a) d = std::max(d, r - r_a);
  }
  const double dz = x.z() < 0.0 ? -x.z() : std::max(0.0, x.z() - b);
  if (dz == 0.0) return d;
  return d > 0.0 ? std::hypot(d, dz) : dz;
}

// Where the ball centre leaves the tooth space: from q along the horizontal direction `out` to
// the radius r_out (the first crossing). Falls back to the radial direction through q when `out`
// misses that circle.
Eigen::Vector3d out_of_space(const Eigen::Vector3d& q, Eigen::Vector2d out, double r_out,
                             bool internal) {
  const Eigen::Vector2d p(q.x(), q.y());
  const auto crossing = [&](const Eigen::Vector2d& u) {
    const double pu = p.dot(u), disc = pu * pu - p.squaredNorm() + r_out * r_out;
    if (disc < 0.0) return -1.0;
    return internal ? -pu - std::sqrt(disc) : -pu + std::sqrt(disc);
  };
  double t = out.norm() > 0.0 ? crossing(out.normalized()) : -1.0;
  if (!(t >= 0.0)) {
    out = (internal ? -1.0 : 1.0) * p.normalized();
    t = std::max(0.0, crossing(out));
  } else {
    out.normalize();
  }
  const Eigen::Vector2d e = p + t * out;
  return {e.x(), e.y(), q.z()};
}

}  // namespace

double clearance_above_face_mm(const PlanStylus& stylus, double clearance_mm) {
  return std::max(clearance_mm, 2.0 * stylus.ball_radius_mm + 5.0);
}

double stylus_margin_mm(const InvoluteGear& gear, const PlanStylus& stylus,
                        const Eigen::Vector3d& centre, const Eigen::Vector3d& shaft,
                        double shaft_length_mm) {
  const double r_a = 0.5 * gear.tip_diameter_mm(), b = gear.face_width_mm();
  const auto outside = [&](const Eigen::Vector3d& x, double radius) {
    const double r = std::hypot(x.x(), x.y());
    return x.z() > b + radius || x.z() < -radius ||
           (gear.internal() ? r < r_a - radius : r > r_a + radius);
  };
  double margin = outside(centre, stylus.ball_radius_mm)
                      ? kInf
                      : gear_distance_mm(gear, centre) - stylus.ball_radius_mm;
  if (stylus.shaft == PlanShaftAxis::kNone || stylus.shaft_radius_mm <= 0.0) return margin;
  const double r_s = stylus.shaft_radius_mm;
  const double start =
      std::sqrt(std::max(0.0, stylus.ball_radius_mm * stylus.ball_radius_mm - r_s * r_s));
  for (double s = start; s <= shaft_length_mm; s += kShaftStepMm) {
    const Eigen::Vector3d x = centre + s * shaft;
    if (outside(x, r_s)) {
      // Past the gear along the shaft: an axial shaft above the face, a radial one beyond the
      // tip circle stays there (both move away from the gear along the shaft).
      if (s > start) break;
      continue;
    }
    margin = std::min(margin, gear_distance_mm(gear, x) - r_s);
  }
  return margin;
}

ClearancePlan plan_clearance_moves(const InvoluteGear& gear,
                                   const std::vector<PlannedPoint>& sequence,
                                   const PlanStylus& stylus, double approach_mm,
                                   double clearance_mm) {
  ClearancePlan plan;
  if (sequence.empty()) return plan;
  const double R = stylus.ball_radius_mm, a = approach_mm, b = gear.face_width_mm();
  const double h = clearance_above_face_mm(stylus, clearance_mm);
  plan.clearance_height_mm = b + h;
  const bool internal = gear.internal(), helical = gear.helical();
  const double r_a = 0.5 * gear.tip_diameter_mm();
  const double c = std::max(a, 1.0), body = std::max(R, stylus.shaft_radius_mm);
  const double r_out = internal ? r_a - body - c : r_a + body + c;
  if (r_out <= 0.0) {
    throw InputError({}, "stylus", "ball radius " + std::to_string(R) + " mm",
                     "a stylus that fits inside the ring gear's tip circle (r_a " +
                         std::to_string(r_a) + " mm) with " + std::to_string(c) +
                         " mm to spare, to leave the tooth space towards the axis");
  }
  const std::size_t n = sequence.size();
  std::vector<Eigen::Vector3d> pre(n);
  for (std::size_t k = 0; k < n; ++k) {
    pre[k] = sequence[k].point + (R + a) * sequence[k].normal;
  }
  const auto same_trace = [&](std::size_t k, std::size_t l) {
    return sequence[k].tooth == sequence[l].tooth && sequence[k].side == sequence[l].side &&
           sequence[k].j == sequence[l].j;
  };
  // Sensors: one vertical one, or for a radial shaft one per trace (the horizontal radial
  // direction through the trace's middle pre-position, towards the axis on a ring gear).
  std::vector<int> sensor_of(n, 0);
  if (stylus.shaft == PlanShaftAxis::kRadial) {
    for (std::size_t first = 0; first < n;) {
      std::size_t last = first;
      while (last + 1 < n && same_trace(first, last + 1)) ++last;
      const Eigen::Vector3d& mid = pre[(first + last) / 2];
      Eigen::Vector3d u(mid.x(), mid.y(), 0.0);
      u = (internal ? -1.0 : 1.0) * u.normalized();
      plan.sensors.push_back({u});
      for (std::size_t k = first; k <= last; ++k) {
        sensor_of[k] = static_cast<int>(plan.sensors.size()) - 1;
      }
      first = last + 1;
    }
  } else {
    plan.sensors.push_back({Eigen::Vector3d::UnitZ()});
  }
  // The stylus length the moves need: an axial stylus reaches from the lowest pre-position to
  // 10 mm above the clearance height; a radial one from the deepest pre-position out of the
  // space plus the clearance h.
  double lowest = kInf, deepest = 0.0;
  for (const Eigen::Vector3d& q : pre) {
    lowest = std::min(lowest, q.z());
    const double r = std::hypot(q.x(), q.y());
    deepest = std::max(deepest, internal ? r - r_out : r_out - r);
  }
  plan.stylus_length_mm = stylus.shaft == PlanShaftAxis::kRadial
                              ? deepest + h
                              : plan.clearance_height_mm + 10.0 - lowest;
  const auto shaft_of = [&](std::size_t k) { return plan.sensors[sensor_of[k]].shaft_direction; };
  // Out of the space and up from q (reversed: in).
  const auto exit_path = [&](std::size_t k) {
    std::vector<Eigen::Vector3d> path;
    const Eigen::Vector3d& q = pre[k];
    if (helical) {
      const Eigen::Vector3d u = shaft_of(k);
      const Eigen::Vector2d out = stylus.shaft == PlanShaftAxis::kRadial
                                      ? Eigen::Vector2d(u.x(), u.y())
                                      : Eigen::Vector2d::Zero();
      const Eigen::Vector3d e = out_of_space(q, out, r_out, internal);
      path.push_back(e);
      path.push_back({e.x(), e.y(), plan.clearance_height_mm});
    } else {
      path.push_back({q.x(), q.y(), plan.clearance_height_mm});
    }
    return path;
  };
  const auto direct_clear = [&](std::size_t from, std::size_t to) {
    const Eigen::Vector3d d = pre[to] - pre[from];
    const int steps = std::max(1, static_cast<int>(std::ceil(d.norm() / kDirectStepMm)));
    for (int s = 0; s <= steps; ++s) {
      const Eigen::Vector3d x = pre[from] + (static_cast<double>(s) / steps) * d;
      if (stylus_margin_mm(gear, stylus, x, shaft_of(to), plan.stylus_length_mm) < 0.5 * a) {
        return false;
      }
    }
    return true;
  };
  plan.touches.resize(n);
  for (std::size_t k = 0; k < n; ++k) {
    TouchMoves& t = plan.touches[k];
    t.pre_position = pre[k];
    t.sensor = sensor_of[k];
    if (k > 0 && same_trace(k - 1, k) && direct_clear(k - 1, k)) {
      t.descent = {pre[k]};
      ++plan.direct_moves;
      continue;
    }
    if (k > 0) t.lift = exit_path(k - 1);
    t.select_sensor = k == 0 || sensor_of[k] != sensor_of[k - 1];
    std::vector<Eigen::Vector3d> in = exit_path(k);
    std::reverse(in.begin(), in.end());
    in.push_back(pre[k]);
    t.descent = std::move(in);
    ++plan.lifted_moves;
  }
  plan.final_lift = exit_path(n - 1);
  return plan;
}

}  // namespace gearmc
