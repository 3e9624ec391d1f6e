// Tolerance systems for spur gears: the symbols of each standard's tolerance kinds, and the
// resolution of a scenario's tolerance spec for one gear — the standard's values (GOST 1643-81's
// table in gost_1643_81.cpp, ISO 1328-1:2013's formulas in iso_1328_1.cpp) with the scenario's
// explicit values (overrides) on top; an overridden kind is never looked up.
//
// Convention for the tooth thickness norms (GOST 1643-81; ISO kinds use the same storage):
// E_Hs (kThicknessUpper) is stored as the positive magnitude GOST tabulates (P1: 110 µm), T_H
// (kThicknessTolerance) as the positive shift tolerance (P1: 100 µm). The additional rack shift
// of an external gear, which thins the tooth, lies in [-(E_Hs + T_H), -E_Hs]; the tooth
// thickness change is 2·shift·tan(alpha). Neither is looked up from a table (they depend on the
// backlash class and the centre distance, which are not modelled): they exist only when the
// scenario gives them.
#include "gears/tolerances.h"

#include <cmath>
#include <sstream>
#include <string_view>
#include <vector>

#include "gears/involute_gear.h"
#include "gears/tolerance_standards.h"

namespace gearmc {
namespace {

struct KindSymbols {
  ToleranceKind kind;
  const char* gost;  // nullptr: GOST 1643-81 has no such norm
  const char* iso;   // nullptr: ISO 1328-1:2013 has no such tolerance
};

// In enum order (all_tolerance_kinds() is built from it).
constexpr KindSymbols kSymbolTable[] = {
    {ToleranceKind::kRunout, "F_r", "F_r"},
    {ToleranceKind::kCumulativePitch, "F_p", "F_p"},
    {ToleranceKind::kSinglePitch, "f_pt", "f_p"},
    {ToleranceKind::kBasePitch, "f_pb", nullptr},
    {ToleranceKind::kProfileTotal, "f_f", "F_alpha"},
    {ToleranceKind::kProfileSlope, nullptr, "f_H_alpha"},
    {ToleranceKind::kProfileForm, nullptr, "f_f_alpha"},
    {ToleranceKind::kHelixTotal, "F_beta", "F_beta"},
    {ToleranceKind::kHelixSlope, nullptr, "f_H_beta"},
    {ToleranceKind::kHelixForm, nullptr, "f_f_beta"},
    {ToleranceKind::kThicknessUpper, "E_Hs", "E_Hs"},
    {ToleranceKind::kThicknessTolerance, "T_H", "T_H"},
};

const char* symbol_or_null(ToleranceKind kind, ToleranceStandard standard) {
  for (const KindSymbols& row : kSymbolTable) {
    if (row.kind == kind) {
      return standard == ToleranceStandard::kGost1643_81 ? row.gost : row.iso;
    }
  }
  return nullptr;
}

}  // namespace

namespace tolerance_detail {

// A name for messages: the symbol in `standard`, else in the other standard.
std::string kind_label(ToleranceKind kind, ToleranceStandard standard) {
  if (const char* s = symbol_or_null(kind, standard)) return s;
  const ToleranceStandard other = standard == ToleranceStandard::kGost1643_81
                                      ? ToleranceStandard::kIso1328_1_2013
                                      : ToleranceStandard::kGost1643_81;
  if (const char* s = symbol_or_null(kind, other)) return s;
  return "tolerance kind #" + std::to_string(static_cast<int>(kind));
}

}  // namespace tolerance_detail

using tolerance_detail::kind_label;

// A grade / class number written as 1-2 decimal digits without a leading zero, within
// [lowest, highest]; nullopt otherwise.
std::optional<int> parse_grade_number(std::string_view text, int lowest, int highest) {
  if (text.empty() || text.size() > 2 || text.front() == '0') return std::nullopt;
  int value = 0;
  for (char c : text) {
    if (c < '0' || c > '9') return std::nullopt;
    value = value * 10 + (c - '0');
  }
  if (value < lowest || value > highest) return std::nullopt;
  return value;
}

const std::vector<ToleranceKind>& all_tolerance_kinds() {
  static const std::vector<ToleranceKind> kinds = [] {
    std::vector<ToleranceKind> all;
    for (const KindSymbols& row : kSymbolTable) all.push_back(row.kind);
    return all;
  }();
  return kinds;
}

std::optional<std::string> tolerance_symbol(ToleranceKind kind, ToleranceStandard standard) {
  if (const char* s = symbol_or_null(kind, standard)) return std::string(s);
  return std::nullopt;
}

std::optional<ToleranceKind> tolerance_kind_from_symbol(const std::string& symbol,
                                                        ToleranceStandard standard) {
  // Case-sensitive: ISO's F_p (cumulative) and f_p (single pitch) differ only in case.
  for (const KindSymbols& row : kSymbolTable) {
    const char* s = standard == ToleranceStandard::kGost1643_81 ? row.gost : row.iso;
    if (s != nullptr && symbol == s) return row.kind;
  }
  return std::nullopt;
}

std::string standard_name(ToleranceStandard standard) {
  return standard == ToleranceStandard::kGost1643_81 ? "gost_1643_81" : "iso_1328_1_2013";
}

std::optional<double> ToleranceSet::get_um(ToleranceKind kind) const {
  const auto it = values.find(kind);
  if (it == values.end()) return std::nullopt;
  return it->second.value_um;
}

ToleranceSet resolve_tolerances(const ToleranceSpec& spec, const InvoluteGear& gear) {
  for (const auto& [kind, value] : spec.overrides_um) {
    if (!(std::isfinite(value) && value >= 0.0)) {
      std::ostringstream why;
      why << "tolerance override " << kind_label(kind, spec.standard) << " = " << value
          << " µm must be a finite magnitude >= 0 µm (E_Hs too is stored as a positive "
             "magnitude, P1: 110 µm)";
      throw ToleranceError(why.str());
    }
  }
  ToleranceSet set;
  set.standard = spec.standard;
  set.grade = spec.grade;
  if (spec.standard == ToleranceStandard::kGost1643_81) {
    tolerance_detail::resolve_gost(spec, gear, set);
  } else {
    tolerance_detail::resolve_iso(spec, gear, set);
  }
  // The user states these values, so they count as confirmed. Kinds the standard lacks are
  // accepted (the scenario parser validates the symbols).
  for (const auto& [kind, value] : spec.overrides_um) {
    set.values[kind] = Tolerance{value, "scenario override", true};
  }
  return set;
}

}  // namespace gearmc
