// Tests of reading a generic CMM point table (engine/readings/point_table): a hand-written
// German-style table (`;` between fields, decimal comma, µm, columns in another order and with
// other names) gives the readings computed by hand; the table a CMM would export for simulated
// readings reads back as the same readings as the gearmc CSV, and `gearmc diagnose --columns`
// on it names the hidden effect as on the CSV; bad tables and mappings are refused with one
// message at file:line:column.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "core/input_error.h"
#include "engine/readings/point_table.h"
#include "engine/run/simulate.h"
#include "engine/scenario/scenario.h"
#include "tests/support/run_gearmc.h"
#include "tests/support/temp_paths.h"

using ::gearmc::testing_support::fresh_temp_path;

namespace gearmc {
namespace {

namespace fs = std::filesystem;
using testing_support::run_gearmc;

// The mapping of the German-style tables below.
const std::string kGermanMapping =
    "# columns of the gear program's export\n"
    "columns:\n"
    "  tooth: Zahn\n"
    "  flank: Flanke\n"
    "  i: I\n"
    "  j: J\n"
    "  order: Nr\n"
    "  nominal: {x: X_soll, y: Y_soll, z: Z_soll}\n"
    "  normal: {i: NX, j: NY, k: NZ}\n"
    "  measured: {x: X_ist, y: Y_ist, z: Z_ist}\n"
    "unit: um\n"
    "decimal: \",\"\n";

void expect_near(const Eigen::Vector3d& a, const Eigen::Vector3d& b, double tol) {
  EXPECT_LT((a - b).norm(), tol) << a.transpose() << " vs " << b.transpose();
}

TEST(PointTable, GermanStyleTableGivesTheHandComputedReadings) {
  // Stylus radius R = 0.5 mm. Lengths in µm, so mm = µm / 1000; E is the compensated point
  // (X_ist…), c = E + R n; the reading e = ((c − p)·n − R)·1000 µm = (E − p)·n in µm.
  //  line 4: p = (30, 4, 5) mm, n = (1, 0, 0), E = (30.0015, 4, 5) mm
  //          → c = (30.5015, 4, 5) mm, e = +1.5 µm; order 5, tooth 1, L, i 2, j 0.
  //  line 5: p = (−12.5005, 20, −3.00025) mm, n = (0.6, 0.8, 0) (|n| = 1),
  //          E = p − 2 µm·n = (−12.5017, 19.9984, −3.00025) mm
  //          → c = E + 0.5 n = (−12.2017, 20.3984, −3.00025) mm, e = −2 µm; order 3, R flank.
  //  line 7: n = (0, 0, 1.0004): |n| − 1 = 4e-4 < 1e-3, normalised to (0, 0, 1);
  //          p = (0, 0, 10) mm, E = (0, 0, 10.0008) mm → c = (0, 0, 10.5008) mm, e = 0.8 µm.
  const std::string table =
      "\xEF\xBB\xBF# Messprotokoll Zahnrad, Export\r\n"  // with a UTF-8 byte order mark
      "Nr;Flanke;Zahn;J;I;X_soll;Y_soll;Z_soll;X_ist;Y_ist;Z_ist;NX;NY;NZ;Kommentar\r\n"
      "\r\n"
      "5;L;1;0;2;30000,0;4000,0;5000,0;30001,5;4000,0;5000,0;1;0;0;ok\r\n"
      "3;r;2;1;0;-12500,5;20000;-3000,25;-12501,7;19998,4;-3000,25;0,6;0,8;0;\"ok\"\r\n"
      "# Kommentarzeile\r\n"
      "4; Left ;2;2;1;0;0;10000;0;0;+10000,8;0;0;1,0004;\r\n";
  const Readings r = parse_point_table(
      table, "table.csv", parse_point_table_columns(kGermanMapping, "columns.yaml"), 0.5);
  ASSERT_EQ(r.rows.size(), 3u);
  EXPECT_EQ(r.stylus_radius_mm, 0.5);
  const ReadingRow &a = r.rows[0], &b = r.rows[1], &c = r.rows[2];
  EXPECT_EQ(std::tie(a.gear, a.tooth, a.side, a.i, a.j, a.order, a.line),
            std::make_tuple(0, 1, FlankSide::kLeft, 2, 0, 5, 4));
  EXPECT_EQ(std::tie(b.gear, b.tooth, b.side, b.i, b.j, b.order, b.line),
            std::make_tuple(0, 2, FlankSide::kRight, 0, 1, 3, 5));
  EXPECT_EQ(std::tie(c.gear, c.tooth, c.side, c.i, c.j, c.order, c.line),
            std::make_tuple(0, 2, FlankSide::kLeft, 1, 2, 4, 7));
  expect_near(a.p, {30, 4, 5}, 1e-12);
  expect_near(a.n, {1, 0, 0}, 1e-15);
  expect_near(a.c, {30.5015, 4, 5}, 1e-12);
  expect_near(b.p, {-12.5005, 20, -3.00025}, 1e-12);
  expect_near(b.n, {0.6, 0.8, 0}, 1e-15);
  expect_near(b.c, {-12.2017, 20.3984, -3.00025}, 1e-12);
  expect_near(c.n, {0, 0, 1}, 1e-15);
  expect_near(c.c, {0, 0, 10.5008}, 1e-12);
  EXPECT_NEAR(measured_deviation_um(a, 0.5), 1.5, 1e-9);
  EXPECT_NEAR(measured_deviation_um(b, 0.5), -2.0, 1e-9);
  EXPECT_NEAR(measured_deviation_um(c, 0.5), 0.8, 1e-9);
}

TEST(PointTable, DeviationColumnInInchTableWithTabs) {
  // Inch lengths (1 in = 25.4 mm), tab separator (detected), deviation along n in µm, no order
  // column (order = row position), a gear column. p = (1, 2, 0.5) in = (25.4, 50.8, 12.7) mm,
  // n = (0, 0, 1), dev = 3 µm → c = p + (0.5 + 0.003) n = (25.4, 50.8, 13.203) mm, e = 3 µm.
  const std::string mapping =
      "columns:\n  gear: Gear\n  tooth: Tooth\n  flank: Side\n  i: Row\n  j: Col\n"
      "  nominal: {x: X, y: Y, z: Z}\n  normal: {i: I, j: J, k: K}\n  deviation_um: Dev\n"
      "unit: in\n";
  const std::string table =
      "Gear\tTooth\tSide\tRow\tCol\tX\tY\tZ\tI\tJ\tK\tDev\n"
      "2\t7\tRIGHT\t3\t4\t1\t2\t0.5\t0\t0\t1\t3.0\n"
      "2\t7\tl\t3\t5\t1\t2\t0.5\t0\t0\t1\t-1e-1\n";
  const Readings r =
      parse_point_table(table, "t.txt", parse_point_table_columns(mapping, "m.yaml"), 0.5);
  ASSERT_EQ(r.rows.size(), 2u);
  EXPECT_EQ(std::tie(r.rows[0].gear, r.rows[0].tooth, r.rows[0].side, r.rows[0].i, r.rows[0].j,
                     r.rows[0].order),
            std::make_tuple(2, 7, FlankSide::kRight, 3, 4, 0));
  EXPECT_EQ(r.rows[1].order, 1);
  EXPECT_EQ(r.rows[1].side, FlankSide::kLeft);
  expect_near(r.rows[0].p, {25.4, 50.8, 12.7}, 1e-12);
  expect_near(r.rows[0].c, {25.4, 50.8, 13.203}, 1e-12);
  EXPECT_NEAR(measured_deviation_um(r.rows[0], 0.5), 3.0, 1e-9);
  // `inch` is `in`, `µm` is `um` (the spellings of real exports and users).
  std::string inch = mapping;
  inch.replace(inch.find("unit: in"), 8, "unit: inch");
  const Readings r_inch =
      parse_point_table(table, "t.txt", parse_point_table_columns(inch, "m.yaml"), 0.5);
  expect_near(r_inch.rows[0].c, {25.4, 50.8, 13.203}, 1e-12);
  std::string micro = mapping;
  micro.replace(micro.find("unit: in"), 8, "unit: µm");
  const Readings r_um =
      parse_point_table(table, "t.txt", parse_point_table_columns(micro, "m.yaml"), 0.5);
  expect_near(r_um.rows[0].p, {1e-3, 2e-3, 0.5e-3}, 1e-15);  // 1, 2, 0.5 µm
  EXPECT_NEAR(measured_deviation_um(r.rows[1], 0.5), -0.1, 1e-9);
  // The separator named in the mapping (as the word or a YAML tab escape) reads the same; ';'
  // finds no such row (one field per line).
  for (const std::string sep : {"tab", "\"\\t\""}) {
    const Readings named = parse_point_table(
        table, "t.txt", parse_point_table_columns(mapping + "separator: " + sep + "\n", "m.yaml"),
        0.5);
    ASSERT_EQ(named.rows.size(), 2u) << sep;
    EXPECT_EQ(named.rows[0].c, r.rows[0].c) << sep;
  }
  try {
    parse_point_table(table, "t.txt",
                      parse_point_table_columns(mapping + "separator: \";\"\n", "m.yaml"), 0.5);
    ADD_FAILURE() << "a tab table read with separator ';'";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(
                  "m.yaml:2:9: columns.gear: got 'Gear', expected a column "
                  "of the header line of t.txt (line 1, separator ;, which makes it one "
                  "column: is the separator right?)"),
              std::string::npos)
        << e.what();
  }
}

TEST(PointTable, TheExampleOfTheFormatsPageReadsAsItSays) {
  // docs/formats.md's example mapping and table (the first two code blocks of the section): two
  // readings, e = (E − p)·n = 1.5 µm and −0.5 µm as the page says (by hand: E − p = (0.9, −1.2,
  // 0) µm along n = (0.6, −0.8, 0) gives 0.54 + 0.96 = 1.5; (−0.3, −0.4, 0) µm along (0.6, 0.8, 0)
  // gives −0.18 − 0.32 = −0.5).
  std::ifstream in(fs::path(GEARMC_SOURCE_DIR) / "docs" / "formats.md");
  std::stringstream page;
  page << in.rdbuf();
  const std::string md = page.str();
  const std::size_t section = md.find("## CMM point table and its column mapping");
  ASSERT_NE(section, std::string::npos);
  const auto block = [&](std::size_t from, std::size_t* end) {
    const std::size_t open = md.find("```", from);
    const std::size_t body = md.find('\n', open) + 1;
    *end = md.find("```", body);
    return md.substr(body, *end - body);
  };
  std::size_t end = 0;
  const std::string mapping = block(section, &end);
  const std::string table = block(end + 3, &end);
  const Readings r = parse_point_table(table, "table.csv",
                                       parse_point_table_columns(mapping, "mapping.yaml"), 0.5);
  ASSERT_EQ(r.rows.size(), 2u);
  EXPECT_EQ(r.rows[0].side, FlankSide::kLeft);
  EXPECT_EQ(r.rows[1].side, FlankSide::kRight);
  EXPECT_NEAR(measured_deviation_um(r.rows[0], 0.5), 1.5, 1e-6);
  EXPECT_NEAR(measured_deviation_um(r.rows[1], 0.5), -0.5, 1e-6);
}

// A number as a German export writes it: 17 significant digits, decimal comma.
std::string german(double v) {
  std::ostringstream s;
  s.precision(17);
  s << v;
  std::string t = s.str();
  std::replace(t.begin(), t.end(), '.', ',');
  return t;
}

// The table a CMM exports for `readings` (µm, `;`, decimal comma, columns in another order than
// the CSV's): compensated points E = c − R n, or the deviation e along n when `deviation`.
std::string german_table_of(const Readings& readings, bool deviation) {
  std::string out = "# Export\nMesspunkt;Zahn;Flanke;Rad;" +
                    std::string(deviation ? "Abw" : "Z_ist;Y_ist;X_ist") +
                    ";NK;NJ;NI;Z_soll;Y_soll;X_soll;Profil;Linie;Kommentar\n";
  const double R = readings.stylus_radius_mm;
  for (const ReadingRow& row : readings.rows) {
    const Eigen::Vector3d e = (row.c - R * row.n) * 1000.0, p = row.p * 1000.0;
    out += std::to_string(row.order) + ";" + std::to_string(row.tooth) + ";" +
           (row.side == FlankSide::kRight ? "Right" : "Left") + ";" + std::to_string(row.gear) +
           ";";
    out += deviation ? german(measured_deviation_um(row, R))
                     : german(e.z()) + ";" + german(e.y()) + ";" + german(e.x());
    out += ";" + german(row.n.z()) + ";" + german(row.n.y()) + ";" + german(row.n.x()) + ";" +
           german(p.z()) + ";" + german(p.y()) + ";" + german(p.x()) + ";" + std::to_string(row.i) +
           ";" + std::to_string(row.j) + ";-\n";
  }
  return out;
}

const std::string kRoundTripMapping =
    "columns:\n  gear: Rad\n  tooth: Zahn\n  flank: Flanke\n  i: Profil\n  j: Linie\n"
    "  order: Messpunkt\n  nominal: {x: X_soll, y: Y_soll, z: Z_soll}\n"
    "  normal: {i: NI, j: NJ, k: NK}\n  measured: {x: X_ist, y: Y_ist, z: Z_ist}\n"
    "unit: um\ndecimal: \",\"\nseparator: \";\"\n";

TEST(PointTable, TableOfSimulatedReadingsReadsBackAsTheCsvAndDiagnosesAlike) {
  // Readings of the diagnose example's truth (lobing 0.75 µm, noise 0.3 µm, nominal master).
  const std::string scenarios = std::string(GEARMC_SOURCE_DIR) + "/scenarios/diagnose/";
  SimulateOptions o;
  o.master = true;
  const Readings truth =
      simulate_readings(load_scenario_file(scenarios + "lobing_truth.yaml"), o).readings;
  const Readings csv = parse_readings(format_readings(truth), "truth.csv");
  const std::string text = german_table_of(truth, false);
  const Readings back = parse_point_table(
      text, "table.csv", parse_point_table_columns(kRoundTripMapping, "columns.yaml"),
      truth.stylus_radius_mm);
  ASSERT_EQ(back.rows.size(), csv.rows.size());
  for (std::size_t k = 0; k < csv.rows.size(); ++k) {
    const ReadingRow &a = csv.rows[k], &b = back.rows[k];
    EXPECT_EQ(std::tie(a.gear, a.tooth, a.side, a.i, a.j, a.order),
              std::tie(b.gear, b.tooth, b.side, b.i, b.j, b.order));
    // 17 digits in µm: the values agree to far better than 1e-9 mm.
    EXPECT_LT((a.p - b.p).norm(), 1e-9);
    EXPECT_LT((a.n - b.n).norm(), 1e-9);
    EXPECT_LT((a.c - b.c).norm(), 1e-9);
  }
  // The same table with the deviation along n instead of the point: the same readings e.
  std::string dev_mapping = kRoundTripMapping;
  const std::string measured = "  measured: {x: X_ist, y: Y_ist, z: Z_ist}";
  dev_mapping.replace(dev_mapping.find(measured), measured.size(), "  deviation_um: Abw");
  const Readings dev =
      parse_point_table(german_table_of(truth, true), "dev.csv",
                        parse_point_table_columns(dev_mapping, "dev.yaml"), truth.stylus_radius_mm);
  ASSERT_EQ(dev.rows.size(), csv.rows.size());
  for (std::size_t k = 0; k < csv.rows.size(); ++k) {
    EXPECT_NEAR(measured_deviation_um(dev.rows[k], dev.stylus_radius_mm),
                measured_deviation_um(csv.rows[k], csv.stylus_radius_mm), 1e-6);
  }

  // `gearmc diagnose --columns` on the table names the hidden lobing (README example).
  const fs::path dir = fresh_temp_path("point_table");
  fs::remove_all(dir);
  fs::create_directories(dir);
  std::ofstream(dir / "table.csv", std::ios::binary) << text;
  std::ofstream(dir / "columns.yaml", std::ios::binary) << kRoundTripMapping;
  const auto r = run_gearmc("diagnose --model " + scenarios + "lobing_model.yaml --measured " +
                            (dir / "table.csv").string() + " --columns " +
                            (dir / "columns.yaml").string() + " --out " + (dir / "out").string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = nlohmann::json::parse(std::ifstream(dir / "out" / "diagnosis.json"));
  EXPECT_EQ(j["named_effect"], "probe_lobing");

  // A bad mapping through the command line: exit 2, one located message, nothing written.
  std::ofstream(dir / "bad.yaml", std::ios::binary)
      << std::string(kRoundTripMapping).replace(kRoundTripMapping.find("Zahn"), 4, "Zahnn");
  const auto bad = run_gearmc("diagnose --model " + scenarios + "lobing_model.yaml --measured " +
                              (dir / "table.csv").string() + " --columns " +
                              (dir / "bad.yaml").string() + " --out " + (dir / "bad").string());
  EXPECT_EQ(bad.exit_code, 2);
  // "  tooth: Zahnn" is line 3 of the mapping; the name starts in column 10.
  EXPECT_NE(bad.err.find((dir / "bad.yaml").string() +
                         ":3:10: columns.tooth: got 'Zahnn', expected a column of the header "
                         "line of " +
                         (dir / "table.csv").string() +
                         " (line 2, separator ;); did you mean "
                         "'Zahn'?"),
            std::string::npos)
      << bad.err;
  EXPECT_FALSE(fs::exists(dir / "bad"));
}

TEST(PointTable, BadTablesAreRefusedWithTheirPlace) {
  const PointTableColumns columns = parse_point_table_columns(kGermanMapping, "columns.yaml");
  const std::string header = "Nr;Flanke;Zahn;J;I;X_soll;Y_soll;Z_soll;X_ist;Y_ist;Z_ist;NX;NY;NZ\n";
  struct Case {
    std::string text, expected;
  };
  // Columns of a row "5;L;1;0;2;30000,0;4000,0;5000,0;…": X_soll starts at byte 11, NX at 55,
  // the row ends at 57 when NX,NY,NZ are "1;0;0" without the last field.
  const std::vector<Case> cases = {
      {header + "5;L;1;0;2;30000.0;4000,0;5000,0;30001,5;4000,0;5000,0;1;0;0\n",
       "table.csv:2:11: X_soll: got '30000.0', expected a finite number with decimal comma (µm)"},
      {header + "5;L;1;0;2;abc;4000,0;5000,0;30001,5;4000,0;5000,0;1;0;0\n",
       "table.csv:2:11: X_soll: got 'abc', expected a finite number"},
      {header + "5;L;1;0;2;30000,0;4000,0;5000,0;30001,5;4000,0;5000,0;0,6;0,6;0\n",
       "table.csv:2:55: NX,NY,NZ: got '0,6;0,6;0', expected a unit normal (|n| = 1 within 1e-3"},
      {header + "5;L;1;0;2;30000,0;4000,0;5000,0;30001,5;4000,0;5000,0;1;0\n",
       "table.csv:2:58: row has 13 fields, expected 14 (as the header line, separator ;)"},
      {header + "5;L;1;0;2;30000,0;4000,0;5000,0;30001,5;4000,0;5000,0;1;0;0;7\n",
       "table.csv:2:60: row has 15 fields, expected 14"},
      {header + "5;X;1;0;2;30000,0;4000,0;5000,0;30001,5;4000,0;5000,0;1;0;0\n",
       "table.csv:2:3: Flanke: got 'X', expected L or R"},
      {header + "5;L;0;0;2;30000,0;4000,0;5000,0;30001,5;4000,0;5000,0;1;0;0\n",
       "table.csv:2:5: Zahn: got '0', expected an integer >= 1"},
      {header + "5;L;1;0;2;30000,0;4000,0;5000,0;30001,5;4000,0;5000,0;1;0;0\n" +
           "5;L;1;0;3;30000,0;4000,0;5000,0;30001,5;4000,0;5000,0;1;0;0\n",
       "table.csv:3:1: Nr: got '5', expected an order not used by an earlier row"},
      {"# nur Kopf\n" + header + "\n",
       "table.csv: the point table has no rows after its header "
       "line (line 2)"},
      {"# leer\n\n", "table.csv: no header line"},
      {"Nr,Flanke,Zahn\n1,L,1\n",
       "table.csv:1:1: header line: got 'Nr,Flanke,Zahn', expected "
       "column names separated by ';', tab (with decimal ',' not by "
       "',')"},
  };
  for (const Case& c : cases) {
    try {
      parse_point_table(c.text, "table.csv", columns, 0.5);
      ADD_FAILURE() << "accepted: " << c.text;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(c.expected), std::string::npos)
          << e.what() << "\nexpected: " << c.expected;
    }
  }
}

TEST(PointTable, BadMappingsAreRefusedWithTheirPlace) {
  const std::string table =
      "Nr;Flanke;Zahn;J;I;X_soll;Y_soll;Z_soll;X_ist;Y_ist;Z_ist;NX;NY;NZ\n"
      "5;L;1;0;2;30000,0;4000,0;5000,0;30001,5;4000,0;5000,0;1;0;0\n";
  const auto with = [](const std::string& from, const std::string& to) {
    std::string m = kGermanMapping;
    m.replace(m.find(from), from.size(), to);
    return m;
  };
  struct Case {
    std::string mapping, expected;
  };
  const std::vector<Case> cases = {
      // "  nominal: {x: X_soll, y: Y_Soll, …": line 8, Y_Soll starts at column 27;
      // "  normal: {i: NX, j: NY, k: NY}": the second NY at column 29.
      {with("Y_soll", "Y_Soll"),
       "columns.yaml:8:27: columns.nominal.y: got 'Y_Soll', expected a column of the header line "
       "of table.csv (line 1, separator ;); did you mean 'Y_soll'?"},
      {with("k: NZ", "k: NY"),
       "columns.yaml:9:29: columns.normal.k: got 'NY', expected a column not mapped already "
       "(columns.normal.j names it)"},
      {with("decimal: \",\"", "decimal: \",\"\nseparator: \",\""),
       "columns.yaml:13:12: separator: got ',', expected ';' or tab: with decimal ','"},
      {with("unit: um", "unit: micron"), "columns.yaml:11:7: unit: got 'micron', expected one of"},
      {with("  measured: {x: X_ist, y: Y_ist, z: Z_ist}\n", ""),
       "columns.yaml:2:1: columns.measured: expected measured: {x, y, z} (the compensated points) "
       "or deviation_um"},
      {with("  order: Nr\n", "  order: Nr\n  deviation_um: Abw\n"),
       "columns.yaml:8:17: columns.deviation_um: got 'Abw', expected either measured"},
      {with("  flank: Flanke\n", "  flanke: Flanke\n"),
       "columns.yaml:4:3: columns.flanke: got 'flanke'"},
  };
  for (const Case& c : cases) {
    try {
      parse_point_table(table, "table.csv", parse_point_table_columns(c.mapping, "columns.yaml"),
                        0.5);
      ADD_FAILURE() << "accepted: " << c.mapping;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(c.expected), std::string::npos)
          << e.what() << "\nexpected: " << c.expected;
    }
  }
}

}  // namespace
}  // namespace gearmc
