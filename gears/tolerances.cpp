// Tolerance systems for spur gears. ISO 1328-1:2013 tolerances are computed from the standard's
// closed-form class-5 formulas, scaled to class A by sqrt(2)^(A-5) and rounded as the standard
// prescribes (docs/reference-values.md, "ISO 1328-1:2013 flank tolerances [verified]"). GOST
// 1643-81 has no formulas, only tables; this file holds the part of those tables around P1's gear
// (reference diameter over 125 up to 400 mm, module over 3.5 up to 6.3 mm, face width over 40 up to
// 100 mm, grades 4-8) as one constant table whose every row says where its number comes from and
// whether it is confirmed (P1 Table 1) or only recalled / derived (docs/reference-values.md). A
// scenario's explicit values (overrides) always win, and a kind that is overridden is never looked
// up, so a gear outside the table works when the scenario gives every norm itself.
//
// Convention for the tooth thickness norms (GOST 1643-81; ISO kinds use the same storage):
// E_Hs (kThicknessUpper) is stored as the positive magnitude GOST tabulates (P1: 110 µm), T_H
// (kThicknessTolerance) as the positive shift tolerance (P1: 100 µm). The additional rack shift
// of an external gear, which thins the tooth, lies in [-(E_Hs + T_H), -E_Hs]; the tooth
// thickness change is 2·shift·tan(alpha). Neither is looked up from a table (they depend on the
// backlash class and the centre distance, which are not modelled): they exist only when the
// scenario gives them.
#include "gears/tolerances.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <string_view>
#include <vector>

#include "gears/involute_gear.h"

namespace gearmc {
namespace {

// ---------------------------------------------------------------------------------------------
// Symbols.

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

// A name for messages: the symbol in `standard`, else in the other standard.
std::string kind_label(ToleranceKind kind, ToleranceStandard standard) {
  if (const char* s = symbol_or_null(kind, standard)) return s;
  const ToleranceStandard other = standard == ToleranceStandard::kGost1643_81
                                      ? ToleranceStandard::kIso1328_1_2013
                                      : ToleranceStandard::kGost1643_81;
  if (const char* s = symbol_or_null(kind, other)) return s;
  return "tolerance kind #" + std::to_string(static_cast<int>(kind));
}

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

// ---------------------------------------------------------------------------------------------
// ISO 1328-1:2013.

constexpr int kIsoLowestClass = 1;
constexpr int kIsoHighestClass = 11;

// Throws unless lo <= value <= hi (NaN is outside too). ISO 1328-1:2013 forbids extrapolation.
void check_iso_scope(const char* quantity, double value, double lo, double hi, const char* unit) {
  if (lo <= value && value <= hi) return;
  std::ostringstream why;
  why << "ISO 1328-1:2013 is not applicable: " << quantity << " = " << value << unit
      << " is outside its scope " << lo << unit << " ... " << hi << unit
      << " (the standard's formulas must not be extrapolated)";
  throw ToleranceError(why.str());
}

// The class-5 formula of each ISO kind, as written into the value's source.
const char* iso_formula(ToleranceKind kind) {
  switch (kind) {
    case ToleranceKind::kSinglePitch:
      return "f_pT = 0.001d + 0.4m_n + 5";
    case ToleranceKind::kCumulativePitch:
      return "F_pT = 0.002d + 0.55sqrt(d) + 0.7m_n + 12";
    case ToleranceKind::kRunout:
      return "F_rT = 0.9 F_pT (from the unrounded F_pT; stated in ISO 1328-2 / later editions, "
             "docs/reference-values.md)";
    case ToleranceKind::kProfileSlope:
      return "f_HalphaT = 0.4m_n + 0.001d + 4";
    case ToleranceKind::kProfileForm:
      return "f_falphaT = 0.55m_n + 5";
    case ToleranceKind::kProfileTotal:
      return "F_alphaT = sqrt(f_HalphaT^2 + f_falphaT^2) (from the unrounded components)";
    case ToleranceKind::kHelixSlope:
      return "f_HbetaT = 0.05sqrt(d) + 0.35sqrt(b) + 4";
    case ToleranceKind::kHelixForm:
      return "f_fbetaT = 0.07sqrt(d) + 0.45sqrt(b) + 4";
    case ToleranceKind::kHelixTotal:
      return "F_betaT = sqrt(f_HbetaT^2 + f_fbetaT^2) (from the unrounded components)";
    default:
      return nullptr;  // not computed by ISO 1328-1:2013 here
  }
}

// The kinds iso1328_tolerances() computes, with their field.
struct IsoField {
  ToleranceKind kind;
  double Iso1328Tolerances::*value;
};
constexpr IsoField kIsoFields[] = {
    {ToleranceKind::kRunout, &Iso1328Tolerances::runout},
    {ToleranceKind::kCumulativePitch, &Iso1328Tolerances::cumulative_pitch},
    {ToleranceKind::kSinglePitch, &Iso1328Tolerances::single_pitch},
    {ToleranceKind::kProfileTotal, &Iso1328Tolerances::profile_total},
    {ToleranceKind::kProfileSlope, &Iso1328Tolerances::profile_slope},
    {ToleranceKind::kProfileForm, &Iso1328Tolerances::profile_form},
    {ToleranceKind::kHelixTotal, &Iso1328Tolerances::helix_total},
    {ToleranceKind::kHelixSlope, &Iso1328Tolerances::helix_slope},
    {ToleranceKind::kHelixForm, &Iso1328Tolerances::helix_form},
};

std::string iso_source(ToleranceKind kind, int tolerance_class) {
  std::ostringstream s;
  s << "ISO 1328-1:2013 class " << tolerance_class << " formula " << iso_formula(kind);
  if (tolerance_class != 5) {
    s << ", class-5 value times sqrt(2)^(" << tolerance_class << "-5)";
  }
  s << ", rounded";
  return s.str();
}

// ---------------------------------------------------------------------------------------------
// GOST 1643-81 table.

constexpr double kUnbounded = std::numeric_limits<double>::infinity();

// A GOST size range "over `over` up to and including `up_to`" (GOST's "св. … до …"); a norm that
// does not depend on the quantity uses (0, infinity).
struct SizeRange {
  double over_mm;
  double up_to_mm;
  bool contains(double value) const { return over_mm < value && value <= up_to_mm; }
  bool bounded() const { return over_mm > 0.0 || up_to_mm < kUnbounded; }
};

constexpr SizeRange kAnySize = {0.0, kUnbounded};
constexpr SizeRange kDiameter125To400 = {125.0, 400.0};  // reference diameter d, mm
constexpr SizeRange kModule3p5To6p3 = {3.5, 6.3};        // module m, mm
constexpr SizeRange kWidth40To100 = {40.0, 100.0};       // face width b, mm (F_beta only)

struct GostNormRow {
  ToleranceKind kind;
  int grade;
  SizeRange diameter, module, face_width;
  double value_um;  // the norm's magnitude; ±f_pt and ±f_pb are the limit deviations ±value
  const char* source;
  bool confirmed;
};

constexpr const char* kRecalled =
    "recalled (docs/reference-values.md), not checked against the standard";
constexpr const char* kP1 = "P1 Table 1";

// GOST 1643-81 norms around P1's gear (d 134.4 mm, m 5.6 mm, b 78.89 mm). Values from
// docs/reference-values.md ("GOST 1643-81 [recalled, except where P1 states it]"); P1 states f_pb
// and f_f of grade 5. Where docs/reference-values.md gives no value, the value is derived from the
// neighbouring grade with GOST's grade-to-grade ratio of about 1.4 and rounded to 1 µm
// (unconfirmed).
constexpr GostNormRow kGostTable[] = {
    // Kinematic norm: radial runout F_r (depends on d and m).
    {ToleranceKind::kRunout, 4, kDiameter125To400, kModule3p5To6p3, kAnySize, 18.0,
     "derived: grade-5 value 25 / 1.4 = 17.9, rounded to 1 µm; unconfirmed", false},
    {ToleranceKind::kRunout, 5, kDiameter125To400, kModule3p5To6p3, kAnySize, 25.0, kRecalled,
     false},
    {ToleranceKind::kRunout, 6, kDiameter125To400, kModule3p5To6p3, kAnySize, 40.0,
     "recalled (docs/reference-values.md), not checked against the standard; P1 Table 1 uses F_r = "
     "50 µm "
     "for its grade-6 gear: give F_r explicitly to follow P1",
     false},
    {ToleranceKind::kRunout, 7, kDiameter125To400, kModule3p5To6p3, kAnySize, 56.0, kRecalled,
     false},
    {ToleranceKind::kRunout, 8, kDiameter125To400, kModule3p5To6p3, kAnySize, 71.0, kRecalled,
     false},

    // Smoothness norm: single pitch limit deviations ±f_pt (d, m).
    {ToleranceKind::kSinglePitch, 4, kDiameter125To400, kModule3p5To6p3, kAnySize, 7.0,
     "derived: grade-5 value 10 / 1.4 = 7.1, rounded to 1 µm; unconfirmed", false},
    {ToleranceKind::kSinglePitch, 5, kDiameter125To400, kModule3p5To6p3, kAnySize, 10.0, kRecalled,
     false},
    {ToleranceKind::kSinglePitch, 6, kDiameter125To400, kModule3p5To6p3, kAnySize, 14.0, kRecalled,
     false},
    {ToleranceKind::kSinglePitch, 7, kDiameter125To400, kModule3p5To6p3, kAnySize, 20.0, kRecalled,
     false},
    {ToleranceKind::kSinglePitch, 8, kDiameter125To400, kModule3p5To6p3, kAnySize, 28.0, kRecalled,
     false},

    // Smoothness norm: base pitch limit deviations ±f_pb (d, m).
    {ToleranceKind::kBasePitch, 4, kDiameter125To400, kModule3p5To6p3, kAnySize, 6.0,
     "derived: grade-5 value 9 (P1 Table 1) / 1.4 = 6.4, rounded to 1 µm; unconfirmed", false},
    {ToleranceKind::kBasePitch, 5, kDiameter125To400, kModule3p5To6p3, kAnySize, 9.0, kP1, true},
    {ToleranceKind::kBasePitch, 6, kDiameter125To400, kModule3p5To6p3, kAnySize, 13.0,
     "derived: grade-5 value 9 (P1 Table 1) * 1.4 = 12.6, rounded to 1 µm; unconfirmed", false},
    {ToleranceKind::kBasePitch, 7, kDiameter125To400, kModule3p5To6p3, kAnySize, 18.0,
     "derived: grade-6 value 13 * 1.4 = 18.2, rounded to 1 µm; unconfirmed", false},
    {ToleranceKind::kBasePitch, 8, kDiameter125To400, kModule3p5To6p3, kAnySize, 25.0,
     "derived: grade-7 value 18 * 1.4 = 25.2, rounded to 1 µm; unconfirmed", false},

    // Smoothness norm: profile tolerance f_f, the total profile band (closer to ISO F_alpha than
    // to f_falpha, docs/reference-values.md) (d, m).
    {ToleranceKind::kProfileTotal, 4, kDiameter125To400, kModule3p5To6p3, kAnySize, 6.0,
     "derived: grade-5 value 8 (P1 Table 1) / 1.4 = 5.7, rounded to 1 µm; unconfirmed", false},
    {ToleranceKind::kProfileTotal, 5, kDiameter125To400, kModule3p5To6p3, kAnySize, 8.0, kP1, true},
    {ToleranceKind::kProfileTotal, 6, kDiameter125To400, kModule3p5To6p3, kAnySize, 11.0, kRecalled,
     false},
    {ToleranceKind::kProfileTotal, 7, kDiameter125To400, kModule3p5To6p3, kAnySize, 16.0, kRecalled,
     false},
    {ToleranceKind::kProfileTotal, 8, kDiameter125To400, kModule3p5To6p3, kAnySize, 22.0, kRecalled,
     false},

    // Contact norm: helix (tooth direction) tolerance F_beta (depends on the face width only).
    {ToleranceKind::kHelixTotal, 4, kAnySize, kAnySize, kWidth40To100, 7.0,
     "derived: grade-5 value 10 / 1.4 = 7.1, rounded to 1 µm; unconfirmed", false},
    {ToleranceKind::kHelixTotal, 5, kAnySize, kAnySize, kWidth40To100, 10.0, kRecalled, false},
    {ToleranceKind::kHelixTotal, 6, kAnySize, kAnySize, kWidth40To100, 12.0, kRecalled, false},
    {ToleranceKind::kHelixTotal, 7, kAnySize, kAnySize, kWidth40To100, 16.0, kRecalled, false},
    {ToleranceKind::kHelixTotal, 8, kAnySize, kAnySize, kWidth40To100, 25.0, kRecalled, false},
};

// The GOST norms the table holds. F_p (a GOST norm too), E_Hs and T_H are not tabulated here:
// they exist only when the scenario gives them.
constexpr ToleranceKind kGostTabulatedKinds[] = {
    ToleranceKind::kRunout, ToleranceKind::kSinglePitch, ToleranceKind::kBasePitch,
    ToleranceKind::kProfileTotal, ToleranceKind::kHelixTotal};

constexpr int kGostLowestGrade = 1;
constexpr int kGostHighestGrade = 12;

// GOST 1643-81 grades of the three norm groups.
struct GostGrades {
  int kinematic, smoothness, contact;
};

GostGrades parse_gost_grade(const std::string& grade) {
  std::vector<std::string_view> parts;
  std::string_view rest = grade;
  for (std::size_t dash; (dash = rest.find('-')) != std::string_view::npos;) {
    parts.push_back(rest.substr(0, dash));
    rest.remove_prefix(dash + 1);
  }
  parts.push_back(rest);
  std::vector<int> numbers;
  for (std::string_view part : parts) {
    const std::optional<int> n = parse_grade_number(part, kGostLowestGrade, kGostHighestGrade);
    if (!n) break;
    numbers.push_back(*n);
  }
  if (numbers.size() == parts.size() && numbers.size() == 1) {
    return {numbers[0], numbers[0], numbers[0]};
  }
  if (numbers.size() == parts.size() && numbers.size() == 3) {
    return {numbers[0], numbers[1], numbers[2]};
  }
  throw ToleranceError("GOST 1643-81 grade \"" + grade +
                       "\" is not of the form \"K-S-C\" (kinematic-smoothness-contact grades, "
                       "each 1 ... 12, e.g. \"6-5-5\") or a single grade 1 ... 12 such as \"7\"");
}

// Which grade of `grades` a tabulated norm uses, and the name of that group.
int gost_grade_for(ToleranceKind kind, const GostGrades& grades, const char** group) {
  switch (kind) {
    case ToleranceKind::kRunout:
    case ToleranceKind::kCumulativePitch:
      *group = "kinematic";
      return grades.kinematic;
    case ToleranceKind::kHelixTotal:
      *group = "contact";
      return grades.contact;
    default:
      *group = "smoothness";
      return grades.smoothness;
  }
}

std::string describe_range(const SizeRange& range) {
  std::ostringstream s;
  s << "over " << range.over_mm << " up to " << range.up_to_mm << " mm";
  return s.str();
}

// Looks up one norm. On success returns the row; otherwise appends to `missing` what is missing.
const GostNormRow* find_gost_row(ToleranceKind kind, int grade, const char* group, double d_mm,
                                 double m_mm, double b_mm, std::vector<std::string>& missing) {
  const std::string symbol = kind_label(kind, ToleranceStandard::kGost1643_81);
  std::vector<const GostNormRow*> of_grade;
  int lowest = kGostHighestGrade + 1, highest = kGostLowestGrade - 1;
  for (const GostNormRow& row : kGostTable) {
    if (row.kind != kind) continue;
    lowest = std::min(lowest, row.grade);
    highest = std::max(highest, row.grade);
    if (row.grade == grade) of_grade.push_back(&row);
  }
  for (const GostNormRow* row : of_grade) {
    if (row->diameter.contains(d_mm) && row->module.contains(m_mm) &&
        row->face_width.contains(b_mm)) {
      return row;
    }
  }
  std::ostringstream why;
  why << symbol << " (" << group << " grade " << grade << "): ";
  if (of_grade.empty()) {
    why << "grade " << grade << " is not tabulated (tabulated grades " << lowest << " ... "
        << highest << ")";
    missing.push_back(why.str());
    return nullptr;
  }
  // Name every quantity that lies outside all tabulated ranges of this norm and grade.
  struct Quantity {
    const char* name;
    double value;
    SizeRange GostNormRow::*range;
  };
  const Quantity quantities[] = {{"reference diameter d", d_mm, &GostNormRow::diameter},
                                 {"module m", m_mm, &GostNormRow::module},
                                 {"face width b", b_mm, &GostNormRow::face_width}};
  bool named = false;
  for (const Quantity& q : quantities) {
    bool inside = false;
    std::string ranges;
    for (const GostNormRow* row : of_grade) {
      const SizeRange& range = row->*q.range;
      inside = inside || range.contains(q.value);
      if (range.bounded()) ranges += (ranges.empty() ? "" : ", ") + describe_range(range);
    }
    if (inside) continue;
    why << (named ? "; " : "") << q.name << " = " << q.value << " mm is outside the tabulated "
        << "range " << ranges;
    named = true;
  }
  if (!named) {
    why << "no tabulated row covers d = " << d_mm << " mm, m = " << m_mm << " mm, b = " << b_mm
        << " mm together";
  }
  missing.push_back(why.str());
  return nullptr;
}

void resolve_gost(const ToleranceSpec& spec, const InvoluteGear& gear, ToleranceSet& set) {
  const GostGrades grades = parse_gost_grade(spec.grade);
  std::vector<std::string> missing;
  std::string missing_symbols;
  for (ToleranceKind kind : kGostTabulatedKinds) {
    if (spec.overrides_um.count(kind) != 0) continue;  // given by the scenario: no lookup
    const char* group = "";
    const int grade = gost_grade_for(kind, grades, &group);
    const GostNormRow* row = find_gost_row(kind, grade, group, gear.reference_diameter_mm(),
                                           gear.module_mm(), gear.face_width_mm(), missing);
    if (row != nullptr) {
      set.values[kind] = Tolerance{row->value_um, row->source, row->confirmed};
    } else {
      missing_symbols +=
          (missing_symbols.empty() ? "" : ", ") + kind_label(kind, ToleranceStandard::kGost1643_81);
    }
  }
  if (missing.empty()) return;
  std::string why = "GOST 1643-81 table has no value for grade \"" + spec.grade + "\": ";
  for (std::size_t i = 0; i < missing.size(); ++i) why += (i == 0 ? "" : "; ") + missing[i];
  why += ". The scenario can give explicit values instead (tolerance overrides_um: " +
         missing_symbols + ")";
  throw ToleranceError(why);
}

void resolve_iso(const ToleranceSpec& spec, const InvoluteGear& gear, ToleranceSet& set) {
  const std::optional<int> tolerance_class =
      parse_grade_number(spec.grade, kIsoLowestClass, kIsoHighestClass);
  if (!tolerance_class) {
    throw ToleranceError("ISO 1328-1:2013 flank tolerance class \"" + spec.grade +
                         "\" is not one of 1 ... 11");
  }
  bool needed = false;
  for (const IsoField& field : kIsoFields) {
    needed = needed || spec.overrides_um.count(field.kind) == 0;
  }
  if (!needed) return;  // every formula value is overridden: the scope does not matter
  Iso1328Tolerances computed{};
  try {
    computed = iso1328_tolerances(*tolerance_class, gear.reference_diameter_mm(), gear.module_mm(),
                                  gear.face_width_mm(), gear.teeth());
  } catch (const ToleranceError& e) {
    throw ToleranceError(
        std::string(e.what()) +
        ". The scenario can give explicit values instead (tolerance overrides_um)");
  }
  for (const IsoField& field : kIsoFields) {
    if (spec.overrides_um.count(field.kind) != 0) continue;
    set.values[field.kind] =
        Tolerance{computed.*field.value, iso_source(field.kind, *tolerance_class), true};
  }
}

}  // namespace

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

// ISO 1328-1:2013 rounding (docs/reference-values.md): values > 10 µm to 1 µm, 5 ... 10 µm to 0.5
// µm, < 5 µm to 0.1 µm. The step is chosen from the unrounded value; exactly 5 and exactly 10 fall
// in the 0.5 µm band, which leaves them unchanged, so the boundary values themselves are not
// ambiguous; what the rule decides is e.g. 10.3 -> 10 (1 µm step) but 9.8 -> 10.0 and 4.97 -> 5.0
// (0.1 µm step). Halves round away from zero (std::round); docs/reference-values.md states no tie
// rule. Negative inputs use the band of their magnitude.
double iso1328_round(double value_um) {
  const double magnitude = std::abs(value_um);
  if (magnitude > 10.0) return std::round(value_um);
  if (magnitude >= 5.0) return std::round(value_um * 2.0) / 2.0;
  return std::round(value_um * 10.0) / 10.0;
}

// ISO 1328-1:2013 (docs/reference-values.md, verified): class-5 formulas with the gear's actual d,
// m_n, b, times sqrt(2)^(A-5); totals and the runout from the unrounded components, each value
// rounded last. The helix angle limit (beta <= 45 deg) always holds for the spur gears modelled
// here.
Iso1328Tolerances iso1328_tolerances(int tolerance_class, double d_mm, double m_n_mm, double b_mm,
                                     int z) {
  if (tolerance_class < kIsoLowestClass || tolerance_class > kIsoHighestClass) {
    throw ToleranceError("ISO 1328-1:2013 flank tolerance class " +
                         std::to_string(tolerance_class) + " is outside its classes 1 ... 11");
  }
  check_iso_scope("number of teeth z", z, 5, 1000, "");
  check_iso_scope("reference diameter d", d_mm, 5.0, 15000.0, " mm");
  check_iso_scope("normal module m_n", m_n_mm, 0.5, 70.0, " mm");
  check_iso_scope("face width b", b_mm, 4.0, 1200.0, " mm");

  const double scale = std::pow(std::sqrt(2.0), tolerance_class - 5);
  const double sqrt_d = std::sqrt(d_mm), sqrt_b = std::sqrt(b_mm);
  const double f_p = (0.001 * d_mm + 0.4 * m_n_mm + 5.0) * scale;
  const double cumulative = (0.002 * d_mm + 0.55 * sqrt_d + 0.7 * m_n_mm + 12.0) * scale;
  const double f_h_alpha = (0.4 * m_n_mm + 0.001 * d_mm + 4.0) * scale;
  const double f_f_alpha = (0.55 * m_n_mm + 5.0) * scale;
  const double f_h_beta = (0.05 * sqrt_d + 0.35 * sqrt_b + 4.0) * scale;
  const double f_f_beta = (0.07 * sqrt_d + 0.45 * sqrt_b + 4.0) * scale;

  Iso1328Tolerances t;
  t.single_pitch = iso1328_round(f_p);
  t.cumulative_pitch = iso1328_round(cumulative);
  t.runout =
      iso1328_round(0.9 * cumulative);  // ISO 1328-2 / later editions (docs/reference-values.md)
  t.profile_slope = iso1328_round(f_h_alpha);
  t.profile_form = iso1328_round(f_f_alpha);
  t.profile_total = iso1328_round(std::hypot(f_h_alpha, f_f_alpha));
  t.helix_slope = iso1328_round(f_h_beta);
  t.helix_form = iso1328_round(f_f_beta);
  t.helix_total = iso1328_round(std::hypot(f_h_beta, f_f_beta));
  return t;
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
    resolve_gost(spec, gear, set);
  } else {
    resolve_iso(spec, gear, set);
  }
  // The user states these values, so they count as confirmed. Kinds the standard lacks are
  // accepted (the scenario parser validates the symbols).
  for (const auto& [kind, value] : spec.overrides_um) {
    set.values[kind] = Tolerance{value, "scenario override", true};
  }
  return set;
}

}  // namespace gearmc
