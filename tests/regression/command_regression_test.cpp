// Regression references of `gearmc simulate` and `gearmc diagnose` (as regression_test.cpp has
// for `gearmc run`): change detectors for the measuring pipeline (contact, effects, readings)
// and the diagnosis. Each case runs the gearmc executable with a fixed seed on a small input
// (seconds) and compares a JSON view of its output with the stored reference
// scenarios/…/NAME.{simulate,diagnose}.ref.json (reference_compare.h: counts and strings
// exactly, reals to a relative 1e-9).
//
// The simulate view of a readings CSV (thousands of rows) is kept small and readable:
//  - the key lines of the header and the column names (the "# made by" provenance comment is
//    left out: it holds the date, the command and the build commit);
//  - the number of rows per flank side, and an FNV-1a digest of the integer columns
//    (gear, tooth, flank, i, j, order) of every row, compared exactly;
//  - the measured deviation e = ((c − p)·n − R)·1000 − ref_dev µm of every row summarised
//    (mean, std, min, max) — what a failing diff shows first;
//  - weighted checksums Σ w_k x_k over all rows of p, n (mm), of c − p (µm) and of e (µm), with
//    fixed pseudo-random weights w_k ∈ [1, 2) (so that reordering rows changes them): a change of
//    one value by more than 1e-7 (kReadingsAbsolute) or 1e-9 of the checksum's size moves its
//    checksum beyond the tolerance;
//  - every (rows / 12)-th row in full, to show what a changed row looks like.
// The diagnose view is diagnosis.json without its provenance (date, command, build commit).
//
// Regenerating after an intended change of results: scripts/update-references, and say in the
// commit message why the results changed.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "tests/regression/reference_compare.h"
#include "tests/support/run_gearmc.h"
#include "tests/support/temp_paths.h"
#include "tests/support/text_files.h"

using ::gearmc::testing_support::fresh_temp_path;

namespace gearmc {
namespace {

using testing_support::read_text;
using testing_support::write_text;

namespace fs = std::filesystem;
using nlohmann::ordered_json;
using testing_support::run_gearmc;

std::vector<std::string> split(const std::string& line, char separator) {
  std::vector<std::string> fields;
  std::string field;
  std::istringstream s(line);
  while (std::getline(s, field, separator)) fields.push_back(field);
  if (!line.empty() && line.back() == separator) fields.emplace_back();
  return fields;
}

// 64-bit FNV-1a (Fowler, Noll, Vo).
void fnv1a(std::uint64_t& h, const std::string& text) {
  for (unsigned char c : text) {
    h ^= c;
    h *= 0x100000001b3ULL;
  }
}

// The weight of row k in the checksums: in [1, 2), from Knuth's multiplicative hash of k.
double row_weight(std::size_t k) {
  const std::uint32_t h = static_cast<std::uint32_t>(k) * 2654435761U;
  return 1.0 + static_cast<double>(h) / 4294967296.0;
}

double rounded(double v) {  // 12 significant digits: the view's sample rows stay readable
  std::ostringstream s;
  s.precision(12);
  s << v;
  return std::stod(s.str());
}

// The view of a readings CSV described at the top of this file; failures are test failures.
ordered_json readings_view(const std::string& text) {
  ordered_json view;
  std::istringstream in(text);
  std::string line;
  std::vector<std::string> header, columns;
  while (std::getline(in, line)) {
    if (line.rfind("#", 0) != 0) {
      columns = split(line, ',');
      break;
    }
    if (line.rfind("# made by", 0) != 0) header.push_back(line);
  }
  view["header"] = header;
  view["columns"] = columns;
  double radius_mm = 0.0;
  for (const std::string& h : header) {
    if (h.rfind("# stylus_radius_mm=", 0) == 0) radius_mm = std::stod(h.substr(19));
  }
  const bool has_ref = columns.size() == 16;
  std::vector<std::vector<std::string>> rows;
  while (std::getline(in, line)) {
    if (!line.empty()) rows.push_back(split(line, ','));
  }
  const std::size_t stride = std::max<std::size_t>(1, rows.size() / 12);
  std::uint64_t digest = 0xcbf29ce484222325ULL;
  long left = 0, right = 0;
  double sum_e = 0.0, sum_e2 = 0.0, min_e = INFINITY, max_e = -INFINITY;
  const std::vector<std::string> checksum_names = {
      "px_mm", "py_mm", "pz_mm", "nx", "ny", "nz", "cx-px_um", "cy-py_um", "cz-pz_um", "e_um"};
  std::vector<double> checksum(checksum_names.size(), 0.0);
  ordered_json samples = ordered_json::array();
  for (std::size_t k = 0; k < rows.size(); ++k) {
    const std::vector<std::string>& f = rows[k];
    EXPECT_EQ(f.size(), columns.size()) << "row " << k;
    if (f.size() != columns.size()) return view;
    fnv1a(digest, f[0] + ',' + f[1] + ',' + f[2] + ',' + f[3] + ',' + f[4] + ',' + f[5] + '\n');
    (f[2] == "R" ? right : left) += 1;
    double p[3], n[3], c[3];
    for (int a = 0; a < 3; ++a) {
      p[a] = std::stod(f[6 + a]);
      n[a] = std::stod(f[9 + a]);
      c[a] = std::stod(f[12 + a]);
    }
    const double ref_dev = has_ref ? std::stod(f[15]) : 0.0;
    double along = 0.0;
    for (int a = 0; a < 3; ++a) along += (c[a] - p[a]) * n[a];
    const double e = (along - radius_mm) * 1000.0 - ref_dev;
    sum_e += e;
    sum_e2 += e * e;
    min_e = std::min(min_e, e);
    max_e = std::max(max_e, e);
    const double w = row_weight(k);
    for (int a = 0; a < 3; ++a) {
      checksum[a] += w * p[a];
      checksum[3 + a] += w * n[a];
      checksum[6 + a] += w * (c[a] - p[a]) * 1000.0;
    }
    checksum[9] += w * e;
    if (k % stride == 0) {
      ordered_json row;
      for (std::size_t col = 0; col < columns.size(); ++col) {
        row[columns[col]] = col == 2  ? ordered_json(f[col])
                            : col < 6 ? ordered_json(std::stol(f[col]))
                                      : ordered_json(std::stod(f[col]));
      }
      row["e_um"] = rounded(e);
      samples.push_back(row);
    }
  }
  const double count = static_cast<double>(rows.size());
  view["rows"] = rows.size();
  view["rows_per_flank"] = {{"L", left}, {"R", right}};
  char hex[17];
  std::snprintf(hex, sizeof hex, "%016llx", static_cast<unsigned long long>(digest));
  view["index_columns_fnv1a64"] = hex;
  if (!rows.empty()) {
    const double mean = sum_e / count;
    view["e_um"] = {{"mean", mean},
                    {"std", std::sqrt(std::max(0.0, sum_e2 / count - mean * mean))},
                    {"min", min_e},
                    {"max", max_e}};
  }
  ordered_json sums;
  for (std::size_t c = 0; c < checksum.size(); ++c) sums[checksum_names[c]] = checksum[c];
  view["weighted_checksums"] = sums;
  view["sample_rows"] = samples;
  return view;
}

// Writes (--update) or compares a reference.
void check_reference(const fs::path& reference_path, const std::string& about,
                     const ordered_json& actual, double absolute) {
  if (regression::update_mode()) {
    ordered_json reference;
    reference["_about"] = about;
    for (const auto& [key, value] : actual.items()) reference[key] = value;
    std::ofstream(reference_path) << reference.dump(2) << "\n";
    GTEST_SKIP() << "reference written: " << reference_path;
  }
  std::ifstream reference_file(reference_path);
  ASSERT_TRUE(reference_file) << "no stored reference " << reference_path
                              << "; create it with scripts/update-references";
  const std::string report =
      regression::differences_from(ordered_json::parse(reference_file), actual, absolute);
  EXPECT_TRUE(report.empty())
      << reference_path << " differs:\n"
      << report
      << "If the change is intended, run scripts/update-references and give the reason in the "
         "commit message.";
}

// The absolute tolerance of the readings view's reals near zero (µm for e, mm for coordinates):
// e = (c − p)·n·1000 cancels ~70 mm coordinates, so a last-bit difference of sin/cos (about
// 1.4e-14 mm at 70 mm) moves e by ~1.4e-11 µm and the checksums over 2 400 rows by up to ~1e-9;
// 1e-7 stays far above that and far below any change of the model (≥ 1e-4 µm).
constexpr double kReadingsAbsolute = 1e-7;

struct SimulateCase {
  std::string name;       // test name
  std::string scenario;   // relative to the source tree
  std::string options;    // after --out
  std::string reference;  // relative to the source tree
};

const std::vector<SimulateCase>& simulate_cases() {
  static const std::vector<SimulateCase> cases = {
      // P2's 6-lobed pre-travel and noise on P1's master gear (the README's diagnose example).
      {"lobing_truth_master", "scenarios/diagnose/lobing_truth.yaml", "--master",
       "scenarios/diagnose/lobing_truth.simulate.ref.json"},
      // The same lobing qualified by P2's mean-of-six strategy, with repeatability.
      {"p2_probe_mean6_master", "scenarios/p2_probe_mean6.yaml", "--master",
       "scenarios/p2_probe_mean6.simulate.ref.json"},
      // Perturbed gears with six machine effects, and the calibrated deviations column.
      {"cmm_iso10360_typical_2_gears", "scenarios/cmm_iso10360_typical.yaml",
       "--gears 2 --reference-deviations", "scenarios/cmm_iso10360_typical.simulate.ref.json"},
  };
  return cases;
}

class SimulateRegression : public ::testing::TestWithParam<SimulateCase> {};

TEST_P(SimulateRegression, MatchesStoredReference) {
  const SimulateCase& c = GetParam();
  const fs::path source(GEARMC_SOURCE_DIR);
  const fs::path csv = fresh_temp_path("regression_" + c.name + ".csv");
  fs::remove(csv);
  const auto result = run_gearmc("simulate " + (source / c.scenario).string() + " --out " +
                                 csv.string() + " " + c.options);
  ASSERT_EQ(result.exit_code, 0) << result.err;
  const ordered_json actual = readings_view(read_text(csv));
  fs::remove(csv);
  check_reference(source / c.reference,
                  "Regression reference of `gearmc simulate " + c.scenario + " " + c.options +
                      "`: a view of its readings CSV (header, row counts, a digest of the index "
                      "columns, statistics and weighted checksums of every row, every "
                      "(rows/12)-th row). Written by scripts/update-references; compared by "
                      "tests/regression/command_regression_test.cpp.",
                  actual, kReadingsAbsolute);
}

INSTANTIATE_TEST_SUITE_P(Commands, SimulateRegression, ::testing::ValuesIn(simulate_cases()),
                         [](const ::testing::TestParamInfo<SimulateCase>& param_info) {
                           return param_info.param.name;
                         });

// The README's diagnose example: readings simulated from lobing_truth.yaml (master gear, seed 1)
// diagnosed against lobing_model.yaml (noise only) with the default seed and null replicates.
TEST(DiagnoseRegression, LobingExampleMatchesStoredReference) {
  const fs::path source(GEARMC_SOURCE_DIR);
  const fs::path work = fresh_temp_path("regression_diagnose_lobing");
  fs::remove_all(work);
  fs::create_directories(work);
  const fs::path csv = work / "lobing.csv";
  auto result =
      run_gearmc("simulate " + (source / "scenarios/diagnose/lobing_truth.yaml").string() +
                 " --master --out " + csv.string());
  ASSERT_EQ(result.exit_code, 0) << result.err;
  result =
      run_gearmc("diagnose --model " + (source / "scenarios/diagnose/lobing_model.yaml").string() +
                 " --measured " + csv.string() + " --out " + (work / "out").string());
  ASSERT_EQ(result.exit_code, 0) << result.err;
  std::ifstream file(work / "out" / "diagnosis.json");
  ASSERT_TRUE(file) << "no diagnosis.json";
  ordered_json actual = ordered_json::parse(file);
  actual.erase("provenance");
  fs::remove_all(work);
  check_reference(source / "scenarios/diagnose/lobing_model.diagnose.ref.json",
                  "Regression reference of `gearmc diagnose --model "
                  "scenarios/diagnose/lobing_model.yaml --measured lobing.csv` with lobing.csv "
                  "from `gearmc simulate scenarios/diagnose/lobing_truth.yaml --master`: "
                  "diagnosis.json without its provenance. Written by scripts/update-references; "
                  "compared by tests/regression/command_regression_test.cpp.",
                  actual, 1e-12);
}

}  // namespace
}  // namespace gearmc
