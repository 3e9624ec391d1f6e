// The readings CSV of docs/formats.md: what a CMM recorded when probing a gear, one row per point
// (the nominal point p and outward normal n, the recorded stylus centre c at trigger, the
// probing order), written by `gearmc simulate` and read by `gearmc diagnose`. Real CMM data
// exported to this format is read the same way.
//
//   # gearmc readings v1
//   # stylus_radius_mm=0.5
//   gear,tooth,flank,i,j,order,px,py,pz,nx,ny,nz,cx,cy,cz[,ref_dev_um]
//
// Lengths in mm, ref_dev_um in µm, gear frame = CMM frame (docs/formats.md conventions).
// The measured deviation of a point is e = ((c − p)·n − R)·1000 µm (measured_deviation_um).
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <optional>
#include <ostream>
#include <string>
#include <utility>
#include <vector>

#include "gears/involute_gear.h"
#include "gears/point_key.h"

namespace gearmc {

struct ReadingRow : PointKey {
  int order = 0;  // probing sequence, 0-based per file
  Eigen::Vector3d p = Eigen::Vector3d::Zero(), n = Eigen::Vector3d::UnitX();
  Eigen::Vector3d c = Eigen::Vector3d::Zero();  // recorded stylus centre at trigger, mm
  std::optional<double> ref_dev_um;             // calibrated deviation of the artefact at p along n
  // Where the row is in its file, for messages (1-based; 0 for readings made in memory): `line`
  // holds the measured values (DMIS: the FA(…) statement), `key_column` its point's identity
  // (DMIS: the label; a point table: the tooth column), `measured_column` the measured value;
  // the nominal point and normal are at nominal_line:nominal_column (DMIS: the F(…)
  // statement; otherwise the same line).
  int line = 0;
  std::uint16_t source = 0;  // which file of Readings::sources (several files read together)
  int key_column = 0;
  int measured_column = 0;
  int nominal_line = 0;
  int nominal_column = 0;
};

struct Readings {
  double stylus_radius_mm = 0.5;
  bool has_ref_dev = false;  // the ref_dev_um column is present (then every row has it)
  // The file is gearmc's readings CSV (field k of a row is its k-th comma-separated field).
  bool is_readings_csv = false;
  std::vector<ReadingRow> rows;
  // Values valid but outside their usual range (parameter_ranges.h), whole located messages.
  std::vector<std::string> warnings;
  // Free comment lines written after the header's key lines (e.g. what made the file); the
  // reader skips free comments, so they are not read back.
  std::vector<std::string> comments;
  // The rows were matched to the model's gear (point_matching.h): their tooth, flank and nominal
  // point come from the projection, i and j count sections and points in them (not the model's
  // probing grid), and feet[k] holds row k's (roll length, z) on its flank (mm).
  bool labels_from_matching = false;
  // The files the rows come from, when several were read together (row.source indexes it);
  // empty: one file.
  std::vector<std::string> sources;
  std::vector<std::pair<double, double>> feet;
};

// e = ((c − p)·n − R)·1000 µm, less ref_dev_um when given: the measurement error of the point
// along n for a calibrated artefact (ref_dev_um = its true deviation), else the deviation.
double measured_deviation_um(const ReadingRow& row, double stylus_radius_mm);

// The file's text (shortest round-trip decimal for every real number).
std::string format_readings(const Readings& readings);
// The same text piece by piece, for a file written while its rows are made (`gearmc simulate`
// streams its rows to disk): the header of `readings` (its rows are ignored), then each row.
void write_readings_header(std::ostream& out, const Readings& readings);
void write_reading_row(std::ostream& out, const ReadingRow& row, bool has_ref_dev);
// Writes the file atomically (temp name, then rename); throws std::runtime_error on I/O errors.
void write_readings(const std::string& path, const Readings& readings);

// Reads and validates a readings file. Bad input throws InputError naming the file and CSV line
// (and column number of the field): a missing or unknown header line or column, a wrong unit
// in the header (e.g. stylus_radius_in=), a non-numeric, NaN or infinite field, a flank other
// than L/R, a normal that is not a unit vector (|n| off by > 1e-6), a row with too few or too
// many fields, an order used twice, a file without rows, a number outside its plausible range
// (readings_ranges()), a line longer than kMaxReadingsLineBytes. read_readings reads only a
// regular file of at most kMaxReadingsBytes. Lines may end in LF, CRLF or CR.
Readings read_readings(const std::string& path);
// Same from text; `source_name` is used in messages.
Readings parse_readings(const std::string& text, const std::string& source_name);

}  // namespace gearmc
