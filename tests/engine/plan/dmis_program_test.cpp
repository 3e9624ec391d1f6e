// Tests of the DMIS program `gearmc export-plan` writes (engine/plan/dmis_plan.h,
// engine/plan/clearance_moves.h), on the spur P1 gear (built in), the ring gear
// scenarios/ring_gear_z72.yaml, a helical gear (z 31, m_n 4, α_n 20°, β 15° right, x 0.2, b 40,
// as tests/engine/scenario/helical_scenario_test.cpp, with a 1 mm ball on a horizontal 0.8 mm
// shaft) and P1 with a 0.3 mm axial shaft:
//   - the grammar: every statement parses with the independent DMIS parser of
//     tests/support/dmis_grammar.h, and the program is consistent: units and sensor before the
//     first move, every feature defined before it is measured, constructed or output, every MEAS
//     closed by ENDMES, every planned point measured once and both its nominal and actual output;
//   - the collision sweep: every move the program makes (GOTO segments, the PTMEAS approach
//     and retract along the vector) replayed in straight segments between consecutive ball-centre
//     positions, the ball and the shaft sampled densely against an inside-the-tooth test written
//     here (ISO 21771's half tooth angle, not gearmc's contact code), the gear grown by 50 µm;
//     the old program's straight moves between the touches (the GOTOs removed) must collide, so
//     the sweep is known to see collisions.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <filesystem>
#include <map>
#include <numbers>
#include <set>
#include <string>
#include <vector>

#include "engine/plan/dmis_plan.h"
#include "engine/scenario/scenario.h"
#include "tests/support/dmis_grammar.h"
#include "tests/support/run_gearmc.h"
#include "tests/support/temp_paths.h"
#include "tests/support/text_files.h"

using ::gearmc::testing_support::fresh_temp_path;

namespace gearmc {
namespace {

namespace fs = std::filesystem;
using testing_support::DmisParseError;
using testing_support::DmisStatement;
using testing_support::DmisToken;
using testing_support::parse_dmis_program;
using testing_support::read_text;
using testing_support::run_gearmc;
using testing_support::write_text;

constexpr double kPi = std::numbers::pi;

struct Case {
  std::string name, yaml;  // yaml empty: the built-in P1
};

// The helical gear of tests/engine/scenario/helical_scenario_test.cpp (helical_yaml), probed with
// a horizontal stylus as gear-measuring machines do (docs/scenarios.md, "The stylus").
const std::string kHelicalYaml =
    "name: helical\n"
    "gear:\n"
    "  teeth: 31\n"
    "  module_mm: 4\n"
    "  pressure_angle_deg: 20\n"
    "  helix_angle_deg: 15\n"
    "  hand: right\n"
    "  profile_shift: 0.2\n"
    "  face_width_mm: 40\n"
    "tolerances: {standard: iso_1328_1_2013, grade: 6}\n"
    "stylus:\n"
    "  radius_mm: 1.0\n"
    "  shaft_diameter_mm: 0.8\n"
    "  shaft_axis: radial\n";

std::vector<Case> cases() {
  std::string p1_shaft = read_text(std::string(GEARMC_SOURCE_DIR) + "/scenarios/p1_reference.yaml");
  const std::size_t at = p1_shaft.find("  radius_mm: 0.5");
  p1_shaft.insert(p1_shaft.find('\n', at) + 1, "  shaft_diameter_mm: 0.3\n  shaft_axis: z\n");
  return {{"p1", ""},
          {"ring", read_text(std::string(GEARMC_SOURCE_DIR) + "/scenarios/ring_gear_z72.yaml")},
          {"helical", kHelicalYaml},
          {"p1_axial_shaft", p1_shaft}};
}

struct Exported {
  Scenario scenario;
  std::string program;
};

// The program `gearmc export-plan` writes for `c`.
Exported export_program(const Case& c) {
  const fs::path dir = fresh_temp_path("dmis_program_" + c.name);
  fs::remove_all(dir);
  fs::create_directories(dir);
  std::string args = "export-plan --format dmis --out " + (dir / "plan.dmi").string();
  Exported e;
  if (c.yaml.empty()) {
    e.scenario = reference_scenario();
  } else {
    write_text(dir / "s.yaml", c.yaml);
    args += " " + (dir / "s.yaml").string();
    e.scenario = parse_scenario(c.yaml, "s.yaml");
  }
  const auto r = run_gearmc(args);
  EXPECT_EQ(r.exit_code, 0) << r.err;
  e.program = read_text(dir / "plan.dmi");
  return e;
}

// The consistency of a parsed program; the problems found (empty: none).
std::vector<std::string> program_problems(const std::vector<DmisStatement>& st,
                                          const std::vector<std::string>& planned) {
  std::vector<std::string> bad;
  const auto where = [](const DmisStatement& s) { return "line " + std::to_string(s.line) + ": "; };
  if (st.empty() || st.front().major != "DMISMN") bad.push_back("does not start with DMISMN");
  if (st.empty() || st.back().major != "ENDFIL") bad.push_back("does not end with ENDFIL");
  std::set<std::string> sensors, features, measured, datums, output_f, output_fa;
  std::vector<std::string> measure_order;
  bool units = false, selected = false, in_meas = false;
  int touches_in_meas = 0;
  std::string meas_label;
  for (const DmisStatement& s : st) {
    const std::string& m = s.major;
    if (m == "UNITS") units = true;
    if (m == "SNSDEF") sensors.insert(s.defines_name);
    if (m == "SNSLCT") {
      if (!sensors.count(s.param(0).text)) bad.push_back(where(s) + "SNSLCT of an undefined S");
      selected = true;
    }
    if ((m == "GOTO" || m == "MEAS" || m == "PTMEAS") && !(units && selected && !sensors.empty())) {
      bad.push_back(where(s) + m + " before UNITS, SNSDEF and SNSLCT");
    }
    if (m == "FEAT") {
      if (!features.insert(s.defines_name).second) bad.push_back(where(s) + "defined twice");
    }
    if (m == "MEAS") {
      if (in_meas) bad.push_back(where(s) + "MEAS inside MEAS");
      meas_label = s.param(1).text;
      if (!features.count(meas_label)) bad.push_back(where(s) + "MEAS of undefined " + meas_label);
      in_meas = true;
      touches_in_meas = 0;
    }
    if (m == "PTMEAS") {
      if (!in_meas) bad.push_back(where(s) + "PTMEAS outside MEAS");
      ++touches_in_meas;
    }
    if (m == "GOTO" && in_meas) bad.push_back(where(s) + "GOTO inside MEAS");
    if (m == "ENDMES") {
      if (!in_meas) bad.push_back(where(s) + "ENDMES without MEAS");
      in_meas = false;
      measured.insert(meas_label);
      if (meas_label.rfind("SETUP_", 0) != 0) {
        measure_order.push_back(meas_label);
        if (touches_in_meas != 1) bad.push_back(where(s) + meas_label + ": not one PTMEAS");
      }
    }
    if (m == "CONST") {
      if (!features.count(s.param(1).text)) bad.push_back(where(s) + "CONST of undefined");
      for (int k : {3, 4}) {
        if (!measured.count(s.param(k).text)) bad.push_back(where(s) + "CONST of unmeasured");
      }
      measured.insert(s.param(1).text);
    }
    if (m == "DATDEF") {
      if (!measured.count(s.param(0).text)) bad.push_back(where(s) + "DATDEF of unmeasured");
      datums.insert(s.param(1).text);
    }
    if (m == "DATSET") {
      for (int k : {0, 4, 6}) {
        if (!datums.count(s.param(k).text)) bad.push_back(where(s) + "DATSET of undefined datum");
      }
    }
    if (m == "OUTPUT") {
      const DmisToken& f = s.param(0);
      const bool actual = f.label_type == "FA";
      if (!features.count(f.text)) bad.push_back(where(s) + "OUTPUT of undefined " + f.text);
      if (actual && !measured.count(f.text)) bad.push_back(where(s) + "OUTPUT/FA of unmeasured");
      if (!(actual ? output_fa : output_f).insert(f.text).second) {
        bad.push_back(where(s) + "output twice");
      }
    }
  }
  if (in_meas) bad.push_back("MEAS without ENDMES at the end");
  if (measure_order != planned) bad.push_back("the measured points are not the plan in order");
  for (const std::string& p : planned) {
    if (!output_f.count(p) || !output_fa.count(p)) bad.push_back(p + " not output");
  }
  return bad;
}

std::vector<std::string> planned_labels(const Scenario& s) {
  std::vector<std::string> out;
  for (const PlannedPoint& q : probing_sequence(InvoluteGear(s.gear), s.probing)) {
    out.push_back(dmis_point_label(q.tooth, q.side, q.i, q.j));
  }
  return out;
}

TEST(DmisProgram, EveryStatementParsesAndTheProgramIsConsistent) {
  for (const Case& c : cases()) {
    SCOPED_TRACE(c.name);
    const Exported e = export_program(c);
    std::vector<DmisStatement> st;
    try {
      st = parse_dmis_program(e.program);
    } catch (const DmisParseError& error) {
      ADD_FAILURE() << error.what();
      continue;
    }
    const std::vector<std::string> problems = program_problems(st, planned_labels(e.scenario));
    EXPECT_TRUE(problems.empty()) << problems.size() << " problems, first: " << problems[0];
    // The stylus the scenario gives: ball diameter 2R on every sensor.
    int sensors = 0;
    for (const DmisStatement& s : st) {
      if (s.major != "SNSDEF") continue;
      ++sensors;
      EXPECT_NEAR(s.param(9).number, 2.0 * e.scenario.stylus_radius_mm, 1e-9);
    }
    EXPECT_GE(sensors, 1);
    // The set-up step: three datums and the frame.
    EXPECT_NE(e.program.find("D(GEAR)=DATSET/DA(A),ZDIR,XORIG,YORIG,DA(B),ZORIG,DA(C),XDIR"),
              std::string::npos);
  }
  // The checks can fail: the parser refuses statements outside the vocabulary or with the
  // wrong parameters, the consistency check a MEAS left open and an output of an undefined
  // feature.
  EXPECT_THROW(parse_dmis_program("DMISMN/'x',05.3\nGOTO/1,2\n"), DmisParseError);
  EXPECT_THROW(parse_dmis_program("DMISMN/'x',05.3\nFLY/1.0\n"), DmisParseError);
  EXPECT_THROW(parse_dmis_program("F(A)=FEAT/POINT,CART,1,2,3,0,0\n"), DmisParseError);
  EXPECT_THROW(parse_dmis_program("GOTO/1,2,3$\n"), DmisParseError);
  EXPECT_THROW(parse_dmis_program("OUTPUT/F(A B)\n"), DmisParseError);
  const auto broken = parse_dmis_program(
      "DMISMN/'x',05.3\nUNITS/MM,ANGDEC\nS(P)=SNSDEF/PROBE,INDEX,POL,0,0,0,0,1,50,1\n"
      "SNSLCT/S(P)\nF(T001L_I00_J00)=FEAT/POINT,CART,1,2,3,$\n 1,0,0\n"
      "MEAS/POINT,F(T001L_I00_J00),1\nPTMEAS/CART,1,2,3,1,0,0\nOUTPUT/F(B)\nENDFIL\n");
  // OUTPUT of the undefined F(B), the MEAS left open, so T001L_I00_J00 neither counted as measured
  // in the plan's order nor output: 4 problems.
  EXPECT_EQ(program_problems(broken, {"T001L_I00_J00"}).size(), 4u);
}

// ---- The collision sweep ------------------------------------------------------------------

// The nominal gear's solid, independent of gearmc's flank and contact code: in the transverse
// section at height z (turned back by the helix, z·2 tan β / d, counter-clockwise for a right
// hand, ISO 21771), a point at radius r lies in tooth k's material when r is between the root
// and the tip circle and its angle from the tooth's centre line is within the half tooth angle
// ψ(r) = s_t/d + inv α_t − inv α_r (ISO 21771 §5.3; a ring gear's tooth widens outward:
// ψ(r) = s_t/d − inv α_t + inv α_r), below the base circle ψ(r_b) (a radial flank); plus the body
// inside the root circle (a ring gear's outside it) for 0 ≤ z ≤ b. Grown by g: the radii and
// faces by g, the angle by g/r.
struct SolidGear {
  explicit SolidGear(const Scenario& s) {
    const GearParameters& p = s.gear;
    const InvoluteGear g(p);  // only its tip and root diameters (overridable in the scenario)
    z = p.teeth;
    internal = p.internal;
    b = p.face_width_mm;
    const double beta = p.helix_angle_deg * kPi / 180, alpha_n = p.pressure_angle_deg * kPi / 180;
    const double m_t = p.module_mm / std::cos(beta);
    alpha_t = std::atan(std::tan(alpha_n) / std::cos(beta));
    d = m_t * z;
    r_b = 0.5 * d * std::cos(alpha_t);
    s_t = m_t * (kPi / 2 + 2 * p.profile_shift * std::tan(alpha_n));
    turn_per_mm = (p.hand == Hand::kRight ? 1.0 : -1.0) * 2 * std::tan(beta) / d;
    r_a = 0.5 * g.tip_diameter_mm();
    r_f = 0.5 * g.root_diameter_mm();
  }
  static double inv(double a) { return std::tan(a) - a; }
  bool inside(const Eigen::Vector3d& x, double grow) const {
    if (x.z() < -grow || x.z() > b + grow) return false;
    const double r = std::hypot(x.x(), x.y());
    if (!internal) {
      if (r > r_a + grow) return false;
      if (r < r_f + grow) return true;
    } else {
      if (r < r_a - grow) return false;
      if (r > r_f - grow) return true;
    }
    const double turn = std::clamp(x.z(), 0.0, b) * turn_per_mm;
    const double tau = 2 * kPi / z;
    const double delta = std::abs(std::remainder(std::atan2(x.y(), x.x()) - turn, tau));
    const double alpha_r = std::acos(std::min(1.0, r_b / r));
    const double psi =
        internal ? s_t / d - inv(alpha_t) + inv(alpha_r) : s_t / d + inv(alpha_t) - inv(alpha_r);
    return delta <= psi + grow / r;
  }
  // True when no point within `rho` of x lies in the solid grown by `grow` (conservative: every
  // such point has its radius within r ± rho, its height within z ± rho, its polar angle within
  // asin(rho / r) of x's; ψ is monotonic in r, the helix turns the section by at most
  // rho |dturn/dz|). Lets the sweep skip the ball's surface far from the teeth.
  bool clear(const Eigen::Vector3d& x, double rho, double grow) const {
    if (x.z() > b + grow + rho || x.z() < -grow - rho) return true;
    const double r = std::hypot(x.x(), x.y());
    if (r <= 2 * rho) return false;
    if (!internal) {
      if (r - rho > r_a + grow) return true;
      if (r - rho <= r_f + grow) return false;
    } else {
      if (r + rho < r_a - grow) return true;
      if (r + rho >= r_f - grow) return false;
    }
    const double r_min = r - rho, r_psi = internal ? r + rho : r_min;
    const double alpha = std::acos(std::min(1.0, r_b / r_psi));
    const double psi_max =
        internal ? s_t / d - inv(alpha_t) + inv(alpha) : s_t / d + inv(alpha_t) - inv(alpha);
    const double turn = std::clamp(x.z(), 0.0, b) * turn_per_mm;
    const double delta = std::abs(std::remainder(std::atan2(x.y(), x.x()) - turn, 2 * kPi / z));
    const double spread = std::asin(rho / r) + rho * std::abs(turn_per_mm);
    return delta - spread > psi_max + grow / r_min;
  }
  int z;
  bool internal;
  double b, alpha_t, d, r_b, s_t, turn_per_mm, r_a, r_f;
};

constexpr double kGrowMm = 0.05;      // the gear grown by 50 µm (form and set-up errors)
constexpr double kStepMm = 0.1;       // ball centres along each segment
constexpr double kShaftStepMm = 0.2;  // along the shaft's axis
constexpr int kBallPoints = 400;      // on the ball's surface (Fibonacci sphere)
constexpr int kShaftRingPoints = 12;  // around the shaft's axis

// Resolution: with 400 points the ball's surface is sampled every ~0.18 R (0.09 mm for
// R = 0.5 mm, 0.18 mm for R = 1 mm), so a flat of the grown solid entering the ball deeper than
// R (1 − cos 0.09) ≈ 0.004 R (2 µm, 4 µm) is seen for sure, a tooth's tip corner (about a right
// angle) deeper than about half the spacing (45 µm, 90 µm); consecutive centres 0.1 mm apart add
// 0.1² / (8 R) (2.5 µm, 1.3 µm). The shaft: 12 points around its axis every 0.2 mm.
std::vector<Eigen::Vector3d> sphere_points() {
  std::vector<Eigen::Vector3d> out;
  const double golden = kPi * (3 - std::sqrt(5.0));
  for (int k = 0; k < kBallPoints; ++k) {
    const double y = 1 - 2 * (k + 0.5) / kBallPoints, r = std::sqrt(1 - y * y);
    out.emplace_back(r * std::cos(golden * k), y, r * std::sin(golden * k));
  }
  return out;
}

struct Collision {
  int line;           // the statement that made the move
  std::string after;  // the last touch before it
  std::string part;   // ball or shaft
  Eigen::Vector3d centre;
};

struct SweepResult {
  std::vector<Collision> collisions;  // at most one per segment
  int segments = 0;
  long centres = 0;
  long sampled = 0;  // centres near the teeth, where the ball's surface was sampled
};

// Replays the moves of `st` (from the first GOTO or PTMEAS after MODE/AUTO; with `drop_gotos`
// the GOTOs are left out, i.e. the old program's straight moves from touch to touch).
// With `straight_up` the GOTOs are left out too and each touch is followed by a lift straight up
// along +Z to 5 mm above the gear (the spur gear's way out, wrong for a helical gear).
SweepResult sweep(const std::vector<DmisStatement>& st, const Scenario& s, bool drop_gotos,
                  bool straight_up = false) {
  const SolidGear gear(s);
  const std::vector<Eigen::Vector3d> sphere = sphere_points();
  std::map<std::string, std::pair<Eigen::Vector3d, double>> sensors;  // direction, length
  double R = 0, apprch = 0, retrct = 0;
  const double r_s = 0.5 * s.stylus_shaft_diameter_mm;
  Eigen::Vector3d shaft = Eigen::Vector3d::UnitZ();
  double shaft_length = 0;
  bool automatic = false, have_position = false;
  Eigen::Vector3d at;
  std::string after = "(start)", current_feature;
  SweepResult result;
  long& sampled = result.sampled;
  const auto ball_hits = [&](const Eigen::Vector3d& c) {
    // Out of reach of the grown solid: above, below, beyond the tip circle (inside a ring
    // gear's).
    const double reach = R + kGrowMm, r = std::hypot(c.x(), c.y());
    if (c.z() > gear.b + reach || c.z() < -reach) return false;
    if (gear.internal ? r < gear.r_a - reach : r > gear.r_a + reach) return false;
    if (gear.clear(c, R, kGrowMm)) return false;
    ++sampled;
    if (gear.inside(c, kGrowMm)) return true;
    for (const Eigen::Vector3d& d : sphere) {
      if (gear.inside(c + R * d, kGrowMm)) return true;
    }
    return false;
  };
  const auto shaft_hits = [&](const Eigen::Vector3d& c) {
    if (r_s <= 0) return false;
    const Eigen::Vector3d e1 = shaft.unitOrthogonal(), e2 = shaft.cross(e1);
    for (double t = std::sqrt(R * R - r_s * r_s); t <= shaft_length; t += kShaftStepMm) {
      const Eigen::Vector3d a = c + t * shaft;
      if (!gear.clear(a, r_s, kGrowMm)) {  // near the solid: the ring around the axis
        for (int k = 0; k < kShaftRingPoints; ++k) {
          const double phi = 2 * kPi * k / kShaftRingPoints;
          if (gear.inside(a + r_s * (std::cos(phi) * e1 + std::sin(phi) * e2), kGrowMm)) {
            return true;
          }
        }
        if (gear.inside(a, kGrowMm)) return true;
      }
    }
    return false;
  };
  // A straight move of the ball centre from `from` to `to`; the ball is not checked in the last
  // (first) `skip_end` (`skip_start`) mm: the touch itself meets the flank.
  const auto move = [&](const Eigen::Vector3d& from, const Eigen::Vector3d& to, int line,
                        double skip_start, double skip_end) {
    ++result.segments;
    const double length = (to - from).norm();
    const int steps = std::max(1, static_cast<int>(std::ceil(length / kStepMm)));
    for (int k = 0; k <= steps; ++k) {
      const double t = length * k / steps;
      const Eigen::Vector3d c =
          length > 0 ? Eigen::Vector3d(from + (t / length) * (to - from)) : from;
      ++result.centres;
      const bool check_ball = t >= skip_start && t <= length - skip_end;
      std::string part = check_ball && ball_hits(c) ? "ball" : shaft_hits(c) ? "shaft" : "";
      if (!part.empty()) {
        result.collisions.push_back({line, after, part, c});
        return;
      }
    }
  };
  for (const DmisStatement& x : st) {
    if (x.major == "SNSDEF") {
      const double A = x.param(3).number * kPi / 180, B = x.param(4).number * kPi / 180;
      sensors[x.defines_name] = {
          {std::sin(A) * std::cos(B), std::sin(A) * std::sin(B), std::cos(A)}, x.param(8).number};
      R = 0.5 * x.param(9).number;
    } else if (x.major == "SNSLCT") {
      std::tie(shaft, shaft_length) = sensors.at(x.param(0).text);
    } else if (x.major == "SNSET") {
      if (x.param(0).text == "APPRCH") apprch = x.param(1).number;
      if (x.param(0).text == "RETRCT") retrct = x.param(1).number;
    } else if (x.major == "MODE") {
      automatic = x.param(0).text == "AUTO";
    } else if (x.major == "FEAT") {
      current_feature = x.defines_name;
    } else if (automatic && x.major == "GOTO" && !drop_gotos) {
      const Eigen::Vector3d to(x.param(0).number, x.param(1).number, x.param(2).number);
      if (have_position) move(at, to, x.line, 0, 0);
      at = to;
      have_position = true;
    } else if (automatic && x.major == "PTMEAS") {
      const Eigen::Vector3d p(x.param(1).number, x.param(2).number, x.param(3).number);
      const Eigen::Vector3d v =
          Eigen::Vector3d(x.param(4).number, x.param(5).number, x.param(6).number).normalized();
      const Eigen::Vector3d approach = p + (R + apprch) * v, touch = p + R * v;
      const Eigen::Vector3d retract = p + (R + retrct) * v;
      const double skip = kGrowMm + 1e-3 * R;
      if (have_position) move(at, approach, x.line, 0, 0);
      move(approach, touch, x.line, 0, skip);
      move(touch, retract, x.line, skip, 0);
      at = retract;
      have_position = true;
      after = current_feature;
      if (straight_up) {
        move(retract, {retract.x(), retract.y(), gear.b + 5}, x.line, 0, 0);
        have_position = false;
      }
    }
  }
  return result;
}

TEST(DmisProgram, NoMoveOfTheProgramHitsTheGearButTheOldStraightMovesDo) {
  for (const Case& c : cases()) {
    SCOPED_TRACE(c.name);
    const Exported e = export_program(c);
    const std::vector<DmisStatement> st = parse_dmis_program(e.program);
    const SweepResult r = sweep(st, e.scenario, false);
    EXPECT_GT(r.segments, 3 * static_cast<int>(planned_labels(e.scenario).size()));
    EXPECT_TRUE(r.collisions.empty())
        << r.collisions.size() << " of " << r.segments << " moves collide; first: line "
        << r.collisions[0].line << " after " << r.collisions[0].after << ", "
        << r.collisions[0].part << " at " << r.collisions[0].centre.transpose();
    std::printf(
        "[ sweep    ] %s: %d moves, %ld ball centres (%ld near the teeth), %zu collisions\n",
        c.name.c_str(), r.segments, r.centres, r.sampled, r.collisions.size());
    if (c.name == "helical") {
      // Straight up out of a helical gear's space (the space turns under the stylus, 0.27 mm
      // per mm of height at the reference circle: tan 15° / 1): most lifts hit a flank, so the
      // program's radial lift is needed and the sweep sees the difference.
      const SweepResult up = sweep(st, e.scenario, true, true);
      std::printf("[ sweep    ] helical lifted straight up: %zu of %d moves collide\n",
                  up.collisions.size(), up.segments);
      EXPECT_GT(up.collisions.size(), planned_labels(e.scenario).size() / 2);
    }
    if (c.name != "p1") continue;
    // The old program (no GOTO: from each touch's retract point straight to the next touch's
    // approach point): the move from tooth 1's L flank (its last point T001L_I09_J04) to its R
    // flank crosses the tooth, and so does every tooth's; the sweep must see them.
    const SweepResult old = sweep(st, e.scenario, true);
    std::set<std::string> after;
    for (const Collision& k : old.collisions) after.insert(k.after);
    std::printf("[ sweep    ] p1 without the clearance moves: %zu of %d moves collide\n",
                old.collisions.size(), old.segments);
    EXPECT_TRUE(after.count("T001L_I09_J04"));
    for (int tooth = 1; tooth <= 24; ++tooth) {
      EXPECT_TRUE(after.count(dmis_point_label(tooth, FlankSide::kLeft, 9, 4))) << tooth;
    }
  }
}

}  // namespace
}  // namespace gearmc
