// Readings from a generic CMM point table: the table of compensated points that CMM software
// exports (one row per probed point, one header line of column names), in any column order,
// with the software's own column names, lengths in mm, µm or inch, a decimal point or comma and
// `,`, `;` or tab between fields. A mapping (PointTableColumns, read from a small YAML file,
// docs/formats.md "Point table") names the columns holding gearmc's fields: tooth, flank, grid
// indices i and j, optionally gear and probing order, the nominal point p and outward unit
// normal n, and EITHER the measured point E (compensated along n: E = O − R n, as a CMM reports
// it) OR the measured deviation along n in µm. Each row becomes one readings row:
//   p, n = the nominal point (mm) and normal (normalised; direction cosines, no unit),
//   c = E + R n, or c = p + (R + dev/1000) n when the deviation is given, with R the stylus
//   radius (mm) the CMM compensated with, so that e = ((c − p)·n − R)·1000 µm is the reading,
//   order = the order column, else the row's position (0-based), gear = the gear column, else 0.
// Bad input — a mapped column the header lacks (with a "did you mean"), a field that is not a
// number in the table's decimal style, a flank other than L/R/left/right, a normal that is not
// a unit vector within 1e-3, a row with another number of fields than the header, no rows — is
// one InputError with file:line:column (exit 2). Frames as docs/formats.md: gear frame = CMM.
#pragma once

#include <Eigen/Core>
#include <optional>
#include <string>
#include <vector>

#include "core/input_error.h"
#include "engine/readings/readings_csv.h"

namespace gearmc {

// One column of the table named by the mapping, and where the mapping names it (for messages;
// an empty file when the mapping was made in code).
struct TableColumn {
  std::string name;
  InputLocation where;
};

enum class TableLengthUnit { kMm, kUm, kInch };

// What the measured coordinates are: compensated surface points E = O − R n (what CMM software
// reports, the default) or the stylus centres O themselves.
enum class MeasuredPointKind { kSurface, kStylusCentre };

struct PointTableColumns {
  // The label-free form (`columns: {x, y, z, …}`): only the measured points are required; each
  // is matched to its tooth, flank and foot point on the model's gear (point_matching.h). Then
  // i, j, k name the normal's direction cosines (a hint, as CMM exports label them), and tooth
  // and flank are hints. The labelled form (`nominal`, `normal`, `measured` or `deviation_um`):
  // tooth, flank, i, j (grid indices), nominal and normal are required.
  bool label_free = false;
  std::optional<TableColumn> gear;  // gear index (label-free: also spelled `run`); absent: 0
  std::optional<TableColumn> tooth, flank;  // flank: L/R or left/right (any case)
  std::optional<TableColumn> i, j;          // labelled form: grid indices
  std::optional<TableColumn> order;         // absent: the row's position in the table, 0-based
  std::optional<TableColumn> nominal_x, nominal_y, nominal_z;
  std::optional<TableColumn> normal_i, normal_j, normal_k;
  // The labelled form: exactly one of the measured point (all three) or the deviation along n
  // (µm). The label-free form: the measured point.
  std::optional<TableColumn> measured_x, measured_y, measured_z;
  std::optional<TableColumn> deviation_um;
  MeasuredPointKind points = MeasuredPointKind::kSurface;
  TableLengthUnit unit = TableLengthUnit::kMm;  // of the nominal and measured coordinates
  char decimal = '.';                           // '.' or ','
  std::optional<char> separator;  // ',', ';' or '\t'; absent: detected from the header line
};

// A measured point of a label-free table, before it is matched to the gear (point_matching.h).
struct UnlabelledPoint {
  Eigen::Vector3d measured = Eigen::Vector3d::Zero();  // E or O (MeasuredPointKind), mm
  std::optional<Eigen::Vector3d> normal_hint;          // unit
  std::optional<Eigen::Vector3d> nominal_hint;         // the planned point, mm
  std::optional<int> tooth_hint;
  std::optional<FlankSide> side_hint;
  int gear = 0;              // the gear (or run) column, else 0
  int order = 0;             // the order column, else the row's position
  int line = 0, column = 0;  // the row's line and its x field's column (1-based)
};

struct UnlabelledPoints {
  std::string source;
  double stylus_radius_mm = 0.5;
  MeasuredPointKind kind = MeasuredPointKind::kSurface;
  std::vector<UnlabelledPoint> points;
  std::vector<std::string> warnings;
};

// The mapping file (YAML, docs/formats.md "Point table"); InputError at its line:column for an
// unknown or missing key, a bad unit, decimal or separator, a decimal comma with separator ','.
PointTableColumns parse_point_table_columns(const std::string& yaml_text, const std::string& file);
PointTableColumns read_point_table_columns(const std::string& path);

// The table's rows as readings (the labelled form); `stylus_radius_mm` is the radius the CMM
// compensated with. A label-free mapping is an InputError here: read_unlabelled_points reads it.
Readings parse_point_table(const std::string& text, const std::string& source,
                           const PointTableColumns& columns, double stylus_radius_mm);
Readings read_point_table(const std::string& path, const PointTableColumns& columns,
                          double stylus_radius_mm);

// The rows of a label-free table (columns.label_free), with their hints.
UnlabelledPoints parse_unlabelled_points(const std::string& text, const std::string& source,
                                         const PointTableColumns& columns, double stylus_radius_mm);
UnlabelledPoints read_unlabelled_points(const std::string& path, const PointTableColumns& columns,
                                        double stylus_radius_mm);

}  // namespace gearmc
