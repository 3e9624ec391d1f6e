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

#include <optional>
#include <string>

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

struct PointTableColumns {
  std::optional<TableColumn> gear;   // absent: every row is gear 0
  TableColumn tooth, flank, i, j;    // flank: L/R or left/right (any case)
  std::optional<TableColumn> order;  // absent: the row's position in the table, 0-based
  TableColumn nominal_x, nominal_y, nominal_z;
  TableColumn normal_i, normal_j, normal_k;
  // Exactly one of: the measured compensated point (all three), or the deviation along n (µm).
  std::optional<TableColumn> measured_x, measured_y, measured_z;
  std::optional<TableColumn> deviation_um;
  TableLengthUnit unit = TableLengthUnit::kMm;  // of the nominal and measured coordinates
  char decimal = '.';                           // '.' or ','
  std::optional<char> separator;  // ',', ';' or '\t'; absent: detected from the header line
};

// The mapping file (YAML, docs/formats.md "Point table"); InputError at its line:column for an
// unknown or missing key, a bad unit, decimal or separator, a decimal comma with separator ','.
PointTableColumns parse_point_table_columns(const std::string& yaml_text, const std::string& file);
PointTableColumns read_point_table_columns(const std::string& path);

// The table's rows as readings; `stylus_radius_mm` is the radius the CMM compensated with.
Readings parse_point_table(const std::string& text, const std::string& source,
                           const PointTableColumns& columns, double stylus_radius_mm);
Readings read_point_table(const std::string& path, const PointTableColumns& columns,
                          double stylus_radius_mm);

}  // namespace gearmc
