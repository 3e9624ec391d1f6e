// The readings' own resolution (reading_grid.h): a Rayleigh test of the measured deviations on
// steps of k · 0.01 µm, and the dither that makes rounded readings continuous again.
#include "engine/apps/diagnose/reading_grid.h"

#include <cmath>

#include "core/random_stream.h"
#include "engine/apps/diagnose/coordinate_grid.h"

namespace gearmc {
namespace {

constexpr double kUnitUm = 0.01;
constexpr int kMaxMultiple = 1000;
// Printed readings lie on their grid exactly (up to the text's own digits): R = 1. A looser
// threshold (the coordinate grid's 0.5, for latching with noise) would take a coarse rounding with
// few distinct values for a grid of another step.
constexpr double kThreshold = 0.999;
constexpr int kMinReadings = 100;
constexpr std::uint32_t kDitherSubIndex = 4000;

}  // namespace

ReadingGrid detect_reading_grid(const std::vector<ResidualPoint>& points) {
  ReadingGrid out;
  if (static_cast<int>(points.size()) < kMinReadings) {
    out.skipped_because = "fewer than " + std::to_string(kMinReadings) + " readings";
    return out;
  }
  out.ran = true;
  std::vector<double> m;
  double sum = 0.0, sum2 = 0.0;
  for (const ResidualPoint& p : points) {
    m.push_back(p.measured_um);
    sum += p.measured_um;
  }
  const double n = static_cast<double>(m.size()), mean = sum / n;
  for (double v : m) sum2 += (v - mean) * (v - mean);
  const double spread = 2.0 * std::sqrt(sum2 / n);
  if (grid_resultant(m, kUnitUm) < kThreshold) return out;
  for (int k = kMaxMultiple; k >= 1; --k) {
    const double step = k * kUnitUm;
    if (step >= spread) continue;
    const double r = grid_resultant(m, step);
    if (r >= kThreshold) {
      out.step_um = step;
      out.resultant = r;
      return out;
    }
  }
  return out;
}

void dither_readings(std::vector<ResidualPoint>& points, double step_um, std::uint64_t seed) {
  RandomStream rng(seed, 0, StreamPurpose::kDiagnoseNull, kDitherSubIndex);
  for (ResidualPoint& p : points) p.residual_um += step_um * (rng.uniform() - 0.5);
}

}  // namespace gearmc
