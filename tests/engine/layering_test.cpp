// The layering rules of docs/architecture.md, checked on the sources: `gears/` and `surfaces/`
// never include `engine/`, and nothing outside `engine/cli/` includes `engine/cli/` (the command
// line is the top layer). A violation names the file and the include.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

namespace {

namespace fs = std::filesystem;

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

TEST(Layering, GearsAndSurfacesNeverIncludeEngine) {
  EXPECT_GT(check_folder("gears", "engine/", ""), 5);
  EXPECT_GT(check_folder("surfaces", "engine/", ""), 3);
}

TEST(Layering, NothingOutsideTheCommandLineIncludesIt) {
  EXPECT_GT(check_folder("engine", "engine/cli/", "engine/cli/"), 50);
  EXPECT_GT(check_folder("tests", "engine/cli/", ""), 20);
}

}  // namespace
