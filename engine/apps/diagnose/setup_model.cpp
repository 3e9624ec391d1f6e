// The runs' set-up columns and their F test (setup_model.h).
#include "engine/apps/diagnose/setup_model.h"

#include <algorithm>
#include <map>

#include "core/special_functions.h"
#include "engine/apps/diagnose/linear_model.h"

namespace gearmc {

SetupColumns setup_columns(const std::vector<ResidualPoint>& points) {
  SetupColumns out;
  std::map<int, int> run;  // gear number -> 0 … G − 1
  for (const ResidualPoint& p : points) run.emplace(p.gear, 0);
  int next = 0;
  for (auto& [gear, index] : run) {
    index = next++;
    out.gears.push_back(gear);
  }
  const int g = static_cast<int>(run.size());
  const int n = static_cast<int>(points.size());
  out.x = Eigen::MatrixXd::Zero(n, 3 * std::max(0, g - 1));
  if (g < 2) return out;
  out.common.resize(n, 3);
  for (int k = 0; k < n; ++k) {
    const PointContext& c = points[k].context;
    out.common(k, 0) = c.n.x();
    out.common(k, 1) = c.n.y();
    out.common(k, 2) = 1e-3 * (c.p.x() * c.n.y() - c.p.y() * c.n.x());
    const int index = run.at(points[k].gear);
    if (index == 0) continue;
    out.x.block(k, 3 * (index - 1), 1, 3) = out.common.row(k);
  }
  return out;
}

SetupDifferences test_setup_differences(const Eigen::MatrixXd& x, const Eigen::MatrixXd& common,
                                        const Eigen::VectorXd& r, int dof, double alpha) {
  SetupDifferences out;
  if (x.cols() == 0) return out;
  out.tested = true;
  Eigen::MatrixXd both(x.rows(), common.cols() + x.cols());
  both << common, x;
  const LeastSquaresFit shared = least_squares(common, r);
  const LeastSquaresFit fit = least_squares(both, r);
  const int k = fit.rank - shared.rank;
  out.columns = k;
  const int df2 = dof - fit.rank;
  if (k <= 0 || df2 <= 0 || !(fit.rss > 0.0)) return out;
  out.f = ((shared.rss - fit.rss) / k) / (fit.rss / df2);
  out.p_value = f_distribution_upper_tail(std::max(out.f, 0.0), k, df2);
  out.fitted = out.p_value < alpha;
  return out;
}

}  // namespace gearmc
