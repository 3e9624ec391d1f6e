// Measured points matched to the model's gear by projection onto its flanks (point_matching.h).
#include "engine/readings/point_matching.h"

#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <numbers>
#include <sstream>
#include <string>
#include <tuple>

#include "core/input_error.h"
#include "core/number_text.h"

namespace gearmc {
namespace {

constexpr double kFootTolerance = 1e-10;  // mm: the Gauss–Newton step where it stops
constexpr double kEdgeTolerance = 1e-6;   // mm: a foot this far past the flank's edge is on it
constexpr double kMaxHintAngleDeg = 5.0;  // a normal hint further off refuses the point
constexpr double kSameSectionMm = 1e-3;   // heights closer than this: one section
constexpr std::size_t kNamedRefusals = 10;
// Points of a refused table sampled to say what it fits (describe_misfit).
constexpr std::size_t kMisfitSample = 200;
constexpr double kPlanPointToleranceMm = 1e-3;   // a program's nominal point off the flank
constexpr double kPlanVectorToleranceDeg = 1.0;  // its vector off the flank's normal

Eigen::Vector2d in_base_section(const InvoluteGear& gear, const Eigen::Vector3d& M) {
  if (!gear.helical()) return M.head<2>();
  const double turn = -M.z() * gear.helix_turn_per_mm();
  const double c = std::cos(turn), s = std::sin(turn);
  return {c * M.x() - s * M.y(), s * M.x() + c * M.y()};
}

// The flank point nearest to M, from (L, z): Gauss–Newton on |M - P(L, z)|^2 with the
// tangents by central differences (the flank is smooth; the residual at the foot is normal to
// both tangents).
void refine_foot(const InvoluteGear& gear, const Eigen::Vector3d& M, FlankMatch* m) {
  double L = m->roll_length_mm, z = m->z_mm;
  constexpr double h = 1e-5;  // mm
  for (int it = 0; it < 40; ++it) {
    const Eigen::Vector3d P = gear.flank_point(m->tooth, m->side, L, z).point;
    Eigen::Matrix<double, 3, 2> J;
    J.col(0) = (gear.flank_point(m->tooth, m->side, L + h, z).point -
                gear.flank_point(m->tooth, m->side, L - h, z).point) /
               (2 * h);
    J.col(1) = (gear.flank_point(m->tooth, m->side, L, z + h).point -
                gear.flank_point(m->tooth, m->side, L, z - h).point) /
               (2 * h);
    const Eigen::Vector2d step = (J.transpose() * J).lu().solve(J.transpose() * (M - P));
    L += step.x();
    z += step.y();
    if (L < 1e-6) L = 1e-6;  // roll lengths are positive
    if (step.norm() < kFootTolerance) break;
  }
  m->roll_length_mm = L;
  m->z_mm = z;
}

}  // namespace

FlankMatch match_to_flank(const InvoluteGear& gear, const Eigen::Vector3d& M,
                          std::optional<int> tooth_hint, std::optional<FlankSide> side_hint) {
  FlankMatch best;
  const Eigen::Vector2d X = in_base_section(gear, M);
  if (X.norm() <= 0.5 * gear.base_diameter_mm()) return best;  // no involute through it
  const int z = gear.teeth();
  const double pitch = 2.0 * std::numbers::pi / z;
  const long nearest = std::lround(std::atan2(X.y(), X.x()) / pitch);
  std::vector<int> teeth;
  if (tooth_hint) {
    teeth.push_back(*tooth_hint);
  } else {
    for (long k = nearest - 1; k <= nearest + 1; ++k) {
      teeth.push_back(static_cast<int>(((k % z) + z) % z) + 1);
    }
  }
  double best_distance = std::numeric_limits<double>::infinity();
  for (const int tooth : teeth) {
    for (const FlankSide side : {FlankSide::kLeft, FlankSide::kRight}) {
      if (side_hint && side != *side_hint) continue;
      const TransversePosition at = gear.transverse_position(tooth, side, X);
      if (std::abs(at.distance_mm) < best_distance) {
        best_distance = std::abs(at.distance_mm);
        best.tooth = tooth;
        best.side = side;
        best.roll_length_mm = at.foot_roll_length_mm;
        best.found = true;
      }
    }
  }
  best.z_mm = M.z();
  if (gear.helical()) refine_foot(gear, M, &best);
  best.foot = gear.flank_point(best.tooth, best.side, best.roll_length_mm, best.z_mm);
  best.signed_distance_mm = (M - best.foot.point).dot(best.foot.normal);
  return best;
}

std::vector<std::pair<int, int>> section_labels(
    const std::vector<FlankOfPoint>& flank_of, const std::vector<std::pair<double, double>>& feet) {
  std::map<std::tuple<int, int, int>, std::vector<std::size_t>> flanks;
  for (std::size_t k = 0; k < flank_of.size(); ++k) {
    const FlankOfPoint& f = flank_of[k];
    flanks[{f.gear, f.tooth, f.side == FlankSide::kRight ? 1 : 0}].push_back(k);
  }
  std::vector<std::pair<int, int>> out(flank_of.size());
  for (auto& [key, members] : flanks) {
    std::sort(members.begin(), members.end(),
              [&](std::size_t a, std::size_t c) { return feet[a].second < feet[c].second; });
    int j = 0;
    for (std::size_t start = 0; start < members.size(); ++j) {
      std::size_t end = start + 1;
      while (end < members.size() &&
             feet[members[end]].second - feet[members[start]].second <= kSameSectionMm) {
        ++end;
      }
      std::sort(members.begin() + static_cast<long>(start),
                members.begin() + static_cast<long>(end),
                [&](std::size_t a, std::size_t c) { return feet[a].first < feet[c].first; });
      for (std::size_t k = start; k < end; ++k) {
        out[members[k]] = {static_cast<int>(k - start), j};
      }
      start = end;
    }
  }
  return out;
}

std::vector<ExplicitPlanPoint> plan_from_dmis(const InvoluteGear& gear,
                                              const std::vector<DmisPlanFeature>& features,
                                              const std::string& source) {
  const double L_min = gear.active_roll_length_min_mm(), L_max = gear.active_roll_length_max_mm();
  std::vector<ExplicitPlanPoint> plan;
  std::vector<FlankOfPoint> flank_of;
  std::vector<std::pair<double, double>> feet;
  for (const DmisPlanFeature& f : features) {
    const FlankMatch m = match_to_flank(gear, f.point);
    const InputLocation at{source, f.line, f.values_column};
    const std::string value = short_text(f.point.x(), 10) + "," + short_text(f.point.y(), 10) +
                              "," + short_text(f.point.z(), 10);
    const std::string flank = m.found ? " (nearest: tooth " + std::to_string(m.tooth) +
                                            (m.side == FlankSide::kRight ? " R" : " L") + ")"
                                      : "";
    if (!m.found || !(std::abs(m.signed_distance_mm) <= kPlanPointToleranceMm)) {
      throw InputError(
          at, "FEAT/POINT of " + f.label, value,
          "a point on a flank of the scenario's gear (within " +
              short_text(1e3 * kPlanPointToleranceMm) + " µm; this one " +
              (m.found ? short_text(1e3 * std::abs(m.signed_distance_mm)) + " µm off" + flank
                       : std::string("inside the base circle")) +
              "): is the program for this gear?");
    }
    if (!(m.roll_length_mm >= L_min - kEdgeTolerance &&
          m.roll_length_mm <= L_max + kEdgeTolerance && m.z_mm >= -kEdgeTolerance &&
          m.z_mm <= gear.face_width_mm() + kEdgeTolerance)) {
      throw InputError(at, "FEAT/POINT of " + f.label, value,
                       "a point on the active flank (roll length " + short_text(L_min) + " … " +
                           short_text(L_max) + " mm, z 0 … " + short_text(gear.face_width_mm()) +
                           " mm; this one at roll length " + short_text(m.roll_length_mm) +
                           " mm, z " + short_text(m.z_mm) + " mm" + flank + ")");
    }
    const double angle_deg =
        std::acos(std::clamp(f.vector.dot(m.foot.normal), -1.0, 1.0)) * 180.0 / std::numbers::pi;
    if (!(angle_deg <= kPlanVectorToleranceDeg)) {
      throw InputError(at, "FEAT/POINT of " + f.label, value,
                       "the flank's outward normal as its vector i,j,k (gearmc probes along the "
                       "normal; within " +
                           short_text(kPlanVectorToleranceDeg) + "°, this one " +
                           short_text(angle_deg) + "° off" + flank + ")");
    }
    ExplicitPlanPoint& e = plan.emplace_back();
    e.tooth = m.tooth;
    e.side = m.side;
    e.roll_length_mm = m.roll_length_mm;
    e.z_mm = m.z_mm;
    flank_of.push_back({0, m.tooth, m.side});
    feet.emplace_back(m.roll_length_mm, m.z_mm);
  }
  const std::vector<std::pair<int, int>> labels = section_labels(flank_of, feet);
  for (std::size_t k = 0; k < plan.size(); ++k) {
    plan[k].i = labels[k].first;
    plan[k].j = labels[k].second;
  }
  return plan;
}

namespace {

// Whether M (mm) fits a flank of `gear` (its foot on the active flank, its distance within the
// allowance; a stylus centre R further out).
bool fits_a_flank(const InvoluteGear& gear, const Eigen::Vector3d& M, double offset_mm,
                  double allowance_mm) {
  const FlankMatch m = match_to_flank(gear, M);
  const double L_lo = std::min(gear.active_roll_length_min_mm(), gear.active_roll_length_max_mm());
  const double L_hi = std::max(gear.active_roll_length_min_mm(), gear.active_roll_length_max_mm());
  return m.found && m.roll_length_mm >= L_lo - kEdgeTolerance &&
         m.roll_length_mm <= L_hi + kEdgeTolerance && m.z_mm >= -kEdgeTolerance &&
         m.z_mm <= gear.face_width_mm() + kEdgeTolerance &&
         std::abs(m.signed_distance_mm - offset_mm) <= allowance_mm;
}

Eigen::Vector3d turned(const Eigen::Vector3d& p, double angle) {
  const double c = std::cos(angle), s = std::sin(angle);
  return {c * p.x() - s * p.y(), s * p.x() + c * p.y(), p.z()};
}

}  // namespace

std::string describe_misfit(const InvoluteGear& gear, const UnlabelledPoints& table,
                            double allowance_mm) {
  if (table.points.empty()) return "";
  const double offset = table.kind == MeasuredPointKind::kStylusCentre ? table.stylus_radius_mm : 0;
  // A sample spread over the file (the whole file when small).
  std::vector<Eigen::Vector3d> sample;
  const std::size_t n = table.points.size(), take = std::min<std::size_t>(n, kMisfitSample);
  for (std::size_t k = 0; k < take; ++k) sample.push_back(table.points[k * n / take].measured);
  std::vector<double> radii;
  double z_lo = std::numeric_limits<double>::infinity(), z_hi = -z_lo;
  for (const Eigen::Vector3d& p : sample) {
    radii.push_back(std::hypot(p.x(), p.y()));
    z_lo = std::min(z_lo, p.z());
    z_hi = std::max(z_hi, p.z());
  }
  std::sort(radii.begin(), radii.end());
  const double r_median = radii[radii.size() / 2];
  const double r_form = 0.5 * gear.diameter_at_roll_length(gear.active_roll_length_min_mm());
  const double r_tip = 0.5 * gear.diameter_at_roll_length(gear.active_roll_length_max_mm());
  const double r_lo = std::min(r_form, r_tip) - offset, r_hi = std::max(r_form, r_tip) + offset;
  const double b = gear.face_width_mm();
  std::ostringstream out;
  out << "the points lie " << short_text(radii.front()) << " … " << short_text(radii.back())
      << " mm from the z axis at z " << short_text(z_lo) << " … " << short_text(z_hi)
      << " mm; this gear's flanks run " << short_text(std::min(r_form, r_tip)) << " … "
      << short_text(std::max(r_form, r_tip)) << " mm from it, z 0 … " << short_text(b) << " mm";
  // A unit: a scale that puts the median radius on the flanks.
  struct Scale {
    double factor;
    const char* what;
  };
  for (const Scale s :
       {Scale{25.4, "inch read as mm (`unit: inch`)"},
        Scale{1.0 / 25.4, "mm read as inch (`unit: mm`)"},
        Scale{1e-3, "µm read as mm (`unit: um`)"}, Scale{1e3, "mm read as µm (`unit: mm`)"}}) {
    if (r_median * s.factor >= r_lo && r_median * s.factor <= r_hi) {
      out << ". Scaled by " << short_text(s.factor)
          << " they would lie at the flanks' radii: " << s.what << "? Check the mapping's `unit:`";
      return out.str();
    }
  }
  if (!(r_median >= r_lo - 2 * gear.module_mm() && r_median <= r_hi + 2 * gear.module_mm())) {
    out << ": another gear, or another centre (the gear's axis must be the z axis)";
    return out.str();
  }
  // The face: a z datum elsewhere than the lower face (e.g. the upper one, or mid face).
  double shift = 0.0;
  if (z_lo < -kEdgeTolerance || z_hi > b + kEdgeTolerance) {
    if (z_hi - z_lo <= b + kEdgeTolerance) shift = z_lo < 0 ? -z_lo : b - z_hi;
  }
  // The gear turned about its axis: the rotation (within one pitch) that fits most sampled
  // points, coarse (ten times the allowance) then fine.
  const double r_max = std::max(r_hi, 1.0);
  const double pitch = 2.0 * std::numbers::pi / gear.teeth();
  const auto count_at = [&](double angle, double allowance) {
    int fits = 0;
    for (const Eigen::Vector3d& p : sample) {
      fits +=
          fits_a_flank(gear, turned(p + Eigen::Vector3d(0, 0, shift), angle), offset, allowance);
    }
    return fits;
  };
  // The run of angles (step `step` over [from, to]) where most points fit, as (count, lo, hi):
  // the first run of the largest count.
  struct Run {
    int count = -1;
    double lo = 0.0, hi = 0.0;
  };
  const auto best_run = [&](double from, double to, double step, double allowance) {
    Run run;
    bool extending = false;
    for (double a = from; a <= to; a += step) {
      const int c = count_at(a, allowance);
      if (c > run.count) {
        run = {c, a, a};
        extending = true;
      } else if (c == run.count && extending) {
        run.hi = a;
      } else {
        extending = false;
      }
    }
    return run;
  };
  const double coarse = 10.0 * allowance_mm / r_max, fine = allowance_mm / (2.0 * r_max);
  const Run wide = best_run(-0.5 * pitch, 0.5 * pitch, coarse, 10.0 * allowance_mm);
  const Run narrow = best_run(wide.lo - coarse, wide.hi + coarse, fine, allowance_mm);
  const int best_fine = narrow.count;
  const double angle = 0.5 * (narrow.lo + narrow.hi);
  const bool turned_fits = 10 * best_fine >= 9 * static_cast<int>(sample.size());
  const bool shift_matters = shift != 0.0;
  if (turned_fits && (std::abs(angle) > fine || shift_matters)) {
    out << ". ";
    if (shift_matters) {
      out << "Shifted by " << short_text(shift) << " mm in z (at least: into the face)";
      if (std::abs(angle) > fine) out << " and turned";
    } else {
      out << "Turned";
    }
    if (std::abs(angle) > fine) {
      out << " by " << short_text(angle * 180.0 / std::numbers::pi, 4)
          << "° about the z axis (counter-clockwise seen from +z)";
    }
    out << ", " << best_fine << " of " << sample.size()
        << " sampled points fit its flanks: the part was set up ";
    if (shift_matters) out << "with another z datum";
    if (shift_matters && std::abs(angle) > fine) out << " and ";
    if (std::abs(angle) > fine) {
      out << "turned by " << short_text(-angle * 180.0 / std::numbers::pi, 4)
          << "° against the model (tooth 1's flanks not where the model has them)";
    }
    out << "; align the set-up to the model's datums (docs/formats.md) or transform the "
           "coordinates";
    return out.str();
  }
  out << ": no unit, z datum or turn about the axis makes them fit; another gear?";
  return out.str();
}

Readings match_unlabelled_points(const InvoluteGear& gear, const UnlabelledPoints& table,
                                 double allowance_mm, MatchingSummary* summary) {
  const double R = table.stylus_radius_mm;
  const bool centres = table.kind == MeasuredPointKind::kStylusCentre;
  const double L_min = gear.active_roll_length_min_mm(), L_max = gear.active_roll_length_max_mm();
  const double b = gear.face_width_mm();
  Readings out;
  out.stylus_radius_mm = R;
  out.labels_from_matching = true;
  out.warnings = table.warnings;
  MatchingSummary s;
  s.points = table.points.size();
  double sum_sq = 0.0;
  std::vector<std::string> refusals;
  const UnlabelledPoint* first_refused = nullptr;
  std::string first_reason;
  for (const UnlabelledPoint& q : table.points) {
    // A nominal point names the flank (the measured one may lie far from it); explicit tooth and
    // flank hints come first.
    std::optional<int> tooth = q.tooth_hint;
    std::optional<FlankSide> side = q.side_hint;
    if (q.nominal_hint) {
      const FlankMatch planned = match_to_flank(gear, *q.nominal_hint, tooth, side);
      if (planned.found) {
        tooth = planned.tooth;
        side = planned.side;
      }
    }
    const FlankMatch m = match_to_flank(gear, q.measured, tooth, side);
    const double deviation_mm = m.signed_distance_mm - (centres ? R : 0.0);
    std::string reason;
    if (!m.found) {
      reason = "inside the base circle (no involute flank through it)";
    } else if (!(m.roll_length_mm >= L_min - kEdgeTolerance &&
                 m.roll_length_mm <= L_max + kEdgeTolerance && m.z_mm >= -kEdgeTolerance &&
                 m.z_mm <= b + kEdgeTolerance)) {
      std::ostringstream why;
      why << "its foot on tooth " << m.tooth << (m.side == FlankSide::kRight ? " R" : " L")
          << " (roll length " << short_text(m.roll_length_mm) << " mm, z " << short_text(m.z_mm)
          << " mm) is off the active flank (L " << short_text(L_min) << " … " << short_text(L_max)
          << " mm, z 0 … " << short_text(b) << " mm)";
      reason = why.str();
    } else if (!(std::abs(deviation_mm) <= allowance_mm)) {
      reason = "it lies " + short_text(1e3 * deviation_mm) + " µm from the nearest flank (tooth " +
               std::to_string(m.tooth) + (m.side == FlankSide::kRight ? " R" : " L") +
               "), beyond the " + short_text(1e3 * allowance_mm) +
               " µm the model's tolerances allow";
    } else if (q.normal_hint && q.normal_hint->dot(m.foot.normal) <
                                    std::cos(kMaxHintAngleDeg * std::numbers::pi / 180.0)) {
      reason = "its normal (i, j, k) is " +
               short_text(std::acos(std::clamp(q.normal_hint->dot(m.foot.normal), -1.0, 1.0)) *
                          180.0 / std::numbers::pi) +
               "° off the matched flank's (tooth " + std::to_string(m.tooth) +
               (m.side == FlankSide::kRight ? " R" : " L") + ")";
    }
    if (!reason.empty()) {
      ++s.refused;
      if (!first_refused) {
        first_refused = &q;
        first_reason = reason;
      }
      if (refusals.size() < kNamedRefusals) {
        refusals.push_back(table.source + ":" + std::to_string(q.line) + ": " + reason);
      }
      continue;
    }
    ReadingRow r;
    r.gear = q.gear;
    r.tooth = m.tooth;
    r.side = m.side;
    r.order = q.order;
    r.p = m.foot.point;
    r.n = m.foot.normal;
    r.c = centres ? q.measured : Eigen::Vector3d(q.measured + R * r.n);
    r.line = r.nominal_line = q.line;
    r.key_column = r.measured_column = r.nominal_column = q.column;
    out.rows.push_back(r);
    out.feet.push_back({m.roll_length_mm, m.z_mm});
    s.max_distance_um = std::max(s.max_distance_um, std::abs(1e3 * deviation_mm));
    sum_sq += 1e6 * deviation_mm * deviation_mm;
  }
  const std::size_t matched = out.rows.size();
  if (first_refused && (matched == 0 || 10 * s.refused > s.points)) {
    throw InputError(
        {table.source, first_refused->line, first_refused->column}, "x,y,z",
        short_text(first_refused->measured.x()) + "," + short_text(first_refused->measured.y()) +
            "," + short_text(first_refused->measured.z()),
        "points of the model's gear (" + std::to_string(gear.teeth()) + " teeth, m " +
            short_text(gear.module_mm()) + " mm): " + std::to_string(s.refused) + " of " +
            std::to_string(s.points) + " points fit none of its flanks; this one: " + first_reason +
            "; " + describe_misfit(gear, table, allowance_mm));
  }
  if (s.refused > 0) {
    std::string w = std::to_string(s.refused) + " of " + std::to_string(s.points) +
                    " measured points were not matched to a flank and are left out: ";
    for (std::size_t k = 0; k < refusals.size(); ++k) w += (k ? "; " : "") + refusals[k];
    if (s.refused > refusals.size()) w += "; …";
    out.warnings.push_back(w);
  }
  s.rms_distance_um = matched ? std::sqrt(sum_sq / static_cast<double>(matched)) : 0.0;

  // Grid labels: sections by height, points in a section by roll length.
  std::vector<FlankOfPoint> flank_of;
  flank_of.reserve(matched);
  for (const ReadingRow& r : out.rows) flank_of.push_back({r.gear, r.tooth, r.side});
  const std::vector<std::pair<int, int>> labels = section_labels(flank_of, out.feet);
  for (std::size_t k = 0; k < matched; ++k) {
    out.rows[k].i = labels[k].first;
    out.rows[k].j = labels[k].second;
  }
  if (summary) *summary = s;
  return out;
}

}  // namespace gearmc
