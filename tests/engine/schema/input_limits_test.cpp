// Tests of the limits on user input: files are read only when they are regular files of
// bounded size (a FIFO, /dev/zero, a directory, an oversized file are InputErrors naming the
// file); scenario text must be UTF-8 (a bad byte is an InputError at its line:column); messages
// echo input escaped and shortened; every physical number has a plausible range (an InputError
// beyond the valid range naming the key, a warning beyond the usual one, unit slips named);
// tolerance problems (table range, an F_r the profile and helix tolerances cannot fit) are
// InputErrors at their key when the scenario is loaded, so every command agrees.
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>
#include <yaml-cpp/yaml.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <string>

#include "core/input_error.h"
#include "core/input_file.h"
#include "engine/effects/effect_config.h"
#include "engine/readings/readings_csv.h"
#include "engine/scenario/scenario.h"
#include "engine/schema/parameter_ranges.h"
#include "tests/support/run_gearmc.h"
#include "tests/support/temp_paths.h"

using ::gearmc::testing_support::fresh_temp_path;

#ifndef GEARMC_SOURCE_DIR
#error "GEARMC_SOURCE_DIR (the repository root) must be defined"
#endif

namespace gearmc {
namespace {

using ::testing::HasSubstr;
using ::testing::Not;
using ::testing::StartsWith;

std::string read_text(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

const std::string kP1Path = std::string(GEARMC_SOURCE_DIR) + "/scenarios/p1_reference.yaml";

// The InputError that `action` throws (a test failure when it throws none).
template <typename Action>
InputError input_error(Action action) {
  try {
    action();
  } catch (const InputError& e) {
    return e;
  }
  ADD_FAILURE() << "no InputError";
  return InputError({}, "no error");
}

InputError scenario_error(const std::string& text) {
  return input_error([&] { parse_scenario(text, "t.yaml"); });
}

class CaseFolder {
 public:
  CaseFolder() {
    path_ = std::filesystem::temp_directory_path() /
            ("gearmc_limits_" + std::to_string(::getpid()) + "_" +
             ::testing::UnitTest::GetInstance()->current_test_info()->name());
    std::filesystem::create_directories(path_);
  }
  ~CaseFolder() { std::filesystem::remove_all(path_); }
  std::string file(const std::string& name) const { return (path_ / name).string(); }

 private:
  std::filesystem::path path_;
};

// ---- files ----------------------------------------------------------------------------------

TEST(InputFileTest, RefusesFifoDeviceAndDirectoryBeforeOpening) {
  CaseFolder dir;
  const std::string fifo = dir.file("pipe.yaml");
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  // A FIFO without a writer would block an open(): the stat check refuses it first.
  EXPECT_THAT(input_error([&] { load_scenario_file(fifo); }).what(),
              HasSubstr("it is a FIFO (named pipe), expected a regular file"));
  EXPECT_THAT(input_error([&] { read_readings(fifo); }).what(), HasSubstr("FIFO"));
  EXPECT_THAT(input_error([] { load_scenario_file("/dev/zero"); }).what(),
              HasSubstr("/dev/zero: cannot read the scenario file: it is a device"));
  EXPECT_THAT(input_error([] { read_readings("/dev/zero"); }).what(),
              HasSubstr("/dev/zero: cannot read the readings file: it is a device"));
  EXPECT_THAT(input_error([&] { read_readings(dir.file("")); }).what(),
              HasSubstr("it is a directory"));
}

// A mesh file under `surfaces:` is an input file like the scenario: a FIFO given as the mesh
// once blocked `run` forever (OpenMesh opened it); /dev/zero as a mesh would never end.
TEST(InputFileTest, AMeshFileMustBeARegularFileToo) {
  CaseFolder dir;
  const std::string fifo = dir.file("flank.stl");
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  const std::string text =
      read_text(kP1Path) + "\nsurfaces:\n  - tooth: 1\n    flank: L\n" + "    mesh: flank.stl\n";
  const InputError e = input_error([&] { parse_scenario(text, dir.file("s.yaml")); });
  EXPECT_THAT(e.what(), HasSubstr("it is a FIFO (named pipe), expected a regular file"));
  EXPECT_GT(e.where().line, 0);  // placed at the `mesh` value
  std::filesystem::remove(fifo);
  std::filesystem::create_symlink("/dev/zero", fifo);
  EXPECT_THAT(input_error([&] { parse_scenario(text, dir.file("s.yaml")); }).what(),
              HasSubstr("it is a device, expected a regular file"));
}

TEST(InputFileTest, CapsTheFileSize) {
  CaseFolder dir;
  // Sparse files: the size is checked from stat, nothing is read.
  const std::string big = dir.file("big.yaml");
  std::ofstream(big).close();
  std::filesystem::resize_file(big, kMaxScenarioBytes + 1);
  const InputError e = input_error([&] { load_scenario_file(big); });
  EXPECT_THAT(e.what(), HasSubstr("more than the 64 MiB a scenario file may have"));
  EXPECT_EQ(e.where().file, big);
  std::filesystem::resize_file(big, kMaxReadingsBytes + 1);
  EXPECT_THAT(input_error([&] { read_readings(big); }).what(),
              HasSubstr("more than the 1024 MiB a readings file may have"));
}

TEST(InputFileTest, ReadsARegularFileWhole) {
  EXPECT_EQ(read_input_file(kP1Path, "scenario file", kMaxScenarioBytes), read_text(kP1Path));
}

// ---- UTF-8 and echoed values -----------------------------------------------------------------

TEST(Utf8Test, FindsTheFirstByteThatIsNotUtf8) {
  EXPECT_FALSE(first_invalid_utf8("plain, é, €, 𝄞").has_value());
  EXPECT_EQ(first_invalid_utf8("ab\xff"), 2u);
  EXPECT_EQ(first_invalid_utf8("a\xc0\xaf"), 1u);         // overlong '/'
  EXPECT_EQ(first_invalid_utf8("\xed\xa0\x80"), 0u);      // a UTF-16 surrogate
  EXPECT_EQ(first_invalid_utf8("\xf4\x90\x80\x80"), 0u);  // above U+10FFFF
  EXPECT_EQ(first_invalid_utf8("x\xe2\x82"), 1u);         // cut short
}

TEST(Utf8Test, ScenarioWithBytesThatAreNotUtf8IsAnInputErrorAtTheByte) {
  // The scenario name goes into summary.json: before, nlohmann::json threw type_error 316.
  const InputError e = scenario_error(
      "name: \"ab\xff\xfe\"\ngear: {teeth: 24, module_mm: 5.6, face_width_mm: 78.89}\n");
  EXPECT_EQ(e.where().line, 1);
  EXPECT_EQ(e.where().column, 10);  // the 0xFF byte
  EXPECT_THAT(e.what(), HasSubstr("must be UTF-8 text, but byte 0xFF"));
  // Also in a comment: the text itself is shown in reports.
  EXPECT_EQ(scenario_error("# \xe9t\xe9\ngear: {}\n").where().line, 1);
}

TEST(ShownInputTest, EscapesAndShortens) {
  EXPECT_EQ(shown_input("a\nb\r\tc\x01\x7f"), "a\\nb\\r\\tc\\x01\\x7F");
  EXPECT_EQ(shown_input("\xff\xc3(ok é"), "\\xFF\\xC3(ok é");
  EXPECT_EQ(shown_input(std::string(61, 'x')), std::string(60, 'x') + "…");
  EXPECT_EQ(shown_input(std::string(60, 'x')), std::string(60, 'x'));
  // A UTF-8 character counts as one and is never cut.
  EXPECT_EQ(shown_input(std::string(30, 'x') + "ééééééééééééééééééééééééééééééééé"),
            std::string(30, 'x') + "éééééééééééééééééééééééééééééé…");
}

TEST(ShownInputTest, EveryInputErrorEchoesEscapedAndBounded) {
  const InputError e({"f", 1, 2}, std::string(500, 'k'), "v\x1b[31m" + std::string(5000, 'v'), "x");
  // 120 characters of key, 60 of value, the place and the words around them.
  EXPECT_LT(std::string(e.what()).size(), 260u);
  EXPECT_THAT(e.what(), HasSubstr("v\\x1B[31m"));
  // A binary value in a scenario.
  EXPECT_THAT(
      scenario_error("gear: {teeth: \"\x01\x02\", module_mm: 5.6, face_width_mm: 9}\n").what(),
      HasSubstr("got '\\x01\\x02'"));
}

// ---- readings -------------------------------------------------------------------------------

const std::string kHead =
    "# gearmc readings v1\n# stylus_radius_mm=0.5\n"
    "gear,tooth,flank,i,j,order,px,py,pz,nx,ny,nz,cx,cy,cz\n";
const std::string kRow = "0,1,L,0,0,0,60,0,10,1,0,0,60.5,0,10\n";

InputError readings_error(const std::string& text) {
  return input_error([&] { parse_readings(text, "r.csv"); });
}

TEST(ReadingsLimitsTest, CarriageReturnLineEndsAreLineEnds) {
  std::string cr = kHead + kRow;
  for (char& c : cr) c = c == '\n' ? '\r' : c;
  EXPECT_EQ(parse_readings(cr, "r.csv").rows.size(), 1u);
  // A CR-only file whose header is wrong gives a short message at line 3 (before: the whole
  // file was one line, echoed in full).
  std::string bad = "# gearmc readings v1\r# stylus_radius_mm=0.5\r";
  for (int k = 0; k < 40000; ++k) bad += "gear,1,2\r";
  const InputError e = readings_error(bad);
  EXPECT_EQ(e.where().line, 3);
  EXPECT_LT(std::string(e.what()).size(), 300u);
}

TEST(ReadingsLimitsTest, LongLinesAreRefused) {
  const InputError e = readings_error(kHead + std::string(kMaxReadingsLineBytes + 1, '0') + "\n");
  EXPECT_EQ(e.where().line, 4);
  EXPECT_THAT(e.what(), HasSubstr("a line of at most 4096 bytes"));
}

TEST(ReadingsLimitsTest, FieldCountAndMissingRowsHaveAPlace) {
  const InputError many = readings_error(kHead + "0,1,L,0,0,0,60,0,10,1,0,0,60.5,0,10,7\n");
  EXPECT_EQ(many.where().line, 4);
  EXPECT_EQ(many.where().column, 36);  // the comma before the 16th field
  const InputError few = readings_error(kHead + "0,1,L\n");
  EXPECT_EQ(few.where().column, 6);  // the end of the short row
  const InputError none = readings_error(kHead);
  EXPECT_EQ(none.where().line, 4);
  EXPECT_EQ(none.where().column, 1);
  EXPECT_THAT(none.what(), HasSubstr("no rows after its column line (line 3)"));
}

TEST(ReadingsLimitsTest, NumbersHavePlausibleRanges) {
  // A stylus radius of 1e308 used to pass and fail deep inside the diagnosis.
  const InputError r = readings_error(
      "# gearmc readings v1\n# stylus_radius_mm=1e308\n"
      "gear,tooth,flank,i,j,order,px,py,pz,nx,ny,nz,cx,cy,cz\n" +
      kRow);
  EXPECT_EQ(r.where().line, 2);
  EXPECT_THAT(r.what(),
              HasSubstr("stylus_radius_mm: got '1e308', expected a number from 0.01 to 50 mm"));
  const InputError p = readings_error(kHead + "0,1,L,0,0,0,1e300,0,10,1,0,0,60.5,0,10\n");
  EXPECT_EQ(p.where().column, 13);
  EXPECT_THAT(p.what(), HasSubstr("px: got '1e300'"));
  const InputError e = readings_error(kHead + "0,1,L,0,0,0,60,0,10,1,0,0,99960.5,0,10\n");
  EXPECT_THAT(e.what(), HasSubstr("reading_um"));
  // A radius in the usual range gives no warning; a 20 mm one is valid but warned about.
  EXPECT_TRUE(parse_readings(kHead + kRow, "r.csv").warnings.empty());
  const Readings big = parse_readings(
      "# gearmc readings v1\n# stylus_radius_mm=20\n"
      "gear,tooth,flank,i,j,order,px,py,pz,nx,ny,nz,cx,cy,cz\n"
      "0,1,L,0,0,0,60,0,10,1,0,0,80,0,10\n",
      "r.csv");
  ASSERT_EQ(big.warnings.size(), 1u);
  EXPECT_THAT(big.warnings[0],
              StartsWith("r.csv:2:20: stylus_radius_mm: 20 mm is outside the usual range"));
}

// ---- plausible ranges of scenario numbers ---------------------------------------------------

// P1's gear with every GOST norm given, so that any gear of the valid ranges resolves.
const std::string kBase =
    "gear: {teeth: 24, module_mm: 5.6, face_width_mm: 78.89, profile_shift: 0.5}\n"
    "tolerances: {overrides_um: {F_r: 50, f_pt: 10, f_pb: 9, f_f: 8, F_beta: 10}}\n"
    "probing: {points_along_profile: 4, sections_across_face: 2}\n";

// kBase with the dotted `key` set to `value` (YAML text), through yaml-cpp.
std::string with_value(const std::string& key, const std::string& value) {
  YAML::Node root = YAML::Load(kBase);
  std::vector<std::string> parts;
  std::stringstream in(key);
  for (std::string part; std::getline(in, part, '.');) parts.push_back(part);
  if (parts[0] == "tolerances" && parts.back() == "tolerance") parts.back() = "F_r";
  if (parts[0] == "deviations" && parts.back() == "control_points") {
    parts.insert(parts.end() - 1, "profile");
  }
  YAML::Node leaf = YAML::Load(value);
  if (parts.size() > 2 && parts[1] == "empirical") {  // its required settings first
    root["effects"]["empirical"]["axis"] = "face_position";
    root["effects"]["empirical"]["basis"] = "harmonic";
  }
  if (parts[0] == "cmm") {  // its required MPE_E first; A and K are parts of its text
    root["cmm"]["mpe_e_um"] = "1.8 + L/300";
    if (parts.size() > 2 && parts[1] == "mpe_e_um") {
      root["cmm"]["mpe_e_um"] = parts[2] == "A" ? value + " + L/300" : "1.8 + L/" + value;
      YAML::Emitter out;
      out << root;
      return out.c_str();
    }
    if (parts[1] == "travel_mm" || parts[1] == "placement_mm") {  // three numbers, the first bad
      root["cmm"][parts[1]] = YAML::Load("[" + value + ", 0, 0]");
      YAML::Emitter out;
      out << root;
      return out.c_str();
    }
  }
  if (parts[0] == "claims") {  // a list of maps: one valid claim with the key set
    YAML::Node claim = YAML::Load(
        "{name: c, quantity: delta_rcomp.point, statistic: {quantile: 0.9}, at_most_um: 1}");
    if (parts[1] == "at_least_um") claim.remove("at_most_um");
    if (parts.size() > 2) {
      claim[parts[1]][parts[2]] = leaf;
    } else {
      claim[parts[1]] = leaf;
    }
    root["claims"].push_back(claim);
  } else if (parts.size() > 2 && parts[2] == "harmonics") {  // a list of maps
    YAML::Node harmonic;
    harmonic["order"] = 3;
    harmonic[parts[3]] = leaf;
    root["effects"]["probe_lobing"]["harmonics"].push_back(harmonic);
  } else if (parts.size() > 3 && parts[2] == "terms") {  // the empirical term's list
    YAML::Node term;
    term["order"] = 1;
    term[parts[3]] = leaf;
    root["effects"]["empirical"]["terms"].push_back(term);
  } else {
    std::vector<YAML::Node> chain = {root};
    for (std::size_t i = 0; i + 1 < parts.size(); ++i) chain.push_back(chain.back()[parts[i]]);
    chain.back()[parts.back()] = leaf;
  }
  YAML::Emitter out;
  out << root;
  return out.c_str();
}

std::string number_text(double value) {
  std::ostringstream s;
  s.precision(17);
  s << value;
  return s.str();
}

TEST(ParameterRangesTest, TablesAreConsistent) {
  std::set<std::string> keys;
  for (const RangeTable* table : all_range_tables()) {
    for (const ParameterRange& r : table->entries) {
      EXPECT_TRUE(keys.insert(r.key).second) << "twice: " << r.key;
      EXPECT_FALSE(r.why.empty()) << r.key;
      EXPECT_LE(r.valid.min, r.usual_min) << r.key;
      EXPECT_GE(r.valid.max, r.usual_max) << r.key;
      EXPECT_TRUE(std::isfinite(r.valid.min) && std::isfinite(r.valid.max)) << r.key;
    }
  }
}

TEST(ParameterRangesTest, EveryScenarioNumberBeyondItsRangeIsAnInputErrorAtItsKey) {
  ASSERT_NO_THROW(parse_scenario(kBase, "t.yaml"));
  int checked = 0;
  for (const RangeTable* table : all_range_tables()) {
    if (table == &readings_ranges()) continue;
    for (const ParameterRange& r : table->entries) {
      if (r.key == "probing.points_per_gear") continue;  // derived, tested below
      for (const double bad :
           {r.valid.max + (r.integer ? 1.0 : std::abs(r.valid.max) + 1.0), 1e308}) {
        const InputError e = scenario_error(with_value(r.key, number_text(bad)));
        std::string path = r.key;
        if (path.find(".harmonics.") != std::string::npos) {
          path.replace(path.find(".harmonics."), 11, ".harmonics[0].");
        }
        if (path.find(".terms.") != std::string::npos) {
          path.replace(path.find(".terms."), 7, ".terms[0].");
        }
        if (path == "tolerances.overrides_um.tolerance") path = "tolerances.overrides_um.F_r";
        if (path == "deviations.control_points") path = "deviations.profile.control_points";
        if (path.rfind("claims.", 0) == 0) path.replace(0, 7, "claims[0].");
        if (path == "cmm.travel_mm" || path == "cmm.placement_mm") path += "[0]";
        // A or K of MPE_E: the key the user wrote (a number too large to read is its form's
        // error, a readable one its range's).
        if (path == "cmm.mpe_e_um.A" || path == "cmm.mpe_e_um.K") path = "cmm.mpe_e_um";
        EXPECT_THAT(e.what(), HasSubstr(path + ": got '")) << r.key;
        EXPECT_GT(e.where().line, 0) << r.key;
        ++checked;
      }
    }
  }
  EXPECT_GT(checked, 2 * 40);
}

// Every key a section accepts (as its unknown-key message lists them) is either a number with
// a range entry or one of the known non-numeric settings.
TEST(ParameterRangesTest, EveryNumberKeyOfTheParserHasARange) {
  const std::set<std::string> settings = {"enabled",
                                          "calibration",
                                          "six_directions_use",
                                          "harmonics",
                                          "from_probe_model",
                                          "order",
                                          "stem_material",
                                          "directions",
                                          "max_order",
                                          "basic_rack",
                                          "hand",
                                          "internal",
                                          "modifications",
                                          "teeth",
                                          "flanks",
                                          "order",
                                          "profile_spacing",
                                          "random",
                                          "distribution",
                                          "eccentricity",
                                          "stylus_axis",
                                          "shaft_axis",
                                          "pitch",
                                          "thickness",
                                          "profile",
                                          "helix",
                                          "normal_um",
                                          "axis",
                                          "basis",
                                          "terms",
                                          "layout",
                                          "mpe_e_um",
                                          "verification",
                                          "rotary_table"};
  std::set<std::string> keys;
  for (const RangeTable* table : all_range_tables()) {
    for (const ParameterRange& r : table->entries) keys.insert(r.key);
  }
  auto listed = [&](const std::string& section_yaml, const std::string& path) {
    const std::string message = scenario_error(section_yaml).what();
    const std::string marker = path + " has: ";
    const auto start = message.find(marker);
    EXPECT_NE(start, std::string::npos) << message;
    if (start == std::string::npos) return;
    std::stringstream list(
        message.substr(start + marker.size(), message.find(')', start) - start - marker.size()));
    for (std::string key; std::getline(list, key, ',');) {
      key.erase(0, key.find_first_not_of(' '));
      if (settings.count(key)) continue;
      EXPECT_TRUE(keys.count(path + "." + key)) << path << "." << key << " has no range";
    }
  };
  listed("gear: {bogus: 1}\n", "gear");
  listed("gear: {teeth: 24, module_mm: 5.6, face_width_mm: 78.89, basic_rack: {bogus: 1}}\n",
         "gear.basic_rack");
  listed(kBase + "deviations: {bogus: 1}\n", "deviations");
  listed(kBase + "stylus: {bogus: 1}\n", "stylus");
  listed(kBase + "run: {bogus: 1}\n", "run");
  listed(kBase + "cmm: {mpe_e_um: \"1.8 + L/300\", bogus: 1}\n", "cmm");
  listed(kBase + "cmm: {mpe_e_um: \"1.8 + L/300\", rotary_table: {bogus: 1}}\n",
         "cmm.rotary_table");
  for (const std::string& effect : effect_names()) {
    listed(kBase + "effects: {" + effect + ": {bogus: 1}}\n", "effects." + effect);
  }
  listed(kBase + "effects: {probe_lobing: {from_probe_model: {bogus: 1}}}\n",
         "effects.probe_lobing.from_probe_model");
}

TEST(ParameterRangesTest, PointsPerGearAreBounded) {
  const InputError e = scenario_error(
      "gear: {teeth: 1000, module_mm: 1, face_width_mm: 10}\n"
      "tolerances: {standard: iso_1328_1_2013, grade: 6}\n"
      "probing: {points_along_profile: 1000, sections_across_face: 1000}\n");
  EXPECT_THAT(e.what(), HasSubstr("probing.points_per_gear: got '2000000000'"));
  EXPECT_EQ(e.where().line, 3);
}

TEST(ParameterRangesTest, UnitSlipsAreNamed) {
  EXPECT_THAT(scenario_error(with_value("gear.pressure_angle_deg", "0.349")).what(),
              HasSubstr("radians"));
  EXPECT_THAT(scenario_error(with_value("effects.noise.sigma_um", "300")).what(),
              HasSubstr("in nm? (300 nm = 0.3 µm)"));
  EXPECT_THAT(scenario_error(with_value("tolerances.overrides_um.tolerance", "0.02")).what(),
              HasSubstr("a value in mm? (0.02 mm = 20 µm)"));
}

// A slip hint only on its side of the range: a fraction above 1 may be a percentage, one below
// the usual range is not (issue 29: a lower-tail quantile 0.025 was asked "a percentage?");
// a lower-tail claim is usual, and a quantile of 99.73 is an error with the hint.
TEST(ParameterRangesTest, AUnitSlipIsNamedOnlyOnItsSide) {
  const Scenario short_range = parse_scenario(
      kBase + "evaluation: {parameters: all, profile_end_fraction: 0.6}\n", "t.yaml");
  ASSERT_EQ(short_range.warnings.size(), 1u);
  EXPECT_THAT(short_range.warnings[0], HasSubstr("profile_end_fraction: 0.6 is outside the usual"));
  EXPECT_THAT(short_range.warnings[0], Not(HasSubstr("percentage")));
  EXPECT_THAT(
      scenario_error(kBase + "evaluation: {parameters: all, profile_end_fraction: 95}\n").what(),
      HasSubstr("a percentage?"));
  const std::string claim =
      "claims:\n  - {name: low, quantity: delta_rcomp.point, side: both, statistic: {quantile: "
      "QUANTILE}, at_least_um: -4}\n";
  const auto with_quantile = [&](const std::string& q) {
    std::string c = claim;
    c.replace(c.find("QUANTILE"), 8, q);
    return kBase + c;
  };
  EXPECT_TRUE(parse_scenario(with_quantile("0.025"), "t.yaml").warnings.empty());
  EXPECT_THAT(scenario_error(with_quantile("99.73")).what(),
              HasSubstr("a percentage? (99.73 % is 0.9973)"));
  // Too small a value for a µm key (mm written) gets its hint; too large a one does not.
  const Scenario big =
      parse_scenario(with_value("tolerances.overrides_um.tolerance", "5000"), "t.yaml");
  ASSERT_EQ(big.warnings.size(), 1u);
  EXPECT_THAT(big.warnings[0], Not(HasSubstr("a value in mm?")));
}

TEST(ParameterRangesTest, ValuesOutsideTheUsualRangeAreWarnedAbout) {
  EXPECT_TRUE(parse_scenario(kBase, "t.yaml").warnings.empty());
  const Scenario noisy = parse_scenario(with_value("effects.noise.sigma_um", "20"), "t.yaml");
  ASSERT_EQ(noisy.warnings.size(), 1u);
  EXPECT_THAT(noisy.warnings[0], HasSubstr("effects.noise.sigma_um: 20 µm is outside the usual "
                                           "range 0 … 5 µm (probing noise σ 0.1–0.5 µm)"));
  EXPECT_THAT(noisy.warnings[0], StartsWith("t.yaml:"));
  const Scenario fine = parse_scenario(with_value("gear.module_mm", "0.15"), "t.yaml");
  ASSERT_EQ(fine.warnings.size(), 1u);
  EXPECT_THAT(fine.warnings[0], HasSubstr("gear.module_mm: 0.15 mm is outside the usual range"));
  // Law bounds are checked like numbers; a normal law's sd against half the valid width.
  EXPECT_THAT(scenario_error(with_value("effects.scale.x_ppm", "{uniform: [-1, 1e300]}")).what(),
              HasSubstr("effects.scale.x_ppm.uniform[1]: got '1e300'"));
  EXPECT_THAT(scenario_error(with_value("effects.scale.x_ppm", "{normal: [0, 1e300]}")).what(),
              HasSubstr("effects.scale.x_ppm.normal[1]: got '1e300'"));
}

TEST(ParameterRangesTest, EveryShippedScenarioIsWithinTheUsualRanges) {
  for (const auto& entry :
       std::filesystem::directory_iterator(std::string(GEARMC_SOURCE_DIR) + "/scenarios")) {
    if (entry.path().extension() != ".yaml") continue;
    const Scenario s = load_scenario_file(entry.path().string());
    EXPECT_TRUE(s.warnings.empty()) << entry.path() << ": " << s.warnings.front();
  }
}

// ---- tolerances at load time ----------------------------------------------------------------

TEST(ToleranceCheckTest, TableRangeErrorsArePlacedAtTheGrade) {
  const InputError e = scenario_error(
      "gear: {teeth: 24, module_mm: 1, face_width_mm: 20}\n"
      "tolerances:\n  grade: \"6-5-5\"\n");
  EXPECT_EQ(e.where().line, 3);
  EXPECT_EQ(e.where().column, 10);
  EXPECT_THAT(e.what(), HasSubstr("tolerances.grade: GOST 1643-81 table has no value"));
  // Without a tolerances section (the default grade) the gear is the place.
  EXPECT_EQ(scenario_error("gear: {teeth: 24, module_mm: 1, face_width_mm: 20}\n").where().line, 1);
}

TEST(ToleranceCheckTest, ATightRunoutIsAWarningAtLoadAndNeverAnInternalError) {
  // P1 with F_r = 5 µm: profile (f_f 8 µm) and helix (F_beta 10 µm) deviations at their
  // tolerances give a runout of about 12 µm with no pitch deviation at all. The sampler draws
  // the shapes of such a gear again (rejection sampling, up to 64 draws), so the first gears
  // load, with a warning at F_r that a run may meet a gear it cannot fit; `run` used to stop
  // with an internal error at the first such gear while `geometry` accepted the file.
  std::string text = read_text(kP1Path);
  text.replace(text.find("F_r: 50 "), 8, "F_r: 5  ");
  const Scenario tight = parse_scenario(text, "p1.yaml");
  ASSERT_EQ(tight.warnings.size(), 1u);
  EXPECT_THAT(tight.warnings[0], HasSubstr("p1.yaml:23:10: tolerances.overrides_um.F_r: F_r "
                                           "leaves little room"));
  // A run that meets a gear no draw can fit (gear 112 of seed 1) is bad input, exit 2.
  const std::string path = fresh_temp_path("fr5.yaml").string();
  std::ofstream(path) << text;
  const auto r = testing_support::run_gearmc("run " + path + " --gears 200 --quiet --out " +
                                             fresh_temp_path("fr5_out").string());
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_THAT(r.err, HasSubstr("raise F_r"));
  EXPECT_THAT(r.err, Not(HasSubstr("internal error")));
  // P1 itself (F_r 50 µm) loads without a warning.
  EXPECT_TRUE(parse_scenario(read_text(kP1Path), "p1.yaml").warnings.empty());
}

}  // namespace
}  // namespace gearmc
