// Tests of the DMIS round trip (engine/plan/dmis_plan, engine/readings/dmis_results): the
// program `gearmc export-plan` writes holds every planned point in probing order with its nominal
// point, outward normal and approach vector; the results a CMM would write for it (made here
// from simulated readings: FA = the compensated point E = c − R n) read back into the same
// readings, and `gearmc diagnose` on them names the hidden effect as it does on the CSV; bad
// DMIS results are refused with file:line:column.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <regex>
#include <sstream>

#include "core/input_error.h"
#include "engine/effects/effect_config.h"
#include "engine/plan/dmis_plan.h"
#include "engine/readings/dmis_results.h"
#include "engine/run/simulate.h"
#include "tests/support/run_gearmc.h"
#include "tests/support/temp_paths.h"
#include "tests/support/text_files.h"

using ::gearmc::testing_support::fresh_temp_path;

namespace gearmc {
namespace {

using testing_support::read_text;
using testing_support::write_text;

namespace fs = std::filesystem;
using testing_support::run_gearmc;

std::string full(const Eigen::Vector3d& v) {
  std::ostringstream s;
  s.precision(17);
  s << v.x() << "," << v.y() << "," << v.z();
  return s.str();
}

// What a CMM writes after running the plan: nominal and actual feature per measured reading.
std::string dmis_results_of(const Readings& readings) {
  std::string out = "DMISMN/'results',05.3\nUNITS/MM,ANGDEC\n";
  const double R = readings.stylus_radius_mm;
  for (const ReadingRow& row : readings.rows) {
    const std::string label = dmis_point_label(row.tooth, row.side, row.i, row.j);
    out += "F(" + label + ")=FEAT/POINT,CART," + full(row.p) + "," + full(row.n) + "\n";
    out += "$$ measured\nFA(" + label + ")=FEAT/POINT,CART,$\n  " + full(row.c - R * row.n) + "," +
           full(row.n) + "\n";
  }
  return out + "ENDFIL\n";
}

TEST(DmisPlan, ExportPlanWritesEveryPlannedPointInProbingOrder) {
  const fs::path dir = fresh_temp_path("dmis_plan");
  fs::remove_all(dir);
  fs::create_directories(dir);
  const std::string file = (dir / "plan.dmi").string();
  const auto r = run_gearmc("export-plan --format dmis --out " + file);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string text = read_text(file);
  const Scenario s = reference_scenario();
  const std::vector<PlannedPoint> plan = probing_sequence(InvoluteGear(s.gear), s.probing);
  ASSERT_EQ(plan.size(), 2400u);
  static const std::regex feature(R"(^F\((\w+)\)=FEAT/POINT,CART,(.*)$)");
  static const std::regex touch(R"(^PTMEAS/CART,(.*)$)");
  std::istringstream in(text);
  std::size_t k = 0;
  std::string line, last;
  std::vector<double> nominal;
  bool setup = false;
  while (std::getline(in, line)) {
    last = line;
    EXPECT_EQ(line.find(",-0.000"), std::string::npos) << line;
    std::smatch m;
    const auto numbers = [](const std::string& list) {
      std::vector<double> v;
      std::stringstream fields(list);
      for (std::string x; std::getline(fields, x, ',');) v.push_back(std::stod(x));
      return v;
    };
    if (std::regex_match(line, m, feature) && m[1].str().rfind(kDmisSetupPrefix, 0) == 0) {
      setup = true;  // the operator's set-up step (its own test: dmis_program_test.cpp)
    } else if (std::regex_match(line, m, feature)) {
      setup = false;
      ASSERT_LT(k, plan.size());
      const PlannedPoint& q = plan[k];
      EXPECT_EQ(m[1].str(), dmis_point_label(q.tooth, q.side, q.i, q.j));
      nominal = numbers(m[2].str());
      ASSERT_EQ(nominal.size(), 6u);
      // 6 decimals for the point (1 nm), 9 for the normal.
      for (int a = 0; a < 3; ++a) {
        EXPECT_NEAR(nominal[a], q.point[a], 5e-7);
        EXPECT_NEAR(nominal[3 + a], q.normal[a], 5e-10);
      }
    } else if (!setup && std::regex_match(line, m, touch)) {
      // The touch: at the nominal point, approach vector = outward normal (probe travels along
      // −n, as the stylus approaches in gearmc's model).
      EXPECT_EQ(numbers(m[1].str()), nominal);
      ++k;
    }
  }
  EXPECT_EQ(k, plan.size());
  EXPECT_EQ(last, "ENDFIL");
  EXPECT_EQ(text.rfind("DMISMN/'gearmc probing plan of p1_reference',05.3", 0), 0u);

  // Bad input: an unknown format, exit 2, nothing written.
  const auto bad = run_gearmc("export-plan --format iges --out " + (dir / "x.dmi").string());
  EXPECT_EQ(bad.exit_code, 2);
  EXPECT_NE(bad.err.find("--format: got 'iges', expected dmis"), std::string::npos) << bad.err;
  EXPECT_FALSE(fs::exists(dir / "x.dmi"));
}

TEST(DmisResults, ResultsOfThePlanReadBackAsTheSameReadingsAndDiagnoseAlike) {
  // Readings of the diagnose example's truth (lobing 0.75 µm, noise 0.3 µm, nominal master),
  // written as a CMM's DMIS results (with a `$` continuation and a `$$` comment), read back:
  // the same p, n and c (to 1e-9 mm: the numbers are written with 17 digits) and order.
  const std::string scenarios = std::string(GEARMC_SOURCE_DIR) + "/scenarios/diagnose/";
  SimulateOptions o;
  o.master = true;
  const Readings truth =
      simulate_readings(load_scenario_file(scenarios + "lobing_truth.yaml"), o).readings;
  const std::string text = dmis_results_of(truth);
  const Readings back = parse_dmis_results(text, "results.dmo", truth.stylus_radius_mm);
  ASSERT_EQ(back.rows.size(), truth.rows.size());
  for (std::size_t k = 0; k < truth.rows.size(); ++k) {
    const ReadingRow &a = truth.rows[k], &b = back.rows[k];
    EXPECT_EQ(std::tie(a.tooth, a.side, a.i, a.j), std::tie(b.tooth, b.side, b.i, b.j));
    EXPECT_EQ(b.order, static_cast<int>(k));
    EXPECT_LT((a.p - b.p).norm(), 1e-9);
    EXPECT_LT((a.n - b.n).norm(), 1e-9);
    EXPECT_LT((a.c - b.c).norm(), 1e-9);
  }
  // Diagnosing the DMIS file names the hidden lobing, as the CSV does (README example).
  const fs::path dir = fresh_temp_path("dmis_results");
  fs::remove_all(dir);
  fs::create_directories(dir);
  {
    std::ofstream out(dir / "results.dmo", std::ios::binary);
    out << text;
  }
  const auto r = run_gearmc("diagnose --model " + scenarios + "lobing_model.yaml --measured " +
                            (dir / "results.dmo").string() + " --out " + (dir / "out").string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = nlohmann::json::parse(std::ifstream(dir / "out" / "diagnosis.json"));
  EXPECT_EQ(j["named_effect"], "probe_lobing");
}

TEST(DmisResults, TheProgramsOutputStatementsCarryWhatDiagnoseReadsBack) {
  // A CMM running the exported program writes, per OUTPUT statement, the feature it names:
  // OUTPUT/F(label) the nominal F(label)=FEAT/POINT,… as programmed, OUTPUT/FA(label) the
  // actual FA(label)=FEAT/POINT,CART,E,n with E the compensated point. Emulated here with
  // E = p + e n, e = (k mod 7 − 3) µm for the k-th output, plus the set-up step's actuals (a CMM
  // that writes every actual): the results read back as one reading per planned point, in the
  // plan's order, each with its e, and the set-up features skipped.
  const fs::path dir = fresh_temp_path("dmis_outputs");
  fs::remove_all(dir);
  fs::create_directories(dir);
  const auto r = run_gearmc("export-plan --format dmis --out " + (dir / "plan.dmi").string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  std::istringstream in(read_text(dir / "plan.dmi"));
  std::map<std::string, std::string> nominal;  // label -> the values of its FEAT/POINT
  std::string results = "DMISMN/'results',05.3\nUNITS/MM,ANGDEC\n";
  static const std::regex feature(R"(^F\((\w+)\)=FEAT/POINT,CART,(.*)$)");
  static const std::regex output(R"(^OUTPUT/(FA?)\((\w+)\)$)");
  int outputs = 0;
  std::vector<double> expected_um;
  for (std::string line; std::getline(in, line);) {
    std::smatch m;
    if (std::regex_match(line, m, feature)) {
      nominal[m[1].str()] = m[2].str();
    } else if (std::regex_match(line, m, output)) {
      const std::string label = m[2].str();
      ASSERT_TRUE(nominal.count(label)) << line;
      if (m[1].str() == "F") {
        results += "F(" + label + ")=FEAT/POINT,CART," + nominal[label] + "\n";
        continue;
      }
      std::vector<double> v;
      std::stringstream fields(nominal[label]);
      for (std::string x; std::getline(fields, x, ',');) v.push_back(std::stod(x));
      const Eigen::Vector3d p(v[0], v[1], v[2]), n(v[3], v[4], v[5]);
      const double e_um = (outputs++ % 7) - 3.0;
      expected_um.push_back(e_um);
      results +=
          "FA(" + label + ")=FEAT/POINT,CART," + full(p + 1e-3 * e_um * n) + "," + full(n) + "\n";
    } else if (line.rfind("ENDMES", 0) == 0 && nominal.count("SETUP_T1L") &&
               results.find("FA(SETUP_T1L)") == std::string::npos) {
      results += "FA(SETUP_T1L)=FEAT/POINT,CART," + nominal["SETUP_T1L"] + "\n";
    }
  }
  results += "ENDFIL\n";
  EXPECT_NE(results.find("FA(SETUP_T1L)"), std::string::npos);
  const Scenario s = reference_scenario();
  const std::vector<PlannedPoint> plan = probing_sequence(InvoluteGear(s.gear), s.probing);
  const Readings back = parse_dmis_results(results, "results.dmo", s.stylus_radius_mm);
  ASSERT_EQ(back.rows.size(), plan.size());
  for (std::size_t k = 0; k < plan.size(); ++k) {
    EXPECT_EQ(std::tie(back.rows[k].tooth, back.rows[k].side, back.rows[k].i, back.rows[k].j),
              std::tie(plan[k].tooth, plan[k].side, plan[k].i, plan[k].j));
    // 6 decimals for the nominal point (1 nm) and 17 digits for the actual: e to 1e-3 µm.
    EXPECT_NEAR(measured_deviation_um(back.rows[k], s.stylus_radius_mm), expected_um[k], 2e-3);
  }
}

TEST(DmisResults, BadResultsAreRefusedWithTheirPlace) {
  const std::string head = "DMISMN/'r',05.3\n";
  const std::string nominal = "F(T001L_I00_J00)=FEAT/POINT,CART,66.7,-6.2,3.9,0.2472,-0.969,0\n";
  struct Case {
    std::string text, expected;
  };
  const std::vector<Case> cases = {
      {head + "FA(T001L_I00_J00)=FEAT/POINT,CART,66.7,-6.2,3.9,0.2472,-0.969,0\n",
       "results.dmo:2:4: FA(T001L_I00_J00): got 'no nominal'"},
      {head + nominal + "FA(T001L_I00_J00)=FEAT/POINT,CART,66.7,abc,3.9,0.2472,-0.969,0\n",
       "results.dmo:3:40: FEAT/POINT of T001L_I00_J00: got 'abc', expected a finite number"},
      {head + nominal + "FA(T001L_I00_J00)=FEAT/POINT,CART,66.7,-6.2,3.9,0.2472\n",
       "got '4 numbers', expected 6 numbers"},
      {head + "F(P1)=FEAT/POINT,CART,1,2,3,1,0,0\nFA(P1)=FEAT/POINT,CART,1,2,3,1,0,0\n",
       "results.dmo:3:4: FA label: got 'P1', expected a label of gearmc's plan"},
      {head + nominal + "FA(T001L_I00_J00)=FEAT/POINT,CART,66.7,-6.2,3.9,0.2472,-0.969,0\n" +
           "FA(T001L_I00_J00)=FEAT/POINT,CART,66.7,-6.2,3.9,0.2472,-0.969,0\n",
       "results.dmo:4:4: FA(T001L_I00_J00): got 'measured again (first at line 3)'"},
      {head + nominal + "ENDFIL\n", "no measured points"},
      // Labels the plan's form T<1-4 digits><L|R>_I<1-3>_J<1-3> does not allow.
      {head + "F(T12345L_I0_J0)=FEAT/POINT,CART,1,2,3,1,0,0\n" +
           "FA(T12345L_I0_J0)=FEAT/POINT,CART,1,2,3,1,0,0\n",
       "FA label: got 'T12345L_I0_J0'"},
      {head +
           "F(T1X_I0_J0)=FEAT/POINT,CART,1,2,3,1,0,0\nFA(T1X_I0_J0)=FEAT/POINT,CART,1,2,3,1,0,0\n",
       "FA label: got 'T1X_I0_J0'"},
      {head + "F(T1L_I0_J0x)=FEAT/POINT,CART,1,2,3,1,0,0\n" +
           "FA(T1L_I0_J0x)=FEAT/POINT,CART,1,2,3,1,0,0\n",
       "FA label: got 'T1L_I0_J0x'"},
      // A 4 MB label on one statement (std::regex overflowed the stack on such lines): refused
      // by the statement cap at the statement's first line, before anything scans it.
      {head + "F(" + std::string(4'000'000, 'Q') + ")=FEAT/POINT,CART,1,2,3,1,0,0\nFA(" +
           std::string(4'000'000, 'Q') + ") = feat / point , cart ,1,2,3,1,0,0\n",
       "results.dmo:2:1: a DMIS statement of at most 16384 bytes"},
      // The cap counts continuation lines joined: 2000 lines of 10 bytes ending in `$`.
      {head + "F(T1L_I0_J0)=FEAT/POINT,CART,1,2,3,1,0,0" +
           [] {
             std::string s;
             for (int k = 0; k < 2000; ++k) s += "          $\n";
             return s;
           }() +
           "\n",
       "results.dmo:2:1: a DMIS statement of at most 16384 bytes"},
      // A length unit DMIS does not have (ANSI/DMIS 105.2 §6.2: MM, CM, METER, INCH, FEET).
      {head + "UNITS/FURLONG,ANGDEC\n" + nominal, "results.dmo:2:7: UNITS: got 'FURLONG'"},
      // A reading 1 m off its nominal along n (a measured point of another part, or µm read as
      // mm): beyond the readings range of (c − p)·n − R, ±100 000 µm, at the FA's values.
      {head + nominal + "FA(T001L_I00_J00)=FEAT/POINT,CART,1066.7,-6.2,3.9,0.2472,-0.969,0\n",
       "results.dmo:3:35: reading_um: got '(FA - F)·n = "},
      // A coordinate beyond a CMM's volume (100 m), placed at its field.
      {head + "F(T001L_I00_J00)=FEAT/POINT,CART,66.7,1e6,3.9,0.2472,-0.969,0\n",
       "results.dmo:2:39: FEAT/POINT of T001L_I00_J00 y: got '1e6'"},
  };
  for (const Case& c : cases) {
    try {
      parse_dmis_results(c.text, "results.dmo", 0.5);
      ADD_FAILURE() << "accepted: " << c.text;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(c.expected), std::string::npos)
          << e.what() << "\nexpected: " << c.expected;
    }
  }
  // Keywords in any case and blanks between the tokens; labels with leading zeros.
  const Readings r =
      parse_dmis_results(head + "f ( T2R_I1_J003 ) = Feat/Point , Cart, 1,2,3,1,0,0\n" +
                             "Fa(T2R_I1_J003)=FEAT/POINT,CART,1,2,3.002,1,0,0\n",
                         "results.dmo", 0.5);
  ASSERT_EQ(r.rows.size(), 1u);
  EXPECT_EQ(r.rows[0].tooth, 2);
  EXPECT_EQ(r.rows[0].side, FlankSide::kRight);
  EXPECT_EQ(r.rows[0].i, 1);
  EXPECT_EQ(r.rows[0].j, 3);
  // Inch results (UNITS/INCH, the unit of many US programs) in mm: 25.4 mm per inch exactly
  // (the international inch, 1959); the unit holds until the next UNITS statement.
  const Readings inch = parse_dmis_results(
      head + "UNITS/INCH,ANGDEC\nF(T2R_I1_J3)=FEAT/POINT,CART,1,2,3,1,0,0\n" +
          "FA(T2R_I1_J3)=FEAT/POINT,CART,1.0001,2,3,1,0,0\nunits / mm, angdec\n" +
          "F(T2R_I2_J3)=FEAT/POINT,CART,25.4,50.8,76.2,1,0,0\n" +
          "FA(T2R_I2_J3)=FEAT/POINT,CART,25.4,50.8,76.2,1,0,0\n",
      "results.dmo", 0.5);
  ASSERT_EQ(inch.rows.size(), 2u);
  EXPECT_LT((inch.rows[0].p - Eigen::Vector3d(25.4, 50.8, 76.2)).norm(), 1e-12);
  EXPECT_NEAR(measured_deviation_um(inch.rows[0], 0.5), 2.54, 1e-9);  // 0.0001 inch
  EXPECT_LT((inch.rows[1].p - inch.rows[0].p).norm(), 1e-12);
  EXPECT_NEAR(measured_deviation_um(inch.rows[1], 0.5), 0.0, 1e-9);
  // Where each row came from, for the diagnosis's messages: the FA label and values, and the
  // nominal F statement's values.
  EXPECT_EQ(inch.rows[0].line, 4);
  EXPECT_EQ(inch.rows[0].key_column, 4);
  EXPECT_EQ(inch.rows[0].measured_column, 31);
  EXPECT_EQ(inch.rows[0].nominal_line, 3);
  EXPECT_EQ(inch.rows[0].nominal_column, 30);
  EXPECT_TRUE(is_dmis_file("a/b.DMO"));

  // The diagnosis's own checks of DMIS rows name the statement they come from: a tooth the
  // model's gear (24 teeth) lacks at the FA label, a nominal point off the gear at the F values
  // (they were once placed by reading the file as a CSV: wrong line, no column).
  const std::string model =
      std::string(GEARMC_SOURCE_DIR) + "/scenarios/diagnose/lobing_model.yaml";
  const fs::path dir = fresh_temp_path("dmis_places");
  fs::remove_all(dir);
  fs::create_directories(dir);
  const auto diagnose = [&](const std::string& text) {
    std::ofstream(dir / "r.dmo", std::ios::binary) << text;
    return run_gearmc("diagnose --model " + model + " --measured " + (dir / "r.dmo").string() +
                      " --out " + (dir / "out").string());
  };
  const auto tooth =
      diagnose(head + "F(T099L_I00_J00)=FEAT/POINT,CART,66.7,-6.2,3.9,0.2472,-0.969,0\n" +
               "FA(T099L_I00_J00)=FEAT/POINT,CART,66.7,-6.2,3.9,0.2472,-0.969,0\n");
  EXPECT_EQ(tooth.exit_code, 2);
  EXPECT_NE(tooth.err.find("r.dmo:3:4: tooth: got '99'"), std::string::npos) << tooth.err;
  const auto off = diagnose(head + "F(T001L_I00_J00)=FEAT/POINT,CART,500,0,3.9,1,0,0\n" +
                            "FA(T001L_I00_J00)=FEAT/POINT,CART,500,0,3.9,1,0,0\n");
  EXPECT_EQ(off.exit_code, 2);
  EXPECT_NE(off.err.find("r.dmo:2:34: px,py,pz: got '500,0,3.9'"), std::string::npos) << off.err;
  EXPECT_FALSE(fs::exists(dir / "out"));
  fs::remove_all(dir);
  EXPECT_TRUE(is_dmis_file("x.dmi"));
  EXPECT_FALSE(is_dmis_file("x.csv"));
}

}  // namespace
}  // namespace gearmc
