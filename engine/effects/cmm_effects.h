// A CMM from its data sheet (`cmm:`, docs/cmm.md): the constrained Monte Carlo of virtual CMMs
// put into the effect chain. The section's MPE_E (ISO 10360-2), MPE_P (ISO 10360-5), layout and
// travel are read, machines are drawn from the prior they scale and kept when they pass both
// acceptance tests (engine/machine/machine_prior.h), and two effects measure every gear on one
// kept machine, drawn per gear (uniformly among the kept ones, the same machine for both):
//  * `cmm_geometry` (machine stage): the kept machine's 21 error functions move the recorded
//    stylus centre by its tip error, the stylus offset's Abbe arms included, relative to the
//    gear's datums (the axis and the lower face, measured on the same machine);
//  * `cmm_probing` (probe stage, only with MPE_P): its probe's pre-travel left after
//    qualification, along the approach −n, and its touch scatter;
//  * `cmm_rotary_table` (workpiece stage, only with `rotary_table:`): the gear turned on the
//    machine's table, each tooth brought to the probing region (+X) — the table's own error
//    motions move it, and `cmm_geometry` then takes the machine's error where the tooth is
//    probed, not where it lies on the gear.
// Their one parameter, `machine`, is the kept machine's index (uniform over [0, N), the machine
// floor(value)); it is not a physical quantity, so their first-order signatures are zero (the
// diagnosis does not fit it). Frames: gear frame = machine axes, mm; errors µm.
// Engine-internal (exposes the YAML reader).
#pragma once

#include <array>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "core/yaml_reader.h"
#include "engine/effects/measurement_effect.h"
#include "engine/machine/machine_prior.h"
#include "engine/machine/rotary_axis.h"
#include "engine/machine/verification.h"

namespace gearmc {

// The `cmm:` section as read, and the machines it gave.
struct CmmModel {
  MachineLayout layout = MachineLayout::kBridge;
  std::string mpe_e_text;  // as written, e.g. "1.8 + L/300"; empty without `mpe_e_um`
  // Without `mpe_e_um` (a verification table instead): the prior's A and K chosen from the
  // table (prior_scales_from_table), and no MPE_E to pass.
  bool mpe_from_table = false;
  LengthMpe mpe_e;
  std::optional<double> mpe_p_um;
  Eigen::Vector3d travel_mm = Eigen::Vector3d(700.0, 1000.0, 600.0);
  Eigen::Vector3d placement_mm = Eigen::Vector3d::Zero();
  double stylus_length_mm = 50.0;
  int machines_wanted = 200;
  int order = 3;
  std::uint64_t seed = 1;      // the scenario's
  double face_width_mm = 0.0;  // the gear's: where its axis datum is measured (below)
  // `verification:` — the user's measured length errors (as opened: relative to the scenario's
  // folder) and the posterior they give; empty and null without it.
  std::string verification_path;
  std::string verification_written;  // as the scenario writes it (outputs show this)
  std::vector<VerificationRow> verification;
  std::shared_ptr<const MachinePosterior> posterior;
  // `rotary_table:` — the gear turned on a table, each tooth probed in the same region of the
  // machine: its data sheet, the kept tables (one per kept machine, the same index), how many
  // were drawn. Without it the gear stands still and the machine moves around it.
  std::optional<RotaryTableSpec> table;
  std::vector<RotaryTableErrors> tables;
  int tables_drawn = 0;
  InputLocation where;  // the `cmm:` key (for messages of commands that refuse the section)
  ConstrainedMachines kept;
};

// Reads `cmm:` and draws its machines (seed: the scenario's). `gear_radius_mm`, `face_width_mm`
// and the stylus (`radial_shaft`: along the radius, else along z) place the gear in the travel (a
// gear that leaves it is an InputError). Throws
// InputError with file:line:column for bad keys and values, and at `mpe_e_um` when the prior
// cannot meet the data sheet (the acceptance rate in the message).
std::shared_ptr<const CmmModel> read_cmm(const YamlValue& section, std::uint64_t seed,
                                         double gear_radius_mm, double face_width_mm,
                                         bool radial_shaft, bool internal,
                                         std::vector<std::string>* warnings);

// Reads a verification table (docs/cmm.md, "Your verification results"): a CSV with the header
// `position,length_mm,error_um[,u_um]` (any order; lines starting with # are comments), one
// measured length error per line — position one of length_test_positions()'s names, the length
// within the position's line through the travel, the error in µm, its standard uncertainty u_um
// (else `default_u_um`; neither: an error). Throws InputError at file:line:column.
std::vector<VerificationRow> read_verification_table(const std::string& text,
                                                     const std::string& source,
                                                     const Eigen::Vector3d& travel_mm,
                                                     std::optional<double> default_u_um);

// Adds `cmm_geometry` (and `cmm_probing` with MPE_P, `cmm_rotary_table` with a table) for
// `model` to `chain`.
void add_cmm_effects(const std::shared_ptr<const CmmModel>& model, bool radial_shaft, bool internal,
                     EffectChain& chain);

// The stylus offset (mm, from the ram's reference point to the ball centre) for a ball centre at
// `centre_mm`: −ℓ ẑ for a shaft along z (the scenario's `stylus.shaft_axis: z`); for a radial
// shaft −ℓ r̂ on an external gear (the ram outside) and +ℓ r̂ on a ring gear (the ram towards the
// axis), r̂ the radial unit vector.
Eigen::Vector3d stylus_offset_mm(const Eigen::Vector3d& centre_mm, double length_mm,
                                 bool radial_shaft, bool internal);

class CmmGeometryEffect : public MeasurementEffect {
 public:
  CmmGeometryEffect(std::shared_ptr<const CmmModel> model, bool radial_shaft, bool internal);
  std::string_view name() const override { return "cmm_geometry"; }
  EffectStage stage() const override { return EffectStage::kMachine; }
  void apply(const PointContext& point, std::span<const double> values, Eigen::Vector3d& centre_mm,
             RandomStream& rng) const override;
  void signature(const PointContext& point, std::span<const double> values,
                 std::span<double> out) const override;
  const CmmModel& model() const { return *model_; }

 private:
  std::shared_ptr<const CmmModel> model_;
  bool radial_;
  bool internal_;
  std::vector<std::array<Eigen::Vector3d, 2>> axis_errors_;  // per kept machine (shaft along z)
};

// The kept machine's rotary table (workpiece stage, like `rotary_table`): its error motions at
// the table angle that brings the point's tooth to the probing region.
class CmmRotaryTableEffect : public MeasurementEffect {
 public:
  explicit CmmRotaryTableEffect(std::shared_ptr<const CmmModel> model);
  std::string_view name() const override { return "cmm_rotary_table"; }
  EffectStage stage() const override { return EffectStage::kWorkpiece; }
  void apply(const PointContext& point, std::span<const double> values, Eigen::Vector3d& centre_mm,
             RandomStream& rng) const override;
  void signature(const PointContext& point, std::span<const double> values,
                 std::span<double> out) const override;

 private:
  std::shared_ptr<const CmmModel> model_;
};

class CmmProbingEffect : public MeasurementEffect {
 public:
  explicit CmmProbingEffect(std::shared_ptr<const CmmModel> model);
  std::string_view name() const override { return "cmm_probing"; }
  EffectStage stage() const override { return EffectStage::kProbe; }
  void apply(const PointContext& point, std::span<const double> values, Eigen::Vector3d& centre_mm,
             RandomStream& rng) const override;
  void apply_mean(const PointContext& point, std::span<const double> values,
                  Eigen::Vector3d& centre_mm) const override;
  PointLaw point_law(std::span<const double> values) const override;
  void signature(const PointContext& point, std::span<const double> values,
                 std::span<double> out) const override;

 private:
  std::shared_ptr<const CmmModel> model_;
};

// The machine's error at a ball centre (µm) relative to the gear's datums, as a gear measurement
// sees it: the gear's axis and its lower face are measured on the same machine before the
// flanks, so the error the machine makes there is part of the datum, not of the flanks. The axis
// is the line through the machine's errors (x, y) on the axis at z = 0 and z = b (a bore or
// journals probed at both ends: its offset and tilt), the z datum the error's z on the axis at
// z = 0. Without this, a machine's local offset would read as the gear's eccentricity.
Eigen::Vector3d datum_relative_error_um(const KinematicMachine& machine,
                                        const Eigen::Vector3d& centre_mm,
                                        const Eigen::Vector3d& stylus_mm, double face_width_mm);

// The kept machine a `machine` value names: floor(value) within [0, N).
std::size_t cmm_machine_index(const CmmModel& model, double value);

}  // namespace gearmc
