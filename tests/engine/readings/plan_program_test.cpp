// A user's DMIS program as the probing plan (`gearmc run --plan`, `gearmc simulate --plan`;
// engine/cli/plan_program.h, engine/readings/point_matching.h: plan_from_dmis):
//  * a hand-written program in INCH with continuation lines — a profile scan of 20 points on
//    tooth 3's R flank of P1's gear at z = 30 mm, nominal points and normals computed here from
//    the involute's polar form (ISO 21771: polar angle tooth centre + ψ(r), ψ = s/d + inv α −
//    inv α_r; the normal perpendicular to the curve's numerical tangent, away from the tooth),
//    not from gearmc's flank code — drives `simulate`: 20 readings per gear, labelled tooth 3 R,
//    i 0 … 19 along the profile in one section, each nominal point the program's to its
//    rounding (7 decimals of an inch: 1.27e-6 mm per coordinate, 2.2e-6 mm in all);
//  * the program `export-plan` writes for the helical example drives `run` exactly as the
//    scenario's own grid does (the same statistics in summary.json to 1e-9 µm, the ISO 1328-1
//    parameters to 1e-5 µm: the program's traces are the grid's mid section and column);
//  * a hand-written program of one profile trace and one helix trace per flank on a gear with a
//    deterministic linear deviation k_L L + k_z z (deviations.normal_um): the evaluation takes
//    the program's traces and states f_Hα = k_L L_α and f_Hβ = k_z L_β (a straight line's rise
//    over the evaluation range), F_α and F_β the rise over the trace's own points (over the
//    range for the true values), no form deviation; L_α from the form and tip circles of
//    docs/scenarios.md (d_Ff 133.328 mm, d_a 155.693 mm) and the base circle m z cos α;
//  * a point 50 µm off the flank, and one whose vector is 5° off the normal, are refused at their
//    statement (exit 2, file:line:column), and so is `--plan` with dedicated evaluation scans.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <numbers>
#include <sstream>

#include "engine/readings/readings_csv.h"
#include "tests/support/run_gearmc.h"
#include "tests/support/temp_paths.h"
#include "tests/support/text_files.h"

namespace gearmc {
namespace {

namespace fs = std::filesystem;
using testing_support::read_text;
using testing_support::run_gearmc;
using testing_support::write_text;

// P1's gear (scenarios/p1_reference.yaml): z 24, m 5.6 mm, α 20°, x 0.90116.
struct PolarInvolute {
  double z = 24, m = 5.6, alpha = 20.0 * std::numbers::pi / 180.0, x = 0.90116;
  double d() const { return m * z; }
  double rb() const { return 0.5 * d() * std::cos(alpha); }
  double inv(double a) const { return std::tan(a) - a; }
  // Half tooth angle at radius r: s/d + inv α − inv α_r, s = m (π/2 + 2 x tan α).
  double psi(double r) const {
    const double s = m * (std::numbers::pi / 2 + 2 * x * std::tan(alpha));
    return s / d() + inv(alpha) - inv(std::acos(rb() / r));
  }
  // The R flank (counter-clockwise side) of tooth k (centred on (k - 1) 2π/z) at radius r.
  Eigen::Vector2d point(int k, double r) const {
    const double a = (k - 1) * 2 * std::numbers::pi / z + psi(r);
    return {r * std::cos(a), r * std::sin(a)};
  }
  // Its outward normal: perpendicular to the numerical tangent, pointing counter-clockwise.
  Eigen::Vector2d normal(int k, double r) const {
    const double h = 1e-6;
    const Eigen::Vector2d t = (point(k, r + h) - point(k, r - h)).normalized();
    Eigen::Vector2d n(-t.y(), t.x());
    const Eigen::Vector2d P = point(k, r);
    const Eigen::Vector2d ccw(-P.y(), P.x());
    return n.dot(ccw) > 0 ? n : Eigen::Vector2d(-n);
  }
};

std::string fixed(double v, int digits) {
  std::ostringstream s;
  s.setf(std::ios::fixed);
  s.precision(digits);
  s << v;
  return s.str();
}

TEST(PlanProgram, AHandWrittenProgramInInchDrivesSimulate) {
  const fs::path dir = testing_support::fresh_temp_path("plan_program");
  fs::create_directories(dir);
  const PolarInvolute g;
  // Radii from the form circle (d_Ff 133.328 mm, docs/scenarios.md) to the tip (d_a 155.693 mm)
  // with a margin: 67.2 … 77.2 mm.
  std::ostringstream program;
  program << "DMISMN/'a user''s profile scan',05.3\n$$ tooth 3, R flank, z = 30 mm\n"
             "UNITS/INCH,ANGDEC\n";
  std::vector<Eigen::Vector3d> nominal;
  for (int i = 0; i < 20; ++i) {
    const double r = 67.2 + 10.0 * i / 19.0;
    const Eigen::Vector2d P = g.point(3, r), n = g.normal(3, r);
    nominal.emplace_back(P.x(), P.y(), 30.0);
    const std::string label = "SCAN_" + std::to_string(i);
    // 7 decimals of an inch: each coordinate rounded by up to 0.5e-7 inch = 1.27e-6 mm.
    program << "F(" << label << ")=FEAT/POINT,CART," << fixed(P.x() / 25.4, 7) << ","
            << fixed(P.y() / 25.4, 7) << ",$\n  " << fixed(30.0 / 25.4, 7) << "," << fixed(n.x(), 9)
            << "," << fixed(n.y(), 9) << ",0\n"
            << "MEAS/POINT,F(" << label << "),1\nPTMEAS/CART," << fixed(P.x() / 25.4, 7) << ","
            << fixed(P.y() / 25.4, 7) << "," << fixed(30.0 / 25.4, 7) << "," << fixed(n.x(), 9)
            << "," << fixed(n.y(), 9) << ",0\nENDMES\n";
  }
  program << "ENDFIL\n";
  write_text(dir / "scan.dmi", program.str());
  const std::string csv = (dir / "scan.csv").string();
  const auto r =
      run_gearmc("simulate --gears 2 --plan " + (dir / "scan.dmi").string() + " --out " + csv);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const Readings readings = read_readings(csv);
  ASSERT_EQ(readings.rows.size(), 40u);
  for (std::size_t k = 0; k < readings.rows.size(); ++k) {
    const ReadingRow& row = readings.rows[k];
    EXPECT_EQ(row.tooth, 3);
    EXPECT_EQ(row.side, FlankSide::kRight);
    EXPECT_EQ(row.j, 0);
    EXPECT_EQ(row.i, static_cast<int>(k % 20));
    EXPECT_LT((row.p - nominal[k % 20]).norm(), std::sqrt(3.0) * 1.27e-6) << k;
  }
}

TEST(PlanProgram, TheExportedProgramRunsAsTheScenariosGrid) {
  const fs::path dir = testing_support::fresh_temp_path("plan_program_helical");
  fs::create_directories(dir);
  write_text(dir / "h.yaml",
             "name: helical\n"
             "gear: {teeth: 31, module_mm: 4, pressure_angle_deg: 20, helix_angle_deg: 15, "
             "hand: right, profile_shift: 0.2, face_width_mm: 40}\n"
             "tolerances: {standard: iso_1328_1_2013, grade: 6}\n"
             "probing: {points_along_profile: 6, sections_across_face: 4, teeth: [2, 9, 17]}\n"
             "evaluation: {parameters: all}\n"
             "run: {gears: 3}\n");
  const std::string s = (dir / "h.yaml").string(), plan = (dir / "h.dmi").string();
  ASSERT_EQ(run_gearmc("export-plan " + s + " --format dmis --out " + plan).exit_code, 0);
  const auto grid = run_gearmc("run " + s + " --out " + (dir / "grid").string());
  const auto program =
      run_gearmc("run " + s + " --plan " + plan + " --out " + (dir / "program").string());
  ASSERT_EQ(grid.exit_code, 0) << grid.err;
  ASSERT_EQ(program.exit_code, 0) << program.err;
  const auto a = nlohmann::json::parse(read_text(dir / "grid" / "summary.json"));
  const auto b = nlohmann::json::parse(read_text(dir / "program" / "summary.json"));
  EXPECT_EQ(a["contacts"], b["contacts"]);
  EXPECT_EQ(a["contacts"], 3 * 3 * 2 * 6 * 4);
  // The program's nominals are written to 1 nm: the contacts agree far below a nanometre in
  // δRcomp; every statistic of every group to 1e-9 µm.
  ASSERT_TRUE(a.contains("delta_rcomp_um"));
  for (const auto& [group, stats] : a["delta_rcomp_um"].items()) {
    for (const auto& [name, value] : stats.items()) {
      if (!value.is_number()) continue;
      EXPECT_NEAR(value.get<double>(), b["delta_rcomp_um"][group][name].get<double>(), 1e-9)
          << group << "." << name;
    }
  }
  // The gear parameters: the program's traces are the grid's section nearest mid face and
  // column nearest mid profile (every section and column has as many points: the ties decide).
  ASSERT_TRUE(a.contains("parameters"));
  int compared = 0;
  for (const auto& [symbol, sides] : a["parameters"].items()) {
    for (const auto& [side, values] : sides.items()) {
      if (!values.contains("measured")) continue;
      for (const char* which : {"measured", "true"}) {
        for (const char* stat : {"mean", "std", "max"}) {
          if (!values[which][stat].is_number()) continue;
          // The program's nominals are rounded to 1 nm: a trace point sits up to ~2 nm along the
          // flank from the grid's, its deviation differs by the slope (µm/mm) times that.
          EXPECT_NEAR(values[which][stat].get<double>(),
                      b["parameters"][symbol][side][which][stat].get<double>(), 1e-5)
              << symbol << "." << side << "." << which << "." << stat;
          ++compared;
        }
      }
    }
  }
  EXPECT_GE(compared, 6 * 2 * 2 * 3);  // six profile and helix parameters, both sides
  EXPECT_EQ(b["parameter_evaluation"]["profile_trace"],
            "per flank the program's transverse section with the most points in the profile "
            "range (ties: nearest mid face)");
}

TEST(PlanProgram, AProgramsOwnTracesAreEvaluated) {
  const fs::path dir = testing_support::fresh_temp_path("plan_program_traces");
  fs::create_directories(dir);
  const PolarInvolute g;
  // Per flank R of teeth 3 and 7: a profile trace of 15 points at z = 30 mm (radii 67.0 … 77.6
  // mm, inside the form and tip circles) and a helix trace of 12 points at r = 72 mm (z 1 …
  // 77 mm), in program order profile then helix; plus one stray point (z 50, r 70) that belongs
  // to neither trace.
  std::ostringstream program;
  program << "DMISMN/'profile and helix traces',05.3\nUNITS/MM,ANGDEC\n";
  int label = 0;
  const auto point = [&](int tooth, double r, double z) {
    const Eigen::Vector2d P = g.point(tooth, r), n = g.normal(tooth, r);
    const std::string name = "P" + std::to_string(label++);
    program << "F(" << name << ")=FEAT/POINT,CART," << fixed(P.x(), 7) << "," << fixed(P.y(), 7)
            << "," << fixed(z, 7) << "," << fixed(n.x(), 9) << "," << fixed(n.y(), 9) << ",0\n"
            << "MEAS/POINT,F(" << name << "),1\nPTMEAS/CART," << fixed(P.x(), 7) << ","
            << fixed(P.y(), 7) << "," << fixed(z, 7) << "," << fixed(n.x(), 9) << ","
            << fixed(n.y(), 9) << ",0\nENDMES\n";
  };
  for (const int tooth : {3, 7}) {
    for (int i = 0; i < 15; ++i) point(tooth, 67.0 + 10.6 * i / 14.0, 30.0);
    for (int j = 0; j < 12; ++j) point(tooth, 72.0, 1.0 + 76.0 * j / 11.0);
    point(tooth, 70.0, 50.0);
  }
  program << "ENDFIL\n";
  write_text(dir / "traces.dmi", program.str());
  // A deterministic deviation, linear in L and z (µm; L, z in mm), no machine effects.
  const double kL = 0.4, kz = -0.05;
  write_text(dir / "gear.yaml",
             "name: program_traces\n"
             "gear: {teeth: 24, module_mm: 5.6, pressure_angle_deg: 20, profile_shift: 0.90116, "
             "face_width_mm: 78.89, basic_rack: {addendum: 1.0, dedendum: 1.25, root_radius: "
             "0.38}}\n"
             "tolerances: {standard: iso_1328_1_2013, grade: 6}\n"
             "deviations: {random: false, normal_um: \"0.4 * L - 0.05 * z\"}\n"
             "evaluation: {parameters: [F_alpha, f_Halpha, f_falpha, F_beta, f_Hbeta, f_fbeta], "
             "profile_end_fraction: 1, helix_end_exclusion_mm: 0}\n"
             "run: {gears: 2}\n");
  const auto r = run_gearmc("run " + (dir / "gear.yaml").string() + " --plan " +
                            (dir / "traces.dmi").string() + " --out " + (dir / "out").string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto s = nlohmann::json::parse(read_text(dir / "out" / "summary.json"));
  // The evaluation ranges: L from the form to the tip circle, z over the whole face.
  const double rb = g.rb();
  const auto roll = [&](double d) { return std::sqrt(0.25 * d * d - rb * rb); };
  const auto& how = s["parameter_evaluation"];
  EXPECT_NEAR(how["profile_range_mm"][0].get<double>(), roll(133.328), 2e-3);
  EXPECT_NEAR(how["profile_range_mm"][1].get<double>(), roll(155.693), 2e-3);
  EXPECT_NEAR(how["helix_range_mm"][1].get<double>(), 78.89, 1e-12);
  const double L_alpha =
      how["profile_range_mm"][1].get<double>() - how["profile_range_mm"][0].get<double>();
  const double L_beta = 78.89;
  // The total deviation is the spread of the trace's own points: k_L over their roll lengths
  // (r 67.0 … 77.6 mm, L = sqrt(r² − r_b²)) and k_z over their z (1 … 77 mm).
  const double L_span = roll(2 * 77.6) - roll(2 * 67.0), z_span = 76.0;
  const auto& p = s["parameters"];
  const auto stat = [&](const char* symbol, const char* which) {
    const auto& v = p[symbol]["right"];
    EXPECT_EQ(v["items"], 4) << symbol;  // two flanks, two gears
    EXPECT_EQ(v["not_evaluated"], 0) << symbol;
    return v[which]["mean"].get<double>();
  };
  // A straight deviation's rise over the range (the slope deviation), its total and no form;
  // the probing error of a 0.5 mm ball on slopes of 0.4 µm/mm is far below 1 nm. The measured
  // total spans the trace's own points, the true one (the real surface's dense trace) the range.
  for (const char* which : {"measured", "true"}) {
    const bool measured = std::string(which) == "measured";
    EXPECT_NEAR(stat("f_Halpha", which), kL * L_alpha, 2e-3) << which;
    EXPECT_NEAR(stat("F_alpha", which), std::abs(kL) * (measured ? L_span : L_alpha), 2e-3)
        << which;
    EXPECT_NEAR(stat("f_falpha", which), 0.0, 2e-3) << which;
    EXPECT_NEAR(stat("f_Hbeta", which), kz * L_beta, 2e-3) << which;
    EXPECT_NEAR(stat("F_beta", which), std::abs(kz) * (measured ? z_span : L_beta), 2e-3) << which;
    EXPECT_NEAR(stat("f_fbeta", which), 0.0, 2e-3) << which;
  }
}

TEST(PlanProgram, PointsOffTheGearAreRefusedAtTheirStatement) {
  const fs::path dir = testing_support::fresh_temp_path("plan_program_bad");
  fs::create_directories(dir);
  const PolarInvolute g;
  const Eigen::Vector2d P = g.point(1, 72.0), n = g.normal(1, 72.0);
  const auto statement = [&](const Eigen::Vector2d& at, const Eigen::Vector2d& v) {
    return "F(P1)=FEAT/POINT,CART," + fixed(at.x(), 6) + "," + fixed(at.y(), 6) + ",20," +
           fixed(v.x(), 9) + "," + fixed(v.y(), 9) + ",0\n";
  };
  const double turn = 5.0 * std::numbers::pi / 180.0;
  const Eigen::Vector2d tilted(std::cos(turn) * n.x() - std::sin(turn) * n.y(),
                               std::sin(turn) * n.x() + std::cos(turn) * n.y());
  struct Case {
    std::string text, expected;
  };
  const Case cases[] = {
      {statement(P + 0.05 * n, n), "off.dmi:2:23: FEAT/POINT of P1: got"},
      {statement(P, tilted), "tilted.dmi:2:23: FEAT/POINT of P1: got"},
  };
  const char* names[] = {"off.dmi", "tilted.dmi"};
  const char* why[] = {"50 µm off (nearest: tooth 1 R)", "5° off"};
  for (int k = 0; k < 2; ++k) {
    write_text(dir / names[k], "UNITS/MM,ANGDEC\n" + cases[k].text);
    const auto r = run_gearmc("run --plan " + (dir / names[k]).string() + " --out " +
                              (dir / ("out" + std::to_string(k))).string());
    EXPECT_EQ(r.exit_code, 2) << r.err;
    EXPECT_NE(r.err.find(cases[k].expected), std::string::npos) << r.err;
    EXPECT_NE(r.err.find(why[k]), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(dir / ("out" + std::to_string(k))));
  }
  // With dedicated evaluation scans the plan is refused (the program does not run them).
  write_text(dir / "good.dmi", "UNITS/MM,ANGDEC\n" + statement(P, n));
  write_text(dir / "eval.yaml",
             read_text(fs::path(GEARMC_SOURCE_DIR) / "scenarios" / "p1_reference.yaml") +
                 "evaluation: {parameters: [f_Halpha], profile_points: 30}\n");
  const auto e = run_gearmc("run " + (dir / "eval.yaml").string() + " --plan " +
                            (dir / "good.dmi").string() + " --out " + (dir / "eval").string());
  EXPECT_EQ(e.exit_code, 2);
  // At the key (on the appended last line): file:line:column, the key, its value, what was
  // expected.
  const std::string eval_text = read_text(dir / "eval.yaml");
  const auto last_line = std::count(eval_text.begin(), eval_text.end(), '\n');
  EXPECT_NE(e.err.find("eval.yaml:" + std::to_string(last_line) + ":"), std::string::npos) << e.err;
  EXPECT_NE(e.err.find("evaluation.profile_points: got '30', expected 0 with --plan"),
            std::string::npos)
      << e.err;
  EXPECT_NE(e.err.find("drop it to evaluate the program's own profile and helix traces"),
            std::string::npos)
      << e.err;
  EXPECT_FALSE(fs::exists(dir / "eval"));
  // So are several traces per flank (a program gives one of each kind per flank).
  write_text(dir / "sections.yaml",
             read_text(fs::path(GEARMC_SOURCE_DIR) / "scenarios" / "p1_reference.yaml") +
                 "evaluation: {parameters: [f_Halpha], profile_sections: 2}\n");
  const auto sec =
      run_gearmc("run " + (dir / "sections.yaml").string() + " --plan " +
                 (dir / "good.dmi").string() + " --out " + (dir / "sections").string());
  EXPECT_EQ(sec.exit_code, 2);
  EXPECT_NE(sec.err.find("sections.yaml:" + std::to_string(last_line) + ":"), std::string::npos)
      << sec.err;
  EXPECT_NE(sec.err.find("evaluation.profile_sections: got '2', expected 1 with --plan"),
            std::string::npos)
      << sec.err;
  EXPECT_FALSE(fs::exists(dir / "sections"));
  // The good point alone runs.
  const auto ok = run_gearmc("run --gears 2 --plan " + (dir / "good.dmi").string() + " --out " +
                             (dir / "ok").string());
  EXPECT_EQ(ok.exit_code, 0) << ok.err;
}

}  // namespace
}  // namespace gearmc
