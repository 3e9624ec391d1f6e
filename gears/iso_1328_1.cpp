// ISO 1328-1:2013 flank tolerances of a spur gear, computed from the standard's closed-form
// class-5 formulas, scaled to class A by sqrt(2)^(A-5) and rounded as the standard prescribes
// (docs/reference-values.md, "ISO 1328-1:2013 flank tolerances [verified]"): the public
// iso1328_tolerances and iso1328_round (tolerances.h) and the resolution of a scenario's ISO
// class (resolve_iso).
#include <cmath>
#include <sstream>
#include <string>

#include "gears/tolerance_standards.h"

namespace gearmc {
namespace {

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

}  // namespace

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

std::optional<int> iso1328_class_met(ToleranceKind kind, double value_um, double d_mm,
                                     double m_n_mm, double b_mm, int z) {
  const IsoField* field = nullptr;
  for (const IsoField& f : kIsoFields) {
    if (f.kind == kind) field = &f;
  }
  if (field == nullptr || !std::isfinite(value_um)) return std::nullopt;
  for (int a = kIsoLowestClass; a <= kIsoHighestClass; ++a) {
    if (std::abs(value_um) <= iso1328_tolerances(a, d_mm, m_n_mm, b_mm, z).*(field->value)) {
      return a;
    }
  }
  return std::nullopt;
}

namespace tolerance_detail {

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

}  // namespace tolerance_detail
}  // namespace gearmc
