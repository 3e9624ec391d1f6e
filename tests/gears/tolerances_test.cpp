// Tests of gears/tolerances: ISO 1328-1:2013 formulas, class scaling, rounding and scope; the
// GOST 1643-81 table for P1's gear; symbols; and resolve_tolerances with and without scenario
// overrides. Reference values come from docs/reference-values.md and
// P1 Table 1 (docs/sources.md); every expected number below says which one, or shows its
// arithmetic.
#include "gears/tolerances.h"
#include "tests/support/p1_fixtures.h"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <string>

#include "gears/involute_gear.h"

namespace gearmc {
namespace {

// P1 Table 1 (docs/sources.md): z 24, m 5.6 mm, alpha 20 deg, x 0.90116, b 78.89 mm -> d 134.4 mm.
GearParameters p1_parameters() { return testing_support::p1_gear_parameters(); }

GearParameters parameters(int teeth, double module_mm, double face_width_mm) {
  GearParameters p;
  p.teeth = teeth;
  p.module_mm = module_mm;
  p.face_width_mm = face_width_mm;
  return p;
}

// The ToleranceError message of `action`, or "" (and a test failure) when it does not throw one.
std::string tolerance_error(const std::function<void()>& action) {
  try {
    action();
  } catch (const ToleranceError& e) {
    return e.what();
  }
  ADD_FAILURE() << "expected a ToleranceError";
  return "";
}

::testing::AssertionResult Contains(const std::string& text, const std::string& part) {
  if (text.find(part) != std::string::npos) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << "\"" << text << "\" does not contain \"" << part << "\"";
}

// The unrounded class-5 values of ISO 1328-1:2013 (docs/reference-values.md table), written out
// again here independently of the implementation.
struct IsoClass5 {
  double f_p, F_p, f_H_alpha, f_f_alpha, f_H_beta, f_f_beta;
};
IsoClass5 iso_class5(double d, double m, double b) {
  return {0.001 * d + 0.4 * m + 5.0,
          0.002 * d + 0.55 * std::sqrt(d) + 0.7 * m + 12.0,
          0.4 * m + 0.001 * d + 4.0,
          0.55 * m + 5.0,
          0.05 * std::sqrt(d) + 0.35 * std::sqrt(b) + 4.0,
          0.07 * std::sqrt(d) + 0.45 * std::sqrt(b) + 4.0};
}

// ----------------------------------------------------------------------------------------------
// ISO 1328-1:2013

TEST(Iso1328Tolerances, P1GearClass5MatchesReferences) {
  // docs/reference-values.md: "For P1's gear (d 134.4, m 5.6, b 78.89) class 5 gives f_pT 7.5, F_pT
  // 23, F_rT 20, f_HαT 6.5, f_fαT 8.0, F_αT 10, f_HβT 7.5, f_fβT 9.0, F_βT 12."
  const Iso1328Tolerances t = iso1328_tolerances(5, 134.4, 5.6, 78.89, 24);
  EXPECT_DOUBLE_EQ(t.single_pitch, 7.5);
  EXPECT_DOUBLE_EQ(t.cumulative_pitch, 23.0);
  // 0.9 * unrounded F_pT 22.565 = 20.31 -> 20; from the rounded F_pT it would be 0.9 * 23 = 20.7
  // -> 21, so this also checks that F_rT uses the unrounded F_pT.
  EXPECT_DOUBLE_EQ(t.runout, 20.0);
  EXPECT_DOUBLE_EQ(t.profile_slope, 6.5);
  EXPECT_DOUBLE_EQ(t.profile_form, 8.0);
  EXPECT_DOUBLE_EQ(t.profile_total, 10.0);
  EXPECT_DOUBLE_EQ(t.helix_slope, 7.5);
  EXPECT_DOUBLE_EQ(t.helix_form, 9.0);
  EXPECT_DOUBLE_EQ(t.helix_total, 12.0);
}

TEST(Iso1328Tolerances, ClassMetIsTheFinestClassWhoseToleranceHoldsTheValue) {
  // P1's gear. By hand from the class-5 formulas: F_αT unrounded hypot(6.3744, 8.08) = 10.2917;
  // class 1 = /4 = 2.573 → 2.6, class 4 = /√2 = 7.277 → 7.5, class 5 → 10, class 6 = 14.555 → 15,
  // class 11 = ×8 = 82.33 → 82. f_HαT: class 5 6.3744 → 6.5, class 6 9.015 → 9.0.
  const auto cls = [](ToleranceKind k, double v) {
    return iso1328_class_met(k, v, 134.4, 5.6, 78.89, 24);
  };
  EXPECT_EQ(cls(ToleranceKind::kProfileTotal, 0.0), 1);
  EXPECT_EQ(cls(ToleranceKind::kProfileTotal, 2.6), 1);
  EXPECT_EQ(cls(ToleranceKind::kProfileTotal, 2.61), 2);
  EXPECT_EQ(cls(ToleranceKind::kProfileTotal, 7.5), 4);
  EXPECT_EQ(cls(ToleranceKind::kProfileTotal, 7.51), 5);
  EXPECT_EQ(cls(ToleranceKind::kProfileTotal, 10.0), 5);
  EXPECT_EQ(cls(ToleranceKind::kProfileTotal, 10.01), 6);
  EXPECT_EQ(cls(ToleranceKind::kProfileTotal, 82.0), 11);
  EXPECT_EQ(cls(ToleranceKind::kProfileTotal, 82.01), std::nullopt);
  // Signed deviations by their magnitude.
  EXPECT_EQ(cls(ToleranceKind::kProfileSlope, -6.5), 5);
  EXPECT_EQ(cls(ToleranceKind::kProfileSlope, -6.51), 6);
  EXPECT_EQ(cls(ToleranceKind::kProfileSlope, 9.0), 6);
  // No ISO formula, no value: no class.
  EXPECT_EQ(cls(ToleranceKind::kBasePitch, 1.0), std::nullopt);
  EXPECT_EQ(cls(ToleranceKind::kProfileTotal, std::nan("")), std::nullopt);
  // Outside the standard's scope (z = 4): refused, as the tolerances themselves.
  EXPECT_THROW(iso1328_class_met(ToleranceKind::kProfileTotal, 1.0, 134.4, 5.6, 78.89, 4),
               ToleranceError);
}

TEST(Iso1328Tolerances, Class7IsClass5TimesTwoBeforeRounding) {
  // docs/reference-values.md: class A = class-5 value * sqrt(2)^(A-5); A = 7 -> factor 2.
  const IsoClass5 c5 = iso_class5(134.4, 5.6, 78.89);
  // Unrounded class-7 values of P1's gear (2 * class 5):
  //   f_p   2 * (0.1344 + 2.24 + 5)                    = 14.7488 -> 15
  //   F_p   2 * (0.2688 + 0.55*11.5931 + 3.92 + 12)    = 45.1300 -> 45
  //   F_r   0.9 * 45.1300                              = 40.6170 -> 41
  //   f_Ha  2 * (2.24 + 0.1344 + 4)                    = 12.7488 -> 13
  //   f_fa  2 * (3.08 + 5)                             = 16.1600 -> 16
  //   F_a   hypot(12.7488, 16.16)                      = 20.5834 -> 21
  //   f_Hb  2 * (0.05*11.5931 + 0.35*8.8820 + 4)       = 15.3767 -> 15
  //   f_fb  2 * (0.07*11.5931 + 0.45*8.8820 + 4)       = 17.6168 -> 18
  //   F_b   hypot(15.3767, 17.6168)                    = 23.3837 -> 23
  EXPECT_NEAR(2.0 * c5.f_p, 14.7488, 1e-4);
  EXPECT_NEAR(2.0 * c5.F_p, 45.1300, 1e-4);
  EXPECT_NEAR(2.0 * c5.f_H_alpha, 12.7488, 1e-4);
  EXPECT_NEAR(2.0 * c5.f_f_alpha, 16.1600, 1e-4);
  EXPECT_NEAR(2.0 * c5.f_H_beta, 15.3767, 1e-4);
  EXPECT_NEAR(2.0 * c5.f_f_beta, 17.6168, 1e-4);
  const Iso1328Tolerances t = iso1328_tolerances(7, 134.4, 5.6, 78.89, 24);
  EXPECT_DOUBLE_EQ(t.single_pitch, 15.0);
  EXPECT_DOUBLE_EQ(t.cumulative_pitch, 45.0);
  EXPECT_DOUBLE_EQ(t.runout, 41.0);
  EXPECT_DOUBLE_EQ(t.profile_slope, 13.0);
  EXPECT_DOUBLE_EQ(t.profile_form, 16.0);
  EXPECT_DOUBLE_EQ(t.profile_total, 21.0);
  EXPECT_DOUBLE_EQ(t.helix_slope, 15.0);
  EXPECT_DOUBLE_EQ(t.helix_form, 18.0);
  EXPECT_DOUBLE_EQ(t.helix_total, 23.0);
}

TEST(Iso1328Tolerances, Class1UsesTheTenthMicrometreStep) {
  // Class 1 = class 5 * sqrt(2)^-4 = class 5 / 4 (docs/reference-values.md); P1's gear:
  //   f_p 7.3744/4 = 1.8436 -> 1.8;  F_p 22.5650/4 = 5.6413 -> 5.5 (0.5 µm band);
  //   F_r 0.9*5.6413 = 5.0771 -> 5.0; f_Ha 6.3744/4 = 1.5936 -> 1.6; f_fa 8.08/4 = 2.02 -> 2.0;
  //   F_a hypot(1.5936, 2.02) = 2.5729 -> 2.6; f_Hb 7.6884/4 = 1.9221 -> 1.9;
  //   f_fb 8.8084/4 = 2.2021 -> 2.2; F_b hypot(1.9221, 2.2021) = 2.9230 -> 2.9.
  const IsoClass5 c5 = iso_class5(134.4, 5.6, 78.89);
  EXPECT_NEAR(c5.F_p / 4.0, 5.6413, 1e-4);
  const Iso1328Tolerances t = iso1328_tolerances(1, 134.4, 5.6, 78.89, 24);
  EXPECT_DOUBLE_EQ(t.single_pitch, 1.8);
  EXPECT_DOUBLE_EQ(t.cumulative_pitch, 5.5);
  EXPECT_DOUBLE_EQ(t.runout, 5.0);
  EXPECT_DOUBLE_EQ(t.profile_slope, 1.6);
  EXPECT_DOUBLE_EQ(t.profile_form, 2.0);
  EXPECT_DOUBLE_EQ(t.profile_total, 2.6);
  EXPECT_DOUBLE_EQ(t.helix_slope, 1.9);
  EXPECT_DOUBLE_EQ(t.helix_form, 2.2);
  EXPECT_DOUBLE_EQ(t.helix_total, 2.9);
}

TEST(Iso1328Tolerances, TotalsComeFromUnroundedComponents) {
  // docs/reference-values.md: "Totals are computed from unrounded components, then rounded."
  // Class 6 (factor sqrt(2)) of P1's gear: f_Hb 7.688357*sqrt(2) = 10.8730 -> 11,
  // f_fb 8.808419*sqrt(2) = 12.4570 -> 12; F_b = hypot(10.8730, 12.4570) = 16.5348 -> 17, whereas
  // hypot(11, 12) = 16.28 would give 16. Also f_p 7.3744*sqrt(2) = 10.4290 -> 10 (1 µm band; the
  // 0.5 µm band would give 10.5).
  const IsoClass5 c5 = iso_class5(134.4, 5.6, 78.89);
  EXPECT_NEAR(std::hypot(c5.f_H_beta, c5.f_f_beta) * std::sqrt(2.0), 16.5348, 1e-4);
  const Iso1328Tolerances t6 = iso1328_tolerances(6, 134.4, 5.6, 78.89, 24);
  EXPECT_DOUBLE_EQ(t6.helix_slope, 11.0);
  EXPECT_DOUBLE_EQ(t6.helix_form, 12.0);
  EXPECT_DOUBLE_EQ(t6.helix_total, 17.0);
  EXPECT_DOUBLE_EQ(t6.single_pitch, 10.0);

  // Class 11 (factor 8): f_Ha 6.3744*8 = 50.9952 -> 51, f_fa 8.08*8 = 64.64 -> 65;
  // F_a = hypot(50.9952, 64.64) = 82.3337 -> 82, whereas hypot(51, 65) = 82.62 would give 83.
  // F_r = 0.9 * 22.565006*8 = 162.468 -> 162, whereas 0.9 * rounded F_p 181 = 162.9 would give 163.
  EXPECT_NEAR(std::hypot(c5.f_H_alpha, c5.f_f_alpha) * 8.0, 82.3337, 1e-4);
  const Iso1328Tolerances t11 = iso1328_tolerances(11, 134.4, 5.6, 78.89, 24);
  EXPECT_DOUBLE_EQ(t11.profile_slope, 51.0);
  EXPECT_DOUBLE_EQ(t11.profile_form, 65.0);
  EXPECT_DOUBLE_EQ(t11.profile_total, 82.0);
  EXPECT_DOUBLE_EQ(t11.cumulative_pitch, 181.0);
  EXPECT_DOUBLE_EQ(t11.runout, 162.0);
}

TEST(Iso1328Round, StepDependsOnTheUnroundedValue) {
  // docs/reference-values.md: > 10 µm -> 1 µm; 5-10 µm -> 0.5 µm; < 5 µm -> 0.1 µm.
  EXPECT_DOUBLE_EQ(iso1328_round(22.565), 23.0);
  EXPECT_DOUBLE_EQ(iso1328_round(10.3), 10.0);  // 1 µm band (0.5 µm would give 10.5)
  EXPECT_DOUBLE_EQ(iso1328_round(10.6), 11.0);
  EXPECT_DOUBLE_EQ(iso1328_round(10.0), 10.0);  // exactly 10: unchanged
  EXPECT_DOUBLE_EQ(iso1328_round(9.8), 10.0);   // 0.5 µm band
  EXPECT_DOUBLE_EQ(iso1328_round(7.3744), 7.5);
  EXPECT_DOUBLE_EQ(iso1328_round(7.2), 7.0);
  EXPECT_DOUBLE_EQ(iso1328_round(5.3), 5.5);  // 0.5 µm band (0.1 µm would give 5.3)
  EXPECT_DOUBLE_EQ(iso1328_round(5.0), 5.0);  // exactly 5: unchanged
  EXPECT_DOUBLE_EQ(iso1328_round(4.97), 5.0);
  EXPECT_DOUBLE_EQ(iso1328_round(4.7), 4.7);  // 0.1 µm band (0.5 µm would give 4.5)
  EXPECT_DOUBLE_EQ(iso1328_round(1.8436), 1.8);
  EXPECT_DOUBLE_EQ(iso1328_round(0.04), 0.0);
  // Halves round up (away from zero); 10.5, 7.25 and 2.25 are exact binary numbers.
  EXPECT_DOUBLE_EQ(iso1328_round(10.5), 11.0);
  EXPECT_DOUBLE_EQ(iso1328_round(7.25), 7.5);
  EXPECT_DOUBLE_EQ(iso1328_round(2.25), 2.3);
}

TEST(Iso1328Tolerances, ScopeLimitsAreInclusive) {
  // docs/reference-values.md scope: 5 <= z <= 1000, 5 <= d <= 15000, 0.5 <= m_n <= 70, 4 <= b <=
  // 1200.
  EXPECT_NO_THROW(iso1328_tolerances(5, 5.0, 0.5, 4.0, 5));
  EXPECT_NO_THROW(iso1328_tolerances(5, 15000.0, 70.0, 1200.0, 1000));
  EXPECT_NO_THROW(iso1328_tolerances(1, 134.4, 5.6, 78.89, 24));
  EXPECT_NO_THROW(iso1328_tolerances(11, 134.4, 5.6, 78.89, 24));
}

TEST(Iso1328Tolerances, OutOfScopeThrowsNamingQuantityValueAndRange) {
  std::string why = tolerance_error([] { iso1328_tolerances(5, 134.4, 5.6, 78.89, 4); });
  EXPECT_TRUE(Contains(why, "number of teeth z = 4"));
  EXPECT_TRUE(Contains(why, "5 ... 1000"));
  why = tolerance_error([] { iso1328_tolerances(5, 134.4, 5.6, 78.89, 1001); });
  EXPECT_TRUE(Contains(why, "z = 1001"));
  why = tolerance_error([] { iso1328_tolerances(5, 4.9, 0.5, 10.0, 10); });
  EXPECT_TRUE(Contains(why, "reference diameter d = 4.9 mm"));
  EXPECT_TRUE(Contains(why, "5 mm ... 15000 mm"));
  why = tolerance_error([] { iso1328_tolerances(5, 15001.0, 5.6, 78.89, 24); });
  EXPECT_TRUE(Contains(why, "d = 15001 mm"));
  why = tolerance_error([] { iso1328_tolerances(5, 134.4, 0.4, 78.89, 24); });
  EXPECT_TRUE(Contains(why, "normal module m_n = 0.4 mm"));
  EXPECT_TRUE(Contains(why, "0.5 mm ... 70 mm"));
  why = tolerance_error([] { iso1328_tolerances(5, 134.4, 71.0, 78.89, 24); });
  EXPECT_TRUE(Contains(why, "m_n = 71 mm"));
  why = tolerance_error([] { iso1328_tolerances(5, 134.4, 5.6, 3.0, 24); });
  EXPECT_TRUE(Contains(why, "face width b = 3 mm"));
  EXPECT_TRUE(Contains(why, "4 mm ... 1200 mm"));
  why = tolerance_error([] { iso1328_tolerances(5, 134.4, 5.6, 1201.0, 24); });
  EXPECT_TRUE(Contains(why, "b = 1201 mm"));
  why = tolerance_error([] { iso1328_tolerances(5, std::nan(""), 5.6, 78.89, 24); });
  EXPECT_TRUE(Contains(why, "reference diameter d"));
}

TEST(Iso1328Tolerances, ClassOutsideOneToElevenThrows) {
  std::string why = tolerance_error([] { iso1328_tolerances(0, 134.4, 5.6, 78.89, 24); });
  EXPECT_TRUE(Contains(why, "class 0"));
  EXPECT_TRUE(Contains(why, "1 ... 11"));
  why = tolerance_error([] { iso1328_tolerances(12, 134.4, 5.6, 78.89, 24); });
  EXPECT_TRUE(Contains(why, "class 12"));
}

// ----------------------------------------------------------------------------------------------
// Symbols (tolerances.h comment).

TEST(ToleranceSymbols, GostAndIsoSpellings) {
  using K = ToleranceKind;
  const auto gost = ToleranceStandard::kGost1643_81;
  const auto iso = ToleranceStandard::kIso1328_1_2013;
  const std::vector<std::pair<K, std::optional<std::string>>> gost_expected = {
      {K::kRunout, "F_r"},
      {K::kCumulativePitch, "F_p"},
      {K::kSinglePitch, "f_pt"},
      {K::kBasePitch, "f_pb"},
      {K::kProfileTotal, "f_f"},
      {K::kProfileSlope, std::nullopt},
      {K::kProfileForm, std::nullopt},
      {K::kHelixTotal, "F_beta"},
      {K::kHelixSlope, std::nullopt},
      {K::kHelixForm, std::nullopt},
      {K::kThicknessUpper, "E_Hs"},
      {K::kThicknessTolerance, "T_H"}};
  const std::vector<std::pair<K, std::optional<std::string>>> iso_expected = {
      {K::kRunout, "F_r"},
      {K::kCumulativePitch, "F_p"},
      {K::kSinglePitch, "f_p"},
      {K::kBasePitch, std::nullopt},
      {K::kProfileTotal, "F_alpha"},
      {K::kProfileSlope, "f_H_alpha"},
      {K::kProfileForm, "f_f_alpha"},
      {K::kHelixTotal, "F_beta"},
      {K::kHelixSlope, "f_H_beta"},
      {K::kHelixForm, "f_f_beta"},
      {K::kThicknessUpper, "E_Hs"},
      {K::kThicknessTolerance, "T_H"}};
  for (const auto& [standard, expected] : {std::pair{gost, gost_expected}, {iso, iso_expected}}) {
    for (const auto& [kind, symbol] : expected) {
      EXPECT_EQ(tolerance_symbol(kind, standard), symbol)
          << standard_name(standard) << " kind " << static_cast<int>(kind);
      if (symbol) {
        EXPECT_EQ(tolerance_kind_from_symbol(*symbol, standard), kind) << *symbol;
      }
    }
  }
  // Case matters: ISO's f_p is the single pitch, F_p the cumulative pitch.
  EXPECT_EQ(tolerance_kind_from_symbol("f_p", iso), K::kSinglePitch);
  EXPECT_EQ(tolerance_kind_from_symbol("F_p", iso), K::kCumulativePitch);
  EXPECT_EQ(tolerance_kind_from_symbol("f_f", iso), std::nullopt);
  EXPECT_EQ(tolerance_kind_from_symbol("f_pb", iso), std::nullopt);
  EXPECT_EQ(tolerance_kind_from_symbol("f_H_alpha", gost), std::nullopt);
  EXPECT_EQ(tolerance_kind_from_symbol("F_R", gost), std::nullopt);
  EXPECT_EQ(tolerance_kind_from_symbol("", gost), std::nullopt);
}

TEST(ToleranceSymbols, StandardNamesAndKindOrder) {
  EXPECT_EQ(standard_name(ToleranceStandard::kGost1643_81), "gost_1643_81");
  EXPECT_EQ(standard_name(ToleranceStandard::kIso1328_1_2013), "iso_1328_1_2013");
  const std::vector<ToleranceKind>& kinds = all_tolerance_kinds();
  ASSERT_EQ(kinds.size(), 12u);
  for (std::size_t i = 0; i < kinds.size(); ++i) {
    EXPECT_EQ(static_cast<std::size_t>(kinds[i]), i);  // enum order
  }
}

// ----------------------------------------------------------------------------------------------
// GOST 1643-81 through resolve_tolerances.

class GostResolve : public ::testing::Test {
 protected:
  void SetUp() override { ASSERT_EQ(validate_gear_parameters(p1_parameters()), ""); }
  InvoluteGear p1_gear_{p1_parameters()};
};

TEST_F(GostResolve, P1GearFromTheTable) {
  ASSERT_DOUBLE_EQ(p1_gear_.reference_diameter_mm(), 134.4);  // P1 Table 1
  ToleranceSpec spec;
  spec.standard = ToleranceStandard::kGost1643_81;
  spec.grade = "6-5-5";  // P1 Table 1
  const ToleranceSet set = resolve_tolerances(spec, p1_gear_);
  EXPECT_EQ(set.standard, ToleranceStandard::kGost1643_81);
  EXPECT_EQ(set.grade, "6-5-5");

  // ±f_pb grade 5 = 9 µm: P1 Table 1 (confirmed).
  ASSERT_EQ(set.values.count(ToleranceKind::kBasePitch), 1u);
  EXPECT_DOUBLE_EQ(set.values.at(ToleranceKind::kBasePitch).value_um, 9.0);
  EXPECT_EQ(set.values.at(ToleranceKind::kBasePitch).source, "P1 Table 1");
  EXPECT_TRUE(set.values.at(ToleranceKind::kBasePitch).confirmed);
  // f_f grade 5 = 8 µm: P1 Table 1 (confirmed); it is the total profile band.
  EXPECT_EQ(set.get_um(ToleranceKind::kProfileTotal), 8.0);
  EXPECT_TRUE(set.values.at(ToleranceKind::kProfileTotal).confirmed);
  EXPECT_EQ(set.values.at(ToleranceKind::kProfileTotal).source, "P1 Table 1");

  // Recalled (docs/reference-values.md), hence unconfirmed: F_r grade 6 = 40 (P1 itself uses 50, so
  // the source flags the mismatch), ±f_pt grade 5 = 10, F_beta grade 5 (b 40-100 mm) = 10.
  EXPECT_EQ(set.get_um(ToleranceKind::kRunout), 40.0);
  EXPECT_FALSE(set.values.at(ToleranceKind::kRunout).confirmed);
  EXPECT_TRUE(Contains(set.values.at(ToleranceKind::kRunout).source, "recalled"));
  EXPECT_TRUE(Contains(set.values.at(ToleranceKind::kRunout).source, "50"));
  EXPECT_EQ(set.get_um(ToleranceKind::kSinglePitch), 10.0);
  EXPECT_FALSE(set.values.at(ToleranceKind::kSinglePitch).confirmed);
  EXPECT_EQ(set.values.at(ToleranceKind::kSinglePitch).source,
            "recalled (docs/reference-values.md), not checked against the standard");
  EXPECT_EQ(set.get_um(ToleranceKind::kHelixTotal), 10.0);
  EXPECT_FALSE(set.values.at(ToleranceKind::kHelixTotal).confirmed);

  // Not tabulated (F_p) or not looked up at all (E_Hs, T_H), and kinds GOST lacks: absent.
  EXPECT_EQ(set.values.size(), 5u);
  for (ToleranceKind absent :
       {ToleranceKind::kCumulativePitch, ToleranceKind::kThicknessUpper,
        ToleranceKind::kThicknessTolerance, ToleranceKind::kProfileSlope,
        ToleranceKind::kProfileForm, ToleranceKind::kHelixSlope, ToleranceKind::kHelixForm}) {
    EXPECT_EQ(set.get_um(absent), std::nullopt) << static_cast<int>(absent);
  }
}

TEST_F(GostResolve, P1GearWithP1Overrides) {
  // P1 Table 1: F_r 50, ±f_pb 9, f_f 8, E_Hs 110 (stored as a positive magnitude), T_H 100 µm.
  ToleranceSpec spec;
  spec.grade = "6-5-5";
  spec.overrides_um = {{ToleranceKind::kRunout, 50.0},
                       {ToleranceKind::kBasePitch, 9.0},
                       {ToleranceKind::kProfileTotal, 8.0},
                       {ToleranceKind::kThicknessUpper, 110.0},
                       {ToleranceKind::kThicknessTolerance, 100.0}};
  const ToleranceSet set = resolve_tolerances(spec, p1_gear_);
  for (const auto& [kind, value] : spec.overrides_um) {
    ASSERT_EQ(set.values.count(kind), 1u);
    EXPECT_DOUBLE_EQ(set.values.at(kind).value_um, value);
    EXPECT_EQ(set.values.at(kind).source, "scenario override");
    EXPECT_TRUE(set.values.at(kind).confirmed);
  }
  // Not overridden: still from the table (docs/reference-values.md, recalled).
  EXPECT_EQ(set.get_um(ToleranceKind::kSinglePitch), 10.0);
  EXPECT_EQ(set.get_um(ToleranceKind::kHelixTotal), 10.0);
  EXPECT_EQ(set.values.size(), 7u);
}

TEST_F(GostResolve, SingleGradeMeansAllThree) {
  // Grade 7 everywhere (docs/reference-values.md: F_r 56, ±f_pt 20, f_f 16, F_beta 16, all
  // recalled); ±f_pb grade 7 derived: 9 (P1) * 1.4 = 12.6 -> 13 (grade 6), 13 * 1.4 = 18.2 -> 18.
  ToleranceSpec spec;
  spec.grade = "7";
  const ToleranceSet set = resolve_tolerances(spec, p1_gear_);
  EXPECT_EQ(set.get_um(ToleranceKind::kRunout), 56.0);
  EXPECT_EQ(set.get_um(ToleranceKind::kSinglePitch), 20.0);
  EXPECT_EQ(set.get_um(ToleranceKind::kBasePitch), 18.0);
  EXPECT_EQ(set.get_um(ToleranceKind::kProfileTotal), 16.0);
  EXPECT_EQ(set.get_um(ToleranceKind::kHelixTotal), 16.0);
  for (const auto& [kind, tolerance] : set.values) {
    EXPECT_FALSE(tolerance.confirmed) << static_cast<int>(kind);
  }
  EXPECT_TRUE(Contains(set.values.at(ToleranceKind::kBasePitch).source, "derived"));
}

TEST_F(GostResolve, GradesGoToTheirNormGroups) {
  // "K-S-C": F_r uses K, f_pt/f_pb/f_f use S, F_beta uses C. "8-6-5" (docs/reference-values.md
  // values): F_r grade 8 = 71, ±f_pt grade 6 = 14, f_f grade 6 = 11, F_beta grade 5 = 10; ±f_pb
  // grade 6 derived 9 * 1.4 = 12.6 -> 13.
  ToleranceSpec spec;
  spec.grade = "8-6-5";
  const ToleranceSet set = resolve_tolerances(spec, p1_gear_);
  EXPECT_EQ(set.get_um(ToleranceKind::kRunout), 71.0);
  EXPECT_EQ(set.get_um(ToleranceKind::kSinglePitch), 14.0);
  EXPECT_EQ(set.get_um(ToleranceKind::kBasePitch), 13.0);
  EXPECT_EQ(set.get_um(ToleranceKind::kProfileTotal), 11.0);
  EXPECT_EQ(set.get_um(ToleranceKind::kHelixTotal), 10.0);
}

TEST_F(GostResolve, DerivedGrades4And8) {
  // Grade 4 is not in docs/reference-values.md: grade-5 value / 1.4, rounded to 1 µm (unconfirmed):
  //   F_r 25/1.4 = 17.9 -> 18; ±f_pt 10/1.4 = 7.1 -> 7; ±f_pb 9/1.4 = 6.4 -> 6;
  //   f_f 8/1.4 = 5.7 -> 6; F_beta 10/1.4 = 7.1 -> 7.
  ToleranceSpec spec;
  spec.grade = "4";
  ToleranceSet set = resolve_tolerances(spec, p1_gear_);
  EXPECT_EQ(set.get_um(ToleranceKind::kRunout), 18.0);
  EXPECT_EQ(set.get_um(ToleranceKind::kSinglePitch), 7.0);
  EXPECT_EQ(set.get_um(ToleranceKind::kBasePitch), 6.0);
  EXPECT_EQ(set.get_um(ToleranceKind::kProfileTotal), 6.0);
  EXPECT_EQ(set.get_um(ToleranceKind::kHelixTotal), 7.0);
  for (const auto& [kind, tolerance] : set.values) {
    EXPECT_FALSE(tolerance.confirmed) << static_cast<int>(kind);
    EXPECT_TRUE(Contains(tolerance.source, "derived")) << tolerance.source;
    EXPECT_TRUE(Contains(tolerance.source, "1.4")) << tolerance.source;
  }
  // Grade 8: docs/reference-values.md F_r 71, ±f_pt 28, f_f 22, F_beta 25; ±f_pb derived 18 * 1.4
  // = 25.2
  // -> 25.
  spec.grade = "8";
  set = resolve_tolerances(spec, p1_gear_);
  EXPECT_EQ(set.get_um(ToleranceKind::kRunout), 71.0);
  EXPECT_EQ(set.get_um(ToleranceKind::kSinglePitch), 28.0);
  EXPECT_EQ(set.get_um(ToleranceKind::kBasePitch), 25.0);
  EXPECT_EQ(set.get_um(ToleranceKind::kProfileTotal), 22.0);
  EXPECT_EQ(set.get_um(ToleranceKind::kHelixTotal), 25.0);
}

TEST(GostResolveOutsideTable, LargeGearThrowsNamingTheMissingRange) {
  // d = 6 * 100 = 600 mm lies above the tabulated 125-400 mm range.
  const GearParameters p = parameters(100, 6.0, 50.0);
  ASSERT_EQ(validate_gear_parameters(p), "");
  const InvoluteGear gear(p);
  ToleranceSpec spec;
  spec.grade = "6-5-5";
  const std::string why = tolerance_error([&] { resolve_tolerances(spec, gear); });
  EXPECT_TRUE(Contains(why, "GOST 1643-81"));
  EXPECT_TRUE(Contains(why, "F_r"));
  EXPECT_TRUE(Contains(why, "f_pb"));
  EXPECT_TRUE(Contains(why, "reference diameter d = 600 mm"));
  EXPECT_TRUE(Contains(why, "over 125 up to 400 mm"));
  EXPECT_TRUE(Contains(why, "overrides"));
  // F_beta depends on the face width only, and b = 50 mm is tabulated.
  EXPECT_FALSE(Contains(why, "F_beta"));
}

TEST(GostResolveOutsideTable, OnlyNeededNormsAreLookedUp) {
  const InvoluteGear gear(parameters(100, 6.0, 50.0));  // d = 600 mm, outside the table
  ToleranceSpec spec;
  spec.grade = "6-5-5";
  spec.overrides_um = {{ToleranceKind::kRunout, 50.0},
                       {ToleranceKind::kBasePitch, 9.0},
                       {ToleranceKind::kProfileTotal, 8.0}};
  // f_pt still needs the table: the message names it and no overridden norm.
  const std::string why = tolerance_error([&] { resolve_tolerances(spec, gear); });
  EXPECT_TRUE(Contains(why, "f_pt"));
  EXPECT_FALSE(Contains(why, "F_r"));
  EXPECT_FALSE(Contains(why, "f_pb"));
  // With every tabulated norm overridden the gear resolves.
  spec.overrides_um[ToleranceKind::kSinglePitch] = 14.0;
  const ToleranceSet set = resolve_tolerances(spec, gear);
  EXPECT_EQ(set.get_um(ToleranceKind::kSinglePitch), 14.0);
  EXPECT_EQ(set.values.at(ToleranceKind::kSinglePitch).source, "scenario override");
  EXPECT_EQ(set.get_um(ToleranceKind::kHelixTotal),
            10.0);  // b = 50 mm: docs/reference-values.md grade 5
  EXPECT_EQ(set.values.size(), 5u);
}

TEST(GostResolveOutsideTable, ModuleAndFaceWidthRanges) {
  // GOST ranges read "over ... up to ..." ("св. ... до ..."): m = 3.5 belongs to the range below
  // 3.5-6.3, so the module 3.5 mm gear (d = 3.5 * 40 = 140 mm) is not tabulated.
  const InvoluteGear small_module(parameters(40, 3.5, 50.0));
  ToleranceSpec spec;
  spec.grade = "6-5-5";
  std::string why = tolerance_error([&] { resolve_tolerances(spec, small_module); });
  EXPECT_TRUE(Contains(why, "module m = 3.5 mm"));
  EXPECT_TRUE(Contains(why, "over 3.5 up to 6.3 mm"));
  // m = 6.3 and d = 6.3 * 60 = 378 mm are inside; b = 100 is the upper end of 40-100 mm.
  EXPECT_NO_THROW(resolve_tolerances(spec, InvoluteGear(parameters(60, 6.3, 100.0))));
  // b = 30 mm is below the tabulated F_beta range; only F_beta is missing.
  why = tolerance_error([&] { resolve_tolerances(spec, InvoluteGear(parameters(24, 5.6, 30.0))); });
  EXPECT_TRUE(Contains(why, "F_beta"));
  EXPECT_TRUE(Contains(why, "face width b = 30 mm"));
  EXPECT_TRUE(Contains(why, "over 40 up to 100 mm"));
  EXPECT_FALSE(Contains(why, "f_pb"));
}

TEST_F(GostResolve, UntabulatedGradeThrowsUnlessOverridden) {
  ToleranceSpec spec;
  spec.grade = "9-5-5";  // a valid GOST grade, but the table holds grades 4-8 only
  const std::string why = tolerance_error([&] { resolve_tolerances(spec, p1_gear_); });
  EXPECT_TRUE(Contains(why, "F_r"));
  EXPECT_TRUE(Contains(why, "grade 9 is not tabulated"));
  EXPECT_TRUE(Contains(why, "4 ... 8"));
  EXPECT_TRUE(Contains(why, "overrides"));
  EXPECT_FALSE(Contains(why, "f_pb"));
  spec.overrides_um[ToleranceKind::kRunout] = 50.0;
  EXPECT_EQ(resolve_tolerances(spec, p1_gear_).get_um(ToleranceKind::kRunout), 50.0);
}

TEST_F(GostResolve, BadGradeStringsThrow) {
  for (const char* bad : {"", "6-5", "6-5-5-5", "a", "6-5-x", "13", "0", "6--5", "6-5-5-", " 7",
                          "7 ", "06-5-5", "6–5–5", "6,5,5", "-7"}) {
    ToleranceSpec spec;
    spec.grade = bad;
    const std::string why = tolerance_error([&] { resolve_tolerances(spec, p1_gear_); });
    EXPECT_TRUE(Contains(why, "K-S-C")) << "grade \"" << bad << "\"";
  }
  // A bad grade is an error even when every norm is overridden.
  ToleranceSpec spec;
  spec.grade = "6-5";
  spec.overrides_um = {{ToleranceKind::kRunout, 50.0},
                       {ToleranceKind::kSinglePitch, 10.0},
                       {ToleranceKind::kBasePitch, 9.0},
                       {ToleranceKind::kProfileTotal, 8.0},
                       {ToleranceKind::kHelixTotal, 10.0}};
  EXPECT_THROW(resolve_tolerances(spec, p1_gear_), ToleranceError);
}

TEST_F(GostResolve, OverridesOfKindsGostLacksAreKept) {
  ToleranceSpec spec;
  spec.grade = "6-5-5";
  spec.overrides_um = {{ToleranceKind::kProfileForm, 5.0}, {ToleranceKind::kCumulativePitch, 40}};
  const ToleranceSet set = resolve_tolerances(spec, p1_gear_);
  EXPECT_EQ(set.get_um(ToleranceKind::kProfileForm), 5.0);
  EXPECT_EQ(set.get_um(ToleranceKind::kCumulativePitch), 40.0);
  EXPECT_EQ(set.values.at(ToleranceKind::kProfileForm).source, "scenario override");
}

TEST_F(GostResolve, NegativeOrNonFiniteOverridesThrow) {
  // E_Hs is stored as a positive magnitude (P1: 110 µm); -110 is the other sign convention.
  ToleranceSpec spec;
  spec.grade = "6-5-5";
  spec.overrides_um = {{ToleranceKind::kThicknessUpper, -110.0}};
  const std::string why = tolerance_error([&] { resolve_tolerances(spec, p1_gear_); });
  EXPECT_TRUE(Contains(why, "E_Hs = -110"));
  spec.overrides_um = {{ToleranceKind::kRunout, std::nan("")}};
  EXPECT_THROW(resolve_tolerances(spec, p1_gear_), ToleranceError);
}

// ----------------------------------------------------------------------------------------------
// ISO 1328-1:2013 through resolve_tolerances.

TEST_F(GostResolve, IsoClass5ForP1Gear) {
  ToleranceSpec spec;
  spec.standard = ToleranceStandard::kIso1328_1_2013;
  spec.grade = "5";
  spec.overrides_um = {{ToleranceKind::kThicknessUpper, 110.0}};
  const ToleranceSet set = resolve_tolerances(spec, p1_gear_);
  EXPECT_EQ(set.standard, ToleranceStandard::kIso1328_1_2013);
  // docs/reference-values.md, P1's gear class 5.
  EXPECT_EQ(set.get_um(ToleranceKind::kSinglePitch), 7.5);
  EXPECT_EQ(set.get_um(ToleranceKind::kCumulativePitch), 23.0);
  EXPECT_EQ(set.get_um(ToleranceKind::kRunout), 20.0);
  EXPECT_EQ(set.get_um(ToleranceKind::kProfileSlope), 6.5);
  EXPECT_EQ(set.get_um(ToleranceKind::kProfileForm), 8.0);
  EXPECT_EQ(set.get_um(ToleranceKind::kProfileTotal), 10.0);
  EXPECT_EQ(set.get_um(ToleranceKind::kHelixSlope), 7.5);
  EXPECT_EQ(set.get_um(ToleranceKind::kHelixForm), 9.0);
  EXPECT_EQ(set.get_um(ToleranceKind::kHelixTotal), 12.0);
  for (ToleranceKind kind : {ToleranceKind::kSinglePitch, ToleranceKind::kRunout,
                             ToleranceKind::kProfileTotal, ToleranceKind::kHelixForm}) {
    EXPECT_TRUE(set.values.at(kind).confirmed);
    EXPECT_TRUE(Contains(set.values.at(kind).source, "ISO 1328-1:2013 class 5 formula"));
  }
  EXPECT_TRUE(
      Contains(set.values.at(ToleranceKind::kSinglePitch).source, "f_pT = 0.001d + 0.4m_n + 5"));
  EXPECT_TRUE(Contains(set.values.at(ToleranceKind::kRunout).source, "ISO 1328-2"));
  // ISO has no base pitch; T_H is not computed; E_Hs only from the override.
  EXPECT_EQ(set.get_um(ToleranceKind::kBasePitch), std::nullopt);
  EXPECT_EQ(set.get_um(ToleranceKind::kThicknessTolerance), std::nullopt);
  EXPECT_EQ(set.get_um(ToleranceKind::kThicknessUpper), 110.0);
  EXPECT_EQ(set.values.size(), 10u);
}

TEST_F(GostResolve, IsoClassStringAndScaledSource) {
  ToleranceSpec spec;
  spec.standard = ToleranceStandard::kIso1328_1_2013;
  spec.grade = "7";
  const ToleranceSet set = resolve_tolerances(spec, p1_gear_);
  EXPECT_EQ(set.get_um(ToleranceKind::kSinglePitch), 15.0);  // see Class7IsClass5TimesTwo...
  EXPECT_TRUE(Contains(set.values.at(ToleranceKind::kSinglePitch).source, "sqrt(2)^(7-5)"));
  for (const char* bad : {"0", "12", "", "5a", "05", "5.0", "6-5-5"}) {
    spec.grade = bad;
    const std::string why = tolerance_error([&] { resolve_tolerances(spec, p1_gear_); });
    EXPECT_TRUE(Contains(why, "1 ... 11")) << "class \"" << bad << "\"";
  }
}

TEST(IsoResolveOutsideScope, ThrowsUnlessEveryFormulaValueIsOverridden) {
  // m = 0.4 mm is below ISO 1328-1:2013's 0.5 mm (docs/reference-values.md scope).
  const GearParameters p = parameters(24, 0.4, 5.0);
  ASSERT_EQ(validate_gear_parameters(p), "");
  const InvoluteGear gear(p);
  ToleranceSpec spec;
  spec.standard = ToleranceStandard::kIso1328_1_2013;
  spec.grade = "5";
  const std::string why = tolerance_error([&] { resolve_tolerances(spec, gear); });
  EXPECT_TRUE(Contains(why, "normal module m_n = 0.4 mm"));
  EXPECT_TRUE(Contains(why, "overrides"));
  for (ToleranceKind kind : all_tolerance_kinds()) {
    if (kind == ToleranceKind::kBasePitch || kind == ToleranceKind::kThicknessUpper ||
        kind == ToleranceKind::kThicknessTolerance) {
      continue;
    }
    spec.overrides_um[kind] = 3.0;
  }
  const ToleranceSet set = resolve_tolerances(spec, gear);
  EXPECT_EQ(set.values.size(), 9u);
  EXPECT_EQ(set.get_um(ToleranceKind::kHelixForm), 3.0);
}

// The grade / class syntax both standards and the scenario reader share: 1-2 decimal digits, no
// leading zero, within the range (GOST 1643-81 grades 1..12, ISO 1328-1 classes 1..11).
TEST(GradeNumber, DigitsWithoutLeadingZeroWithinTheRange) {
  EXPECT_EQ(parse_grade_number("1", 1, 12), 1);
  EXPECT_EQ(parse_grade_number("12", 1, 12), 12);
  EXPECT_EQ(parse_grade_number("11", 1, 11), 11);
  for (const char* bad : {"", "0", "05", "13", "123", "1a", "-1", "+5", " 5", "5.0"}) {
    EXPECT_FALSE(parse_grade_number(bad, 1, 12).has_value()) << bad;
  }
  EXPECT_FALSE(parse_grade_number("12", 1, 11).has_value());
}

}  // namespace
}  // namespace gearmc
