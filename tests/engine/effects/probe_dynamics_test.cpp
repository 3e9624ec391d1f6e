// The physical touch-trigger probe model (engine/effects/probe_dynamics) against independent
// answers: the stylus constants against hand formulas (Euler–Bernoulli, Hertz); the seat's
// trigger force against the statics of a three-leg seat; the CVODE pre-travel against its
// closed-form quasi-static limit and its first-order speed correction; the lobing harmonics
// against the Fourier coefficients of the seat law (closed form) and against the quasi-static
// samples; the 3-fold symmetry, P2's "up to 1:2" between opposite directions, the growth with
// stylus length and with speed, a CVODE root in every direction, and parameter checks.
#include "engine/effects/probe_dynamics.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>
#include <vector>

namespace gearmc {
namespace {

constexpr double kPi = std::numbers::pi;

// 2ζ/ω (s): the first-order lag of the trigger caused by the stylus damping force c ẇ ≈ c v
// reaching the seat (derivation in probe_dynamics.cpp).
double damping_lag_s(const ProbeDynamics& probe) {
  return 2.0 * probe.parameters().stylus_damping_ratio /
         (2.0 * kPi * probe.stylus().natural_frequency_hz);
}

// Fourier analysis of samples at φ_j = 2πj/n, written out here independently of
// ProbeDynamics::lobing_harmonics: returns (A_k, B_k) with p ≈ p0 + Σ A_k cos kφ + B_k sin kφ.
struct Coefficients {
  double a, b;
};
Coefficients fourier(const std::vector<double>& samples, int k) {
  const int n = static_cast<int>(samples.size());
  Coefficients c{0, 0};
  for (int j = 0; j < n; ++j) {
    const double phi = 2 * kPi * j / n;
    c.a += 2.0 / n * samples[j] * std::cos(k * phi);
    c.b += 2.0 / n * samples[j] * std::sin(k * phi);
  }
  return c;
}

// The default probe at 2 mm/s, 24 directions (15°), orders 1–9: computed once for several
// tests (24 CVODE solves).
const LobingHarmonics& default_lobing() {
  static const LobingHarmonics lobing =
      ProbeDynamics(ProbeDynamicsParameters{}).lobing_harmonics(24, 2.0, 9);
  return lobing;
}

TEST(ProbeDynamics, StylusConstantsMatchHandFormulas) {
  const ProbeDynamics probe{ProbeDynamicsParameters{}};
  const auto& s = probe.stylus();
  // Tungsten-carbide stem Ø0.7 × 20 mm, E 630 GPa: I = π d⁴/64 = 0.0117860 mm⁴,
  // k_b = 3EI/ℓ³ = 3 · 630e3 · 0.0117859 / 8000 = 2.78441 N/mm (Euler–Bernoulli cantilever).
  EXPECT_NEAR(s.bending_stiffness_n_per_mm, 2.78441, 1e-5);
  // k_a = EA/ℓ = 630e3 · 0.384845 / 20 = 12122.6 N/mm.
  EXPECT_NEAR(s.axial_stiffness_n_per_mm, 12122.6, 0.1);
  // Ruby (373 GPa, 0.28) on steel (210 GPa, 0.30): 1/E* = 0.9216/373 + 0.91/210 → E* =
  // 146.970 GPa; K_H = (4/3) E* √0.5 mm = 1.38565e5 N/mm^1.5 (Johnson 1985, §4.2).
  EXPECT_NEAR(s.contact_modulus_gpa, 146.970, 1e-3);
  EXPECT_NEAR(s.hertz_constant, 4.0 / 3.0 * 146.970e3 * std::sqrt(0.5), 1.0);
  // m = ρ_ruby π D³/6 + (33/140) ρ_WC A ℓ = 2.04204e-6 + 2.72140e-5 = 2.92561e-5 kg.
  EXPECT_NEAR(s.effective_tip_mass_kg, 2.92561e-5, 1e-10);
}

TEST(ProbeDynamics, TriggerForceFollowsTheStaticsOfAThreeLegSeat) {
  // Reference: moment balance of the seat (derivation in probe_dynamics.cpp): the preload's
  // lever arm about the pivot line (through the two front legs), seen along the approach, is
  // (r_s/2)/cos Δ, so F_trig = F_s r_s / L towards a leg (Δ = π/3) and F_s r_s / (2L)
  // opposite a leg (Δ = 0).
  ProbeDynamicsParameters p;
  const ProbeDynamics probe{p};
  const double lever = p.seat_height_mm + p.stylus_length_mm;  // 28.75 mm
  const double leg = p.first_leg_azimuth_rad;
  EXPECT_NEAR(probe.trigger_force_n(leg), p.seat_preload_n * p.seat_radius_mm / lever, 1e-14);
  EXPECT_NEAR(probe.trigger_force_n(leg + kPi), p.seat_preload_n * p.seat_radius_mm / (2 * lever),
              1e-14);
  // The derivation of the default seat height: F_0 = 0.08 N with a 10 mm stylus.
  p.stylus_length_mm = 10;
  EXPECT_NEAR(ProbeDynamics(p).trigger_force_n(leg + kPi), 0.08, 1e-12);
  // Period 2π/3, and η scales the force by (1 − η).
  for (double phi = 0; phi < 2 * kPi; phi += 0.1) {
    EXPECT_NEAR(probe.trigger_force_n(phi), probe.trigger_force_n(phi + 2 * kPi / 3), 1e-14);
  }
  ProbeDynamicsParameters q;
  q.trigger_unload_fraction = 0.25;
  EXPECT_NEAR(ProbeDynamics(q).trigger_force_n(0.3), 0.75 * probe.trigger_force_n(0.3), 1e-14);
}

TEST(ProbeDynamics, CvodeTendsToTheQuasiStaticClosedFormAtLowSpeed) {
  // Reference: p_qs = F_trig/k_b + (F_trig/K_H)^(2/3) (force balance, exact for v → 0).
  // Tolerance 1e-3 µm at v = 0.05 mm/s, because the remaining differences are the damping lag
  // (2ζ/ω) v = 2.1e-4 µm, the Hunt–Crossley contact factor (~2e-5 µm) and the solver
  // (< 1e-7 µm); a wrong force, stiffness or trigger condition would be off by ≥ 0.05 µm.
  const ProbeDynamics probe{ProbeDynamicsParameters{}};
  for (double phi : {0.0, 0.4, 1.0, kPi / 2, 2.0, kPi / 2 + kPi, 5.5}) {
    const double qs = probe.quasi_static_pretravel_um(phi);
    EXPECT_NEAR(probe.pretravel_um(phi, 0.05), qs, 1e-3) << "phi " << phi;
  }
  // The closed form itself, opposite a leg: F = 0.0521739 N, bending F/k_b = 18.73784 µm,
  // indentation (F/K_H)^(2/3) = 0.05214 µm (hand calculation with the constants above).
  EXPECT_NEAR(probe.quasi_static_pretravel_um(kPi / 2 + kPi), 18.73784 + 0.05214, 1e-4);
  // First-order speed correction: dp/dv = −(2ζ/ω)(1 − k_b/(k_b + k_c)) ≈ −2ζ/ω (k_c ≈ 700 k_b
  // at the trigger): −4.10e-3 µm per mm/s; checked to 2 %.
  const double slope = probe.pretravel_um(1.0, 2.0) - probe.pretravel_um(1.0, 1.0);  // per mm/s
  EXPECT_NEAR(slope, -1e3 * damping_lag_s(probe), 0.02 * 1e3 * damping_lag_s(probe));
}

TEST(ProbeDynamics, LobingIsThreeFoldWithMaximaTowardsTheLegs) {
  const auto& lobing = default_lobing();
  ASSERT_EQ(lobing.harmonics.size(), 9u);
  const double a3 = lobing.harmonics[2].amplitude_um;
  double others_sq = 0;
  for (const auto& h : lobing.harmonics) {
    if (h.order == 3) continue;
    EXPECT_LT(h.amplitude_um, a3) << "order " << h.order;
    others_sq += h.amplitude_um * h.amplitude_um;
    // A 2π/3-periodic function has only orders 3, 6, 9, …: the others vanish to solver
    // tolerance (pre-travel error < 1e-7 µm).
    if (h.order % 3 != 0) {
      EXPECT_LT(h.amplitude_um, 1e-5) << "order " << h.order;
    }
  }
  // k = 3 carries most of the non-constant part: for the seat law P/cos Δ, a_3²/2 is 82.7 % of
  // the variance of p(φ) (continuous series; 84.6 % of orders 3, 6, 9). Sampled at 24
  // directions the orders alias (n ± k onto k) and the share of a_3² among the orders ≤ 9 is
  // 77.3 % (closed form, sampled alike; 81.7 % at 36, 83.9 % at 72 directions); a_3 > 2 a_6.
  EXPECT_GT(a3 * a3 / (a3 * a3 + others_sq), 0.75);
  EXPECT_GT(a3, 2 * lobing.harmonics[5].amplitude_um);
  // Maximum pre-travel towards a leg (the largest trigger force): φ_3 = θ0 = π/2.
  EXPECT_NEAR(lobing.harmonics[2].phase_deg, 90.0, 1e-6 * 180.0 / kPi);
  // p(φ + 2π/3) = p(φ) to solver tolerance: 24 samples, a shift of 8.
  for (int j = 0; j < 24; ++j) {
    EXPECT_NEAR(lobing.pretravel_um[j], lobing.pretravel_um[(j + 8) % 24], 1e-5) << j;
  }
}

TEST(ProbeDynamics, LobingHarmonicsMatchTheSeatLaw) {
  // (1) The seat law in closed form. With a rigid contact (Hertz term ~1e-4 µm), p(φ) = P /
  // cos Δ(φ), P = F_0/k_b, |Δ| ≤ π/3 around each anti-leg direction. Its Fourier series:
  //   p0  = (3/2π) ∫ P/cos Δ dΔ = (3/π) ln(2 + √3) P
  //   a_3 = (3/π) |∫ P cos 3Δ / cos Δ dΔ| = (3/π) |∫ (2 cos 2Δ − 1) dΔ| P = (2 − 3√3/π) P
  // (integrals over [−π/3, π/3]). Checked on 3600 quasi-static samples, to 1e-3 µm.
  ProbeDynamicsParameters rigid;
  rigid.ball_material.youngs_modulus_gpa = 1e7;
  rigid.workpiece_material.youngs_modulus_gpa = 1e7;
  const ProbeDynamics stiff{rigid};
  const double P = 1e3 * stiff.trigger_force_n(rigid.first_leg_azimuth_rad + kPi) /
                   stiff.stylus().bending_stiffness_n_per_mm;
  std::vector<double> samples(3600);
  double mean = 0;
  for (int j = 0; j < 3600; ++j) {
    samples[j] = stiff.quasi_static_pretravel_um(2 * kPi * j / 3600);
    mean += samples[j] / 3600;
  }
  const Coefficients c3 = fourier(samples, 3);
  EXPECT_NEAR(mean, 3 / kPi * std::log(2 + std::sqrt(3.0)) * P, 1e-3);
  EXPECT_NEAR(std::hypot(c3.a, c3.b), (2 - 3 * std::sqrt(3.0) / kPi) * P, 1e-3);

  // (2) The CVODE harmonics of the default probe at 2 mm/s against the same analysis of the
  // closed-form quasi-static pre-travel at the same 24 directions (same aliasing): the speed
  // only shifts p0 by ≈ −(2ζ/ω) v, the shape agrees to 1e-3 µm.
  const ProbeDynamics probe{ProbeDynamicsParameters{}};
  const auto& lobing = default_lobing();
  std::vector<double> qs(24);
  double qs_mean = 0;
  for (int j = 0; j < 24; ++j) {
    qs[j] = probe.quasi_static_pretravel_um(lobing.azimuth_rad[j]);
    qs_mean += qs[j] / 24;
  }
  const double speed_mm_s = 2.0;  // default_lobing()'s speed
  EXPECT_NEAR(lobing.p0_um, qs_mean - 1e3 * damping_lag_s(probe) * speed_mm_s, 1e-3);
  for (const auto& h : lobing.harmonics) {
    const Coefficients c = fourier(qs, h.order);
    EXPECT_NEAR(h.amplitude_um, std::hypot(c.a, c.b), 1e-3) << "order " << h.order;
  }
}

TEST(ProbeDynamics, OppositeDirectionsDifferUpToOneToTwo) {
  // P2 (docs/sources.md): kinematic probes show up to about 1:2 between opposite directions. Here
  // towards a leg the trigger force is exactly twice the one opposite; the Hertz term
  // (∝ F^(2/3)) keeps the pre-travel ratio just below 2.
  const ProbeDynamics probe{ProbeDynamicsParameters{}};
  const double leg = probe.parameters().first_leg_azimuth_rad;
  const double ratio = probe.pretravel_um(leg, 1.0) / probe.pretravel_um(leg + kPi, 1.0);
  EXPECT_GT(ratio, 1.95);
  EXPECT_LE(ratio, 2.0);
}

TEST(ProbeDynamics, PretravelGrowsWithStylusLength) {
  // Bending ∝ F_trig/k_b ∝ ℓ³/(h + ℓ): strictly increasing (18.78, 46.94, 88.41, 143.26 µm
  // opposite a leg at 2 mm/s); each value is its quasi-static value minus the first-order
  // damping lag (2ζ/ω)v (0.008 µm at 20 mm, 0.050 µm at 50 mm: ω falls with the length), to
  // 3 % of the lag + 1e-3 µm.
  const double speed_mm_s = 2.0;
  double previous = 0;
  for (double length : {20.0, 30.0, 40.0, 50.0}) {
    ProbeDynamicsParameters p;
    p.stylus_length_mm = length;
    const ProbeDynamics probe{p};
    const double phi = p.first_leg_azimuth_rad + kPi;
    const double pre = probe.pretravel_um(phi, speed_mm_s);
    EXPECT_GT(pre, previous) << "length " << length;
    const double lag_um = 1e3 * damping_lag_s(probe) * speed_mm_s;
    EXPECT_NEAR(pre, probe.quasi_static_pretravel_um(phi) - lag_um, 0.03 * lag_um + 1e-3)
        << "length " << length;
    previous = pre;
  }
}

TEST(ProbeDynamics, PretravelVersusSpeed) {
  // Mechanics alone: the stylus damping force reaches the seat, so p(v) = p_qs − (2ζ/ω) v to
  // first order (a slight decrease, −4.1e-3 µm per mm/s here); checked to 3 % up to 8 mm/s.
  const ProbeDynamics bare{ProbeDynamicsParameters{}};
  const double phi = 0.3;
  for (double v : {0.5, 1.0, 2.0, 4.0, 8.0}) {
    const double lag_um = 1e3 * damping_lag_s(bare) * v;
    EXPECT_NEAR(bare.pretravel_um(phi, v), bare.quasi_static_pretravel_um(phi) - lag_um,
                0.03 * lag_um + 1e-4)
        << "v " << v;
  }
  // With a trigger latency t_d the CMM latches t_d·v later: p grows strictly with speed, with
  // slope t_d − 2ζ/ω. t_d = 20 µs is an assumed test value, not a probe specification.
  ProbeDynamicsParameters p;
  p.trigger_latency_s = 20e-6;
  const ProbeDynamics probe{p};
  double previous = 0;
  for (double v : {0.5, 1.0, 2.0, 4.0, 8.0}) {
    const double pre = probe.pretravel_um(phi, v);
    EXPECT_GT(pre, previous) << "v " << v;
    const double expected_slope = 1e3 * (p.trigger_latency_s - damping_lag_s(probe));
    EXPECT_NEAR(pre - probe.quasi_static_pretravel_um(phi), expected_slope * v,
                0.03 * std::abs(expected_slope) * v + 1e-4)
        << "v " << v;
    previous = pre;
  }
}

TEST(ProbeDynamics, CvodeFindsTheTriggerInEveryDirection) {
  // At 2 mm/s (24 directions, shared) and at 0.2 and 20 mm/s (12 directions each; after the
  // impact the tip bounces off the flank by up to ~0.9 µm at 20 mm/s, so the contact force is
  // switched off and on): a root is found, the seat force at the root equals F_trig(φ) to
  // root-finding accuracy, and the pre-travel is positive and finite.
  for (double p : default_lobing().pretravel_um) EXPECT_TRUE(std::isfinite(p) && p > 0);
  const ProbeDynamics probe{ProbeDynamicsParameters{}};
  for (double v : {0.2, 20.0}) {
    for (int j = 0; j < 12; ++j) {
      const double phi = 2 * kPi * (j + 0.5) / 12;
      PretravelSolution s;
      ASSERT_NO_THROW(s = probe.solve(phi, v)) << "phi " << phi << " v " << v;
      EXPECT_NEAR(s.seat_force_n / probe.trigger_force_n(phi), 1.0, 1e-6);
      EXPECT_GT(s.steps, 0);
      EXPECT_TRUE(std::isfinite(s.pretravel_um) && s.pretravel_um > 0);
      EXPECT_NEAR(s.pretravel_um, 1e3 * v * s.trigger_time_s, 1e-9);
    }
  }
}

TEST(ProbeDynamics, InvalidParametersAreRejected) {
  using testing::HasSubstr;
  auto rejects = [](auto change, const char* name) {
    ProbeDynamicsParameters p;
    change(p);
    try {
      ProbeDynamics probe{p};
      ADD_FAILURE() << name << " accepted";
    } catch (const std::invalid_argument& e) {
      EXPECT_THAT(e.what(), HasSubstr(name));
    }
  };
  rejects([](auto& p) { p.stylus_length_mm = -20; }, "stylus_length_mm");
  rejects([](auto& p) { p.stylus_length_mm = std::nan(""); }, "stylus_length_mm");
  rejects([](auto& p) { p.stem_diameter_mm = 0; }, "stem_diameter_mm");
  rejects([](auto& p) { p.stem_diameter_mm = 1.2; }, "stem_diameter_mm");  // ≥ ball
  rejects([](auto& p) { p.ball_diameter_mm = -1; }, "ball_diameter_mm");
  rejects([](auto& p) { p.stem_material.youngs_modulus_gpa = 0; },
          "stem_material.youngs_modulus_gpa");
  rejects([](auto& p) { p.ball_material.poisson_ratio = 0.5; }, "ball_material.poisson_ratio");
  rejects([](auto& p) { p.workpiece_material.density_kg_m3 = -1; },
          "workpiece_material.density_kg_m3");
  rejects([](auto& p) { p.seat_preload_n = 0; }, "seat_preload_n");
  rejects([](auto& p) { p.seat_radius_mm = INFINITY; }, "seat_radius_mm");
  rejects([](auto& p) { p.seat_height_mm = -1; }, "seat_height_mm");
  rejects([](auto& p) { p.trigger_unload_fraction = 1; }, "trigger_unload_fraction");
  rejects([](auto& p) { p.stylus_damping_ratio = -0.1; }, "stylus_damping_ratio");
  rejects([](auto& p) { p.contact_restitution = 0; }, "contact_restitution");
  rejects([](auto& p) { p.trigger_latency_s = -1e-6; }, "trigger_latency_s");

  const ProbeDynamics probe{ProbeDynamicsParameters{}};
  EXPECT_THROW(probe.pretravel_um(0.0, 0.0), std::invalid_argument);
  EXPECT_THROW(probe.pretravel_um(0.0, -1.0), std::invalid_argument);
  EXPECT_THROW(probe.pretravel_um(std::nan(""), 1.0), std::invalid_argument);
  EXPECT_THROW(probe.quasi_static_pretravel_um(INFINITY), std::invalid_argument);
  EXPECT_THROW(probe.lobing_harmonics(6, 1.0, 3), std::invalid_argument);  // Nyquist
  EXPECT_THROW(probe.lobing_harmonics(12, 1.0, 0), std::invalid_argument);
  try {
    probe.pretravel_um(0.0, -1.0);
  } catch (const std::invalid_argument& e) {
    EXPECT_THAT(e.what(), HasSubstr("speed_mm_s: got -1"));
  }
}

}  // namespace
}  // namespace gearmc
