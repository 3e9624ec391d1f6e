// Tests of the input layer the scenario reader stands on: the "did you mean" search for unknown
// keys, InputError's message format, and the YAML reader's paths, open maps and strict scalars.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "core/input_error.h"
#include "core/yaml_reader.h"

namespace gearmc {
namespace {

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
