// Rows of a readings file the diagnosis refuses (see readings_check.h).
#include "engine/diagnose/readings_check.h"

#include <cmath>
#include <fstream>
#include <sstream>

#include "engine/io/input_error.h"

namespace gearmc {
namespace {

// CSV columns of a readings row (readings_csv.h).
enum Field { kGear = 0, kTooth = 1, kI = 3, kJ = 4, kPx = 6, kCx = 12 };
const char* const kFieldNames[] = {"gear", "tooth", "flank", "i",  "j",  "order", "px", "py",
                                   "pz",   "nx",    "ny",    "nz", "cx", "cy",    "cz"};

struct RowPlace {
  InputLocation where;
  std::string text;  // the row's line ("" when unknown)
};

// File, line and column of field `field` of data row `row` (0-based), by reading the file again.
RowPlace locate(const std::string& path, std::size_t row, int field) {
  RowPlace out;
  out.where = {path.empty() ? "<readings>" : path, 0, 0};
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    out.where.file = "<readings> row " + std::to_string(row + 1);
    return out;
  }
  std::string line;
  int line_no = 0;
  bool columns_seen = false;
  std::size_t data = 0;
  while (std::getline(in, line)) {
    ++line_no;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.empty() || line[0] == '#') continue;
    if (!columns_seen) {
      columns_seen = true;
      continue;
    }
    if (data++ != row) continue;
    out.where.line = line_no;
    std::size_t start = 0;
    for (int f = 0; f < field && start != std::string::npos; ++f) {
      start = line.find(',', start);
      if (start != std::string::npos) ++start;
    }
    out.where.column = start == std::string::npos ? 0 : static_cast<int>(start) + 1;
    out.text = line;
    return out;
  }
  out.where.file = path + " row " + std::to_string(row + 1);
  return out;
}

std::string number_text(double v) {
  std::ostringstream s;
  s.precision(17);
  s << v;
  return s.str();
}

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

}  // namespace

void check_readings_against_model(const Scenario& model, const Readings& readings,
                                  const std::string& readings_path) {
  const int teeth = model.gear.teeth;
  const InvoluteGear gear(model.gear);
  const double tip_radius = gear.tip_diameter_mm() / 2.0, module = gear.module_mm();
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
  for (std::size_t k = 0; k < readings.rows.size(); ++k) {
    const ReadingRow& row = readings.rows[k];
    auto refuse = [&](int field, int value, const std::string& expected) {
      throw InputError(locate(readings_path, k, field).where, kFieldNames[field],
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
    if (row.i < 0 || row.i >= n) {
      refuse(kI, row.i, "a profile index i in 0 … " + std::to_string(n - 1) + grid);
    }
    if (row.j < 0 || row.j >= m) {
      refuse(kJ, row.j, "a face index j in 0 … " + std::to_string(m - 1) + grid);
    }
    // The nominal point must lie on the model's gear: within one module of its tip cylinder.
    const double radial = std::hypot(row.p.x(), row.p.y());
    if (!(radial <= tip_radius + module) || !(row.p.z() >= -module) ||
        !(row.p.z() <= face + module)) {
      throw InputError(
          locate(readings_path, k, kPx).where, "px,py,pz",
          number_text(row.p.x()) + "," + number_text(row.p.y()) + "," + number_text(row.p.z()),
          "a nominal point on the model's gear: radius √(px² + py²) ≤ " +
              number_text(tip_radius + module) + " mm (tip radius + one module) and " +
              number_text(-module) + " ≤ pz ≤ " + number_text(face + module) + " mm");
    }
  }
}

void check_residuals(const Residuals& residuals, const Readings& readings,
                     const std::string& readings_path) {
  for (std::size_t k = 0; k < residuals.points.size() && k < readings.rows.size(); ++k) {
    const ResidualPoint& p = residuals.points[k];
    const double R = residuals.stylus_radius_mm;
    if (!std::isfinite(p.measured_um) || std::abs(p.measured_um) > kMaxDeviationUm) {
      const RowPlace place = locate(readings_path, k, kCx);
      throw InputError(place.where, "cx,cy,cz",
                       number_text(readings.rows[k].c.x()) + "," +
                           number_text(readings.rows[k].c.y()) + "," +
                           number_text(readings.rows[k].c.z()),
                       "a stylus centre whose deviation ((c − p)·n − R)·1000 from the nominal "
                       "point (here " +
                           number_text(p.measured_um) + " µm with R = " + number_text(R) +
                           " mm) is finite and within ±1e+09 µm (1 km)");
    }
    if (!std::isfinite(p.predicted_um) || !std::isfinite(p.residual_um)) {
      const RowPlace place = locate(readings_path, k, kCx);
      throw InputError(place.where,
                       "the model's prediction for this reading is not a finite number (" +
                           number_text(p.predicted_um) + " µm) with the header's stylus radius " +
                           number_text(R) +
                           " mm: expected a stylus radius and a reading the model can probe");
    }
  }
}

}  // namespace gearmc
