// Exact first contact of a spherical stylus tip with a real flank (P1's model, docs/sources.md):
// the tip centre moves along the nominal normal n towards the flank, O(t) = p + t n, and the
// first contact is the largest t at which the sphere of radius R touches the surface:
//   t* = max over (L, z) of  f(L, z) = w.n + sqrt(R^2 - |w_perp|^2),  w = S(L, z) - p,
// w_perp = w - (w.n) n. f is maximised by a safeguarded Newton iteration on its gradient
// (tangency), which finds the nearest local maximum; a certificate (contact_certificate.h)
// then proves that no point of the flank within the stylus's footprint (|w_perp| < R) has
// f > t* + kCertificateToleranceMm, i.e. rises above the found sphere by more than 1e-2 nm
// along n. Where it finds a higher point the Newton iteration restarts there (at most
// kMaxCertificateRestarts times); where it cannot prove the bound the point gets status
// kUncertified with the reason, and no value. Then C = S(L*, z*) (true contact point),
// O = p + t* n, the CMM reports E = O - R n, delta_Rcomp = |C - E| and the normal error is
// (E - C).n. Lengths mm; the errors in µm.
#pragma once

#include <Eigen/Core>

#include "engine/contact/contact_states.h"
#include "gears/base_angle.h"
#include "surfaces/analytic_flank.h"

namespace gearmc {

struct FlankCurvatureBound;  // contact_certificate.h

// The flank's parameter box: where the real flank exists (roll length from the form circle to
// the tip circle, z from 0 to b). A maximum that wants to leave it is an edge contact.
struct FlankExtent {
  double roll_length_min, roll_length_max, z_min, z_max;
};

struct ContactResult {
  enum class Status {
    kOk,            // converged to an interior tangency
    kEdge,          // the sphere touches the flank's edge first (collision, not a flank point)
    kCollision,     // the sphere meets another part of the tooth space first (see reason)
    kNotConverged,  // numerical failure: counted, never used as a value
    kUncertified,   // converged, but not proven the first contact (`failure` says why):
                    // counted with the failed contacts, never used as a value
  };
  Status status = Status::kNotConverged;
  Eigen::Vector3d contact;              // C, mm
  Eigen::Vector3d centre;               // O, mm
  Eigen::Vector3d reported;             // E = O - R n, mm
  double roll_length_mm = 0, z_mm = 0;  // parameters of C
  double delta_um = 0;                  // |C - E|
  double normal_error_um = 0;           // (E - C).n
  int iterations = 0;                   // Newton iterations, all restarts included
  int restarts = 0;                     // Newton restarts from a higher point the certificate found
  // kCollision: what the sphere meets (neighbour flank, root; on a mesh flank touching at the
  // start of the approach, mesh_probe.h).
  CollisionKind collision = CollisionKind::kNone;
  // kNotConverged: why, when it is not the Newton iteration's failure (no mesh contact: the
  // sphere passed a mesh flank without touching it, mesh_probe.h). kUncertified: the
  // certificate's reason (contact_certificate.h) or the restart cap. kNone otherwise.
  ContactFailure failure = ContactFailure::kNone;
};

// The stylus's pre-position distance outside the planned point along n (mm): where the
// approach that check_tooth_space checks starts.
inline constexpr double kProbeApproachMm = 1.0;

// How often the Newton iteration restarts from a higher point before the contact is given up
// as kUncertified ("restart_cap"). Each restart raises t* by more than the certificate's
// tolerance.
inline constexpr int kMaxCertificateRestarts = 8;

// p, n: planned point and nominal outward unit normal (datum frame, mm); R: tip radius (mm);
// (L0, z0): the flank parameters of p, the starting guess.
ContactResult solve_contact(const AnalyticFlank& flank, const FlankExtent& extent,
                            const Eigen::Vector3d& p, const Eigen::Vector3d& n, double R, double L0,
                            double z0);
// The same with the base point's angle at L0 given (gears/base_angle.h): the planned point's
// profile tangent is (cos, sin) of it (InvoluteGear::flank_point), so a caller holding the
// nominal flank point saves the solve's one sincos. `angle_at_L0` must be base_angle(gear,
// tooth, side, L0) of the flank; the other overload computes it. `flank_bound` (optional):
// flank_curvature_bound(flank, R, extent.roll_length_min, extent.roll_length_max)
// (contact_certificate.h), computed once for all of the flank's points: the certificate tries it
// before the point's own bound (same verdicts, fewer operations).
ContactResult solve_contact(const AnalyticFlank& flank, const FlankExtent& extent,
                            const Eigen::Vector3d& p, const Eigen::Vector3d& n, double R, double L0,
                            double z0, const BaseAngle& angle_at_L0,
                            const FlankCurvatureBound* flank_bound = nullptr);

// The objective f(L, z) above (mm), -infinity where the sphere cannot reach the point. Exposed
// for independent checks.
double contact_height(const AnalyticFlank& flank, const Eigen::Vector3d& p,
                      const Eigen::Vector3d& n, double R, double L, double z);

}  // namespace gearmc
