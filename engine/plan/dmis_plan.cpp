// The probing plan as a DMIS program (see dmis_plan.h).
#include "engine/plan/dmis_plan.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <sstream>

namespace gearmc {
namespace {

constexpr double kDeg = 180.0 / std::numbers::pi;

// `v` with `decimals` decimals, never "-0.000…" (a value that rounds to zero is written 0).
std::string fixed_number(double v, int decimals) {
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, "%.*f", decimals, v);
  std::string text = buffer;
  if (text[0] == '-' && text.find_first_not_of("-0.") == std::string::npos) text.erase(0, 1);
  return text;
}

std::string xyz(const Eigen::Vector3d& p) {
  std::string out;
  for (int a = 0; a < 3; ++a) out += (a ? "," : "") + fixed_number(p[a], 6);
  return out;
}

// "x,y,z,i,j,k": point with 6 decimals (1 nm), unit vector with 9.
std::string point_and_vector(const Eigen::Vector3d& p, const Eigen::Vector3d& n) {
  std::string out = xyz(p);
  for (int a = 0; a < 3; ++a) out += "," + fixed_number(n[a], 9);
  return out;
}

// DMIS text strings are in single quotes; a quote inside is left out.
std::string quoted(const std::string& text) {
  std::string out = "'";
  for (char c : text) {
    if (c != '\'' && c != '\n' && c != '\r') out += c;
  }
  return out + "'";
}

// The sensor label of orientation `k` of `plan` (one sensor: STYLUS; one per trace of a radial
// stylus: STYLUS_<k+1>).
std::string sensor_label(const ClearancePlan& plan, int k) {
  if (plan.sensors.size() == 1) return "STYLUS";
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "STYLUS_%03d", k + 1);
  return buffer;
}

void point_measurement(std::ostream& out, const std::string& label, const Eigen::Vector3d& p,
                       const Eigen::Vector3d& n) {
  const std::string pv = point_and_vector(p, n);
  out << "F(" << label << ")=FEAT/POINT,CART," << pv << "\n";
  out << "MEAS/POINT,F(" << label << "),1\n";
  out << "PTMEAS/CART," << pv << "\n";
  out << "ENDMES\n";
}

// The operator's set-up step: the datum features measured by hand and the datum frame
// (dmis_plan.h).
void setup_step(std::ostream& out, const InvoluteGear& gear) {
  const double b = gear.face_width_mm(), d_a = gear.tip_diameter_mm();
  const double r_f = 0.5 * gear.root_diameter_mm();
  const double z_s = 0.5 * b;  // tooth 1's section
  const double L_ref = gear.roll_length_at_diameter(gear.reference_diameter_mm());
  const FlankPoint left = gear.flank_point(1, FlankSide::kLeft, L_ref, z_s);
  const FlankPoint right = gear.flank_point(1, FlankSide::kRight, L_ref, z_s);
  const double turn = z_s * gear.helix_turn_per_mm();  // tooth 1's centre line in section z_s
  const double r_ref = 0.5 * gear.reference_diameter_mm();
  const Eigen::Vector3d radial(std::cos(turn), std::sin(turn), 0.0);
  const Eigen::Vector3d tooth_centre = r_ref * radial + z_s * Eigen::Vector3d::UnitZ();
  // A point of the lower face: on the body inside the root circle (external), outside it
  // (ring gear).
  const double face_r = gear.internal() ? r_f + gear.module_mm() : 0.5 * r_f;
  out << "$$ ---- Operator's set-up step (by hand, MODE/MAN): align the gear before the "
         "program runs.\n"
      << "$$ gearmc's frame is this datum frame: DAT(A) the gear axis (the tip cylinder, "
         "d_a "
      << fixed_number(d_a, 4)
      << " mm) = +Z and the X, Y origin; DAT(B) the lower face = the Z origin (z = 0, upper "
         "face z = "
      << fixed_number(b, 4)
      << "); DAT(C) tooth 1 (midpoint of its flanks on the reference circle d = "
      << fixed_number(gear.reference_diameter_mm(), 4) << " mm, at z = " << fixed_number(z_s, 4)
      << ") on +X" << (gear.helical() ? ", turned back by the helix to the section z = 0" : "")
      << ".\n";
  out << "MODE/MAN\n";
  out << "TEXT/OPER,"
      << quoted(
             "Set-up: measure the tip cylinder, the lower face and both flanks of tooth 1 by "
             "hand; the datum frame of DATSET is the frame of the program")
      << "\n";
  out << "F(SETUP_AXIS)=FEAT/CYLNDR," << (gear.internal() ? "INNER" : "OUTER")
      << ",CART,0,0,0,0,0,1," << fixed_number(d_a, 6) << "," << fixed_number(b, 6) << "\n";
  out << "MEAS/CYLNDR,F(SETUP_AXIS),8\nENDMES\n";
  out << "F(SETUP_FACE)=FEAT/PLANE,CART," << fixed_number(face_r, 6) << ",0,0,0,0,-1\n";
  out << "MEAS/PLANE,F(SETUP_FACE),3\nENDMES\n";
  point_measurement(out, "SETUP_T1L", left.point, left.normal);
  point_measurement(out, "SETUP_T1R", right.point, right.normal);
  out << "F(SETUP_T1)=FEAT/POINT,CART," << point_and_vector(tooth_centre, radial) << "\n";
  out << "CONST/POINT,F(SETUP_T1),MIDPT,FA(SETUP_T1L),FA(SETUP_T1R)\n";
  out << "DATDEF/FA(SETUP_AXIS),DAT(A)\n";
  out << "DATDEF/FA(SETUP_FACE),DAT(B)\n";
  out << "DATDEF/FA(SETUP_T1),DAT(C)\n";
  out << "D(GEAR)=DATSET/DA(A),ZDIR,XORIG,YORIG,DA(B),ZORIG,DA(C),XDIR\n";
  if (gear.helical()) {
    out << "D(GEAR_Z0)=ROTATE/ZAXIS," << fixed_number(-turn * kDeg, 6) << "\n";
  }
  out << "TEXT/OPER,"
      << quoted(
             "Leave the stylus above the gear (higher than the upper face plus twice the "
             "ball diameter) before the program continues")
      << "\n";
  out << "$$ ---- End of the set-up step.\n";
}

void gotos(std::ostream& out, const std::vector<Eigen::Vector3d>& path) {
  for (const Eigen::Vector3d& p : path) out << "GOTO/" << xyz(p) << "\n";
}

}  // namespace

std::string dmis_point_label(int tooth, FlankSide side, int i, int j) {
  char buffer[48];
  std::snprintf(buffer, sizeof buffer, "T%03d%c_I%02d_J%02d", tooth,
                side == FlankSide::kRight ? 'R' : 'L', i, j);
  return buffer;
}

std::string dmis_program(const InvoluteGear& gear, const std::vector<PlannedPoint>& sequence,
                         const DmisProgramOptions& o) {
  const ClearancePlan plan =
      plan_clearance_moves(gear, sequence, o.stylus, o.approach_mm, o.clearance_mm);
  const PlanStylus& s = o.stylus;
  std::ostringstream out;
  out << "DMISMN/" << quoted(o.title) << ",05.3\n";
  for (const std::string& c : o.comments) out << "$$ " << c << "\n";
  out << "$$ " << sequence.size()
      << " points; FEAT/POINT = nominal point and outward normal, PTMEAS vector = approach "
         "vector (the probe travels along its negative)\n";
  out << "UNITS/MM,ANGDEC\n";
  const bool shaft = s.shaft != PlanShaftAxis::kNone && s.shaft_radius_mm > 0.0;
  out << "$$ Stylus: ball diameter " << fixed_number(2.0 * s.ball_radius_mm, 4) << " mm"
      << (shaft ? ", shaft diameter " + fixed_number(2.0 * s.shaft_radius_mm, 4) + " mm " +
                      (s.shaft == PlanShaftAxis::kAxial
                           ? "parallel to the gear axis, from above"
                           : "horizontal, radially out of the tooth space (one indexed "
                             "orientation per trace)")
                : ", shaft not given (vertical stylus assumed)")
      << "; INDEX,POL A = tilt from the vertical, B = turn about +Z from +X (ball-to-head "
         "direction (sin A cos B, sin A sin B, cos A)); length "
      << fixed_number(plan.stylus_length_mm, 3)
      << " mm = the least the clearance moves need (replace it by the qualified stylus's)\n";
  for (std::size_t k = 0; k < plan.sensors.size(); ++k) {
    const Eigen::Vector3d& u = plan.sensors[k].shaft_direction;
    const double A = std::acos(std::clamp(u.z(), -1.0, 1.0)) * kDeg;
    const double B = std::hypot(u.x(), u.y()) > 1e-12 ? std::atan2(u.y(), u.x()) * kDeg : 0.0;
    out << "S(" << sensor_label(plan, static_cast<int>(k)) << ")=SNSDEF/PROBE,INDEX,POL,"
        << fixed_number(A, 6) << "," << fixed_number(B, 6) << ",0,0,1,"
        << fixed_number(plan.stylus_length_mm, 3) << "," << fixed_number(2.0 * s.ball_radius_mm, 6)
        << "\n";
  }
  const int first_sensor = plan.touches.empty() ? 0 : plan.touches.front().sensor;
  out << "SNSLCT/S(" << sensor_label(plan, first_sensor) << ")\n";
  const std::string a = fixed_number(o.approach_mm, 3);
  out << "SNSET/APPRCH," << a << "\nSNSET/RETRCT," << a << "\nSNSET/SEARCH," << a << "\n";
  setup_step(out, gear);
  out << "MODE/AUTO,PROG,MAN\n";
  out << "$$ Clearance moves (GOTO = ball centre): within a trace from pre-position to "
         "pre-position (p + (R + a) n) where that stays clear, else "
      << (gear.helical() ? "radially out of the tooth space, " : "")
      << "up to z = " << fixed_number(plan.clearance_height_mm, 3)
      << ", across and down into the next tooth space; " << plan.direct_moves << " direct, "
      << plan.lifted_moves << " lifted\n";
  for (std::size_t k = 0; k < sequence.size(); ++k) {
    const PlannedPoint& q = sequence[k];
    const TouchMoves& t = plan.touches[k];
    gotos(out, t.lift);
    if (t.select_sensor && k > 0) out << "SNSLCT/S(" << sensor_label(plan, t.sensor) << ")\n";
    gotos(out, t.descent);
    const std::string label = dmis_point_label(q.tooth, q.side, q.i, q.j);
    point_measurement(out, label, q.point, q.normal);
    out << "OUTPUT/F(" << label << ")\nOUTPUT/FA(" << label << ")\n";
  }
  gotos(out, plan.final_lift);
  out << "ENDFIL\n";
  return out.str();
}

}  // namespace gearmc
