// Tests of the bounded data behind the diagnosis report's plots
// (engine/apps/diagnose/report_plot_data.h): histogram bins from the central quantiles, not the
// range, and a scatter sample that is bounded, deterministic and keeps the extremes.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

#include "engine/apps/diagnose/diagnosis.h"
#include "engine/apps/diagnose/report_plot_data.h"
#include "engine/statistics/histogram.h"
#include "tests/support/diagnose_readings.h"

namespace gearmc {
namespace {

// --- Bounded report data, zero noise floor, statuses ------------------------------------------

TEST(DiagnoseReportData, HistogramBinsComeFromTheCentralQuantilesNotTheRange) {
  // 10 000 residuals in [−1, 1) µm plus one at 10¹¹ µm (a reading 10⁸ mm off) and one at −10⁹:
  // the old range-based bin count would have been 10¹¹ / 50 = 2·10⁹ bins. Now at most 62 bins of a
  // 1-2-5 width covering the 0.5 %–99.5 % quantiles (−0.99, 0.99 µm: the 51st and 9 952nd of the
  // 10 002 sorted values) widened by half their span, 0.99 µm, each side: ±1.98 µm (more than
  // ±3σ, σ = 0.3), so the width is 3.96 / 60 = 0.066 → 0.1 µm, from ⌊−1.98 / 0.1⌋ · 0.1 = −2.0.
  std::vector<double> v;
  for (int k = 0; k < 10000; ++k) v.push_back(-1.0 + 2.0 * k / 10000.0);
  v.push_back(1e11);
  v.push_back(-1e9);
  const DisplayBins b = display_bins(v, 0.3);
  EXPECT_LE(b.bins, 62u);
  EXPECT_DOUBLE_EQ(b.width_um, 0.1);
  EXPECT_NEAR(b.lo_um, -2.0, 1e-12);
  Histogram h(b.lo_um, b.width_um, b.bins);
  for (double x : v) h.add(x);
  EXPECT_EQ(h.overflow(), 1u);
  EXPECT_EQ(h.underflow(), 1u);
  EXPECT_EQ(h.overflow_max(), 1e11);
  // Degenerate inputs still give a valid histogram: all equal, σ 0; empty; non-finite ignored.
  const DisplayBins same = display_bins(std::vector<double>(5, 2.5), 0.0);
  EXPECT_GT(same.width_um, 0.0);
  EXPECT_LE(same.bins, 62u);
  EXPECT_LE(same.lo_um, 0.0);
  EXPECT_GE(same.lo_um + same.width_um * static_cast<double>(same.bins), 2.5);
  const DisplayBins none = display_bins(std::vector<double>{}, 0.0);
  EXPECT_GE(none.bins, 1u);
  const DisplayBins wild =
      display_bins(std::vector<double>{std::numeric_limits<double>::quiet_NaN(), 1.0, 3.0}, 0.0);
  EXPECT_TRUE(std::isfinite(wild.lo_um) && std::isfinite(wild.width_um));
}

TEST(DiagnoseReportData, ScatterSampleIsBoundedDeterministicAndKeepsTheExtremes) {
  std::vector<double> v;
  for (int k = 0; k < 100000; ++k) v.push_back(std::sin(0.001 * k));
  v[77777] = 50.0;   // the largest
  v[12345] = -40.0;  // the smallest
  const std::vector<std::size_t> a = plotted_sample(v, 5000, 1);
  EXPECT_EQ(a.size(), 5000u);
  EXPECT_TRUE(std::is_sorted(a.begin(), a.end()));
  EXPECT_TRUE(std::binary_search(a.begin(), a.end(), 77777u));
  EXPECT_TRUE(std::binary_search(a.begin(), a.end(), 12345u));
  EXPECT_EQ(a, plotted_sample(v, 5000, 1));
  // Uniform over the indices: each tenth of the file holds 500 ± 3·√(5000·0.1·0.9) ≈ 500 ± 64.
  for (int tenth = 0; tenth < 10; ++tenth) {
    const auto in = std::count_if(
        a.begin(), a.end(), [&](std::size_t k) { return static_cast<int>(k / 10000) == tenth; });
    EXPECT_NEAR(static_cast<double>(in), 500.0, 64.0) << "tenth " << tenth;
  }
  EXPECT_EQ(plotted_sample(std::vector<double>(10, 1.0), 5000, 1).size(), 10u);
}

}  // namespace
}  // namespace gearmc
