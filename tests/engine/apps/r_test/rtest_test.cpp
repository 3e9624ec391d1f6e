// P3's contact R-Test (engine/apps/r_test): the instrument geometry, the forward model against a
// hand-built geometry and an independent closed-form trilateration, the calibration recovering
// known base points from noise-free readings, the varied-parameter sensitivities against exact
// derivatives (a linear sub-case and finite differences), the full Monte-Carlo method against the
// Gaussian limit of the whole-chain GUM at tiny input uncertainties, and bit-identical results for
// 1 and 2 threads.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <sstream>

#include "engine/apps/r_test/instrument.h"
#include "engine/apps/r_test/r_test_evaluation.h"
#include "engine/apps/r_test/r_test_model.h"
#include "engine/apps/r_test/register.h"
#include "engine/apps/uncertainty/model.h"

namespace gearmc::rtest {
namespace {

// P3's hardware numbers (docs/r-test.md): R = 15 mm, r = 2.5 mm; λ = 40 mm assumed.
Geometry p3_geometry() { return make_geometry(15.0, 2.5, 40.0); }

// A model file with every input law scaled by `scale` (1 = P3's numbers, in mm).
std::string model_text(double scale, const std::string& extra = "") {
  auto law = [&](double a) {
    std::ostringstream s;
    s.precision(17);
    s << "{uniform: [" << -a * scale << ", " << a * scale << "], dof: 50}";
    return s.str();
  };
  return "name: rt\ninputs:\n  linearity: " + law(0.0025) + "\n  repeatability: " + law(0.0005) +
         "\n  resolution: " + law(0.00005) + "\n  tip_form: " + law(0.0005) +
         "\n  ball_form: " + law(0.0003) + "\n  positioning: " + law(0.0001) +
         "\nbuiltin: {model: r_test, verification_positions: 10, verification_repetitions: 40" +
         extra + "}\nsettings: {trials: 2000, seed: 7}\n";
}

RTestModel make_model(double scale, const std::string& extra = "") {
  register_r_test_model();
  return make_r_test_model(
      uncertainty::parse_uncertainty_model(model_text(scale, extra), "t.yaml"));
}

TEST(RTestInstrument, AxesMutuallyPerpendicularAtArcsinOneOverRootThree) {
  const Geometry g = p3_geometry();
  EXPECT_NEAR(g.alpha * 180 / std::numbers::pi, 35.2644, 1e-4);  // asin(1/√3) = 35.2644°
  for (int i = 0; i < kSensors; ++i) {
    EXPECT_NEAR(g.axis[i].norm(), 1.0, 1e-15);
    for (int j = i + 1; j < kSensors; ++j) EXPECT_NEAR(g.axis[i].dot(g.axis[j]), 0.0, 1e-15);
    // Every axis passes through O: O − C_i1 is parallel to u_i.
    EXPECT_NEAR((g.centre - g.base[i]).normalized().dot(g.axis[i]), 1.0, 1e-15);
  }
}

TEST(RTestInstrument, BallAtCentreFromEqualReadings) {
  // Hand-built: with the ball at O every tip sits on its axis at distance R + r below O, so all
  // three readings equal λ/cos α − (R + r) = 40·√(3/2) − 17.5 = 31.489795 mm, and those readings
  // must give back P = O = (0, 0, λ tan α) = (0, 0, 40/√2).
  const Geometry g = p3_geometry();
  const double l0 = 40.0 * std::sqrt(1.5) - 17.5;
  EXPECT_NEAR(g.reading_at_centre(), l0, 1e-12);
  for (int i = 0; i < kSensors; ++i) {
    EXPECT_NEAR(reading_for(g.base[i], g.axis[i], g.centre, 17.5), l0, 1e-12);
  }
  const BallCentre P =
      solve_ball_centre(g.base, g.axis, Vector3d::Constant(l0), Vector3d::Constant(17.5));
  ASSERT_TRUE(P.ok);
  EXPECT_NEAR((P.centre - Vector3d(0, 0, 40.0 / std::sqrt(2.0))).norm(), 0.0, 1e-12);
}

// Independent closed-form trilateration (three spheres): with the tip centres A, B, C and radii
// ρ_a, ρ_b, ρ_c, the frame e_x = (B − A)/|B − A|, e_y ⟂ in the plane, e_z = e_x × e_y gives
// x = (ρ_a² − ρ_b² + d²)/(2d), y = (ρ_a² − ρ_c² + i² + j² − 2 i x)/(2j), z = ±√(ρ_a² − x² − y²).
Vector3d trilaterate(const Triple& c, const Vector3d& rho, const Vector3d& up) {
  const Vector3d ex = (c[1] - c[0]).normalized();
  const double i = ex.dot(c[2] - c[0]);
  const Vector3d ey = (c[2] - c[0] - i * ex).normalized();
  const Vector3d ez = ex.cross(ey);
  const double d = (c[1] - c[0]).norm(), j = ey.dot(c[2] - c[0]);
  const double x = (rho[0] * rho[0] - rho[1] * rho[1] + d * d) / (2 * d);
  const double y = (rho[0] * rho[0] - rho[2] * rho[2] + i * i + j * j - 2 * i * x) / (2 * j);
  const double z = std::sqrt(rho[0] * rho[0] - x * x - y * y);
  const Vector3d s = ez.dot(up) > 0 ? ez : Vector3d(-ez);
  return c[0] + x * ex + y * ey + z * s;
}

TEST(RTestInstrument, ForwardModelMatchesClosedFormTrilaterationAndChoosesThePhysicalRoot) {
  const Geometry g = p3_geometry();
  const Triple base = {g.base[0] + Vector3d(0.01, -0.02, 0.005), g.base[1],
                       g.base[2] + Vector3d(-0.03, 0.0, 0.01)};
  const Vector3d rho(17.5003, 17.4998, 17.5001);
  for (const Vector3d& offset :
       {Vector3d(0.3, -0.2, 0.1), Vector3d(-0.45, 0.05, -0.3), Vector3d(0.0, 0.4, 0.35)}) {
    const Vector3d truth = g.centre + offset;
    Vector3d l;
    Triple tips;
    for (int i = 0; i < kSensors; ++i) {
      l[i] = reading_for(base[i], g.axis[i], truth, rho[i]);
      tips[i] = base[i] + l[i] * g.axis[i];
    }
    const BallCentre P = solve_ball_centre(base, g.axis, l, rho);
    ASSERT_TRUE(P.ok);
    // The closed form's root on the side the sensors point to (+z: above the tips).
    EXPECT_NEAR((P.centre - trilaterate(tips, rho, Vector3d::UnitZ())).norm(), 0.0, 1e-11);
    EXPECT_NEAR((P.centre - truth).norm(), 0.0, 1e-11);
  }
}

TEST(RTestInstrument, BallCentreDerivativesMatchFiniteDifferences) {
  const Geometry g = p3_geometry();
  const Vector3d truth = g.centre + Vector3d(0.2, -0.1, 0.15);
  Vector3d l;
  for (int i = 0; i < kSensors; ++i) l[i] = reading_for(g.base[i], g.axis[i], truth, 17.5);
  const BallCentreDerivatives D = ball_centre_derivatives(g.base, g.axis, l, truth);
  const double h = 1e-6;  // central differences: error ~ h² |P'''| ≪ 1e-8
  for (int i = 0; i < kSensors; ++i) {
    Vector3d lp = l, lm = l;
    lp[i] += h;
    lm[i] -= h;
    const Vector3d fd = (solve_ball_centre(g.base, g.axis, lp, Vector3d::Constant(17.5)).centre -
                         solve_ball_centre(g.base, g.axis, lm, Vector3d::Constant(17.5)).centre) /
                        (2 * h);
    EXPECT_NEAR((fd - D.d_reading.col(i)).norm(), 0.0, 1e-6);
    for (int k = 0; k < 3; ++k) {
      Triple bp = g.base, bm = g.base;
      bp[i][k] += h;
      bm[i][k] -= h;
      const Vector3d fdb = (solve_ball_centre(bp, g.axis, l, Vector3d::Constant(17.5)).centre -
                            solve_ball_centre(bm, g.axis, l, Vector3d::Constant(17.5)).centre) /
                           (2 * h);
      EXPECT_NEAR((fdb - D.d_base[i].col(k)).norm(), 0.0, 1e-6);
    }
  }
}

SensorData noise_free_data(const Geometry& g, int i, const Vector3d& true_base) {
  SensorData d;
  const double a = 0.3;
  const Vector3d O = g.centre;
  d.points = {O + Vector3d(a, 0, 0), O - Vector3d(a, 0, 0), O + Vector3d(0, a, 0),
              O - Vector3d(0, a, 0), O + Vector3d(0, 0, a), O - Vector3d(0, 0, a)};
  for (int j = 0; j < kCalibrationPoints; ++j) {
    d.rho[j] = 17.5;
    d.readings[j] = reading_for(true_base, g.axis[i], d.points[j], 17.5);
  }
  return d;
}

TEST(RTestCalibration, RecoversKnownBasePointsFromNoiseFreeReadings) {
  // Reference: the construction. Readings generated from known base points (nominal + mounting
  // offsets of tens of µm) with no error; the fit from the nominal start must return them. The
  // lateral coordinates are identified only through the ~1/60 tilt of the contact normals between
  // points (condition number ~1e4), so "exactly" is to the fit's tolerance, 1e-8 mm = 10 pm.
  const Geometry g = p3_geometry();
  const Triple offsets = {Vector3d(0.03, -0.02, 0.04), Vector3d(-0.05, 0.01, -0.02),
                          Vector3d(0.02, 0.05, 0.01)};
  for (int i = 0; i < kSensors; ++i) {
    const Vector3d truth = g.base[i] + offsets[i];
    const SensorData d = noise_free_data(g, i, truth);
    const SensorFit f = calibrate_sensor(g.axis[i], d, g.base[i]);
    ASSERT_TRUE(f.ok) << i;
    EXPECT_LT((f.base - truth).norm(), 1e-8) << i;
    for (double r : f.residuals) EXPECT_LT(std::abs(r), 1e-12);
  }
}

TEST(RTestSensitivities, VariedParameterEqualsExactOnLinearSubCases) {
  // Two directions along which the fitted base point is exactly linear in the data:
  //  * every reading of the sensor + t: the base point − t u reproduces every tip centre, so
  //    dC/dt = −u exactly;
  //  * every calibration point + t v: the whole set-up translates, dC/dt = v exactly.
  // P3's varied-parameter method (δ = 0.01 mm, e = 0.001 mm) and the implicit-function derivative
  // must both give these to the fit's precision: the refits stop within ~1e-9 mm (kFitTolerance),
  // divided by s ≥ 1e-3 mm that is 1e-6, so 1e-5 relative for the varied method; the derivative
  // at a base point that close to the minimum, 1e-7.
  const Geometry g = p3_geometry();
  for (int i = 0; i < kSensors; ++i) {
    const Vector3d truth = g.base[i] + Vector3d(0.01, 0.02, -0.01);
    const SensorData d = noise_free_data(g, i, truth);
    const SensorFit f = calibrate_sensor(g.axis[i], d, g.base[i]);
    const SensorFitDerivatives D = sensor_fit_derivatives(g.axis[i], d, f.base);
    DataDirection readings;
    readings.reading.fill(1.0);
    const Vector3d v(0.3, -0.5, 0.8);
    DataDirection translate;
    translate.point.fill(v);
    for (const auto& [dir, expected] :
         {std::pair{readings, Vector3d(-g.axis[i])}, std::pair{translate, v}}) {
      const VariedSensitivity vs =
          varied_parameter_sensitivity(g.axis[i], d, f.base, dir, 0.01, 0.001);
      ASSERT_TRUE(vs.ok);
      EXPECT_LT((vs.value - expected).norm(), 1e-5 * expected.norm()) << i;
      EXPECT_LT((directional_derivative(D, dir) - expected).norm(), 1e-7 * expected.norm()) << i;
    }
  }
}

TEST(RTestSensitivities, ExactDerivativesMatchFiniteDifferencesWithNoisyData) {
  // The implicit-function derivatives keep the residual-times-curvature terms, so they are exact at
  // a fit with non-zero residuals too. Reference: central differences of the refit with s = 1e-4
  // mm (truncation ~(40 s / 17.5 mm)^2 ~ 5e-8 relative; the refits stop within ~1e-9 mm, i.e.
  // 1e-5 of the difference quotient, whose smallest components here are ~0.2), against a 1e-3
  // relative tolerance.
  const Geometry g = p3_geometry();
  SensorData d = noise_free_data(g, 0, g.base[0]);
  const double noise[kCalibrationPoints] = {2e-3, -1.5e-3, 0.7e-3, -2.2e-3, 1.1e-3, 0.3e-3};
  for (int j = 0; j < kCalibrationPoints; ++j) d.readings[j] += noise[j];
  const SensorFit f = calibrate_sensor(g.axis[0], d, g.base[0]);
  ASSERT_TRUE(f.ok);
  const SensorFitDerivatives D = sensor_fit_derivatives(g.axis[0], d, f.base);
  for (int j = 0; j < kCalibrationPoints; ++j) {
    for (int what = 0; what < 3; ++what) {
      DataDirection dir;
      if (what == 0) dir.reading[j] = 1.0;
      if (what == 1) dir.rho[j] = 1.0;
      if (what == 2) dir.point[j] = Vector3d(0.6, 0.0, 0.8);
      const double s = 1e-4;
      const Vector3d fd = (calibrate_sensor(g.axis[0], moved(d, dir, s), f.base).base -
                           calibrate_sensor(g.axis[0], moved(d, dir, -s), f.base).base) /
                          (2 * s);
      const Vector3d exact = directional_derivative(D, dir);
      EXPECT_LT((fd - exact).norm(), 1e-3 * exact.norm()) << j << " " << what;
    }
  }
}

TEST(RTestMonteCarlo, FullMcmApproachesTheWholeChainGumAtTinyInputUncertainties) {
  // With every input law scaled by 1e-3 the model is linear to ~1e-6 relative, so the standard
  // deviation of the full MCM's error must equal the whole-chain GUM's u (exact variance of a
  // linear function of independent inputs). Tolerance: 4 standard errors of a standard deviation
  // from M = 20000 trials, se/σ = √((κ − 1)/(4M)) ≤ √(2/(4M)) = 0.5 % for kurtosis κ ≤ 3 (sums of
  // uniforms), i.e. 2 % — a false alarm rate of about 6e-5 per axis. Seed 7, trials 0..19999.
  const RTestModel m = make_model(1e-3);
  Calibration exact;
  for (int i = 0; i < kSensors; ++i) {
    exact.data[i] = noise_free_data(m.geometry, i, m.true_base[i]);
    exact.fit[i] = calibrate_sensor(m.geometry.axis[i], exact.data[i], m.geometry.base[i]);
    exact.base[i] = exact.fit[i].base;
  }
  const Prediction gum = whole_chain_gum(m, exact, m.measured);
  const int M = 20000;
  Vector3d sum = Vector3d::Zero(), sq = Vector3d::Zero();
  for (int t = 0; t < M; ++t) {
    Vector3d e;
    ASSERT_TRUE(full_mcm_trial(m, static_cast<std::uint64_t>(t), e));
    sum += e;
    sq += e.cwiseAbs2();
  }
  for (int k = 0; k < 3; ++k) {
    const double mean = sum[k] / M;
    const double sd = std::sqrt((sq[k] - M * mean * mean) / (M - 1));
    EXPECT_NEAR(sd / gum.axis[k].u, 1.0, 0.02) << k;
    EXPECT_LT(std::abs(mean), 4 * gum.axis[k].u / std::sqrt(double(M))) << k;
  }
}

TEST(RTestMonteCarlo, ResultsBitIdenticalForOneAndTwoThreads) {
  const RTestModel m = make_model(1.0);
  RTestRunOptions o;
  o.trials = 3000;
  o.threads = 1;
  const RTestResult a = evaluate_r_test(m, o);
  o.threads = 2;
  const RTestResult b = evaluate_r_test(m, o);
  ASSERT_EQ(a.predictions.size(), b.predictions.size());
  for (std::size_t p = 0; p < a.predictions.size(); ++p) {
    for (int k = 0; k < 3; ++k) {
      EXPECT_EQ(a.predictions[p].axis[k].u, b.predictions[p].axis[k].u) << p;
      EXPECT_EQ(a.predictions[p].axis[k].U, b.predictions[p].axis[k].U) << p;
      EXPECT_EQ(a.predictions[p].axis[k].estimate, b.predictions[p].axis[k].estimate) << p;
    }
  }
  for (int k = 0; k < 3; ++k) {
    EXPECT_EQ(a.verification.pooled95[k], b.verification.pooled95[k]);
    EXPECT_EQ(a.verification.rms[k], b.verification.rms[k]);
  }
  for (std::size_t q = 0; q < a.verification.actual95.size(); ++q) {
    EXPECT_EQ(a.verification.actual95[q], b.verification.actual95[q]);
  }
  EXPECT_EQ(a.verification.failed, 0u);
}

// The verification's 95 % of |error| is the order statistic ⌈0.95 n⌉ of the n finite |e|
// (counted by hand): an off-by-one would take the next one.
TEST(RTestEvaluation, AbsQuantileIsTheCeilOrderStatistic) {
  EXPECT_EQ(rtest::abs_quantile({-5, 1, -2, 3, 4}, 0.95), 5.0);  // ⌈4.75⌉ = 5th of 1 … 5
  EXPECT_EQ(rtest::abs_quantile({-5, 1, -2, 3, 4}, 0.5), 3.0);   // ⌈2.5⌉ = 3rd
  EXPECT_EQ(rtest::abs_quantile({-5, 1, -2, 3, 4}, 0.4), 2.0);   // ⌈2⌉ = 2nd exactly
  std::vector<double> hundred;
  for (int i = 1; i <= 100; ++i) hundred.push_back(i % 2 ? -i : i);
  hundred.push_back(std::nan(""));
  hundred.push_back(INFINITY);
  EXPECT_EQ(rtest::abs_quantile(hundred, 0.95), 95.0);  // 100 finite values: the 95th
  EXPECT_TRUE(std::isnan(rtest::abs_quantile({NAN}, 0.95)));
}

}  // namespace
}  // namespace gearmc::rtest
