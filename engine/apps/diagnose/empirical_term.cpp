// The empirical term fitted along the axis of the remaining structure (see empirical_term.h).
#include "engine/apps/diagnose/empirical_term.h"

#include <algorithm>
#include <cmath>
#include <set>
#include <stdexcept>

#include "engine/apps/diagnose/linear_model.h"
#include "engine/effects/empirical_effect.h"

namespace gearmc {
namespace {

constexpr int kMaxOrder = 6;

Eigen::MatrixXd basis_matrix(const std::vector<double>& x, EmpiricalBasis basis, double from,
                             double to, int order) {
  const int cols = basis == EmpiricalBasis::kLegendre ? order : 2 * order;
  Eigen::MatrixXd b(static_cast<int>(x.size()), cols);
  for (std::size_t r = 0; r < x.size(); ++r) {
    const std::vector<double> v = empirical_basis_values(basis, x[r], from, to, order);
    for (int c = 0; c < cols; ++c) b(static_cast<int>(r), c) = v[static_cast<std::size_t>(c)];
  }
  return b;
}

}  // namespace

std::string empirical_identify_by(const std::string& axis) {
  if (axis == "roll_length") {
    return "measure the profile of a calibrated involute artefact (or this master against its "
           "calibration certificate) and repeat with the gear turned on the table: a form of the "
           "workpiece turns with it, a probe or machine error along the profile stays with the "
           "probing directions and positions";
  }
  if (axis == "face_position") {
    return "measure a calibrated straight artefact (a cylinder or gauge block face along z) at the "
           "gear's place: a structure there too is the z axis's straightness, one only on the gear "
           "is its helix form";
  }
  if (axis == "tooth") {
    return "remeasure with the gear turned on the table by half a turn: structure that turns with "
           "the gear is the workpiece's (pitch, runout), structure that stays in place is the "
           "machine's or the table's";
  }
  if (axis == "flank") {
    return "measure the two opposite faces of a calibrated gauge block with the same stylus and "
           "approach directions: a left/right difference that shows there too is the probe's or "
           "the stylus qualification's in those directions";
  }
  if (axis == "approach_azimuth") {
    return "qualify the probe over many approach directions on a calibrated reference sphere (a "
           "per-direction map): structure that follows the approach direction there is the probe's";
  }
  if (axis == "x_position" || axis == "y_position" || axis == "z_position") {
    return "measure a calibrated length along the " + axis.substr(0, 1) +
           " axis at a pitch finer than a third of the period (a step gauge or a laser "
           "interferometer): a periodic error there is the scale's or its encoder's interpolation "
           "error, for the machine's error map";
  }
  if (axis == "probing_order") {
    return "re-probe the first points at the end of the run and repeat in reverse probing order, "
           "logging the machine and probe temperatures: structure that follows time is a warm-up "
           "or drift";
  }
  return "";
}

EmpiricalTerm fit_empirical_term(const std::vector<ResidualPoint>& points,
                                 const Eigen::VectorXd& residual_after_um, int library_parameters,
                                 double noise_variance_um2, const std::string& axis_name,
                                 double min_delta_bic) {
  EmpiricalTerm out;
  out.axis = axis_name;
  out.identify_by = empirical_identify_by(axis_name);
  const int n = static_cast<int>(points.size());
  const double rss0 = residual_after_um.squaredNorm();
  auto excess = [&](double rss, int parameters) {
    const int dof = n - parameters;
    return dof > 0 ? std::sqrt(std::max(0.0, rss / dof - noise_variance_um2)) : 0.0;
  };
  out.rms_before_um = out.rms_after_um = n > 0 ? std::sqrt(rss0 / n) : 0.0;
  out.excess_rms_before_um = out.excess_rms_after_um = excess(rss0, library_parameters);
  EmpiricalAxis axis;
  try {
    axis = parse_empirical_axis(axis_name);
  } catch (const std::invalid_argument&) {
    out.why_not = axis_name.size() > 9 && axis_name.substr(1) == "_position"
                      ? "a periodic error along a machine axis is not among the empirical terms "
                        "(they follow the gear's own axes): fitted.yaml keeps the library's "
                        "effects only"
                      : "no axis to fit a term along";
    return out;
  }
  const EmpiricalBasis basis = natural_basis(axis);
  out.basis = std::string(empirical_basis_name(basis));
  std::vector<double> x(points.size());
  std::set<long long> distinct;
  for (std::size_t k = 0; k < points.size(); ++k) {
    x[k] = empirical_coordinate(axis, points[k].context);
    distinct.insert(std::llround(x[k] * 1e9));
  }
  if (!x.empty()) {
    out.from = *std::min_element(x.begin(), x.end());
    out.to = *std::max_element(x.begin(), x.end());
  }
  const int d = static_cast<int>(distinct.size());
  out.max_order = basis == EmpiricalBasis::kLegendre ? std::min(kMaxOrder, d - 1)
                                                     : std::min(kMaxOrder, (d - 1) / 2);
  if (out.max_order < 1 || !(rss0 > 0.0)) {
    out.why_not = "the points take " + std::to_string(d) + " distinct positions along " +
                  axis_name + ": too few for a term";
    return out;
  }
  const double ln_n = std::log(static_cast<double>(n));
  out.bic.push_back(0.0);
  int best = 0;
  double best_bic = 0.0;
  for (int k = 1; k <= out.max_order; ++k) {
    const LeastSquaresFit fit =
        least_squares(basis_matrix(x, basis, out.from, out.to, k), residual_after_um);
    if (n - library_parameters - fit.rank <= 0 || !(fit.rss > 0.0)) break;
    const double bic = n * std::log(fit.rss / rss0) + fit.rank * ln_n;
    out.bic.push_back(bic);
    if (bic < best_bic) {
      best_bic = bic;
      best = k;
    }
  }
  out.delta_bic = best_bic;
  if (best == 0 || best_bic > -min_delta_bic) {
    out.why_not = "no order of a " + out.basis + " term along " + axis_name +
                  " lowers the BIC by the selection's " +
                  std::to_string(std::lround(min_delta_bic));
    return out;
  }
  const Eigen::MatrixXd b = basis_matrix(x, basis, out.from, out.to, best);
  const LeastSquaresFit fit = least_squares(b, residual_after_um);
  const int dof = n - library_parameters - fit.rank;
  const double sigma2 = fit.rss / dof;
  out.fitted = true;
  out.order = best;
  for (int c = 0; c < b.cols(); ++c) {
    const int k = basis == EmpiricalBasis::kLegendre ? c + 1 : c / 2 + 1;
    EmpiricalTermValue v;
    v.name = std::string(basis == EmpiricalBasis::kLegendre || c % 2 == 0 ? "a_" : "b_") +
             std::to_string(k) + "_um";
    v.value_um = fit.estimable[c] ? fit.beta[c] : 0.0;
    v.std_error_um = fit.estimable[c] ? std::sqrt(sigma2 * fit.cov_unscaled(c, c)) : 0.0;
    out.terms.push_back(v);
  }
  out.fitted_rms_um = std::sqrt(fit.fitted.squaredNorm() / n);
  out.rms_after_um = std::sqrt(fit.rss / n);
  out.excess_rms_after_um = excess(fit.rss, library_parameters + fit.rank);
  return out;
}

Eigen::MatrixXd empirical_columns(const std::vector<ResidualPoint>& points,
                                  const EmpiricalTerm& term) {
  const EmpiricalAxis axis = parse_empirical_axis(term.axis);
  const EmpiricalBasis basis =
      term.basis == "legendre" ? EmpiricalBasis::kLegendre : EmpiricalBasis::kHarmonic;
  std::vector<double> x(points.size());
  for (std::size_t k = 0; k < points.size(); ++k) {
    x[k] = empirical_coordinate(axis, points[k].context);
  }
  return basis_matrix(x, basis, term.from, term.to, term.order);
}

}  // namespace gearmc
