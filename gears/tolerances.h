// Tolerance systems for spur gears: ISO 1328-1:2013 (closed-form class formulas) and
// GOST 1643-81 (a data table for the size ranges around P1's gear). A scenario names a
// standard and a grade/class and may override any single tolerance; the result is a
// ToleranceSet whose every value (µm) carries its source and whether it is confirmed.
#pragma once

#include <map>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace gearmc {

class InvoluteGear;

enum class ToleranceStandard { kGost1643_81, kIso1328_1_2013 };

// The deviation kinds a tolerance can bound. Signed (±) ones are marked.
enum class ToleranceKind {
  kRunout,              // F_r
  kCumulativePitch,     // F_p
  kSinglePitch,         // ±f_pt (ISO f_pT)
  kBasePitch,           // ±f_pb (GOST; ISO 1328-1:2013 has none)
  kProfileTotal,        // GOST f_f, ISO F_alphaT
  kProfileSlope,        // ±f_Halpha (ISO)
  kProfileForm,         // f_falpha (ISO)
  kHelixTotal,          // F_beta
  kHelixSlope,          // ±f_Hbeta (ISO)
  kHelixForm,           // f_fbeta (ISO)
  kThicknessUpper,      // E_Hs: least additional rack shift, µm, positive magnitude (GOST)
  kThicknessTolerance,  // T_H: tolerance of the rack shift, µm
};

// All kinds, in the order they are printed.
const std::vector<ToleranceKind>& all_tolerance_kinds();

// The symbol of `kind` in `standard` as scenario files and JSON output spell it
// (GOST: F_r, F_p, f_pt, f_pb, f_f, F_beta, E_Hs, T_H; ISO: F_r, F_p, f_p, F_alpha,
// f_H_alpha, f_f_alpha, F_beta, f_H_beta, f_f_beta, E_Hs, T_H); nullopt when the standard
// does not have the kind.
std::optional<std::string> tolerance_symbol(ToleranceKind kind, ToleranceStandard standard);
// Inverse of tolerance_symbol.
std::optional<ToleranceKind> tolerance_kind_from_symbol(const std::string& symbol,
                                                        ToleranceStandard standard);
std::string standard_name(ToleranceStandard standard);  // "gost_1643_81" / "iso_1328_1_2013"
// A grade / class number written as 1-2 decimal digits without a leading zero, within
// [lowest, highest]; nullopt otherwise (GOST 1643-81 grades 1..12, ISO 1328-1 classes 1..11).
std::optional<int> parse_grade_number(std::string_view text, int lowest, int highest);

struct Tolerance {
  double value_um = 0.0;
  std::string source;      // e.g. "ISO 1328-1:2013 eq. (…), class 5", "P1 Table 1", "override"
  bool confirmed = false;  // false: recalled or derived, not checked against the standard
};

// What a scenario says about tolerances.
struct ToleranceSpec {
  ToleranceStandard standard = ToleranceStandard::kGost1643_81;
  // GOST: "K-S-C" (kinematic-smoothness-contact grades, e.g. "6-5-5") or one grade "7";
  // ISO: the flank tolerance class "1" … "11".
  std::string grade = "6-5-5";
  std::map<ToleranceKind, double> overrides_um;  // explicit values, source "scenario override"
};

// Thrown when a standard cannot give a value (gear outside its scope, grade not tabulated).
class ToleranceError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// The resolved tolerances of one gear. Kinds the standard does not define and the scenario
// does not override are absent.
class ToleranceSet {
 public:
  ToleranceStandard standard = ToleranceStandard::kGost1643_81;
  std::string grade;
  std::map<ToleranceKind, Tolerance> values;

  std::optional<double> get_um(ToleranceKind kind) const;
};

// ISO 1328-1:2013 class-A flank tolerances (docs/reference-values.md): class-5 formulas scaled by
// sqrt(2)^(A-5), rounded (> 10 µm to 1 µm, 5–10 µm to 0.5 µm, < 5 µm to 0.1 µm); totals from
// unrounded components. Scope: 5 <= z <= 1000, 5 <= d <= 15000 mm, 0.5 <= m_n <= 70 mm,
// 4 <= b <= 1200 mm; outside it throws ToleranceError (no extrapolation). d, m_n, b in mm.
struct Iso1328Tolerances {
  double single_pitch, cumulative_pitch, runout, profile_slope, profile_form, profile_total,
      helix_slope, helix_form, helix_total;  // µm, rounded
};
Iso1328Tolerances iso1328_tolerances(int tolerance_class, double d_mm, double m_n_mm, double b_mm,
                                     int z);
double iso1328_round(double value_um);
// The ISO 1328-1:2013 flank tolerance class a measured value meets, as gear-measuring software
// prints it beside each value: the finest class A in 1 … 11 whose (rounded) tolerance of `kind`
// is at least |value_um|; nullopt when even class 11's is smaller, or `kind` has no ISO formula
// (f_pb, size). Throws ToleranceError outside the standard's scope, as iso1328_tolerances.
std::optional<int> iso1328_class_met(ToleranceKind kind, double value_um, double d_mm,
                                     double m_n_mm, double b_mm, int z);

// Resolves a spec for a gear: looks up the standard, then applies the overrides.
// Throws ToleranceError when the standard has no value where one was asked for.
ToleranceSet resolve_tolerances(const ToleranceSpec& spec, const InvoluteGear& gear);

}  // namespace gearmc
