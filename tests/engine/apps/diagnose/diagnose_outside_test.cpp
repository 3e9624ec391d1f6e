// Shapes a blind tester found from outside the effect library, on readings from this file's own
// generator (no gearmc effect code): P1's nominal master points, the stylus centre written by
// hand. A clocking (the gear turned about its axis) is named `clocking` with its angle, not
// squareness; heavy-tailed noise of the model's σ is a statement about the noise law, not
// "unexplained structure along" an axis whose own test is not significant.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

#include "engine/apps/diagnose/diagnosis.h"
#include "engine/apps/diagnose/fitted_scenario.h"
#include "tests/support/diagnose_readings.h"

namespace gearmc {
namespace {

// The master's readings with noise `noise(rng)` µm along the normal, the centre then turned about
// the gear axis (z) by `angle_urad` (counter-clockwise from +z).
template <class Noise>
Readings own_readings(std::uint64_t seed, double angle_urad, Noise noise) {
  Readings readings = testing_support::master_readings(reference_scenario());
  std::mt19937_64 rng(seed);
  const double a = angle_urad * 1e-6;
  for (ReadingRow& r : readings.rows) {
    const Eigen::Vector3d c = r.p + (readings.stylus_radius_mm + noise(rng) / 1000.0) * r.n;
    r.c = Eigen::Vector3d(std::cos(a) * c.x() - std::sin(a) * c.y(),
                          std::sin(a) * c.x() + std::cos(a) * c.y(), c.z());
  }
  return readings;
}

double gaussian(std::mt19937_64& rng) { return std::normal_distribution<double>(0.0, 0.3)(rng); }

// Student's t with 4 degrees of freedom scaled to σ 0.3 µm (its variance ν/(ν − 2) = 2).
double student(std::mt19937_64& rng) {
  return 0.3 * std::student_t_distribution<double>(4.0)(rng) / std::sqrt(2.0);
}

TEST(DiagnoseOutside, AClockedGearIsNamedClockingWithItsAngle) {
  // 20 and 10 µrad (1.26 and 0.63 µm at P1's base radius 63.15 mm), seed 1: named, the angle
  // within 3 standard errors; before `clocking` joined the library this was read as squareness
  // (a shear of the axes contains a turn of half its angle) plus a rotary table pattern.
  for (double angle : {20.0, 10.0}) {
    const Diagnosis d = diagnose(testing_support::baseline(), own_readings(1, angle, gaussian));
    ASSERT_EQ(d.named_effect_text(), "clocking") << angle;
    const FittedValue& v = testing_support::value(d.effects.front(), "angle_urad");
    EXPECT_NEAR(v.value, angle, 3.0 * v.std_error) << angle;
    EXPECT_LT(v.std_error, 0.2);
    EXPECT_EQ(d.effects.size(), 1u);
  }
}

TEST(DiagnoseOutside, ASquarenessIsNotTakenForAClocking) {
  // The battery's squareness (20 µrad, gearmc's own simulation) stays squareness: its shear part
  // is not in the clocking's column.
  const Diagnosis d =
      diagnose(testing_support::baseline(), testing_support::hidden("squareness: {xy_urad: 20}\n"));
  EXPECT_EQ(d.named_effect_text(), "squareness");
}

TEST(DiagnoseOutside, HeavyTailedNoiseOfTheModelsSigmaIsALawNotStructure) {
  // Seeds 1–5 of Student-t noise (4 dof) with the model's σ: before the structure needed its own
  // test these were "unexplained structure along" flank or probing order (KS rejected, the axis'
  // F-test p 0.01–0.34). Now no effect and no structure; where the gap test rejects, the law's
  // shape is named — heavier tails (a t law's excess kurtosis is 6/(ν − 4) … infinite at ν = 4).
  int differs = 0;
  for (std::uint64_t seed = 1; seed <= 5; ++seed) {
    const Diagnosis d = diagnose(testing_support::baseline(), own_readings(seed, 0.0, student));
    EXPECT_EQ(d.named_effect_text(), "none") << seed;
    EXPECT_FALSE(d.unexplained_structure) << seed;
    EXPECT_FALSE(d.gap_detected) << seed;
    if (d.law_shape.differs) {
      ++differs;
      EXPECT_EQ(d.law_shape.shape, "heavier tails") << seed;
      EXPECT_GT(d.law_shape.excess_kurtosis, 3.0 * d.law_shape.kurtosis_std_error) << seed;
    }
  }
  EXPECT_GE(differs, 3);  // the KS test at α 0.01 finds the shape in most seeds
  RecordProperty("law_shape_named", differs);
}

TEST(DiagnoseOutside, GaussianNullHasNoLawFinding) {
  // The same generator with Gaussian noise: nothing to say about the law (seeds 1–3).
  for (std::uint64_t seed = 1; seed <= 3; ++seed) {
    const Diagnosis d = diagnose(testing_support::baseline(), own_readings(seed, 0.0, gaussian));
    EXPECT_EQ(d.named_effect_text(), "none") << seed;
    EXPECT_FALSE(d.law_shape.differs) << seed;
  }
}

// Three runs of the master: run g shifted by (sx_g, sy_g) µm (re-clamped), every run drifting
// along x by `drift_um` over its probing sequence (c_x += drift · order/(N − 1)), noise 0.3 µm.
Readings three_runs(std::uint64_t seed, const double (&shift)[3][2], double drift_um) {
  const Readings one = testing_support::master_readings(reference_scenario());
  Readings readings = one;
  readings.rows.clear();
  std::mt19937_64 rng(seed);
  const double last = static_cast<double>(one.rows.size() - 1);
  for (int g = 0; g < 3; ++g) {
    for (ReadingRow r : one.rows) {
      r.gear = g;
      const double dev = gaussian(rng);
      r.c = r.p + (one.stylus_radius_mm + dev / 1000.0) * r.n;
      r.c.x() += (shift[g][0] + drift_um * r.order / last) / 1000.0;
      r.c.y() += shift[g][1] / 1000.0;
      readings.rows.push_back(r);
    }
  }
  return readings;
}

TEST(DiagnoseOutside, RepeatedRunsWithTheirOwnSetUpsAndACommonDrift) {
  // The tester's case: a drift between and within three runs of one gear was blamed on a rotary
  // table "that changes per run". The runs' set-up differences are now in every model (their F
  // test rejects), the first run's shift is `eccentricity`, the drift is named beside it with its
  // value, and no rotary table is fitted. Truth: shifts (µm) below, x drift 0.4 µm: the shift
  // takes the drift's mean, and the increment left beyond it is below the practical size 0.075 µm;
  // only the drift's own contribution (≈ 0.16 µm RMS) passes it (selection.h). Judged on the
  // increment, the drift was dropped and the runs' turns came out 0.8 and 1.0 µrad (> 3 SE).
  const double shift[3][2] = {{-1.2, 0.8}, {2.1, -0.4}, {0.6, 1.9}};
  const Diagnosis d = diagnose(testing_support::baseline(), three_runs(3, shift, 0.4));
  ASSERT_TRUE(d.setups.fitted);
  ASSERT_EQ(d.setups.runs.size(), 2u);
  for (int g = 1; g < 3; ++g) {
    const SetupRun& r = d.setups.runs[static_cast<std::size_t>(g - 1)];
    EXPECT_NEAR(r.shift_x_um, shift[g][0] - shift[0][0], 3.0 * r.shift_x_se_um) << g;
    EXPECT_NEAR(r.shift_y_um, shift[g][1] - shift[0][1], 3.0 * r.shift_y_se_um) << g;
    EXPECT_NEAR(r.turn_urad, 0.0, 3.0 * r.turn_se_urad) << g;
  }
  bool drift = false, table = false;
  for (const FittedEffect& e : d.effects) {
    table = table || e.name == "rotary_table";
    if (e.name != "drift") continue;
    drift = true;
    const FittedValue& v = testing_support::value(e, "x_um");
    EXPECT_NEAR(v.value, 0.4, 3.0 * v.std_error);
  }
  EXPECT_TRUE(drift);
  EXPECT_FALSE(table);
  ASSERT_EQ(d.named_effect_text(), "eccentricity");
  const FittedValue& x = testing_support::value(d.effects.front(), "x_um");
  EXPECT_NEAR(x.value, shift[0][0], 3.0 * x.std_error);
  EXPECT_FALSE(d.unexplained_structure);
}

TEST(DiagnoseOutside, ATablePatternGivesWayToTheEccentricityItsHarmonicsAlsoSpan) {
  // The battery's seed 15 at 0.5× in this file's generator: the first run hardly shifted
  // (0.15, −0.25 µm), x drift 0.5 µm. The rotary table (six columns) took step 1 — its harmonics
  // carry part of the drift's once-around component — and was then kept for the eccentricity its
  // first harmonics also span. With the drift in the model, the eccentricity (two columns) explains
  // the readings as well: it replaces the table (selection.h replace_by_smaller), and the
  // replaced table is listed with the reason. Seeds 1–5: never a rotary table.
  const double shift[3][2] = {{0.15, -0.25}, {1.25, -1.1}, {-2.85, 1.95}};
  for (std::uint64_t seed = 1; seed <= 5; ++seed) {
    const Diagnosis d = diagnose(testing_support::baseline(), three_runs(seed, shift, 0.5));
    bool table = false, drift = false;
    for (const FittedEffect& e : d.effects) {
      table = table || e.name == "rotary_table";
      drift = drift || e.name == "drift";
    }
    EXPECT_FALSE(table) << seed;
    EXPECT_TRUE(drift) << seed;
    EXPECT_FALSE(d.unexplained_structure) << seed;
  }
}

TEST(DiagnoseOutside, RunsOnOneSetUpAddNothingToTheModel) {
  // Three runs without a shift: the set-up test does not reject (seed 4, α 0.01), and nothing is
  // named.
  const double shift[3][2] = {{0.0, 0.0}, {0.0, 0.0}, {0.0, 0.0}};
  const Diagnosis d = diagnose(testing_support::baseline(), three_runs(4, shift, 0.0));
  EXPECT_TRUE(d.setups.tested);
  EXPECT_FALSE(d.setups.fitted);
  EXPECT_GT(d.setups.p_value, 0.01);
  EXPECT_EQ(d.named_effect_text(), "none");
}

TEST(DiagnoseOutside, APeriodicScaleErrorIsFoundOnItsMachineAxisWithItsPeriod) {
  // An x encoder error e = 0.6 sin(2π c_x/25 mm + 1) µm on the recorded centre (seed 1): before
  // the periodic family it was "along tooth" with a harmonic term that removed 0.015 of 0.416 µm
  // RMS. Now the structure is located on x_position, the period within 2 % and the amplitude
  // within 10 % of the truth, and the empirical term says why none is written.
  Readings readings = own_readings(1, 0.0, gaussian);
  for (ReadingRow& r : readings.rows) {
    r.c.x() += 0.6 * std::sin(2.0 * std::numbers::pi * r.c.x() / 25.0 + 1.0) / 1000.0;
  }
  const Diagnosis d = diagnose(testing_support::baseline(), readings);
  ASSERT_TRUE(d.unexplained_structure);
  EXPECT_EQ(d.unexplained_along.axis, "x_position");
  EXPECT_NEAR(d.unexplained_along.period_mm, 25.0, 0.5);
  EXPECT_NEAR(d.unexplained_along.amplitude_um, 0.6, 0.06);
  EXPECT_FALSE(d.empirical.fitted);
  EXPECT_NE(d.empirical.identify_by.find("step gauge"), std::string::npos);
}

TEST(DiagnoseOutside, TheAcceptedFitIsWrittenWhenStructureRemains) {
  // P2's 6-lobed probe (0.75 µm, gearmc's simulation) with an x encoder error added by hand
  // (0.6 µm, period 25 mm): the lobing is accepted, the periodic structure remains and no
  // empirical term can describe it. fitted.yaml still holds the accepted lobing (before, the model
  // was written unchanged whenever the verdict was "unexplained" without an empirical term).
  Readings readings = testing_support::hidden(
      "probe_lobing: {harmonics: [{order: 6, amplitude_um: 0.75, phase_deg: 90}]}\n");
  for (ReadingRow& r : readings.rows) {
    r.c.x() += 0.6 * std::sin(2.0 * std::numbers::pi * r.c.x() / 25.0 + 1.0) / 1000.0;
  }
  const Scenario model = testing_support::baseline();
  const Diagnosis d = diagnose(model, readings);
  ASSERT_EQ(d.finding, DiagnosisFinding::kUnexplained);
  EXPECT_EQ(d.unexplained_along.axis, "x_position");
  ASSERT_FALSE(d.effects.empty());
  EXPECT_EQ(d.effects.front().name, "probe_lobing");
  EXPECT_FALSE(d.fit_refused);
  EXPECT_FALSE(d.empirical.fitted);
  const FittedScenario fitted = fitted_scenario(model, d, "m.yaml", "r.csv");
  EXPECT_NE(fitted.yaml.find("probe_lobing"), std::string::npos) << fitted.yaml;
}

TEST(DiagnoseOutside, AGearAxisStructureStaysOnTheGearAxis) {
  // The periodic family does not take structure that follows the gear: a waviness across the
  // face (0.8 sin(2π z/20 mm) µm on every flank, seed 1) stays along face_position (z_position
  // has no normal component on a spur gear, and x/y periods do not carry it).
  Readings readings = own_readings(1, 0.0, gaussian);
  for (ReadingRow& r : readings.rows) {
    r.c += 0.8e-3 * std::sin(2.0 * std::numbers::pi * r.p.z() / 20.0) * r.n;
  }
  const Diagnosis d = diagnose(testing_support::baseline(), readings);
  ASSERT_TRUE(d.unexplained_structure);
  EXPECT_EQ(d.unexplained_along.axis, "face_position");
}

TEST(DiagnoseOutside, ACoordinateGridBelowThePracticalSizeIsNotStructure) {
  // Coordinates rounded to 0.25 µm (offset 0.17 µm) beside noise 0.3 µm: the grid is found but
  // too fine to be named (0.072 µm along the normal against the practical 0.075 µm); its variance
  // can still push χ² over the gate. Seeds 1–10: never "unexplained" (the latched model's
  // simulation reproduces the residuals), never a machine effect.
  for (std::uint64_t seed = 1; seed <= 10; ++seed) {
    Readings readings = own_readings(seed, 0.0, gaussian);
    for (ReadingRow& r : readings.rows) {
      for (int a = 0; a < 3; ++a) {
        r.c[a] = std::round((r.c[a] - 0.17e-3) / 0.25e-3) * 0.25e-3 + 0.17e-3;
      }
    }
    const Diagnosis d = diagnose(testing_support::baseline(), readings);
    // The grid's extra spread may be read as a larger probing noise (a point-law finding, right
    // in size); never as structure or a machine effect.
    EXPECT_TRUE(d.named_effect_text() == "none" || d.named_effect_text() == "noise")
        << seed << " " << d.named_effect_text();
    EXPECT_FALSE(d.unexplained_structure) << seed;
    EXPECT_TRUE(d.coordinate_grid.found()) << seed;
  }
}

}  // namespace
}  // namespace gearmc
