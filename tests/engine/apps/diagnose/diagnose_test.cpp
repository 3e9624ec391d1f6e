// Tests of the whole diagnosis (engine/apps/diagnose, docs/diagnosis.md) on readings in which one
// effect is hidden: readings simulated with simulate_readings from a truth scenario = the
// built-in reference (P1's gear and 10 × 5 grid on every flank, nominal master) + ONE effect
// + probing noise σ 0.3 µm, diagnosed against the baseline model (the reference with noise
// 0.3 µm only). The truth reaches the diagnosis only through the readings. Reference values are
// the truth's own parameters (the battery's sizes at 1×, docs/diagnosis.md); every test uses fixed
// seeds, so each assertion is deterministic (seed 1 of the simulation, seed 1 of the null
// simulation). Also: readings of another gear are refused, null datasets name nothing, ambiguous
// effects are said to be, and the JSON is the same for the same seed. The diagnosis's parts:
// diagnose_{tools,model,selection,robustness,point_law,report_data}_test.cpp.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include <tbb/global_control.h>

#include "core/input_error.h"
#include "engine/apps/diagnose/diagnosis.h"
#include "engine/apps/diagnose/diagnosis_json.h"
#include "engine/apps/diagnose/point_law_stage.h"
#include "tests/support/diagnose_readings.h"
#include "tests/support/temp_paths.h"

using ::gearmc::testing_support::fresh_temp_path;

namespace gearmc {
namespace {

using testing_support::baseline;
using testing_support::contains;
using testing_support::hidden;
using testing_support::kNoiseUm;
using testing_support::master_readings;
using testing_support::value;
using testing_support::with_effects;

TEST(DiagnoseInput, RowsOutsideTheModelsGearOrPlanAreRefused) {
  // The reference gear has 24 teeth and a 10 × 5 grid (i 0…9, j 0…4).
  const Readings good = master_readings(reference_scenario());
  auto refused = [&](auto change, const std::string& expect) {
    Readings r = good;
    change(r.rows[3]);
    try {
      diagnose(baseline(), r);
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(expect), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("row 4"), std::string::npos) << e.what();
      return;
    }
    ADD_FAILURE() << "accepted: " << expect;
  };
  refused([](ReadingRow& row) { row.tooth = 1000; }, "a tooth in 1 … 24");
  refused([](ReadingRow& row) { row.i = 10; }, "i in 0 … 9");
  refused([](ReadingRow& row) { row.j = 7; }, "j in 0 … 4");
  refused([](ReadingRow& row) { row.c += 1e8 * row.n; }, "within ±1e+09 µm");
  refused([](ReadingRow& row) { row.c += 1e300 * row.n; }, "within ±1e+09 µm");
  // A nominal point 5·10¹⁷ mm off the gear (and its stylus centre with it, so the deviation is
  // fine): the effects' columns would take it as a lever.
  refused(
      [](ReadingRow& row) {
        row.p.z() += 5e17;
        row.c.z() += 5e17;
      },
      "a nominal point on the model's gear");
}

// A file whose labels are all shifted by one constant (1-based grid indices, 0-based teeth) gets
// one message saying so, with the fix, at its first row out of range — not a refusal of that row
// alone as if it were a typo.
TEST(DiagnoseInput, LabelsShiftedAsAWholeAreNamedAsSuch) {
  const Readings good = master_readings(reference_scenario());
  const auto message = [&](auto change) {
    Readings r = good;
    for (ReadingRow& row : r.rows) change(row);
    try {
      diagnose(baseline(), r);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  const std::string one_based = message([](ReadingRow& row) {
    ++row.i;
    ++row.j;
  });
  EXPECT_NE(one_based.find("i: got '10', expected a profile index i in 0 … 9"), std::string::npos)
      << one_based;
  EXPECT_NE(one_based.find("every i of this file lies in 1 … 10: the whole column looks shifted "
                           "by +1 (1-based indices? gearmc counts i and j from 0) — subtract 1 "
                           "from every i; and every j of this file lies in 1 … 5"),
            std::string::npos)
      << one_based;
  const std::string zero_based = message([](ReadingRow& row) { --row.tooth; });
  EXPECT_NE(zero_based.find("every tooth of this file lies in 0 … 23: the whole column looks "
                            "shifted by -1 (0-based teeth? gearmc numbers teeth from 1)"),
            std::string::npos)
      << zero_based;
  // A shift that no single constant undoes is refused row by row as before.
  const std::string spread = message([](ReadingRow& row) { row.i *= 2; });
  EXPECT_EQ(spread.find("whole column"), std::string::npos) << spread;
  EXPECT_NE(spread.find("i in 0 … 9"), std::string::npos) << spread;
}

// --- The diagnosis on readings with one hidden effect -----------------------------------------

struct HiddenEffect {
  const char* yaml;
  const char* name;
  std::vector<std::pair<const char*, double>> truth;  // parameter or coefficient → true value
};

// gtest prints parameters in test names (ctest): the effect's name, not the struct's bytes.
void PrintTo(const HiddenEffect& h, std::ostream* os) { *os << h.name; }

class DiagnoseHiddenEffect : public ::testing::TestWithParam<HiddenEffect> {};

TEST_P(DiagnoseHiddenEffect, NamesFitsAndClosesTheGap) {
  const HiddenEffect& h = GetParam();
  const Diagnosis d = diagnose(baseline(), hidden(h.yaml));
  EXPECT_TRUE(d.gap_detected);
  EXPECT_EQ(d.named_effect_text(), h.name);
  ASSERT_FALSE(d.effects.empty());
  EXPECT_EQ(d.effects.size(), 1u);
  const FittedEffect& e = d.effects.front();
  for (const auto& [parameter, truth] : h.truth) {
    const FittedValue& v = value(e, parameter);
    EXPECT_TRUE(v.estimable) << parameter;
    EXPECT_LE(std::abs(v.value - truth), 3.0 * v.std_error)
        << parameter << " = " << v.value << " ± " << v.std_error << ", truth " << truth;
  }
  EXPECT_EQ(spelling(d.noise.source), "model");
  EXPECT_DOUBLE_EQ(d.noise.sigma_um, kNoiseUm);
  EXPECT_LE(d.gap_after.rms_um, 1.1 * kNoiseUm);
  EXPECT_LE(d.held_out_rms_um, 1.1 * kNoiseUm);
  EXPECT_GT(d.gap_before.rms_um, 1.3 * kNoiseUm);
  EXPECT_GE(d.explained_fraction, 0.95);
  EXPECT_FALSE(d.unexplained_structure);
  // Cluster-aware evidence: after the fit the residuals do not differ from a simulation of the
  // model (flank swaps); the teeth bootstrap interval brackets the RMS after the fit. (Before the
  // fit the energy test compares marginal laws only: it is strong for a shift — the stylus radius
  // case below and DiagnosePointLaw — but weak for zero-mean patterns such as drift along x,
  // whose marginal is a slight widening: p 0.015 there, so it is not asserted for every effect.)
  EXPECT_GT(d.gap_after.energy_p, 0.01);
  EXPECT_LE(d.gap_after.rms_lo_um, d.gap_after.rms_um);
  EXPECT_GE(d.gap_after.rms_hi_um, d.gap_after.rms_um);
  EXPECT_LE(d.gap_after.rms_lo_um, 1.1 * kNoiseUm);
}

// Truth values from the effects' definitions: lobing p(φ) = 0.75 cos(6(φ − 90°)), so its
// coefficients (candidates.h) are cos_6 = 0.75 cos 540° = −0.75, sin_6 = 0, phase 90° ≡ 30°
// modulo the 60° period; the others are the parameters themselves (scale z and drift z are not
// observable on a spur gear).
INSTANTIATE_TEST_SUITE_P(
    Battery, DiagnoseHiddenEffect,
    ::testing::Values(
        HiddenEffect{"probe_lobing: {harmonics: [{order: 6, amplitude_um: 0.75, phase_deg: 90}]}\n",
                     "probe_lobing",
                     {{"amplitude_6_um", 0.75},
                      {"phase_6_deg", 30.0},
                      {"cos_6_um", -0.75},
                      {"sin_6_um", 0.0},
                      {"cos_3_um", 0.0},
                      {"sin_3_um", 0.0},
                      {"pretravel_um", 0.0}}},
        HiddenEffect{"scale: {x_ppm: 10}\n", "scale", {{"x_ppm", 10.0}, {"y_ppm", 0.0}}},
        HiddenEffect{"drift: {x_um: 1}\n", "drift", {{"x_um", 1.0}, {"y_um", 0.0}}},
        HiddenEffect{
            "eccentricity: {x_um: 3, y_um: 4}\n", "eccentricity", {{"x_um", 3.0}, {"y_um", 4.0}}},
        HiddenEffect{"stylus_radius: {error_um: 0.5}\n", "stylus_radius", {{"error_um", 0.5}}}),
    [](const ::testing::TestParamInfo<HiddenEffect>& p) { return std::string(p.param.name); });

TEST(Diagnose, NullDatasetsNameNothing) {
  for (std::uint64_t seed : {1, 2}) {
    const Diagnosis d = diagnose(baseline(), hidden("", seed));
    EXPECT_FALSE(d.gap_detected) << "seed " << seed;
    EXPECT_EQ(d.named_effect_text(), "none") << "seed " << seed;
    EXPECT_TRUE(d.effects.empty());
    EXPECT_FALSE(d.unexplained_structure);
    EXPECT_LE(d.gap_before.rms_um, 1.1 * kNoiseUm);
    EXPECT_GT(d.gap_before.energy_p, 0.01) << "seed " << seed;
    EXPECT_LE(d.gap_before.rms_lo_um, kNoiseUm * 1.02);
    EXPECT_GE(d.gap_before.rms_hi_um, kNoiseUm * 0.98);
  }
}

TEST(Diagnose, StructureLeftAfterAPartialLibraryFitLeadsTheVerdict) {
  // Lobing (6 lobes, 1.5 µm: in the library) plus a waviness across the face outside it,
  // 0.6 sin(2π z / 20 mm) µm: the lobing explains most of the excess variance, but structure
  // remains along the face, so the verdict is "unexplained" with probe_lobing as the partial
  // explanation and face_position as the axis (the waviness varies with z alone, i.e. with the
  // section index j). Seeds 1.
  Scenario truth = with_effects(
      "probe_lobing: {harmonics: [{order: 6, amplitude_um: 1.5, phase_deg: 90}]}\n"
      "noise: {sigma_um: 0.3}\n");
  truth.normal_expression_um = "0.6*sin(2*_pi*z/20)";
  const Diagnosis d = diagnose(baseline(), master_readings(truth));
  EXPECT_TRUE(d.gap_detected);
  EXPECT_TRUE(d.unexplained_structure);
  EXPECT_EQ(d.named_effect_text(), "unexplained");
  EXPECT_GE(d.explained_fraction, 0.5);
  EXPECT_EQ(d.partially_explained_by, "probe_lobing");
  EXPECT_EQ(d.unexplained_along.axis, "face_position");
  EXPECT_LT(d.unexplained_along.p_value, 1e-6);
  ASSERT_FALSE(d.notes.empty());
  EXPECT_NE(d.notes.front().find("structure remains"), std::string::npos);
}

TEST(Diagnose, AnEffectOutsideTheLibraryIsNotNamedWithConfidence) {
  // A waviness across the face, the same on every flank: 0.8 sin(2π z / 20 mm) µm (normal_um).
  // No library signature varies with z alone, so "unexplained structure remains" is the answer.
  Scenario truth = with_effects("noise: {sigma_um: 0.3}\n");
  truth.normal_expression_um = "0.8*sin(2*_pi*z/20)";
  const Diagnosis d = diagnose(baseline(), master_readings(truth));
  EXPECT_TRUE(d.gap_detected);
  EXPECT_EQ(d.named_effect_text(), "unexplained");
  EXPECT_TRUE(d.unexplained_structure);
  EXPECT_LT(d.explained_fraction, 0.5);
  EXPECT_GT(d.gap_after.rms_um, 1.5 * kNoiseUm);
  // Constant along each profile scan, so the second differences show no extra spread: neither a
  // larger noise nor a step quantisation is named for it.
  EXPECT_TRUE(d.point_law.ran);
  EXPECT_EQ(d.point_law.chosen, 0);
  EXPECT_GT(d.point_law.white_p, 0.01);
}

TEST(Diagnose, ConstantPretravelAndStylusRadiusAreAmbiguous) {
  // A pure constant pre-travel p0 = 0.5 µm reads exactly like a stylus radius 0.5 µm too large.
  const Diagnosis d = diagnose(baseline(), hidden("probe_lobing: {pretravel_um: 0.5}\n"));
  ASSERT_TRUE(d.named_effect_text() == "stylus_radius" || d.named_effect_text() == "probe_lobing")
      << d.named_effect_text();
  const std::string other =
      d.named_effect_text() == "stylus_radius" ? "probe_lobing" : "stylus_radius";
  EXPECT_TRUE(contains(d.ambiguous_with, other));
  const FittedEffect& e = d.effects.front();
  const auto it = std::find_if(e.ambiguous.begin(), e.ambiguous.end(),
                               [&](const Ambiguity& a) { return a.with == other; });
  ASSERT_NE(it, e.ambiguous.end());
  EXPECT_NEAR(it->signal_correlation, 1.0, 1e-9);
  EXPECT_NE(it->separate_by.find("sphere"), std::string::npos);
  // The fitted constant is the pre-travel (or radius error) itself.
  const FittedValue& v =
      value(e, d.named_effect_text() == "stylus_radius" ? "error_um" : "pretravel_um");
  EXPECT_LE(std::abs(v.value - 0.5), 3.0 * v.std_error);
}

TEST(Diagnose, ThermalExpansionIsAmbiguousWithScaleAndSaysMeasureTheTemperature) {
  // ΔT_w = 1 K on steel (11.5 ppm/K) is an isotropic scale on a spur gear (n_z = 0).
  const Diagnosis d = diagnose(baseline(), hidden("thermal_expansion: {workpiece_delta_t_k: 1}\n"));
  EXPECT_EQ(d.named_effect_text(), "thermal_expansion");
  EXPECT_TRUE(contains(d.ambiguous_with, "scale"));
  const FittedEffect& e = d.effects.front();
  const FittedValue& v = value(e, "workpiece_delta_t_k");
  EXPECT_LE(std::abs(v.value - 1.0), 3.0 * v.std_error);
  for (const Ambiguity& a : e.ambiguous) {
    if (a.with == "scale") {
      EXPECT_NE(a.separate_by.find("temperature"), std::string::npos);
    }
  }
}

// The null replicates run in parallel (oneTBB); each draws from its own counter-based stream into
// its own slot, so one thread and every thread give the same diagnosis.json byte for byte.
TEST(Diagnose, OneThreadAndAllThreadsGiveTheSameDiagnosis) {
  const Readings readings = hidden(
      "probe_lobing: {harmonics: [{order: 6, amplitude_um: 0.75, phase_deg: 90}]}\n"
      "drift: {x_um: 0.4, y_um: -0.3, z_um: 0}\n");
  std::string serial;
  {
    const tbb::global_control one(tbb::global_control::max_allowed_parallelism, 1);
    serial = diagnosis_json(diagnose(baseline(), readings));
  }
  const std::string parallel = diagnosis_json(diagnose(baseline(), readings));
  EXPECT_EQ(serial, parallel);
  EXPECT_GT(serial.size(), 1000u);  // a whole diagnosis, not an empty one
}

TEST(Diagnose, SameSeedSameResultAndTheJsonOfInterfaceMd) {
  const Readings readings =
      hidden("probe_lobing: {harmonics: [{order: 6, amplitude_um: 0.75, phase_deg: 90}]}\n");
  const std::string first = diagnosis_json(diagnose(baseline(), readings));
  const std::string second = diagnosis_json(diagnose(baseline(), readings));
  EXPECT_EQ(first, second);

  const auto dir = fresh_temp_path("diagnose_test");
  std::filesystem::create_directories(dir);
  write_diagnosis_json((dir / "diagnosis.json").string(), diagnose(baseline(), readings));
  std::ifstream in(dir / "diagnosis.json");
  std::stringstream text;
  text << in.rdbuf();
  EXPECT_EQ(text.str(), first);
  const nlohmann::json j = nlohmann::json::parse(first);
  // docs/formats.md: the keys diagnosis.json has at least.
  EXPECT_TRUE(j.at("gap_detected").get<bool>());
  EXPECT_EQ(j.at("named_effect"), "probe_lobing");
  EXPECT_TRUE(j.at("ambiguous_with").is_array());
  const nlohmann::json& e = j.at("effects").at(0);
  EXPECT_EQ(e.at("name"), "probe_lobing");
  EXPECT_NEAR(e.at("parameters").at("amplitude_6_um").get<double>(), 0.75, 0.03);
  EXPECT_GT(e.at("std_errors").at("amplitude_6_um").get<double>(), 0.0);
  EXPECT_TRUE(e.at("evidence").is_object());
  for (const char* gap : {"gap_before", "gap_after"}) {
    EXPECT_TRUE(j.at(gap).at("rms_um").is_number());
    EXPECT_TRUE(j.at(gap).at("ks").is_number());
  }
  EXPECT_DOUBLE_EQ(j.at("noise_floor_um").get<double>(), kNoiseUm);
  EXPECT_EQ(j.at("spectrum").at("before_um").size(), 13u);
  // Beyond docs/formats.md: the fitted floor, how parameters are meant, the point-law stage and the
  // cluster-aware evidence.
  EXPECT_DOUBLE_EQ(j.at("noise_floor_after_um").get<double>(), kNoiseUm);
  EXPECT_EQ(e.at("parameters_are"), "increments");
  EXPECT_TRUE(j.at("point_law").at("ran").get<bool>());
  EXPECT_EQ(j.at("point_law").at("chosen"), "none");
  EXPECT_EQ(j.at("point_law").at("hypotheses").size(), 4u);
  for (const char* gap : {"gap_before", "gap_after"}) {
    EXPECT_TRUE(j.at(gap).at("energy_p").is_number());
    EXPECT_EQ(j.at(gap).at("rms_ci95_um").size(), 2u);
  }
  std::filesystem::remove_all(dir);
}

TEST(Diagnose, TheLobingOrderStandsOutOfTheNullBandOfTheSpectrum) {
  const Diagnosis d = diagnose(
      baseline(),
      hidden("probe_lobing: {harmonics: [{order: 6, amplitude_um: 0.75, phase_deg: 90}]}\n"));
  ASSERT_EQ(d.spectrum_before_um.size(), 13u);
  // Before: order 6 carries the 0.75 µm lobing, far above its null band; after: within the band
  // at every order but a few (5 % of orders exceed a 95 % band by chance).
  EXPECT_NEAR(d.spectrum_before_um[6], 0.75, 0.05);
  EXPECT_GT(d.spectrum_before_um[6], 5.0 * d.spectrum_null95_before_um[6]);
  int above = 0;
  for (int k = 0; k <= 12; ++k) above += d.spectrum_after_um[k] > d.spectrum_null95_after_um[k];
  EXPECT_LE(above, 2);
}

}  // namespace
}  // namespace gearmc
