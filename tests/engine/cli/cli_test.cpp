// The gearmc executable as a user runs it: exit codes, the geometry JSON of the reference
// scenario (P1's Table 1 and tolerances) and one clear message for bad input.
#include <gtest/gtest.h>

#include "core/provenance.h"
#include "tests/support/run_gearmc.h"
#include "tests/support/temp_paths.h"

#include <nlohmann/json.hpp>

#include <sys/wait.h>
#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace {

using Result = gearmc::testing_support::CommandResult;
using gearmc::testing_support::fresh_temp_path;

Result run(const std::string& args) { return gearmc::testing_support::run_gearmc(args); }

TEST(Cli, GeometryOfTheReferenceScenarioIsP1Table1) {
  const Result r = run("geometry");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto doc = nlohmann::json::parse(r.out);
  const auto& g = doc["geometry_mm"];
  // P1 Table 1 (docs/sources.md), to 0.001 mm.
  EXPECT_NEAR(g["reference_diameter_d"].get<double>(), 134.4, 1e-3);
  EXPECT_NEAR(g["tip_diameter_d_a"].get<double>(), 155.693, 1e-3);
  EXPECT_NEAR(g["root_diameter_d_f"].get<double>(), 130.493, 1e-3);
  EXPECT_NEAR(g["base_diameter_d_b"].get<double>(), 126.295, 1e-3);
  EXPECT_NEAR(g["tooth_thickness_s"].get<double>(), 12.47, 1e-3);
  EXPECT_EQ(doc["scenario"], "p1_reference");
  // P1's tolerances, µm: F_r 50, f_pb 9, f_f 8, E_Hs 110, T_H 100.
  const auto& t = doc["tolerances_um"]["values"];
  EXPECT_EQ(t["F_r"]["value"].get<double>(), 50);
  EXPECT_EQ(t["f_pb"]["value"].get<double>(), 9);
  EXPECT_EQ(t["f_f"]["value"].get<double>(), 8);
  EXPECT_EQ(t["E_Hs"]["value"].get<double>(), 110);
  EXPECT_EQ(t["T_H"]["value"].get<double>(), 100);
  EXPECT_EQ(doc["tolerances_um"]["standard"], "gost_1643_81");
}

TEST(Cli, TheScenarioFileGivesTheSameAnswerAsTheBuiltIn) {
  const Result file =
      run(std::string("geometry ") + GEARMC_SOURCE_DIR + "/scenarios/p1_reference.yaml");
  const Result builtin = run("geometry");
  ASSERT_EQ(file.exit_code, 0) << file.err;
  auto a = nlohmann::json::parse(file.out), b = nlohmann::json::parse(builtin.out);
  a.erase("source");
  b.erase("source");
  EXPECT_EQ(a, b);
}

TEST(Cli, BadInputExitsWithTwoAndOneMessage) {
  const Result missing = run("geometry /nonexistent/scenario.yaml");
  EXPECT_EQ(missing.exit_code, 2);
  EXPECT_NE(missing.err.find("/nonexistent/scenario.yaml"), std::string::npos) << missing.err;
  EXPECT_TRUE(missing.out.empty());

  const std::string path = fresh_temp_path("bad_key.yaml").string();
  std::ofstream(path) << "gear:\n  teeth: 24\n  modul_mm: 5.6\n  face_width_mm: 10\n";
  const Result typo = run("geometry " + path);
  EXPECT_EQ(typo.exit_code, 2);
  EXPECT_NE(typo.err.find(path + ":3:3"), std::string::npos) << typo.err;
  EXPECT_NE(typo.err.find("module_mm"), std::string::npos) << typo.err;  // did you mean

  EXPECT_EQ(run("no-such-command").exit_code, 2);
  EXPECT_EQ(run("geometry a.yaml b.yaml").exit_code, 2);
  EXPECT_EQ(run("--help").exit_code, 0);
}

TEST(Cli, HelpVersionAndSuggestions) {
  // `gearmc` alone and `gearmc help` print the help (exit 0), as --help does.
  const Result bare = run("");
  EXPECT_EQ(bare.exit_code, 0);
  EXPECT_NE(bare.out.find("Usage: gearmc"), std::string::npos) << bare.out;
  EXPECT_EQ(run("help").out, bare.out);
  // --version: the CMake project version and the build's git commit.
  const Result version = run("--version");
  EXPECT_EQ(version.exit_code, 0);
  EXPECT_EQ(version.out.rfind("gearmc 0.1.0 (git ", 0), 0u) << version.out;
  // A mistyped command or option: exit 2, a suggestion, and where the help is.
  const Result command = run("rnu");
  EXPECT_EQ(command.exit_code, 2);
  EXPECT_NE(command.err.find("did you mean 'run'?"), std::string::npos) << command.err;
  const Result option = run("run --gaers 3");
  EXPECT_EQ(option.exit_code, 2);
  EXPECT_NE(option.err.find("did you mean '--gears'?"), std::string::npos) << option.err;
  EXPECT_NE(option.err.find("gearmc run --help"), std::string::npos) << option.err;
  // Each command's help has an example.
  EXPECT_NE(run("run --help").out.find("Example:"), std::string::npos);
}

TEST(Cli, FingerprintAndCommandLineText) {
  // FNV-1a 64 test vectors (draft-eastlake-fnv, and the reference implementation's table):
  // "" -> cbf29ce484222325, "a" -> af63dc4c8601ec8c, "foobar" -> 85944171f73967e8.
  EXPECT_EQ(gearmc::fnv1a64_text(""), "fnv1a64:cbf29ce484222325");
  EXPECT_EQ(gearmc::fnv1a64_text("a"), "fnv1a64:af63dc4c8601ec8c");
  EXPECT_EQ(gearmc::fnv1a64_text("foobar"), "fnv1a64:85944171f73967e8");
  const char* argv[] = {"gearmc", "run", "my file.yaml", "--out", "it's"};
  EXPECT_EQ(gearmc::command_line_text(5, argv), "gearmc run 'my file.yaml' --out 'it'\\''s'");
}

}  // namespace

#include "surfaces/flank_mesh.h"
#include "surfaces/mesh_contact.h"

namespace {

TEST(Cli, ExportMeshWritesAClosedGearThatReadsBack) {
  namespace fs = std::filesystem;
  for (const char* ext : {"stl", "ply", "obj", "off"}) {
    const fs::path file = fresh_temp_path(std::string("cli_gear2.") + ext);
    fs::remove(file);
    const Result r =
        run("export-mesh --gear 2 --profile-samples 8 --face-samples 6 --out " + file.string());
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const gearmc::TriangleMesh mesh = gearmc::read_mesh_file(file.string());
    EXPECT_GT(mesh.n_faces(), 1000u) << ext;
    const gearmc::MeshCheck check = gearmc::check_mesh(mesh);
    EXPECT_TRUE(check.closed) << ext;
    // Volume of P1's gear: b x transverse area = 1.26388e6 mm^3 (flank_mesh_test, analytic);
    // this coarse mesh's chords cut the flanks and tips, so within 1 %.
    EXPECT_NEAR(check.volume_mm3, 1.26388e6, 1.3e4) << ext;
  }
  const Result bad = run("export-mesh --gear 2 --out " + fresh_temp_path("gear.xyz").string());
  EXPECT_EQ(bad.exit_code, 2);
  EXPECT_NE(bad.err.find("--out: got"), std::string::npos) << bad.err;
  EXPECT_EQ(run("export-mesh --gear 2").exit_code, 2);  // --out is required
  // The mesh's size is bounded before any work (the allowed option maxima, 2000 × 20000, once
  // ran out of memory under 4 GB): P1's 24 teeth × (2 × 2000 + 6 + 12) = 96 432 vertices per
  // section, beyond 20 000; 200 × 1000 gives 24 × 418 = 10 032 per section and (1000 + 2) × 10 032
  // = 10 052 064 in all (sections and the end faces' inner rings), beyond 2 000 000.
  const std::string mesh = fresh_temp_path("big.stl").string();
  const Result wide =
      run("export-mesh --gear 0 --profile-samples 2000 --face-samples 20000 --out " + mesh);
  EXPECT_EQ(wide.exit_code, 2);
  EXPECT_NE(wide.err.find("these give 96432 per section"), std::string::npos) << wide.err;
  const Result long_mesh =
      run("export-mesh --gear 0 --profile-samples 200 --face-samples 1000 --out " + mesh);
  EXPECT_EQ(long_mesh.exit_code, 2);
  EXPECT_NE(long_mesh.err.find("10032 per section (24 teeth × (2 × 200 + 18)) and 10052064 in all"),
            std::string::npos)
      << long_mesh.err;
  EXPECT_FALSE(std::filesystem::exists(mesh));
  // A nearly pointed tooth (α 30°, x 0.9: nominal tip thickness 0.08 mm) whose drawn flanks
  // cross before the tip: no closed section exists. Once an abort (SIGABRT); now a message.
  const std::string pointed = fresh_temp_path("pointed.yaml").string();
  {
    std::ifstream in(std::string(GEARMC_SOURCE_DIR) + "/scenarios/p1_reference.yaml");
    std::stringstream text;
    text << in.rdbuf();
    std::string s = text.str();
    const auto at = s.find("pressure_angle_deg: 20");
    ASSERT_NE(at, std::string::npos);
    s.replace(at, 22, "pressure_angle_deg: 30");
    std::ofstream(pointed) << s;
  }
  int refused = 0;
  for (int gear = 0; gear < 8; ++gear) {
    const Result r = run("export-mesh " + pointed + " --gear " + std::to_string(gear) +
                         " --profile-samples 8 --face-samples 4 --out " + mesh);
    EXPECT_TRUE(r.exit_code == 0 || r.exit_code == 2) << r.exit_code << r.err;
    if (r.exit_code == 2) {
      ++refused;
      EXPECT_NE(r.err.find("has flanks that cross before its tip or root arc"), std::string::npos)
          << r.err;
      EXPECT_FALSE(std::filesystem::exists(mesh));
    }
    std::filesystem::remove(mesh);
  }
  EXPECT_GT(refused, 0);  // some of the first 8 gears have crossing flanks
}

TEST(Cli, OutputFilesThatCannotBeWrittenAreBadInputNamedBeforeTheWork) {
  // Before: `simulate` to a folder or an unwritable path said "internal error" (exit 1) after
  // the work, and export-mesh reported a refused path as "No such file or directory". /proc
  // refuses new files even for root (tests may run as root, so file modes prove nothing).
  const std::filesystem::path folder_path = fresh_temp_path("cli_out_folder");
  std::filesystem::create_directories(folder_path);
  const std::string folder = folder_path.string();
  for (const std::string& command :
       {std::string("simulate --out "), std::string("export-mesh --gear 0 --out ")}) {
    const std::string file_ext = command.rfind("simulate", 0) == 0 ? ".csv" : ".stl";
    const Result to_folder = run(command + folder);
    EXPECT_EQ(to_folder.exit_code, 2) << command << to_folder.err;
    EXPECT_NE(to_folder.err.find("not a folder"), std::string::npos) << to_folder.err;
    const Result missing = run(command + "/nonexistent-folder/x" + file_ext);
    EXPECT_EQ(missing.exit_code, 2) << command << missing.err;
    EXPECT_NE(missing.err.find("existing folder"), std::string::npos) << missing.err;
    const Result refused = run(command + "/proc/gearmc-x" + file_ext);
    EXPECT_EQ(refused.exit_code, 2) << command << refused.err;
    EXPECT_EQ(refused.err.find("internal error"), std::string::npos) << refused.err;
    EXPECT_TRUE(refused.out.empty()) << refused.out;  // nothing was computed
  }
}

}  // namespace
