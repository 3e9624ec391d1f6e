// Nominal involute gear geometry, spur and helical (ISO 21771:2007 relations for a gear generated
// by a basic rack, ISO 53 profile A by default; helical: §4, the transverse section is a spur
// gear of module m_t and pressure angle alpha_t). Every relation used here is closed-form; P1's
// Table 1 (docs/sources.md) checks d, d_a, d_f, d_b and s.
#include "gears/involute_gear.h"

#include "core/constants.h"
#include "gears/base_angle.h"

#include <cmath>
#include <numbers>
#include <sstream>

namespace gearmc {
namespace {

double deg_to_rad(double deg) { return deg * kPi / 180.0; }

}  // namespace

double involute_function(double alpha_rad) { return std::tan(alpha_rad) - alpha_rad; }

std::string validate_gear_parameters(const GearParameters& p) {
  std::ostringstream why;
  if (p.teeth < 5) {
    why << "teeth = " << p.teeth << ": at least 5 teeth are needed";
  } else if (!(p.module_mm > 0.0)) {
    why << "module_mm = " << p.module_mm << ": must be > 0";
  } else if (!(p.pressure_angle_deg > 0.0 && p.pressure_angle_deg < 45.0)) {
    why << "pressure_angle_deg = " << p.pressure_angle_deg << ": must lie in (0, 45)";
  } else if (!(p.helix_angle_deg >= 0.0 && p.helix_angle_deg < 45.0)) {
    why << "helix_angle_deg = " << p.helix_angle_deg << ": must lie in [0, 45) (the hand gives "
        << "the direction)";
  } else if (!(p.face_width_mm > 0.0)) {
    why << "face_width_mm = " << p.face_width_mm << ": must be > 0";
  } else if (!(p.rack.addendum > 0.0 && p.rack.dedendum > 0.0 && p.rack.root_radius >= 0.0)) {
    why << "basic rack (addendum " << p.rack.addendum << ", dedendum " << p.rack.dedendum
        << ", root_radius " << p.rack.root_radius << "): addendum and dedendum must be > 0, "
        << "root radius >= 0";
  }
  if (!why.str().empty()) return why.str();

  // The geometry itself: tip above the form circle, no pointed teeth, root below the base circle
  // or at least below the form circle.
  const InvoluteGear gear(p);
  const double d_b = gear.base_diameter_mm();
  if (gear.tip_diameter_mm() <= d_b) {
    why << "tip diameter " << gear.tip_diameter_mm() << " mm is not above the base diameter " << d_b
        << " mm: no involute flank";
  } else if (gear.tip_thickness_mm() <= 0.0) {
    why << "the teeth are pointed: tip thickness " << gear.tip_thickness_mm()
        << " mm at tip diameter " << gear.tip_diameter_mm()
        << " mm (reduce the profile shift or the tip diameter)";
  } else if (gear.form_roll_length_mm() >= gear.tip_roll_length_mm()) {
    why << "the form circle (d_Ff " << gear.form_diameter_mm()
        << " mm) is not below the tip circle (" << gear.tip_diameter_mm()
        << " mm): no usable involute";
  } else if (gear.root_diameter_mm() >= gear.tip_diameter_mm()) {
    why << "root diameter " << gear.root_diameter_mm() << " mm is not below the tip diameter "
        << gear.tip_diameter_mm() << " mm";
  }
  if (!why.str().empty()) return why.str();
  // The modifications must fit on the flank: the reliefs within the active profile (L_Ff … L_a)
  // and each end relief within half the face; a circular relief's amount below its length.
  const FlankModifications& m = p.modifications;
  const double active = gear.tip_roll_length_mm() - gear.form_roll_length_mm();
  const double profile_reliefs = (m.tip_relief.present() ? m.tip_relief.length_mm : 0.0) +
                                 (m.root_relief.present() ? m.root_relief.length_mm : 0.0);
  if (profile_reliefs > active) {
    why << "the tip and root reliefs span " << profile_reliefs
        << " mm of roll length, more than the active profile's " << active << " mm (L_Ff "
        << gear.form_roll_length_mm() << " … L_a " << gear.tip_roll_length_mm() << " mm)";
  } else if (m.end_relief.present() && m.end_relief.length_mm > 0.5 * p.face_width_mm) {
    why << "the end relief's length " << m.end_relief.length_mm
        << " mm is more than half the face width " << p.face_width_mm << " mm";
  }
  for (const FlankRelief* r : {&m.tip_relief, &m.root_relief, &m.end_relief}) {
    if (why.str().empty() && r->present() && !(1e-3 * r->amount_um < r->length_mm)) {
      why << "a relief of " << r->amount_um << " µm over " << r->length_mm
          << " mm is steeper than 45°: its amount must be below its length";
    }
  }
  return why.str();
}

InvoluteGear::InvoluteGear(const GearParameters& p) : parameters_(p) {
  const double m = p.module_mm;  // m_n
  const double x = p.profile_shift;
  alpha_ = deg_to_rad(p.pressure_angle_deg);
  beta_ = deg_to_rad(p.helix_angle_deg);
  // ISO 21771 §4.3: m_t = m_n / cos(beta), tan(alpha_t) = tan(alpha_n) / cos(beta),
  // sin(beta_b) = sin(beta) cos(alpha_n). A spur gear keeps alpha_n itself (atan(tan(a)) need
  // not give back a's last bit), so every spur quantity is the spur formula's, bit for bit.
  m_t_ = m / std::cos(beta_);
  alpha_t_ = beta_ == 0.0 ? alpha_ : std::atan(std::tan(alpha_) / std::cos(beta_));
  beta_b_ = std::asin(std::sin(beta_) * std::cos(alpha_));
  d_ = m_t_ * p.teeth;  // ISO 21771 (reference circle)
  d_a_ = p.tip_diameter_mm.value_or(d_ + 2.0 * m * (p.rack.addendum + x));
  d_f_ = p.root_diameter_mm.value_or(d_ - 2.0 * m * (p.rack.dedendum - x));
  d_b_ = d_ * std::cos(alpha_t_);
  p_b_ = kPi * m_t_ * std::cos(alpha_t_);
  tau_ = 2.0 * kPi / p.teeth;
  s_ = m_t_ * (kPi / 2.0 + 2.0 * x * std::tan(alpha_));  // s_t (ISO 21771 §5.3)
  theta_b_ = s_ / d_ + involute_function(alpha_t_);
  // The section's turn per mm of height: z tan(beta) / r = z tan(beta_b) / r_b (the same lead).
  turn_per_mm_ = beta_ == 0.0 ? 0.0 : hand_sign(p.hand) * std::tan(beta_) / (d_ / 2.0);

  // Form circle generated by the rack (ISO 21771 §5.4 construction): the rack's straight flank
  // ends where its tip fillet starts, h_FfP = h_tool - rho_fP (1 - sin alpha_n) above the datum
  // line (the normal section of the rack); h_tool is the rack height that cuts the root
  // (d - d_f)/2 + x m_n (= h_fP without a root override). That point generates the involute's
  // start on the transverse line of action, (h_FfP - x m_n)/sin(alpha_t) below the pitch point,
  // whose roll length is r sin(alpha_t) (heights are the same in the normal and the transverse
  // section of the rack).
  const double h_tool = (d_ - d_f_) / 2.0 + x * m;
  const double h_FfP = h_tool - p.rack.root_radius * m * (1.0 - std::sin(alpha_));
  const double L_form = d_ / 2.0 * std::sin(alpha_t_) - (h_FfP - x * m) / std::sin(alpha_t_);
  undercut_ = L_form < 0.0;
  L_form_ = undercut_ ? 0.0 : L_form;
  const double r_a = d_a_ / 2.0, r_b = d_b_ / 2.0;
  L_tip_ = r_a > r_b ? std::sqrt(r_a * r_a - r_b * r_b) : 0.0;
  if (p.modifications.any())
    modification_.emplace(p.modifications, L_form_, L_tip_, p.face_width_mm);
}

double InvoluteGear::lead_mm() const { return beta_ == 0.0 ? kInf : kPi * d_ / std::tan(beta_); }

double InvoluteGear::tip_thickness_mm() const {
  if (d_a_ <= d_b_) return 0.0;
  const double alpha_a = std::acos(d_b_ / d_a_);
  // Half tooth angle at radius r: s/d + inv(alpha) - inv(alpha_r).
  return d_a_ * (theta_b_ - involute_function(alpha_a));
}

double InvoluteGear::form_diameter_mm() const { return diameter_at_roll_length(L_form_); }

double InvoluteGear::roll_length_at_diameter(double diameter_mm) const {
  const double r = diameter_mm / 2.0, r_b = d_b_ / 2.0;
  return std::sqrt(std::max(0.0, r * r - r_b * r_b));
}

double InvoluteGear::diameter_at_roll_length(double roll_length_mm) const {
  const double r_b = d_b_ / 2.0;
  return 2.0 * std::sqrt(r_b * r_b + roll_length_mm * roll_length_mm);
}

double InvoluteGear::tooth_centre_angle_rad(int tooth) const { return (tooth - 1) * tau_; }

FlankPoint InvoluteGear::flank_point(int tooth, FlankSide side, double roll_length_mm,
                                     double z_mm) const {
  // R flank of a tooth centred on angle 0: the string unwinds clockwise from the base circle at
  // theta_b, so the base point sits at theta_b - xi (xi = L / r_b) and the normal, which is the
  // string direction, is e'(theta_b - xi); its tangential component at the flank point is
  // cos(atan xi) > 0, i.e. counter-clockwise, as docs/formats.md defines R. L is the mirror image.
  // dP/dL = (L / r_b) e(phi_b) for both sides: the profile tangent points away from the base.
  // The closed form itself is in gears/base_angle.h (shared with the contact solver).
  if (!helical()) {
    return flank_point_at(*this, side, roll_length_mm, z_mm,
                          base_angle(*this, tooth, side, roll_length_mm));
  }
  // Helical: the transverse section at z is the section at 0 turned by z helix_turn_per_mm, so
  // phi_b gains that angle; the transverse construction is the spur one (flank_point_at), then
  // the helicoid's normal tilts out of the transverse plane by beta_b (involute_gear.h).
  const BaseAngle turned = base_angle(*this, tooth, side, roll_length_mm, z_mm);
  FlankPoint fp = flank_point_at(*this, side, roll_length_mm, z_mm, turned);
  const double tilt = side_sign(side) * hand_sign(parameters_.hand);
  const Eigen::Vector3d n_t = fp.normal;
  fp.normal = std::cos(beta_b_) * n_t - tilt * std::sin(beta_b_) * Eigen::Vector3d::UnitZ();
  fp.base_point.z() = z_mm + tilt * roll_length_mm * std::tan(beta_b_);
  return fp;
}

}  // namespace gearmc
