// Measurement effects (docs/architecture.md, principle 6): everything between the stylus touching
// the real flank and the coordinates the CMM records. One effect is one class with a name from
// docs/formats.md, parameters with units (fixed, or drawn per gear from a law), `apply` — which
// moves the recorded stylus centre the way the physical effect does — and `signature`, the
// first-order change of the reading along the nominal normal per unit of each parameter (used
// by the discrepancy diagnosis). An EffectChain holds a scenario's effects in physical order
// (workpiece and set-up → probe → machine → controller → noise) and applies them to each point.
//
// Frames and units: gear frame = CMM frame (gear axis +Z, centre at the origin), mm for
// positions; effect parameters in the units their names say (µm, ppm, µrad, K, deg).
// The reading of a point is its measured deviation along n (docs/formats.md, readings CSV):
//   e = ((c − p)·n − R)·1000 µm,  c = recorded stylus centre, p, n = nominal point and normal.
// An effect that moves c by Δ (mm) changes the reading by 1000 Δ·n µm.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "core/random_stream.h"
#include "gears/involute_gear.h"

namespace gearmc {

// Where a probed point is, as the effects see it.
struct PointContext {
  Eigen::Vector3d p = Eigen::Vector3d::Zero();   // nominal point, mm
  Eigen::Vector3d n = Eigen::Vector3d::UnitX();  // nominal outward unit normal
  Eigen::Vector3d contact_normal = n;            // real surface's outward normal at contact
  double azimuth_rad = 0.0;  // approach azimuth φ = atan2(−n_y, −n_x) (docs/formats.md)
  int order = 0;             // position in the probing sequence (0-based)
  int sequence_length = 1;   // points in the whole sequence (drift runs over it)
  int tooth = 1;
  FlankSide side = FlankSide::kLeft;
  double stylus_radius_mm = 0.5;
  double base_radius_mm = 0.0;  // the gear's base radius r_b (roll length √(r² − r_b²)); 0: unknown
  int teeth = 0;  // the gear's number of teeth z (tooth k's centre line at 2π(k − 1)/z); 0: unknown
};

// The physical order in which effects act on a reading (an EffectChain applies them sorted by
// stage, and in scenario order within a stage).
enum class EffectStage {
  kWorkpiece = 0,   // where the real surface is: set-up eccentricity, thermal expansion
  kProbe = 1,       // stylus and probe: pre-travel, lobing, radius calibration, tip form
  kMachine = 2,     // CMM geometry and its drift: scale, squareness, drift
  kController = 3,  // how the trigger is latched: servo step quantisation
  kNoise = 4,       // random probing noise
  kReadout = 5,     // the scales' count latched on each axis's grid (scale_resolution)
};

// One parameter of an effect: a value in `unit`, fixed or drawn once per gear.
struct EffectParameter {
  enum class Law { kFixed, kUniform, kNormal };
  std::string name;  // as in the scenario, e.g. "x_ppm"
  std::string unit;  // "µm", "ppm", "µrad", "K", "deg", "ppm/K", "mm"
  Law law = Law::kFixed;
  double value = 0.0;         // kFixed: the value; kNormal: the mean
  double spread = 0.0;        // kNormal: standard deviation
  double lo = 0.0, hi = 0.0;  // kUniform: [lo, hi]
  // 0: drawn from its effect's stream with the effect's other parameters. Otherwise drawn alone
  // from the stream (seed, gear, kEffectParameters, shared_stream): parameters of several effects
  // with the same shared_stream and law take the same value in every gear (the `cmm:` section's
  // geometry and probing parts name the same drawn machine). Values ≥ kSharedStreamBase keep
  // these streams apart from the effects' own (indexed 0, 1, … by their place in the chain).
  std::uint32_t shared_stream = 0;
  static constexpr std::uint32_t kSharedStreamBase = 0x5348'0000;
  // This parameter for one gear (fixed parameters consume no random numbers).
  double draw(RandomStream& rng) const;
  // The central value: value for kFixed and kNormal, the midpoint for kUniform.
  double nominal() const;
};

// `p` labelled with its scenario name and unit (the effects' constructors use it).
EffectParameter named(EffectParameter p, const char* name, const char* unit);

// The law of the random part an effect adds to one reading along n (µm), drawn afresh at every
// point: N(0, gaussian_variance) plus, for each uniform width w, −U(0, w) (a latch delay that
// only ever lengthens the travel). Laws of independent parts add (+=).
struct PointLaw {
  double gaussian_variance_um2 = 0.0;
  std::vector<double> uniform_widths_um;
  double mean_um() const;       // −Σ w/2
  double variance_um2() const;  // gaussian variance + Σ w²/12
  PointLaw& operator+=(const PointLaw& other);
};

class MeasurementEffect {
 public:
  explicit MeasurementEffect(std::vector<EffectParameter> parameters)
      : parameters_(std::move(parameters)) {}
  virtual ~MeasurementEffect() = default;
  MeasurementEffect(const MeasurementEffect&) = delete;
  MeasurementEffect& operator=(const MeasurementEffect&) = delete;

  // The name from docs/formats.md's candidate library (e.g. "probe_lobing", "scale").
  virtual std::string_view name() const = 0;
  virtual EffectStage stage() const = 0;
  const std::vector<EffectParameter>& parameters() const { return parameters_; }

  // Moves the recorded stylus centre `centre_mm` (CMM frame, mm) as the effect does at
  // `point`, with parameter values `values` (one per parameters(), in their units). Random
  // parts (repeatability, noise) draw from `rng`, the point's own stream.
  virtual void apply(const PointContext& point, std::span<const double> values,
                     Eigen::Vector3d& centre_mm, RandomStream& rng) const = 0;

  // First-order change of the reading along n (µm) per unit of each parameter at `point`,
  // about `values`; `out` has one entry per parameter. The default differentiates apply()
  // numerically (central differences, the same random numbers on both sides so that random
  // parts cancel), starting from the nominal stylus centre p + R n. Effects override it with
  // the closed form where it is simple (tests check the two agree).
  virtual void signature(const PointContext& point, std::span<const double> values,
                         std::span<double> out) const;

  // The recorded centre averaged over this effect's per-point random numbers (the per-gear
  // parameters `values` given): what the model predicts for a point (engine/apps/diagnose). The
  // default runs apply() once, which is exact for effects that draw no per-point random
  // numbers; effects that do (noise, probe repeatability, step quantisation) override it.
  virtual void apply_mean(const PointContext& point, std::span<const double> values,
                          Eigen::Vector3d& centre_mm) const;
  // The law of the per-point random part of the reading along n at parameter values `values`
  // (default: none). apply() = apply_mean() + a draw from this law, along n.
  virtual PointLaw point_law(std::span<const double> values) const;

 private:
  std::vector<EffectParameter> parameters_;
};

// Parameter values of every effect of a chain for one gear: values[e][i] = parameter i of
// effect e.
using EffectValues = std::vector<std::vector<double>>;

class EffectChain {
 public:
  EffectChain() = default;
  EffectChain(EffectChain&&) = default;
  EffectChain& operator=(EffectChain&&) = default;

  // Adds an effect; the chain keeps effects sorted by stage (stable within a stage).
  void add(std::unique_ptr<MeasurementEffect> effect);
  bool empty() const { return effects_.empty(); }
  std::size_t size() const { return effects_.size(); }
  const MeasurementEffect& effect(std::size_t i) const { return *effects_[i]; }
  // Index of the effect called `name`, or -1.
  int find(std::string_view name) const;

  // Parameter values for gear `gear`: each random parameter of effect e is drawn from the
  // stream (seed, gear, kEffectParameters, e), in parameter order.
  EffectValues draw(std::uint64_t seed, int gear) const;
  // Nominal parameter values (every parameter at its central value).
  EffectValues nominal() const;

  // The recorded stylus centre (mm) when the true stylus centre at contact is `contact_centre`:
  // every effect applied in order. `contributions`, when not empty (size() entries), receives
  // each effect's change of the reading along n, µm.
  Eigen::Vector3d apply(const PointContext& point, const EffectValues& values,
                        const Eigen::Vector3d& contact_centre, RandomStream& rng,
                        std::span<double> contributions = {}) const;
  // The same, every effect averaged over its per-point random numbers (apply_mean).
  Eigen::Vector3d apply_mean(const PointContext& point, const EffectValues& values,
                             const Eigen::Vector3d& contact_centre) const;
  // The law of the per-point random part of a reading: the effects' laws added.
  PointLaw point_law(const EffectValues& values) const;

 private:
  std::vector<std::unique_ptr<MeasurementEffect>> effects_;
};

// The stream of the random parts of the effects at one probed point: keyed by (seed, gear,
// point order), so a point's noise does not depend on which points were probed before it.
inline RandomStream point_effect_stream(std::uint64_t seed, int gear, int order) {
  return RandomStream(seed, static_cast<std::uint32_t>(gear), StreamPurpose::kEffectNoise,
                      static_cast<std::uint32_t>(order));
}

// The reading of a point along n, µm: ((c − p)·n − R)·1000 (docs/formats.md).
inline double reading_um(const PointContext& point, const Eigen::Vector3d& recorded_centre) {
  return ((recorded_centre - point.p).dot(point.n) - point.stylus_radius_mm) * 1000.0;
}

}  // namespace gearmc
