// Rows of a readings file the diagnosis refuses (see readings_check.h).
#include "engine/apps/diagnose/readings_check.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <map>
#include <numbers>
#include <optional>
#include <sstream>
#include <vector>

#include "core/input_error.h"
#include "core/input_file.h"
#include "core/number_text.h"
#include "core/text_lines.h"

namespace gearmc {
namespace {

// CSV columns of a readings row (readings_csv.h).
enum Field { kGear = 0, kTooth = 1, kI = 3, kJ = 4, kPx = 6, kCx = 12 };
const char* const kFieldNames[] = {"gear", "tooth", "flank", "i",  "j",  "order", "px", "py",
                                   "pz",   "nx",    "ny",    "nz", "cx", "cy",    "cz"};

// File, line and column of field `field` of row `k`, from the places the reader kept: the
// nominal point's fields (px…nz) where the nominal is, the stylus centre where the measured value
// is, the key fields where the point's identity is (for gearmc's CSV, the field's own column).
InputLocation locate(const Readings& readings, const std::string& path, std::size_t k, int field) {
  const ReadingRow& row = readings.rows[k];
  // Several files read together: the row's own.
  const std::string& own = readings.sources.empty() ? path : readings.sources.at(row.source);
  const std::string file = own.empty() ? "<readings>" : own;
  if (row.line == 0) return {file + " row " + std::to_string(k + 1), 0, 0};
  if (field >= kPx && field < kCx) return {file, row.nominal_line, row.nominal_column};
  if (field >= kCx) return {file, row.line, row.measured_column};
  if (!readings.is_readings_csv) return {file, row.line, row.key_column};
  // gearmc's CSV: the field's column on the row's line (fields are comma-separated, in order).
  std::string text;
  try {
    text = read_input_file(own, "readings file", kMaxReadingsBytes);
  } catch (const InputError&) {
    return {file, row.line, row.key_column};
  }
  TextLines lines(text, own, kMaxReadingsLineBytes, "a readings CSV");
  TextLine at;
  while (at.number < row.line && lines.next(&at)) {
  }
  if (at.number != row.line) return {file, row.line, row.key_column};
  const std::string& line = at.text;
  std::size_t start = 0;
  for (int f = 0; f < field && start != std::string::npos; ++f) {
    start = line.find(',', start);
    if (start != std::string::npos) ++start;
  }
  return {file, row.line,
          start == std::string::npos ? row.key_column : static_cast<int>(start) + 1};
}

// A number from the file echoed as it reads back (shortest round trip: 3.9, not
// 3.8999999999999999).
std::string number_text(double v) { return shortest_text(v); }

// File, line and column of the header's stylus radius value, by reading the file again.
InputLocation locate_radius(const std::string& path) {
  InputLocation where{path.empty() ? "<readings>" : path, 0, 0};
  std::ifstream in(path, std::ios::binary);
  std::string line;
  for (int line_no = 1; in && std::getline(in, line); ++line_no) {
    const auto at = line.find("stylus_radius_mm=");
    if (!line.empty() && line[0] == '#' && at != std::string::npos) {
      where.line = line_no;
      where.column = static_cast<int>(at + std::string("stylus_radius_mm=").size()) + 1;
      break;
    }
  }
  return where;
}

// What gear the readings' nominal points and normals describe, for the message when they are off
// the model's flanks. An involute point P with outward normal n lies on the line of action, the
// tangent to the base circle at Q = P − (P·n̂) n̂ (n̂: n's unit XY part), so r_b = |P × n̂| and the
// roll length L = P·n̂; the flank's base-circle start angle ψ0 = ∠Q + L/r_b on R flanks and
// ∠Q − L/r_b on L flanks (gears/involute_gear.h, flank_point) is the same for every point of a
// flank and advances by 2π/z from tooth to tooth, which gives z from the tooth numbers; m = d_b /
// (z cos α) with the model's pressure angle α.
std::string describe_gear_of_points(const std::vector<ReadingRow>& rows, double pressure_angle) {
  std::vector<double> base_radii;
  std::map<std::pair<int, int>, std::vector<double>> start_angles;  // (side, tooth) -> ψ0
  for (const ReadingRow& row : rows) {
    const Eigen::Vector2d p(row.p.x(), row.p.y());
    Eigen::Vector2d n(row.n.x(), row.n.y());
    if (!(n.norm() > 1e-6)) continue;
    n.normalize();
    const double rb = std::abs(p.x() * n.y() - p.y() * n.x());
    const double L = p.dot(n);
    if (!(rb > 0.0) || !std::isfinite(rb)) continue;
    base_radii.push_back(rb);
    const Eigen::Vector2d q = p - L * n;
    const int side = row.side == FlankSide::kRight ? 1 : 0;
    start_angles[{side, row.tooth}].push_back(std::atan2(q.y(), q.x()) +
                                              (side == 1 ? 1.0 : -1.0) * L / rb);
  }
  if (base_radii.empty()) return "";
  std::nth_element(base_radii.begin(), base_radii.begin() + base_radii.size() / 2,
                   base_radii.end());
  const double rb = base_radii[base_radii.size() / 2];
  std::ostringstream text;
  text.precision(4);
  text << "the points fit a gear of base diameter " << 2.0 * rb << " mm";
  // z from consecutive measured teeth on the same side: Δψ0 = (t2 − t1)·2π/z.
  std::vector<double> z_estimates;
  const auto mean_angle = [](const std::vector<double>& a) {
    double c = 0.0, s = 0.0;
    for (double v : a) c += std::cos(v), s += std::sin(v);
    return std::atan2(s, c);
  };
  for (int side = 0; side < 2; ++side) {
    const std::pair<int, int>* previous = nullptr;
    double previous_angle = 0.0;
    for (const auto& [key, angles] : start_angles) {
      if (key.first != side) continue;
      const double angle = mean_angle(angles);
      if (previous) {
        double delta = std::fmod(angle - previous_angle, 2.0 * std::numbers::pi);
        if (delta <= 0.0) delta += 2.0 * std::numbers::pi;
        z_estimates.push_back(2.0 * std::numbers::pi * (key.second - previous->second) / delta);
      }
      previous = &key;
      previous_angle = angle;
    }
  }
  if (!z_estimates.empty()) {
    std::nth_element(z_estimates.begin(), z_estimates.begin() + z_estimates.size() / 2,
                     z_estimates.end());
    const long z = std::lround(z_estimates[z_estimates.size() / 2]);
    if (z >= 3) {
      text << ", z " << z << ", m "
           << 2.0 * rb / (static_cast<double>(z) * std::cos(pressure_angle)) << " mm (at the "
           << "model's pressure angle " << pressure_angle * 180.0 / std::numbers::pi << "°)";
    }
  }
  return text.str();
}

// How far (mm) a reading's nominal point may lie from the model's nominal flank: what the model's
// tolerances let the real flank deviate (runout, profile and helix total, thickness allowance
// and tolerance, when the tolerance set has them), at least 10 µm (nominal points written with
// 4 decimals, rounding).
}  // namespace

double nominal_point_allowance_mm(const Scenario& model, const InvoluteGear& gear) {
  double sum_um = 0.0;
  try {
    const ToleranceSet set = resolve_scenario_tolerances(model, gear);
    for (ToleranceKind kind :
         {ToleranceKind::kRunout, ToleranceKind::kProfileTotal, ToleranceKind::kHelixTotal,
          ToleranceKind::kThicknessUpper, ToleranceKind::kThicknessTolerance}) {
      if (const std::optional<double> v = set.get_um(kind)) sum_um += std::abs(*v);
    }
  } catch (const std::exception&) {  // unresolvable tolerances are refused elsewhere
  }
  return std::max(sum_um, 10.0) * 1e-3;
}

namespace {

// A label column whose values leave its range but would all fit once shifted by one constant
// (1-based grid indices, 0-based teeth, an export that counts from another start): one message
// for the whole file, at its first row out of range, with the shift that fixes it — instead of
// refusing the file row by row.
void refuse_shifted_labels(const Readings& readings, const std::string& path, int teeth, int n,
                           int m, const std::string& grid) {
  struct Label {
    int field;
    const char* name;
    int lo, hi;
    int ReadingRow::*value;
    std::string range;
  };
  const Label labels[] = {
      {kTooth, "tooth", 1, teeth, &ReadingRow::tooth,
       "a tooth in 1 … " + std::to_string(teeth) + " (the model's gear has " +
           std::to_string(teeth) + " teeth)"},
      {kI, "i", 0, n - 1, &ReadingRow::i,
       "a profile index i in 0 … " + std::to_string(n - 1) + grid},
      {kJ, "j", 0, m - 1, &ReadingRow::j, "a face index j in 0 … " + std::to_string(m - 1) + grid}};
  // Every shifted column is named in the one message (a file with 1-based i usually has 1-based
  // j too), at the first shifted column's first row out of range.
  struct Finding {
    InputLocation where;
    std::string key, value, expected;
  };
  std::optional<Finding> first;
  std::string others;
  for (const Label& label : labels) {
    if (readings.rows.empty()) return;
    int lowest = readings.rows.front().*label.value, highest = lowest;
    std::size_t first_out = readings.rows.size();
    for (std::size_t k = 0; k < readings.rows.size(); ++k) {
      const int v = readings.rows[k].*label.value;
      lowest = std::min(lowest, v);
      highest = std::max(highest, v);
      if ((v < label.lo || v > label.hi) && first_out == readings.rows.size()) first_out = k;
    }
    if (first_out == readings.rows.size()) continue;  // every value in range
    // The one shift that brings every value into range, if there is one.
    const long shift = highest > label.hi ? static_cast<long>(highest) - label.hi
                                          : static_cast<long>(lowest) - label.lo;
    if (static_cast<long>(lowest) - shift < label.lo ||
        static_cast<long>(highest) - shift > label.hi) {
      continue;  // no single shift fits: the row-by-row check says what is wrong
    }
    const std::string by = (shift > 0 ? "+" : "") + std::to_string(shift);
    const char* hint = label.field == kTooth
                           ? (shift == -1 ? " (0-based teeth? gearmc numbers teeth from 1)" : "")
                           : (shift == 1 ? " (1-based indices? gearmc counts i and j from 0)" : "");
    const std::string finding =
        "every " + std::string(label.name) + " of this file lies in " + std::to_string(lowest) +
        " … " + std::to_string(highest) + ": the whole column looks shifted by " + by + hint +
        " — subtract " + std::to_string(shift) + " from every " + label.name;
    if (!first) {
      first = Finding{locate(readings, path, first_out, label.field), kFieldNames[label.field],
                      std::to_string(readings.rows[first_out].*label.value),
                      label.range + "; " + finding};
    } else {
      others += "; and " + finding;
    }
  }
  if (first) throw InputError(first->where, first->key, first->value, first->expected + others);
}

}  // namespace

void check_readings_against_model(const Scenario& model, const Readings& readings,
                                  const std::string& readings_path) {
  const int teeth = model.gear.teeth;
  const InvoluteGear gear(model.gear);
  // The teeth's outermost radius: the tip's, of an internal gear the root's.
  const double tip_radius = std::max(gear.tip_diameter_mm(), gear.root_diameter_mm()) / 2.0;
  const double module = gear.module_mm();
  const std::string outermost = gear.internal() ? "root radius" : "tip radius";
  const double face = gear.face_width_mm();
  const int n = model.probing.grid.points_along_profile;
  const int m = model.probing.grid.sections_across_face;
  const std::string grid = " of the model's " + std::to_string(n) + " × " + std::to_string(m) +
                           " probing grid (" + std::to_string(n) + " points along the profile, " +
                           std::to_string(m) + " sections across the face)";
  const double radius = readings.stylus_radius_mm;
  if (!(radius > 0.0 && radius <= kMaxStylusRadiusMm)) {
    throw InputError(locate_radius(readings_path), "stylus_radius_mm", number_text(radius),
                     "a stylus ball radius in (0, " + number_text(kMaxStylusRadiusMm) + "] mm");
  }
  // The header names the ball the readings were compensated with; the model must probe with the
  // same one (a calibration error of it is the stylus_radius effect, not another ball).
  if (std::abs(radius - model.stylus_radius_mm) > 1e-9 * std::max(1.0, radius)) {
    throw InputError(locate_radius(readings_path), "stylus_radius_mm", number_text(radius),
                     "the model scenario's stylus radius " + number_text(model.stylus_radius_mm) +
                         " mm (stylus.radius_mm): the readings were taken with another ball; "
                         "set stylus.radius_mm in the model to the ball that measured");
  }
  // Rows labelled by matching (point_matching.h) lie on the model's flanks by construction; their
  // i and j count sections and points, not the model's grid.
  const bool matched = readings.labels_from_matching;
  if (!matched) refuse_shifted_labels(readings, readings_path, teeth, n, m, grid);
  for (std::size_t k = 0; k < readings.rows.size(); ++k) {
    const ReadingRow& row = readings.rows[k];
    auto refuse = [&](int field, int value, const std::string& expected) {
      throw InputError(locate(readings, readings_path, k, field), kFieldNames[field],
                       std::to_string(value), expected);
    };
    if (row.gear < 0 || row.gear > kMaxGearIndex) {
      refuse(kGear, row.gear, "a gear index in 0 … " + std::to_string(kMaxGearIndex));
    }
    if (row.tooth < 1 || row.tooth > teeth) {
      refuse(kTooth, row.tooth,
             "a tooth in 1 … " + std::to_string(teeth) + " (the model's gear has " +
                 std::to_string(teeth) + " teeth)");
    }
    if (!matched && (row.i < 0 || row.i >= n)) {
      refuse(kI, row.i, "a profile index i in 0 … " + std::to_string(n - 1) + grid);
    }
    if (!matched && (row.j < 0 || row.j >= m)) {
      refuse(kJ, row.j, "a face index j in 0 … " + std::to_string(m - 1) + grid);
    }
    // The nominal point must lie on the model's gear: within one module of its tip cylinder.
    const double radial = std::hypot(row.p.x(), row.p.y());
    if (!(radial <= tip_radius + module) || !(row.p.z() >= -module) ||
        !(row.p.z() <= face + module)) {
      throw InputError(
          locate(readings, readings_path, k, kPx), "px,py,pz",
          number_text(row.p.x()) + "," + number_text(row.p.y()) + "," + number_text(row.p.z()),
          "a nominal point on the model's gear: radius √(px² + py²) ≤ " +
              number_text(tip_radius + module) + " mm (" + outermost + " + one module) and " +
              number_text(-module) + " ≤ pz ≤ " + number_text(face + module) + " mm");
    }
  }
  // The nominal points and normals must be the model gear's: each point on its tooth's nominal
  // flank (at the point's own radius and height) within what the tolerances allow, each normal
  // within 1° of that flank's normal. Readings of another gear are refused with what they fit.
  if (matched) return;
  const double allowed_mm = nominal_point_allowance_mm(model, gear);
  const double rb = gear.base_diameter_mm() / 2.0;
  constexpr double kMaxNormalAngleDeg = 1.0;
  std::size_t off = 0, worst = 0;
  double worst_mm = -1.0, worst_deg = 0.0;
  for (std::size_t k = 0; k < readings.rows.size(); ++k) {
    const ReadingRow& row = readings.rows[k];
    const double radial = std::hypot(row.p.x(), row.p.y());
    double distance_mm = rb - radial, angle_deg = 0.0;
    if (radial > rb) {
      const FlankPoint fp =
          gear.flank_point(row.tooth, row.side, std::sqrt(radial * radial - rb * rb), row.p.z());
      distance_mm = (row.p - fp.point).norm();
      const double cosine = row.n.normalized().dot(fp.normal);
      angle_deg = std::acos(std::clamp(cosine, -1.0, 1.0)) * 180.0 / std::numbers::pi;
    }
    if (!(distance_mm <= allowed_mm) || !(angle_deg <= kMaxNormalAngleDeg)) {
      ++off;
      if (distance_mm > worst_mm) {
        worst_mm = distance_mm;
        worst_deg = angle_deg;
        worst = k;
      }
    }
  }
  if (off > 0) {
    const ReadingRow& row = readings.rows[worst];
    const std::string fit = describe_gear_of_points(readings.rows, gear.pressure_angle_rad());
    throw InputError(
        locate(readings, readings_path, worst, kPx), "px,py,pz",
        number_text(row.p.x()) + "," + number_text(row.p.y()) + "," + number_text(row.p.z()),
        "nominal points on the model's gear: " + std::to_string(off) + " of " +
            std::to_string(readings.rows.size()) +
            " readings are off its nominal flanks (this one by " + short_text(worst_mm) +
            " mm, normal " + short_text(worst_deg) + "° off, at tooth " +
            std::to_string(row.tooth) + (row.side == FlankSide::kRight ? " R" : " L") +
            "; the model's tolerances allow " + short_text(allowed_mm) + " mm and " +
            short_text(kMaxNormalAngleDeg) + "°)" + (fit.empty() ? "" : "; " + fit) +
            ": are these readings of the model's gear (" + std::to_string(gear.teeth()) +
            " teeth, m " + short_text(gear.module_mm()) + " mm)?");
  }
}

void check_residuals(const Residuals& residuals, const Readings& readings,
                     const std::string& readings_path) {
  for (std::size_t k = 0; k < residuals.points.size() && k < readings.rows.size(); ++k) {
    const ResidualPoint& p = residuals.points[k];
    const double R = readings.stylus_radius_mm;
    if (!std::isfinite(p.measured_um) || std::abs(p.measured_um) > kMaxDeviationUm) {
      const InputLocation place = locate(readings, readings_path, k, kCx);
      throw InputError(place, "cx,cy,cz",
                       number_text(readings.rows[k].c.x()) + "," +
                           number_text(readings.rows[k].c.y()) + "," +
                           number_text(readings.rows[k].c.z()),
                       "a stylus centre whose deviation ((c − p)·n − R)·1000 from the nominal "
                       "point (here " +
                           number_text(p.measured_um) + " µm with R = " + number_text(R) +
                           " mm) is finite and within ±1e+09 µm (1 km)");
    }
    if (!std::isfinite(p.predicted_um) || !std::isfinite(p.residual_um)) {
      const InputLocation place = locate(readings, readings_path, k, kCx);
      throw InputError(place,
                       "the model's prediction for this reading is not a finite number (" +
                           number_text(p.predicted_um) + " µm) with the header's stylus radius " +
                           number_text(R) +
                           " mm: expected a stylus radius and a reading the model can probe");
    }
  }
}

}  // namespace gearmc
