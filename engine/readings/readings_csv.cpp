// Reading and writing the readings CSV (see readings_csv.h).
#include "engine/readings/readings_csv.h"

#include <charconv>
#include <cmath>
#include <fstream>
#include <set>
#include <sstream>

#include "core/input_error.h"
#include "core/input_file.h"
#include "core/number_text.h"
#include "core/output_files.h"
#include "core/text_lines.h"
#include "engine/schema/parameter_ranges.h"

namespace gearmc {
namespace {

const std::vector<std::string> kColumns = {"gear",  "tooth", "flank", "i",  "j",
                                           "order", "px",    "py",    "pz", "nx",
                                           "ny",    "nz",    "cx",    "cy", "cz"};

std::vector<std::string> split(const std::string& line, std::vector<int>* columns) {
  std::vector<std::string> fields;
  std::size_t start = 0;
  for (;;) {
    const std::size_t comma = line.find(',', start);
    columns->push_back(static_cast<int>(start) + 1);
    fields.push_back(
        line.substr(start, comma == std::string::npos ? std::string::npos : comma - start));
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  for (std::string& f : fields) {  // trim spaces
    const auto b = f.find_first_not_of(" \t"), e = f.find_last_not_of(" \t");
    f = b == std::string::npos ? "" : f.substr(b, e - b + 1);
  }
  return fields;
}

}  // namespace

double measured_deviation_um(const ReadingRow& row, double stylus_radius_mm) {
  return ((row.c - row.p).dot(row.n) - stylus_radius_mm) * 1000.0 - row.ref_dev_um.value_or(0.0);
}

void write_readings_header(std::ostream& out, const Readings& readings) {
  out << "# gearmc readings v1\n# stylus_radius_mm=" << shortest_text(readings.stylus_radius_mm)
      << "\n";
  for (const std::string& comment : readings.comments) {
    // One line each, and never a key line: '=' and line breaks are replaced.
    std::string text = comment;
    for (char& c : text) {
      if (c == '\n' || c == '\r') c = ' ';
      if (c == '=') c = ':';
    }
    out << "# " << text << "\n";
  }
  for (std::size_t k = 0; k < kColumns.size(); ++k) out << (k ? "," : "") << kColumns[k];
  if (readings.has_ref_dev) out << ",ref_dev_um";
  out << "\n";
}

void write_reading_row(std::ostream& out, const ReadingRow& r, bool has_ref_dev) {
  out << r.gear << ',' << r.tooth << ',' << (r.side == FlankSide::kRight ? 'R' : 'L') << ',' << r.i
      << ',' << r.j << ',' << r.order;
  for (const Eigen::Vector3d* v : {&r.p, &r.n, &r.c}) {
    for (int a = 0; a < 3; ++a) out << ',' << shortest_text((*v)[a]);
  }
  if (has_ref_dev) out << ',' << shortest_text(r.ref_dev_um.value_or(0.0));
  out << "\n";
}

std::string format_readings(const Readings& readings) {
  std::ostringstream out;
  write_readings_header(out, readings);
  for (const ReadingRow& r : readings.rows) write_reading_row(out, r, readings.has_ref_dev);
  return out.str();
}

void write_readings(const std::string& path, const Readings& readings) {
  write_file_atomically(path, format_readings(readings));
}

Readings read_readings(const std::string& path) {
  return parse_readings(read_input_file(path, "readings file", kMaxReadingsBytes), path);
}

Readings parse_readings(const std::string& text, const std::string& source) {
  Readings readings;
  readings.is_readings_csv = true;
  TextLines in(text, source, kMaxReadingsLineBytes, "a readings CSV");
  TextLine next;
  const std::string& line = next.text;
  const int& line_no = next.number;
  auto error = [&](int column, const std::string& key, const std::string& value,
                   const std::string& expected) {
    return InputError({source, line_no, column}, key, value, expected);
  };
  const RangeTable& ranges = readings_ranges();
  // Header: the version line, key=value comment lines, then the column line.
  bool version = false, radius = false;
  std::vector<std::string> header;
  int header_line = 0;
  while (in.next(&next)) {
    if (line.empty()) continue;
    if (line[0] == '#') {
      const std::string body = line.substr(line.find_first_not_of("# ") == std::string::npos
                                               ? line.size()
                                               : line.find_first_not_of("# "));
      if (!version) {
        if (body != "gearmc readings v1") {
          throw error(1, "header", line, "the first line '# gearmc readings v1'");
        }
        version = true;
        continue;
      }
      const auto eq = body.find('=');
      const std::string key = body.substr(0, eq);
      if (eq == std::string::npos) continue;  // a free comment
      if (key.rfind("stylus_radius", 0) == 0 && key != "stylus_radius_mm") {
        throw error(1, key, body, "the stylus radius in millimetres: '# stylus_radius_mm=R'");
      }
      if (key == "stylus_radius_mm") {
        const std::string v = body.substr(eq + 1);
        double r = 0.0;
        const auto res = std::from_chars(v.data(), v.data() + v.size(), r);
        const int column = static_cast<int>(line.find('=')) + 2;
        if (res.ec != std::errc() || res.ptr != v.data() + v.size() || !std::isfinite(r)) {
          throw error(column, "stylus_radius_mm", v, describe_range(ranges.at("stylus_radius_mm")));
        }
        check_ranged(r, ranges.at("stylus_radius_mm"), {source, line_no, column}, v,
                     &readings.warnings);
        readings.stylus_radius_mm = r;
        radius = true;
      }
      continue;
    }
    if (!version) throw error(1, "header", line, "the first line '# gearmc readings v1'");
    if (!radius) {
      throw error(1, "stylus_radius_mm", line,
                  "a header line '# stylus_radius_mm=R' before the column names");
    }
    std::vector<int> cols;
    header = split(line, &cols);
    header_line = line_no;
    for (std::size_t k = 0; k < kColumns.size(); ++k) {
      if (k >= header.size() || header[k] != kColumns[k]) {
        throw error(k < cols.size() ? cols[k] : static_cast<int>(line.size()) + 1,
                    "column " + std::to_string(k + 1), k < header.size() ? header[k] : "",
                    "'" + kColumns[k] +
                        "' (columns: gear,tooth,flank,i,j,order,px,py,pz,nx,"
                        "ny,nz,cx,cy,cz[,ref_dev_um])");
      }
    }
    if (header.size() == kColumns.size() + 1 && header.back() == "ref_dev_um") {
      readings.has_ref_dev = true;
    } else if (header.size() != kColumns.size()) {
      throw error(cols[kColumns.size()], "column " + std::to_string(kColumns.size() + 1),
                  header[kColumns.size()], "'ref_dev_um' or the end of the line");
    }
    break;
  }
  if (header.empty()) {
    throw InputError({source, line_no + 1, 1},
                     "the readings file ends before its column line 'gear,tooth,flank,...'");
  }
  const std::size_t width = header.size();
  std::set<int> orders;
  while (in.next(&next)) {
    if (line.empty() || line[0] == '#') continue;
    std::vector<int> cols;
    const std::vector<std::string> f = split(line, &cols);
    if (f.size() != width) {
      // Placed at the first field too many, or at the end of a short row.
      const int column = f.size() > width ? cols[width] - 1 : static_cast<int>(line.size()) + 1;
      throw InputError({source, line_no, column}, "row has " + std::to_string(f.size()) +
                                                      " fields, expected " + std::to_string(width) +
                                                      " (as the column line)");
    }
    auto integer = [&](std::size_t k, int min) {
      int v = 0;
      const auto res = std::from_chars(f[k].data(), f[k].data() + f[k].size(), v);
      if (res.ec != std::errc() || res.ptr != f[k].data() + f[k].size() || v < min) {
        throw error(cols[k], header[k], f[k], "an integer >= " + std::to_string(min));
      }
      return v;
    };
    auto real = [&](std::size_t k, const ParameterRange* range) {
      double v = 0.0;
      const auto res = std::from_chars(f[k].data(), f[k].data() + f[k].size(), v);
      if (res.ec != std::errc() || res.ptr != f[k].data() + f[k].size() || !std::isfinite(v)) {
        throw error(cols[k], header[k], f[k], "a finite number");
      }
      if (range != nullptr) {
        ParameterRange named = *range;
        named.key = header[k];
        check_ranged(v, named, {source, line_no, cols[k]}, f[k], nullptr);
      }
      return v;
    };
    const ParameterRange& coordinate = ranges.at("coordinate_mm");
    ReadingRow r;
    r.gear = integer(0, 0);
    r.tooth = integer(1, 1);
    if (f[2] != "L" && f[2] != "R") throw error(cols[2], "flank", f[2], "L or R");
    r.side = f[2] == "R" ? FlankSide::kRight : FlankSide::kLeft;
    r.i = integer(3, 0);
    r.j = integer(4, 0);
    r.order = integer(5, 0);
    if (!orders.insert(r.order).second) {
      throw error(cols[5], "order", f[5], "an order not used by an earlier row");
    }
    for (int a = 0; a < 3; ++a) {
      r.p[a] = real(6 + a, &coordinate);
      r.n[a] = real(9 + a, nullptr);  // checked as a unit vector below
      r.c[a] = real(12 + a, &coordinate);
    }
    if (std::abs(r.n.norm() - 1.0) > 1e-6) {
      throw error(cols[9], "nx,ny,nz", f[9] + "," + f[10] + "," + f[11],
                  "a unit normal (|n| = 1 within 1e-6)");
    }
    if (readings.has_ref_dev) r.ref_dev_um = real(15, &ranges.at("ref_dev_um"));
    // The reading itself: far off means a stylus radius or coordinates in other units.
    const double e = measured_deviation_um(r, readings.stylus_radius_mm);
    check_ranged(e, ranges.at("reading_um"), {source, line_no, cols[12]},
                 "(c - p)·n - R = " + shortest_text(e) + " µm", nullptr);
    r.line = r.nominal_line = line_no;
    r.key_column = cols[0];
    r.measured_column = cols[12];
    r.nominal_column = cols[6];
    readings.rows.push_back(r);
  }
  if (readings.rows.empty()) {
    throw InputError({source, line_no + 1, 1},
                     "the readings file has no rows after its column line (line " +
                         std::to_string(header_line) + ")");
  }
  return readings;
}

}  // namespace gearmc
