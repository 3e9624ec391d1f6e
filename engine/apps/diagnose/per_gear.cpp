// Step 4c of the diagnosis: whether a selected effect's value varies from gear to gear (see
// diagnosis_stages.h per_gear_variation).
#include <algorithm>
#include <cmath>
#include <map>
#include <sstream>

#include "core/special_functions.h"
#include "engine/apps/diagnose/diagnosis_stages.h"

namespace gearmc::diagnosis_stages {

void per_gear_variation(State& state, Diagnosis& out) {
  const std::vector<ResidualPoint>& points = state.residuals.points;
  std::map<int, int> gear_index;  // gear number -> 0 … G − 1
  for (const ResidualPoint& p : points) gear_index.emplace(p.gear, 0);
  const int G = static_cast<int>(gear_index.size());
  if (G < 2) return;
  int next = 0;
  for (auto& [gear, index] : gear_index) index = next++;
  const int rows = state.rows;
  const std::vector<int>& selected = out.selection.selected;
  // The per-gear design holds rows × (columns + (G − 1)·q) numbers: beyond kMaxPerGearCells
  // (5·10^6 doubles, 40 MB) the test is not made, and a note says so.
  int widest = 0;
  for (std::size_t s = 0; s < selected.size(); ++s) {
    widest = std::max(widest,
                      static_cast<int>(state.candidates[selected[s]].observable_indices().size()));
  }
  const double cells =
      static_cast<double>(rows) * (static_cast<double>(state.x_selected.cols()) +
                                   static_cast<double>(G - 1) * static_cast<double>(widest) *
                                       static_cast<double>(selected.size()));
  if (!selected.empty() && cells > kMaxPerGearCells) {
    out.notes.push_back("the readings hold " + std::to_string(G) +
                        " gears: a fit with one value per gear and effect (" +
                        std::to_string(static_cast<long long>(cells)) +
                        " numbers) is beyond this diagnosis's memory budget, so whether an "
                        "effect differs from gear to gear was not tested; diagnose fewer gears "
                        "at a time to test it");
    return;
  }
  const double shared_rss = state.fit.rss;
  const int shared_rank = state.fit.rank;
  for (std::size_t s = 0; s < selected.size() && s < out.effects.size(); ++s) {
    FittedEffect& effect = out.effects[s];
    if (effect.absolute || effect.per_gear_from_setups) continue;  // values, not columns
    const int q = static_cast<int>(state.candidates[selected[s]].observable_indices().size());
    const int offset = state.offsets[s];
    // [other effects' columns | this effect's columns, one block per gear].
    const int others = static_cast<int>(state.x_selected.cols()) - q;
    Eigen::MatrixXd x(rows, others + G * q);
    x.leftCols(offset) = state.x_selected.leftCols(offset);
    x.middleCols(offset, others - offset) =
        state.x_selected.middleCols(offset + q, others - offset);
    x.rightCols(G * q).setZero();
    for (int k = 0; k < rows; ++k) {
      const int g = gear_index.at(points[k].gear);
      x.block(k, others + g * q, 1, q) = state.x_selected.block(k, offset, 1, q);
    }
    const LeastSquaresFit split = least_squares(x, state.r);
    const int df1 = split.rank - shared_rank, df2 = rows - split.rank;
    if (df1 <= 0 || df2 <= 0 || !(split.rss > 0.0)) continue;
    const double f = ((shared_rss - split.rss) / df1) / (split.rss / df2);
    effect.per_gear_p = f_distribution_upper_tail(std::max(f, 0.0), df1, df2);
    effect.varies_per_gear = effect.per_gear_p < out.alpha;
    if (!effect.varies_per_gear) continue;
    const double sigma2 = split.rss / df2;
    for (const auto& [gear, g] : gear_index) {
      FittedEffect::GearValues values;
      values.gear = gear;
      const CandidateDesign& candidate = state.candidates[selected[s]];
      int column = 0;
      for (std::size_t c = 0; c < effect.coefficients.size(); ++c) {
        const FittedValue& shared = effect.coefficients[c];
        FittedValue v{shared.name, shared.unit};
        if (candidate.observable[c] && column < q) {
          const int at = others + g * q + column++;
          v.estimable = split.estimable[at];
          if (v.estimable) {
            v.value = split.beta[at];
            v.std_error = std::sqrt(sigma2 * split.cov_unscaled(at, at));
          }
        }
        values.coefficients.push_back(v);
      }
      effect.per_gear.push_back(std::move(values));
    }
    std::ostringstream text;
    text << effect.name << " differs from gear to gear (F test of one value per gear against one "
         << "for all " << G << " gears, p = " << effect.per_gear_p
         << "): its per-gear values are in diagnosis.json";
    out.notes.push_back(text.str());
  }
  // The "after" fit: the varying effects with one value per gear, the others shared.
  // (An effect whose per-gear values come from the runs' set-up differences, setup_model.h, is
  // not split again: its per-gear columns are in the base.)
  std::vector<std::size_t> varying;
  for (std::size_t s = 0; s < selected.size() && s < out.effects.size(); ++s) {
    if (out.effects[s].varies_per_gear && !out.effects[s].per_gear_from_setups) {
      varying.push_back(s);
    }
  }
  if (varying.empty()) return;
  int columns = 0;
  std::vector<int> width(selected.size());
  for (std::size_t s = 0; s < selected.size(); ++s) {
    const int q = static_cast<int>(state.candidates[selected[s]].observable_indices().size());
    const bool split = std::find(varying.begin(), varying.end(), s) != varying.end();
    width[s] = split ? G * q : q;
    columns += width[s];
  }
  // The base of every model (a production gear's part, the runs' set-ups) is in this fit too, as
  // in the shared one: state.r is projected off it, the effects' columns are not (Frisch–Waugh).
  const int base_columns = static_cast<int>(state.base_x.cols());
  Eigen::MatrixXd x = Eigen::MatrixXd::Zero(rows, columns + base_columns);
  if (base_columns > 0) x.rightCols(base_columns) = state.base_x;
  for (std::size_t s = 0, at = 0; s < selected.size(); ++s) {
    const int q = static_cast<int>(state.candidates[selected[s]].observable_indices().size());
    const int offset = state.offsets[s];
    if (width[s] == q) {
      x.middleCols(static_cast<Eigen::Index>(at), q) = state.x_selected.middleCols(offset, q);
    } else {
      for (int k = 0; k < rows; ++k) {
        const int g = gear_index.at(points[k].gear);
        x.block(k, static_cast<Eigen::Index>(at) + g * q, 1, q) =
            state.x_selected.block(k, offset, 1, q);
      }
    }
    at += static_cast<std::size_t>(width[s]);
  }
  const LeastSquaresFit fit = least_squares(x, state.r);
  // The per-gear values reported are this joint fit's (every varying effect split), not the
  // test's, where the other effects were shared: two effects that both vary per gear would
  // otherwise each carry part of the other's variation.
  const double sigma2 = rows > fit.rank ? fit.rss / (rows - fit.rank) : 0.0;
  for (std::size_t s = 0, at = 0; s < selected.size(); ++s) {
    const int q = static_cast<int>(state.candidates[selected[s]].observable_indices().size());
    if (width[s] != q || std::find(varying.begin(), varying.end(), s) != varying.end()) {
      FittedEffect& effect = out.effects[s];
      const CandidateDesign& candidate = state.candidates[selected[s]];
      for (auto& values : effect.per_gear) {
        const int g = gear_index.at(values.gear);
        int column = 0;
        for (std::size_t c = 0; c < values.coefficients.size(); ++c) {
          if (!candidate.observable[c] || column >= q) continue;
          const int k = static_cast<int>(at) + g * q + column++;
          FittedValue& v = values.coefficients[c];
          v.estimable = fit.estimable[k];
          v.value = v.estimable ? fit.beta[k] : kNotAvailable;
          v.std_error = v.estimable ? std::sqrt(sigma2 * fit.cov_unscaled(k, k)) : kNotAvailable;
        }
      }
    }
    at += static_cast<std::size_t>(width[s]);
  }
  state.x_after = std::move(x);
  state.x_after_set = true;
  state.p_after = fit.rank;
  state.r_after = state.r - fit.fitted;
  state.per_gear_fit = true;
}

}  // namespace gearmc::diagnosis_stages
