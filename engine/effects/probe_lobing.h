// Probe pre-travel and lobing with P2's qualification strategies (docs/sources.md [P2],
// docs/reference-values.md "Probe pre-travel and lobing").
//
// A touch-trigger probe signals only after travelling a direction-dependent pre-travel
//   p(φ) = p0 + Σ_k a_k cos(k (φ − φ_k))   [µm]
// beyond the touch, so the recorded stylus centre lies p(φ) further along the approach (−n).
// P2 measured ±0.75 µm with period π/3 (6 lobes, k = 6) on its own probe; kinematic probes show
// 3 lobes (k = 3) and up to 1:2 between opposite directions. Unidirectional repeatability adds
// N(0, σ²) to each trigger.
//
// Qualification (P2): the software compensates with a conditional radius R_cond = R − ΔR,
// ΔR being the pre-travel it assumes for the approach direction; the residual pre-travel error
// of a reading is p(φ) − ΔR(φ). Strategies:
//  * none:            ΔR = 0 (no pre-travel compensation).
//  * mean6:           P2 variant 1: two 3-point qualifications with period 2π/3, the second
//                     rotated by π/6; ΔR = the mean pre-travel of the six directions, one value
//                     for every direction.
//  * six_directions:  P2 variant 2: three extremum directions with period 2π/3, one on +Y
//                     (90°, 210°, 330° for the default start of 90°), plus +X, −X, −Y;
//                     ΔR(φ) = the value of the nearest of the six directions, or (use:
//                     interpolated) linear interpolation in φ between neighbouring directions.
//  * per_direction:   ΔR(φ) = p(φ) exactly (a probe mapped in every direction): the residual
//                     is the repeatability alone.
// Qualification readings are taken as the mean of many repetitions (P2: 10), so ΔR uses the
// deterministic p(φ) (the mean of 10 has σ/√10; neglected here, stated in the README).
#pragma once

#include <string>
#include <vector>

#include "engine/effects/lobing_harmonic.h"
#include "engine/effects/measurement_effect.h"

namespace gearmc {

enum class ProbeQualification { kNone, kMean6, kSixDirections, kPerDirection };
enum class SixDirectionUse { kNearest, kInterpolated };

struct ProbeQualificationSpec {
  ProbeQualification strategy = ProbeQualification::kNone;
  SixDirectionUse use = SixDirectionUse::kNearest;
  double start_deg = 90.0;  // first qualification direction (P2 variant 2: +Y)
};

// The qualification directions (radians, in [0, 2π)) a strategy probes; empty for none and
// per_direction.
std::vector<double> qualification_directions_rad(const ProbeQualificationSpec& spec);

// Pre-travel model: p(φ) from p0 and harmonics.
struct LobingModel {
  double pretravel_um = 0.0;  // p0
  std::vector<LobingHarmonic> harmonics;
  double pretravel_at(double azimuth_rad) const;  // µm
};

// ΔR(φ) (µm) that the qualification strategy assigns to approach azimuth φ, for a probe whose
// true pre-travel is `model`.
double qualification_correction_um(const LobingModel& model, const ProbeQualificationSpec& spec,
                                   double azimuth_rad);

// The effect `probe_lobing`. Parameters, in order: pretravel_um, then amplitude_<k>_um and
// phase_<k>_deg for each harmonic, then repeatability_um. The recorded centre moves along −n
// by p(φ) + repeatability·N(0,1) and back by ΔR(φ) of the qualification.
class ProbeLobingEffect : public MeasurementEffect {
 public:
  ProbeLobingEffect(EffectParameter pretravel, std::vector<int> orders,
                    std::vector<EffectParameter> amplitude_and_phase, EffectParameter repeatability,
                    ProbeQualificationSpec qualification);
  std::string_view name() const override { return "probe_lobing"; }
  EffectStage stage() const override { return EffectStage::kProbe; }
  void apply(const PointContext& point, std::span<const double> values, Eigen::Vector3d& centre_mm,
             RandomStream& rng) const override;
  // Without the repeatability draw; its law is N(0, repeatability²) along n.
  void apply_mean(const PointContext& point, std::span<const double> values,
                  Eigen::Vector3d& centre_mm) const override;
  PointLaw point_law(std::span<const double> values) const override;
  const ProbeQualificationSpec& qualification() const { return qualification_; }
  // The lobing model for parameter values `values`.
  LobingModel model(std::span<const double> values) const;
  // Residual pre-travel error (µm) p(φ) − ΔR(φ) without repeatability.
  double residual_um(std::span<const double> values, double azimuth_rad) const;

 private:
  std::vector<int> orders_;
  ProbeQualificationSpec qualification_;
};

}  // namespace gearmc
