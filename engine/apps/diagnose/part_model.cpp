// The workpiece's own deviations of a production gear (part_model.h): per flank the columns of its
// position, profile and helix slopes and crownings, and their values read back as a gear
// metrologist states them.
#include "engine/apps/diagnose/part_model.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <tuple>

#include "engine/apps/diagnose/linear_model.h"

namespace gearmc {

namespace {

// The profile coordinate of a point: its roll length √(r² − r_b²) (mm), or r where r_b is unknown.
double roll_length_mm(const ResidualPoint& p) {
  const double r2 = p.context.p.x() * p.context.p.x() + p.context.p.y() * p.context.p.y();
  const double rb = p.context.base_radius_mm;
  return rb > 0.0 ? std::sqrt(std::max(0.0, r2 - rb * rb)) : std::sqrt(r2);
}

// The number of distinct values of `v` (1 µm apart at least).
int distinct(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  int count = 0;
  for (std::size_t k = 0; k < v.size(); ++k) {
    if (k == 0 || v[k] - v[k - 1] > 1e-3) ++count;
  }
  return count;
}

double normalised(double v, double from, double to) {
  return to > from ? 2.0 * (v - from) / (to - from) - 1.0 : 0.0;
}

double legendre(int order, double t) { return order == 1 ? t : 0.5 * (3.0 * t * t - 1.0); }

}  // namespace

PartColumns part_columns(const std::vector<ResidualPoint>& points,
                         const std::vector<int>& turned_by_teeth) {
  PartColumns out;
  std::map<std::tuple<int, int, int>, std::vector<int>> rows_of;
  for (std::size_t k = 0; k < points.size(); ++k) {
    const ResidualPoint& p = points[k];
    int gear = p.gear, tooth = p.tooth;
    if (!turned_by_teeth.empty()) {  // one gear in several set-ups: the gear's own tooth
      const int z = std::max(1, p.context.teeth);
      const int turned = turned_by_teeth.at(static_cast<std::size_t>(p.gear));
      gear = 0;
      tooth = ((tooth - 1 + turned) % z + z) % z + 1;
    }
    rows_of[{gear, tooth, p.side == FlankSide::kRight ? 1 : 0}].push_back(static_cast<int>(k));
  }
  int columns = 0;
  for (const auto& [key, rows] : rows_of) {
    PartFlank f;
    f.gear = std::get<0>(key);
    f.tooth = std::get<1>(key);
    f.side = std::get<2>(key) ? FlankSide::kRight : FlankSide::kLeft;
    f.points = static_cast<int>(rows.size());
    std::vector<double> l, z;
    for (int k : rows) {
      l.push_back(roll_length_mm(points[static_cast<std::size_t>(k)]));
      z.push_back(points[static_cast<std::size_t>(k)].context.p.z());
    }
    f.profile_from_mm = *std::min_element(l.begin(), l.end());
    f.profile_to_mm = *std::max_element(l.begin(), l.end());
    f.face_from_mm = *std::min_element(z.begin(), z.end());
    f.face_to_mm = *std::max_element(z.begin(), z.end());
    const int along_profile = distinct(l), across_face = distinct(z);
    f.terms.push_back(PartTerm::kPosition);
    if (along_profile >= 2) f.terms.push_back(PartTerm::kProfileSlope);
    if (along_profile >= 3) f.terms.push_back(PartTerm::kProfileCrowning);
    if (across_face >= 2) f.terms.push_back(PartTerm::kHelixSlope);
    if (across_face >= 3) f.terms.push_back(PartTerm::kHelixCrowning);
    f.first_column = columns;
    columns += static_cast<int>(f.terms.size());
    out.flanks.push_back(std::move(f));
  }
  const int n = static_cast<int>(points.size());
  out.x = Eigen::MatrixXd::Zero(n, columns);
  // Each flank's block and its orthonormal basis (the blocks are disjoint in rows, so the blocks'
  // bases side by side are a basis of the whole).
  std::vector<Eigen::MatrixXd> bases;
  int rank = 0;
  std::size_t index = 0;
  for (const auto& [key, rows] : rows_of) {
    const PartFlank& f = out.flanks[index++];
    Eigen::MatrixXd block(static_cast<int>(rows.size()), static_cast<int>(f.terms.size()));
    for (std::size_t r = 0; r < rows.size(); ++r) {
      const ResidualPoint& p = points[static_cast<std::size_t>(rows[r])];
      const double x = normalised(roll_length_mm(p), f.profile_from_mm, f.profile_to_mm);
      const double y = normalised(p.context.p.z(), f.face_from_mm, f.face_to_mm);
      for (std::size_t t = 0; t < f.terms.size(); ++t) {
        double v = 1.0;
        switch (f.terms[t]) {
          case PartTerm::kPosition:
            v = 1.0;
            break;
          case PartTerm::kProfileSlope:
            v = legendre(1, x);
            break;
          case PartTerm::kProfileCrowning:
            v = legendre(2, x);
            break;
          case PartTerm::kHelixSlope:
            v = legendre(1, y);
            break;
          case PartTerm::kHelixCrowning:
            v = legendre(2, y);
            break;
        }
        block(static_cast<int>(r), static_cast<int>(t)) = v;
      }
    }
    for (std::size_t r = 0; r < rows.size(); ++r) {
      out.x.block(rows[r], f.first_column, 1, block.cols()) = block.row(static_cast<int>(r));
    }
    bases.push_back(orthonormal_basis(block).q);
    rank += static_cast<int>(bases.back().cols());
  }
  out.q = Eigen::MatrixXd::Zero(n, rank);
  index = 0;
  int at = 0;
  for (const auto& [key, rows] : rows_of) {
    const Eigen::MatrixXd& b = bases[index++];
    for (std::size_t r = 0; r < rows.size(); ++r) {
      out.q.block(rows[r], at, 1, b.cols()) = b.row(static_cast<int>(r));
    }
    at += static_cast<int>(b.cols());
  }
  return out;
}

PartDeviations part_deviations(const PartColumns& part, const Eigen::VectorXd& beta,
                               const Eigen::MatrixXd& cov, const std::vector<bool>& estimable,
                               double sigma2_um2) {
  PartDeviations out;
  out.fitted = true;
  out.columns = part.columns();
  out.rank = part.rank();
  const double s2 = std::max(0.0, sigma2_um2);
  for (const PartFlank& f : part.flanks) {
    PartFlankDeviations d;
    d.flank = f;
    for (std::size_t t = 0; t < f.terms.size(); ++t) {
      const int c = f.first_column + static_cast<int>(t);
      if (!estimable[static_cast<std::size_t>(c)]) continue;
      const double se = std::sqrt(s2 * cov(c, c));
      // The metrologist's value: a linear function g·β of the coefficient (part_model.h).
      auto set = [&](PartValue& v, double g) {
        v.value_um = g * beta[c];
        v.u_um = 2.0 * std::abs(g) * se;
        v.estimable = true;
      };
      switch (f.terms[t]) {
        case PartTerm::kPosition:
          set(d.position, 1.0);
          break;
        case PartTerm::kProfileSlope:
          set(d.f_h_alpha, 2.0);
          break;
        case PartTerm::kProfileCrowning:
          set(d.c_alpha, -1.5);
          break;
        case PartTerm::kHelixSlope:
          set(d.f_h_beta, 2.0);
          break;
        case PartTerm::kHelixCrowning:
          set(d.c_beta, -1.5);
          break;
      }
    }
    out.flanks.push_back(std::move(d));
  }
  for (const FlankSide side : {FlankSide::kLeft, FlankSide::kRight}) {
    PartSideSummary s;
    s.side = side;
    double pos_min = INFINITY, pos_max = -INFINITY;
    s.f_h_alpha_min_um = s.f_h_beta_min_um = INFINITY;
    s.f_h_alpha_max_um = s.f_h_beta_max_um = -INFINITY;
    int positions = 0, crown_alpha = 0, crown_beta = 0;
    for (const PartFlankDeviations& d : out.flanks) {
      if (d.flank.side != side) continue;
      ++s.flanks;
      if (d.position.estimable) {
        s.position_mean_um += d.position.value_um;
        pos_min = std::min(pos_min, d.position.value_um);
        pos_max = std::max(pos_max, d.position.value_um);
        ++positions;
      }
      if (d.f_h_alpha.estimable) {
        s.f_h_alpha_mean_um += d.f_h_alpha.value_um;
        s.f_h_alpha_min_um = std::min(s.f_h_alpha_min_um, d.f_h_alpha.value_um);
        s.f_h_alpha_max_um = std::max(s.f_h_alpha_max_um, d.f_h_alpha.value_um);
        ++s.estimable_alpha;
      }
      if (d.f_h_beta.estimable) {
        s.f_h_beta_mean_um += d.f_h_beta.value_um;
        s.f_h_beta_min_um = std::min(s.f_h_beta_min_um, d.f_h_beta.value_um);
        s.f_h_beta_max_um = std::max(s.f_h_beta_max_um, d.f_h_beta.value_um);
        ++s.estimable_beta;
      }
      if (d.c_alpha.estimable) {
        s.c_alpha_mean_um += d.c_alpha.value_um;
        ++crown_alpha;
      }
      if (d.c_beta.estimable) {
        s.c_beta_mean_um += d.c_beta.value_um;
        ++crown_beta;
      }
    }
    if (s.flanks == 0) continue;
    if (positions > 0) {
      s.position_mean_um /= positions;
      s.position_range_um = pos_max - pos_min;
    }
    if (s.estimable_alpha > 0) s.f_h_alpha_mean_um /= s.estimable_alpha;
    if (s.estimable_beta > 0) s.f_h_beta_mean_um /= s.estimable_beta;
    if (crown_alpha > 0) s.c_alpha_mean_um /= crown_alpha;
    if (crown_beta > 0) s.c_beta_mean_um /= crown_beta;
    if (s.estimable_alpha == 0) s.f_h_alpha_min_um = s.f_h_alpha_max_um = 0.0;
    if (s.estimable_beta == 0) s.f_h_beta_min_um = s.f_h_beta_max_um = 0.0;
    out.sides.push_back(s);
  }
  return out;
}

std::string separate_from_part(const std::string& effect) {
  static const std::set<std::string> constant = {"stylus_radius", "stylus_bending",
                                                 "step_quantization"};
  static const std::set<std::string> slope = {"scale", "thermal_expansion", "squareness",
                                              "straightness", "eccentricity"};
  if (constant.count(effect)) {
    return "a constant along the normal on every flank is the teeth's thickness or the probe's "
           "size: qualify the stylus on a calibrated sphere or ring, or measure a calibrated "
           "master on the same plan";
  }
  if (slope.count(effect)) {
    return "the same slope on every tooth is the part's profile or helix slope or the machine's "
           "geometry: measure the gear again turned on the table by a few teeth (the part's "
           "deviations turn with the gear, the machine's stay where they are), or a calibrated "
           "master";
  }
  if (effect == "probe_lobing") {
    return "over one flank the approach direction turns only by the flank's roll angle, so a "
           "lobed pre-travel looks like the flank's form: qualify the stylus on a calibrated "
           "sphere over all approach directions, or measure a calibrated master on the same plan";
  }
  if (effect == "clocking") {
    return "a turn of the whole gear moves every left flank one way and every right flank the "
           "other, as a common change of every tooth's position: the part's positions carry it. It "
           "is the alignment's, not the machine's, and the pitch and runout deviations, which are "
           "taken about the gear's own datum, do not contain it";
  }
  if (effect == "rotary_table") {
    return "a pitch pattern is the part's or the table's: measure the gear again turned by k "
           "teeth (closure: the part's pattern moves by k teeth, the table's stays)";
  }
  if (effect == "drift" || effect == "probe_warmup") {
    return "a change along the probing order that is smooth within each flank looks like the "
           "flank's form: measure the flanks in another order (or twice), the part's form does "
           "not follow the order";
  }
  return "measure the gear again turned on the table (the part's deviations turn with it), or a "
         "calibrated master on the same plan";
}

}  // namespace gearmc
