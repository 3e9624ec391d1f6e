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
  const auto add = [&](const char* key, const std::optional<TableColumn>& column) {
    if (column) out.push_back({key, &*column});
  };
  const bool lf = c.label_free;
  add(lf ? "columns.run" : "columns.gear", c.gear);
  add("columns.tooth", c.tooth);
  add("columns.flank", c.flank);
  add("columns.i", c.i);
  add("columns.j", c.j);
  add("columns.order", c.order);
  add("columns.nominal.x", c.nominal_x);
  add("columns.nominal.y", c.nominal_y);
  add("columns.nominal.z", c.nominal_z);
  add(lf ? "columns.i" : "columns.normal.i", c.normal_i);
  add(lf ? "columns.j" : "columns.normal.j", c.normal_j);
  add(lf ? "columns.k" : "columns.normal.k", c.normal_k);
  add(lf ? "columns.x" : "columns.measured.x", c.measured_x);
  add(lf ? "columns.y" : "columns.measured.y", c.measured_y);
  add(lf ? "columns.z" : "columns.measured.z", c.measured_z);
  add("columns.deviation_um", c.deviation_um);
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
  const YamlMap top = root.as_map({"columns", "points", "unit", "decimal", "separator"});
  const YamlMap m =
      top.require_map("columns", {"gear", "run", "tooth", "flank", "i", "j", "k", "order",
                                  "nominal", "normal", "measured", "deviation_um", "x", "y", "z"});
  PointTableColumns c;
  const auto axis = [](const YamlMap& map, const std::string& a) {
    return column_of(map.require(a, "the name of the table's column holding " + a));
  };
  const auto optional = [&](const char* key) -> std::optional<TableColumn> {
    if (auto v = m.find(key)) return column_of(*v);
    return std::nullopt;
  };
  c.label_free = m.find("x") || m.find("y") || m.find("z");
  if (c.label_free) {
    // The label-free form: the measured point; i, j, k the normal (a hint), tooth and flank
    // hints, a run or gear column, the order.
    for (const char* labelled : {"normal", "measured", "deviation_um"}) {
      if (auto v = m.find(labelled)) {
        throw InputError(v->key_location(), std::string("columns.") + labelled, "",
                         "x, y, z and the optional hints of the label-free form (i, j, k: the "
                         "normal; nominal: {x, y, z}; tooth, flank, run, order), or the labelled "
                         "form (tooth, flank, i, j, nominal, normal, measured or deviation_um) "
                         "without x, y, z");
      }
    }
    c.measured_x = axis(m, "x");
    c.measured_y = axis(m, "y");
    c.measured_z = axis(m, "z");
    const int normal_keys = (m.find("i") ? 1 : 0) + (m.find("j") ? 1 : 0) + (m.find("k") ? 1 : 0);
    if (normal_keys != 0 && normal_keys != 3) {
      throw m.missing(!m.find("i")   ? "i"
                      : !m.find("j") ? "j"
                                     : "k",
                      "all three of i, j, k (the normal's direction cosines) or none");
    }
    if (normal_keys == 3) {
      c.normal_i = axis(m, "i");
      c.normal_j = axis(m, "j");
      c.normal_k = axis(m, "k");
    }
    c.tooth = optional("tooth");
    c.flank = optional("flank");
    if (const auto nominal = m.get_map("nominal", {"x", "y", "z"})) {
      c.nominal_x = axis(*nominal, "x");
      c.nominal_y = axis(*nominal, "y");
      c.nominal_z = axis(*nominal, "z");
    }
    if (auto gear = m.find("gear")) {
      if (m.find("run")) throw gear->error("either gear or run (the same column), not both");
    }
    c.gear = m.find("run") ? optional("run") : optional("gear");
    c.order = optional("order");
  } else {
    const auto required = [&](const std::string& key) {
      return column_of(m.require(key, "the name of the table's column holding " + key));
    };
    if (auto v = m.find("k")) {
      throw v->error(
          "no k: in the labelled form i and j are grid indices and the normal is normal: {i, j, "
          "k}; the label-free form names the measured point x, y, z");
    }
    if (auto v = m.find("run")) c.gear = column_of(*v);
    if (auto v = m.find("gear")) {
      if (c.gear) throw v->error("either gear or run (the same column), not both");
      c.gear = column_of(*v);
    }
    c.tooth = required("tooth");
    c.flank = required("flank");
    c.i = required("i");
    c.j = required("j");
    c.order = optional("order");
    const YamlMap nominal = m.require_map("nominal", {"x", "y", "z"});
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
                      "measured: {x, y, z} (the compensated points) or deviation_um (the "
                      "measured deviation along the normal, µm)");
    }
  }
  if (auto v = top.get_choice("points", {"surface", "stylus_centre"})) {
    c.points =
        *v == "stylus_centre" ? MeasuredPointKind::kStylusCentre : MeasuredPointKind::kSurface;
    if (c.deviation_um && c.points == MeasuredPointKind::kStylusCentre) {
      throw top.find("points")->error("surface: a deviation along the normal is of the surface");
    }
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

namespace {

// A point table being read: its header (separator, where each mapped column is), then its data
// rows one by one, with the field readers that turn a mapped column's field into a value or
// into one located InputError.
class TableRows {
 public:
  TableRows(const std::string& text, const std::string& source, const PointTableColumns& columns)
      : in_(text, source, kMaxTableLineBytes, "a point table"),
        source_(source),
        columns_(columns),
        scale_(columns.unit == TableLengthUnit::kUm     ? 1e-3
               : columns.unit == TableLengthUnit::kInch ? 25.4
                                                        : 1.0),
        unit_name_(columns.unit == TableLengthUnit::kUm     ? "µm"
                   : columns.unit == TableLengthUnit::kInch ? "in"
                                                            : "mm") {
    read_header();
  }

  // The next data row; false after the last one.
  bool next() {
    while (in_.next(&line_)) {
      if (skipped(line_.text)) continue;
      fields_ = split(line_.text, separator_);
      if (fields_.size() != header_.size()) {
        const int column = fields_.size() > header_.size()
                               ? fields_[header_.size()].column - 1
                               : static_cast<int>(line_.text.size()) + 1;
        throw InputError({source_, line_.number, column},
                         "row has " + std::to_string(fields_.size()) + " fields, expected " +
                             std::to_string(header_.size()) + " (as the header line, separator " +
                             separator_name(separator_) + ")");
      }
      return true;
    }
    return false;
  }

  int line() const { return line_.number; }
  int header_line() const { return header_line_.number; }
  char separator() const { return separator_; }
  const Field& field(const TableColumn& c) const { return fields_[index_.at(&c)]; }
  InputError error(const TableColumn& c, const std::string& expected) const {
    const Field& x = field(c);
    return InputError({source_, line_.number, x.column}, c.name, x.text, expected);
  }

  int integer(const TableColumn& c, int min) const {
    const std::string& t = field(c).text;
    int v = 0;
    const auto res = std::from_chars(t.data(), t.data() + t.size(), v);
    if (t.empty() || res.ec != std::errc() || res.ptr != t.data() + t.size() || v < min) {
      throw error(c, "an integer >= " + std::to_string(min));
    }
    return v;
  }

  // A finite number in the table's decimal style (one leading '+' allowed).
  double real(const TableColumn& c, const std::string& unit) const {
    std::string t = field(c).text;
    const std::string expected = std::string("a finite number with decimal ") +
                                 (columns_.decimal == ',' ? "comma" : "point") +
                                 (unit.empty() ? "" : " (" + unit + ")");
    if (columns_.decimal == ',') {
      if (t.find('.') != std::string::npos) throw error(c, expected);
      std::replace(t.begin(), t.end(), ',', '.');
    }
    if (!t.empty() && t[0] == '+') t.erase(0, 1);
    double v = 0.0;
    const auto res = std::from_chars(t.data(), t.data() + t.size(), v);
    if (t.empty() || res.ec != std::errc() || res.ptr != t.data() + t.size() || !std::isfinite(v)) {
      throw error(c, expected);
    }
    return v;
  }

  // A coordinate in mm, within its plausible range.
  double length(const TableColumn& c) const {
    const double v = real(c, unit_name_) * scale_;
    ParameterRange named = readings_ranges().at("coordinate_mm");
    named.key = c.name;
    check_ranged(v, named, {source_, line_.number, field(c).column},
                 field(c).text + " " + unit_name_ + " = " + shortest_text(v) + " mm", nullptr);
    return v;
  }

  Eigen::Vector3d point(const TableColumn& x, const TableColumn& y, const TableColumn& z) const {
    return {length(x), length(y), length(z)};
  }

  FlankSide flank(const TableColumn& c) const {
    const std::string flank = lower(field(c).text);
    if (flank == "l" || flank == "left") return FlankSide::kLeft;
    if (flank == "r" || flank == "right") return FlankSide::kRight;
    throw error(c, "L or R (or left, right; any case)");
  }

  // A unit normal (|n| = 1 within 1e-3), normalised.
  Eigen::Vector3d normal(const TableColumn& i, const TableColumn& j, const TableColumn& k) const {
    Eigen::Vector3d n{real(i, ""), real(j, ""), real(k, "")};
    if (std::abs(n.norm() - 1.0) > 1e-3) {
      const std::string sep = separator_name(separator_);
      throw InputError(
          {source_, line_.number, field(i).column}, i.name + "," + j.name + "," + k.name,
          field(i).text + sep + field(j).text + sep + field(k).text,
          "a unit normal (|n| = 1 within 1e-3; here |n| = " + shortest_text(n.norm()) + ")");
    }
    return n.normalized();
  }

  // The order of the row: its column, else the row's position; an order used twice is refused.
  int order(std::size_t position) {
    const int v = columns_.order ? integer(*columns_.order, 0) : static_cast<int>(position);
    if (!orders_.insert(v).second)
      throw error(*columns_.order, "an order not used by an earlier row");
    return v;
  }

  InputError no_rows() const {
    return InputError({source_, line_.number + 1, 1},
                      source_ + ": the point table has no rows after its header line (line " +
                          std::to_string(header_line_.number) + ")");
  }

 private:
  void read_header() {
    bool found_header = false;
    while (in_.next(&header_line_)) {
      if (!skipped(header_line_.text)) {
        found_header = true;
        break;
      }
    }
    if (!found_header) {
      throw InputError({source_, std::max(header_line_.number, 1), 1},
                       source_ + ": no header line (the column names) and no rows in this table");
    }
    const std::vector<Mapped> mapped = mapped_columns(columns_);

    // The separator: as the mapping says, else the candidate that finds the most mapped names in
    // the header line (a decimal comma rules out ',').
    if (columns_.separator) {
      separator_ = *columns_.separator;
    } else {
      std::size_t best = 0;
      for (const char candidate : {'\t', ';', ','}) {
        if (candidate == ',' && columns_.decimal == ',') continue;
        if (header_line_.text.find(candidate) == std::string::npos) continue;
        std::set<std::string> names;
        for (const Field& f : split(header_line_.text, candidate)) names.insert(f.text);
        std::size_t found = 0;
        for (const Mapped& m : mapped) found += names.count(m.column->name);
        if (separator_ == '\0' || found > best) {
          separator_ = candidate;
          best = found;
        }
      }
      if (separator_ == '\0') {
        throw InputError(
            {source_, header_line_.number, 1}, "header line", header_line_.text,
            std::string("column names separated by ';', tab") +
                (columns_.decimal == ',' ? " (with decimal ',' not by ',')" : " or ','"));
      }
    }

    // The header: where each mapped column is.
    header_ = split(header_line_.text, separator_);
    std::vector<std::string> names;
    for (const Field& f : header_) names.push_back(f.text);
    std::map<std::string, std::string> used_by;  // column name → the key mapping it first
    for (const Mapped& m : mapped) {
      const TableColumn& col = *m.column;
      const InputLocation where =
          col.where.file.empty() ? InputLocation{source_, header_line_.number, 1} : col.where;
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
            "a column of the header line of " + source_ + " (line " +
                std::to_string(header_line_.number) + ", separator " + separator_name(separator_) +
                (one_column ? ", which makes it one column: is the separator right?)" : ")"),
            one_column ? "" : did_you_mean(col.name, names));
      }
      if (const auto again = std::find(found + 1, names.end(), col.name); again != names.end()) {
        throw InputError({source_, header_line_.number, header_[again - names.begin()].column},
                         "header line", col.name,
                         "column names that are distinct (" + m.key + " names this one)");
      }
      index_[&col] = static_cast<std::size_t>(found - names.begin());
    }
    line_ = header_line_;
  }

  TextLines in_;
  std::string source_;
  const PointTableColumns& columns_;
  double scale_;
  std::string unit_name_;
  TextLine header_line_, line_;
  char separator_ = '\0';
  std::vector<Field> header_, fields_;
  std::map<const TableColumn*, std::size_t> index_;
  std::set<int> orders_;
};

}  // namespace

Readings parse_point_table(const std::string& text, const std::string& source,
                           const PointTableColumns& columns, double stylus_radius_mm) {
  if (columns.label_free) {
    throw InputError({source, 0, 0},
                     source +
                         ": a label-free mapping (columns x, y, z): its points are matched "
                         "to the model's gear (read_unlabelled_points)");
  }
  TableRows table(text, source, columns);
  const RangeTable& ranges = readings_ranges();
  Readings readings;
  readings.stylus_radius_mm = stylus_radius_mm;
  while (table.next()) {
    ReadingRow r;
    r.gear = columns.gear ? table.integer(*columns.gear, 0) : 0;
    r.tooth = table.integer(*columns.tooth, 1);
    r.side = table.flank(*columns.flank);
    r.i = table.integer(*columns.i, 0);
    r.j = table.integer(*columns.j, 0);
    r.order = table.order(readings.rows.size());
    r.p = table.point(*columns.nominal_x, *columns.nominal_y, *columns.nominal_z);
    r.n = table.normal(*columns.normal_i, *columns.normal_j, *columns.normal_k);
    InputLocation reading_at{source, table.line(), 0};
    if (columns.deviation_um) {
      const double dev = table.real(*columns.deviation_um, "µm");
      r.c = r.p + (stylus_radius_mm + dev / 1000.0) * r.n;
      reading_at.column = table.field(*columns.deviation_um).column;
    } else {
      const Eigen::Vector3d m =
          table.point(*columns.measured_x, *columns.measured_y, *columns.measured_z);
      r.c = columns.points == MeasuredPointKind::kStylusCentre ? m : m + stylus_radius_mm * r.n;
      reading_at.column = table.field(*columns.measured_x).column;
    }
    // The reading itself: far off means points in another unit than the mapping says.
    const double e_um = measured_deviation_um(r, stylus_radius_mm);
    check_ranged(e_um, ranges.at("reading_um"), reading_at,
                 "(E - p)·n = " + shortest_text(e_um) + " µm", nullptr);
    r.line = r.nominal_line = table.line();
    r.key_column = table.field(*columns.tooth).column;
    r.measured_column = reading_at.column;
    r.nominal_column = table.field(*columns.nominal_x).column;
    readings.rows.push_back(r);
  }
  if (readings.rows.empty()) throw table.no_rows();
  return readings;
}

UnlabelledPoints parse_unlabelled_points(const std::string& text, const std::string& source,
                                         const PointTableColumns& columns,
                                         double stylus_radius_mm) {
  if (!columns.label_free) {
    throw InputError({source, 0, 0}, source + ": a labelled mapping: parse_point_table reads it");
  }
  TableRows table(text, source, columns);
  UnlabelledPoints out;
  out.source = source;
  out.stylus_radius_mm = stylus_radius_mm;
  out.kind = columns.points;
  while (table.next()) {
    UnlabelledPoint q;
    q.measured = table.point(*columns.measured_x, *columns.measured_y, *columns.measured_z);
    if (columns.normal_i) {
      q.normal_hint = table.normal(*columns.normal_i, *columns.normal_j, *columns.normal_k);
    }
    if (columns.nominal_x) {
      q.nominal_hint = table.point(*columns.nominal_x, *columns.nominal_y, *columns.nominal_z);
    }
    if (columns.tooth) q.tooth_hint = table.integer(*columns.tooth, 1);
    if (columns.flank) q.side_hint = table.flank(*columns.flank);
    q.gear = columns.gear ? table.integer(*columns.gear, 0) : 0;
    q.order = table.order(out.points.size());
    q.line = table.line();
    q.column = table.field(*columns.measured_x).column;
    out.points.push_back(q);
  }
  if (out.points.empty()) throw table.no_rows();
  return out;
}

Readings read_point_table(const std::string& path, const PointTableColumns& columns,
                          double stylus_radius_mm) {
  return parse_point_table(read_input_file(path, "point table", kMaxReadingsBytes), path, columns,
                           stylus_radius_mm);
}

UnlabelledPoints read_unlabelled_points(const std::string& path, const PointTableColumns& columns,
                                        double stylus_radius_mm) {
  return parse_unlabelled_points(read_input_file(path, "point table", kMaxReadingsBytes), path,
                                 columns, stylus_radius_mm);
}

}  // namespace gearmc
