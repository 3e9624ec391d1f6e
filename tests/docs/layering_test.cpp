// The layering rules of docs/architecture.md, checked on the sources: `core/` includes no other
// code folder, `gears/` never includes `surfaces/` or `engine/`, `surfaces/` never includes
// `engine/`, nothing outside `engine/cli/` includes `engine/cli/` (the command line is the top
// layer), and inside `engine/` a file of layer Y (`engine/<stage>/` or `engine/apps/<app>/`)
// includes `engine/X/…` only when the "Engine layers" table lets Y use X. The table is read from
// docs/architecture.md (the build reads the same table to link the layers' libraries); its "may
// use" entries must name rows above (the layers are acyclic, lowest first) and every engine
// folder must have a row. A violation names the file, the line and the include.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <vector>

namespace {

namespace fs = std::filesystem;
using ::testing::ElementsAre;
using ::testing::HasSubstr;

int check_folder(const std::string& folder, const std::string& forbidden,
                 const std::string& allowed_prefix) {
  int files = 0;
  const fs::path root(GEARMC_SOURCE_DIR);
  for (const auto& entry : fs::recursive_directory_iterator(root / folder)) {
    const std::string ext = entry.path().extension().string();
    if (ext != ".cpp" && ext != ".h") continue;
    const std::string rel = fs::relative(entry.path(), root).string();
    if (!allowed_prefix.empty() && rel.rfind(allowed_prefix, 0) == 0) continue;
    ++files;
    std::ifstream in(entry.path());
    int line_no = 0;
    for (std::string line; std::getline(in, line);) {
      ++line_no;
      if (line.rfind("#include", 0) != 0) continue;
      EXPECT_EQ(line.find("\"" + forbidden), std::string::npos)
          << rel << ":" << line_no << ": " << line;
    }
  }
  return files;
}

TEST(Layering, LowerFoldersNeverIncludeHigherOnes) {
  for (const char* higher : {"gears/", "surfaces/", "engine/"}) {
    EXPECT_GT(check_folder("core", higher, ""), 10) << higher;
  }
  EXPECT_GT(check_folder("gears", "surfaces/", ""), 5);
  EXPECT_GT(check_folder("gears", "engine/", ""), 5);
  EXPECT_GT(check_folder("surfaces", "engine/", ""), 3);
}

TEST(Layering, NothingOutsideTheCommandLineIncludesIt) {
  EXPECT_GT(check_folder("engine", "engine/cli/", "engine/cli/"), 50);
  EXPECT_GT(check_folder("tests", "engine/cli/", ""), 20);
}

// ---------------------------------------------------------------------------------------------
// The engine's layer table

struct LayerTable {
  std::vector<std::string> order;                     // rows, lowest first
  std::map<std::string, std::set<std::string>> uses;  // folder -> folders it may use
  std::vector<std::string> problems;                  // entries that do not name a row above
};

// Rows "| `engine/<layer>/` | job | `a` `b` … |" of `markdown` (<layer> a stage "run" or an
// application "apps/diagnose"); the last cell lists the layers the row's layer may use ("—" for
// none).
LayerTable parse_layer_table(const std::string& markdown) {
  LayerTable table;
  const std::regex row(R"(^\| `engine/([a-z_/]+)/` \|.*\|([^|]*)\|\s*$)");
  const std::regex used("`([a-z_/]+)`");
  std::istringstream in(markdown);
  for (std::string line; std::getline(in, line);) {
    std::smatch m;
    if (!std::regex_match(line, m, row)) continue;
    const std::string folder = m[1];
    const std::string cell = m[2];
    std::set<std::string>& allowed = table.uses[folder];
    for (std::sregex_iterator it(cell.begin(), cell.end(), used), end; it != end; ++it) {
      const std::string x = (*it)[1];
      if (std::find(table.order.begin(), table.order.end(), x) == table.order.end()) {
        table.problems.push_back("engine/" + folder + " may use '" + x +
                                 "', which is not a layer above it in the table");
      }
      allowed.insert(x);
    }
    table.order.push_back(folder);
  }
  return table;
}

// The engine layer of a path relative to the repository: "run" for "engine/run/…", "apps/check"
// for "engine/apps/check/…"; empty outside engine/.
std::string layer_of(const std::string& path) {
  static const std::regex layer(R"(^engine/(apps/[a-z_]+|[a-z_]+)/)");
  std::smatch m;
  return std::regex_search(path, m, layer) ? std::string(m[1]) : std::string();
}

// Violations of `table` in one file's text: each "path:line: engine/Y includes engine/X (…)"
// for an include of another engine layer X that Y may not use. `path` is relative to the
// repository ("engine/Y/…").
std::vector<std::string> layer_violations(const LayerTable& table, const std::string& path,
                                          const std::string& text) {
  std::vector<std::string> found;
  const std::string y = layer_of(path);
  if (y.empty()) return found;
  const auto allowed = table.uses.find(y);
  const std::regex include(R"(^\s*#\s*include\s*"(engine/[a-z_/]+\.[a-z]+))");
  std::istringstream in(text);
  int line_no = 0;
  for (std::string line; std::getline(in, line);) {
    ++line_no;
    std::smatch inc;
    if (!std::regex_search(line, inc, include)) continue;
    const std::string x = layer_of(inc[1]);
    if (x.empty() || x == y) continue;
    if (allowed == table.uses.end() || !allowed->second.contains(x)) {
      found.push_back(path + ":" + std::to_string(line_no) + ": engine/" + y + " includes engine/" +
                      x + " (" + line + "), which its layer may not use");
    }
  }
  return found;
}

std::string read_text(const fs::path& file) {
  std::ifstream in(file);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

LayerTable repository_table() {
  return parse_layer_table(read_text(fs::path(GEARMC_SOURCE_DIR) / "docs" / "architecture.md"));
}

TEST(Layering, TheTableIsOrderedLowestFirstAndNamesEveryEngineFolder) {
  const LayerTable table = repository_table();
  EXPECT_GE(table.order.size(), 10u);
  EXPECT_TRUE(table.problems.empty()) << ::testing::PrintToString(table.problems);
  ASSERT_FALSE(table.order.empty());
  EXPECT_EQ(table.order.front(), "schema");  // the lowest stage
  EXPECT_EQ(table.order.back(), "cli");      // the top
  const fs::path engine = fs::path(GEARMC_SOURCE_DIR) / "engine";
  int folders = 0;
  for (const auto& entry : fs::recursive_directory_iterator(engine)) {
    if (!entry.is_directory()) continue;
    const std::string folder = fs::relative(entry.path(), engine).string();
    if (folder == "apps") continue;  // the applications' parent, no code of its own
    ++folders;
    EXPECT_TRUE(table.uses.contains(folder)) << "engine/" << folder << " has no row in the table";
  }
  EXPECT_GE(folders, 15);
}

TEST(Layering, EveryEngineIncludeFollowsTheTable) {
  const LayerTable table = repository_table();
  const fs::path root(GEARMC_SOURCE_DIR);
  int files = 0;
  for (const auto& entry : fs::recursive_directory_iterator(root / "engine")) {
    const std::string ext = entry.path().extension().string();
    if (ext != ".cpp" && ext != ".h" && ext != ".in") continue;
    ++files;
    const std::string rel = fs::relative(entry.path(), root).string();
    for (const std::string& v : layer_violations(table, rel, read_text(entry.path()))) {
      ADD_FAILURE() << v;
    }
  }
  EXPECT_GT(files, 80);
}

// The checker on synthetic text, so that a test shows it can fail.
TEST(Layering, TheCheckerFindsAnIncludeAgainstTheTable) {
  const LayerTable table = parse_layer_table(
      "| layer | job | may use |\n|---|---|---|\n"
      "| `engine/schema/` | keys | — |\n"
      "| `engine/effects/` | effects | `schema` |\n"
      "| `engine/scenario/` | input | `schema` `effects` |\n"
      "| `engine/apps/check/` | claims | `scenario` |\n");
  EXPECT_TRUE(table.problems.empty());
  EXPECT_THAT(table.order, ElementsAre("schema", "effects", "scenario", "apps/check"));

  // Allowed: own folder, a folder the row lists, non-engine headers.
  EXPECT_TRUE(layer_violations(table, "engine/scenario/scenario.cpp",
                               "#include \"engine/scenario/scenario.h\"\n"
                               "#include \"engine/effects/effect_config.h\"\n"
                               "#include \"core/input_error.h\"\n#include <vector>\n"
                               "#include \"gears/involute_gear.h\"\n")
                  .empty());
  // An application may include the layers its row lists, not one it does not.
  EXPECT_TRUE(layer_violations(table, "engine/apps/check/claim_tracker.cpp",
                               "#include \"engine/scenario/scenario.h\"\n"
                               "#include \"engine/apps/check/claim_tracker.h\"\n")
                  .empty());
  EXPECT_EQ(layer_violations(table, "engine/apps/check/claim_tracker.cpp",
                             "#include \"engine/effects/effects.h\"\n")
                .size(),
            1u);
  // Against the table: effects includes scenario (a layer above) or an application.
  const std::vector<std::string> upward = layer_violations(
      table, "engine/effects/effect_config.h",
      "// reads\n#include \"core/yaml_reader.h\"\n#include \"engine/scenario/scenario.h\"\n");
  ASSERT_EQ(upward.size(), 1u);
  EXPECT_THAT(upward[0], HasSubstr("engine/effects/effect_config.h:3: engine/effects includes "
                                   "engine/scenario"));
  EXPECT_EQ(layer_violations(table, "engine/effects/x.cpp",
                             "  #  include \"engine/apps/check/claim_tracker.h\"\n")
                .size(),
            1u);
  // A folder without a row may include no other engine folder.
  EXPECT_EQ(
      layer_violations(table, "engine/newthing/a.cpp", "#include \"engine/effects/e.h\"\n").size(),
      1u);
  EXPECT_TRUE(layer_violations(table, "engine/newthing/a.cpp", "#include \"core/a.h\"\n").empty());
}

TEST(Layering, TheTableRefusesAUseOfALayerNotAbove) {
  const LayerTable table = parse_layer_table(
      "| `engine/schema/` | keys | `scenario` |\n"
      "| `engine/scenario/` | input | `schema` |\n");
  ASSERT_EQ(table.problems.size(), 1u);
  EXPECT_THAT(table.problems[0], HasSubstr("engine/schema may use 'scenario'"));
}

}  // namespace
