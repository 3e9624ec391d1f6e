// Readings from a CMM's DMIS output (see dmis_results.h).
#include "engine/readings/dmis_results.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <map>
#include <optional>
#include <string_view>
#include <vector>

#include "core/input_error.h"
#include "core/input_file.h"
#include "core/number_text.h"
#include "engine/schema/parameter_ranges.h"

namespace gearmc {
namespace {

// Label prefix of the set-up features of gearmc's program (kDmisSetupPrefix in
// engine/plan/dmis_plan.h, a layer this one does not use).
constexpr char kSetupLabelPrefix[] = "SETUP_";

std::string upper(std::string s) {
  for (char& c : s) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  return s;
}

struct Statement {
  std::string text;  // continuation lines joined, comment removed
  int line = 0;      // where it starts
};

// The file's statements: `$$` comments removed, lines ending in `$` joined to the next. A
// statement longer than kMaxDmisStatementBytes is an InputError at its first line (a binary file,
// or not DMIS).
std::vector<Statement> statements(const std::string& text, const std::string& source) {
  std::vector<Statement> out;
  std::string current;
  int start = 0, line_no = 0;
  std::size_t at = 0;
  while (at <= text.size()) {
    std::size_t end = text.find_first_of("\r\n", at);
    if (end == std::string::npos) end = text.size();
    std::string line = text.substr(at, end - at);
    ++line_no;
    at = end + 1;
    if (end < text.size() && text[end] == '\r' && end + 1 < text.size() && text[end + 1] == '\n') {
      ++at;
    }
    if (const std::size_t comment = line.find("$$"); comment != std::string::npos) {
      line.erase(comment);
    }
    while (!line.empty() && std::isspace(static_cast<unsigned char>(line.back()))) line.pop_back();
    if (current.empty()) start = line_no;
    if (current.size() + line.size() > kMaxDmisStatementBytes) {
      throw InputError({source, start, 1},
                       "a DMIS statement of at most " + std::to_string(kMaxDmisStatementBytes) +
                           " bytes, but the statement starting here is longer (is it a DMIS "
                           "file?)");
    }
    if (!line.empty() && line.back() == '$') {
      line.pop_back();
      current += line;
      continue;
    }
    current += line;
    if (current.find_first_not_of(" \t") != std::string::npos) out.push_back({current, start});
    current.clear();
    if (end == text.size()) break;
  }
  if (!current.empty()) out.push_back({current, start});
  return out;
}

// F(label)=FEAT/POINT,CART,<values> or FA(label)=… (keywords in any case, blanks anywhere
// between the tokens): its kind, its label (blanks trimmed) and where <values> starts. Scanned
// by hand in one pass (the standard library's regex engine recurses once per character and
// overflowed the stack on long statements).
struct FeatureStatement {
  bool is_actual = false;
  std::string label;
  std::size_t label_at = 0;  // where the label starts
  std::size_t values = 0;
};

std::optional<FeatureStatement> point_feature(const std::string& s) {
  std::size_t i = 0;
  const auto blanks = [&] {
    while (i < s.size() && std::isspace(static_cast<unsigned char>(s[i]))) ++i;
  };
  const auto token = [&](std::string_view word) {  // case-insensitive
    if (s.size() - i < word.size()) return false;
    for (std::size_t k = 0; k < word.size(); ++k) {
      if (std::toupper(static_cast<unsigned char>(s[i + k])) != word[k]) return false;
    }
    i += word.size();
    return true;
  };
  FeatureStatement f;
  blanks();
  if (!token("F")) return std::nullopt;
  f.is_actual = token("A");
  blanks();
  if (!token("(")) return std::nullopt;
  const std::size_t close = s.find(')', i);
  if (close == std::string::npos) return std::nullopt;
  std::size_t b = i, e = close;
  while (b < e && std::isspace(static_cast<unsigned char>(s[b]))) ++b;
  while (e > b && std::isspace(static_cast<unsigned char>(s[e - 1]))) --e;
  f.label = s.substr(b, e - b);
  f.label_at = b;
  i = close + 1;
  for (std::string_view word : {"=", "FEAT", "/", "POINT", ",", "CART", ","}) {
    blanks();
    if (!token(word)) return std::nullopt;
  }
  f.values = i;
  return f;
}

// The place T<tooth><L|R>_I<i>_J<j> of a label of gearmc's plan (tooth 1–4 digits, i and j 1–3
// digits), or nothing.
std::optional<GridPosition> plan_label(const std::string& label) {
  std::size_t i = 0;
  const auto digits = [&](std::size_t most, int& value) {
    const std::size_t first = i;
    value = 0;
    while (i < label.size() && i - first < most && label[i] >= '0' && label[i] <= '9') {
      value = 10 * value + (label[i++] - '0');
    }
    return i > first && (i == label.size() || label[i] < '0' || label[i] > '9');
  };
  GridPosition at;
  if (label.empty() || label[i++] != 'T' || !digits(4, at.tooth) || i >= label.size()) {
    return std::nullopt;
  }
  if (label[i] != 'L' && label[i] != 'R') return std::nullopt;
  at.side = label[i++] == 'R' ? FlankSide::kRight : FlankSide::kLeft;
  if (label.compare(i, 2, "_I") != 0) return std::nullopt;
  i += 2;
  if (!digits(3, at.i) || label.compare(i, 2, "_J") != 0) return std::nullopt;
  i += 2;
  if (!digits(3, at.j) || i != label.size()) return std::nullopt;
  return at;
}

struct PointFeature {
  Eigen::Vector3d point, vector;  // mm (converted from the file's UNITS), unit vector
  int line = 0;
  int label_column = 0, values_column = 0;
};

// The length unit of a UNITS/<length>,<angle> statement, in mm, or nothing when `s` is another
// statement. DMIS 5.3 (ANSI/DMIS 105.2) §6.2: MM, CM, METER, INCH, FEET; any case.
std::optional<double> units_statement(const std::string& s, const InputLocation& where) {
  std::size_t i = s.find_first_not_of(" \t");
  if (i == std::string::npos || upper(s.substr(i, 5)) != "UNITS") return std::nullopt;
  i = s.find_first_not_of(" \t", i + 5);
  if (i == std::string::npos || s[i] != '/') return std::nullopt;
  const std::size_t end = s.find(',', i + 1);
  std::string unit = s.substr(i + 1, end == std::string::npos ? std::string::npos : end - i - 1);
  const std::size_t b = unit.find_first_not_of(" \t"), e = unit.find_last_not_of(" \t");
  unit = b == std::string::npos ? "" : upper(unit.substr(b, e - b + 1));
  if (unit == "MM") return 1.0;
  if (unit == "CM") return 10.0;
  if (unit == "METER") return 1000.0;
  if (unit == "INCH") return 25.4;
  if (unit == "FEET") return 304.8;
  throw InputError({where.file, where.line, where.column + static_cast<int>(i) + 2}, "UNITS", unit,
                   "a DMIS length unit: MM, CM, METER, INCH or FEET");
}

// Every F(label)=FEAT/POINT and FA(label)=FEAT/POINT statement of a DMIS file, in file order,
// lengths converted to mm by the UNITS in force, vectors normalised (bad statements: InputError).
struct LabelledFeature {
  bool is_actual;
  std::string label;
  PointFeature feature;
};
std::vector<LabelledFeature> point_features(const std::string& text, const std::string& source) {
  std::vector<LabelledFeature> out;
  const RangeTable& ranges = readings_ranges();
  double mm_per_unit = 1.0;  // DMIS's default unit is MM until a UNITS statement says otherwise
  std::string unit_name = "mm";
  for (const Statement& st : statements(text, source)) {
    if (const auto unit = units_statement(st.text, {source, st.line, 0})) {
      mm_per_unit = *unit;
      unit_name = *unit == 1.0     ? "mm"
                  : *unit == 10.0  ? "cm"
                  : *unit == 25.4  ? "inch"
                  : *unit == 304.8 ? "feet"
                                   : "m";
      continue;
    }
    const std::optional<FeatureStatement> m = point_feature(st.text);
    if (!m) continue;
    const bool is_actual = m->is_actual;
    const std::string label = m->label;
    const int values_column = static_cast<int>(m->values) + 1;
    std::vector<double> v;
    std::string field;
    std::size_t pos = 0;
    const std::string list = st.text.substr(m->values);
    while (pos <= list.size()) {
      std::size_t comma = list.find(',', pos);
      if (comma == std::string::npos) comma = list.size();
      field = list.substr(pos, comma - pos);
      const std::size_t b = field.find_first_not_of(" \t"), e = field.find_last_not_of(" \t");
      field = b == std::string::npos ? "" : field.substr(b, e - b + 1);
      std::size_t used = 0;
      double x = std::nan("");
      try {
        x = std::stod(field, &used);
      } catch (const std::exception&) {
        used = 0;
      }
      const InputLocation at{source, st.line, values_column + static_cast<int>(pos)};
      if (used != field.size() || field.empty() || !std::isfinite(x)) {
        throw InputError(at, "FEAT/POINT of " + label, field,
                         "a finite number (x,y,z in " + unit_name + ", then i,j,k)");
      }
      if (v.size() < 3) {  // a coordinate: in mm, within a CMM's volume
        x *= mm_per_unit;
        ParameterRange named = ranges.at("coordinate_mm");
        named.key = std::string("FEAT/POINT of ") + label + " " + "xyz"[v.size()];
        check_ranged(x, named, at, field + (unit_name == "mm" ? "" : " " + unit_name), nullptr);
      }
      v.push_back(x);
      pos = comma + 1;
      if (comma == list.size()) break;
    }
    if (v.size() != 6) {
      throw InputError({source, st.line, values_column}, "FEAT/POINT of " + label,
                       std::to_string(v.size()) + " numbers", "6 numbers: x,y,z,i,j,k");
    }
    PointFeature f{{v[0], v[1], v[2]},
                   {v[3], v[4], v[5]},
                   st.line,
                   static_cast<int>(m->label_at) + 1,
                   values_column};
    if (!(f.vector.norm() > 0.5 && f.vector.norm() < 1.5)) {
      throw InputError({source, st.line, values_column}, "FEAT/POINT of " + label,
                       "|i,j,k| = " + std::to_string(f.vector.norm()), "a unit vector");
    }
    f.vector.normalize();
    out.push_back({is_actual, label, f});
  }
  return out;
}

}  // namespace

bool is_dmis_file(const std::string& path) {
  const std::size_t dot = path.rfind('.');
  if (dot == std::string::npos) return false;
  const std::string ext = upper(path.substr(dot + 1));
  return ext == "DMO" || ext == "DMI" || ext == "DMS" || ext == "DMIS";
}

Readings parse_dmis_results(const std::string& text, const std::string& source,
                            double stylus_radius_mm) {
  std::map<std::string, PointFeature> nominal;
  std::vector<std::pair<std::string, PointFeature>> actual;
  for (LabelledFeature& f : point_features(text, source)) {
    if (f.is_actual) {
      actual.emplace_back(f.label, f.feature);
    } else {
      nominal[f.label] = f.feature;
    }
  }
  const RangeTable& ranges = readings_ranges();
  Readings readings;
  readings.stylus_radius_mm = stylus_radius_mm;
  std::map<std::string, int> seen;
  for (const auto& [label, f] : actual) {
    // The operator's set-up features of the program (SETUP_AXIS, SETUP_T1L, …; the program's
    // OUTPUT statements do not ask for them, but a CMM that writes every actual writes them
    // too) are not results of the plan.
    if (label.rfind(kSetupLabelPrefix, 0) == 0) continue;
    const std::optional<GridPosition> at = plan_label(label);
    const InputLocation label_at{source, f.line, f.label_column};
    if (!at) {
      throw InputError(label_at, "FA label", label,
                       "a label of gearmc's plan, T<tooth><L|R>_I<i>_J<j> (gearmc export-plan)");
    }
    const auto found = nominal.find(label);
    if (found == nominal.end()) {
      throw InputError(label_at, "FA(" + label + ")", "no nominal",
                       "the nominal feature F(" + label + ")=FEAT/POINT,… in the file");
    }
    if (const auto [it, inserted] = seen.emplace(label, f.line); !inserted) {
      throw InputError(label_at, "FA(" + label + ")",
                       "measured again (first at line " + std::to_string(it->second) + ")",
                       "one result per planned point");
    }
    ReadingRow row;
    row.key() = point_key(0, *at);
    row.order = static_cast<int>(readings.rows.size());
    row.p = found->second.point;
    row.n = found->second.vector;
    row.c = f.point + stylus_radius_mm * row.n;
    row.line = f.line;
    row.key_column = f.label_column;
    row.measured_column = f.values_column;
    row.nominal_line = found->second.line;
    row.nominal_column = found->second.values_column;
    // The reading itself, as the CSV reader checks it: far off means another unit or gear.
    const double e_um = measured_deviation_um(row, stylus_radius_mm);
    check_ranged(e_um, ranges.at("reading_um"), {source, f.line, f.values_column},
                 "(FA - F)·n = " + shortest_text(e_um) + " µm", nullptr);
    readings.rows.push_back(row);
  }
  if (readings.rows.empty()) {
    throw InputError({source, 0, 0}, source +
                                         ": no measured points (FA(…)=FEAT/POINT records) "
                                         "in this DMIS file");
  }
  return readings;
}

std::vector<DmisPlanFeature> parse_dmis_plan(const std::string& text, const std::string& source) {
  std::vector<DmisPlanFeature> out;
  for (const LabelledFeature& f : point_features(text, source)) {
    if (f.is_actual || f.label.rfind(kSetupLabelPrefix, 0) == 0) continue;
    out.push_back({f.label, f.feature.point, f.feature.vector, f.feature.line,
                   f.feature.label_column, f.feature.values_column});
  }
  if (out.empty()) {
    throw InputError({source, 1, 1}, source +
                                         ": no planned points (F(…)=FEAT/POINT,CART,x,y,z,"
                                         "i,j,k statements) in this DMIS program");
  }
  return out;
}

std::vector<DmisPlanFeature> read_dmis_plan(const std::string& path) {
  return parse_dmis_plan(read_input_file(path, "DMIS program", kMaxReadingsBytes), path);
}

Readings read_dmis_results(const std::string& path, double stylus_radius_mm) {
  return parse_dmis_results(read_input_file(path, "DMIS results file", kMaxReadingsBytes), path,
                            stylus_radius_mm);
}

}  // namespace gearmc
