// The gear parameters of every simulated measurement (see parameter_evaluation.h).
#include "engine/evaluation/parameter_evaluation.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/constants.h"
#include "core/number_text.h"
#include "engine/contact/contact.h"
#include "engine/contact/tooth_space.h"
#include "engine/effects/measurement_effect.h"
#include "engine/evaluation/trace_filter.h"
#include "gears/size_dimensions.h"
#include "surfaces/analytic_flank.h"

namespace gearmc {
namespace {

// Distances to mid face or mid profile closer than this are a tie (mm): with an even number of
// sections the two middle ones are equally far up to rounding, which must not decide.
constexpr double kTieMm = 1e-6;

// The grid coordinate nearest `target` (the first of a tie).
int nearest(const std::vector<double>& values, double target) {
  int best = 0;
  for (int i = 1; i < static_cast<int>(values.size()); ++i) {
    if (std::abs(values[i] - target) < std::abs(values[best] - target) - kTieMm) best = i;
  }
  return best;
}

// A program's points closer than this in z (a transverse section) or in roll length (a helix
// trace) run on one trace, mm: DMIS programs print coordinates to 0.1 µm or finer.
constexpr double kSameTraceMm = 1e-3;
// The fewest points of a trace in its evaluation range (evaluate_trace_over needs 3).
constexpr int kMinTracePoints = 3;

// Groups of `values` (indices) closer than kSameTraceMm to the group's first, in increasing value.
std::vector<std::vector<std::size_t>> trace_groups(const std::vector<double>& values) {
  std::vector<std::size_t> order(values.size());
  for (std::size_t k = 0; k < order.size(); ++k) order[k] = k;
  std::sort(order.begin(), order.end(),
            [&](std::size_t a, std::size_t b) { return values[a] < values[b]; });
  std::vector<std::vector<std::size_t>> groups;
  for (std::size_t k = 0; k < order.size();) {
    std::vector<std::size_t>& g = groups.emplace_back();
    const double first = values[order[k]];
    while (k < order.size() && values[order[k]] - first <= kSameTraceMm) g.push_back(order[k++]);
  }
  return groups;
}

}  // namespace

ParameterEvaluator::ParameterEvaluator(const MeasurementModel& model, const EvaluationSpec& spec)
    : model_(model), spec_(spec) {
  const InvoluteGear& gear = model.gear();
  const double L0 = gear.form_roll_length_mm(), L1 = gear.tip_roll_length_mm();
  const double b = gear.face_width_mm();
  // From the form circle towards the tip (on an internal gear towards smaller L).
  profile_start_ = L0;
  profile_end_ = L0 + spec.profile_end_fraction * (L1 - L0);
  profile_sign_ = gear.roll_sign();
  const double c = spec.helix_end_exclusion_mm.value_or(std::min(0.05 * b, gear.module_mm()));
  helix_start_ = c;
  helix_end_ = b - c;
  const double r = gear.reference_diameter_mm() / 2, rb = gear.base_diameter_mm() / 2;
  reference_L_ = std::sqrt(r * r - rb * rb);
  // ISO 1328-1 states profile, helix and pitch deviations in the transverse plane; a deviation
  // along the helicoid's normal is the transverse one times cos(beta_b) (the helicoid's normal
  // is cos(beta_b) n_t -/+ sin(beta_b) e_z, docs/contact.md): 1 on a spur gear, exactly.
  transverse_per_normal_ = 1.0 / std::cos(gear.base_helix_angle_rad());
  ball_L_ = 0.5 * (profile_start_ + profile_end_);

  // Which parameters the plan allows.
  const std::vector<PlanFlank>& flanks = model.flanks();
  const bool every_tooth = model.probed_teeth() == gear.teeth();
  const bool both_sides = model.scenario().probing.left && model.scenario().probing.right;
  for (const std::string& symbol : spec.parameters) {
    const GearParameter p = *parameter_from_symbol(symbol);
    const bool pitch = p == GearParameter::kfpt || p == GearParameter::kFp;
    if ((pitch || p == GearParameter::kFr) && !every_tooth) {
      notes_.push_back(symbol + ": not evaluated, not every tooth is probed (probing.teeth)");
      continue;
    }
    if (p == GearParameter::kFr && !both_sides) {
      notes_.push_back(symbol + ": not evaluated, the ball needs both flanks of every space");
      continue;
    }
    parameters_.push_back(p);
  }

  // Where the traces run: one trace (1 section) at mid face / mid profile, several at the centres
  // of equal parts of L_β / L_α; on the grid its section nearest mid face and column nearest mid
  // profile, several spread alike over the grid's (the scenario check keeps them at most the
  // grid's count); or the dedicated scans there.
  std::vector<double> Ls, zs;
  if (!flanks.empty()) {
    for (const PlanPoint& q : flanks.front().points) {
      if (q.j == 0) Ls.push_back(q.roll_length_mm);
      if (q.i == 0) zs.push_back(q.z_mm);
    }
  }
  const int n_profile = std::max(1, spec.profile_sections);
  const int n_helix = std::max(1, spec.helix_sections);
  middle_profile_ = (n_profile - 1) / 2;
  middle_helix_ = (n_helix - 1) / 2;
  const auto spread = [](int n, int count, int k, int nearest_middle) {
    if (n == 1) return nearest_middle;
    return std::min(count - 1, static_cast<int>(std::floor((k + 0.5) * count / n)));
  };
  std::vector<double> profile_zs, helix_Ls;
  for (int k = 0; k < n_profile; ++k) {
    const double z = helix_start_ + (helix_end_ - helix_start_) * (k + 0.5) / n_profile;
    if (spec.profile_points > 0 || zs.empty()) {
      profile_zs.push_back(z);
    } else {
      grid_sections_.push_back(spread(n_profile, static_cast<int>(zs.size()), k,
                                      nearest(zs, 0.5 * (helix_start_ + helix_end_))));
      profile_zs.push_back(zs[static_cast<std::size_t>(grid_sections_.back())]);
    }
  }
  for (int k = 0; k < n_helix; ++k) {
    const double L = profile_start_ + (profile_end_ - profile_start_) * (k + 0.5) / n_helix;
    if (spec.helix_points > 0 || Ls.empty()) {
      helix_Ls.push_back(L);
    } else {
      grid_columns_.push_back(
          spread(n_helix, static_cast<int>(Ls.size()), k, nearest(Ls, ball_L_)));
      helix_Ls.push_back(Ls[static_cast<std::size_t>(grid_columns_.back())]);
    }
  }
  profile_z_ = profile_zs[static_cast<std::size_t>(middle_profile_)];
  helix_L_ = helix_Ls[static_cast<std::size_t>(middle_helix_)];
  if (spec.profile_points > 0 || spec.helix_points > 0) {
    const double R = model.stylus_radius_mm();
    int order = model.sequence_length();  // the scans follow the grid, flank after flank
    for (const PlanFlank& f : flanks) {
      std::vector<int>& trace = scan_trace_.emplace_back();
      PlanFlank& s = scans_.emplace_back();
      s.tooth = f.tooth;
      s.side = f.side;
      s.mesh = f.mesh;
      auto add = [&](int i, int j, double L, double z) {
        PlanPoint& q = s.points.emplace_back();
        q.tooth = f.tooth;
        q.side = f.side;
        q.i = i;
        q.j = j;
        q.roll_length_mm = L;
        q.z_mm = z;
        q.nominal = gear.flank_point(f.tooth, f.side, L, z);
        q.order = order++;
        q.clearance_mm =
            tooth_space_clearance(gear, f.tooth, f.side, q.nominal.point + R * q.nominal.normal,
                                  q.nominal.normal, model.stylus_shape(), kProbeApproachMm)
                .smallest();
      };
      // Profile scans: j = 0; helix scans: i = 0, j ≥ 1 (scan_trace_ says which trace).
      const int np = spec.profile_points, nh = spec.helix_points;
      for (int t = 0; t < n_profile && np > 0; ++t) {
        for (int i = 0; i < np; ++i) {
          add(i, 0, profile_start_ + (profile_end_ - profile_start_) * i / (np - 1),
              profile_zs[static_cast<std::size_t>(t)]);
          trace.push_back(t);
        }
      }
      for (int t = 0; t < n_helix && nh > 0; ++t) {
        for (int j = 0; j < nh; ++j) {
          add(0, 1 + j, helix_Ls[static_cast<std::size_t>(t)],
              helix_start_ + (helix_end_ - helix_start_) * j / (nh - 1));
          trace.push_back(t);
        }
      }
    }
  }
  // Which points make each flank's traces.
  program_ = !model.scenario().probing.points.empty();
  trace_member_.resize(flanks.size());
  profile_trace_.resize(flanks.size());
  helix_trace_.resize(flanks.size());
  flank_profile_z_.assign(flanks.size(), profile_zs);
  flank_helix_L_.assign(flanks.size(), helix_Ls);
  for (std::size_t f = 0; f < flanks.size(); ++f) {
    std::vector<unsigned char>& member = trace_member_[f];
    member.assign(flanks[f].points.size(), 0);
    profile_trace_[f].assign(flanks[f].points.size(), -1);
    helix_trace_[f].assign(flanks[f].points.size(), -1);
    if (program_) {
      choose_program_traces(f);
      continue;
    }
    for (std::size_t k = 0; k < member.size(); ++k) {
      const PlanPoint& q = flanks[f].points[k];
      for (std::size_t t = 0; t < grid_sections_.size(); ++t) {
        if (q.j != grid_sections_[t]) continue;
        member[k] |= kInProfile;
        profile_trace_[f][k] = static_cast<int>(t);
      }
      for (std::size_t t = 0; t < grid_columns_.size(); ++t) {
        if (q.i != grid_columns_[t]) continue;
        member[k] |= kInHelix;
        helix_trace_[f][k] = static_cast<int>(t);
      }
    }
  }
  if (program_) {
    // Pitch and runout compare the teeth in one transverse section: the program's profile
    // traces must share theirs.
    double z_lo = std::numeric_limits<double>::infinity(), z_hi = -z_lo;
    for (std::size_t f = 0; f < flanks.size(); ++f) {
      const double z = flank_profile_z_[f][0];
      if (std::isnan(z)) continue;
      z_lo = std::min(z_lo, z);
      z_hi = std::max(z_hi, z);
    }
    if (z_hi >= z_lo) profile_z_ = z_lo;
    if (z_hi - z_lo > kSameTraceMm) {
      for (const GearParameter p : {GearParameter::kfpt, GearParameter::kFp, GearParameter::kFr}) {
        const auto at = std::find(parameters_.begin(), parameters_.end(), p);
        if (at == parameters_.end()) continue;
        parameters_.erase(at);
        notes_.push_back(std::string(parameter_symbol(p)) +
                         ": not evaluated, the program's profile traces are not in one transverse "
                         "section (z " +
                         short_text(z_lo) + " … " + short_text(z_hi) + " mm)");
      }
    }
  }
  balls_ = ball_contacts(gear, ball_L_, profile_z_);
  // The size gauges (the scenario check refused gauges touching outside L_α when listed).
  if (evaluates(GearParameter::kEWk)) {
    span_k_ = evaluation_span_teeth(gear, spec);
    if (span_k_) span_L_ = span_contact_roll_length_mm(gear, *span_k_);
  }
  if (evaluates(GearParameter::kEMdK)) {
    size_ball_D_ = evaluation_ball_diameter_mm(gear, spec);
    if (size_ball_D_) {
      const BallPosition ball = ball_position(gear, *size_ball_D_);
      size_ball_L_ = ball.contact_roll_length_mm;  // the deviations are read here
      // The normals where they point at the centre in its section (see BallPosition).
      size_balls_ = ball_contacts(gear, ball.section_foot_roll_length_mm, profile_z_);
    }
  }
  for (const auto& [p, known] : {std::pair{GearParameter::kEWk, span_k_.has_value()},
                                 std::pair{GearParameter::kEMdK, size_ball_D_.has_value()}}) {
    if (known) continue;
    const auto at = std::find(parameters_.begin(), parameters_.end(), p);
    if (at == parameters_.end()) continue;
    parameters_.erase(at);
    notes_.push_back(parameter_symbol(p) + ": not evaluated, no gauge touches within L_α");
  }
}

void ParameterEvaluator::choose_program_traces(std::size_t f) {
  const PlanFlank& flank = model_.flanks()[f];
  std::vector<unsigned char>& member = trace_member_[f];
  std::vector<double> zs, Ls;
  for (const PlanPoint& q : flank.points) {
    zs.push_back(q.z_mm);
    Ls.push_back(q.roll_length_mm);
  }
  // The profile trace: the section with the most points in the profile range (roll lengths
  // between form and tip ends), ties to the one nearest mid face (of two as near, the lower z);
  // the helix trace likewise (of two as near mid profile, the smaller roll length: on an external
  // gear the grid's order, so a program of the grid's points evaluates as the grid).
  const double mid_face = 0.5 * (helix_start_ + helix_end_);
  const double L_lo = std::min(profile_start_, profile_end_) - kSameTraceMm;
  const double L_hi = std::max(profile_start_, profile_end_) + kSameTraceMm;
  const auto pick = [&](const std::vector<double>& across, bool profile) {
    const std::vector<std::vector<std::size_t>> groups = trace_groups(across);
    int best = -1, best_count = 0;
    double best_distance = 0.0;
    for (std::size_t g = 0; g < groups.size(); ++g) {
      int count = 0;
      for (const std::size_t k : groups[g]) {
        const double along = profile ? Ls[k] : zs[k];
        count += profile
                     ? along >= L_lo && along <= L_hi
                     : along >= helix_start_ - kSameTraceMm && along <= helix_end_ + kSameTraceMm;
      }
      const double distance = std::abs(across[groups[g].front()] - (profile ? mid_face : ball_L_));
      if (count >= kMinTracePoints &&
          (count > best_count || (count == best_count && distance < best_distance - kTieMm))) {
        best = static_cast<int>(g), best_count = count, best_distance = distance;
      }
    }
    if (best < 0) return std::numeric_limits<double>::quiet_NaN();
    for (const std::size_t k : groups[static_cast<std::size_t>(best)]) {
      member[k] |= profile ? kInProfile : kInHelix;
      (profile ? profile_trace_ : helix_trace_)[f][k] = 0;
    }
    return across[groups[static_cast<std::size_t>(best)].front()];
  };
  flank_profile_z_[f] = {pick(zs, true)};
  flank_helix_L_[f] = {pick(Ls, false)};
}

ParameterEvaluator::~ParameterEvaluator() = default;

bool ParameterEvaluator::evaluates(GearParameter p) const {
  return std::find(parameters_.begin(), parameters_.end(), p) != parameters_.end();
}

int ParameterEvaluator::effect_count() const { return static_cast<int>(model_.effects().size()); }

ParameterEvaluator::Gear::Gear(const ParameterEvaluator& evaluator,
                               const GearMeasurement& measurement)
    : e_(evaluator), measurement_(measurement) {
  grid_.resize(e_.model_.flanks().size());
  for (std::size_t f = 0; f < grid_.size(); ++f) {
    grid_[f].resize(e_.model_.flanks()[f].points.size());
  }
}

void ParameterEvaluator::Gear::record(int flank_index, const PointMeasurement& m) {
  const PlanFlank& flank = e_.model_.flanks()[static_cast<std::size_t>(flank_index)];
  const std::size_t at = static_cast<std::size_t>(m.plan - flank.points.data());
  // Only the points of the traces are kept (the grid's mid section and column, or the
  // program's traces).
  if (e_.trace_member_[static_cast<std::size_t>(flank_index)][at] == 0) return;
  PointRecord& r = grid_[static_cast<std::size_t>(flank_index)][at];
  r.recorded = true;
  r.valid = m.valid();
  if (!r.valid) return;
  fill(r, m);
}

void ParameterEvaluator::Gear::fill(PointRecord& r, const PointMeasurement& m) const {
  const Eigen::Vector3d& p = m.plan->nominal.point;
  const Eigen::Vector3d& n = m.plan->nominal.normal;
  const double R = e_.model_.stylus_radius_mm();
  const double k = e_.transverse_per_normal_;
  r.measured_um = k * (1e3 * ((m.recorded_centre - p).dot(n) - R));
  r.base_um = k * (1e3 * (m.contact.contact - p).dot(n) + m.contact.normal_error_um);
  r.contributions.resize(m.contributions.size());
  for (std::size_t e = 0; e < m.contributions.size(); ++e)
    r.contributions[e] = k * m.contributions[e];
}

GearParameterValues ParameterEvaluator::Gear::finish(bool keep_traces) {
  // Probe the dedicated scans through the same pipeline.
  std::vector<std::vector<PointRecord>> scans(e_.scans_.size());
  for (std::size_t f = 0; f < e_.scans_.size(); ++f) {
    const PlanFlank& s = e_.scans_[f];
    scans[f].resize(s.points.size());
    measurement_.measure_flank(s, [&](const PointMeasurement& m) {
      PointRecord& r = scans[f][static_cast<std::size_t>(m.plan - s.points.data())];
      r.recorded = true;
      r.valid = m.valid();
      if (!r.valid) return;
      fill(r, m);
    });
  }

  const MeasurementModel& model = e_.model_;
  const InvoluteGear& gear = model.gear();
  const PerturbedGear& g = measurement_.perturbed();
  const int effects = e_.effect_count();
  // Variants of a trace: 0 measured, 1 true at the points, 2 … 1+E one effect alone, 2+E
  // δRcomp alone (budget only with effects).
  const int variants = effects > 0 ? 3 + effects : 2;
  GearParameterValues out;
  const auto put = [&](GearParameter p, int side, const std::vector<double>& v, double dense) {
    if (!e_.evaluates(p)) return;
    ParameterValue value;
    value.measured = v[0];
    value.true_points = v[1];
    value.true_dense = dense;
    value.budget.assign(v.begin() + 2, v.end());
    out.values[static_cast<int>(p)][side].push_back(std::move(value));
  };

  // Per flank: the profile and helix traces' variants; the pitch and ball deviations.
  const int teeth = gear.teeth();
  std::vector<std::vector<double>> pitch_u[2], ball_d[2];  // [side][variant][tooth-1]
  std::vector<double> pitch_dense[2], ball_dense[2];
  // The size gauges' readings of every flank: at the reference circle, the span's jaws, the
  // ball's contact ([gauge][side][variant][tooth-1]; dense: [gauge][side][tooth-1]).
  const double gauge_L[3] = {e_.reference_L_, e_.span_L_, e_.size_ball_L_};
  // Only the gauges of the sizes asked for are read (each reading of the real surface costs two
  // surface evaluations per flank).
  const bool gauge_used[3] = {e_.evaluates(GearParameter::kEsn), e_.evaluates(GearParameter::kEWk),
                              e_.evaluates(GearParameter::kEMdK)};
  std::vector<std::vector<double>> gauge_d[3][2];
  std::vector<double> gauge_dense[3][2];
  for (int s = 0; s < 2; ++s) {
    pitch_u[s].assign(variants, std::vector<double>(teeth, kNaN));
    ball_d[s].assign(variants, std::vector<double>(teeth, kNaN));
    pitch_dense[s].assign(teeth, kNaN);
    ball_dense[s].assign(teeth, kNaN);
    for (int gauge = 0; gauge < 3; ++gauge) {
      gauge_d[gauge][s].assign(variants, std::vector<double>(teeth, kNaN));
      gauge_dense[gauge][s].assign(teeth, kNaN);
    }
  }
  const std::vector<PlanFlank>& flanks = model.flanks();
  // The pitch is an arc on the reference circle of the transverse section, where the involute's
  // pressure angle is alpha_t (= alpha_n on a spur gear).
  const double alpha = gear.transverse_pressure_angle_rad();
  for (std::size_t f = 0; f < flanks.size(); ++f) {
    const PlanFlank& flank = flanks[f];
    const int s = flank.side == FlankSide::kRight ? 1 : 0;
    const AnalyticFlank surface(gear, flank.tooth, flank.side, g.flank(flank.tooth, flank.side),
                                g.eccentricity_mm, model.expression());
    // The real surface's deviation along the nominal normal line through the nominal point
    // (L, z) — where a probe moving along that line meets it. The surface point of the same
    // parameters is moved sideways by the eccentricity e (up to ~10 µm; times a slope of a few
    // µm/mm that is tens of nm): one Newton step on L puts it on the line, (S(L') − p)·t = 0
    // with |∂S/∂L| = L / r_b on the involute (the deviation changes it by a relative 1e-3);
    // what remains is second order in e (ΔL² times the involute's curvature: a few pm).
    // Deviations are stated against the design flank (ISO 1328-1): the design modification m(L,
    // z) is subtracted from every trace value (the real surface and the readings both carry it).
    const DesignModification* design = gear.design_modification();
    const double rb = gear.base_diameter_mm() / 2;
    const auto true_deviation = [&](double L, double z) {
      const FlankPoint nominal = gear.flank_point(flank.tooth, flank.side, L, z);
      const double off_line = (surface.point(L, z) - nominal.point).dot(nominal.profile_tangent);
      const double at = L - off_line * rb / L;
      const double d = e_.transverse_per_normal_ * 1e3 *
                       (surface.point(at, z) - nominal.point).dot(nominal.normal);
      return design ? d - design->value_um(L, z) : d;
    };
    // One trace: its points (records with their abscissa), evaluated in every variant. A profile
    // trace's abscissa is sigma L (sigma = roll sign): it grows from the root to the tip on
    // either kind of gear, so the slope deviation f_Halpha is the rise towards the tip (ISO
    // 1328-1) and the ranges are increasing intervals; charts keep L itself.
    const double ps = e_.profile_sign_;
    struct Sample {
      double x;
      const PointRecord* record;
      double L, z;
    };
    const auto trace_samples = [&](bool profile, int trace) {
      std::vector<Sample> samples;
      const bool scanned = profile ? e_.spec_.profile_points > 0 : e_.spec_.helix_points > 0;
      if (scanned) {
        const PlanFlank& scan = e_.scans_[f];
        for (std::size_t k = 0; k < scan.points.size(); ++k) {
          const PlanPoint& q = scan.points[k];
          if ((q.j == 0) != profile || e_.scan_trace_[f][k] != trace) continue;
          samples.push_back(
              {profile ? ps * q.roll_length_mm : q.z_mm, &scans[f][k], q.roll_length_mm, q.z_mm});
        }
      } else {
        for (std::size_t k = 0; k < flank.points.size(); ++k) {
          const PlanPoint& q = flank.points[k];
          if ((profile ? e_.profile_trace_ : e_.helix_trace_)[f][k] != trace) continue;
          samples.push_back(
              {profile ? ps * q.roll_length_mm : q.z_mm, &grid_[f][k], q.roll_length_mm, q.z_mm});
        }
      }
      std::sort(samples.begin(), samples.end(),
                [](const Sample& a, const Sample& b) { return a.x < b.x; });
      return samples;
    };
    // Every trace of the flank (EvaluationSpec::profile_sections, helix_sections); the middle
    // profile trace also gives pitch, runout and sizes, the middle traces the charts.
    std::vector<std::pair<bool, int>> traces;
    for (std::size_t t = 0; t < e_.flank_profile_z_[f].size(); ++t) {
      traces.emplace_back(true, static_cast<int>(t));
    }
    for (std::size_t t = 0; t < e_.flank_helix_L_[f].size(); ++t) {
      traces.emplace_back(false, static_cast<int>(t));
    }
    for (const auto& [profile, trace] : traces) {
      const double across =
          (profile ? e_.flank_profile_z_ : e_.flank_helix_L_)[f][static_cast<std::size_t>(trace)];
      const bool middle = trace == (profile ? e_.middle_profile_ : e_.middle_helix_);
      if (std::isnan(across)) {
        // A program with no such trace on this flank: its values are not evaluated.
        const std::vector<double> none(variants, kNaN);
        put(profile ? GearParameter::kFalpha : GearParameter::kFbeta, s, none, kNaN);
        put(profile ? GearParameter::kfHalpha : GearParameter::kfHbeta, s, none, kNaN);
        put(profile ? GearParameter::kffalpha : GearParameter::kffbeta, s, none, kNaN);
        continue;
      }
      const std::vector<Sample> samples = trace_samples(profile, trace);
      std::vector<double> x;
      std::vector<std::vector<double>> d(variants);
      FlankTrace chart;
      chart.tooth = flank.tooth;
      chart.side = flank.side;
      for (const Sample& sample : samples) {
        chart.x_mm.push_back(profile ? sample.L : sample.x);
        const double t = true_deviation(sample.L, sample.z);
        const double m = design ? design->value_um(sample.L, sample.z) : 0.0;
        const double measured =
            design ? sample.record->measured_um - m : sample.record->measured_um;
        const double base = design ? sample.record->base_um - m : sample.record->base_um;
        chart.true_um.push_back(t);
        chart.measured_um.push_back(sample.record->valid ? measured : kNaN);
        if (!sample.record->valid) continue;
        x.push_back(sample.x);
        d[0].push_back(measured);
        d[1].push_back(t);
        for (int e = 0; e < effects; ++e) {
          const double c = e < static_cast<int>(sample.record->contributions.size())
                               ? sample.record->contributions[e]
                               : 0.0;
          d[2 + e].push_back(base + c);
        }
        if (effects > 0) d[2 + effects].push_back(base);
      }
      const double a = profile ? ps * e_.profile_start_ : e_.helix_start_;
      const double b = profile ? ps * e_.profile_end_ : e_.helix_end_;
      const int n_dense = e_.spec_.truth_points;
      std::vector<double> xd(n_dense), dd(n_dense);
      for (int i = 0; i < n_dense; ++i) {
        xd[i] = a + (b - a) * i / (n_dense - 1);
        dd[i] = profile ? true_deviation(ps * xd[i], across) : true_deviation(across, xd[i]);
      }
      // The trace parameters of filtered traces (ISO 16610-21 Gaussian, `*_cutoff_mm`), the
      // real surface's dense trace filtered alike; pitch and sizes read the unfiltered traces.
      const std::optional<double> cutoff =
          profile ? e_.spec_.profile_cutoff_mm : e_.spec_.helix_cutoff_mm;
      const auto filtered = [&](const std::vector<double>& xs, const std::vector<double>& ds) {
        return cutoff ? gaussian_regression_filter(xs, ds, *cutoff) : ds;
      };
      const auto dense = evaluate_trace_over(xd, filtered(xd, dd), a, b);
      std::vector<std::optional<TraceResult>> results(variants);
      for (int v = 0; v < variants; ++v)
        results[v] = evaluate_trace_over(x, filtered(x, d[v]), a, b);
      const auto column = [&](auto field) {
        std::vector<double> values(variants);
        for (int v = 0; v < variants; ++v) values[v] = results[v] ? field(*results[v]) : kNaN;
        return values;
      };
      const auto total = [](const TraceResult& r) { return r.total_um; };
      const auto slope = [](const TraceResult& r) { return r.slope_um; };
      const auto form = [](const TraceResult& r) { return r.form_um; };
      put(profile ? GearParameter::kFalpha : GearParameter::kFbeta, s, column(total),
          dense->total_um);
      put(profile ? GearParameter::kfHalpha : GearParameter::kfHbeta, s, column(slope),
          dense->slope_um);
      put(profile ? GearParameter::kffalpha : GearParameter::kffbeta, s, column(form),
          dense->form_um);
      if (keep_traces) {
        chart.dense_x_mm = xd;
        if (profile) {
          for (double& v : chart.dense_x_mm) v *= ps;
        }
        chart.dense_um = dd;
      }
      chart.range_start_mm = profile ? e_.profile_start_ : a;
      chart.range_end_mm = profile ? e_.profile_end_ : b;
      if (results[0]) {
        chart.measured_line = *results[0];
        // The chart's abscissa is L: the line's slope per mm of L is sigma times that per mm of
        // sigma L (its intercept is at the range's start either way).
        if (profile) chart.measured_line.slope_um_per_mm *= ps;
      }
      if (dense) {
        chart.true_line = *dense;
        if (profile) chart.true_line.slope_um_per_mm *= ps;
      }
      if (keep_traces && middle)
        (profile ? out.traces.profile : out.traces.helix).push_back(std::move(chart));
      if (profile && middle && x.size() >= 2) {
        const int k = flank.tooth - 1;
        for (int v = 0; v < variants; ++v) {
          pitch_u[s][v][k] = flank_arc_position_um(
              flank.side, interpolate_trace(x, d[v], ps * e_.reference_L_), alpha);
          ball_d[s][v][k] = interpolate_trace(x, d[v], ps * e_.ball_L_);
        }
        pitch_dense[s][k] = flank_arc_position_um(
            flank.side, true_deviation(e_.reference_L_, e_.profile_z_), alpha);
        ball_dense[s][k] = true_deviation(e_.ball_L_, e_.profile_z_);
        for (int gauge = 0; gauge < 3; ++gauge) {
          if (!gauge_used[gauge]) continue;
          for (int v = 0; v < variants; ++v) {
            gauge_d[gauge][s][v][k] = interpolate_trace(x, d[v], ps * gauge_L[gauge]);
          }
          gauge_dense[gauge][s][k] = true_deviation(gauge_L[gauge], e_.profile_z_);
        }
      }
    }
  }
  const auto complete = [](const std::vector<double>& v) {
    return std::none_of(v.begin(), v.end(), [](double x) { return std::isnan(x); });
  };
  // Pitch per side: every tooth's position is needed.
  if (e_.evaluates(GearParameter::kfpt) || e_.evaluates(GearParameter::kFp)) {
    for (int s = 0; s < 2; ++s) {
      if (!complete(pitch_dense[s]) && std::all_of(pitch_dense[s].begin(), pitch_dense[s].end(),
                                                   [](double x) { return std::isnan(x); })) {
        continue;  // the side is not probed
      }
      std::vector<PitchResult> r(variants);
      std::vector<bool> ok(variants);
      for (int v = 0; v < variants; ++v) {
        ok[v] = complete(pitch_u[s][v]);
        if (ok[v]) r[v] = evaluate_pitch(pitch_u[s][v]);
      }
      const PitchResult dense = evaluate_pitch(pitch_dense[s]);
      for (int k = 0; k < teeth; ++k) {
        std::vector<double> v(variants);
        for (int i = 0; i < variants; ++i) v[i] = ok[i] ? r[i].single_um[k] : kNaN;
        put(GearParameter::kfpt, s, v, dense.single_um[k]);
      }
      std::vector<double> v(variants);
      for (int i = 0; i < variants; ++i) v[i] = ok[i] ? r[i].cumulative_um : kNaN;
      put(GearParameter::kFp, s, v, dense.cumulative_um);
      out.traces.pitch_measured[s] = ok[0] ? r[0].single_um : std::vector<double>(teeth, kNaN);
      out.traces.pitch_true[s] = dense.single_um;
    }
  }
  if (e_.evaluates(GearParameter::kFr) && complete(ball_dense[0]) && complete(ball_dense[1])) {
    std::vector<double> v(variants);
    for (int i = 0; i < variants; ++i) {
      v[i] = complete(ball_d[1][i]) && complete(ball_d[0][i])
                 ? runout_um(e_.balls_, ball_d[1][i], ball_d[0][i])
                 : kNaN;
    }
    put(GearParameter::kFr, 0, v, runout_um(e_.balls_, ball_dense[1], ball_dense[0]));
    for (int k = 0; k < teeth; ++k) {
      const int next = (k + 1) % teeth;
      out.traces.ball_measured.push_back(
          complete(ball_d[1][0]) && complete(ball_d[0][0])
              ? ball_radial_displacement_um(e_.balls_[k], ball_d[1][0][k], ball_d[0][0][next])
              : kNaN);
      out.traces.ball_true.push_back(
          ball_radial_displacement_um(e_.balls_[k], ball_dense[1][k], ball_dense[0][next]));
    }
  }
  // The size deviations: an item for every tooth (E_sn), span (E_Wk) or ball pair (E_MdK)
  // whose flanks were all evaluated.
  const auto size_item = [&](GearParameter p, const auto& value_of) {
    std::vector<double> v(variants);
    for (int i = 0; i < variants; ++i) v[i] = value_of(i);
    const double dense = value_of(-1);
    if (std::isnan(dense) || std::isnan(v[0])) return;  // a flank not probed
    put(p, 0, v, dense);
  };
  // d of gauge g, side s, variant v (−1: dense truth), tooth k (0-based, taken modulo z).
  const auto reading = [&](int gauge, int s, int v, int k) {
    k = (k % teeth + teeth) % teeth;
    return v < 0 ? gauge_dense[gauge][s][k] : gauge_d[gauge][s][v][k];
  };
  if (e_.evaluates(GearParameter::kEsn)) {
    for (int k = 0; k < teeth; ++k) {
      size_item(GearParameter::kEsn, [&](int v) {
        return tooth_thickness_deviation_um(reading(0, 0, v, k), reading(0, 1, v, k), alpha,
                                            gear.helix_angle_rad());
      });
    }
  }
  if (e_.evaluates(GearParameter::kEWk)) {
    const int span = *e_.span_k_;
    for (int k = 0; k < teeth; ++k) {  // teeth k+1 … k+span: L of the first, R of the last
      size_item(GearParameter::kEWk, [&](int v) {
        return span_deviation_um(reading(1, 0, v, k), reading(1, 1, v, k + span - 1),
                                 gear.base_helix_angle_rad());
      });
    }
  }
  if (e_.evaluates(GearParameter::kEMdK)) {
    // Ball k sits in space k (between R of tooth k+1 and L of tooth k+2); its partner opposite
    // (even z: z/2 pairs) or nearly so (odd z: every space with the one (z−1)/2 further on).
    const int across = teeth / 2;
    const int pairs = teeth % 2 == 0 ? across : teeth;
    const auto ball = [&](int k) -> const BallContact& {
      return e_.size_balls_[static_cast<std::size_t>(k % teeth)];
    };
    const auto shift = [&](int v, int k) {
      return ball_displacement_um(ball(k), reading(2, 1, v, k), reading(2, 0, v, k + 1));
    };
    for (int k = 0; k < pairs; ++k) {
      size_item(GearParameter::kEMdK, [&](int v) {
        return ball_dimension_deviation_um(ball(k), shift(v, k), ball(k + across),
                                           shift(v, k + across));
      });
    }
  }
  return out;
}

void ParameterSamples::append(int gear, GearParameterValues&& g) {
  for (int p = 0; p < kGearParameterCount; ++p) {
    for (int s = 0; s < 2; ++s) {
      auto& to = values[p][s];
      auto& from = g.values[p][s];
      to.insert(to.end(), std::make_move_iterator(from.begin()),
                std::make_move_iterator(from.end()));
    }
  }
  if (!chart_gear) {
    chart_gear = gear;
    chart = std::move(g.traces);
  }
}

}  // namespace gearmc
