// A flank whose real surface is a mesh file (scenario `surfaces:`): the probe's
// result semantics on hand-made situations (contact, border = edge, miss = failed, touching at
// the start of the approach = collision) and the nominal-flank coordinates it reports; a
// scenario whose mesh is the analytic perturbed flank, meshed finely, reproduces the analytic
// per-point delta_Rcomp of that gear within a tolerance derived from the measured convergence
// order; the mesh replaces the flank in every gear and nothing else; results stay bit-identical
// for any thread count; `gearmc run --points` writes consistent rows for the mesh flank; and each
// kind of bad `surfaces:` input is one InputError at the right line:column (exit 2 from the CLI).
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include <unistd.h>

#include "core/input_error.h"
#include "engine/contact/mesh_probe.h"
#include "engine/run/monte_carlo.h"
#include "engine/scenario/scenario.h"
#include "surfaces/flank_mesh.h"
#include "tests/support/run_compare.h"
#include "tests/support/run_gearmc.h"
#include "tests/support/temp_paths.h"

using ::gearmc::testing_support::fresh_temp_path;

namespace gearmc {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;

constexpr double kR = 0.5;  // P1's stylus, mm

// A fresh folder under the test temp dir, one per process (ctest runs each test in its own
// process, in parallel).
fs::path temp_folder(const std::string& name) {
  const fs::path dir = fresh_temp_path("mesh_surface_" + name);
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

// The reference scenario (P1's gear, tolerances and grid) with `extra` appended.
std::string reference_with(const std::string& extra) {
  return reference_scenario().source_text + "\n" + extra;
}

std::string surfaces_entry(int tooth, char flank, const std::string& mesh,
                           const std::string& contact = "") {
  std::string s = "  - tooth: " + std::to_string(tooth) + "\n    flank: " + flank +
                  "\n    mesh: " + mesh + "\n";
  if (!contact.empty()) s += "    contact: " + contact + "\n";
  return s;
}

// Real flank `tooth`, `side` of gear k of `scenario` (the same surface a run probes).
struct RealFlank {
  InvoluteGear gear;
  PerturbedGear perturbed;
  RealFlank(const Scenario& scenario, int k)
      : gear(scenario.gear),
        perturbed(GearSampler(gear, resolve_scenario_tolerances(scenario, gear),
                              scenario.deviations, scenario.seed)
                      .draw(k)) {}
  AnalyticFlank flank(int tooth, FlankSide side) const {
    return AnalyticFlank(gear, tooth, side, perturbed.flank(tooth, side),
                         perturbed.eccentricity_mm);
  }
};

// ---- the probe on hand-made meshes --------------------------------------------------------

// The nominal flank of tooth 5 (no deviation) over a (L, z) box, moved by `offset_mm` along the
// normal, with steps of about 0.5 mm.
TriangleMesh nominal_flank_mesh(const InvoluteGear& gear, FlankSide side, double z0, double z1,
                                double offset_mm = 0.0) {
  const int nL = 48, nz = 1 + static_cast<int>(std::ceil((z1 - z0) / 0.5));
  TriangleMesh mesh;
  std::vector<TriangleMesh::VertexHandle> v;
  const double L0 = gear.form_roll_length_mm(), L1 = gear.tip_roll_length_mm();
  for (int j = 0; j < nz; ++j) {
    for (int i = 0; i < nL; ++i) {
      const FlankPoint fp =
          gear.flank_point(5, side, L0 + (L1 - L0) * i / (nL - 1), z0 + (z1 - z0) * j / (nz - 1));
      const Eigen::Vector3d x = fp.point + offset_mm * fp.normal;
      v.push_back(mesh.add_vertex({x.x(), x.y(), x.z()}));
    }
  }
  for (int j = 0; j + 1 < nz; ++j) {
    for (int i = 0; i + 1 < nL; ++i) {
      const int a = j * nL + i;
      mesh.add_face(v[a], v[a + 1], v[a + nL + 1]);
      mesh.add_face(v[a], v[a + nL + 1], v[a + nL]);
    }
  }
  return mesh;
}

TEST(MeshFlankProbe, NominalFlankCoordinatesInvertTheFlankPoint) {
  const InvoluteGear gear(reference_scenario().gear);
  for (int tooth : {1, 7, 24}) {
    for (FlankSide side : {FlankSide::kLeft, FlankSide::kRight}) {
      for (double L : {22.0, 33.3, 45.0}) {
        for (double d : {-0.3, 0.0, 0.02, 0.9}) {
          const FlankPoint fp = gear.flank_point(tooth, side, L, 12.5);
          const NominalFlankCoordinates c =
              nominal_flank_coordinates(gear, tooth, side, fp.point + d * fp.normal);
          EXPECT_NEAR(c.roll_length_mm, L, 1e-9);
          EXPECT_NEAR(c.offset_mm, d, 1e-9);  // + = outside the material
          EXPECT_EQ(c.z_mm, 12.5);
        }
      }
    }
  }
}

TEST(MeshFlankProbe, ContactEdgeMissAndTouchingAtTheStart) {
  const InvoluteGear gear(reference_scenario().gear);
  for (FlankSide side : {FlankSide::kLeft, FlankSide::kRight}) {
    SCOPED_TRACE(side_letter(side));
    // The nominal flank from z = 0 to 40 mm only (a partial scan).
    const MeshFlankProbe probe(gear, 5, side, nominal_flank_mesh(gear, side, 0.0, 40.0),
                               MeshContactPoint::kSmoothed);
    // Inside: an ordinary contact. On the nominal flank the contact is at p, within the mesh's
    // chord error (L step 0.5 mm: 0.5^2/8 * 45/63.15^2 = 0.35 µm).
    const FlankPoint inside = gear.flank_point(5, side, 33.0, 20.0);
    ContactResult r = probe.probe(inside.point, inside.normal, kR);
    ASSERT_EQ(r.status, ContactResult::Status::kOk);
    EXPECT_NEAR((r.contact - r.centre).norm(), kR, 1e-12);
    EXPECT_LT((r.contact - inside.point).norm(), 1e-3);
    EXPECT_NEAR(r.roll_length_mm, 33.0, 0.01);
    EXPECT_NEAR(r.z_mm, 20.0, 0.01);
    EXPECT_NEAR(r.delta_um, 1e3 * (r.contact - (r.centre - kR * inside.normal)).norm(), 1e-9);
    // At z = 40.2 the sphere meets the mesh's border edge z = 40 first: an edge contact.
    const FlankPoint near_border = gear.flank_point(5, side, 33.0, 40.2);
    EXPECT_EQ(probe.probe(near_border.point, near_border.normal, kR).status,
              ContactResult::Status::kEdge);
    // At z = 60 there is no mesh: the sphere passes it, a failed contact that says why.
    const FlankPoint beyond = gear.flank_point(5, side, 33.0, 60.0);
    r = probe.probe(beyond.point, beyond.normal, kR);
    EXPECT_EQ(r.status, ContactResult::Status::kNotConverged);
    EXPECT_EQ(spelling(r.failure), "no_mesh_contact");
    // A surface 1.2 mm proud of the nominal flank is already touched where the approach starts
    // (1 mm outside the nominal touching position): a collision, not a measured value.
    const MeshFlankProbe proud(gear, 5, side, nominal_flank_mesh(gear, side, 0.0, 78.89, 1.2),
                               MeshContactPoint::kFacets);
    r = proud.probe(inside.point, inside.normal, kR);
    EXPECT_EQ(r.status, ContactResult::Status::kCollision);
    EXPECT_EQ(spelling(r.collision), "touching_at_start");
    // 0.8 mm proud is still inside the search window: found, 0.8 mm further out.
    const MeshFlankProbe raised(gear, 5, side, nominal_flank_mesh(gear, side, 0.0, 78.89, 0.8),
                                MeshContactPoint::kFacets);
    r = raised.probe(inside.point, inside.normal, kR);
    ASSERT_EQ(r.status, ContactResult::Status::kOk);
    EXPECT_NEAR((r.centre - inside.point).dot(inside.normal), kR + 0.8, 1e-3);
  }
}

// ---- a scenario whose mesh is the analytic perturbed flank ---------------------------------

// Per-point comparison of the mesh flank 3R with the analytic flank 3R of gear 0.
//
// Tolerance, from the measured convergence (tests/surfaces/mesh_contact_test.cpp: on P1's
// gear and tolerances with P1's grid and R = 0.5 mm, the stylus centre O converges with order
// 1.93 and the smoothed contact point C_s with order 2.00, both <= 79 nm at 0.25 mm steps, within
// the interpolation bound e <= 89 nm there, which is dominated by the involute's curvature and
// so holds for every gear of the scenario; the exact facet point C only with order 1.06, 765 nm):
// delta = |C - E| with E = O - R n, so |delta_mesh - delta| <= |C_s,mesh - C| + |O_mesh - O|
// <= 2 e = 0.18 µm at h = 0.25 mm. The file is binary STL, single precision: vertices move by up
// to |x| 2^-24 <= 5 nm, i.e. a surface shift of <= 5 nm and facet tilts of up to ~5 nm / 0.25 mm
// = 2e-5 rad, <= 10 nm in C_s at R = 0.5 mm. Asserted at h = 0.25 mm: max |d delta| < 0.2 µm,
// max |dO| and max |dC_s| < 0.1 µm (e + rounding); and from h = 0.5 to 0.25 mm |dO| and |dC_s|
// fall by more than 3 (order > 1.58; measured 4.2, order 2.07).
// Measured here (the test prints it):
//   h mm   max|d delta| µm  max|dO| µm  max|dC_s| µm
//   0.50           0.0289      0.3313        0.3326
//   0.25           0.0148      0.0790        0.0790
//   0.25 facets: max|d delta| 0.8117 µm
// delta's own error is far below |dO| + |dC_s|: the chord error of the mesh is mostly an offset
// along the normal, which moves O and C_s together and leaves delta unchanged (an offset gives
// no delta); what remains are tilt errors and the file's float rounding, so delta's error does
// not show a clean order. The facet contact point is 50 times worse at h = 0.25 mm: that is why
// `contact: smoothed` is the default for meshes of smooth flanks.
TEST(MeshSurfaceScenario, AnalyticFlankMeshGivesTheAnalyticDeltaRcomp) {
  const fs::path dir = temp_folder("convergence");
  const std::string plan = "run: {gears: 2}\n";
  std::string base = reference_scenario().source_text;
  base = base.substr(0, base.find("run:"));  // the reference's run section is replaced
  const Scenario analytic_scenario = parse_scenario(base + plan, (dir / "a.yaml").string());
  const MonteCarloRun analytic(analytic_scenario);
  const GearOutcome exact = analytic.measure_gear(0, true);
  const RealFlank real(analytic_scenario, 0);
  const AnalyticFlank flank = real.flank(3, FlankSide::kRight);

  const double steps[] = {0.5, 0.25};
  double max_delta_error[2] = {0, 0}, max_centre_error[2] = {0, 0}, max_contact_error[2] = {0, 0};
  double facet_delta_error = 0.0;
  for (int s = 0; s < 2; ++s) {
    const std::string file = "flank_3R_" + std::to_string(s) + ".stl";
    write_mesh_file(mesh_flank(flank, whole_flank_spec(real.gear, steps[s], steps[s])),
                    (dir / file).string());
    for (const std::string contact : {"smoothed", "facets"}) {
      if (contact == "facets" && s == 0) continue;
      const Scenario scenario = parse_scenario(
          base + plan + "surfaces:\n" + surfaces_entry(3, 'R', file, contact),
          (dir / "m.yaml").string());  // the mesh path is relative to the scenario's folder
      ASSERT_EQ(scenario.surfaces.size(), 1u);
      EXPECT_EQ(scenario.surfaces[0].mesh_path, (dir / file).string());
      const MonteCarloRun mc(scenario);
      const GearOutcome meshed = mc.measure_gear(0, true);
      ASSERT_EQ(meshed.points.size(), exact.points.size());
      EXPECT_EQ(meshed.failed + meshed.edge + meshed.collisions, 0u);
      int compared = 0;
      for (std::size_t k = 0; k < exact.points.size(); ++k) {
        const ProbedPoint &a = exact.points[k], &m = meshed.points[k];
        ASSERT_EQ(m.tooth, a.tooth);
        ASSERT_EQ(m.side, a.side);
        ASSERT_EQ(m.contact.status, ContactResult::Status::kOk);
        if (a.tooth != 3 || a.side != FlankSide::kRight) {
          // Every other flank is the analytic one, bit for bit.
          EXPECT_EQ(m.contact.delta_um, a.contact.delta_um);
          continue;
        }
        ++compared;
        EXPECT_NEAR((m.contact.contact - m.contact.centre).norm(), kR, 1e-12);
        const double dd = std::abs(m.contact.delta_um - a.contact.delta_um);
        if (contact == "facets") {
          facet_delta_error = std::max(facet_delta_error, dd);
          continue;
        }
        max_delta_error[s] = std::max(max_delta_error[s], dd);
        max_centre_error[s] =
            std::max(max_centre_error[s], 1e3 * (m.contact.centre - a.contact.centre).norm());
        max_contact_error[s] =
            std::max(max_contact_error[s], 1e3 * (m.contact.contact - a.contact.contact).norm());
      }
      EXPECT_EQ(compared, 50);
    }
  }
  std::printf(
      "  h mm   max|d delta| µm  max|dO| µm  max|dC_s| µm   (flank 3R of gear 0, 50 points)\n");
  for (int s = 0; s < 2; ++s) {
    std::printf("  %4.2f   %14.4f  %10.4f  %12.4f\n", steps[s], max_delta_error[s],
                max_centre_error[s], max_contact_error[s]);
  }
  std::printf("  0.25 facets: max|d delta| %.4f µm\n", facet_delta_error);
  EXPECT_LT(max_delta_error[1], 0.2);
  EXPECT_LT(max_centre_error[1], 0.1);
  EXPECT_LT(max_contact_error[1], 0.1);
  EXPECT_GT(max_centre_error[0], 3 * max_centre_error[1]);
  EXPECT_GT(max_contact_error[0], 3 * max_contact_error[1]);
  EXPECT_GT(facet_delta_error, 4 * max_delta_error[1]);
}

TEST(MeshSurfaceScenario, TheMeshIsTheFlankOfEveryGearAndThreadsDoNotMatter) {
  const fs::path dir = temp_folder("every_gear");
  const Scenario plain = reference_scenario();
  const RealFlank real(plain, 0);
  write_mesh_file(
      mesh_flank(real.flank(7, FlankSide::kLeft), whole_flank_spec(real.gear, 1.0, 2.0)),
      (dir / "flank_7L.ply").string());
  const Scenario scenario =
      parse_scenario(reference_with("surfaces:\n" + surfaces_entry(7, 'L', "flank_7L.ply")),
                     (dir / "s.yaml").string());
  const MonteCarloRun mc(scenario);
  const GearOutcome g0 = mc.measure_gear(0, true), g3 = mc.measure_gear(3, true);
  int same = 0, differ = 0;
  for (std::size_t k = 0; k < g0.points.size(); ++k) {
    const ProbedPoint &a = g0.points[k], &b = g3.points[k];
    ASSERT_EQ(a.contact.status, ContactResult::Status::kOk);
    if (a.tooth == 7 && a.side == FlankSide::kLeft) {
      // The same mesh in gear 0 and gear 3: the same contact, whatever gear 3's deviations.
      EXPECT_EQ(a.contact.centre, b.contact.centre);
      EXPECT_EQ(a.contact.delta_um, b.contact.delta_um);
      ++same;
    } else {
      differ += a.contact.delta_um != b.contact.delta_um;
    }
  }
  EXPECT_EQ(same, 50);
  EXPECT_GT(differ, 2000);  // the analytic flanks differ from gear to gear
  RunOptions one;
  one.end_gear = 6;
  one.threads = 1;
  RunOptions two = one;
  two.threads = 2;
  const RunResults a = mc.run(one), b = mc.run(two);
  testing_support::expect_identical_statistics(a, b);
  EXPECT_EQ(a.contacts, 6u * 24 * 2 * 50);
  EXPECT_EQ(a.failed_contacts + a.edge_contacts + a.collisions, 0u);
}

// A mesh that covers only part of the flank: the points it misses are counted as failed
// contacts, never dropped silently.
TEST(MeshSurfaceScenario, UncoveredPointsAreCountedNotDropped) {
  const fs::path dir = temp_folder("partial");
  const Scenario plain = reference_scenario();
  const RealFlank real(plain, 0);
  FlankMeshSpec spec = whole_flank_spec(real.gear, 1.0, 1.0);
  spec.z_max_mm = 30.0;  // sections j = 0, 1 (z = 3.9, 21.7 mm) are covered, 2..4 are not
  spec.z_samples = 31;
  write_mesh_file(mesh_flank(real.flank(2, FlankSide::kRight), spec),
                  (dir / "partial.obj").string());
  const Scenario scenario =
      parse_scenario(reference_with("surfaces:\n" + surfaces_entry(2, 'R', "partial.obj")),
                     (dir / "s.yaml").string());
  const GearOutcome g = MonteCarloRun(scenario).measure_gear(1, true);
  EXPECT_EQ(g.contacts, 24u * 2 * 50);
  EXPECT_EQ(g.failed, 30u);  // 3 sections x 10 profile points
  EXPECT_EQ(g.point_delta[1].size(), 24u * 50 - 30);
  for (const ProbedPoint& p : g.points) {
    if (p.tooth == 2 && p.side == FlankSide::kRight && p.j >= 2) {
      EXPECT_EQ(spelling(p.contact.failure), "no_mesh_contact");
    }
  }
}

// ---- gearmc run --points with a mesh written by gearmc export-mesh ------------------------

TEST(MeshSurfaceCli, RunWritesPointsOnTheExportedMesh) {
  const fs::path dir = temp_folder("cli");
  // The whole gear 0 as export-mesh writes it (datum frame, mm), used as flank 3R's surface.
  const testing_support::CommandResult exported =
      testing_support::run_gearmc("export-mesh --gear 0 --out " + (dir / "gear0.stl").string());
  ASSERT_EQ(exported.exit_code, 0) << exported.err;
  std::ofstream(dir / "s.yaml") << reference_with("surfaces:\n" +
                                                  surfaces_entry(3, 'R', "gear0.stl", "smoothed"));
  const testing_support::CommandResult r =
      testing_support::run_gearmc("run " + (dir / "s.yaml").string() +
                                  " --gears 2 --points --quiet --out " + (dir / "out").string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_THAT(r.out, HasSubstr("flank 3R is the mesh"));
  std::ifstream points(dir / "out" / "points.csv");
  std::string line;
  std::getline(points, line);  // column names (the first line)
  ASSERT_EQ(line.rfind("gear,tooth,flank", 0), 0u) << line;
  int rows = 0, mesh_rows = 0;
  std::vector<std::string> first_gear_rows;
  while (std::getline(points, line)) {
    std::stringstream ss(line);
    std::string cell;
    std::vector<std::string> cells;
    while (std::getline(ss, cell, ',')) cells.push_back(cell);
    ASSERT_EQ(cells.size(), 23u);
    ASSERT_EQ(cells[22], "ok") << line;
    ++rows;
    if (cells[1] != "3" || cells[2] != "R") continue;
    ++mesh_rows;
    auto vec = [&](int k) {
      return Eigen::Vector3d(std::stod(cells[k]), std::stod(cells[k + 1]), std::stod(cells[k + 2]));
    };
    const Eigen::Vector3d n = vec(8), c = vec(11), o = vec(14), e = vec(17);
    EXPECT_NEAR((c - o).norm(), kR, 1e-9);  // |C - O| = R (17 digits in the file)
    EXPECT_NEAR((e - (o - kR * n)).norm(), 0.0, 1e-12);
    EXPECT_NEAR(std::stod(cells[20]), 1e3 * (c - e).norm(), 1e-9);
    EXPECT_NEAR(std::stod(cells[21]), 1e3 * (e - c).dot(n), 1e-9);
    // The same mesh in both gears: the rows differ only in the gear column.
    const std::string rest = line.substr(line.find(','));
    if (cells[0] == "0") {
      first_gear_rows.push_back(rest);
    } else {
      EXPECT_EQ(rest, first_gear_rows.at(mesh_rows - 51));
    }
  }
  EXPECT_EQ(rows, 2 * 24 * 2 * 50);
  EXPECT_EQ(mesh_rows, 2 * 50);
  std::ifstream summary_file(dir / "out" / "summary.json");
  const std::string summary((std::istreambuf_iterator<char>(summary_file)), {});
  EXPECT_THAT(summary, HasSubstr("\"mesh_surfaces\""));
  EXPECT_THAT(summary, HasSubstr("\"contact\": \"smoothed\""));
  std::ifstream report_file(dir / "out" / "report.html");
  const std::string report((std::istreambuf_iterator<char>(report_file)), {});
  EXPECT_THAT(report, HasSubstr("Flank 3R is the mesh"));
}

// ---- bad input -----------------------------------------------------------------------------

// The InputError that parsing `text` (as the file `path`) throws.
InputError parse_error(const std::string& text, const fs::path& path) {
  try {
    parse_scenario(text, path.string());
  } catch (const InputError& e) {
    return e;
  }
  ADD_FAILURE() << "no InputError for:\n" << text;
  return InputError({}, "no error");
}

// The line of the reference text + "surfaces:\n" where the first entry starts.
int first_entry_line() {
  const std::string text = reference_scenario().source_text + "\n";
  return static_cast<int>(std::count(text.begin(), text.end(), '\n')) + 2;
}

class MeshSurfaceInputTest : public testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new fs::path(temp_folder("bad_input"));
    const Scenario plain = reference_scenario();
    const RealFlank real(plain, 0);
    write_mesh_file(
        mesh_flank(real.flank(3, FlankSide::kRight), whole_flank_spec(real.gear, 2.0, 4.0)),
        (*dir_ / "flank_3R.stl").string());
  }
  static void TearDownTestSuite() { delete dir_; }
  // Parses the reference scenario with `surfaces` appended, as the file <dir>/s.yaml.
  static InputError error_for(const std::string& surfaces) {
    return parse_error(reference_with("surfaces:\n" + surfaces), *dir_ / "s.yaml");
  }
  static void expect_at(const InputError& e, int line, int column) {
    EXPECT_EQ(e.where().file, (*dir_ / "s.yaml").string()) << e.what();
    EXPECT_EQ(e.where().line, line) << e.what();
    EXPECT_EQ(e.where().column, column) << e.what();
  }
  static fs::path* dir_;
};
fs::path* MeshSurfaceInputTest::dir_ = nullptr;

TEST_F(MeshSurfaceInputTest, AGoodEntryParses) {
  const Scenario s = parse_scenario(
      reference_with("surfaces:\n" + surfaces_entry(3, 'R', "flank_3R.stl", "facets")),
      (*dir_ / "s.yaml").string());
  ASSERT_EQ(s.surfaces.size(), 1u);
  EXPECT_EQ(s.surfaces[0].tooth, 3);
  EXPECT_EQ(s.surfaces[0].side, FlankSide::kRight);
  EXPECT_EQ(s.surfaces[0].contact, MeshContactPoint::kFacets);
  EXPECT_GT(s.surfaces[0].mesh->n_faces(), 100u);
}

TEST_F(MeshSurfaceInputTest, UnknownKeyWithHint) {
  const InputError e = error_for(surfaces_entry(3, 'R', "flank_3R.stl") + "    contcat: facets\n");
  expect_at(e, first_entry_line() + 3, 5);
  EXPECT_THAT(e.what(), HasSubstr("surfaces[0].contcat"));
  EXPECT_THAT(e.what(), HasSubstr("did you mean 'contact'?"));
}

TEST_F(MeshSurfaceInputTest, ToothOutOfRange) {
  for (int tooth : {0, 25}) {
    const InputError e = error_for(surfaces_entry(tooth, 'R', "flank_3R.stl"));
    expect_at(e, first_entry_line(), 12);
    EXPECT_THAT(e.what(), HasSubstr("surfaces[0].tooth: got '" + std::to_string(tooth) +
                                    "', expected an integer from 1 to 24"));
  }
}

TEST_F(MeshSurfaceInputTest, FlankMustBeLOrR) {
  const InputError e = error_for(surfaces_entry(3, 'X', "flank_3R.stl"));
  expect_at(e, first_entry_line() + 1, 12);
  EXPECT_THAT(e.what(), HasSubstr("surfaces[0].flank: got 'X', expected one of L, R"));
}

TEST_F(MeshSurfaceInputTest, ContactMustBeSmoothedOrFacets) {
  const InputError e = error_for(surfaces_entry(3, 'R', "flank_3R.stl", "smooth"));
  expect_at(e, first_entry_line() + 3, 14);
  EXPECT_THAT(e.what(), HasSubstr("surfaces[0].contact: got 'smooth'"));
  EXPECT_THAT(e.what(), HasSubstr("did you mean 'smoothed'?"));
}

TEST_F(MeshSurfaceInputTest, MissingMeshKey) {
  const InputError e = error_for("  - tooth: 3\n    flank: R\n");
  EXPECT_THAT(e.what(), HasSubstr("surfaces[0].mesh"));
  EXPECT_THAT(e.what(), HasSubstr("required key is missing"));
}

TEST_F(MeshSurfaceInputTest, MissingMeshFile) {
  const InputError e = error_for(surfaces_entry(3, 'R', "no_such_flank.stl"));
  expect_at(e, first_entry_line() + 2, 11);
  EXPECT_THAT(e.what(), HasSubstr("surfaces[0].mesh: got 'no_such_flank.stl', expected a "
                                  "triangle mesh file"));
  EXPECT_THAT(e.what(), HasSubstr((*dir_ / "no_such_flank.stl").string()));  // as resolved
  EXPECT_THAT(e.what(), HasSubstr("cannot read mesh file"));
  EXPECT_THAT(e.what(), HasSubstr("No such file or directory"));  // the system's reason
}

TEST_F(MeshSurfaceInputTest, UnknownMeshExtension) {
  const InputError e = error_for(surfaces_entry(3, 'R', "flank_3R.xyz"));
  expect_at(e, first_entry_line() + 2, 11);
  EXPECT_THAT(e.what(), HasSubstr("unknown extension '.xyz'"));
}

TEST_F(MeshSurfaceInputTest, InvalidMeshFile) {
  std::ofstream(*dir_ / "garbage.off") << "this is not an OFF file\n";
  const InputError e = error_for(surfaces_entry(3, 'R', "garbage.off"));
  expect_at(e, first_entry_line() + 2, 11);
  EXPECT_THAT(e.what(), HasSubstr("surfaces[0].mesh: got 'garbage.off'"));
  EXPECT_THAT(e.what(), HasSubstr("not a valid OFF file"));
}

TEST_F(MeshSurfaceInputTest, MeshWithoutTriangles) {
  std::ofstream(*dir_ / "points.off") << "OFF\n3 0 0\n0 0 0\n1 0 0\n0 1 0\n";
  const InputError e = error_for(surfaces_entry(3, 'R', "points.off"));
  expect_at(e, first_entry_line() + 2, 11);
  EXPECT_THAT(e.what(), HasSubstr("contains no triangles"));
}

TEST_F(MeshSurfaceInputTest, MeshOfAnotherFlank) {
  // flank_3R.stl named as the surface of 4R (one pitch away) and of 3L (across the tooth).
  for (const auto& [tooth, flank] : {std::pair{4, 'R'}, std::pair{3, 'L'}}) {
    const InputError e = error_for(surfaces_entry(tooth, flank, "flank_3R.stl"));
    expect_at(e, first_entry_line() + 2, 11);
    EXPECT_THAT(e.what(), HasSubstr("no vertex of"));
    EXPECT_THAT(e.what(),
                HasSubstr("within 1 mm of the nominal flank " + std::to_string(tooth) + flank));
  }
}

TEST_F(MeshSurfaceInputTest, MeshInOtherUnits) {
  // The same flank in metres: no vertex near the flank.
  TriangleMesh metres = read_mesh_file((*dir_ / "flank_3R.stl").string());
  for (const TriangleMesh::VertexHandle v : metres.vertices()) metres.point(v) *= 1e-3;
  write_mesh_file(metres, (*dir_ / "flank_3R_m.stl").string());
  const InputError e = error_for(surfaces_entry(3, 'R', "flank_3R_m.stl"));
  expect_at(e, first_entry_line() + 2, 11);
  EXPECT_THAT(e.what(), HasSubstr("another frame or unit"));
}

TEST_F(MeshSurfaceInputTest, NonFiniteCoordinate) {
  // Binary STL stores raw floats, so a NaN survives the file (text formats fail to parse it).
  TriangleMesh mesh = read_mesh_file((*dir_ / "flank_3R.stl").string());
  mesh.point(TriangleMesh::VertexHandle(5))[1] = std::numeric_limits<double>::quiet_NaN();
  write_mesh_file(mesh, (*dir_ / "nan.stl").string());
  const InputError e = error_for(surfaces_entry(3, 'R', "nan.stl"));
  expect_at(e, first_entry_line() + 2, 11);
  EXPECT_THAT(e.what(), HasSubstr("has a coordinate that is not a finite number"));
}

TEST_F(MeshSurfaceInputTest, FlankGivenTwice) {
  const InputError e = error_for(surfaces_entry(3, 'R', "flank_3R.stl") +
                                 surfaces_entry(3, 'R', "flank_3R.stl", "facets"));
  expect_at(e, first_entry_line() + 4, 12);
  EXPECT_THAT(e.what(), HasSubstr("surfaces[1].flank"));
  EXPECT_THAT(e.what(), HasSubstr("already given at line " + std::to_string(first_entry_line())));
}

TEST_F(MeshSurfaceInputTest, FlankTheProbingPlanLeavesOut) {
  std::string text = reference_scenario().source_text;
  text.replace(text.find("flanks: both"), 12, "flanks: L   ");
  const InputError e = parse_error(text + "\nsurfaces:\n" + surfaces_entry(3, 'R', "flank_3R.stl"),
                                   *dir_ / "s.yaml");
  expect_at(e, first_entry_line(), 12);
  EXPECT_THAT(e.what(), HasSubstr("a flank the probing plan probes"));
}

TEST_F(MeshSurfaceInputTest, SurfacesMustBeAList) {
  const InputError e = parse_error(reference_with("surfaces: {tooth: 3, flank: R, mesh: a.stl}\n"),
                                   *dir_ / "s.yaml");
  expect_at(e, first_entry_line() - 1, 11);
  EXPECT_THAT(e.what(), HasSubstr("surfaces: got '{tooth: 3, flank: R, mesh: a.stl}', expected a "
                                  "list of flank meshes"));
}

TEST_F(MeshSurfaceInputTest, TheCliExitsWithTwoAndNamesThePlace) {
  std::ofstream(*dir_ / "cli.yaml")
      << reference_with("surfaces:\n" + surfaces_entry(3, 'R', "missing.ply"));
  const testing_support::CommandResult r =
      testing_support::run_gearmc("run " + (*dir_ / "cli.yaml").string() + " --gears 1 --quiet");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_THAT(r.err, HasSubstr((*dir_ / "cli.yaml").string() + ":" +
                               std::to_string(first_entry_line() + 2) +
                               ":11: surfaces[0].mesh: "
                               "got 'missing.ply'"));
  EXPECT_TRUE(r.out.empty()) << r.out;
}

}  // namespace
}  // namespace gearmc
