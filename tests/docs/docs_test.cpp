// The documentation cannot drift from the code: docs/scenario-keys.md is exactly what the key
// table the scenario readers take their keys, choices and defaults from and the range tables
// they check numbers against generate, every page under docs/ and the README link only to files
// that exist in the repository, and every file: function of docs/architecture.md's walk exists.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>

#include "engine/schema/parameter_ranges.h"
#include "engine/schema/scenario_keys.h"
#include "tests/support/text_files.h"

namespace gearmc {
namespace {

using testing_support::read_text;
using testing_support::write_text;

namespace fs = std::filesystem;

TEST(Docs, ScenarioKeysPageIsTheKeyAndRangeTables) {
  const fs::path page = fs::path(GEARMC_SOURCE_DIR) / "docs" / "scenario-keys.md";
  ASSERT_TRUE(fs::exists(page));
  EXPECT_EQ(read_text(page), scenario_keys_markdown())
      << "docs/scenario-keys.md differs from the key and range tables: run scripts/update-docs";
  // Spot checks that the generated text is the reference it claims to be: every key of the
  // table is a row, non-numeric keys with their type, default and allowed values.
  const std::string md = scenario_keys_markdown();
  for (const ScenarioKey& k : scenario_keys()) {
    EXPECT_NE(md.find("| `" + k.key + "` | "), std::string::npos) << k.key;
  }
  EXPECT_NE(md.find("| `probing.flanks` | choice |  | both | `both`, `L`, `R` |"),
            std::string::npos);
  EXPECT_NE(md.find("| `deviations.random` | boolean |  | true | true, false |"),
            std::string::npos);
  EXPECT_NE(md.find("| `effects.probe_lobing.calibration` | choice |  | none | `none`, `mean6`"),
            std::string::npos);
  EXPECT_NE(md.find("| `gear.module_mm` | number | mm | required | a number from 0.01 to 200 |"),
            std::string::npos);
  EXPECT_NE(md.find("| `gear.module_mm` | mm |"), std::string::npos);  // the range table
  EXPECT_NE(md.find("### effects"), std::string::npos);
  EXPECT_NE(md.find("### readings"), std::string::npos);
}

TEST(Docs, LocalLinksPointToFilesInTheRepository) {
  // [text](target) with a relative target: the file must exist (anchors are not checked).
  const std::regex link(R"(\]\(([^)#:\s]+)(#[^)]*)?\))");
  std::vector<fs::path> pages = {fs::path(GEARMC_SOURCE_DIR) / "README.md"};
  for (const auto& entry : fs::directory_iterator(fs::path(GEARMC_SOURCE_DIR) / "docs")) {
    if (entry.path().extension() == ".md") pages.push_back(entry.path());
  }
  int links = 0;
  for (const fs::path& page : pages) {
    const std::string text = read_text(page);
    for (auto it = std::sregex_iterator(text.begin(), text.end(), link);
         it != std::sregex_iterator(); ++it) {
      const fs::path target = page.parent_path() / (*it)[1].str();
      EXPECT_TRUE(fs::exists(target)) << page.filename() << " links to " << (*it)[1].str();
      ++links;
    }
    // Nothing refers to the design notes that are not part of the repository (docs/sources.md
    // is, and the link check above covers it).
    for (const char* outside : {"interface.md", "references.md", "design.md"}) {
      EXPECT_EQ(text.find(outside), std::string::npos) << page.filename() << " names " << outside;
    }
  }
  EXPECT_GT(links, 20);
}

}  // namespace
}  // namespace gearmc

namespace gearmc {
namespace {

// Every "`path: function`" that docs/architecture.md names (its "Follow one gear" walk) is a file
// of the repository that defines that function: the file exists and holds the function's last
// name followed by "(" (a definition or declaration, e.g. "GearSampler::draw" as "draw(" in
// gears/deviations.cpp). A renamed function or moved file fails here, naming the pair.
TEST(Docs, ArchitectureWalkNamesFunctionsWhereTheyAre) {
  const fs::path root(GEARMC_SOURCE_DIR);
  const std::string text = read_text(root / "docs" / "architecture.md");
  const std::regex pair(R"(`([a-z0-9_/]+\.(?:cpp|h|in)): ([A-Za-z_][A-Za-z0-9_:]*)`)");
  int pairs = 0;
  for (std::sregex_iterator it(text.begin(), text.end(), pair), end; it != end; ++it) {
    ++pairs;
    const std::string file = (*it)[1], function = (*it)[2];
    ASSERT_TRUE(fs::exists(root / file)) << file << " (for " << function << ") does not exist";
    const std::size_t colon = function.rfind(':');
    const std::string name = colon == std::string::npos ? function : function.substr(colon + 1);
    const std::string source = read_text(root / file);
    EXPECT_TRUE(std::regex_search(source, std::regex("\\b" + name + "\\s*\\(")))
        << file << " defines no " << function;
  }
  EXPECT_GE(pairs, 30) << "the walk names fewer file: function pairs than expected";
}

}  // namespace
}  // namespace gearmc
