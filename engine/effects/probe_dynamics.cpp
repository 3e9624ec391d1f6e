// Kinematic touch-trigger probe: stylus bending + tip mass + Hertz contact + three-leg seat,
// integrated from touch to trigger with SUNDIALS CVODE 6.4 (BDF, dense direct linear solver,
// analytic Jacobian, root finding on the trigger condition). The seat's trigger force, the
// equations of motion, their dimensionless form and the quasi-static limit are derived in the
// comments where they are implemented. See probe_dynamics.h for the parameters and sources.
#include "engine/effects/probe_dynamics.h"

#include <cvode/cvode.h>
#include <nvector/nvector_serial.h>
#include <sundials/sundials_context.h>
#include <sunlinsol/sunlinsol_dense.h>
#include <sunmatrix/sunmatrix_dense.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <numbers>
#include <sstream>
#include <stdexcept>
#include <string>

#include "core/constants.h"

namespace gearmc {
namespace {

// ---------------------------------------------------------------------------------------------
// Parameter checks: one std::invalid_argument naming the parameter, the value and the range.

void require(bool ok, const std::string& name, double value, const char* expected) {
  if (ok) return;
  std::ostringstream message;
  message << "ProbeDynamicsParameters." << name << ": got " << value << ", expected " << expected;
  throw std::invalid_argument(message.str());
}

bool positive(double x) { return std::isfinite(x) && x > 0; }

void check_material(const ElasticMaterial& material, const std::string& name) {
  require(positive(material.youngs_modulus_gpa), name + ".youngs_modulus_gpa",
          material.youngs_modulus_gpa, "a finite value > 0 (GPa)");
  require(std::isfinite(material.poisson_ratio) && material.poisson_ratio >= 0 &&
              material.poisson_ratio < 0.5,
          name + ".poisson_ratio", material.poisson_ratio, "a value in [0, 0.5)");
  require(positive(material.density_kg_m3), name + ".density_kg_m3", material.density_kg_m3,
          "a finite value > 0 (kg/m^3)");
}

void check_parameters(const ProbeDynamicsParameters& p) {
  require(positive(p.stylus_length_mm), "stylus_length_mm", p.stylus_length_mm,
          "a finite value > 0 (mm)");
  require(positive(p.stem_diameter_mm), "stem_diameter_mm", p.stem_diameter_mm,
          "a finite value > 0 (mm)");
  require(positive(p.ball_diameter_mm), "ball_diameter_mm", p.ball_diameter_mm,
          "a finite value > 0 (mm)");
  // A stem as thick as the ball would touch a flank before the ball does.
  require(p.stem_diameter_mm < p.ball_diameter_mm, "stem_diameter_mm", p.stem_diameter_mm,
          "a value below ball_diameter_mm (a ball stylus)");
  check_material(p.stem_material, "stem_material");
  check_material(p.ball_material, "ball_material");
  check_material(p.workpiece_material, "workpiece_material");
  require(positive(p.seat_preload_n), "seat_preload_n", p.seat_preload_n, "a finite value > 0 (N)");
  require(positive(p.seat_radius_mm), "seat_radius_mm", p.seat_radius_mm,
          "a finite value > 0 (mm)");
  require(std::isfinite(p.seat_height_mm) && p.seat_height_mm >= 0, "seat_height_mm",
          p.seat_height_mm, "a finite value >= 0 (mm)");
  require(std::isfinite(p.first_leg_azimuth_rad), "first_leg_azimuth_rad", p.first_leg_azimuth_rad,
          "a finite angle (rad)");
  require(std::isfinite(p.trigger_unload_fraction) && p.trigger_unload_fraction >= 0 &&
              p.trigger_unload_fraction < 1,
          "trigger_unload_fraction", p.trigger_unload_fraction, "a value in [0, 1)");
  require(std::isfinite(p.stylus_damping_ratio) && p.stylus_damping_ratio >= 0,
          "stylus_damping_ratio", p.stylus_damping_ratio, "a finite value >= 0");
  require(std::isfinite(p.contact_restitution) && p.contact_restitution > 0 &&
              p.contact_restitution <= 1,
          "contact_restitution", p.contact_restitution, "a value in (0, 1]");
  require(std::isfinite(p.trigger_latency_s) && p.trigger_latency_s >= 0, "trigger_latency_s",
          p.trigger_latency_s, "a finite value >= 0 (s)");
}

void check_direction_and_speed(double phi_rad, double speed_mm_s) {
  if (!std::isfinite(phi_rad)) {
    throw std::invalid_argument("ProbeDynamics: approach azimuth phi_rad must be finite");
  }
  if (!positive(speed_mm_s)) {
    std::ostringstream message;
    message << "ProbeDynamics: approach speed_mm_s: got " << speed_mm_s
            << ", expected a finite value > 0 (mm/s)";
    throw std::invalid_argument(message.str());
  }
}

// Euler–Bernoulli cantilever and Hertz constants.
StylusProperties derive_stylus(const ProbeDynamicsParameters& p) {
  StylusProperties s;
  const double l = p.stylus_length_mm;
  const double d = p.stem_diameter_mm;
  const double e_stem = p.stem_material.youngs_modulus_gpa * 1e3;  // N/mm²
  const double inertia = kPi * d * d * d * d / 64.0;               // I, mm⁴
  const double area = kPi * d * d / 4.0;                           // A, mm²
  // Cantilever clamped at the mounting face with a lateral end load at the ball centre:
  // tip deflection F ℓ³ / (3EI) → k_b = 3EI/ℓ³ (Euler–Bernoulli; e.g. Roark's Formulas for
  // Stress and Strain, Table 8.1 case 1a [recalled]). Axial: k_a = EA/ℓ.
  s.bending_stiffness_n_per_mm = 3.0 * e_stem * inertia / (l * l * l);
  s.axial_stiffness_n_per_mm = e_stem * area / l;
  // Lumped tip mass: the ball plus the stem's Rayleigh equivalent mass for the first bending
  // mode of a cantilever, 33/140 of its mass (Rayleigh's energy method with the static
  // deflection shape; e.g. Thomson, Theory of Vibration with Applications, §2 [recalled]).
  const double ball_volume_m3 = kPi * std::pow(p.ball_diameter_mm, 3) / 6.0 * 1e-9;  // mm³ → m³
  const double stem_volume_m3 = area * l * 1e-9;
  s.effective_tip_mass_kg = p.ball_material.density_kg_m3 * ball_volume_m3 +
                            33.0 / 140.0 * p.stem_material.density_kg_m3 * stem_volume_m3;
  s.natural_frequency_hz =
      std::sqrt(s.bending_stiffness_n_per_mm * 1e3 / s.effective_tip_mass_kg) / (2.0 * kPi);
  // Hertz, sphere on a flat (Johnson, Contact Mechanics, CUP 1985, §4.2, flat = R2 → ∞):
  // F = (4/3) E* √R δ^(3/2), 1/E* = (1−ν1²)/E1 + (1−ν2²)/E2. The involute flank's own
  // curvature (radius = roll length, 21–45 mm on P1's gear) changes R by < 3 % and is ignored.
  const auto& b = p.ball_material;
  const auto& w = p.workpiece_material;
  s.contact_modulus_gpa = 1.0 / ((1.0 - b.poisson_ratio * b.poisson_ratio) / b.youngs_modulus_gpa +
                                 (1.0 - w.poisson_ratio * w.poisson_ratio) / w.youngs_modulus_gpa);
  s.hertz_constant = 4.0 / 3.0 * s.contact_modulus_gpa * 1e3 * std::sqrt(p.ball_diameter_mm / 2);
  return s;
}

// ---------------------------------------------------------------------------------------------
// Equations of motion after touch, along the approach direction u (+ = towards the material):
//
//   body (stylus carrier, seated):  X_b(t) = v t           (CMM drives it at constant speed)
//   tip (ball centre):              X_t(t), touching the flank at X = 0 when t = 0
//   stylus bending:                 w = X_b − X_t          (the tip lags behind the body)
//   Hertz indentation:              δ = X_t
//   contact force (Hunt–Crossley):  F_H = K_H max(δ, 0)^(3/2) · max(0, 1 + χ δ̇),
//                                   χ = 3(1 − e)/(2 v)  (Hunt & Crossley 1975: the damping
//                                   grows with the Hertz force, so F_H is continuous at touch
//                                   and an impact at speed v loses the energy that a
//                                   restitution e ≈ 1 implies; the contact cannot pull: ≥ 0;
//                                   0 while the tip is off the flank after a bounce)
//   m Ẍ_t = k w + c ẇ − F_H,        c = 2 ζ √(k m)
//
// Without contact damping the tip would ring on the stiff Hertz spring (≈ 30× the stylus
// stiffness near the trigger) almost undamped after the impact, a real but negligible
// oscillation that an accurate integrator would have to resolve over ~10⁵ periods.
//
// State (w, ẇ, δ): ẅ = −Ẍ_t = (F_H − k w − c ẇ)/m,  δ̇ = v − ẇ;  w = ẇ = δ = 0 at t = 0 (the
// tip moves with the body until it touches). The stylus pushes on the seat with k w + c ẇ; the
// probe triggers when that force reaches F_trig(φ).
//
// Dimensionless form (states O(1), so one relative/absolute tolerance fits all): length unit
// x0 = F_trig/k (bending at the trigger), time unit t0 = x0/v, velocity unit v:
//   y0 = w/x0,  y1 = ẇ/v,  y2 = δ/x0,  τ = t/t0,  Ω = ω t0 (ω² = k/m),  κ = K_H √x0 / k
//   y0' = y1
//   y1' = Ω² (κ max(y2, 0)^(3/2) max(0, 1 + β (1 − y1)) − y0) − 2 ζ Ω y1,  β = 3(1 − e)/2
//         (χ δ̇ = β (1 − y1): the damping term is speed-independent in these units)
//   y2' = 1 − y1
//   trigger root  g = (k w + c ẇ)/F_trig − 1 = y0 + (2ζ/Ω) y1 − 1
// and the body travel at the trigger is v t = x0 τ. At low speed Ω is large (the contact and
// the stylus are stiff against the slow ramp): a stiff problem, hence BDF with Newton.

struct Dimensionless {
  double omega = 0;  // Ω
  double zeta = 0;   // ζ
  double kappa = 0;  // κ
  double beta = 0;   // β
};

// Dimensionless contact force F_H / F_trig and the damping factor max(0, 1 + β(1 − y1)).
struct ContactTerms {
  double force, factor;
};
ContactTerms contact_terms(const Dimensionless& s, const sunrealtype* Y) {
  const double d = std::max(Y[2], 0.0);
  const double factor = std::max(0.0, 1.0 + s.beta * (1.0 - Y[1]));
  return {s.kappa * d * std::sqrt(d) * factor, factor};
}

int rhs(sunrealtype /*tau*/, N_Vector y, N_Vector ydot, void* user_data) {
  const auto& s = *static_cast<const Dimensionless*>(user_data);
  const sunrealtype* Y = N_VGetArrayPointer(y);
  sunrealtype* D = N_VGetArrayPointer(ydot);
  D[0] = Y[1];
  D[1] = s.omega * s.omega * (contact_terms(s, Y).force - Y[0]) - 2.0 * s.zeta * s.omega * Y[1];
  D[2] = 1.0 - Y[1];
  return 0;
}

int jacobian(sunrealtype /*tau*/, N_Vector y, N_Vector /*fy*/, SUNMatrix J, void* user_data,
             N_Vector /*tmp1*/, N_Vector /*tmp2*/, N_Vector /*tmp3*/) {
  const auto& s = *static_cast<const Dimensionless*>(user_data);
  const sunrealtype* Y = N_VGetArrayPointer(y);
  const double d = std::max(Y[2], 0.0);
  const double w2 = s.omega * s.omega;
  const double factor = contact_terms(s, Y).factor;
  SUNMatZero(J);
  SM_ELEMENT_D(J, 0, 1) = 1.0;
  SM_ELEMENT_D(J, 1, 0) = -w2;
  SM_ELEMENT_D(J, 1, 1) =
      -2.0 * s.zeta * s.omega - (factor > 0 ? w2 * s.kappa * d * std::sqrt(d) * s.beta : 0.0);
  SM_ELEMENT_D(J, 1, 2) = 1.5 * w2 * s.kappa * std::sqrt(d) * factor;
  SM_ELEMENT_D(J, 2, 1) = -1.0;
  return 0;
}

int trigger_condition(sunrealtype /*tau*/, N_Vector y, sunrealtype* gout, void* user_data) {
  const auto& s = *static_cast<const Dimensionless*>(user_data);
  const sunrealtype* Y = N_VGetArrayPointer(y);
  gout[0] = Y[0] + 2.0 * s.zeta / s.omega * Y[1] - 1.0;
  return 0;
}

// CVODE's error messages go into the exception instead of stderr.
void record_cvode_error(int /*code*/, const char* module, const char* function, char* msg,
                        void* user_data) {
  auto& text = *static_cast<std::string*>(user_data);
  text = std::string(module) + "::" + function + ": " + msg;
}

// Owners of the SUNDIALS objects of one solve (released in reverse order of creation).
struct CvodeSession {
  SUNContext context = nullptr;
  N_Vector y = nullptr;
  SUNMatrix matrix = nullptr;
  SUNLinearSolver solver = nullptr;
  void* cvode = nullptr;
  std::string last_error;

  CvodeSession() = default;
  CvodeSession(const CvodeSession&) = delete;
  CvodeSession& operator=(const CvodeSession&) = delete;
  ~CvodeSession() {
    if (cvode) CVodeFree(&cvode);
    if (solver) SUNLinSolFree(solver);
    if (matrix) SUNMatDestroy(matrix);
    if (y) N_VDestroy(y);
    if (context) SUNContext_Free(&context);
  }

  void check(int flag, const char* call) const {
    if (flag >= 0) return;
    char* name = CVodeGetReturnFlagName(static_cast<long>(flag));  // malloc'ed by CVODE
    std::ostringstream message;
    message << "ProbeDynamics: CVODE " << call << " failed (" << (name ? name : "?") << ")";
    std::free(name);
    if (!last_error.empty()) message << ": " << last_error;
    throw std::runtime_error(message.str());
  }
  void check_created(const void* object, const char* call) const {
    if (!object) throw std::runtime_error(std::string("ProbeDynamics: ") + call + " failed");
  }
};

// Tolerances of the dimensionless solve (states O(1)). Against a reference solve at rtol 1e-12
// the default probe's pre-travel agrees to < 1e-7 µm at 0.05–8 mm/s with these (measured);
// tighter tolerances only cost steps (≈ 1 400–2 000 steps, 3–5 ms per solve here).
constexpr double kRelativeTolerance = 1e-7;
constexpr double kAbsoluteTolerance = 1e-9;
constexpr long kMaxSteps = 500000;

}  // namespace

ProbeDynamics::ProbeDynamics(const ProbeDynamicsParameters& parameters) : parameters_(parameters) {
  check_parameters(parameters_);
  stylus_ = derive_stylus(parameters_);
}

double ProbeDynamics::lever_arm_mm() const {
  return parameters_.seat_height_mm + parameters_.stylus_length_mm;
}

// Trigger force of a three-leg kinematic seat (the Estler et al. 1996 mechanism, derived here).
// Seat plane z = 0, legs at p_i = r_s e_i, e_i = (cos θ_i, sin θ_i), θ_i = θ0 + 2πi/3; the
// spring presses the carrier down with F_s on the axis; the seat gives vertical reactions
// R_i ≥ 0 (lateral loads are taken by the V-contacts). Approaching along u = (cos φ, sin φ),
// the flank pushes the ball back with −F u at depth L = h + ℓ below the seat plane.
//   vertical forces:      Σ R_i = F_s
//   moments about origin: the tip force gives (0,0,−L) × (−F u) = L F (ẑ × u), a reaction
//                         gives p_i × R_i ẑ = −R_i (ẑ × p_i); so Σ R_i p_i = L F u.
// With Σ e_i = 0 and Σ e_i e_iᵀ = (3/2) I, the unique solution is
//   R_i = F_s/3 + (2 L F / (3 r_s)) (u·e_i),
// i.e. the centre of pressure moves towards u by L F / F_s. The rear leg (most negative u·e_i)
// unloads first; the carrier then tilts about the line through the two front legs (the pivot
// line, at distance r_s/2 from the axis). Trigger when min R_i = η F_s/3:
//   F_trig(φ) = (1 − η) F_s r_s / (2 L c(φ)),  c(φ) = max_i(−u·e_i) = cos Δ(φ),
// Δ = angle between u and the nearest anti-leg direction −e_i, |Δ| ≤ π/3: equivalently the
// lever arm of the preload about the pivot line, r_s/2, seen along u is (r_s/2)/cos Δ. Period
// 2π/3; F_0 = (1−η) F_s r_s/(2L) when approaching opposite a leg, 2 F_0 towards a leg: the 1:2
// between opposite directions that P2 reports for kinematic probes.
double ProbeDynamics::trigger_force_n(double phi_rad) const {
  if (!std::isfinite(phi_rad)) {
    throw std::invalid_argument("ProbeDynamics: approach azimuth phi_rad must be finite");
  }
  const auto& p = parameters_;
  double c = -1.0;
  for (int i = 0; i < 3; ++i) {
    const double theta = p.first_leg_azimuth_rad + 2.0 * kPi * i / 3.0;
    c = std::max(c, -std::cos(phi_rad - theta));  // −u·e_i
  }
  return (1.0 - p.trigger_unload_fraction) * p.seat_preload_n * p.seat_radius_mm /
         (2.0 * lever_arm_mm() * c);
}

// v → 0: no inertia and no stylus damping force (c ẇ ∝ v), so at the trigger k_b w = F_H =
// F_trig and the body has travelled w + δ = F_trig/k_b + (F_trig/K_H)^(2/3). (The
// Hunt–Crossley factor 1 + χ δ̇ tends to 1 + β k_b/(k_b + k_c) ≈ 1 + 4e-4 at the trigger, k_c =
// dF_H/dδ, which moves δ by ~2e-5 µm for the default probe; the closed form ignores it.) The
// first-order speed correction is −(2ζ/ω) v (1 − k_b/(k_b + k_c)): the damping force c ẇ
// reaches the seat, so less bending is needed.
double ProbeDynamics::quasi_static_pretravel_um(double phi_rad) const {
  const double force = trigger_force_n(phi_rad);
  const double bending_mm = force / stylus_.bending_stiffness_n_per_mm;
  const double indentation_mm = std::pow(force / stylus_.hertz_constant, 2.0 / 3.0);
  return 1e3 * (bending_mm + indentation_mm);
}

PretravelSolution ProbeDynamics::solve(double phi_rad, double speed_mm_s) const {
  check_direction_and_speed(phi_rad, speed_mm_s);
  const double force = trigger_force_n(phi_rad);
  const double k = stylus_.bending_stiffness_n_per_mm;
  const double x0 = force / k;                                              // mm
  const double t0 = x0 / speed_mm_s;                                        // s
  const double omega = std::sqrt(k * 1e3 / stylus_.effective_tip_mass_kg);  // rad/s
  Dimensionless data;
  data.omega = omega * t0;
  data.zeta = parameters_.stylus_damping_ratio;
  data.kappa = stylus_.hertz_constant * std::sqrt(x0) / k;
  data.beta = 1.5 * (1.0 - parameters_.contact_restitution);
  // Quasi-static trigger time in τ (1 + δ/x0); the integration stops at 4× it.
  const double tau_quasi_static = 1.0 + std::pow(data.kappa, -2.0 / 3.0);
  const double tau_end = 4.0 * tau_quasi_static;

  CvodeSession s;
  s.check(SUNContext_Create(nullptr, &s.context), "SUNContext_Create");
  s.y = N_VNew_Serial(3, s.context);
  s.check_created(s.y, "N_VNew_Serial");
  N_VConst(0.0, s.y);  // touch: no bending, no bending rate, no indentation
  s.cvode = CVodeCreate(CV_BDF, s.context);
  s.check_created(s.cvode, "CVodeCreate");
  s.check(CVodeSetErrHandlerFn(s.cvode, record_cvode_error, &s.last_error), "CVodeSetErrHandlerFn");
  s.check(CVodeInit(s.cvode, rhs, 0.0, s.y), "CVodeInit");
  s.check(CVodeSetUserData(s.cvode, &data), "CVodeSetUserData");
  s.check(CVodeSStolerances(s.cvode, kRelativeTolerance, kAbsoluteTolerance), "CVodeSStolerances");
  s.matrix = SUNDenseMatrix(3, 3, s.context);
  s.check_created(s.matrix, "SUNDenseMatrix");
  s.solver = SUNLinSol_Dense(s.y, s.matrix, s.context);
  s.check_created(s.solver, "SUNLinSol_Dense");
  s.check(CVodeSetLinearSolver(s.cvode, s.solver, s.matrix), "CVodeSetLinearSolver");
  s.check(CVodeSetJacFn(s.cvode, jacobian), "CVodeSetJacFn");
  s.check(CVodeSetMaxNumSteps(s.cvode, kMaxSteps), "CVodeSetMaxNumSteps");
  s.check(CVodeSetStopTime(s.cvode, tau_end), "CVodeSetStopTime");
  s.check(CVodeRootInit(s.cvode, 1, trigger_condition), "CVodeRootInit");
  int rising_only = 1;  // g goes from −1 upwards; only an upward crossing is a trigger
  s.check(CVodeSetRootDirection(s.cvode, &rising_only), "CVodeSetRootDirection");

  sunrealtype tau = 0.0;
  const int flag = CVode(s.cvode, tau_end, s.y, &tau, CV_NORMAL);
  s.check(flag, "CVode");
  if (flag != CV_ROOT_RETURN) {
    std::ostringstream message;
    message << "ProbeDynamics: no trigger within " << 1e3 * x0 * tau_end << " um of travel (phi "
            << phi_rad << " rad, speed " << speed_mm_s << " mm/s)";
    throw std::runtime_error(message.str());
  }

  const sunrealtype* Y = N_VGetArrayPointer(s.y);
  PretravelSolution out;
  out.trigger_time_s = tau * t0;
  out.pretravel_um = 1e3 * (x0 * tau + speed_mm_s * parameters_.trigger_latency_s);
  out.deflection_um = 1e3 * x0 * Y[0];
  out.indentation_um = 1e3 * x0 * Y[2];
  out.seat_force_n = force * (Y[0] + 2.0 * data.zeta / data.omega * Y[1]);
  out.contact_force_n = force * contact_terms(data, Y).force;
  s.check(CVodeGetNumSteps(s.cvode, &out.steps), "CVodeGetNumSteps");
  return out;
}

double ProbeDynamics::pretravel_um(double phi_rad, double speed_mm_s) const {
  return solve(phi_rad, speed_mm_s).pretravel_um;
}

// Discrete Fourier analysis of p at φ_j = 2πj/n: for 1 ≤ k < n/2
//   A_k = (2/n) Σ p_j cos(kφ_j),  B_k = (2/n) Σ p_j sin(kφ_j),
//   a_k cos(k(φ − φ_k)) = A_k cos kφ + B_k sin kφ
//   →  a_k = √(A_k² + B_k²),  φ_k = atan2(B_k, A_k)/k.
// Exact for a trigonometric polynomial of order < n/2; otherwise orders above n/2 alias.
LobingHarmonics ProbeDynamics::lobing_harmonics(int n_directions, double speed_mm_s,
                                                int max_order) const {
  if (max_order < 1 || n_directions <= 2 * max_order) {
    std::ostringstream message;
    message << "ProbeDynamics::lobing_harmonics: got n_directions " << n_directions
            << ", max_order " << max_order
            << ", expected max_order >= 1 and n_directions > 2*max_order (Nyquist)";
    throw std::invalid_argument(message.str());
  }
  check_direction_and_speed(0.0, speed_mm_s);
  LobingHarmonics out;
  out.azimuth_rad.resize(n_directions);
  out.pretravel_um.resize(n_directions);
  double sum = 0;
  for (int j = 0; j < n_directions; ++j) {
    out.azimuth_rad[j] = 2.0 * kPi * j / n_directions;
    out.pretravel_um[j] = pretravel_um(out.azimuth_rad[j], speed_mm_s);
    sum += out.pretravel_um[j];
  }
  out.p0_um = sum / n_directions;
  for (int k = 1; k <= max_order; ++k) {
    double a = 0, b = 0;
    for (int j = 0; j < n_directions; ++j) {
      a += out.pretravel_um[j] * std::cos(k * out.azimuth_rad[j]);
      b += out.pretravel_um[j] * std::sin(k * out.azimuth_rad[j]);
    }
    a *= 2.0 / n_directions;
    b *= 2.0 / n_directions;
    LobingHarmonic h;
    h.order = k;
    h.amplitude_um = std::hypot(a, b);
    double phase_rad = std::atan2(b, a) / k;
    if (phase_rad < 0) phase_rad += 2.0 * kPi / k;
    h.phase_deg = phase_rad * 180.0 / kPi;
    out.harmonics.push_back(h);
  }
  return out;
}

}  // namespace gearmc
