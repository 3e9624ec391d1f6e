// Nominal involute gear geometry, spur and helical: the dimensions of a gear cut by a basic rack
// (ISO 21771, ISO 53 profile A by default) and closed-form flank points, outward unit normals and
// profile curvature for both flanks of every tooth, in the conventions of docs/formats.md:
// gear axis +Z, z = 0 on the lower face, tooth 1 centred on +X, teeth numbered counter-clockwise
// seen from +Z, flank R = outward normal with a positive counter-clockwise tangential component,
// profile position = roll length L = sqrt(r^2 - r_b^2) in mm. All lengths in mm, angles in rad.
// Public API (docs/api.md): a stable part of the C++ interface, installed with its includes.
#pragma once

#include <Eigen/Core>
#include <optional>
#include <string>

#include "gears/flank_modifications.h"

namespace gearmc {

// Which flank of a tooth. R: outward normal turns counter-clockwise (the +Y flank of tooth 1).
enum class FlankSide { kLeft, kRight };

// +1 for R, -1 for L (the `side` variable of deviation expressions, docs/formats.md).
constexpr double side_sign(FlankSide side) { return side == FlankSide::kRight ? 1.0 : -1.0; }
constexpr char side_letter(FlankSide side) { return side == FlankSide::kRight ? 'R' : 'L'; }

// Hand of a helical gear (ISO 21771): a right-hand gear's transverse section at height z is the
// section at z = 0 turned counter-clockwise seen from +Z by z tan(beta) / r (a right-handed
// screw); a left-hand gear's clockwise.
enum class Hand { kRight, kLeft };

// +1 for right hand, -1 for left.
constexpr double hand_sign(Hand hand) { return hand == Hand::kRight ? 1.0 : -1.0; }

// Basic rack profile, every value in modules (ISO 53 profile A by default).
struct BasicRack {
  double addendum = 1.0;      // h_aP / m: generates the gear's dedendum
  double dedendum = 1.25;     // h_fP / m: the tool tip, generates the root
  double root_radius = 0.38;  // rho_fP / m: tool tip radius, generates the root fillet
};

// What defines a gear. Lengths in mm, angles in degrees. The module and the pressure angle are
// the normal ones (m_n, alpha_n, ISO 21771), the design data of a helical gear; for a spur gear
// normal = transverse.
struct GearParameters {
  int teeth = 24;
  double module_mm = 5.6;            // m_n
  double pressure_angle_deg = 20.0;  // alpha_n
  double helix_angle_deg = 0.0;      // beta at the reference diameter, [0, 45); 0 = spur
  Hand hand = Hand::kRight;          // meaningful when helix_angle_deg > 0
  double profile_shift = 0.0;        // x, dimensionless (times m_n)
  double face_width_mm = 10.0;
  BasicRack rack;
  std::optional<double> tip_diameter_mm;   // overrides d_a = d + 2 m_n (h_aP/m + x)
  std::optional<double> root_diameter_mm;  // overrides d_f = d - 2 m_n (h_fP/m - x)
  FlankModifications modifications;        // the design flank (flank_modifications.h)
};

// inv(alpha) = tan(alpha) - alpha, alpha in rad.
double involute_function(double alpha_rad);

// A point of a nominal flank with its local frame (gear frame, mm).
struct FlankPoint {
  Eigen::Vector3d point;            // on the nominal flank
  Eigen::Vector3d normal;           // unit, pointing out of the material
  Eigen::Vector3d profile_tangent;  // unit, direction of increasing roll length (transverse)
  Eigen::Vector3d base_point;       // where the normal line touches the base cylinder (spur: z
                                    // as the point's)
  double profile_curvature_per_mm;  // 1/L in the transverse section: the involute is convex,
                                    // its centre of curvature is the section's base point; zero
                                    // curvature across the face on a spur gear
};

// Nominal geometry of one gear. Construct only from validated parameters
// (`validate_gear_parameters` says what is wrong with them). Diameters, pitches, thicknesses and
// roll lengths are transverse (ISO 21771): for a helical gear they are those of the transverse
// section, which is an involute spur gear of module m_t and pressure angle alpha_t.
class InvoluteGear {
 public:
  explicit InvoluteGear(const GearParameters& parameters);

  const GearParameters& parameters() const { return parameters_; }
  int teeth() const { return parameters_.teeth; }
  double module_mm() const { return parameters_.module_mm; }  // normal module m_n
  double pressure_angle_rad() const { return alpha_; }        // normal pressure angle alpha_n
  double face_width_mm() const { return parameters_.face_width_mm; }

  // Helical gears (ISO 21771 §4): beta, the hand, m_t = m_n / cos(beta), tan(alpha_t) =
  // tan(alpha_n) / cos(beta), the base helix angle (sin(beta_b) = sin(beta) cos(alpha_n)) and
  // the lead p_z = pi d / tan(beta) (infinite on a spur gear). On a spur gear m_t = m_n and
  // alpha_t = alpha_n exactly.
  bool helical() const { return beta_ != 0.0; }
  double helix_angle_rad() const { return beta_; }
  Hand hand() const { return parameters_.hand; }
  double transverse_module_mm() const { return m_t_; }
  double transverse_pressure_angle_rad() const { return alpha_t_; }
  double base_helix_angle_rad() const { return beta_b_; }
  double lead_mm() const;
  // The turn of the transverse section per mm of height, +/- tan(beta_b) / r_b (rad/mm; right
  // hand counter-clockwise seen from +Z, 0 on a spur gear).
  double helix_turn_per_mm() const { return turn_per_mm_; }

  double reference_diameter_mm() const { return d_; }  // d = m_t z
  double tip_diameter_mm() const { return d_a_; }
  double root_diameter_mm() const { return d_f_; }
  double base_diameter_mm() const { return d_b_; }   // d_b = d cos(alpha_t)
  double base_pitch_mm() const { return p_b_; }      // transverse p_bt = pi m_t cos(alpha_t)
  double angular_pitch_rad() const { return tau_; }  // 2 pi / z
  // Transverse arc tooth thickness on the reference circle, s_t = m_t (pi/2 + 2 x tan(alpha_n)).
  double tooth_thickness_mm() const { return s_; }
  // Arc tooth thickness on the tip circle (must be > 0: no pointed teeth).
  double tip_thickness_mm() const;
  // Start of the involute generated by the rack's straight flank (form circle, ISO 21771):
  // roll length L_Ff = r sin(alpha_t) - (h_FfP - x m_n)/sin(alpha_t), h_FfP = h_tool - rho_fP
  // (1 - sin alpha_n), h_tool = the rack height that cuts the root. Clamped to 0 when the rack
  // undercuts.
  double form_roll_length_mm() const { return L_form_; }
  double form_diameter_mm() const;
  bool undercut() const { return undercut_; }
  double tip_roll_length_mm() const { return L_tip_; }  // sqrt(r_a^2 - r_b^2)
  double roll_length_at_diameter(double diameter_mm) const;
  double diameter_at_roll_length(double roll_length_mm) const;

  // Polar angle of the centre line of tooth `tooth` (1..z): (tooth - 1) * 2 pi / z.
  double tooth_centre_angle_rad(int tooth) const;
  // Polar angle, relative to the tooth centre line, where the R flank leaves the base circle in
  // the section z = 0: theta_b = s_t/d + inv(alpha_t). The L flank is its mirror image.
  double base_half_angle_rad() const { return theta_b_; }

  // Nominal flank point at roll length L (mm, > 0) and height z (mm) on tooth 1..z, side L or R.
  // Closed form: P = r_b e(phi_b) + L n_t + z e_z with phi_b = tooth angle +/- (theta_b - L/r_b)
  // + z helix_turn_per_mm (the transverse section turned by the helix), n_t = +/- e'(phi_b) the
  // transverse normal. On a helical gear the normal of the involute helicoid is cos(beta_b) n_t
  // - (+/-)(hand) sin(beta_b) e_z (it lies in the plane of n_t and e_z, perpendicular to dP/dz =
  // e_z + helix_turn_per_mm (r_b e' -/+ L e)), and the base point is where the normal line meets
  // the base cylinder, at height z + (+/-)(hand) L tan(beta_b).
  FlankPoint flank_point(int tooth, FlankSide side, double roll_length_mm, double z_mm) const;

  // The designed modifications as curves (null when the gear has none: the flank is the
  // involute, bit for bit).
  const DesignModification* design_modification() const {
    return modification_ ? &*modification_ : nullptr;
  }

 private:
  GearParameters parameters_;
  double alpha_, beta_, m_t_, alpha_t_, beta_b_, turn_per_mm_;
  double d_, d_a_, d_f_, d_b_, p_b_, tau_, s_, theta_b_, L_form_, L_tip_;
  bool undercut_;
  std::optional<DesignModification> modification_;
};

// Empty when the parameters make a gear; otherwise what is wrong, in one sentence.
std::string validate_gear_parameters(const GearParameters& parameters);

}  // namespace gearmc
