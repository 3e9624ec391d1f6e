// Physical model of a kinematic touch-trigger probe: why the pre-travel of a
// Renishaw TP-type probe depends on the approach direction and the approach speed. The stylus
// is an Euler–Bernoulli cantilever (bending spring k_b = 3EI/ℓ³) carrying the effective tip
// mass, the ball touches the flank through a Hertzian ball-on-plane contact, and the stylus
// carrier sits on a three-leg kinematic seat held by a spring preload; the probe triggers when
// one leg of the seat unloads, so the lateral trigger force depends on the approach azimuth
// with period 2π/3 (three lobes, P2 and docs/reference-values.md). The CMM drives the probe body at
// a constant speed; SUNDIALS CVODE (BDF, dense Newton) integrates the tip dynamics from the instant
// of touch to the trigger, located by CVODE's root finding: the trigger is the instant the force
// the stylus transmits to the seat (bending + damping force; it equals the contact force minus the
// tip's inertia force, the same in the quasi-static limit) reaches the direction-dependent seat
// trigger force F_trig(φ). The result is the pre-travel p(φ, v) — how far the CMM has moved beyond
// the touch when it latches the position — its closed-form quasi-static limit, and its harmonics
// p(φ) = p0 + Σ a_k cos(k(φ − φ_k)), which feed the `probe_lobing` effect. Lineage of the model
// (abstracts read, volume/pages recalled): Estler et al., "Error compensation for CMM touch trigger
// probes", Precision Engineering 19 (1996) 85–97 (kinematic seat + stylus bending); Woźniak &
// Dobosz, "Metrological feasibilities of CMM touch trigger probes. Part I: 3D theoretical model of
// probe pretravel", Measurement 34 (2003) 273–286. Not modelled: friction at the flank, gravity on
// a horizontal stylus, seat-contact compliance, approaches out of the XY plane. Parameter values
// and their standing are listed with ProbeDynamicsParameters below.
//
// Frames and units. Probe frame = CMM frame with the stylus along −Z; the approach azimuth φ
// (rad) is the direction of the probe's motion in the XY plane, φ = atan2(−n_y, −n_x) for a
// point with outward normal n (docs/formats.md). Lengths mm, forces N, moduli GPa, densities
// kg/m³, times s, speeds mm/s, pre-travel µm.
#pragma once

#include <vector>

#include "engine/effects/lobing_harmonic.h"

namespace gearmc {

// Isotropic linear-elastic material of a stylus part or of the workpiece.
struct ElasticMaterial {
  double youngs_modulus_gpa = 0;  // E, GPa
  double poisson_ratio = 0;       // ν, in [0, 0.5)
  double density_kg_m3 = 0;       // ρ, kg/m³
};

// Typical values. [read] = taken from the page named; [recalled] = a handbook value not re-read.
namespace probe_materials {
// Steel (stylus stems, gears): E 210 GPa, ν 0.30 [recalled: EN 1993-1-1 §3.2.6];
// ρ 7850 kg/m³ [recalled: EN 1991-1-1 Table A.4].
inline constexpr ElasticMaterial kSteel{210.0, 0.30, 7850.0};
// Tungsten carbide: E 630 GPa, ν 0.24, ρ 15 g/cm³ [read: makeitfrom.com "Tungsten Carbide
// (WC)"]; cemented WC-Co stylus grades: ρ 14.8–14.95 g/cm³ [read: labgages.com stylus
// material table]; Wikipedia gives E 530–700 GPa.
inline constexpr ElasticMaterial kTungstenCarbide{630.0, 0.24, 15000.0};
// Ceramic stem, zirconia Y-TZP: E 205 GPa, ν 0.30, ρ 6.05 g/cm³ [read:
// vinayaktechnoceramics.in zirconia table, Table 2; benthamopen zirconia Table 1: 210 GPa].
inline constexpr ElasticMaterial kZirconia{205.0, 0.30, 6050.0};
// Ruby (Cr-doped sapphire) ball: E 373 GPa [read: Aggarwal & Ramdas, "Physical Properties of
// Diamond and Sapphire", CRC 2019, ch. 4 abstract], ν 0.28 [read: makeitfrom.com synthetic
// sapphire], ρ 3.90 g/cm³ [read: labgages.com stylus ball table].
inline constexpr ElasticMaterial kRuby{373.0, 0.28, 3900.0};
}  // namespace probe_materials

// Parameters of the probe model. Defaults: a TP20-like kinematic probe (standard-force module)
// with a 20 mm tungsten-carbide stylus and P1's Ø1 mm ball. Each value says its standing:
// [P1]/[P2] = docs/sources.md, [read] = a page actually read, [recalled] = believed but not
// re-checked against the data sheet, [assumed] = a plausible number without a source,
// [derived] = computed from the others. Plausibility check (not a calibration): with a 10 mm
// steel stylus (Ø1 mm stem, Ø2 mm ball) at 8 mm/s the model's pre-travel varies by 2.6 µm
// peak to peak (±1.3 µm) over the directions, against the TP20's 2-D form ±0.6 … ±1.0 µm with
// a 10 mm stylus [recalled, docs/reference-values.md]; a 50 mm steel stylus (Ø1.5 mm) gives 20 µm
// peak to peak, against 16 µm measured by Shen & Springer (1998) with a 50 mm stylus on their
// probe.
struct ProbeDynamicsParameters {
  // --- stylus (a straight, uniform stem with a ball at its end) ---
  // ℓ: free length from the stylus mounting face to the ball centre, mm. [assumed: within the
  // 20–50 mm of typical M2 styli; P2 used 50 mm]
  double stylus_length_mm = 20.0;
  // Stem diameter, mm. [assumed: the usual stem of a Ø1 mm-ball stylus; real stems are stepped
  // (thicker near the thread), so a uniform stem under-estimates the stiffness]
  double stem_diameter_mm = 0.7;
  // Tip ball diameter, mm. [P1: R = 0.5 mm]
  double ball_diameter_mm = 1.0;
  ElasticMaterial stem_material = probe_materials::kTungstenCarbide;
  ElasticMaterial ball_material = probe_materials::kRuby;
  ElasticMaterial workpiece_material = probe_materials::kSteel;  // the gear flank

  // --- kinematic seat (three legs at 120° on a circle, spring-preloaded) ---
  // F_s: axial spring preload, N. Pushing along the stylus axis lifts all three legs at once,
  // so F_s is the probe's Z trigger force. [recalled: TP20 standard-force module, Z trigger
  // force 0.75 N]
  double seat_preload_n = 0.75;
  // r_s: radius of the circle through the three leg contacts, mm. [assumed: fits the Ø13.2 mm
  // TP20 body]
  double seat_radius_mm = 4.0;
  // h: height of the seat plane above the stylus mounting face, mm; the lever arm of a lateral
  // tip force about the seat is L = h + ℓ. [derived: with F_s and r_s above, F_0 = F_s r_s /
  // (2L) = 0.08 N at a 10 mm stylus, the recalled TP20 standard-force XY trigger force]
  double seat_height_mm = 8.75;
  // θ0: azimuth of the first leg in the probe XY frame, rad; the others at θ0 ± 2π/3.
  // Approaching towards a leg needs the largest trigger force. [assumed: a leg on +Y, the
  // layout of P2's variant-2 calibration with an extremum direction on +Y]
  double first_leg_azimuth_rad = 1.5707963267948966;
  // η: the probe triggers when the reaction of the unloading leg has dropped to η times its
  // preloaded share F_s/3 (resistive probes open the circuit as the contact force falls).
  // In [0, 1). [assumed: 0 = trigger at complete unloading]
  double trigger_unload_fraction = 0.0;

  // --- dynamics and electronics ---
  // ζ: viscous damping ratio of the stylus bending mode (material + joints). [assumed]
  double stylus_damping_ratio = 0.02;
  // e: coefficient of restitution of the ball–flank impact, sets the Hunt–Crossley contact
  // damping (Hunt & Crossley, J. Appl. Mech. 42 (1975) 440–445 [recalled]). In (0, 1].
  // [assumed]
  double contact_restitution = 0.8;
  // t_d: delay between the trigger and the latching of the CMM scales (electronics, filter,
  // mean sampling delay), s; adds t_d·v to the pre-travel in every direction. [assumed: 0,
  // latched in hardware; a constant delay is removed by qualifying at the gauging speed, as
  // Renishaw's TP7 user's guide (2019, p. 17) advises]
  double trigger_latency_s = 0.0;
};

// Stiffness, mass and contact constants derived from the parameters.
struct StylusProperties {
  double bending_stiffness_n_per_mm = 0;  // k_b = 3EI/ℓ³ at the ball centre (lateral)
  double axial_stiffness_n_per_mm = 0;    // k_a = EA/ℓ (reported; the XY model uses k_b)
  double effective_tip_mass_kg = 0;       // m = m_ball + (33/140) m_stem
  double natural_frequency_hz = 0;        // √(k_b/m) / 2π, stylus on a free tip
  double contact_modulus_gpa = 0;         // E*, 1/E* = (1−ν1²)/E1 + (1−ν2²)/E2
  double hertz_constant = 0;              // K_H = (4/3) E* √R, N/mm^1.5
};

// One CVODE integration from touch (t = 0) to trigger.
struct PretravelSolution {
  double pretravel_um = 0;     // body travel from touch to the latched position, incl. t_d·v
  double trigger_time_s = 0;   // t at the trigger (root of the trigger condition)
  double deflection_um = 0;    // stylus bending w at the trigger
  double indentation_um = 0;   // Hertz indentation δ at the trigger
  double seat_force_n = 0;     // force the stylus puts on the seat at the trigger = F_trig(φ)
  double contact_force_n = 0;  // Hertz force at the trigger
  long steps = 0;              // CVODE steps taken
};

// p(φ) sampled at φ_j = 2πj/n (j = 0 … n−1) and its discrete Fourier analysis
// p(φ) ≈ p0 + Σ_{k=1..K} a_k cos(k(φ − φ_k)).
struct LobingHarmonics {
  double p0_um = 0;                       // mean pre-travel
  std::vector<LobingHarmonic> harmonics;  // k = 1 … max_order; a_k ≥ 0, φ_k in [0, 360/k)°
  std::vector<double> azimuth_rad;        // φ_j
  std::vector<double> pretravel_um;       // p(φ_j)
};

// The probe model. Immutable after construction; every method is const and may be called from
// several threads at once (each CVODE solve owns its SUNDIALS context).
class ProbeDynamics {
 public:
  // Throws std::invalid_argument naming the parameter when a value is out of range.
  explicit ProbeDynamics(const ProbeDynamicsParameters& parameters);

  const ProbeDynamicsParameters& parameters() const { return parameters_; }
  const StylusProperties& stylus() const { return stylus_; }

  // L = h + ℓ, the lever arm of a lateral tip force about the seat plane, mm.
  double lever_arm_mm() const;
  // Lateral force at the ball (N) that unloads a leg of the seat when approaching along azimuth
  // φ (rad, probe XY frame): F_trig(φ) = (1−η) F_s r_s / (2 L cos Δ(φ)), Δ = angle between the
  // approach and the nearest direction opposite a leg, |Δ| ≤ π/3 (derivation in the .cpp).
  double trigger_force_n(double phi_rad) const;
  // v → 0 limit, closed form: p = F_trig/k_b + (F_trig/K_H)^(2/3), µm (no latency term).
  double quasi_static_pretravel_um(double phi_rad) const;
  // CVODE integration at approach speed v (mm/s) along azimuth φ (rad). Throws
  // std::invalid_argument for a bad φ or v, std::runtime_error if CVODE fails or no trigger
  // occurs.
  PretravelSolution solve(double phi_rad, double speed_mm_s) const;
  // solve(φ, v).pretravel_um, µm.
  double pretravel_um(double phi_rad, double speed_mm_s) const;
  // p(φ) at n_directions equally spaced azimuths (from φ = 0) at speed v (mm/s), and its
  // harmonics k = 1 … max_order by discrete Fourier analysis; needs max_order ≥ 1 and
  // n_directions > 2·max_order (Nyquist). The seat law has a cusp towards each leg, so its
  // series converges slowly (a_k ~ k⁻²) and orders n ± k alias onto k: with the default probe,
  // a_3 is 6.573 µm from 72 directions against 6.48 µm (+ ~0.01 µm Hertz) for the continuous
  // series. One CVODE solve per direction (a few ms each).
  LobingHarmonics lobing_harmonics(int n_directions, double speed_mm_s, int max_order) const;

 private:
  ProbeDynamicsParameters parameters_;
  StylusProperties stylus_;
};

}  // namespace gearmc
