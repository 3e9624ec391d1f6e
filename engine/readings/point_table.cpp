// Readings from a generic CMM point table and its column mapping (see point_table.h).
#include "engine/readings/point_table.h"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <map>
#include <set>
#include <vector>

#include "core/input_file.h"
#include "core/number_text.h"
#include "core/text_lines.h"
#include "core/yaml_reader.h"
#include "engine/schema/parameter_ranges.h"

namespace gearmc {
namespace {

// Longest line of a table: CMM exports carry many more columns than gearmc reads (feature
// names, tolerances, dates); 64 columns of 250 bytes each.
constexpr std::size_t kMaxTableLineBytes = 16384;

std::string lower(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

std::string separator_name(char s) { return s == '\t' ? "tab" : std::string(1, s); }

// One field of a line: its text (spaces and one pair of surrounding double quotes removed) and
// its 1-based column (of its first byte after leading spaces).
struct Field {
  std::string text;
  int column = 0;
};

std::vector<Field> split(const std::string& line, char separator) {
  std::vector<Field> out;
  std::size_t start = 0;
  for (;;) {
    std::size_t end = line.find(separator, start);
    if (end == std::string::npos) end = line.size();
    std::size_t b = start, e = end;
    while (b < e && (line[b] == ' ' || line[b] == '\t') && line[b] != separator) ++b;
    while (e > b && (line[e - 1] == ' ' || line[e - 1] == '\t') && line[e - 1] != separator) --e;
    if (e - b >= 2 && line[b] == '"' && line[e - 1] == '"') {
      ++b;
      --e;
    }
    out.push_back({line.substr(b, e - b), static_cast<int>(b) + 1});
    if (end == line.size()) break;
    start = end + 1;
  }
  return out;
}

bool skipped(const std::string& line) {
  const std::size_t b = line.find_first_not_of(" \t");
  return b == std::string::npos || line[b] == '#';
}

// A mapped column: our field's key (as the mapping file spells it) and the table's column.
struct Mapped {
  std::string key;
  const TableColumn* column;
};

std::vector<Mapped> mapped_columns(const PointTableColumns& c) {
  std::vector<Mapped> out;
  if (c.gear) out.push_back({"columns.gear", &*c.gear});
  out.push_back({"columns.tooth", &c.tooth});
  out.push_back({"columns.flank", &c.flank});
  out.push_back({"columns.i", &c.i});
  out.push_back({"columns.j", &c.j});
  if (c.order) out.push_back({"columns.order", &*c.order});
  out.push_back({"columns.nominal.x", &c.nominal_x});
  out.push_back({"columns.nominal.y", &c.nominal_y});
  out.push_back({"columns.nominal.z", &c.nominal_z});
  out.push_back({"columns.normal.i", &c.normal_i});
  out.push_back({"columns.normal.j", &c.normal_j});
  out.push_back({"columns.normal.k", &c.normal_k});
  if (c.measured_x) out.push_back({"columns.measured.x", &*c.measured_x});
  if (c.measured_y) out.push_back({"columns.measured.y", &*c.measured_y});
  if (c.measured_z) out.push_back({"columns.measured.z", &*c.measured_z});
  if (c.deviation_um) out.push_back({"columns.deviation_um", &*c.deviation_um});
  return out;
}

TableColumn column_of(const YamlValue& v) {
  const std::string name = v.as_string();
  if (name.empty()) throw v.error("a column name of the table's header line");
  return {name, v.location()};
}

}  // namespace

PointTableColumns parse_point_table_columns(const std::string& yaml_text, const std::string& file) {
  const YamlValue root = parse_yaml_document(yaml_text, file);
  const YamlMap top = root.as_map({"columns", "unit", "decimal", "separator"});
  const YamlMap m = top.require_map("columns", {"gear", "tooth", "flank", "i", "j", "order",
                                                "nominal", "normal", "measured", "deviation_um"});
  PointTableColumns c;
  const auto required = [&](const std::string& key) {
    return column_of(m.require(key, "the name of the table's column holding " + key));
  };
  if (auto v = m.find("gear")) c.gear = column_of(*v);
  c.tooth = required("tooth");
  c.flank = required("flank");
  c.i = required("i");
  c.j = required("j");
  if (auto v = m.find("order")) c.order = column_of(*v);
  const YamlMap nominal = m.require_map("nominal", {"x", "y", "z"});
  const auto axis = [](const YamlMap& map, const std::string& a) {
    return column_of(map.require(a, "the name of the table's column holding " + a));
  };
  c.nominal_x = axis(nominal, "x");
  c.nominal_y = axis(nominal, "y");
  c.nominal_z = axis(nominal, "z");
  const YamlMap normal = m.require_map("normal", {"i", "j", "k"});
  c.normal_i = axis(normal, "i");
  c.normal_j = axis(normal, "j");
  c.normal_k = axis(normal, "k");
  const auto measured = m.get_map("measured", {"x", "y", "z"});
  if (auto v = m.find("deviation_um")) {
    if (measured) {
      throw v->error("either measured: {x, y, z} or deviation_um, not both");
    }
    c.deviation_um = column_of(*v);
  } else if (measured) {
    c.measured_x = axis(*measured, "x");
    c.measured_y = axis(*measured, "y");
    c.measured_z = axis(*measured, "z");
  } else {
    throw m.missing("measured",
                    "measured: {x, y, z} (the compensated points) or deviation_um (the measured "
                    "deviation along the normal, µm)");
  }
  // µm and inch as exports and users write them, um and in as plain ASCII.
  if (auto v = top.get_choice("unit", {"mm", "um", "µm", "in", "inch"})) {
    c.unit = *v == "um" || *v == "µm"     ? TableLengthUnit::kUm
             : *v == "in" || *v == "inch" ? TableLengthUnit::kInch
                                          : TableLengthUnit::kMm;
  }
  if (auto v = top.find("decimal")) c.decimal = v->as_choice({".", ","})[0];
  if (auto v = top.find("separator")) {
    const std::string s = v->as_choice({",", ";", "tab", "\t"});
    c.separator = s == "tab" ? '\t' : s[0];  // "tab", or a tab character ("\t")
    if (c.decimal == ',' && *c.separator == ',') {
      throw v->error("';' or tab: with decimal ',' the fields cannot be separated by ','");
    }
  }
  return c;
}

PointTableColumns read_point_table_columns(const std::string& path) {
  const std::string text = read_input_file(path, "point table columns file", kMaxScenarioBytes);
  require_utf8(text, path, "point table columns file");
  return parse_point_table_columns(text, path);
}

Readings parse_point_table(const std::string& text, const std::string& source,
                           const PointTableColumns& columns, double stylus_radius_mm) {
  TextLines in(text, source, kMaxTableLineBytes, "a point table");
  TextLine header_line;
  bool found_header = false;
  while (in.next(&header_line)) {
    if (!skipped(header_line.text)) {
      found_header = true;
      break;
    }
  }
  if (!found_header) {
    throw InputError({source, std::max(header_line.number, 1), 1},
                     source + ": no header line (the column names) and no rows in this table");
  }
  const std::vector<Mapped> mapped = mapped_columns(columns);

  // The separator: as the mapping says, else the candidate that finds the most mapped names in
  // the header line (a decimal comma rules out ',').
  char separator = '\0';
  if (columns.separator) {
    separator = *columns.separator;
  } else {
    std::size_t best = 0;
    for (const char candidate : {'\t', ';', ','}) {
      if (candidate == ',' && columns.decimal == ',') continue;
      if (header_line.text.find(candidate) == std::string::npos) continue;
      std::set<std::string> names;
      for (const Field& f : split(header_line.text, candidate)) names.insert(f.text);
      std::size_t found = 0;
      for (const Mapped& m : mapped) found += names.count(m.column->name);
      if (separator == '\0' || found > best) {
        separator = candidate;
        best = found;
      }
    }
    if (separator == '\0') {
      throw InputError({source, header_line.number, 1}, "header line", header_line.text,
                       std::string("column names separated by ';', tab") +
                           (columns.decimal == ',' ? " (with decimal ',' not by ',')" : " or ','"));
    }
  }

  // The header: where each mapped column is.
  const std::vector<Field> header = split(header_line.text, separator);
  std::vector<std::string> names;
  for (const Field& f : header) names.push_back(f.text);
  std::map<const TableColumn*, std::size_t> index;
  std::map<std::string, std::string> used_by;  // column name → the key mapping it first
  for (const Mapped& m : mapped) {
    const TableColumn& col = *m.column;
    const InputLocation where =
        col.where.file.empty() ? InputLocation{source, header_line.number, 1} : col.where;
    if (const auto [it, inserted] = used_by.emplace(col.name, m.key); !inserted) {
      throw InputError(where, m.key, col.name,
                       "a column not mapped already (" + it->second + " names it)");
    }
    const auto found = std::find(names.begin(), names.end(), col.name);
    if (found == names.end()) {
      // A header of one column: the separator is wrong, no name is a likely typo.
      const bool one_column = names.size() == 1;
      throw InputError(
          where, m.key, col.name,
          "a column of the header line of " + source + " (line " +
              std::to_string(header_line.number) + ", separator " + separator_name(separator) +
              (one_column ? ", which makes it one column: is the separator right?)" : ")"),
          one_column ? "" : did_you_mean(col.name, names));
    }
    if (const auto again = std::find(found + 1, names.end(), col.name); again != names.end()) {
      throw InputError({source, header_line.number, header[again - names.begin()].column},
                       "header line", col.name,
                       "column names that are distinct (" + m.key + " names this one)");
    }
    index[&col] = static_cast<std::size_t>(found - names.begin());
  }

  const double scale = columns.unit == TableLengthUnit::kUm     ? 1e-3
                       : columns.unit == TableLengthUnit::kInch ? 25.4
                                                                : 1.0;
  const std::string unit_name = columns.unit == TableLengthUnit::kUm     ? "µm"
                                : columns.unit == TableLengthUnit::kInch ? "in"
                                                                         : "mm";
  const RangeTable& ranges = readings_ranges();
  Readings readings;
  readings.stylus_radius_mm = stylus_radius_mm;
  std::set<int> orders;
  TextLine line = header_line;
  while (in.next(&line)) {
    if (skipped(line.text)) continue;
    const std::vector<Field> f = split(line.text, separator);
    if (f.size() != header.size()) {
      const int column = f.size() > header.size() ? f[header.size()].column - 1
                                                  : static_cast<int>(line.text.size()) + 1;
      throw InputError({source, line.number, column},
                       "row has " + std::to_string(f.size()) + " fields, expected " +
                           std::to_string(header.size()) + " (as the header line, separator " +
                           separator_name(separator) + ")");
    }
    const auto field = [&](const TableColumn& c) -> const Field& { return f[index.at(&c)]; };
    const auto error = [&](const TableColumn& c, const std::string& expected) {
      const Field& x = field(c);
      return InputError({source, line.number, x.column}, c.name, x.text, expected);
    };
    const auto integer = [&](const TableColumn& c, int min) {
      const std::string& t = field(c).text;
      int v = 0;
      const auto res = std::from_chars(t.data(), t.data() + t.size(), v);
      if (t.empty() || res.ec != std::errc() || res.ptr != t.data() + t.size() || v < min) {
        throw error(c, "an integer >= " + std::to_string(min));
      }
      return v;
    };
    // A finite number in the table's decimal style (one leading '+' allowed).
    const auto real = [&](const TableColumn& c, const std::string& unit) {
      std::string t = field(c).text;
      const std::string expected = std::string("a finite number with decimal ") +
                                   (columns.decimal == ',' ? "comma" : "point") +
                                   (unit.empty() ? "" : " (" + unit + ")");
      if (columns.decimal == ',') {
        if (t.find('.') != std::string::npos) throw error(c, expected);
        std::replace(t.begin(), t.end(), ',', '.');
      }
      if (!t.empty() && t[0] == '+') t.erase(0, 1);
      double v = 0.0;
      const auto res = std::from_chars(t.data(), t.data() + t.size(), v);
      if (t.empty() || res.ec != std::errc() || res.ptr != t.data() + t.size() ||
          !std::isfinite(v)) {
        throw error(c, expected);
      }
      return v;
    };
    const ParameterRange& coordinate = ranges.at("coordinate_mm");
    const auto length = [&](const TableColumn& c) {
      const double v = real(c, unit_name) * scale;
      ParameterRange named = coordinate;
      named.key = c.name;
      check_ranged(v, named, {source, line.number, field(c).column},
                   field(c).text + " " + unit_name + " = " + shortest_text(v) + " mm", nullptr);
      return v;
    };

    ReadingRow r;
    r.gear = columns.gear ? integer(*columns.gear, 0) : 0;
    r.tooth = integer(columns.tooth, 1);
    const std::string flank = lower(field(columns.flank).text);
    if (flank == "l" || flank == "left") {
      r.side = FlankSide::kLeft;
    } else if (flank == "r" || flank == "right") {
      r.side = FlankSide::kRight;
    } else {
      throw error(columns.flank, "L or R (or left, right; any case)");
    }
    r.i = integer(columns.i, 0);
    r.j = integer(columns.j, 0);
    r.order = columns.order ? integer(*columns.order, 0) : static_cast<int>(readings.rows.size());
    if (!orders.insert(r.order).second) {
      throw error(*columns.order, "an order not used by an earlier row");
    }
    r.p = {length(columns.nominal_x), length(columns.nominal_y), length(columns.nominal_z)};
    r.n = {real(columns.normal_i, ""), real(columns.normal_j, ""), real(columns.normal_k, "")};
    if (std::abs(r.n.norm() - 1.0) > 1e-3) {
      throw InputError(
          {source, line.number, field(columns.normal_i).column},
          columns.normal_i.name + "," + columns.normal_j.name + "," + columns.normal_k.name,
          field(columns.normal_i).text + separator_name(separator) + field(columns.normal_j).text +
              separator_name(separator) + field(columns.normal_k).text,
          "a unit normal (|n| = 1 within 1e-3; here |n| = " + shortest_text(r.n.norm()) + ")");
    }
    r.n.normalize();
    InputLocation reading_at{source, line.number, 0};
    if (columns.deviation_um) {
      const double dev = real(*columns.deviation_um, "µm");
      r.c = r.p + (stylus_radius_mm + dev / 1000.0) * r.n;
      reading_at.column = field(*columns.deviation_um).column;
    } else {
      const Eigen::Vector3d e{length(*columns.measured_x), length(*columns.measured_y),
                              length(*columns.measured_z)};
      r.c = e + stylus_radius_mm * r.n;
      reading_at.column = field(*columns.measured_x).column;
    }
    // The reading itself: far off means points in another unit than the mapping says.
    const double e_um = measured_deviation_um(r, stylus_radius_mm);
    check_ranged(e_um, ranges.at("reading_um"), reading_at,
                 "(E - p)·n = " + shortest_text(e_um) + " µm", nullptr);
    r.line = r.nominal_line = line.number;
    r.key_column = field(columns.tooth).column;
    r.measured_column = reading_at.column;
    r.nominal_column = field(columns.nominal_x).column;
    readings.rows.push_back(r);
  }
  if (readings.rows.empty()) {
    throw InputError({source, line.number + 1, 1},
                     source + ": the point table has no rows after its header line (line " +
                         std::to_string(header_line.number) + ")");
  }
  return readings;
}

Readings read_point_table(const std::string& path, const PointTableColumns& columns,
                          double stylus_radius_mm) {
  return parse_point_table(read_input_file(path, "point table", kMaxReadingsBytes), path, columns,
                           stylus_radius_mm);
}

}  // namespace gearmc
