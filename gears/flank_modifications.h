// Designed flank modifications: the design flank is the involute (helicoid) moved along its
// transverse normal by m(L, z) = profile(L) + helix(z), µm (negative = material removed), the
// same on every flank of the gear. Profile: tip relief and root relief (amount C over a length
// of roll, circular), profile crowning; helix: crowning, end relief at both ends (circular),
// helix slope modification. Deviations are measured against this design flank, as gear software
// does (ISO 1328-1:2013 §3: the design profile and helix include the modifications; ISO 21771
// and DIN 3960 name the shapes). Lengths in mm (roll length L, face position z), amounts in µm.
//
// Shapes, with x the distance into the modified zone (mm) and c = C / 1000 (mm):
// - circular relief: the arc of radius rho = (l² + c²) / (2c) tangent to the unmodified flank at
//   the relief's start and c below it at x = l (its sagitta), m = -(rho - sqrt(rho² - x²)),
//   continued past x = l by its tangent (C1; the flank ends there or before);
// - crowning: the parabola m = -C (2 (t - t_mid) / w)² over the range of width w (the active
//   profile L_Ff … L_a, or the face 0 … b), C at both ends, continued outside by its tangents;
// - helix slope modification H: m = H (z - b/2) / b (+ = more material towards z = b).
// All are C1 with bounded second derivatives (a curvature jump where a relief starts), so the
// contact solver's Newton steps and its curvature certificate hold as on an unmodified flank.
// - linear relief (tip, root and end reliefs): m = -c x / l, a straight line from the start:
//   the flank has a kink (a convex ridge) there, along the face for a tip or root relief, across
//   it for an end relief; the curve reports it (kinks()), and where the ball rests on the ridge
//   the contact solver maximises along it (engine/contact/contact.cpp).
#pragma once

#include <vector>

namespace gearmc {

// A relief at one end of the profile or at both ends of the face.
struct FlankRelief {
  double amount_um = 0.0;  // C, material removed at the end
  double length_mm = 0.0;  // l: roll length (profile) or face width (helix) it spans
  bool linear = false;     // a straight relief (a kink at its start) instead of the arc
  bool present() const { return amount_um > 0.0 && length_mm > 0.0; }
};

// The scenario's `gear: modifications:` (docs/scenarios.md).
struct FlankModifications {
  FlankRelief tip_relief;   // ends at the tip circle (roll length L_a)
  FlankRelief root_relief;  // ends at the form circle (roll length L_Ff)
  double profile_crowning_um = 0.0;
  double helix_crowning_um = 0.0;
  FlankRelief end_relief;  // at both faces, z = 0 and z = b
  double helix_slope_um = 0.0;
  bool any() const;
};

// One trace's modification m(t) (µm, t in mm): a sum of terms, each C1 with a bounded second
// derivative.
class ModificationCurve {
 public:
  // A circular (or linear) relief starting at `start` and reaching `amount_um` at start +
  // direction × length (direction +1: towards larger t, -1: towards smaller t).
  void add_relief(double start, int direction, const FlankRelief& relief);
  // Where the curve has a kink (the starts of its linear reliefs), increasing.
  std::vector<double> kinks() const;
  // Crowning C over [from, to] (both > from), m = -C (2 (t - mid) / (to - from))².
  void add_crowning(double from, double to, double amount_um);
  // m += slope_um_per_mm × (t - mid).
  void add_slope(double mid, double slope_um_per_mm);

  bool empty() const { return terms_.empty(); }
  // m, m' (µm/mm) and m'' (µm/mm²) at t.
  void evaluate(double t, double* value, double* first, double* second) const;
  double value(double t) const;
  // Bounds of m' and m'' over all t and of |m| over [from, to] (each term is monotone on each
  // side of its vertex, so its extremes lie at the interval's ends or at the vertex).
  struct Bounds {
    double first_lo = 0, first_hi = 0, second_lo = 0, second_hi = 0;
  };
  Bounds derivative_bounds() const;
  double magnitude_bound(double from, double to) const;

 private:
  struct Term {
    enum class Kind { kRelief, kLinearRelief, kCrowning, kSlope } kind;
    double start = 0, direction = 1, length = 0, rho = 0;  // relief (mm)
    double from = 0, to = 0, amount = 0;                   // crowning (µm over [from, to])
    double mid = 0, slope = 0;                             // slope (µm/mm)
  };
  static void evaluate_term(const Term& term, double t, double* v, double* d1, double* d2);
  std::vector<Term> terms_;
};

// The design modification of a gear: the profile curve in L over the active profile
// [L_form, L_tip] and the helix curve in z over [0, b].
struct DesignModification {
  DesignModification(const FlankModifications& modifications, double form_roll_length_mm,
                     double tip_roll_length_mm, double face_width_mm);
  ModificationCurve profile, helix;
  double form_roll_length_mm, tip_roll_length_mm, face_width_mm;
  // The roll lengths where a linear tip or root relief starts: the flank's ridges along the face
  // (profile.kinks()).
  std::vector<double> profile_kinks;
  // The face positions where a linear end relief starts: the ridges across the face at z = l and
  // z = b - l (helix.kinks()).
  std::vector<double> helix_kinks;
  // m(L, z), µm.
  double value_um(double L, double z) const { return profile.value(L) + helix.value(z); }
};

}  // namespace gearmc
