// The stylus in the tooth space (tooth_space.h): clearances of ball and shaft along the
// approach, against the nominal flanks in transverse sections.
#include "engine/contact/tooth_space.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

namespace gearmc {
namespace {

// Distance (mm) in the transverse plane from point X to the nominal flank `side` of `tooth`,
// limited to the flank's real extent (the active profile): closed form along the normal when
// the foot lies on the flank (InvoluteGear::transverse_position), else the distance to the end.
double distance_to_flank(const InvoluteGear& gear, int tooth, FlankSide side,
                         const Eigen::Vector2d& X) {
  const TransversePosition at = gear.transverse_position(tooth, side, X);
  const double L_min = gear.active_roll_length_min_mm(), L_max = gear.active_roll_length_max_mm();
  if (at.foot_roll_length_mm >= L_min && at.foot_roll_length_mm <= L_max) {
    return std::abs(at.distance_mm);
  }
  const double L_end = at.foot_roll_length_mm < L_min ? L_min : L_max;
  return (gear.flank_point(tooth, side, L_end, 0.0).point.head<2>() - X).norm();
}

struct FlankRef {
  int tooth;
  FlankSide side;
};

// The flank facing `side` of `tooth` across the tooth space: R of tooth k faces L of tooth k+1;
// L of tooth k faces R of tooth k-1.
FlankRef facing_flank(const InvoluteGear& gear, int tooth, FlankSide side) {
  const int z = gear.teeth();
  return side == FlankSide::kRight ? FlankRef{tooth % z + 1, FlankSide::kLeft}
                                   : FlankRef{(tooth + z - 2) % z + 1, FlankSide::kRight};
}

// X (transverse coordinates at height z, mm) turned back to the z = 0 section: a helical gear's
// section turns by z helix_turn_per_mm.
Eigen::Vector2d in_base_section(const InvoluteGear& gear, const Eigen::Vector2d& X, double z) {
  if (!gear.helical()) return X;
  const double turn = -z * gear.helix_turn_per_mm();
  const double cs = std::cos(turn), sn = std::sin(turn);
  return Eigen::Vector2d(cs * X.x() - sn * X.y(), sn * X.x() + cs * X.y());
}

// The flank's transverse distance from X in the section at height z (mm).
double section_distance(const InvoluteGear& gear, FlankRef flank, const Eigen::Vector2d& X,
                        double z) {
  return distance_to_flank(gear, flank.tooth, flank.side, in_base_section(gear, X, z));
}

// cos(beta_a), beta_a the steepest helix angle on the tooth (at the tip circle of an external
// gear, the root circle of an internal one; tan(beta_y) = tan(beta) d_y / d): a transverse
// distance d_t to a flank times it is a lower bound of the distance in space (see
// tooth_space_clearance). 1 for a spur gear.
double steepest_helix_cos(const InvoluteGear& gear) {
  if (!gear.helical()) return 1.0;
  const double d_steepest = std::max(gear.tip_diameter_mm(), gear.root_diameter_mm());
  return std::cos(
      std::atan(std::tan(gear.helix_angle_rad()) * d_steepest / gear.reference_diameter_mm()));
}

// A lower bound of min g over [a, b] for g Lipschitz with constant `lipschitz`: on [a, b],
// g >= (g(a) + g(b))/2 - lipschitz (b - a)/2, so a branch and bound splits the intervals whose
// bound lies more than kShaftTolerance below the smallest value seen (and below kShaftEnough,
// where the exact value no longer matters). The result is <= min g and >= min(min g -
// kShaftTolerance, kShaftEnough) (or, after kShaftMaxEvaluations, still <= min g).
constexpr double kShaftTolerance = 1e-4;  // mm
constexpr double kShaftEnough = 0.1;      // mm
constexpr int kShaftMaxEvaluations = 4096;

template <class G>
double lipschitz_minimum(const G& g, double a, double b, double lipschitz) {
  struct Bracket {
    double a, b, ga, gb;
  };
  std::vector<Bracket> open{{a, b, g(a), g(b)}};
  double best = std::min(open.front().ga, open.front().gb);
  double lower = std::numeric_limits<double>::infinity();
  int evaluations = 2;
  while (!open.empty()) {
    const Bracket I = open.back();
    open.pop_back();
    const double bound = 0.5 * (I.ga + I.gb) - 0.5 * lipschitz * (I.b - I.a);
    if (bound >= best - kShaftTolerance || bound >= kShaftEnough ||
        evaluations >= kShaftMaxEvaluations) {
      lower = std::min(lower, bound);  // g >= bound on I
      continue;
    }
    const double m = 0.5 * (I.a + I.b), gm = g(m);
    ++evaluations;
    best = std::min(best, gm);
    open.push_back({I.a, m, I.ga, gm});
    open.push_back({m, I.b, gm, I.gb});
  }
  return lower;
}

// A shaft parallel to the axis (ShaftAxis::kZ): the cylinder of radius r_s about the vertical
// line through the ball centre (x, y, z_0), from z_0 up to the top face z = b. Its section at
// height z is the disc of radius r_s about (x, y); the disc meets the tooth's section where the
// distance from (x, y) to one of the space's flanks (limited to their active profile, so the tip
// corners count) falls below r_s or where it crosses the root circle: exact in every section.
// (Checked from where the shaft leaves the ball, z_0 + sqrt(R^2 - r_s^2).)
// g(z) = min(d_probed(z), d_facing(z)) - r_s is Lipschitz in z with constant |(x, y)|
// |helix_turn_per_mm| (the turned point moves that fast, distances are 1-Lipschitz in it). A
// spur gear's sections do not turn: g is constant, two evaluations.
double axial_shaft_clearance(const InvoluteGear& gear, FlankRef probed, FlankRef facing,
                             const Eigen::Vector3d& centre, double r_s, double out_of_ball) {
  const double z_top = gear.face_width_mm(), z_0 = centre.z() + out_of_ball;
  if (z_0 >= z_top) return std::numeric_limits<double>::infinity();
  const Eigen::Vector2d X = centre.head<2>();
  const auto g = [&](double z) {
    return std::min(section_distance(gear, probed, X, z), section_distance(gear, facing, X, z)) -
           r_s;
  };
  return lipschitz_minimum(g, z_0, z_top, X.norm() * std::abs(gear.helix_turn_per_mm()));
}

// A radial shaft (ShaftAxis::kRadial, a horizontal stylus reaching into the space from outside
// the gear, or from the axis into a ring gear): the cylinder of radius r_s about the segment
// in the transverse plane of the ball centre from the centre along the radius, outwards to the
// tip circle plus r_s (inwards to the ring's tip circle minus r_s), beyond which no tooth can
// touch it. Its points Y(s) at arc length s lie d_t(Y) cos(beta_a) or more from a flank in
// space (the bound of the ball's check); g(s) = cos(beta_a) min(d_probed, d_facing)(Y(s)) - r_s
// is 1-Lipschitz in s.
double radial_shaft_clearance(const InvoluteGear& gear, FlankRef probed, FlankRef facing,
                              const Eigen::Vector3d& centre, double r_s, double out_of_ball) {
  const Eigen::Vector2d X = centre.head<2>();
  const double r = X.norm(), r_tip = 0.5 * gear.tip_diameter_mm();
  const double length = gear.internal() ? r - (r_tip - r_s) : r_tip + r_s - r;
  if (length <= out_of_ball || r == 0.0) return std::numeric_limits<double>::infinity();
  const Eigen::Vector2d along = (gear.internal() ? -1.0 : 1.0) * X / r;
  const double cos_helix = steepest_helix_cos(gear);
  const auto g = [&](double s) {
    const Eigen::Vector2d Y = X + s * along;
    return cos_helix * std::min(section_distance(gear, probed, Y, centre.z()),
                                section_distance(gear, facing, Y, centre.z())) -
           r_s;
  };
  return lipschitz_minimum(g, out_of_ball, length, 1.0);
}

double shaft_clearance(const InvoluteGear& gear, FlankRef probed, FlankRef facing,
                       const Eigen::Vector3d& centre, const StylusShape& stylus) {
  const double r_s = stylus.shaft_radius_mm;
  const double r = centre.head<2>().norm(), r_root = 0.5 * gear.root_diameter_mm();
  const double root = gear.internal() ? r_root - r - r_s : r - r_s - r_root;
  // The shaft leaves the ball sqrt(R^2 - r_s^2) from its centre; inside it the ball's own
  // clearance covers it.
  const double out_of_ball =
      std::sqrt(std::max(0.0, stylus.radius_mm * stylus.radius_mm - r_s * r_s));
  return std::min(root,
                  stylus.shaft_axis == ShaftAxis::kZ
                      ? axial_shaft_clearance(gear, probed, facing, centre, r_s, out_of_ball)
                      : radial_shaft_clearance(gear, probed, facing, centre, r_s, out_of_ball));
}

}  // namespace

double ToothSpaceClearance::smallest() const {
  return std::min({facing_flank_mm, root_mm, shaft_mm});
}

double shaft_clearance(const InvoluteGear& gear, int tooth, FlankSide side,
                       const Eigen::Vector3d& centre, const StylusShape& stylus) {
  if (stylus.shaft_radius_mm <= 0.0) return std::numeric_limits<double>::infinity();
  return shaft_clearance(gear, FlankRef{tooth, side}, facing_flank(gear, tooth, side), centre,
                         stylus);
}

ToothSpaceClearance tooth_space_clearance(const InvoluteGear& gear, int tooth, FlankSide side,
                                          const Eigen::Vector3d& centre, const Eigen::Vector3d& n,
                                          const StylusShape& stylus, double approach_mm) {
  const double R = stylus.radius_mm;
  const double r_root = 0.5 * gear.root_diameter_mm();
  const bool internal = gear.internal();  // an internal gear's root lies outside its flanks
  // Along the approach the sphere moves away from the facing flank and up from the root; check
  // the path at a few stations (start, middle, end) — enough for a straight approach.
  const Eigen::Vector3d start = centre + approach_mm * n;
  constexpr double kClear = std::numeric_limits<double>::infinity();
  ToothSpaceClearance c{kClear, kClear, kClear};
  const FlankRef probed{tooth, side}, facing = facing_flank(gear, tooth, side);
  // A helical gear: the station's transverse section turned back to z = 0 (the section turns by
  // z helix_turn_per_mm), the transverse distance there, times cos(beta_a), beta_a the helix
  // angle at the tip circle (tan(beta_a) = tan(beta) r_a / r, the steepest helix on the tooth):
  // a lower bound of the distance in space (the flank's tangent plane at the transverse foot
  // supports the locally convex tooth and lies d_t cos(beta_b) >= d_t cos(beta_a) away; the tip
  // edge, a helix of angle beta_a, at least d_t cos(beta_a)). The approach is then never passed
  // as clear when it is not; it may be refused a few per cent early. An internal gear's flank is
  // concave but still an involute helicoid of the base cylinder: the points at transverse
  // distance d_t from it lie on a parallel helicoid d_t cos(beta_b) away (gear flanks of one base
  // cylinder and lead are equidistant); its steepest helix, at the root side, gives the factor.
  const bool helical = gear.helical();
  const double cos_tip_helix = steepest_helix_cos(gear);
  for (double a : {0.0, 0.25, 0.5, 0.75, 1.0}) {
    const Eigen::Vector3d station = start + a * (centre - start);
    const Eigen::Vector2d X = in_base_section(gear, station.head<2>(), station.z());
    const double d = distance_to_flank(gear, facing.tooth, facing.side, X);
    c.facing_flank_mm = std::min(c.facing_flank_mm, (helical ? cos_tip_helix * d : d) - R);
    c.root_mm = std::min(c.root_mm, internal ? r_root - X.norm() - R : X.norm() - R - r_root);
    if (stylus.shaft_radius_mm > 0.0) {
      c.shaft_mm = std::min(c.shaft_mm, shaft_clearance(gear, probed, facing, station, stylus));
    }
  }
  return c;
}

void check_tooth_space(const InvoluteGear& gear, int tooth, FlankSide side,
                       const Eigen::Vector3d& n, const StylusShape& stylus, double approach_mm,
                       ContactResult* result) {
  if (result->status != ContactResult::Status::kOk) return;
  const ToothSpaceClearance c =
      tooth_space_clearance(gear, tooth, side, result->centre, n, stylus, approach_mm);
  if (c.facing_flank_mm < 0.0) {
    result->status = ContactResult::Status::kCollision;
    result->collision = CollisionKind::kNeighbourFlank;
  } else if (c.root_mm < 0.0) {
    result->status = ContactResult::Status::kCollision;
    result->collision = CollisionKind::kRoot;
  } else if (c.shaft_mm < 0.0) {
    result->status = ContactResult::Status::kCollision;
    result->collision = CollisionKind::kShaft;
  }
}

}  // namespace gearmc
