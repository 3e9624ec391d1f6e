// Implementation of gum.h; formulas cited there.
#include "engine/apps/uncertainty/gum.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/constants.h"
#include "core/input_error.h"
#include "core/number_text.h"
#include "core/special_functions.h"
#include "engine/apps/uncertainty/model_function.h"

namespace gearmc::uncertainty {
namespace {

// h with x + h and x − h representable as written: h is rounded to (x + h) − x.
double exact_step(double x, double h) {
  volatile double xp = x + h;
  return xp - x;
}

}  // namespace

double welch_satterthwaite(double u_c, const std::vector<double>& contributions,
                           const std::vector<double>& dof) {
  double denom = 0.0;
  for (std::size_t i = 0; i < contributions.size(); ++i) {
    if (std::isinf(dof[i]) || contributions[i] == 0.0) continue;
    denom += std::pow(contributions[i], 4) / dof[i];
  }
  if (denom == 0.0) return kInf;
  return std::pow(u_c, 4) / denom;
}

double coverage_factor(double p, double nu_eff) {
  const double q = 0.5 * (1.0 + p);
  // Above 1e7 degrees of freedom t and normal differ by < 1e-7 relative.
  if (std::isinf(nu_eff) || nu_eff > 1e7) return normal_quantile(q);
  return student_t_quantile(q, std::max(1.0, std::floor(nu_eff)));
}

std::vector<std::vector<double>> sensitivities(ModelFunction& f, const std::vector<double>& x,
                                               const std::vector<double>& steps) {
  const std::size_t n = x.size(), m = f.outputs();
  std::vector<std::vector<double>> c(m, std::vector<double>(n, 0.0));
  std::vector<double> xp = x, yp(m), ym(m);
  for (std::size_t i = 0; i < n; ++i) {
    const double h = steps[i];
    xp[i] = x[i] + h;
    f.evaluate(xp.data(), yp.data());
    xp[i] = x[i] - h;
    f.evaluate(xp.data(), ym.data());
    xp[i] = x[i];
    for (std::size_t j = 0; j < m; ++j) c[j][i] = (yp[j] - ym[j]) / (2.0 * h);
  }
  return c;
}

GumResult evaluate_gum(const UncertaintyModel& model) {
  ModelFunction f(model);
  const std::size_t n = model.inputs.size(), m = f.outputs();
  GumResult r;
  r.second_order = model.settings.second_order;
  std::vector<double> steps(n), dof(n);
  for (std::size_t i = 0; i < n; ++i) {
    const Law& law = model.inputs[i].law;
    r.x.push_back(law.mean());
    r.u.push_back(law.gum_u());
    dof[i] = model.inputs[i].dof;
    const double wanted =
        r.u[i] > 0 ? kSensitivityStepFraction * r.u[i] : 1e-6 * std::max(1.0, std::fabs(r.x[i]));
    const double h = std::max(wanted, kMinRelativeStep * std::fabs(r.x[i]));
    steps[i] = exact_step(r.x[i], h);
    if (h > wanted && r.u[i] > 0) {
      r.warnings.push_back("the sensitivity to " + model.inputs[i].name +
                           " is a central difference over ±" + shortest_text(steps[i]) +
                           ", wider than 1e-3 u = " + shortest_text(wanted) + ": its estimate " +
                           shortest_text(r.x[i]) +
                           " leaves no finer step in double precision (a non-linear model is "
                           "linearised over that width)");
    }
  }
  r.steps = steps;
  std::vector<double> y(m);
  f.evaluate(r.x.data(), y.data());
  const auto c = sensitivities(f, r.x, steps);
  // A sensitivity hidden by the output's resolution: y = 1e20 + X2 moves in steps of 16384, so
  // X2 ± h leaves it unchanged and c = 0 although Y depends on X2. Told apart from a true zero
  // by a probe a million steps (or a thousand of y's resolutions) wide; said, not hidden (the
  // GUM u(y) misses that input).
  {
    std::vector<double> xp = r.x, yp(m), ym(m);
    for (std::size_t i = 0; i < n; ++i) {
      if (!(r.u[i] > 0)) continue;
      for (std::size_t k = 0; k < m; ++k) {
        const double resolution = std::nextafter(std::fabs(y[k]), kInf) - std::fabs(y[k]);
        if (!(std::fabs(c[k][i]) * 2.0 * steps[i] < 1e3 * resolution)) continue;
        // wide enough to move y by a thousand of its steps if c is of order 1
        const double probe = std::max(1e6 * steps[i], 1e3 * resolution);
        xp[i] = r.x[i] + probe;
        f.evaluate(xp.data(), yp.data());
        xp[i] = r.x[i] - probe;
        f.evaluate(xp.data(), ym.data());
        xp[i] = r.x[i];
        if (yp[k] != ym[k]) {
          r.warnings.push_back(
              "the sensitivity of " + model.outputs[k].name + " to " + model.inputs[i].name +
              " is lost in the output's resolution: " + model.outputs[k].name + " = " +
              shortest_text(y[k]) + " moves in steps of " + shortest_text(resolution) +
              " in double precision, more than " + model.inputs[i].name + " ± " +
              shortest_text(steps[i]) +
              " changes it, so its c and its part of u(y) are not "
              "known; subtract a constant in the output's expression (e.g. compute the deviation "
              "from a nominal)");
        }
      }
    }
  }

  // An output whose every first-order term vanishes (c_i u_i = 0 for every uncertain input: the
  // estimates sit at an extremum or saddle of the model, e.g. y = x² at x = 0) has u = 0 by the
  // law of propagation, which is wrong: its u comes from the higher-order terms (JCGM 100 5.1.2,
  // note), computed for it even when not requested, and said.
  std::vector<bool> flat(m, false);
  bool any_flat = false;
  if (std::any_of(r.u.begin(), r.u.end(), [](double u) { return u > 0; })) {
    for (std::size_t k = 0; k < m; ++k) {
      flat[k] = true;
      for (std::size_t i = 0; i < n; ++i) {
        if (r.u[i] > 0 && c[k][i] * r.u[i] != 0.0) flat[k] = false;
      }
      any_flat = any_flat || flat[k];
    }
  }

  // Higher-order terms (JCGM 100 5.1.2 note) with steps h_i = 1e-2 u_i.
  std::vector<double> second(m, 0.0);
  if (r.second_order || any_flat) {
    std::vector<double> H(n);
    for (std::size_t i = 0; i < n; ++i) H[i] = r.u[i] > 0 ? exact_step(r.x[i], 1e-2 * r.u[i]) : 0.0;
    std::vector<double> xx = r.x, out(m);
    auto at = [&](std::size_t i, double di, std::size_t j, double dj, std::size_t k) {
      xx = r.x;
      xx[i] += di;
      xx[j] += dj;
      f.evaluate(xx.data(), out.data());
      return out[k];
    };
    for (std::size_t k = 0; k < m; ++k) {
      for (std::size_t i = 0; i < n; ++i) {
        if (H[i] == 0) continue;
        for (std::size_t j = 0; j < n; ++j) {
          if (H[j] == 0) continue;
          const double hi = H[i], hj = H[j];
          double d2 = 0.0, d3 = 0.0;
          if (i == j) {
            const double fp = at(i, hi, i, 0, k), fm = at(i, -hi, i, 0, k), f0 = y[k];
            const double fp2 = at(i, 2 * hi, i, 0, k), fm2 = at(i, -2 * hi, i, 0, k);
            // Differences of differences: 2 f0 overflows for |f| near the double's largest
            // value, and a constant output must give exactly 0.
            d2 = ((fp - f0) - (f0 - fm)) / (hi * hi);
            d3 = ((fp2 - fp) - (fp - fm) + (fm - fm2)) / (2 * hi * hi * hi);
          } else {
            d2 = ((at(i, hi, j, hj, k) - at(i, hi, j, -hj, k)) -
                  (at(i, -hi, j, hj, k) - at(i, -hi, j, -hj, k))) /
                 (4 * hi * hj);
            // ∂³f/∂xi∂xj² = [D_jj f(x + h_i e_i) − D_jj f(x − h_i e_i)] / (2 h_i)
            const double p0 = at(i, hi, j, 0, k), m0 = at(i, -hi, j, 0, k);
            const double djj_p =
                ((at(i, hi, j, hj, k) - p0) - (p0 - at(i, hi, j, -hj, k))) / (hj * hj);
            const double djj_m =
                ((at(i, -hi, j, hj, k) - m0) - (m0 - at(i, -hi, j, -hj, k))) / (hj * hj);
            d3 = (djj_p - djj_m) / (2 * hi);
          }
          second[k] += (0.5 * d2 * d2 + c[k][i] * d3) * r.u[i] * r.u[i] * r.u[j] * r.u[j];
        }
      }
    }
  }

  const double p = model.settings.coverage_probability;
  for (std::size_t k = 0; k < m; ++k) {
    GumOutput o;
    o.name = model.outputs[k].name;
    o.estimate = y[k];
    o.sensitivities = c[k];
    double var = 0.0;
    for (std::size_t i = 0; i < n; ++i) {
      o.contributions.push_back(std::fabs(c[k][i]) * r.u[i]);
      for (std::size_t j = 0; j < n; ++j) {
        var += c[k][i] * c[k][j] * model.correlation(Eigen::Index(i), Eigen::Index(j)) * r.u[i] *
               r.u[j];
      }
    }
    o.u_first_order = std::sqrt(std::max(0.0, var));
    // Flat with a second-order variance: an extremum or saddle. Flat without one: the output
    // does not depend on the inputs near the estimates (a constant), u = 0 is right.
    const bool vanishes = flat[k] && second[k] > 0.0;
    if (!r.second_order && !vanishes) second[k] = 0.0;  // computed for another output only
    o.second_order_variance = second[k];
    o.first_order_vanishes = vanishes;
    if (vanishes) {
      r.warnings.push_back(
          "every first-order sensitivity of " + o.name +
          " is zero at the input estimates (an extremum or saddle of the model there): the law "
          "of propagation would give u = 0, so u(" +
          o.name +
          ") is taken from the higher-order terms of JCGM 100 5.1.2 (note; inputs as "
          "uncorrelated), ν_eff is not defined (no first-order contribution) and k is the normal "
          "law's; the output's law is far from normal there, so prefer the Monte Carlo "
          "(JCGM 101) interval");
    }
    o.u = std::sqrt(std::max(0.0, var + second[k]));
    // Tested before the max() above can hide it: max(0, NaN) is 0, so a sensitivity that is not
    // finite (the model overflowing next to the estimate) once gave u = 0 and "inf" cells.
    const bool sensitivities_finite =
        std::all_of(c[k].begin(), c[k].end(), [](double v) { return std::isfinite(v); });
    if (!std::isfinite(o.estimate) || !std::isfinite(var + second[k]) || !sensitivities_finite) {
      std::string inputs;
      for (std::size_t i = 0; i < n; ++i) {
        inputs += (i ? ", " : "") + model.inputs[i].name + " = " + shortest_text(r.x[i]);
      }
      std::string which = std::isfinite(o.estimate) ? "u(y) = " + shortest_text(o.u)
                                                    : "y = " + shortest_text(o.estimate);
      for (std::size_t i = 0; i < n && std::isfinite(o.estimate); ++i) {
        if (!std::isfinite(c[k][i])) {
          which = "d" + o.name + "/d" + model.inputs[i].name + " = " + shortest_text(c[k][i]);
          break;
        }
      }
      throw InputError(model.outputs[k].where, "outputs." + model.outputs[k].name, which,
                       "a model with a finite value, sensitivities and u at the input estimates (" +
                           inputs + ") for the GUM's linearisation");
    }
    o.nu_eff = welch_satterthwaite(o.u, o.contributions, dof);
    o.k = coverage_factor(p, o.nu_eff);
    o.U = o.k * o.u;
    o.lo = o.estimate - o.U;
    o.hi = o.estimate + o.U;
    r.outputs.push_back(std::move(o));
  }
  return r;
}

}  // namespace gearmc::uncertainty
