// Readings printed on a grid along the normal (engine/apps/diagnose/reading_grid.h): the rounding
// is a statement about the reading's law, not structure. The rounding is done here by this file's
// own code (the measured deviation e = ((c − p)·n − R)·1000 µm rounded to the step, c rebuilt as p
// + (R + e/1000) n), on readings simulated by gearmc from the battery's truths.
#include <gtest/gtest.h>

#include <cmath>

#include "engine/apps/diagnose/diagnosis.h"
#include "engine/apps/diagnose/reading_grid.h"
#include "tests/support/diagnose_readings.h"

namespace gearmc {
namespace {

using testing_support::baseline;
using testing_support::hidden;

Readings printed(Readings readings, double step_um, double offset_um = 0.0) {
  const double radius = readings.stylus_radius_mm;
  for (ReadingRow& r : readings.rows) {
    const double e = ((r.c - r.p).dot(r.n) - radius) * 1000.0;
    const double printed = std::round((e - offset_um) / step_um) * step_um + offset_um;
    r.c = r.p + (radius + printed / 1000.0) * r.n;
  }
  return readings;
}

TEST(DiagnoseReadingGrid, NullReadingsPrintedToATenthOfAMicronHaveNoGap) {
  // Seeds 1–6 of the null (noise 0.3 µm only), printed to 0.1 µm: before the dither all six were
  // reported as unexplained structure (the KS test saw the rounding's lumps). Each diagnosis is a
  // test at α = 0.01: at most one chance flag is accepted (two or more of six: P < 0.2 %).
  int flagged = 0;
  for (std::uint64_t seed = 1; seed <= 6; ++seed) {
    const Diagnosis d = diagnose(baseline(), printed(hidden("", seed), 0.1));
    ASSERT_TRUE(d.reading_grid.found()) << seed;
    EXPECT_NEAR(d.reading_grid.step_um, 0.1, 1e-12);
    EXPECT_NEAR(d.reading_grid.resultant, 1.0, 1e-6);
    flagged += d.gap_detected ? 1 : 0;
  }
  EXPECT_LE(flagged, 1);
}

TEST(DiagnoseReadingGrid, APrintedEffectIsStillNamedAndAnOffsetGridIsFound) {
  // The battery's lobing (0.75 µm, 6 lobes) printed to 0.1 µm with the grid offset by 0.037 µm:
  // the grid is found (the resultant does not see an offset) and the lobing named within 3
  // standard errors of 0.75.
  const Diagnosis d = diagnose(
      baseline(),
      printed(
          hidden("probe_lobing: {harmonics: [{order: 6, amplitude_um: 0.75, phase_deg: 90}]}\n"),
          0.1, 0.037));
  EXPECT_NEAR(d.reading_grid.step_um, 0.1, 1e-12);
  ASSERT_EQ(d.named_effect_text(), "probe_lobing");
  const FittedValue& a = testing_support::value(d.effects.front(), "amplitude_6_um");
  EXPECT_NEAR(a.value, 0.75, 3.0 * a.std_error);
}

TEST(DiagnoseReadingGrid, ContinuousOrConstantReadingsHaveNoGrid) {
  // Unrounded readings: no step (the chance of a false grid is below 1e-8, reading_grid.h).
  const Residuals continuous = compute_residuals(baseline(), hidden("", 3));
  EXPECT_FALSE(detect_reading_grid(continuous.points).found());
  // Readings that do not vary (a noise-free nominal master): every step "fits", none is a grid.
  const Residuals constant =
      compute_residuals(baseline(), testing_support::master_readings(reference_scenario()));
  EXPECT_FALSE(detect_reading_grid(constant.points).found());
  // A coarse print (0.5 µm against σ 0.3) is found, and the diagnosis says its law is approximate.
  const Diagnosis d = diagnose(baseline(), printed(hidden("", 2), 0.5));
  EXPECT_NEAR(d.reading_grid.step_um, 0.5, 1e-12);
  bool warned = false;
  for (const std::string& n : d.notes) warned = warned || n.find("coarse") != std::string::npos;
  EXPECT_TRUE(warned);
}

}  // namespace
}  // namespace gearmc
