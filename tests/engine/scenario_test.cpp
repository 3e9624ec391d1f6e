// Tests of scenario parsing: the reference scenario file parses to P1's gear and tolerances
// (Pechenin, Rusanov, Bolotov 2018, Table 1), defaults and every section's keys are read, and each
// kind of bad input (YAML syntax, unreadable file, unknown key, wrong type, out of range, missing
// key, not a map, empty file, duplicate key, bad grade or tolerance symbol, impossible gear) is
// one InputError at the exact line:column with the key, the value and what was expected.
// Also the "did you mean" search, InputError's message format and the YAML reader helpers.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>

#include "engine/io/input_error.h"
#include "engine/io/yaml_reader.h"
#include "engine/scenario/scenario.h"

#ifndef GEARMC_SOURCE_DIR
#error "GEARMC_SOURCE_DIR (the repository root) must be defined"
#endif

namespace gearmc {
namespace {

using ::testing::HasSubstr;
using ::testing::Not;

// The smallest valid gear section (P1's gear without the profile shift).
const std::string kGear =
    "gear:\n"
    "  teeth: 24\n"
    "  module_mm: 5.6\n"
    "  face_width_mm: 78.89\n";

// The InputError that parsing `text` throws (a test failure when it throws none).
InputError parse_error(const std::string& text, const std::string& source = "t.yaml") {
  try {
    parse_scenario(text, source);
  } catch (const InputError& e) {
    return e;
  }
  ADD_FAILURE() << "no InputError for:\n" << text;
  return InputError({}, "no error");
}

void expect_at(const InputError& e, int line, int column, const std::string& file = "t.yaml") {
  EXPECT_EQ(e.where().file, file) << e.what();
  EXPECT_EQ(e.where().line, line) << e.what();
  EXPECT_EQ(e.where().column, column) << e.what();
}

// ---- the reference scenario -----------------------------------------------------------------

TEST(ScenarioTest, ReferenceFileParsesToP1Values) {
  const std::string path = std::string(GEARMC_SOURCE_DIR) + "/scenarios/p1_reference.yaml";
  const Scenario s = load_scenario_file(path);
  EXPECT_EQ(s.name, "p1_reference");
  EXPECT_EQ(s.source_path, path);
  std::ifstream in(path);
  std::ostringstream text;
  text << in.rdbuf();
  EXPECT_EQ(s.source_text, text.str());
  EXPECT_EQ(s.seed, 1u);

  // P1 Table 1: z 24, m 5.6 mm, alpha 20 deg, x 0.90116, b 78.89 mm, ISO 53 profile A rack.
  EXPECT_EQ(s.gear.teeth, 24);
  EXPECT_DOUBLE_EQ(s.gear.module_mm, 5.6);
  EXPECT_DOUBLE_EQ(s.gear.pressure_angle_deg, 20.0);
  EXPECT_DOUBLE_EQ(s.gear.profile_shift, 0.90116);
  EXPECT_DOUBLE_EQ(s.gear.face_width_mm, 78.89);
  EXPECT_DOUBLE_EQ(s.gear.rack.addendum, 1.0);
  EXPECT_DOUBLE_EQ(s.gear.rack.dedendum, 1.25);
  EXPECT_DOUBLE_EQ(s.gear.rack.root_radius, 0.38);
  EXPECT_FALSE(s.gear.tip_diameter_mm.has_value());
  EXPECT_FALSE(s.gear.root_diameter_mm.has_value());

  // P1 Table 1 tolerances, GOST 1643-81 grade 6-5-5.
  EXPECT_EQ(s.tolerances.standard, ToleranceStandard::kGost1643_81);
  EXPECT_EQ(s.tolerances.grade, "6-5-5");
  const std::map<ToleranceKind, double> expected_overrides = {
      {ToleranceKind::kRunout, 50.0},
      {ToleranceKind::kBasePitch, 9.0},
      {ToleranceKind::kProfileTotal, 8.0},
      {ToleranceKind::kThicknessUpper, 110.0},
      {ToleranceKind::kThicknessTolerance, 100.0}};
  EXPECT_EQ(s.tolerances.overrides_um, expected_overrides);

  EXPECT_TRUE(s.deviations.random);
  for (const DeviationDistribution* law :
       {&s.deviations.eccentricity, &s.deviations.pitch, &s.deviations.thickness,
        &s.deviations.profile_slope, &s.deviations.profile_form, &s.deviations.helix_slope,
        &s.deviations.helix_form}) {
    EXPECT_EQ(law->law, DeviationDistribution::Law::kUniform);
    EXPECT_DOUBLE_EQ(law->k, 3.0);
  }
  EXPECT_EQ(s.deviations.profile_form_control_points, 8);
  EXPECT_EQ(s.deviations.helix_form_control_points, 6);
  EXPECT_TRUE(s.normal_expression_um.empty());
}

TEST(ScenarioTest, ParseScenarioKeepsTextAndSourceName) {
  const std::string text = "name: mine\nseed: 42\n" + kGear;
  const Scenario s = parse_scenario(text, "<memory>");
  EXPECT_EQ(s.name, "mine");
  EXPECT_EQ(s.seed, 42u);
  EXPECT_EQ(s.source_path, "<memory>");
  EXPECT_EQ(s.source_text, text);
}

// ---- defaults and every key -----------------------------------------------------------------

TEST(ScenarioTest, DefaultsOfAMinimalScenario) {
  const Scenario s = parse_scenario(kGear, "some/dir/my_case.yaml");
  EXPECT_EQ(s.name, "my_case");  // the file's stem
  EXPECT_EQ(s.seed, 1u);
  EXPECT_DOUBLE_EQ(s.gear.pressure_angle_deg, 20.0);
  EXPECT_DOUBLE_EQ(s.gear.profile_shift, 0.0);
  const BasicRack iso53;
  EXPECT_DOUBLE_EQ(s.gear.rack.addendum, iso53.addendum);
  EXPECT_DOUBLE_EQ(s.gear.rack.dedendum, iso53.dedendum);
  EXPECT_DOUBLE_EQ(s.gear.rack.root_radius, iso53.root_radius);
  EXPECT_EQ(s.tolerances.standard, ToleranceStandard::kGost1643_81);
  EXPECT_EQ(s.tolerances.grade, "6-5-5");
  EXPECT_TRUE(s.tolerances.overrides_um.empty());
  EXPECT_TRUE(s.deviations.random);
  EXPECT_EQ(s.deviations.pitch.law, DeviationDistribution::Law::kUniform);
  EXPECT_DOUBLE_EQ(s.deviations.pitch.k, 3.0);
  EXPECT_EQ(s.deviations.profile_form_control_points, 8);
  EXPECT_EQ(s.deviations.helix_form_control_points, 6);
  EXPECT_TRUE(s.normal_expression_um.empty());
}

TEST(ScenarioTest, ReadsEveryGearKey) {
  const Scenario s = parse_scenario(
      "gear:\n"
      "  teeth: 30\n"
      "  module_mm: 2\n"
      "  pressure_angle_deg: 25\n"
      "  profile_shift: -0.2\n"
      "  face_width_mm: 20\n"
      "  tip_diameter_mm: 63.5\n"
      "  root_diameter_mm: 54.5\n"
      "  basic_rack: {addendum: 1, dedendum: 1.4, root_radius: 0.25}\n"
      "tolerances: {standard: iso_1328_1_2013, grade: 6}\n",  // outside the GOST table held
      "t.yaml");
  EXPECT_EQ(s.gear.teeth, 30);
  EXPECT_DOUBLE_EQ(s.gear.module_mm, 2.0);
  EXPECT_DOUBLE_EQ(s.gear.pressure_angle_deg, 25.0);
  EXPECT_DOUBLE_EQ(s.gear.profile_shift, -0.2);
  EXPECT_DOUBLE_EQ(s.gear.face_width_mm, 20.0);
  EXPECT_EQ(s.gear.tip_diameter_mm, 63.5);
  EXPECT_EQ(s.gear.root_diameter_mm, 54.5);
  EXPECT_DOUBLE_EQ(s.gear.rack.dedendum, 1.4);
  EXPECT_DOUBLE_EQ(s.gear.rack.root_radius, 0.25);
}

TEST(ScenarioTest, ReadsDeviationLawsGroupOverridesAndExpression) {
  const Scenario s = parse_scenario(kGear +
                                        "deviations:\n"
                                        "  random: false\n"
                                        "  distribution: normal\n"
                                        "  k: 2\n"
                                        "  pitch: {distribution: uniform}\n"
                                        "  thickness: {k: 4}\n"
                                        "  profile: {k: 2.5, control_points: 12}\n"
                                        "  helix: {distribution: uniform, control_points: 4}\n"
                                        "  normal_um: \"2*sin(2*_pi*L/5) + 0.1*(z-39.445)\"\n",
                                    "t.yaml");
  const DeviationModel& d = s.deviations;
  using Law = DeviationDistribution::Law;
  EXPECT_FALSE(d.random);
  EXPECT_EQ(d.eccentricity.law, Law::kNormal);  // the default law
  EXPECT_DOUBLE_EQ(d.eccentricity.k, 2.0);
  EXPECT_EQ(d.pitch.law, Law::kUniform);  // law overridden, k inherited
  EXPECT_DOUBLE_EQ(d.pitch.k, 2.0);
  EXPECT_EQ(d.thickness.law, Law::kNormal);  // k overridden, law inherited
  EXPECT_DOUBLE_EQ(d.thickness.k, 4.0);
  for (const DeviationDistribution* law : {&d.profile_slope, &d.profile_form}) {
    EXPECT_EQ(law->law, Law::kNormal);
    EXPECT_DOUBLE_EQ(law->k, 2.5);
  }
  for (const DeviationDistribution* law : {&d.helix_slope, &d.helix_form}) {
    EXPECT_EQ(law->law, Law::kUniform);
    EXPECT_DOUBLE_EQ(law->k, 2.0);
  }
  EXPECT_EQ(d.profile_form_control_points, 12);
  EXPECT_EQ(d.helix_form_control_points, 4);
  EXPECT_EQ(s.normal_expression_um, "2*sin(2*_pi*L/5) + 0.1*(z-39.445)");
}

TEST(ScenarioTest, ReadsIsoTolerancesAndGrades) {
  const Scenario iso = parse_scenario(kGear +
                                          "tolerances:\n"
                                          "  standard: iso_1328_1_2013\n"
                                          "  grade: 5\n"
                                          "  overrides_um: {f_H_alpha: 6.5, F_p: 20, f_p: 5}\n",
                                      "t.yaml");
  EXPECT_EQ(iso.tolerances.standard, ToleranceStandard::kIso1328_1_2013);
  EXPECT_EQ(iso.tolerances.grade, "5");
  const std::map<ToleranceKind, double> expected = {{ToleranceKind::kProfileSlope, 6.5},
                                                    {ToleranceKind::kCumulativePitch, 20.0},
                                                    {ToleranceKind::kSinglePitch, 5.0}};
  EXPECT_EQ(iso.tolerances.overrides_um, expected);

  EXPECT_EQ(parse_scenario(kGear + "tolerances: {grade: 7}\n", "t.yaml").tolerances.grade, "7");
  // Contact grade 12 is not in the GOST table held: F_beta is given.
  EXPECT_EQ(
      parse_scenario(kGear + "tolerances: {grade: 8-7-12, overrides_um: {F_beta: 40}}\n", "t.yaml")
          .tolerances.grade,
      "8-7-12");
  // E_Hs may be 0 (a magnitude); the largest seed fits.
  EXPECT_EQ(parse_scenario(kGear + "tolerances: {overrides_um: {E_Hs: 0}}\n", "t.yaml")
                .tolerances.overrides_um.at(ToleranceKind::kThicknessUpper),
            0.0);
  EXPECT_EQ(parse_scenario("seed: 18446744073709551615\n" + kGear, "t.yaml").seed,
            std::numeric_limits<std::uint64_t>::max());
}

TEST(ScenarioTest, NumberSyntaxAcceptedForRealValues) {
  // Integers, exponents, a leading '+' are numbers; the scalar is read exactly.
  const Scenario s = parse_scenario(
      "gear: {teeth: +24, module_mm: 56e-1, face_width_mm: 78.890, profile_shift: -.5}\n", "t");
  EXPECT_EQ(s.gear.teeth, 24);
  EXPECT_DOUBLE_EQ(s.gear.module_mm, 5.6);
  EXPECT_DOUBLE_EQ(s.gear.face_width_mm, 78.89);
  EXPECT_DOUBLE_EQ(s.gear.profile_shift, -0.5);
}

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
            "gear, tolerances, deviations, probing, stylus, run, surfaces, effects, claims, "
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
  EXPECT_THAT(parse_error(kGear + "deviations: {k: 0}\n").what(),
              HasSubstr("deviations.k: got '0', expected a number > 0 and <= 100"));
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

// ---- did_you_mean and InputError ------------------------------------------------------------

TEST(DidYouMeanTest, FindsTheClosestLikelyTypo) {
  const std::vector<std::string> keys = {"teeth", "module_mm", "pressure_angle_deg",
                                         "profile_shift", "face_width_mm"};
  EXPECT_EQ(did_you_mean("teeht", keys), "teeth");         // transposition = 2 edits
  EXPECT_EQ(did_you_mean("modulemm", keys), "module_mm");  // deletion
  EXPECT_EQ(did_you_mean("face_width", keys), "face_width_mm");
  EXPECT_EQ(did_you_mean("pressure_angle", keys), "pressure_angle_deg");  // 4 <= 14/3
  EXPECT_EQ(did_you_mean("teeth", keys), "teeth");
}

TEST(DidYouMeanTest, NothingWhenTooFar) {
  EXPECT_EQ(did_you_mean("colour", {"teeth", "module_mm"}), "");
  EXPECT_EQ(did_you_mean("abc", {}), "");
  // Truncated names: the one candidate starting with the word; none when several do.
  EXPECT_EQ(did_you_mean("iso_1328_1", {"gost_1643_81", "iso_1328_1_2013"}), "iso_1328_1_2013");
  EXPECT_EQ(did_you_mean("radius", {"radius_mm"}), "radius_mm");
  EXPECT_EQ(did_you_mean("face", {"face_width_mm", "face_width_in"}), "");
  EXPECT_EQ(did_you_mean("ra", {"radius_mm"}), "");  // too short to guess
  // Limit max(2, |word| / 3): 3 edits are too many for a 6-letter word.
  EXPECT_EQ(did_you_mean("abcdef", {"abcxyz"}), "");
  EXPECT_EQ(did_you_mean("abcdef", {"abcdxy"}), "abcdxy");
}

TEST(DidYouMeanTest, FirstOfEquallyCloseCandidatesWins) {
  EXPECT_EQ(did_you_mean("f_p", {"F_p", "f_pb", "f_pt"}), "F_p");
  EXPECT_EQ(did_you_mean("f_p", {"f_pt", "F_p"}), "f_pt");
}

TEST(InputErrorTest, MessageFormatLeavesOutEmptyParts) {
  EXPECT_STREQ(InputError({"a.yaml", 3, 7}, "gear.teeth", "x", "an integer", "teeth").what(),
               "a.yaml:3:7: gear.teeth: got 'x', expected an integer; did you mean 'teeth'?");
  EXPECT_STREQ(InputError({"a.yaml", 3, 0}, "k", "", "something").what(),
               "a.yaml:3: k: expected something");
  EXPECT_STREQ(InputError({"a.yaml", 0, 0}, "", "v", "").what(), "a.yaml: got 'v'");
  const InputError keyed({"a.csv", 12, 0}, "row", "1,2", "15 columns");
  EXPECT_EQ(keyed.key(), "row");
  EXPECT_EQ(keyed.where().line, 12);
}

TEST(InputErrorTest, FreeMessageGetsItsPlaceUnlessItNamesIt) {
  EXPECT_STREQ(InputError({"f.csv", 4, 0}, "bad row").what(), "f.csv:4: bad row");
  EXPECT_STREQ(InputError({"f.csv", 0, 0}, "f.csv: cannot read").what(), "f.csv: cannot read");
  EXPECT_STREQ(InputError({}, "plain").what(), "plain");
}

// ---- the YAML reader ------------------------------------------------------------------------

TEST(YamlReaderTest, SequencesHaveIndexedPaths) {
  const YamlValue root = parse_yaml_document("effects:\n  - {name: drift}\n  - 7\n", "r.yaml");
  YamlMap top = root.as_map({"effects"});
  const std::vector<YamlValue> items = top.find("effects")->as_sequence();
  ASSERT_EQ(items.size(), 2u);
  EXPECT_EQ(items[0].as_map({"name"}).get_string("name"), "drift");
  const InputError e = items[1].error("a map");
  EXPECT_EQ(std::string(e.what()), "r.yaml:3:5: effects[1]: got '7', expected a map");
}

TEST(YamlReaderTest, OpenMapListsEntriesInOrder) {
  const YamlValue root = parse_yaml_document("{b: 1, a: 2}", "r.yaml");
  const YamlMap map = root.as_open_map();
  ASSERT_EQ(map.entries().size(), 2u);
  EXPECT_EQ(map.entries()[0].key, "b");
  EXPECT_EQ(map.entries()[1].value.as_int(), 2);
  EXPECT_EQ(map.entries()[1].value.path(), "a");
  EXPECT_EQ(map.entries()[1].value.key_location().column, 8);
}

TEST(YamlReaderTest, StrictScalars) {
  const auto value = [](const std::string& text) {
    return parse_yaml_document("v: " + text, "r").as_open_map().entries()[0].value;
  };
  EXPECT_EQ(value("-12").as_int(), -12);
  EXPECT_THROW(value("0x10").as_int(), InputError);
  EXPECT_THROW(value("1e3").as_int(), InputError);
  EXPECT_THROW(value("1_000").as_int(), InputError);
  EXPECT_THROW(value("99999999999999999999").as_int(), InputError);
  EXPECT_DOUBLE_EQ(value("1e3").as_number(), 1000.0);
  EXPECT_THROW(value(".nan").as_number(), InputError);
  EXPECT_THROW(value("5 mm").as_number(), InputError);
  EXPECT_THROW(value("'1.5'").as_number(), InputError);
  EXPECT_TRUE(value("True").as_bool());
  EXPECT_FALSE(value("FALSE").as_bool());
  EXPECT_THROW(value("on").as_bool(), InputError);
  EXPECT_THROW(value("\"true\"").as_bool(), InputError);
  EXPECT_EQ(value("'quoted text'").as_string(), "quoted text");
  EXPECT_THROW(value("[a]").as_string(), InputError);
}

}  // namespace
}  // namespace gearmc

// ---- probing, stylus, run ---------------------------------------------------------------------

namespace gearmc {
namespace {

TEST(ScenarioTest, ProbingStylusAndRunSections) {
  const Scenario d = parse_scenario(kGear, "t.yaml");
  // Defaults are P1's set-up (docs/sources.md): N 10, M 5, 5 % margins, all teeth, both flanks,
  // R 0.5 mm, 50 gears.
  EXPECT_EQ(d.probing.grid.points_along_profile, 10);
  EXPECT_EQ(d.probing.grid.sections_across_face, 5);
  EXPECT_DOUBLE_EQ(d.probing.grid.margin_fraction, 0.05);
  EXPECT_TRUE(d.probing.teeth.empty());
  EXPECT_TRUE(d.probing.left && d.probing.right);
  EXPECT_DOUBLE_EQ(d.stylus_radius_mm, 0.5);
  EXPECT_EQ(d.gears, 50);

  const Scenario s = parse_scenario(kGear +
                                        "probing:\n"
                                        "  points_along_profile: 20\n"
                                        "  sections_across_face: 7\n"
                                        "  margin_fraction: 0.1\n"
                                        "  profile_spacing: arc_length\n"
                                        "  teeth: [1, 5, 24]\n"
                                        "  flanks: R\n"
                                        "stylus: {radius_mm: 1.5}\n"
                                        "run: {gears: 7}\n",
                                    "t.yaml");
  EXPECT_EQ(s.probing.grid.points_along_profile, 20);
  EXPECT_EQ(s.probing.grid.sections_across_face, 7);
  EXPECT_DOUBLE_EQ(s.probing.grid.margin_fraction, 0.1);
  EXPECT_EQ(s.probing.grid.spacing, ProfileSpacing::kArcLength);
  EXPECT_EQ(s.probing.teeth, (std::vector<int>{1, 5, 24}));
  EXPECT_FALSE(s.probing.left);
  EXPECT_TRUE(s.probing.right);
  EXPECT_DOUBLE_EQ(s.stylus_radius_mm, 1.5);
  EXPECT_EQ(s.gears, 7);
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
  const InputError typo = parse_error(kGear + "stylus: {radius: 1}\n");
  EXPECT_NE(std::string(typo.what()).find("did you mean 'radius_mm'"), std::string::npos)
      << typo.what();
}

}  // namespace
}  // namespace gearmc
