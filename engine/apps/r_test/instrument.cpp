// Implementation of instrument.h; the formulas are derived there.
#include "engine/apps/r_test/instrument.h"

#include <cmath>
#include <limits>
#include <numbers>

namespace gearmc::rtest {

double Geometry::reading_at_centre() const {
  return base_radius / std::cos(alpha) - contact_radius();
}

Geometry make_geometry(double ball_radius, double tip_radius, double base_radius) {
  Geometry g;
  g.ball_radius = ball_radius;
  g.tip_radius = tip_radius;
  g.base_radius = base_radius;
  g.alpha = std::asin(1.0 / std::sqrt(3.0));
  const double ca = std::cos(g.alpha), sa = std::sin(g.alpha);
  for (int i = 0; i < kSensors; ++i) {
    const double th = 2.0 * std::numbers::pi * i / kSensors;
    g.base[i] = Vector3d(base_radius * std::cos(th), base_radius * std::sin(th), 0.0);
    g.axis[i] = Vector3d(-ca * std::cos(th), -ca * std::sin(th), sa);
  }
  g.centre = Vector3d(0.0, 0.0, base_radius * std::tan(g.alpha));
  return g;
}

double reading_for(const Vector3d& base, const Vector3d& axis, const Vector3d& ball_centre,
                   double rho) {
  const Vector3d w = ball_centre - base;
  const double a = axis.dot(w);
  const double lateral2 = w.squaredNorm() - a * a;
  const double d = rho * rho - lateral2;
  if (d < 0.0) return std::numeric_limits<double>::quiet_NaN();
  return a - std::sqrt(d);
}

BallCentre solve_ball_centre(const Triple& base, const Triple& axis, const Vector3d& readings,
                             const Vector3d& rho) {
  BallCentre out;
  Triple tip;
  Matrix3d U;
  Vector3d b;
  for (int i = 0; i < kSensors; ++i) {
    tip[i] = base[i] + readings[i] * axis[i];
    U.row(i) = axis[i].transpose();
    b[i] = rho[i] + axis[i].dot(tip[i]);
  }
  Vector3d P = U.partialPivLu().solve(b);
  auto residual = [&](const Vector3d& X) {
    Vector3d F;
    for (int i = 0; i < kSensors; ++i) F[i] = (X - tip[i]).norm() - rho[i];
    return F;
  };
  Vector3d F = residual(P);
  for (int it = 1; it <= 50; ++it) {
    out.iterations = it;
    Matrix3d N;
    for (int i = 0; i < kSensors; ++i) N.row(i) = (P - tip[i]).normalized().transpose();
    const Vector3d step = -N.partialPivLu().solve(F);
    if (!step.allFinite()) return out;
    double t = 1.0;
    Vector3d Pn = P + step, Fn = residual(Pn);
    for (int h = 0; h < 30 && Fn.norm() > F.norm() && Fn.norm() > 1e-13; ++h) {
      t *= 0.5;
      Pn = P + t * step;
      Fn = residual(Pn);
    }
    P = Pn;
    F = Fn;
    if (t * step.norm() < 1e-12) break;
  }
  out.centre = P;
  bool beyond = true;
  for (int i = 0; i < kSensors; ++i) beyond = beyond && axis[i].dot(P - tip[i]) > 0.0;
  out.ok = beyond && F.allFinite() && F.cwiseAbs().maxCoeff() < 1e-9;
  return out;
}

BallCentreDerivatives ball_centre_derivatives(const Triple& base, const Triple& axis,
                                              const Vector3d& readings,
                                              const Vector3d& ball_centre) {
  Matrix3d N;
  Triple n;
  for (int i = 0; i < kSensors; ++i) {
    n[i] = (ball_centre - base[i] - readings[i] * axis[i]).normalized();
    N.row(i) = n[i].transpose();
  }
  const Matrix3d Ninv = N.inverse();
  BallCentreDerivatives D;
  for (int i = 0; i < kSensors; ++i) {
    D.d_base[i] = Ninv.col(i) * n[i].transpose();
    D.d_reading.col(i) = Ninv.col(i) * n[i].dot(axis[i]);
    D.d_rho.col(i) = Ninv.col(i);
  }
  return D;
}

namespace {

struct Residuals {
  std::array<double, kCalibrationPoints> g{};
  std::array<Vector3d, kCalibrationPoints> m;  // unit v_j
  std::array<double, kCalibrationPoints> length{};
  double cost = 0.0;
};

Residuals residuals_at(const Vector3d& axis, const SensorData& d, const Vector3d& C) {
  Residuals r;
  for (int j = 0; j < kCalibrationPoints; ++j) {
    const Vector3d v = d.points[j] - C - d.readings[j] * axis;
    r.length[j] = v.norm();
    r.m[j] = v / r.length[j];
    r.g[j] = r.length[j] - d.rho[j];
    r.cost += r.g[j] * r.g[j];
  }
  return r;
}

}  // namespace

SensorFit calibrate_sensor(const Vector3d& axis, const SensorData& data, const Vector3d& start) {
  SensorFit fit;
  Vector3d C = start;
  Residuals r = residuals_at(axis, data, C);
  double mu = 0.0;  // Marquardt's damping; 0: Gauss–Newton
  for (int it = 1; it <= 100; ++it) {
    fit.iterations = it;
    // J row j = −m_j^T; A = J^T J; gradient J^T g.
    Matrix3d A = Matrix3d::Zero();
    Vector3d grad = Vector3d::Zero();
    for (int j = 0; j < kCalibrationPoints; ++j) {
      A += r.m[j] * r.m[j].transpose();
      grad -= r.g[j] * r.m[j];
    }
    // Converged when the undamped (Gauss–Newton) step from here is negligible: it is the distance
    // to the minimum to first order (damped steps can be short far from it along the
    // ill-conditioned lateral directions, so their length says nothing).
    const Vector3d gn = -A.ldlt().solve(grad);
    if (!gn.allFinite()) break;
    if (gn.norm() < kFitTolerance) {
      const Residuals rn = residuals_at(axis, data, C + gn);
      if (rn.cost <= r.cost) {
        C += gn;
        r = rn;
      }
      fit.ok = true;
      break;
    }
    bool accepted = false;
    const double cost_before = r.cost;
    for (int tries = 0; tries < 60 && !accepted; ++tries) {
      Matrix3d Am = A;
      Am.diagonal() += mu * A.diagonal();
      const Vector3d step = mu == 0.0 ? gn : Vector3d(-Am.ldlt().solve(grad));
      const Residuals rn = residuals_at(axis, data, C + step);
      // Near the minimum a Gauss–Newton step changes the sum of squares by less than its
      // rounding (the lateral directions are flat): it is taken unless the sum clearly grows.
      const double slack = mu == 0.0 ? 1e-12 * r.cost : 0.0;
      if (step.allFinite() && std::isfinite(rn.cost) && rn.cost <= r.cost + slack) {
        C += step;
        r = rn;
        accepted = true;
      } else {
        mu = mu == 0.0 ? 1e-6 : 4.0 * mu;
      }
    }
    if (!accepted) {
      // No decrease even with heavy damping: the sum of squares is flat to rounding here. That is
      // the minimum when the Gauss–Newton step is within the rounding floor of the lateral
      // coordinates (up to ~1e-8 mm with µm residuals), else a failure.
      fit.ok = gn.norm() < kFitFloor;
      break;
    }
    // A decrease at the rounding level of the sum of squares with a Gauss–Newton step within the
    // floor: the minimum.
    if (cost_before - r.cost <= 1e-12 * cost_before && gn.norm() < kFitFloor) {
      fit.ok = true;
      break;
    }
    mu = mu < 1e-9 ? 0.0 : mu / 10.0;
  }
  fit.base = C;
  fit.residuals = r.g;
  return fit;
}

SensorFitDerivatives sensor_fit_derivatives(const Vector3d& axis, const SensorData& data,
                                            const Vector3d& base) {
  const Residuals r = residuals_at(axis, data, base);
  Matrix3d dGdC = Matrix3d::Zero();
  for (int j = 0; j < kCalibrationPoints; ++j) {
    const Matrix3d proj = Matrix3d::Identity() - r.m[j] * r.m[j].transpose();
    dGdC += r.m[j] * r.m[j].transpose() + r.g[j] * proj / r.length[j];
  }
  const Matrix3d inv = dGdC.inverse();
  SensorFitDerivatives D;
  for (int j = 0; j < kCalibrationPoints; ++j) {
    const Matrix3d proj = Matrix3d::Identity() - r.m[j] * r.m[j].transpose();
    const Vector3d dGdl = r.m[j].dot(axis) * r.m[j] + r.g[j] * proj * axis / r.length[j];
    const Vector3d dGdrho = r.m[j];
    const Matrix3d dGdP = -r.m[j] * r.m[j].transpose() - r.g[j] * proj / r.length[j];
    D.d_reading.col(j) = -inv * dGdl;
    D.d_rho.col(j) = -inv * dGdrho;
    D.d_point[j] = -inv * dGdP;
  }
  return D;
}

SensorData moved(const SensorData& data, const DataDirection& d, double s) {
  SensorData out = data;
  for (int j = 0; j < kCalibrationPoints; ++j) {
    out.readings[j] += s * d.reading[j];
    out.rho[j] += s * d.rho[j];
    out.points[j] += s * d.point[j];
  }
  return out;
}

Vector3d directional_derivative(const SensorFitDerivatives& D, const DataDirection& d) {
  Vector3d v = Vector3d::Zero();
  for (int j = 0; j < kCalibrationPoints; ++j) {
    v += D.d_reading.col(j) * d.reading[j] + D.d_rho.col(j) * d.rho[j] + D.d_point[j] * d.point[j];
  }
  return v;
}

VariedSensitivity varied_parameter_sensitivity(const Vector3d& axis, const SensorData& data,
                                               const Vector3d& base, const DataDirection& d,
                                               double delta, double step) {
  VariedSensitivity out;
  const int n = static_cast<int>(std::lround(delta / step));
  int count = 0;
  for (int k = -n; k <= n; ++k) {
    if (k == 0) continue;
    const double s = k * step;
    const SensorFit f = calibrate_sensor(axis, moved(data, d, s), base);
    out.ok = out.ok && f.ok;
    out.value += (f.base - base) / s;
    ++count;
  }
  if (count > 0) out.value /= count;
  return out;
}

}  // namespace gearmc::rtest
