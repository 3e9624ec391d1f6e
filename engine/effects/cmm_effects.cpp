// A CMM from its data sheet: the effects that measure on the kept machines, and the datum and
// stylus geometry they share (cmm_effects.h; the `cmm:` reader is cmm_section.cpp).
#include "engine/effects/cmm_effects.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>

#include "engine/effects/rotary_table.h"

namespace gearmc {
namespace {

// Every kept machine is named by this one shared stream (EffectParameter::shared_stream).
constexpr std::uint32_t kMachineStream = EffectParameter::kSharedStreamBase + 1;

EffectParameter machine_parameter(int kept) {
  EffectParameter p;
  p.name = "machine";
  p.unit = "";
  p.law = EffectParameter::Law::kUniform;
  p.lo = 0.0;
  p.hi = static_cast<double>(kept);
  p.shared_stream = kMachineStream;
  return p;
}

}  // namespace

namespace {

// The machine's error on the gear's axis at z = 0 and z = b (the datum's two ends).
std::array<Eigen::Vector3d, 2> axis_errors_um(const KinematicMachine& machine,
                                              const Eigen::Vector3d& stylus_mm,
                                              double face_width_mm) {
  return {machine.tip_error_um(Eigen::Vector3d::Zero(), stylus_mm),
          machine.tip_error_um(Eigen::Vector3d(0.0, 0.0, face_width_mm), stylus_mm)};
}

Eigen::Vector3d relative_to_datum(const Eigen::Vector3d& error_um,
                                  const std::array<Eigen::Vector3d, 2>& axis, double z_mm,
                                  double face_width_mm) {
  const double f = face_width_mm > 0.0 ? z_mm / face_width_mm : 0.0;
  Eigen::Vector3d datum = axis[0] + f * (axis[1] - axis[0]);
  datum.z() = axis[0].z();  // the lower face is the z datum
  return error_um - datum;
}

}  // namespace

Eigen::Vector3d datum_relative_error_um(const KinematicMachine& machine,
                                        const Eigen::Vector3d& centre_mm,
                                        const Eigen::Vector3d& stylus_mm, double face_width_mm) {
  return relative_to_datum(machine.tip_error_um(centre_mm, stylus_mm),
                           axis_errors_um(machine, stylus_mm, face_width_mm), centre_mm.z(),
                           face_width_mm);
}

std::size_t cmm_machine_index(const CmmModel& model, double value) {
  const std::size_t n = model.kept.kept.size();
  if (n == 0) throw std::logic_error("cmm: no kept machine");
  const double f = std::floor(value);
  if (!(f >= 0.0)) return 0;
  return std::min(static_cast<std::size_t>(f), n - 1);
}

Eigen::Vector3d stylus_offset_mm(const Eigen::Vector3d& centre_mm, double length_mm,
                                 bool radial_shaft, bool internal) {
  if (!radial_shaft) return Eigen::Vector3d(0.0, 0.0, -length_mm);
  const double r = std::hypot(centre_mm.x(), centre_mm.y());
  if (r < 1e-12) return Eigen::Vector3d(0.0, 0.0, -length_mm);
  const Eigen::Vector3d radial(centre_mm.x() / r, centre_mm.y() / r, 0.0);
  return (internal ? length_mm : -length_mm) * radial;
}

void add_cmm_effects(const std::shared_ptr<const CmmModel>& model, bool radial_shaft, bool internal,
                     EffectChain& chain) {
  chain.add(std::make_unique<CmmGeometryEffect>(model, radial_shaft, internal));
  if (model->table) chain.add(std::make_unique<CmmRotaryTableEffect>(model));
  if (model->mpe_p_um) chain.add(std::make_unique<CmmProbingEffect>(model));
}

CmmGeometryEffect::CmmGeometryEffect(std::shared_ptr<const CmmModel> model, bool radial_shaft,
                                     bool internal)
    : MeasurementEffect({machine_parameter(static_cast<int>(model->kept.kept.size()))}),
      model_(std::move(model)),
      radial_(radial_shaft),
      internal_(internal) {
  if (!radial_) {
    const Eigen::Vector3d t(0.0, 0.0, -model_->stylus_length_mm);
    for (const KinematicMachine& m : model_->kept.kept) {
      axis_errors_.push_back(axis_errors_um(m, t, model_->face_width_mm));
    }
  }
}

void CmmGeometryEffect::apply(const PointContext& point, std::span<const double> values,
                              Eigen::Vector3d& centre_mm, RandomStream&) const {
  const std::size_t i = cmm_machine_index(*model_, values[0]);
  const KinematicMachine& m = model_->kept.kept[i];
  // With a rotary table the tooth is probed where the table turned it (θ back to +X): the
  // machine's error is taken there and turned with the gear. Without one: the identity.
  const Eigen::Matrix3d to_machine =
      model_->table
          ? Eigen::AngleAxisd(-table_angle_rad(point), Eigen::Vector3d::UnitZ()).toRotationMatrix()
          : Eigen::Matrix3d::Identity();
  const Eigen::Vector3d c = to_machine * centre_mm;
  const Eigen::Vector3d t = stylus_offset_mm(c, model_->stylus_length_mm, radial_, internal_);
  // A stylus along z is the same at every point: its datum errors were computed once (the axis
  // is the table's, the same in every turn).
  const std::array<Eigen::Vector3d, 2> axis =
      radial_ ? axis_errors_um(m, t, model_->face_width_mm) : axis_errors_[i];
  centre_mm += 1e-3 * (to_machine.transpose() *
                       relative_to_datum(m.tip_error_um(c, t), axis, c.z(), model_->face_width_mm));
}

CmmRotaryTableEffect::CmmRotaryTableEffect(std::shared_ptr<const CmmModel> model)
    : MeasurementEffect({machine_parameter(static_cast<int>(model->kept.kept.size()))}),
      model_(std::move(model)) {}

void CmmRotaryTableEffect::apply(const PointContext& point, std::span<const double> values,
                                 Eigen::Vector3d& centre_mm, RandomStream&) const {
  const RotaryTableErrors& table = model_->tables[cmm_machine_index(*model_, values[0])];
  centre_mm += table.displacement_mm(table_angle_rad(point), centre_mm);
}

void CmmRotaryTableEffect::signature(const PointContext&, std::span<const double>,
                                     std::span<double> out) const {
  std::fill(out.begin(), out.end(), 0.0);
}

void CmmGeometryEffect::signature(const PointContext&, std::span<const double>,
                                  std::span<double> out) const {
  std::fill(out.begin(), out.end(), 0.0);
}

CmmProbingEffect::CmmProbingEffect(std::shared_ptr<const CmmModel> model)
    : MeasurementEffect({machine_parameter(static_cast<int>(model->kept.kept.size()))}),
      model_(std::move(model)) {}

void CmmProbingEffect::apply_mean(const PointContext& point, std::span<const double> values,
                                  Eigen::Vector3d& centre_mm) const {
  const CmmProbe& probe = model_->kept.probes[cmm_machine_index(*model_, values[0])];
  // The recorded centre lies p(d) further along the approach d = −n.
  centre_mm -= 1e-3 * probe.pretravel_um(-point.n) * point.n;
}

void CmmProbingEffect::apply(const PointContext& point, std::span<const double> values,
                             Eigen::Vector3d& centre_mm, RandomStream& rng) const {
  apply_mean(point, values, centre_mm);
  const CmmProbe& probe = model_->kept.probes[cmm_machine_index(*model_, values[0])];
  centre_mm -= 1e-3 * probe.noise_um * rng.normal() * point.n;
}

PointLaw CmmProbingEffect::point_law(std::span<const double> values) const {
  const CmmProbe& probe = model_->kept.probes[cmm_machine_index(*model_, values[0])];
  PointLaw law;
  law.gaussian_variance_um2 = probe.noise_um * probe.noise_um;
  return law;
}

void CmmProbingEffect::signature(const PointContext&, std::span<const double>,
                                 std::span<double> out) const {
  std::fill(out.begin(), out.end(), 0.0);
}

}  // namespace gearmc
