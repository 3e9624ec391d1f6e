// The profile/helix filter (engine/evaluation/trace_filter.h) against the Gaussian's own
// definition (ISO 16610-21): a sine of wavelength λ comes through with the amplitude ratio
// exp(−π (α λc / λ)²), α = √(ln 2/π) — one half at λ = λc — away from the ends; a constant and a
// straight line come through unchanged everywhere, also at the ends and on uneven spacing (the
// first-order regression's purpose; a renormalised plain Gaussian would bend a line's ends by
// 0.15 × slope × λc, which the test would catch); and in a run, `profile_cutoff_mm` removes a
// short wave from f_fα while a long one stays, for the measured and the true values alike.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include "engine/evaluation/parameter_evaluation.h"
#include "engine/evaluation/trace_filter.h"
#include "engine/run/monte_carlo.h"
#include "engine/scenario/scenario.h"

namespace gearmc {
namespace {

constexpr double kPi = std::numbers::pi;

std::vector<double> grid(double a, double b, int n) {
  std::vector<double> x(n);
  for (int i = 0; i < n; ++i) x[i] = a + (b - a) * i / (n - 1);
  return x;
}

TEST(TraceFilter, AlphaIsTheHalfTransmissionWidth) {
  // α² π = ln 2 exactly: exp(−π α²) = 1/2.
  EXPECT_NEAR(kGaussianFilterAlpha, std::sqrt(std::log(2.0) / kPi), 1e-17);
  EXPECT_NEAR(gaussian_filter_transmission(0.8, 0.8), 0.5, 1e-15);
}

TEST(TraceFilter, SinesComeThroughWithTheGaussianTransmission) {
  // 20 mm of trace sampled every 5 µm; amplitude read at the middle 6 mm (> 1.4 λc from the
  // ends), as the sine's projection (exact for a pure sine over whole periods).
  const double cutoff = 0.8;
  const std::vector<double> x = grid(0.0, 20.0, 4001);
  for (const double wavelength : {0.8, 0.4, 0.25, 1.6, 4.0}) {
    std::vector<double> d(x.size());
    for (std::size_t i = 0; i < x.size(); ++i) d[i] = std::sin(2 * kPi * x[i] / wavelength);
    const std::vector<double> f = gaussian_regression_filter(x, d, cutoff);
    double num = 0, den = 0;
    for (std::size_t i = 0; i < x.size(); ++i) {
      if (x[i] < 7.0 || x[i] > 13.0) continue;
      num += f[i] * d[i];
      den += d[i] * d[i];
    }
    const double expected = gaussian_filter_transmission(wavelength, cutoff);
    // The discrete sum of a 5 µm grid matches the integral to ~1e-6; the first-order term's
    // correction vanishes in the interior of a periodic signal.
    EXPECT_NEAR(num / den, expected, 2e-4) << "λ " << wavelength;
  }
  // At the cut-off itself: one half.
  EXPECT_NEAR(gaussian_filter_transmission(0.8, 0.8), 0.5, 1e-12);
}

TEST(TraceFilter, StraightTracesStayStraightAtTheEndsAndOnUnevenSpacing) {
  // A trace 3 λc long (a gear profile is often that short) with uneven spacing.
  std::vector<double> x;
  for (int i = 0; i < 40; ++i) x.push_back(2.4 * std::pow(i / 39.0, 1.3));
  std::vector<double> line(x.size()), constant(x.size(), 2.5);
  for (std::size_t i = 0; i < x.size(); ++i) line[i] = 1.5 - 3.0 * x[i];
  const std::vector<double> fl = gaussian_regression_filter(x, line, 0.8);
  const std::vector<double> fc = gaussian_regression_filter(x, constant, 0.8);
  for (std::size_t i = 0; i < x.size(); ++i) {
    EXPECT_NEAR(fl[i], line[i], 1e-12) << "x " << x[i];
    EXPECT_NEAR(fc[i], 2.5, 1e-12);
  }
  // A plain (zeroth-order) Gaussian renormalised at the ends would be off by
  // α λc / π × slope = 0.1196 × 3 = 0.36 µm at x = 0: far beyond the tolerance above.
  EXPECT_GT(kGaussianFilterAlpha * 0.8 / kPi * 3.0, 0.3);
}

TEST(TraceFilter, SamplesFarApartAreLeftAlone) {
  // Spacing 10 λc: no neighbour weighs anything, every sample is its own value.
  const std::vector<double> x = {0.0, 1.0, 2.0, 3.0};
  const std::vector<double> d = {1.0, -2.0, 0.5, 3.0};
  const std::vector<double> f = gaussian_regression_filter(x, d, 0.1);
  for (std::size_t i = 0; i < x.size(); ++i) EXPECT_DOUBLE_EQ(f[i], d[i]);
}

TEST(TraceFilter, ProfileCutoffRemovesAShortWaveFromTheFormDeviation) {
  // P1's gear with a known real deviation: a 0.05 µm sine of wavelength 0.1 mm of roll length
  // (transmission exp(−π (α 0.8/0.1)²) = 0.5^64: nothing; gentle enough for the stylus ball to
  // follow — with 0.2 µm its δRcomp error reached 0.04 µm in the filtered form) plus a parabola over the profile (its waves are
  // longer than 10 mm: through unchanged to 0.3 %). Unfiltered f_fα sees both; with λc 0.8 mm
  // only the parabola's form remains, in the measured and the true value.
  const std::string base =
      "name: f\nseed: 1\n"
      "gear: {teeth: 24, module_mm: 5.6, pressure_angle_deg: 20, profile_shift: 0.90116, "
      "face_width_mm: 78.89}\n"
      "tolerances: {standard: iso_1328_1_2013, grade: 5}\n"
      "probing: {points_along_profile: 5, sections_across_face: 3, teeth: [1], flanks: R}\n"
      "deviations: {random: false, normal_um: \"0.05*sin(2*_pi*L/0.1) + ((L-30)/15)^2\"}\n";
  const auto form = [&](const std::string& filter) {
    const Scenario s = parse_scenario(
        base + "evaluation: {parameters: [f_falpha], profile_points: 1500, truth_points: 3000" +
            filter + "}\n",
        "f.yaml");
    const MonteCarloRun mc(s);
    RunOptions o;
    o.end_gear = 1;
    o.threads = 1;
    const RunResults r = mc.run(o);
    return r.parameters->values[static_cast<int>(GearParameter::kffalpha)][1].at(0);
  };
  const ParameterValue raw = form("");
  const ParameterValue filtered = form(", profile_cutoff_mm: 0.8");
  // The sine adds its peak-to-valley 0.1 µm to the raw form (its crests meet the parabola's
  // residual extremes within half a period, 0.05 mm, where the residual moves < 0.003 µm; the
  // dense trace's 0.01 mm spacing catches a crest to cos 18°: ≥ 0.095); filtered, it is gone.
  EXPECT_GT(raw.true_dense - filtered.true_dense, 0.095);
  EXPECT_LT(raw.true_dense - filtered.true_dense, 0.103);
  // Measured against the true value at the same points (the measurement error alone: δRcomp's on
  // the sine's slopes ≤ 0.0032 rad, R θ²/2 ≤ 0.003 µm; the 1500-point trace's sampling differs
  // from the dense trace's by ~0.013 µm, which is the sampling error, not the filter's).
  EXPECT_NEAR(filtered.measured, filtered.true_points, 0.01) << filtered.true_dense;
  EXPECT_GT(filtered.true_dense, 0.1);  // the long wave stays
}

}  // namespace
}  // namespace gearmc
