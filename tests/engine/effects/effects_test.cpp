// Tests of the measurement effects (engine/effects): each effect against its analytic case,
// closed-form signatures against numerical differentiation of apply(), the chain's physical
// order and reproducibility, P2's qualification strategies against P2's figures, and the
// `effects:` section's bad-input messages.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <numbers>
#include <vector>

#include "engine/effects/effect_config.h"
#include "engine/effects/effects.h"
#include "engine/effects/probe_dynamics.h"
#include "engine/effects/probe_lobing.h"
#include "engine/plan/probing_grid.h"
#include "tests/support/p1_fixtures.h"

namespace gearmc {
namespace {

constexpr double kPi = std::numbers::pi;

EffectParameter fixed(double v) {
  EffectParameter p;
  p.value = v;
  return p;
}

// Every planned point of P1's gear (N 10, M 5, 5 % margins, all teeth, both flanks) as a
// PointContext in probing order (tooth by tooth, L then R).
std::vector<PointContext> p1_points() {
  const InvoluteGear gear = testing_support::p1_gear();
  ProbingGridSpec spec;  // defaults: P1's grid
  std::vector<PointContext> points;
  for (int tooth = 1; tooth <= gear.teeth(); ++tooth) {
    for (FlankSide side : {FlankSide::kLeft, FlankSide::kRight}) {
      for (const PlannedPoint& q : plan_flank(gear, spec, tooth, side)) {
        PointContext c;
        c.p = q.point;
        c.n = q.normal;
        c.contact_normal = q.normal;
        c.azimuth_rad = std::atan2(-q.normal.y(), -q.normal.x());
        c.tooth = tooth;
        c.side = side;
        c.order = static_cast<int>(points.size());
        points.push_back(c);
      }
    }
  }
  for (PointContext& c : points) c.sequence_length = static_cast<int>(points.size());
  return points;
}

double reading_change(const MeasurementEffect& effect, const PointContext& point,
                      const std::vector<double>& values, std::uint64_t noise_seed = 3) {
  const Eigen::Vector3d start = point.p + point.stylus_radius_mm * point.n;
  Eigen::Vector3d c = start;
  RandomStream rng = point_effect_stream(noise_seed, 0, point.order);
  effect.apply(point, values, c, rng);
  return reading_um(point, c) - reading_um(point, start);
}

TEST(Effects, PureScaleChangesEveryReadingByCentreDotNormalTimesS) {
  // Isotropic scale s: c -> c (1 + s), so the reading changes by 1000 (c·n) s µm (c in mm).
  const double s_ppm = 10.0;
  ScaleEffect scale(fixed(s_ppm), fixed(s_ppm), fixed(s_ppm));
  for (const PointContext& point : p1_points()) {
    const Eigen::Vector3d c = point.p + point.stylus_radius_mm * point.n;
    const double expected = 1000.0 * c.dot(point.n) * s_ppm * 1e-6;
    EXPECT_NEAR(reading_change(scale, point, {s_ppm, s_ppm, s_ppm}), expected, 1e-9);
  }
}

TEST(Effects, ThermalExpansionIsAScaleOfAlphaTimesDeltaT) {
  // Steel gear 1 K warm, scales at 20 °C: scale factor 11.5 ppm (CTE of steel, 11.5e-6 /K).
  ThermalExpansionEffect thermal(fixed(1.0), fixed(0.0), fixed(11.5), fixed(0.0));
  for (const PointContext& point : p1_points()) {
    const Eigen::Vector3d c = point.p + point.stylus_radius_mm * point.n;
    EXPECT_NEAR(reading_change(thermal, point, {1.0, 0.0, 11.5, 0.0}),
                1000.0 * c.dot(point.n) * 11.5e-6, 1e-9);
  }
  // Equal temperatures and CTEs of gear and scale cancel.
  EXPECT_NEAR(reading_change(thermal, p1_points()[7], {2.0, 2.0, 11.5, 11.5}), 0.0, 1e-12);
}

TEST(Effects, LobingWithoutQualificationReproducesItsHarmonicAtTheGearsAzimuths) {
  // P2's probe: 6 lobes, ±0.75 µm. Without compensation each reading is −p(φ) (the centre is
  // recorded p further along −n). A least-squares fit of cos/sin(6φ) over P1's approach
  // azimuths must give back the amplitude and phase.
  ProbeLobingEffect lobing(fixed(0.0), {6}, {fixed(0.75), fixed(20.0)}, fixed(0.0), {});
  const std::vector<double> v = {0.0, 0.75, 20.0, 0.0};
  double scc = 0, sss = 0, scs = 0, syc = 0, sys = 0;
  for (const PointContext& point : p1_points()) {
    const double r = reading_change(lobing, point, v);
    EXPECT_NEAR(r, -0.75 * std::cos(6.0 * (point.azimuth_rad - 20.0 * kPi / 180.0)), 1e-9);
    const double c = std::cos(6.0 * point.azimuth_rad), s = std::sin(6.0 * point.azimuth_rad);
    scc += c * c, sss += s * s, scs += c * s, syc += -r * c, sys += -r * s;
  }
  const double det = scc * sss - scs * scs;
  const double A = (syc * sss - sys * scs) / det, B = (sys * scc - syc * scs) / det;
  EXPECT_NEAR(std::hypot(A, B), 0.75, 1e-9);
  EXPECT_NEAR(std::atan2(B, A) / 6.0 * 180.0 / kPi, 20.0, 1e-7);
}

TEST(Effects, LobingHarmonicComponentsRoundTripAndSumToItsValue) {
  // a cos(k(φ − φ_k)) = a cos(kφ_k) cos kφ + a sin(kφ_k) sin kφ (angle-difference identity), and
  // from_components inverts the components with φ_k reduced to [0, 360/k)°: 100° of a 3-fold
  // harmonic is 100° − 0·120°, and −30° of a 6-fold one is 30° (−30° + 60°).
  for (const LobingHarmonic h : {LobingHarmonic{3, 1.5, 100.0}, LobingHarmonic{6, 0.75, -30.0}}) {
    const double c = h.cos_component_um(), s = h.sin_component_um();
    for (double phi = 0.0; phi < 6.3; phi += 0.7) {
      EXPECT_NEAR(h.value_um(phi), c * std::cos(h.order * phi) + s * std::sin(h.order * phi),
                  1e-12);
    }
    const LobingHarmonic back = LobingHarmonic::from_components(h.order, c, s);
    EXPECT_EQ(back.order, h.order);
    EXPECT_NEAR(back.amplitude_um, h.amplitude_um, 1e-12);
    EXPECT_NEAR(back.phase_deg, h.order == 3 ? 100.0 : 30.0, 1e-9);
  }
}

TEST(Effects, Mean6QualificationLeavesP2sResidualOnASixLobeProbe) {
  // P2 variant 1 on a 6-lobe ±0.75 µm probe whose maxima lie at the qualification start (+Y):
  // one 3-point set hits three maxima, the rotated set three minima, so ΔR = p0 and the
  // residual over all directions is ±0.75 µm (P2: "here ±0.75 µm").
  LobingModel model{2.0, {{6, 0.75, 90.0}}};
  ProbeQualificationSpec spec{ProbeQualification::kMean6, SixDirectionUse::kNearest, 90.0};
  EXPECT_NEAR(qualification_correction_um(model, spec, 0.3), 2.0, 1e-12);
  double lo = 1e9, hi = -1e9;
  for (int i = 0; i < 3600; ++i) {
    const double phi = 2.0 * kPi * i / 3600.0;
    const double r = model.pretravel_at(phi) - qualification_correction_um(model, spec, phi);
    lo = std::min(lo, r), hi = std::max(hi, r);
  }
  EXPECT_NEAR(hi, 0.75, 1e-9);
  EXPECT_NEAR(lo, -0.75, 1e-9);
}

TEST(Effects, SixDirectionsAreExactAtTheirDirectionsAndPerDirectionEverywhere) {
  LobingModel model{1.0, {{3, 1.5, 10.0}, {6, 0.4, 50.0}}};
  ProbeQualificationSpec six{ProbeQualification::kSixDirections, SixDirectionUse::kInterpolated,
                             90.0};
  const std::vector<double> d = qualification_directions_rad(six);
  // P2 variant 2: 90°, 210°, 330° (period 2π/3, one on +Y) and +X, −X, −Y: six directions.
  ASSERT_EQ(d.size(), 6u);
  for (double expected_deg : {0.0, 90.0, 180.0, 210.0, 270.0, 330.0}) {
    EXPECT_TRUE(std::any_of(d.begin(), d.end(), [&](double a) {
      return std::abs(a - expected_deg * kPi / 180.0) < 1e-12;
    })) << expected_deg;
  }
  for (double a : d) {
    EXPECT_NEAR(qualification_correction_um(model, six, a), model.pretravel_at(a), 1e-12);
    six.use = SixDirectionUse::kNearest;
    EXPECT_NEAR(qualification_correction_um(model, six, a + 1e-6), model.pretravel_at(a), 1e-12);
    six.use = SixDirectionUse::kInterpolated;
  }
  // Interpolated: halfway between 0° and 90° is the mean of the two.
  EXPECT_NEAR(qualification_correction_um(model, six, kPi / 4.0),
              0.5 * (model.pretravel_at(0.0) + model.pretravel_at(kPi / 2.0)), 1e-12);
  ProbeQualificationSpec per{ProbeQualification::kPerDirection, SixDirectionUse::kNearest, 0.0};
  EXPECT_NEAR(qualification_correction_um(model, per, 1.234), model.pretravel_at(1.234), 1e-12);
}

TEST(Effects, OppositeDirectionDifferencesMatchP2WithItsRepeatability) {
  // P2: a 6-lobe characteristic is symmetric under φ -> φ + π, so opposite readings differ by
  // repeatability alone; over 36 pairs P2 found mean |difference| 0.1 µm and a 99.73 % interval
  // ±0.3 µm. With unidirectional repeatability σ = 0.07 µm the difference is N(0, 2σ²): mean
  // |d| = 2σ/√π = 0.079 µm, 3·√2·σ = 0.30 µm. Simulated over 36 000 pairs (1000 × P2's 36) the
  // mean |d| must be within 2 % of 0.079 (its standard error is 0.4 %) and the 99.73 % quantile
  // of |d| within 5 % of 0.297.
  const double sigma = 0.07;
  ProbeLobingEffect lobing(fixed(0.0), {6}, {fixed(0.75), fixed(0.0)}, fixed(sigma), {});
  const std::vector<double> v = {0.0, 0.75, 0.0, sigma};
  std::vector<double> d;
  for (int k = 0; k < 36000; ++k) {
    PointContext a, b;
    a.azimuth_rad = 2.0 * kPi * (k % 36) / 36.0;
    a.n = -Eigen::Vector3d(std::cos(a.azimuth_rad), std::sin(a.azimuth_rad), 0.0);
    a.p = -50.0 * a.n;
    b = a;
    b.azimuth_rad = a.azimuth_rad + kPi;
    b.n = -a.n;
    b.p = -50.0 * b.n;
    a.order = 2 * k;
    b.order = 2 * k + 1;
    d.push_back(std::abs(reading_change(lobing, a, v) - reading_change(lobing, b, v)));
  }
  double mean = 0.0;
  for (double x : d) mean += x / static_cast<double>(d.size());
  EXPECT_NEAR(mean, 2.0 * sigma / std::sqrt(kPi), 0.02 * 2.0 * sigma / std::sqrt(kPi));
  std::sort(d.begin(), d.end());
  const double q = d[static_cast<std::size_t>(0.9973 * static_cast<double>(d.size()))];
  EXPECT_NEAR(q, 3.0 * std::sqrt(2.0) * sigma, 0.05 * 3.0 * std::sqrt(2.0) * sigma);
}

TEST(Effects, StepQuantizationErrorIsUniformOnZeroToQEvenOnAPerfectFlank) {
  // The grid's phase is drawn at every point (effects.h), so the latch delay u is U(0, q) also
  // when every travel s is the same (a perfect master flank: offsets 0) and when the travels
  // spread by ±5 µm. Kolmogorov–Smirnov against U(0, 1) at α = 1e-3 (critical D = 1.95/√n,
  // Kolmogorov's asymptotic law) on P1's 4800 points, both cases. apply_mean moves by the mean
  // q/2 and point_law says −U(0, q): the sample mean of the reading is −q/2 within 4 standard
  // errors q/√(12 n).
  const double q_um = 1.0;
  StepQuantizationEffect step(fixed(q_um), 2.0);
  for (const double spread_um : {0.0, 5.0}) {
    std::vector<double> u;
    RandomStream offsets(11, 0, StreamPurpose::kEffectNoise, 999);
    double mean_reading = 0.0;
    for (const PointContext& point : p1_points()) {
      const Eigen::Vector3d start =
          point.p +
          point.n * (point.stylus_radius_mm + 1e-3 * offsets.uniform(-spread_um, spread_um));
      Eigen::Vector3d c = start;
      RandomStream rng = point_effect_stream(1, 0, point.order);
      step.apply(point, std::vector<double>{q_um}, c, rng);
      const double moved_um = -1000.0 * (c - start).dot(point.n);
      EXPECT_GE(moved_um, -1e-9);
      EXPECT_LT(moved_um, q_um + 1e-9);
      u.push_back(moved_um / q_um);
      mean_reading -= moved_um;
    }
    const double n = static_cast<double>(u.size());
    mean_reading /= n;
    EXPECT_NEAR(mean_reading, -0.5 * q_um, 4.0 * q_um / std::sqrt(12.0 * n));
    std::sort(u.begin(), u.end());
    double D = 0.0;
    for (std::size_t i = 0; i < u.size(); ++i) {
      const double rank = static_cast<double>(i);
      D = std::max({D, std::abs(u[i] - rank / n), std::abs((rank + 1.0) / n - u[i])});
    }
    EXPECT_LT(D, 1.95 / std::sqrt(n)) << "spread " << spread_um << " µm";
  }
  const PointContext point = p1_points().front();
  Eigen::Vector3d c = point.p + point.stylus_radius_mm * point.n;
  const Eigen::Vector3d start = c;
  step.apply_mean(point, std::vector<double>{q_um}, c);
  EXPECT_NEAR(1000.0 * (c - start).dot(point.n), -0.5 * q_um, 1e-9);  // mm coordinates ~70
  const PointLaw law = step.point_law(std::vector<double>{q_um});
  ASSERT_EQ(law.uniform_widths_um.size(), 1u);
  EXPECT_DOUBLE_EQ(law.uniform_widths_um[0], q_um);
  EXPECT_DOUBLE_EQ(law.variance_um2(), q_um * q_um / 12.0);  // variance of U(0, q)
}

TEST(Effects, PointLawsOfTheChainAddAndTheMeanOmitsTheRandomParts) {
  // noise σ 0.3 (isotropic: σ² along n), probe repeatability 0.2, step 1 µm: variance
  // 0.09 + 0.04 + 1/12 (independent parts add). apply_mean of the chain equals the lobing
  // residual − q/2 (noise and repeatability average to 0).
  EffectChain chain;
  chain.add(std::make_unique<NoiseEffect>(fixed(0.3)));
  chain.add(std::make_unique<StepQuantizationEffect>(fixed(1.0), 2.0));
  auto lobing = std::make_unique<ProbeLobingEffect>(
      fixed(0.0), std::vector<int>{3}, std::vector<EffectParameter>{fixed(1.5), fixed(0.0)},
      fixed(0.2), ProbeQualificationSpec{});
  const ProbeLobingEffect& lobing_ref = *lobing;
  chain.add(std::move(lobing));
  const EffectValues values = chain.nominal();
  const PointLaw law = chain.point_law(values);
  EXPECT_NEAR(law.variance_um2(), 0.09 + 0.04 + 1.0 / 12.0, 1e-12);
  EXPECT_NEAR(law.mean_um(), -0.5, 1e-12);
  for (const PointContext& point : p1_points()) {
    if (point.order % 500 != 0) continue;
    const Eigen::Vector3d c0 = point.p + point.stylus_radius_mm * point.n;
    const Eigen::Vector3d c = chain.apply_mean(point, values, c0);
    const int e = chain.find("probe_lobing");
    const double expected =
        -lobing_ref.residual_um(values[static_cast<std::size_t>(e)], point.azimuth_rad) - 0.5;
    EXPECT_NEAR(reading_um(point, c), expected, 1e-9);
  }
}

TEST(Effects, DriftGrowsLinearlyOverTheSequence) {
  DriftEffect drift(fixed(1.0), fixed(0.0), fixed(0.0));
  const std::vector<PointContext> points = p1_points();
  for (const PointContext& point : points) {
    const double f = static_cast<double>(point.order) / static_cast<double>(points.size() - 1);
    EXPECT_NEAR(reading_change(drift, point, {1.0, 0.0, 0.0}), f * point.n.x(), 1e-9);
  }
}

TEST(Effects, EccentricityAndStylusRadiusAreTranslationsAlongTheirVectors) {
  EccentricityEffect ecc(fixed(5.0), fixed(-2.0));
  StylusRadiusEffect radius(fixed(0.5));
  for (const PointContext& point : p1_points()) {
    EXPECT_NEAR(reading_change(ecc, point, {5.0, -2.0}), 5.0 * point.n.x() - 2.0 * point.n.y(),
                1e-9);
    EXPECT_NEAR(reading_change(radius, point, {0.5}), -0.5, 1e-9);
  }
}

TEST(Effects, ClockingTurnsTheGearAndMovesEachFlankByPlusMinusBaseRadiusTimesAngle) {
  // A turn θ about the gear axis moves a point of an involute flank along the flank's normal by
  // θ r_b (the involute's normal is tangent to the base circle at distance r_b from the axis),
  // left and right flanks in opposite directions; r_b = m z cos α / 2 from P1's data (m 5.6,
  // z 24, α 20°), not from gearmc. The stylus centre turns exactly: |c| and c_z are kept.
  const double rb = 0.5 * 5.6 * 24.0 * std::cos(20.0 * kPi / 180.0);
  const double angle_urad = 20.0;
  ClockingEffect clocking(fixed(angle_urad));
  for (const PointContext& point : p1_points()) {
    const double expected = rb * angle_urad * 1e-3;  // mm × µrad → µm
    const double change = reading_change(clocking, point, {angle_urad});
    // Beyond first order the turn moves c by (cos θ − 1) c along itself: θ²|c|/2 ≤ 2e-5 µm here.
    EXPECT_NEAR(std::abs(change), expected, 3e-5) << point.tooth;
    const Eigen::Vector3d start = point.p + point.stylus_radius_mm * point.n;
    Eigen::Vector3d c = start;
    RandomStream rng = point_effect_stream(3, 0, point.order);
    const std::vector<double> values = {angle_urad};
    clocking.apply(point, values, c, rng);
    EXPECT_NEAR(c.norm(), start.norm(), 1e-12);
    EXPECT_EQ(c.z(), start.z());
    EXPECT_NEAR(std::atan2(c.y(), c.x()) - std::atan2(start.y(), start.x()), angle_urad * 1e-6,
                1e-12);
  }
  // The two flanks of a tooth move in opposite directions.
  const std::vector<PointContext> points = p1_points();
  const auto first = [&](FlankSide side) {
    return *std::find_if(points.begin(), points.end(),
                         [&](const PointContext& c) { return c.side == side; });
  };
  EXPECT_LT(reading_change(clocking, first(FlankSide::kLeft), {angle_urad}) *
                reading_change(clocking, first(FlankSide::kRight), {angle_urad}),
            0.0);
}

TEST(Effects, ClosedFormSignaturesAgreeWithNumericalDerivatives) {
  // The closed forms overridden by the linear effects against the base class's central
  // differences of apply(); agreement to 1e-6 µm per unit (differences of ~1e-3 µm readings
  // on coordinates of ~80 mm lose about 1e-14 mm to rounding).
  std::vector<std::unique_ptr<MeasurementEffect>> effects;
  effects.push_back(std::make_unique<EccentricityEffect>(fixed(3.0), fixed(1.0)));
  effects.push_back(std::make_unique<StylusRadiusEffect>(fixed(0.4)));
  effects.push_back(std::make_unique<ScaleEffect>(fixed(5.0), fixed(-3.0), fixed(2.0)));
  effects.push_back(std::make_unique<SquarenessEffect>(fixed(20.0), fixed(5.0), fixed(-7.0)));
  effects.push_back(std::make_unique<DriftEffect>(fixed(1.0), fixed(-1.0), fixed(0.5)));
  // Linear to first order only (a turn): its closed form is the derivative at 0, here at 1 µrad
  // off by θ (c·n)·1e-3 ≈ 4e-8 µm per µrad.
  effects.push_back(std::make_unique<ClockingEffect>(fixed(1.0)));
  const std::vector<PointContext> points = p1_points();
  for (const auto& effect : effects) {
    std::vector<double> values;
    for (const auto& p : effect->parameters()) values.push_back(p.value);
    for (std::size_t k = 0; k < points.size(); k += 97) {
      PointContext point = points[k];
      point.p.z() = 10.0 + 0.3 * static_cast<double>(k % 50);  // exercise the z terms
      std::vector<double> closed(values.size()), numeric(values.size());
      effect->signature(point, values, closed);
      effect->MeasurementEffect::signature(point, values, numeric);
      for (std::size_t i = 0; i < values.size(); ++i) {
        EXPECT_NEAR(closed[i], numeric[i], 1e-6) << effect->name() << " parameter " << i;
      }
    }
  }
}

TEST(Effects, ChainAppliesInPhysicalOrderAndDrawsReproducibly) {
  EffectChain chain;
  EffectParameter noisy;
  noisy.law = EffectParameter::Law::kUniform;
  noisy.lo = -5.0;
  noisy.hi = 5.0;
  chain.add(std::make_unique<NoiseEffect>(fixed(0.3)));
  chain.add(std::make_unique<ScaleEffect>(noisy, fixed(0.0), fixed(0.0)));
  chain.add(std::make_unique<EccentricityEffect>(fixed(2.0), fixed(0.0)));
  ASSERT_EQ(chain.size(), 3u);
  EXPECT_EQ(chain.effect(0).name(), "eccentricity");  // workpiece first
  EXPECT_EQ(chain.effect(1).name(), "scale");         // then machine
  EXPECT_EQ(chain.effect(2).name(), "noise");         // noise last
  const EffectValues a = chain.draw(7, 3), b = chain.draw(7, 3), c = chain.draw(7, 4);
  EXPECT_EQ(a, b);
  EXPECT_NE(a[1][0], c[1][0]);
  EXPECT_GE(a[1][0], -5.0);
  EXPECT_LE(a[1][0], 5.0);
  // Contributions add up to the total change of the reading.
  const PointContext point = p1_points()[123];
  const Eigen::Vector3d start = point.p + point.stylus_radius_mm * point.n;
  RandomStream rng = point_effect_stream(7, 3, point.order);
  std::vector<double> contributions(3);
  const Eigen::Vector3d recorded = chain.apply(point, a, start, rng, contributions);
  EXPECT_NEAR(contributions[0] + contributions[1] + contributions[2],
              reading_um(point, recorded) - reading_um(point, start), 1e-9);
  EXPECT_NEAR(contributions[0], 2.0 * point.n.x(), 1e-9);
}

EffectChain parse(const std::string& yaml) {
  return parse_effects(parse_yaml_document(yaml, "e.yaml"));
}

TEST(EffectConfig, ReadsEveryEffectWithLawsAndSkipsDisabledOnes) {
  const EffectChain chain = parse(R"(
probe_lobing:
  pretravel_um: 1.0
  harmonics:
    - {order: 6, amplitude_um: 0.75, phase_deg: 90}
  repeatability_um: 0.07
  calibration: mean6
scale: {x_ppm: {uniform: [-5, 5]}, y_ppm: {normal: [0, 2]}}
noise: {sigma_um: 0.3}
drift: {enabled: false, x_um: 1}
clocking: {angle_urad: {normal: [0, 10]}}
)");
  ASSERT_EQ(chain.size(), 4u);
  // A set-up effect acts first (EffectStage::kWorkpiece), the others in scenario order.
  EXPECT_EQ(chain.effect(0).name(), "clocking");
  EXPECT_EQ(chain.effect(0).parameters()[0].name, "angle_urad");
  EXPECT_EQ(chain.effect(0).parameters()[0].law, EffectParameter::Law::kNormal);
  EXPECT_EQ(chain.effect(1).name(), "probe_lobing");
  EXPECT_EQ(chain.effect(1).parameters().size(), 4u);  // p0, a6, φ6, repeatability
  EXPECT_EQ(chain.effect(1).parameters()[1].name, "amplitude_6_um");
  EXPECT_EQ(chain.effect(2).parameters()[0].law, EffectParameter::Law::kUniform);
  EXPECT_EQ(chain.effect(2).parameters()[1].law, EffectParameter::Law::kNormal);
  EXPECT_EQ(chain.find("drift"), -1);
}

void expect_error(const std::string& yaml, const std::string& message);

TEST(EffectConfig, ProbeLobingFromTheCvodeProbeModel) {
  // from_probe_model: p0 and the orders 3, 6, 9 are those of ProbeDynamics::lobing_harmonics
  // for the same probe and speed (the default TP20-like probe: p0 23.66 µm, a_3 6.57 µm at
  // 90°, engine/effects/probe_dynamics.h); orders that are not multiples of 3 are dropped.
  const EffectChain chain = parse(R"(
probe_lobing:
  from_probe_model: {stylus_length_mm: 20, speed_mm_s: 2, directions: 72, max_order: 9}
  calibration: mean6
)");
  ASSERT_EQ(chain.size(), 1u);
  const auto& lobing = dynamic_cast<const ProbeLobingEffect&>(chain.effect(0));
  std::vector<double> values;
  for (const auto& p : lobing.parameters()) values.push_back(p.value);
  const LobingModel model = lobing.model(values);
  ProbeDynamicsParameters probe;
  probe.stylus_length_mm = 20.0;
  const LobingHarmonics h = ProbeDynamics(probe).lobing_harmonics(72, 2.0, 9);
  EXPECT_DOUBLE_EQ(model.pretravel_um, h.p0_um);
  ASSERT_EQ(model.harmonics.size(), 3u);
  for (const LobingHarmonic& k : model.harmonics) {
    EXPECT_EQ(k.order % 3, 0);
    EXPECT_DOUBLE_EQ(k.amplitude_um,
                     h.harmonics[static_cast<std::size_t>(k.order - 1)].amplitude_um);
  }
  EXPECT_GT(model.harmonics[0].amplitude_um, model.harmonics[1].amplitude_um);  // 3-lobed
  EXPECT_NEAR(model.harmonics[0].phase_deg, 90.0, 1e-6);  // towards the +Y leg
  expect_error("probe_lobing:\n  pretravel_um: 1\n  from_probe_model: {}\n",
               "e.yaml:2:17: probe_lobing.pretravel_um: got '1', expected nothing: "
               "from_probe_model gives p0 and the harmonics");
}

void expect_error(const std::string& yaml, const std::string& message) {
  try {
    parse(yaml);
    ADD_FAILURE() << "no error for:\n" << yaml;
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), message);
  }
}

TEST(EffectConfig, BadInputNamesFileLineColumnKeyAndExpectation) {
  expect_error("scael: {x_ppm: 1}\n",
               "e.yaml:1:1: scael: got 'scael', expected a known key (the top level has: "
               "probe_lobing, stylus_radius, tip_form, scale, squareness, thermal_expansion, "
               "drift, step_quantization, eccentricity, clocking, noise, probe_warmup, straightness, "
               "artefact_form, scale_resolution, empirical, rotary_table, stylus_bending); did "
               "you mean 'scale'?");
  // A negative σ is no nm slip (that hint is for values above the range): no hint.
  expect_error("noise: {sigma_um: -1}\n",
               "e.yaml:1:19: noise.sigma_um: got '-1', expected a number from 0 to 100 µm "
               "(probing noise σ 0.1–0.5 µm)");
  expect_error("noise: {sigma_um: 300}\n",
               "e.yaml:1:19: noise.sigma_um: got '300', expected a number from 0 to 100 µm "
               "(probing noise σ 0.1–0.5 µm); a value in nm? (300 nm = 0.3 µm)");
  expect_error("scale: {x_ppm: {uniform: [3, 1]}}\n",
               "e.yaml:1:26: scale.x_ppm.uniform: got '[3, 1]', expected [lo, hi] with lo <= hi");
  expect_error("probe_lobing: {calibration: mean7}\n",
               "e.yaml:1:29: probe_lobing.calibration: got 'mean7', expected one of none, mean6, "
               "six_directions, per_direction; did you mean 'mean6'?");
}

}  // namespace
}  // namespace gearmc
