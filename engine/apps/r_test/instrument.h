// The contact R-Test of Zhou, Lai, Jiang & Ding ("Calibration uncertainty evaluation of a contact
// R-Test by combining GUM and MCM", docs/sources.md [P3]): a precision ball of radius R on the
// machine spindle, touched by three displacement sensors whose spherical tips (radius r) sit on
// axes that are mutually perpendicular and meet at the point O. Sensor i has the base point C_i1
// on the reference plane M and the axis direction u_i; its reading l_i = |C_i0 C_i1| places the
// tip centre at C_i0 = C_i1 + l_i u_i, and the ball centre P solves |P − C_i0| = R + r, i = 1..3.
//
// Here: the nominal geometry, the forward model (readings → ball centre, a safeguarded Newton
// iteration that keeps the physical root), the exact readings of a ball at a given centre, and
// the calibration of the base points C_i1 from readings at known ball positions (a
// Levenberg–Marquardt least-squares fit per sensor) with the exact derivatives of that implicit
// solution (implicit function theorem).
//
// Frame and units: the machine frame, mm. Origin O' = the projection of O on plane M (z = 0), z
// up towards the ball; sensor i's base point is at azimuth θ_i = 120° (i − 1) from +x.
#pragma once

#include <Eigen/Dense>

#include <array>
#include <cstddef>

namespace gearmc::rtest {

using Eigen::Matrix3d;
using Eigen::Vector3d;

inline constexpr int kSensors = 3;
inline constexpr int kCalibrationPoints = 6;  // P3 drives the ball to 6 known points

using Triple = std::array<Vector3d, kSensors>;

struct Geometry {
  double ball_radius = 15.0;  // R, mm (P3: ceramic ball Ø 30 mm)
  double tip_radius = 2.5;    // r, mm (P3: Keyence GT2-S1 tip)
  double base_radius = 40.0;  // λ, mm: distance of each base point from O' (assumed, see docs)
  double alpha = 0.0;         // angle of each axis to plane M, rad: arcsin(1/√3)
  Triple axis;                // u_i, unit, from C_i1 towards O
  Triple base;                // nominal C_i1
  Vector3d centre;            // O = (0, 0, λ tan α)
  double contact_radius() const { return ball_radius + tip_radius; }  // R + r
  // The reading with the ball centre at O: λ / cos α − (R + r).
  double reading_at_centre() const;
};

// Three mutually perpendicular axes spaced at 120° in azimuth make the angle α = arcsin(1/√3)
// (35.26°) with plane M: u_i · u_j = sin²α − cos²α / 2 = 0.
Geometry make_geometry(double ball_radius, double tip_radius, double base_radius);

// The reading of a sensor (base point `base`, axis `axis`) whose tip touches a ball of centre P
// with tip-ball distance ρ = R + r: l = u·w − √(ρ² − |w|² + (u·w)²), w = P − C_i1 (the tip below
// the ball centre along the axis). NaN when the ball is out of the sensor's reach.
double reading_for(const Vector3d& base, const Vector3d& axis, const Vector3d& ball_centre,
                   double rho);

struct BallCentre {
  Vector3d centre = Vector3d::Zero();
  bool ok = false;  // converged to |F| < 1e-9 mm on the physical root
  int iterations = 0;
};

// The ball centre P from the three readings l_i (mm) and the tip-ball distances ρ_i (mm):
// F_i(P) = |P − C_i0| − ρ_i = 0. Start: the tangent-plane solution u_i·(P − C_i0) = ρ_i; then
// Newton steps with the Jacobian rows n_i = (P − C_i0)/|P − C_i0|, halved while |F| does not
// decrease (at most 30 halvings), stopped when the step is below 1e-12 mm. The equations have
// two roots, mirror images through the plane of the three tip centres; the physical one has the
// ball beyond every tip, u_i·(P − C_i0) > 0, and anything else is reported as ok = false.
BallCentre solve_ball_centre(const Triple& base, const Triple& axis, const Vector3d& readings,
                             const Vector3d& rho);

// ∂P/∂(C_i1, l_i, ρ_i) at a solution P (implicit function theorem on F(P, ·) = 0): with N the
// matrix of rows n_i^T, dP = N⁻¹ (dρ + [n_i·dC_i1] + [n_i·u_i dl_i]).
struct BallCentreDerivatives {
  std::array<Matrix3d, kSensors> d_base;  // column k: ∂P/∂C_i1,k
  Matrix3d d_reading;                     // column i: ∂P/∂l_i
  Matrix3d d_rho;                         // column i: ∂P/∂ρ_i
};
BallCentreDerivatives ball_centre_derivatives(const Triple& base, const Triple& axis,
                                              const Vector3d& readings,
                                              const Vector3d& ball_centre);

// The calibration data of one sensor: the ball centres P_j (mm, machine frame), its readings l_j
// and the tip-ball distances ρ_j it assumes (mm).
struct SensorData {
  std::array<Vector3d, kCalibrationPoints> points;
  std::array<double, kCalibrationPoints> readings{};
  std::array<double, kCalibrationPoints> rho{};
};

struct SensorFit {
  Vector3d base = Vector3d::Zero();
  bool ok = false;
  int iterations = 0;
  std::array<double, kCalibrationPoints> residuals{};  // g_j = |P_j − C_i1 − l_j u| − ρ_j, mm
};

// Least-squares base point of one sensor: minimises Σ_j g_j(C)² with g_j as above, by
// Levenberg–Marquardt (Marquardt's diagonal scaling; Madsen, Nielsen & Tingleff, "Methods for
// non-linear least squares problems", DTU 2004, §3.2) from `start`: each iteration tries the
// Gauss–Newton step first and damps only when the sum of squares would grow. Converged (ok) as
// said above; at most 100 iterations. The axis u is the known design direction (as in P3).
// The lateral coordinates of a base point are known to the fit only through the ~1/60 tilt of the
// contact normals, so rounding leaves Gauss–Newton steps of 1e-9 to 1e-8 mm at the minimum of a
// fit with µm residuals. Converged: a Gauss–Newton step below kFitTolerance, or no decrease of the
// sum of squares possible with a Gauss–Newton step below kFitFloor (1e-3 µm, far below the µm
// the results show).
inline constexpr double kFitTolerance = 1e-8;  // mm
inline constexpr double kFitFloor = 1e-6;      // mm
SensorFit calibrate_sensor(const Vector3d& axis, const SensorData& data, const Vector3d& start);

// Exact derivatives of the fitted base point with respect to the data (implicit function theorem
// on the normal equations G(C, d) = J(C, d)^T g(C, d) = 0: dC/dd = −(∂G/∂C)⁻¹ ∂G/∂d, with the
// second-derivative terms g_j ∂²g_j, so they are exact at a solution with non-zero residuals).
struct SensorFitDerivatives {
  Eigen::Matrix<double, 3, kCalibrationPoints> d_reading;  // column j: ∂C/∂l_j
  Eigen::Matrix<double, 3, kCalibrationPoints> d_rho;      // column j: ∂C/∂ρ_j
  std::array<Matrix3d, kCalibrationPoints> d_point;        // ∂C/∂P_j
};
SensorFitDerivatives sensor_fit_derivatives(const Vector3d& axis, const SensorData& data,
                                            const Vector3d& base);

// A direction in the data space of one sensor's calibration: d(l_j), d(ρ_j), d(P_j).
struct DataDirection {
  std::array<double, kCalibrationPoints> reading{};
  std::array<double, kCalibrationPoints> rho{};
  std::array<Vector3d, kCalibrationPoints> point{};
  DataDirection() { point.fill(Vector3d::Zero()); }
};
SensorData moved(const SensorData& data, const DataDirection& d, double s);
// The exact derivative of the fitted base point along `d`.
Vector3d directional_derivative(const SensorFitDerivatives& D, const DataDirection& d);

// P3's varied-parameter sensitivity: move the data along `d` by s = ±e, ±2e, …, ±δ (the other
// inputs fixed), refit, and average the output changes ΔC(s)/s over the 2δ/e steps. Exact for a
// fit that is linear along d; otherwise differs from the derivative by O(δ²) (the odd terms
// cancel between +s and −s). ok = false when a refit did not converge.
struct VariedSensitivity {
  Vector3d value = Vector3d::Zero();
  bool ok = true;
};
VariedSensitivity varied_parameter_sensitivity(const Vector3d& axis, const SensorData& data,
                                               const Vector3d& base, const DataDirection& d,
                                               double delta, double step);

}  // namespace gearmc::rtest
