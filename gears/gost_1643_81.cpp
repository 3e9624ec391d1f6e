// GOST 1643-81 tolerances of a spur gear. GOST 1643-81 has no formulas, only tables; this file
// holds the part of those tables around P1's gear (reference diameter over 125 up to 400 mm,
// module over 3.5 up to 6.3 mm, face width over 40 up to 100 mm, grades 4-8) as one constant
// table whose every row says where its number comes from and whether it is confirmed (P1
// Table 1) or only recalled / derived (docs/reference-values.md). A kind the scenario overrides
// is never looked up, so a gear outside the table works when the scenario gives every norm
// itself (resolve_tolerances, tolerances.cpp).
#include <algorithm>
#include <limits>
#include <sstream>
#include <string>
#include <string_view>
#include <vector>

#include "gears/tolerance_standards.h"

namespace gearmc::tolerance_detail {
namespace {

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

}  // namespace

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

}  // namespace gearmc::tolerance_detail
