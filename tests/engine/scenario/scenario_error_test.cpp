// Tests of scenario parsing on bad input: each kind of mistake (YAML syntax, unreadable file,
// unknown key, wrong type, out of range, missing key, not a map, empty file, duplicate key, bad
// grade or tolerance symbol, impossible gear, bad probing values) is one InputError at the exact
// line:column with the key, the value and what was expected.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "core/input_error.h"
#include "engine/scenario/scenario.h"
#include "tests/support/scenario_input.h"

namespace gearmc {
namespace {

using ::testing::HasSubstr;
using ::testing::Not;
using testing_support::expect_at;
using testing_support::kGear;
using testing_support::parse_error;

// ---- bad input: YAML syntax, files ----------------------------------------------------------

TEST(ScenarioErrorTest, YamlSyntaxErrorHasFileLineColumn) {
  // Line 4 is indented less than the map it belongs to; yaml-cpp marks column 2 (0-based 3:1).
  const InputError e = parse_error(
      "name: a\n"
      "gear:\n"
      "  teeth: 24\n"
      " module_mm: 5\n");
  expect_at(e, 4, 2);
  EXPECT_EQ(std::string(e.what()), "t.yaml:4:2: invalid YAML: end of map not found");
}

TEST(ScenarioErrorTest, UnclosedFlowSequenceIsASyntaxError) {
  const InputError e = parse_error("name: a\nseed: [1, 2\n");
  expect_at(e, 3, 1);  // yaml-cpp notices at the end of the text
  EXPECT_THAT(e.what(), HasSubstr("invalid YAML: end of sequence flow not found"));
}

TEST(ScenarioErrorTest, MissingFileNamesTheFile) {
  const std::string path = "/nonexistent/gearmc/missing_scenario.yaml";
  try {
    load_scenario_file(path);
    FAIL() << "no InputError";
  } catch (const InputError& e) {
    EXPECT_EQ(e.where().file, path);
    EXPECT_EQ(std::string(e.what()),
              path + ": cannot read the scenario file: No such file or directory");
  }
}

TEST(ScenarioErrorTest, DirectoryIsNotAScenarioFile) {
  const std::string path = std::filesystem::temp_directory_path().string();
  try {
    load_scenario_file(path);
    FAIL() << "no InputError";
  } catch (const InputError& e) {
    EXPECT_EQ(e.where().file, path);
    EXPECT_THAT(e.what(), HasSubstr(path + ": cannot read the scenario file"));
  }
}

TEST(ScenarioErrorTest, ErrorsInAFileNameThatFile) {
  const std::filesystem::path path =
      std::filesystem::temp_directory_path() / "gearmc_scenario_test_bad.yaml";
  {
    std::ofstream out(path);
    out << kGear << "  colour: red\n";
  }
  try {
    load_scenario_file(path.string());
    FAIL() << "no InputError";
  } catch (const InputError& e) {
    expect_at(e, 5, 3, path.string());
    EXPECT_THAT(e.what(), HasSubstr(path.string() + ":5:3: gear.colour: got 'colour'"));
  }
  std::filesystem::remove(path);
}

TEST(ScenarioErrorTest, SecondDocumentIsAnError) {
  const InputError e = parse_error(kGear + "---\nseed: 2\n");
  expect_at(e, 5, 1);  // the '---' that starts the second document
  EXPECT_THAT(e.what(), HasSubstr("expected one YAML document"));
}

// ---- bad input: unknown and duplicate keys --------------------------------------------------

TEST(ScenarioErrorTest, UnknownTopLevelKeyWithHint) {
  const InputError e = parse_error("name: x\nsed: 5\n" + kGear);
  expect_at(e, 2, 1);
  EXPECT_EQ(e.key(), "sed");
  EXPECT_EQ(std::string(e.what()),
            "t.yaml:2:1: sed: got 'sed', expected a known key (the top level has: name, seed, "
            "gear, tolerances, deviations, probing, stylus, run, surfaces, effects, cmm, claims, "
            "evaluation); did you mean 'seed'?");
}

TEST(ScenarioErrorTest, UnknownNestedKeyWithHintIsFoundBeforeMissingRequiredOne) {
  // `modul_mm` is a typo of the required module_mm: the typo is what gets reported.
  const InputError e = parse_error(
      "gear:\n"
      "  teeth: 24\n"
      "  modul_mm: 5.6\n"
      "  face_width_mm: 10\n");
  expect_at(e, 3, 3);
  EXPECT_EQ(e.key(), "gear.modul_mm");
  EXPECT_THAT(e.what(), HasSubstr("t.yaml:3:3: gear.modul_mm: got 'modul_mm', expected a known "
                                  "key (gear has: teeth, module_mm,"));
  EXPECT_THAT(e.what(), HasSubstr("; did you mean 'module_mm'?"));
}

TEST(ScenarioErrorTest, UnknownKeyInFlowMapAtItsColumn) {
  const InputError e = parse_error(kGear + "deviations:\n  profile: {control_point: 8}\n");
  expect_at(e, 6, 13);
  EXPECT_EQ(e.key(), "deviations.profile.control_point");
  EXPECT_THAT(e.what(), HasSubstr("did you mean 'control_points'?"));
}

TEST(ScenarioErrorTest, UnknownKeyWithoutCloseCandidateHasNoHint) {
  const InputError e = parse_error(kGear + "  colour: red\n");
  expect_at(e, 5, 3);
  EXPECT_THAT(e.what(), HasSubstr("gear.colour: got 'colour', expected a known key"));
  EXPECT_THAT(e.what(), Not(HasSubstr("did you mean")));
}

TEST(ScenarioErrorTest, DuplicateKey) {
  const InputError e = parse_error("seed: 1\n" + kGear + "seed: 2\n");
  expect_at(e, 6, 1);
  EXPECT_EQ(std::string(e.what()),
            "t.yaml:6:1: seed: expected each key only once (it is already given at line 1)");
}

// ---- bad input: wrong types -----------------------------------------------------------------

TEST(ScenarioErrorTest, TeethNotANumber) {
  const InputError e = parse_error("gear:\n  teeth: abc\n  module_mm: 5\n  face_width_mm: 9\n");
  expect_at(e, 2, 10);
  EXPECT_EQ(e.key(), "gear.teeth");
  EXPECT_EQ(std::string(e.what()),
            "t.yaml:2:10: gear.teeth: got 'abc', expected an integer from 5 to 1000 (ISO "
            "1328-1:2013 scope z 5–1000)");
}

TEST(ScenarioErrorTest, TeethNotAnInteger) {
  const InputError e = parse_error("gear:\n  teeth: 2.5\n  module_mm: 5\n  face_width_mm: 9\n");
  expect_at(e, 2, 10);
  EXPECT_EQ(std::string(e.what()),
            "t.yaml:2:10: gear.teeth: got '2.5', expected an integer from 5 to 1000 (ISO "
            "1328-1:2013 scope z 5–1000)");
}

TEST(ScenarioErrorTest, QuotedNumberIsText) {
  const InputError e = parse_error("gear:\n  teeth: \"24\"\n  module_mm: 5\n  face_width_mm: 9\n");
  expect_at(e, 2, 10);
  EXPECT_EQ(std::string(e.what()),
            "t.yaml:2:10: gear.teeth: got '24', expected an integer from 5 to 1000 (ISO "
            "1328-1:2013 scope z 5–1000), "
            "written without quotes");
}

TEST(ScenarioErrorTest, BooleanMustBeTrueOrFalse) {
  const InputError e = parse_error(kGear + "deviations:\n  random: maybe\n");
  expect_at(e, 6, 11);
  EXPECT_EQ(e.key(), "deviations.random");
  EXPECT_EQ(std::string(e.what()),
            "t.yaml:6:11: deviations.random: got 'maybe', expected true or false");
  // YAML 1.1 words are not booleans here either.
  EXPECT_THAT(parse_error(kGear + "deviations: {random: yes}\n").what(),
              HasSubstr("got 'yes', expected true or false"));
}

TEST(ScenarioErrorTest, SequenceWhereANumberIsExpected) {
  const InputError e = parse_error("gear:\n  teeth: 24\n  module_mm: [1, 2]\n  face_width_mm: 9\n");
  expect_at(e, 3, 14);
  EXPECT_EQ(std::string(e.what()),
            "t.yaml:3:14: gear.module_mm: got '[1, 2]', expected a number from 0.01 to 200 mm (ISO "
            "1328-1:2013 scope m_n 0.5–70 mm; fine-pitch gears down to 0.2 mm)");
}

TEST(ScenarioErrorTest, EmptyValueIsPlacedAtItsKey) {
  // `module_mm:` with nothing after it is null; yaml-cpp would place it on the next line.
  const InputError e = parse_error("gear:\n  teeth: 24\n  module_mm:\n  face_width_mm: 9\n");
  expect_at(e, 3, 3);
  EXPECT_EQ(std::string(e.what()),
            "t.yaml:3:3: gear.module_mm: got 'null', expected a number from 0.01 to 200 mm (ISO "
            "1328-1:2013 scope m_n 0.5–70 mm; fine-pitch gears down to 0.2 mm)");
}

TEST(ScenarioErrorTest, SectionMustBeAMap) {
  const InputError e = parse_error("gear: 5\n");
  expect_at(e, 1, 7);
  EXPECT_EQ(std::string(e.what()), "t.yaml:1:7: gear: got '5', expected a map of keys and values");
}

TEST(ScenarioErrorTest, UnknownDistributionWithHint) {
  const InputError e = parse_error(kGear + "deviations:\n  pitch: {distribution: unifrom}\n");
  expect_at(e, 6, 25);
  EXPECT_EQ(std::string(e.what()),
            "t.yaml:6:25: deviations.pitch.distribution: got 'unifrom', expected one of uniform, "
            "normal, at_tolerance; did you mean 'uniform'?");
}

TEST(ScenarioErrorTest, NormalExpressionMustBeText) {
  const InputError e = parse_error(kGear + "deviations:\n  normal_um: {L: 1}\n");
  expect_at(e, 6, 14);
  EXPECT_THAT(e.what(), HasSubstr("deviations.normal_um: got '{L: 1}', expected a muParser "
                                  "expression of L, z, tooth, side giving µm"));
  expect_at(parse_error(kGear + "deviations:\n  normal_um: \"  \"\n"), 6, 14);
  // A plain constant is an expression too.
  EXPECT_EQ(parse_scenario(kGear + "deviations: {normal_um: 5}\n", "t").normal_expression_um, "5");
}

TEST(ScenarioErrorTest, NameMustBeOnePathComponent) {
  const InputError e = parse_error("name: ../elsewhere\n" + kGear);
  expect_at(e, 1, 7);
  EXPECT_THAT(e.what(), HasSubstr("name: got '../elsewhere', expected a non-empty name"));
}

// ---- bad input: out of range ----------------------------------------------------------------

TEST(ScenarioErrorTest, TooFewTeeth) {
  const InputError e = parse_error("gear:\n  teeth: 3\n  module_mm: 5\n  face_width_mm: 9\n");
  expect_at(e, 2, 10);
  EXPECT_EQ(std::string(e.what()),
            "t.yaml:2:10: gear.teeth: got '3', expected an integer from 5 to 1000 (ISO 1328-1:2013 "
            "scope z 5–1000)");
}

TEST(ScenarioErrorTest, NegativeModule) {
  const InputError e = parse_error("gear:\n  teeth: 24\n  module_mm: -1\n  face_width_mm: 9\n");
  expect_at(e, 3, 14);
  EXPECT_EQ(std::string(e.what()),
            "t.yaml:3:14: gear.module_mm: got '-1', expected a number from 0.01 to 200 mm (ISO "
            "1328-1:2013 scope m_n 0.5–70 mm; fine-pitch gears down to 0.2 mm); a module in inches "
            "or in µm?");
}

TEST(ScenarioErrorTest, TooFewControlPoints) {
  const InputError e = parse_error(kGear + "deviations:\n  profile: {control_points: 2}\n");
  expect_at(e, 6, 29);
  EXPECT_EQ(e.key(), "deviations.profile.control_points");
  EXPECT_EQ(std::string(e.what()),
            "t.yaml:6:29: deviations.profile.control_points: got '2', expected an integer from 4 "
            "to 64 (B-spline control points of a form deviation; >= 4 for a cubic)");
}

TEST(ScenarioErrorTest, OpenAndClosedRangesAreWorded) {
  EXPECT_THAT(parse_error(kGear + "  pressure_angle_deg: 45\n").what(),
              HasSubstr("gear.pressure_angle_deg: got '45', expected a number >= 5 and < 45 deg"));
  EXPECT_THAT(parse_error(kGear + "  profile_shift: 3.5\n").what(),
              HasSubstr("gear.profile_shift: got '3.5', expected a number from -1.5 to 3"));
  EXPECT_THAT(parse_error(kGear + "  basic_rack: {root_radius: -0.1}\n").what(),
              HasSubstr("gear.basic_rack.root_radius: got '-0.1', expected a number from 0 to 1 "
                        "modules"));
  // k below 0.5 once hung `geometry` (1e-300: rejection sampling of a σ = T/k law within T).
  EXPECT_THAT(parse_error(kGear + "deviations: {k: 1e-300}\n").what(),
              HasSubstr("deviations.k: got '1e-300', expected a number from 0.5 to 100"));
  EXPECT_THAT(parse_error(kGear + "  tip_diameter_mm: .inf\n").what(),
              HasSubstr("gear.tip_diameter_mm: got '.inf', expected a number > 0 and <= 1e+05 mm"));
}

TEST(ScenarioErrorTest, SeedMustBeANonNegative64BitInteger) {
  const InputError negative = parse_error("seed: -1\n" + kGear);
  expect_at(negative, 1, 7);
  EXPECT_EQ(std::string(negative.what()),
            "t.yaml:1:7: seed: got '-1', expected an integer from 0 to 18446744073709551615");
  EXPECT_THAT(parse_error("seed: 18446744073709551616\n" + kGear).what(),
              HasSubstr("seed: got '18446744073709551616', expected an integer from 0 to"));
}

// ---- bad input: missing keys, not a map, empty ----------------------------------------------

TEST(ScenarioErrorTest, MissingGearIsReportedAtTheTopLevel) {
  const InputError e = parse_error("name: x\nseed: 2\n");
  expect_at(e, 1, 1);
  EXPECT_EQ(e.key(), "gear");
  EXPECT_THAT(e.what(), HasSubstr("t.yaml:1:1: gear: expected a map with the keys teeth, "));
  EXPECT_THAT(e.what(), HasSubstr("(required key is missing)"));
}

TEST(ScenarioErrorTest, MissingTeethIsReportedAtTheGearKey) {
  const InputError e = parse_error("seed: 1\ngear:\n  module_mm: 5.6\n  face_width_mm: 10\n");
  expect_at(e, 2, 1);
  EXPECT_EQ(e.key(), "gear.teeth");
  EXPECT_EQ(std::string(e.what()),
            "t.yaml:2:1: gear.teeth: expected an integer from 5 to 1000 (ISO 1328-1:2013 scope z "
            "5–1000) (required key "
            "is missing)");
}

TEST(ScenarioErrorTest, TopLevelNotAMap) {
  const InputError list = parse_error("- gear\n- seed\n");
  expect_at(list, 1, 1);
  EXPECT_EQ(std::string(list.what()),
            "t.yaml:1:1: got '[gear, seed]', expected a map of scenario keys (name, seed, gear, "
            "tolerances, deviations, probing, stylus, run, surfaces, effects, claims, "
            "evaluation)");
  const InputError scalar = parse_error("hello\n");
  expect_at(scalar, 1, 1);
  EXPECT_THAT(scalar.what(), HasSubstr("got 'hello', expected a map of scenario keys"));
}

TEST(ScenarioErrorTest, EmptyFile) {
  for (const std::string text : {"", "\n", "# only a comment\n"}) {
    const InputError e = parse_error(text);
    expect_at(e, 1, 1);
    EXPECT_THAT(e.what(), HasSubstr("but the scenario is empty")) << text;
  }
}

// ---- bad input: tolerances and gear validity ------------------------------------------------

TEST(ScenarioErrorTest, UnknownToleranceSymbolWithHint) {
  const InputError e =
      parse_error(kGear + "tolerances:\n  overrides_um:\n    F_r: 50\n    F_rr: 40\n");
  expect_at(e, 8, 5);
  EXPECT_EQ(e.key(), "tolerances.overrides_um.F_rr");
  EXPECT_EQ(std::string(e.what()),
            "t.yaml:8:5: tolerances.overrides_um.F_rr: got 'F_rr', expected a tolerance symbol "
            "of gost_1643_81 (F_r, F_p, f_pt, f_pb, f_f, F_beta, E_Hs, T_H); did you mean "
            "'F_r'?");
}

TEST(ScenarioErrorTest, ToleranceSymbolOfTheOtherStandard) {
  const InputError e = parse_error(kGear +
                                   "tolerances:\n"
                                   "  standard: iso_1328_1_2013\n"
                                   "  grade: 6\n"
                                   "  overrides_um: {f_pb: 9}\n");
  expect_at(e, 8, 18);
  EXPECT_THAT(e.what(), HasSubstr("expected a tolerance symbol of iso_1328_1_2013 (F_r, F_p, "
                                  "f_p, F_alpha, f_H_alpha, f_f_alpha, F_beta, f_H_beta, "
                                  "f_f_beta, E_Hs, T_H); 'f_pb' is a symbol of gost_1643_81"));
}

TEST(ScenarioErrorTest, ToleranceValuesMustBePositive) {
  const InputError zero = parse_error(kGear + "tolerances:\n  overrides_um: {f_f: 0}\n");
  expect_at(zero, 6, 23);
  EXPECT_EQ(std::string(zero.what()),
            "t.yaml:6:23: tolerances.overrides_um.f_f: got '0', expected a number from 0.5 to "
            "10000 µm (ISO 1328-1:2013 class 1 (finest) gives >= 1.3 µm, class 11 at d 15000 mm "
            "about 1300 µm); a value in mm? (0.02 mm = 20 µm)");
  const InputError negative = parse_error(kGear + "tolerances:\n  overrides_um: {E_Hs: -110}\n");
  EXPECT_THAT(negative.what(),
              HasSubstr("tolerances.overrides_um.E_Hs: got '-110', expected a number from 0 to "
                        "10000 µm (GOST 1643-81 least rack shifts"));
}

TEST(ScenarioErrorTest, UnknownStandardWithHint) {
  const InputError e = parse_error(kGear + "tolerances: {standard: gost_1643_18}\n");
  expect_at(e, 5, 24);
  EXPECT_EQ(std::string(e.what()),
            "t.yaml:5:24: tolerances.standard: got 'gost_1643_18', expected one of gost_1643_81, "
            "iso_1328_1_2013; did you mean 'gost_1643_81'?");
}

TEST(ScenarioErrorTest, GradeFormatDependsOnTheStandard) {
  for (const std::string grade : {"6-5", "13", "6-5-13", "0-5-5", "6-5-5-5", "6.5", "06-5-5"}) {
    const InputError e = parse_error(kGear + "tolerances:\n  grade: \"" + grade + "\"\n");
    expect_at(e, 6, 10);
    EXPECT_THAT(e.what(), HasSubstr("tolerances.grade: got '" + grade +
                                    "', expected a GOST 1643-81 accuracy grade: 'K-S-C'"));
  }
  for (const std::string grade : {"6-5-5", "12", "0"}) {
    const InputError e = parse_error(kGear +
                                     "tolerances:\n"
                                     "  standard: iso_1328_1_2013\n"
                                     "  grade: " +
                                     grade + "\n");
    expect_at(e, 7, 10);
    EXPECT_THAT(e.what(),
                HasSubstr("tolerances.grade: got '" + grade +
                          "', expected an ISO 1328-1:2013 flank tolerance class, an integer "
                          "from 1 to 11"));
  }
}

TEST(ScenarioErrorTest, IsoNeedsAGrade) {
  const InputError e = parse_error(kGear + "tolerances:\n  standard: iso_1328_1_2013\n");
  expect_at(e, 5, 1);
  EXPECT_EQ(e.key(), "tolerances.grade");
  EXPECT_THAT(e.what(), HasSubstr("(required key is missing)"));
}

TEST(ScenarioErrorTest, ImpossibleGearIsReportedAtTheGearKey) {
  // d_b = 24 * 5.6 * cos 20° = 126.3 mm: a tip diameter of 120 mm leaves no involute.
  const InputError e = parse_error("seed: 3\n" + kGear + "  tip_diameter_mm: 120\n");
  expect_at(e, 2, 1);
  EXPECT_EQ(e.key(), "gear");
  EXPECT_THAT(e.what(), HasSubstr("t.yaml:2:1: gear: expected parameters that make a gear, but "
                                  "tip diameter 120 mm is not above the base diameter"));
}

TEST(ScenarioErrorTest, BadProbingValues) {
  expect_at(parse_error(kGear + "probing:\n  teeth: [1, 25]\n"), 6, 14);  // tooth 25 of 24
  expect_at(parse_error(kGear + "probing:\n  teeth: [3, 3]\n"), 6, 14);   // listed twice
  expect_at(parse_error(kGear + "probing:\n  flanks: left\n"), 6, 11);
  expect_at(parse_error(kGear + "probing:\n  margin_fraction: 0.5\n"), 6, 20);
  expect_at(parse_error(kGear + "probing:\n  points_along_profile: 0\n"), 6, 25);
  expect_at(parse_error(kGear + "probing:\n  profile_spacing: angle\n"), 6, 20);
  expect_at(parse_error(kGear + "stylus: {radius_mm: -1}\n"), 5, 21);
  expect_at(parse_error(kGear + "run: {gears: 0}\n"), 5, 14);
  // A stem as thick as the ball (diameter 1 mm for R 0.5 mm), and an unknown axis.
  const InputError thick = parse_error(kGear + "stylus: {radius_mm: 0.5, shaft_diameter_mm: 1}\n");
  expect_at(thick, 5, 45);
  EXPECT_NE(std::string(thick.what()).find("a shaft thinner than the ball (diameter 1 mm)"),
            std::string::npos)
      << thick.what();
  expect_at(parse_error(kGear + "stylus: {shaft_diameter_mm: 0.3, shaft_axis: x}\n"), 5, 46);
  const InputError typo = parse_error(kGear + "stylus: {radius: 1}\n");
  EXPECT_NE(std::string(typo.what()).find("did you mean 'radius_mm'"), std::string::npos)
      << typo.what();
}

}  // namespace
}  // namespace gearmc
