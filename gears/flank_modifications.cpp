// Designed flank modifications (see flank_modifications.h).
#include "gears/flank_modifications.h"

#include <algorithm>
#include <cmath>

namespace gearmc {

bool FlankModifications::any() const {
  return tip_relief.present() || root_relief.present() || end_relief.present() ||
         profile_crowning_um != 0.0 || helix_crowning_um != 0.0 || helix_slope_um != 0.0;
}

void ModificationCurve::add_relief(double start, int direction, const FlankRelief& relief) {
  if (!relief.present()) return;
  Term t{relief.linear ? Term::Kind::kLinearRelief : Term::Kind::kRelief};
  t.start = start;
  t.direction = direction >= 0 ? 1.0 : -1.0;
  t.length = relief.length_mm;
  t.amount = relief.amount_um;
  const double c = 1e-3 * relief.amount_um;
  // The circle through the start (tangent there) with sagitta c over the chord's half l.
  t.rho = (relief.length_mm * relief.length_mm + c * c) / (2.0 * c);
  terms_.push_back(t);
}

void ModificationCurve::add_crowning(double from, double to, double amount_um) {
  if (amount_um == 0.0) return;
  Term t{Term::Kind::kCrowning};
  t.from = from;
  t.to = to;
  t.amount = amount_um;
  terms_.push_back(t);
}

void ModificationCurve::add_slope(double mid, double slope_um_per_mm) {
  if (slope_um_per_mm == 0.0) return;
  Term t{Term::Kind::kSlope};
  t.mid = mid;
  t.slope = slope_um_per_mm;
  terms_.push_back(t);
}

std::vector<double> ModificationCurve::kinks() const {
  std::vector<double> out;
  for (const Term& term : terms_) {
    if (term.kind == Term::Kind::kLinearRelief) out.push_back(term.start);
  }
  std::sort(out.begin(), out.end());
  return out;
}

void ModificationCurve::evaluate_term(const Term& term, double t, double* v, double* d1,
                                      double* d2) {
  switch (term.kind) {
    case Term::Kind::kLinearRelief: {  // m = -c x / l beyond the start (x > 0), 0 before
      const double x = term.direction * (t - term.start);
      if (!(x > 0.0)) {
        *v = *d1 = *d2 = 0.0;
        return;
      }
      const double slope = -term.amount / term.length;  // µm per mm of x
      *v = slope * x;
      *d1 = term.direction * slope;
      *d2 = 0.0;
      return;
    }
    case Term::Kind::kRelief: {
      const double x = term.direction * (t - term.start);
      if (!(x > 0.0)) {
        *v = *d1 = *d2 = 0.0;
        return;
      }
      const double rho = term.rho;
      const double xe = std::min(x, term.length);
      const double s = std::sqrt((rho - xe) * (rho + xe));
      const double m = -xe * xe / (rho + s);  // -(rho - s) without the cancellation, mm
      const double slope = -xe / s;           // dm/dx
      if (x > term.length) {                  // the tangent at the arc's end
        *v = 1e3 * (m + slope * (x - term.length));
        *d1 = 1e3 * term.direction * slope;
        *d2 = 0.0;
        return;
      }
      *v = 1e3 * m;
      *d1 = 1e3 * term.direction * slope;
      *d2 = -1e3 * rho * rho / (s * s * s);
      return;
    }
    case Term::Kind::kCrowning: {
      const double w = term.to - term.from, mid = 0.5 * (term.from + term.to);
      const double k = 4.0 * term.amount / (w * w);  // m = -k (t - mid)²
      const double te = std::clamp(t, term.from, term.to);
      const double m = -k * (te - mid) * (te - mid), slope = -2.0 * k * (te - mid);
      *v = m + slope * (t - te);
      *d1 = slope;
      *d2 = t == te ? -2.0 * k : 0.0;
      return;
    }
    case Term::Kind::kSlope:
      *v = term.slope * (t - term.mid);
      *d1 = term.slope;
      *d2 = 0.0;
      return;
  }
}

void ModificationCurve::evaluate(double t, double* value, double* first, double* second) const {
  *value = *first = *second = 0.0;
  for (const Term& term : terms_) {
    double v, d1, d2;
    evaluate_term(term, t, &v, &d1, &d2);
    *value += v;
    *first += d1;
    *second += d2;
  }
}

double ModificationCurve::value(double t) const {
  double v, d1, d2;
  evaluate(t, &v, &d1, &d2);
  return v;
}

ModificationCurve::Bounds ModificationCurve::derivative_bounds() const {
  Bounds b;
  for (const Term& term : terms_) {
    double lo1 = 0, hi1 = 0, lo2 = 0, hi2 = 0;
    switch (term.kind) {
      case Term::Kind::kLinearRelief: {
        const double end = term.direction * (-term.amount / term.length);
        lo1 = std::min(0.0, end);
        hi1 = std::max(0.0, end);
        break;  // m'' = 0 on both sides of the kink (the kink itself is the solver's)
      }
      case Term::Kind::kRelief: {
        // m' runs monotonically from 0 to its value at x = l (then stays); m'' from -1/rho to
        // -rho² / s(l)³ on the arc, 0 before and after it.
        const double l = term.length, rho = term.rho;
        const double s = std::sqrt((rho - l) * (rho + l));
        const double end = 1e3 * term.direction * (-l / s);
        lo1 = std::min(0.0, end);
        hi1 = std::max(0.0, end);
        lo2 = -1e3 * rho * rho / (s * s * s);
        break;
      }
      case Term::Kind::kCrowning: {
        const double w = term.to - term.from;
        const double end = 4.0 * std::abs(term.amount) / w;  // |m'| at the range's ends
        lo1 = -end;
        hi1 = end;
        const double curvature = -8.0 * term.amount / (w * w);
        lo2 = std::min(0.0, curvature);
        hi2 = std::max(0.0, curvature);
        break;
      }
      case Term::Kind::kSlope:
        lo1 = hi1 = term.slope;
        break;
    }
    b.first_lo += lo1;
    b.first_hi += hi1;
    b.second_lo += lo2;
    b.second_hi += hi2;
  }
  return b;
}

double ModificationCurve::magnitude_bound(double from, double to) const {
  double sum = 0.0;
  for (const Term& term : terms_) {
    double a, b, unused1, unused2;
    evaluate_term(term, from, &a, &unused1, &unused2);
    evaluate_term(term, to, &b, &unused1, &unused2);
    sum += std::max(std::abs(a), std::abs(b));
  }
  return sum;
}

DesignModification::DesignModification(const FlankModifications& m, double L_form, double L_tip,
                                       double b)
    : form_roll_length_mm(L_form), tip_roll_length_mm(L_tip), face_width_mm(b) {
  // The tip end is the larger roll length on an external gear, the smaller on an internal one.
  const int tipward = L_tip >= L_form ? +1 : -1;
  profile.add_relief(L_tip - tipward * m.tip_relief.length_mm, tipward, m.tip_relief);
  profile.add_relief(L_form + tipward * m.root_relief.length_mm, -tipward, m.root_relief);
  profile.add_crowning(std::min(L_form, L_tip), std::max(L_form, L_tip), m.profile_crowning_um);
  helix.add_relief(b - m.end_relief.length_mm, +1, m.end_relief);
  helix.add_relief(m.end_relief.length_mm, -1, m.end_relief);
  helix.add_crowning(0.0, b, m.helix_crowning_um);
  helix.add_slope(0.5 * b, m.helix_slope_um / b);
  profile_kinks = profile.kinks();
  helix_kinks = helix.kinks();
}

}  // namespace gearmc
