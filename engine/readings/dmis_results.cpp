// Readings from a CMM's DMIS output (see dmis_results.h).
#include "engine/readings/dmis_results.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <map>
#include <optional>
#include <regex>
#include <vector>

#include "core/input_error.h"
#include "core/input_file.h"

namespace gearmc {
namespace {

std::string upper(std::string s) {
  for (char& c : s) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  return s;
}

struct Statement {
  std::string text;  // continuation lines joined, comment removed
  int line = 0;      // where it starts
};

// The file's statements: `$$` comments removed, lines ending in `$` joined to the next.
std::vector<Statement> statements(const std::string& text) {
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

struct PointFeature {
  Eigen::Vector3d point, vector;
  int line = 0;
};

}  // namespace

bool is_dmis_file(const std::string& path) {
  const std::size_t dot = path.rfind('.');
  if (dot == std::string::npos) return false;
  const std::string ext = upper(path.substr(dot + 1));
  return ext == "DMO" || ext == "DMI" || ext == "DMS" || ext == "DMIS";
}

Readings parse_dmis_results(const std::string& text, const std::string& source,
                            double stylus_radius_mm) {
  // F(label)=FEAT/POINT,CART,x,y,z,i,j,k and FA(label)=…, with free spaces.
  static const std::regex feature(
      R"(^\s*(FA|F)\s*\(\s*([^)]*?)\s*\)\s*=\s*FEAT\s*/\s*POINT\s*,\s*CART\s*,(.*)$)",
      std::regex::icase);
  static const std::regex label_form(R"(^T(\d{1,4})([LR])_I(\d{1,3})_J(\d{1,3})$)");
  std::map<std::string, PointFeature> nominal;
  std::vector<std::pair<std::string, PointFeature>> actual;
  for (const Statement& st : statements(text)) {
    std::smatch m;
    if (!std::regex_match(st.text, m, feature)) continue;
    const bool is_actual = upper(m[1].str()) == "FA";
    const std::string label = m[2].str();
    const int values_column = static_cast<int>(m.position(3)) + 1;
    std::vector<double> v;
    std::string field;
    std::size_t pos = 0;
    const std::string list = m[3].str();
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
      if (used != field.size() || field.empty() || !std::isfinite(x)) {
        throw InputError({source, st.line, values_column + static_cast<int>(pos)},
                         "FEAT/POINT of " + label, field, "a finite number (x,y,z,i,j,k in mm)");
      }
      v.push_back(x);
      pos = comma + 1;
      if (comma == list.size()) break;
    }
    if (v.size() != 6) {
      throw InputError({source, st.line, values_column}, "FEAT/POINT of " + label,
                       std::to_string(v.size()) + " numbers", "6 numbers: x,y,z,i,j,k");
    }
    PointFeature f{{v[0], v[1], v[2]}, {v[3], v[4], v[5]}, st.line};
    if (!(f.vector.norm() > 0.5 && f.vector.norm() < 1.5)) {
      throw InputError({source, st.line, values_column}, "FEAT/POINT of " + label,
                       "|i,j,k| = " + std::to_string(f.vector.norm()), "a unit vector");
    }
    f.vector.normalize();
    if (is_actual) {
      actual.emplace_back(label, f);
    } else {
      nominal[label] = f;
    }
  }
  Readings readings;
  readings.stylus_radius_mm = stylus_radius_mm;
  std::map<std::string, int> seen;
  for (const auto& [label, f] : actual) {
    std::smatch m;
    if (!std::regex_match(label, m, label_form)) {
      throw InputError({source, f.line, 1}, "FA label", label,
                       "a label of gearmc's plan, T<tooth><L|R>_I<i>_J<j> (gearmc export-plan)");
    }
    const auto found = nominal.find(label);
    if (found == nominal.end()) {
      throw InputError({source, f.line, 1}, "FA(" + label + ")", "no nominal",
                       "the nominal feature F(" + label + ")=FEAT/POINT,… in the file");
    }
    if (const auto [it, inserted] = seen.emplace(label, f.line); !inserted) {
      throw InputError({source, f.line, 1}, "FA(" + label + ")",
                       "measured again (first at line " + std::to_string(it->second) + ")",
                       "one result per planned point");
    }
    ReadingRow row;
    row.gear = 0;
    row.tooth = std::stoi(m[1].str());
    row.side = m[2].str() == "R" ? FlankSide::kRight : FlankSide::kLeft;
    row.i = std::stoi(m[3].str());
    row.j = std::stoi(m[4].str());
    row.order = static_cast<int>(readings.rows.size());
    row.p = found->second.point;
    row.n = found->second.vector;
    row.c = f.point + stylus_radius_mm * row.n;
    row.line = f.line;
    readings.rows.push_back(row);
  }
  if (readings.rows.empty()) {
    throw InputError({source, 0, 0}, source +
                                         ": no measured points (FA(…)=FEAT/POINT records) "
                                         "in this DMIS file");
  }
  return readings;
}

Readings read_dmis_results(const std::string& path, double stylus_radius_mm) {
  return parse_dmis_results(read_input_file(path, "DMIS results file", kMaxReadingsBytes), path,
                            stylus_radius_mm);
}

}  // namespace gearmc
