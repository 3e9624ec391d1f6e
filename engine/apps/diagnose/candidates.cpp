// The candidate effects' design matrices from the library's signatures, and what separates two
// candidates (see candidates.h).
#include "engine/apps/diagnose/candidates.h"

#include <algorithm>
#include <limits>
#include <memory>
#include <optional>
#include <set>

#include <Eigen/QR>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "engine/apps/diagnose/linear_model.h"
#include "engine/effects/artefact_form.h"
#include "engine/effects/effects.h"
#include "engine/effects/probe_lobing.h"
#include "engine/effects/rotary_table.h"
#include "engine/effects/stylus_bending.h"
#include "engine/effects/warmup_straightness.h"

namespace gearmc {
namespace {

EffectParameter fixed_parameter(double value) {
  EffectParameter p;
  p.value = value;
  return p;
}

// A column to take from an effect's signature: parameter index, coefficient name and unit.
struct Pick {
  int parameter;
  std::string coefficient, unit;
};

// Appends to `design` the columns `picks` of `effect`'s signature at every point, about `values`.
void add_columns(CandidateDesign& design, const MeasurementEffect& effect,
                 const std::vector<double>& values, const std::vector<Pick>& picks,
                 const PointContexts& points) {
  const int first = static_cast<int>(design.x.cols());
  design.x.conservativeResize(static_cast<int>(points.size()),
                              first + static_cast<int>(picks.size()));
  // Rows in parallel: each writes only its own row (a signature is a pure function of its point).
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, points.size(), 4096),
                    [&](const tbb::blocked_range<std::size_t>& range) {
                      std::vector<double> out(values.size());
                      for (std::size_t r = range.begin(); r < range.end(); ++r) {
                        effect.signature(points[r], values, out);
                        for (std::size_t c = 0; c < picks.size(); ++c) {
                          design.x(static_cast<int>(r), first + static_cast<int>(c)) =
                              out[picks[c].parameter];
                        }
                      }
                    });
  for (const Pick& pick : picks) {
    design.coefficients.push_back(pick.coefficient);
    design.units.push_back(pick.unit);
  }
}

// Marks the columns that carry information: not negligible against the candidate's largest
// column (1e-6 of its norm: n_z = 1e-17 on a spur gear is no z information) and independent of
// the observable columns before them.
void mark_observable(CandidateDesign& design) {
  const int cols = static_cast<int>(design.x.cols());
  double largest = 0.0;
  for (int c = 0; c < cols; ++c) largest = std::max(largest, design.x.col(c).norm());
  Eigen::MatrixXd x = design.x;
  for (int c = 0; c < cols; ++c) {
    if (!(x.col(c).norm() > 1e-6 * largest)) x.col(c).setZero();
  }
  const ColumnBasis basis = orthonormal_basis(x);
  design.observable.assign(cols, false);
  for (int c : basis.kept) design.observable[c] = true;
}

CandidateDesign start(const std::string& name) {
  CandidateDesign d;
  d.name = name;
  return d;
}

// The R factor (min(rows, cols) × cols, upper trapezoidal) of x's Householder QR.
Eigen::MatrixXd upper_triangle(Eigen::MatrixXd x) {
  Eigen::HouseholderQR<Eigen::Ref<Eigen::MatrixXd>> qr(x);
  const int k = static_cast<int>(std::min(x.rows(), x.cols()));
  return x.topRows(k).triangularView<Eigen::Upper>();
}

}  // namespace

Eigen::MatrixXd CandidateDesign::observable_columns() const {
  const std::vector<int> idx = observable_indices();
  Eigen::MatrixXd out(x.rows(), static_cast<int>(idx.size()));
  for (std::size_t a = 0; a < idx.size(); ++a) out.col(static_cast<int>(a)) = x.col(idx[a]);
  return out;
}

const Eigen::MatrixXd& CandidateDesign::observable_columns(Eigen::MatrixXd& copy) const {
  if (std::find(observable.begin(), observable.end(), false) == observable.end() &&
      static_cast<int>(observable.size()) == x.cols()) {
    return x;
  }
  copy = observable_columns();
  return copy;
}

std::vector<int> CandidateDesign::observable_indices() const {
  std::vector<int> idx;
  for (std::size_t c = 0; c < observable.size(); ++c) {
    if (observable[c]) idx.push_back(static_cast<int>(c));
  }
  return idx;
}

const std::vector<std::string>& candidate_effect_names() {
  static const std::vector<std::string> names = {
      "probe_lobing", "stylus_radius", "scale",        "thermal_expansion",
      "drift",        "squareness",    "eccentricity", "step_quantization",
      "probe_warmup", "straightness",  "rotary_table", "stylus_bending",
      "clocking",     "artefact_form"};
  return names;
}

namespace {

// artefact_form's evaluation ranges: the measured points' own smallest and largest roll length
// and z (a range of 1 mm about a single profile position or section: the orders 2, 3 columns are
// then constant or repeat each other and are marked not observable).
FormRanges form_ranges(const PointContexts& points) {
  FormRanges r{std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity(),
               std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity()};
  for (std::size_t i = 0; i < points.size(); ++i) {
    const PointContext& p = points[i];
    const double roll = ArtefactFormEffect::roll_length_mm(p);
    r.profile_from_mm = std::min(r.profile_from_mm, roll);
    r.profile_to_mm = std::max(r.profile_to_mm, roll);
    r.face_from_mm = std::min(r.face_from_mm, p.p.z());
    r.face_to_mm = std::max(r.face_to_mm, p.p.z());
  }
  if (!(r.profile_to_mm > r.profile_from_mm)) r.profile_to_mm = r.profile_from_mm + 1.0;
  if (!(r.face_to_mm > r.face_from_mm)) r.face_to_mm = r.face_from_mm + 1.0;
  return r;
}

bool form_asked(const CandidateOptions& options) {
  return std::find(options.only.begin(), options.only.end(), "artefact_form") != options.only.end();
}

// The candidates' columns at `points`, in library order, without the observable flags;
// artefact_form when `form` holds its ranges (taken from all points, also when `points` is a
// chunk of them).
std::vector<CandidateDesign> build_designs(const PointContexts& points,
                                           const CandidateOptions& options,
                                           const std::optional<FormRanges>& form) {
  std::vector<CandidateDesign> out;
  // Only the candidates `only` names are made (all when it is empty).
  auto wanted = [&](const char* name) {
    return options.only.empty() ||
           std::find(options.only.begin(), options.only.end(), name) != options.only.end();
  };
  if (wanted("probe_lobing")) {  // probe_lobing: p0, then cos/sin per order
    CandidateDesign d = start("probe_lobing");
    bool first = true;
    for (int k : options.lobing_orders) {
      for (int part = 0; part < 2; ++part) {  // 0: phase 0 → −cos kφ; 1: phase 90°/k → −sin kφ
        const ProbeLobingEffect effect(fixed_parameter(0.0), {k},
                                       {fixed_parameter(0.0), fixed_parameter(part * 90.0 / k)},
                                       fixed_parameter(0.0), ProbeQualificationSpec{});
        std::vector<Pick> picks;
        if (first) picks.push_back({0, "pretravel_um", "µm"});
        first = false;
        picks.push_back({1, (part == 0 ? "cos_" : "sin_") + std::to_string(k) + "_um", "µm"});
        add_columns(d, effect, {0.0, 0.0, part * 90.0 / k, 0.0}, picks, points);
      }
    }
    if (first) {  // no orders: the pre-travel alone
      const ProbeLobingEffect effect(fixed_parameter(0.0), {}, {}, fixed_parameter(0.0),
                                     ProbeQualificationSpec{});
      add_columns(d, effect, {0.0, 0.0}, {{0, "pretravel_um", "µm"}}, points);
    }
    out.push_back(std::move(d));
  }
  if (wanted("stylus_radius")) {
    CandidateDesign d = start("stylus_radius");
    add_columns(d, StylusRadiusEffect(fixed_parameter(0.0)), {0.0}, {{0, "error_um", "µm"}},
                points);
    out.push_back(std::move(d));
  }
  if (wanted("scale")) {
    CandidateDesign d = start("scale");
    add_columns(d, ScaleEffect(fixed_parameter(0.0), fixed_parameter(0.0), fixed_parameter(0.0)),
                {0.0, 0.0, 0.0}, {{0, "x_ppm", "ppm"}, {1, "y_ppm", "ppm"}, {2, "z_ppm", "ppm"}},
                points);
    out.push_back(std::move(d));
  }
  if (wanted("thermal_expansion")) {
    CandidateDesign d = start("thermal_expansion");
    add_columns(d,
                ThermalExpansionEffect(fixed_parameter(0.0), fixed_parameter(0.0),
                                       fixed_parameter(11.5), fixed_parameter(0.0)),
                {0.0, 0.0, 11.5, 0.0}, {{0, "workpiece_delta_t_k", "K"}}, points);
    out.push_back(std::move(d));
  }
  if (wanted("drift")) {
    CandidateDesign d = start("drift");
    add_columns(d, DriftEffect(fixed_parameter(0.0), fixed_parameter(0.0), fixed_parameter(0.0)),
                {0.0, 0.0, 0.0}, {{0, "x_um", "µm"}, {1, "y_um", "µm"}, {2, "z_um", "µm"}}, points);
    out.push_back(std::move(d));
  }
  if (wanted("squareness")) {
    CandidateDesign d = start("squareness");
    add_columns(d,
                SquarenessEffect(fixed_parameter(0.0), fixed_parameter(0.0), fixed_parameter(0.0)),
                {0.0, 0.0, 0.0},
                {{0, "xy_urad", "µrad"}, {1, "xz_urad", "µrad"}, {2, "yz_urad", "µrad"}}, points);
    out.push_back(std::move(d));
  }
  if (wanted("eccentricity")) {
    CandidateDesign d = start("eccentricity");
    add_columns(d, EccentricityEffect(fixed_parameter(0.0), fixed_parameter(0.0)), {0.0, 0.0},
                {{0, "x_um", "µm"}, {1, "y_um", "µm"}}, points);
    out.push_back(std::move(d));
  }
  if (wanted("clocking")) {
    CandidateDesign d = start("clocking");
    add_columns(d, ClockingEffect(fixed_parameter(0.0)), {0.0}, {{0, "angle_urad", "µrad"}},
                points);
    out.push_back(std::move(d));
  }
  if (wanted("step_quantization")) {
    CandidateDesign d = start("step_quantization");
    add_columns(d, StepQuantizationEffect(fixed_parameter(0.0), 2.0), {0.0}, {{0, "step_um", "µm"}},
                points);
    out.push_back(std::move(d));
  }
  if (wanted("probe_warmup")) {
    CandidateDesign d = start("probe_warmup");
    add_columns(d, ProbeWarmupEffect(fixed_parameter(0.0), kWarmupTimeConstant), {0.0},
                {{0, "change_um", "µm"}}, points);
    out.push_back(std::move(d));
  }
  if (wanted("straightness")) {
    CandidateDesign d = start("straightness");
    add_columns(d,
                StraightnessEffect(fixed_parameter(0.0), fixed_parameter(0.0), fixed_parameter(0.0),
                                   fixed_parameter(0.0), kStraightnessLengthMm),
                {0.0, 0.0, 0.0, 0.0},
                {{0, "xy_um", "µm"}, {1, "xz_um", "µm"}, {2, "yx_um", "µm"}, {3, "yz_um", "µm"}},
                points);
    out.push_back(std::move(d));
  }
  // rotary_table: every parameter is linear; the axial pair vanishes on a spur gear (n_z = 0).
  if (wanted("rotary_table")) {
    CandidateDesign d = start("rotary_table");
    std::vector<Pick> picks;
    for (std::size_t i = 0; i < RotaryTableEffect::parameter_names().size(); ++i) {
      picks.push_back(
          {static_cast<int>(i), RotaryTableEffect::parameter_names()[i], i < 4 ? "µm" : "arcsec"});
    }
    add_columns(d, RotaryTableEffect(std::vector<EffectParameter>(8, fixed_parameter(0.0))),
                std::vector<double>(8, 0.0), picks, points);
    out.push_back(std::move(d));
  }
  if (wanted("stylus_bending")) {  // with a vertical stylus (the default)
    CandidateDesign d = start("stylus_bending");
    add_columns(d, StylusBendingEffect(fixed_parameter(0.0), Eigen::Vector3d::UnitZ()), {0.0},
                {{0, "deflection_um", "µm"}}, points);
    out.push_back(std::move(d));
  }
  // artefact_form: only when asked for (`only` names it; see candidates.h).
  if (form) {
    const FormRanges& r = *form;
    CandidateDesign d = start("artefact_form");
    std::vector<Pick> picks;
    for (int k = 0; k < kArtefactFormParameters; ++k) {
      picks.push_back({k, ArtefactFormEffect::parameter_names()[k], "µm"});
    }
    add_columns(d, ArtefactFormEffect({}, r), std::vector<double>(kArtefactFormParameters, 0.0),
                picks, points);
    d.settings = {{"profile_from_mm", r.profile_from_mm},
                  {"profile_to_mm", r.profile_to_mm},
                  {"face_from_mm", r.face_from_mm},
                  {"face_to_mm", r.face_to_mm}};
    out.push_back(std::move(d));
  }
  return out;
}

// The compressed designs from R of [X_1 … X_C, y]: each candidate's columns of R (observability
// decided on them), the residuals R's last column.
void take_columns(CompressedDesigns& out, const Eigen::MatrixXd& r) {
  int at = 0;
  for (CandidateDesign& d : out.candidates) {
    const int q = static_cast<int>(d.coefficients.size());
    d.x = r.middleCols(at, q);
    at += q;
    mark_observable(d);
  }
  out.residual_um = r.col(at);
}

// artefact_form's ranges when it is asked for and there are points.
std::optional<FormRanges> ranges_if_asked(const PointContexts& points,
                                          const CandidateOptions& options) {
  if (points.empty() || !form_asked(options)) return std::nullopt;
  return form_ranges(points);
}

}  // namespace

std::vector<CandidateDesign> candidate_designs(const PointContexts& points,
                                               const CandidateOptions& options) {
  std::vector<CandidateDesign> out =
      build_designs(points, options, ranges_if_asked(points, options));
  for (CandidateDesign& d : out) mark_observable(d);
  return out;
}

CompressedDesigns compressed_candidate_designs(const PointContexts& points,
                                               const Eigen::VectorXd& residual_um,
                                               const CandidateOptions& options) {
  constexpr std::size_t kChunk = 4096;
  const std::size_t n = points.size();
  const std::optional<FormRanges> form = ranges_if_asked(points, options);
  CompressedDesigns out;
  out.rows = static_cast<int>(n);
  // The layout: the designs of an empty chunk (names, coefficients, settings; no rows).
  out.candidates = build_designs(points.slice(0, 0), options, form);
  int columns = 1;
  for (const CandidateDesign& d : out.candidates)
    columns += static_cast<int>(d.coefficients.size());
  const std::size_t chunks = (n + kChunk - 1) / kChunk;
  std::vector<Eigen::MatrixXd> triangles(chunks);
  tbb::parallel_for(std::size_t{0}, chunks, [&](std::size_t k) {
    const std::size_t begin = k * kChunk, count = std::min(kChunk, n - begin);
    const std::vector<CandidateDesign> part =
        build_designs(points.slice(begin, count), options, form);
    Eigen::MatrixXd x(static_cast<int>(count), columns);
    int at = 0;
    for (const CandidateDesign& d : part) {
      x.middleCols(at, d.x.cols()) = d.x;
      at += static_cast<int>(d.x.cols());
    }
    x.col(at) = residual_um.segment(static_cast<int>(begin), static_cast<int>(count));
    triangles[k] = upper_triangle(std::move(x));
  });
  int stacked = 0;
  for (const Eigen::MatrixXd& t : triangles) stacked += static_cast<int>(t.rows());
  Eigen::MatrixXd all(stacked, columns);
  for (std::size_t k = 0, at = 0; k < chunks; ++k) {
    all.middleRows(static_cast<int>(at), triangles[k].rows()) = triangles[k];
    at += static_cast<std::size_t>(triangles[k].rows());
    triangles[k].resize(0, 0);
  }
  take_columns(out, chunks == 0 ? Eigen::MatrixXd(Eigen::MatrixXd::Zero(columns, columns))
                                : upper_triangle(std::move(all)));
  return out;
}

CompressedDesigns compressed_candidate_designs(const PointContexts& points,
                                               const Eigen::VectorXd& residual_um,
                                               const CandidateOptions& options,
                                               const Eigen::MatrixXd& base_q) {
  CompressedDesigns out;
  out.rows = static_cast<int>(points.size()) - static_cast<int>(base_q.cols());
  out.candidates = build_designs(points, options, ranges_if_asked(points, options));
  auto project = [&](const Eigen::MatrixXd& m) -> Eigen::MatrixXd {
    return m - base_q * (base_q.transpose() * m);
  };
  int columns = 1;
  for (const CandidateDesign& d : out.candidates) columns += static_cast<int>(d.x.cols());
  Eigen::MatrixXd all(static_cast<int>(points.size()), columns);
  int at = 0;
  for (CandidateDesign& d : out.candidates) {
    mark_observable(d);
    Eigen::MatrixXd copy;
    const Eigen::MatrixXd& observable = d.observable_columns(copy);
    double correlation = 1.0;
    if (observable.cols() > 0) {
      const Eigen::MatrixXd q = orthonormal_basis(observable).q;
      const std::vector<double> cc = canonical_correlations(base_q, q);
      correlation = static_cast<int>(cc.size()) < q.cols() ? 0.0 : cc.back();
    }
    out.base_correlation.push_back(correlation);
    Eigen::MatrixXd projected = project(d.x);
    for (int c = 0; c < projected.cols(); ++c) {
      if (!(projected.col(c).norm() > 1e-6 * d.x.col(c).norm())) projected.col(c).setZero();
    }
    all.middleCols(at, projected.cols()) = projected;
    at += static_cast<int>(projected.cols());
  }
  all.col(at) = project(residual_um);
  take_columns(out, upper_triangle(std::move(all)));
  return out;
}

Eigen::MatrixXd full_columns(const PointContexts& points, const CandidateOptions& options,
                             const std::vector<CandidateDesign>& compressed,
                             const std::vector<int>& which) {
  CandidateOptions only = options;
  only.only.clear();
  int cols = 0;
  for (int c : which) {
    only.only.push_back(compressed[c].name);
    cols += static_cast<int>(compressed[c].observable_indices().size());
  }
  const std::vector<CandidateDesign> built =
      which.empty() ? std::vector<CandidateDesign>{}
                    : build_designs(points, only, ranges_if_asked(points, only));
  Eigen::MatrixXd x(static_cast<int>(points.size()), cols);
  int at = 0;
  for (int c : which) {
    const auto found = std::find_if(built.begin(), built.end(), [&](const CandidateDesign& d) {
      return d.name == compressed[c].name;
    });
    for (int k : compressed[c].observable_indices()) x.col(at++) = found->x.col(k);
  }
  return x;
}

std::string separating_measurement(std::string_view a, std::string_view b) {
  const std::set<std::string_view> pair = {a, b};
  auto is = [&](std::string_view x, std::string_view y) {
    return pair.count(x) == 1 && pair.count(y) == 1;
  };
  if (is("stylus_radius", "probe_lobing")) {
    return "qualify the stylus on a calibrated reference sphere over all approach directions (or "
           "measure a calibrated ring gauge): a radius error is the same in every direction, "
           "pre-travel and lobing depend on the direction";
  }
  if (is("stylus_radius", "step_quantization") || is("probe_lobing", "step_quantization")) {
    return "repeat the measurement with another approach speed or servo step: the quantisation "
           "shift changes with it, a radius or pre-travel error does not";
  }
  if (is("scale", "thermal_expansion")) {
    return "measure the workpiece and scale temperatures (or repeat at another temperature): "
           "thermal expansion follows the temperature, a scale error does not";
  }
  if (is("eccentricity", "drift")) {
    return "repeat the measurement in reverse probing order, or re-probe the first tooth at the "
           "end: drift changes with the probing order, eccentricity does not";
  }
  const std::set<std::string_view> constant = {"stylus_radius", "probe_lobing",
                                               "step_quantization"};
  const std::set<std::string_view> size = {"scale", "thermal_expansion"};
  if ((constant.count(a) == 1 && size.count(b) == 1) ||
      (constant.count(b) == 1 && size.count(a) == 1)) {
    return "measure a calibrated artefact of another size (a ring gauge or a master gear of "
           "another diameter): a scale or thermal error grows with the distance from the centre, a "
           "radius or pre-travel error does not";
  }
  if (pair.count("clocking") == 1) {
    return "align the gear's angular datum again (probe the datum tooth or the reference tooth "
           "space anew) and remeasure, or measure with the gear turned on the table: a clocking "
           "moves the two flanks of every tooth by ±r_b θ and changes with the alignment, the "
           "machine's errors stay fixed in the CMM frame";
  }
  if (pair.count("rotary_table") == 1) {
    return "remeasure with the gear turned on the rotary table by a few teeth (or measure a "
           "master gear of known pitch and runout): the table's errors stay with the table angle, "
           "the gear's set-up eccentricity and its own pitch deviations turn with the gear";
  }
  if (pair.count("stylus_bending") == 1) {
    return "probe a calibrated sphere at several elevations (or the gear with a horizontal "
           "stylus): bending grows with sin² of the angle between the approach and the stylus, a "
           "radius error is the same in every direction";
  }
  if (pair.count("artefact_form") == 1) {
    return "measure the master gear again turned on the table (or on another CMM, or use its "
           "calibrated form): the artefact's form turns with the gear and stays on every tooth, "
           "the machine's errors stay with the machine's axes";
  }
  if (pair.count("probe_warmup") == 1) {
    return "switch the probe on well before the measurement (or re-probe the first points at the "
           "end with the probe warm): a warm-up change of pre-travel settles, drift and the other "
           "effects do not";
  }
  if (pair.count("straightness") == 1) {
    return "measure a calibrated straight artefact (a straightedge or gauge blocks) along the axes "
           "at the gear's place: straightness shows as a bow along the travel";
  }
  if (pair.count("drift") == 1) {
    return "re-probe the first points at the end of the run: drift shows as a change of the same "
           "point over time";
  }
  if (is("scale", "squareness")) {
    return "measure a calibrated length artefact along the axes and along the diagonals (ISO "
           "10360-2 positions) or a ball plate: squareness shows on the diagonals, scale on the "
           "axis-parallel lengths";
  }
  const std::set<std::string_view> machine = {"scale", "squareness"};
  const std::set<std::string_view> workpiece = {"eccentricity", "thermal_expansion", "clocking"};
  if ((machine.count(a) == 1 && workpiece.count(b) == 1) ||
      (machine.count(b) == 1 && workpiece.count(a) == 1)) {
    return "remeasure with the gear turned on the table (e.g. by 90°): machine errors stay fixed "
           "in the CMM frame, workpiece and set-up errors turn with the gear";
  }
  return "measure a calibrated artefact whose points excite the two signatures differently "
         "(other approach directions, another orientation on the table, another probing order)";
}

}  // namespace gearmc
