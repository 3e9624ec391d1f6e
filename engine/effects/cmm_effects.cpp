// A CMM from its data sheet: the `cmm:` reader and the two effects that measure on the kept
// machines (cmm_effects.h).
#include "engine/effects/cmm_effects.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

#include "engine/schema/parameter_ranges.h"
#include "engine/schema/scenario_keys.h"

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

Eigen::Vector3d read_vector(const YamlValue& value, const ParameterRange& range,
                            std::vector<std::string>* warnings) {
  const std::vector<YamlValue> items = value.as_sequence();
  if (items.size() != 3) {
    throw value.error("three numbers [x, y, z] in " + range.unit);
  }
  Eigen::Vector3d v;
  for (int a = 0; a < 3; ++a)
    v[a] = read_ranged(items[static_cast<std::size_t>(a)], range, warnings);
  return v;
}

std::string mm_text(double v) {
  std::ostringstream s;
  s.precision(4);
  s << v;
  return s.str();
}

}  // namespace

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

std::shared_ptr<const CmmModel> read_cmm(const YamlValue& section, std::uint64_t seed,
                                         double gear_radius_mm, double face_width_mm,
                                         bool radial_shaft, bool internal,
                                         std::vector<std::string>* warnings) {
  const YamlMap map = section.as_map(child_keys("cmm"));
  const RangeTable& ranges = machine_ranges();
  auto model = std::make_shared<CmmModel>();
  model->seed = seed;
  model->where = section.key_location();
  if (const auto layout = map.get_choice("layout", key_choices("cmm.layout"))) {
    model->layout = parse_machine_layout(*layout);
  }
  const YamlValue mpe = map.require("mpe_e_um", "MPE_E as \"A + L/K\" (µm, L in mm)");
  model->mpe_e_text = mpe.as_string();
  try {
    model->mpe_e = parse_length_mpe(model->mpe_e_text);
  } catch (const std::invalid_argument&) {
    throw mpe.error(
        "MPE_E as \"A + L/K\" in µm with L in mm, A >= 0 and K > 0, e.g. \"1.8 + L/300\"");
  }
  // A and K each against their range, named by the key the user wrote.
  for (const auto& [number, part] : {std::pair{model->mpe_e.a_um, "cmm.mpe_e_um.A"},
                                     std::pair{model->mpe_e.k_mm_per_um, "cmm.mpe_e_um.K"}}) {
    ParameterRange range = ranges.at(part);
    range.key = mpe.path();
    check_ranged(number, range, mpe.location(), model->mpe_e_text, warnings);
  }
  model->mpe_p_um = get_ranged(map, "mpe_p_um", ranges.at("cmm.mpe_p_um"), warnings);
  if (const auto travel = map.find("travel_mm")) {
    model->travel_mm = read_vector(*travel, ranges.at("cmm.travel_mm"), warnings);
  }
  if (const auto placement = map.find("placement_mm")) {
    model->placement_mm = read_vector(*placement, ranges.at("cmm.placement_mm"), warnings);
  }
  model->stylus_length_mm =
      get_ranged(map, "stylus_length_mm", ranges.at("cmm.stylus_length_mm"), warnings)
          .value_or(number_default("cmm.stylus_length_mm"));
  model->machines_wanted =
      static_cast<int>(get_ranged_int(map, "machines", ranges.at("cmm.machines"), warnings)
                           .value_or(static_cast<std::int64_t>(number_default("cmm.machines"))));
  model->order =
      static_cast<int>(get_ranged_int(map, "order", ranges.at("cmm.order"), warnings)
                           .value_or(static_cast<std::int64_t>(number_default("cmm.order"))));

  // The gear must lie inside the travel: outside it the error functions (Legendre series over
  // the travel) would be extrapolated.
  {
    const double l = model->stylus_length_mm;
    Eigen::Vector3d reach, low;  // the axes' positions' extremes over the gear's ball centres
    if (!radial_shaft) {
      reach << gear_radius_mm, gear_radius_mm, face_width_mm + l;
      low << -gear_radius_mm, -gear_radius_mm, l;
    } else {
      // The ram outside an external gear, inside a ring gear (towards its axis).
      const double r = internal ? gear_radius_mm : gear_radius_mm + l;
      reach << r, r, face_width_mm;
      low << -r, -r, 0.0;
    }
    for (int a = 0; a < 3; ++a) {
      const double hi = reach[a] + model->placement_mm[a];
      const double lo = low[a] + model->placement_mm[a];
      const double half = 0.5 * model->travel_mm[a];
      if (hi > half || lo < -half) {
        const auto where =
            map.find("placement_mm") ? map.find("placement_mm") : map.find("travel_mm");
        const std::string axis(1, "xyz"[a]);
        const std::string expected =
            "a placement that keeps the gear inside the travel: its ram positions reach " + axis +
            " = " + mm_text(lo) + " … " + mm_text(hi) + " mm, the travel is ±" + mm_text(half) +
            " mm (gear radius " + mm_text(gear_radius_mm) + " mm, stylus " + mm_text(l) + " mm)";
        if (where) throw where->error(expected);
        throw map.missing("travel_mm", expected);
      }
    }
  }

  const MachinePrior prior = [&] {
    MachinePrior p = prior_for(model->mpe_e, model->layout, model->travel_mm);
    p.order = model->order;
    return p;
  }();
  LengthTestOptions test;
  test.stylus_mm = Eigen::Vector3d(0.0, 0.0, -model->stylus_length_mm);
  const ProbePrior probe = model->mpe_p_um ? probe_prior_for(*model->mpe_p_um) : ProbePrior{};
  // An acceptance rate below 1 % is refused: the prior would then say more than the data sheet.
  const int max_draws = std::max(2000, 100 * model->machines_wanted);
  model->kept = draw_constrained(prior, model->mpe_e, model->machines_wanted, max_draws, seed, test,
                                 probe, 0.01);
  if (model->kept.refused) {
    throw InputError(mpe.location(), mpe.path(), model->mpe_e_text,
                     "a data sheet the machine prior can meet; " + model->kept.why);
  }
  // The length test does not depend on where the gear stands; the gear's points do.
  for (KinematicMachine& m : model->kept.kept) m.placement_mm = model->placement_mm;
  return model;
}

void add_cmm_effects(const std::shared_ptr<const CmmModel>& model, bool radial_shaft, bool internal,
                     EffectChain& chain) {
  chain.add(std::make_unique<CmmGeometryEffect>(model, radial_shaft, internal));
  if (model->mpe_p_um) chain.add(std::make_unique<CmmProbingEffect>(model));
}

CmmGeometryEffect::CmmGeometryEffect(std::shared_ptr<const CmmModel> model, bool radial_shaft,
                                     bool internal)
    : MeasurementEffect({machine_parameter(static_cast<int>(model->kept.kept.size()))}),
      model_(std::move(model)),
      radial_(radial_shaft),
      internal_(internal) {}

void CmmGeometryEffect::apply(const PointContext&, std::span<const double> values,
                              Eigen::Vector3d& centre_mm, RandomStream&) const {
  const KinematicMachine& m = model_->kept.kept[cmm_machine_index(*model_, values[0])];
  const Eigen::Vector3d t =
      stylus_offset_mm(centre_mm, model_->stylus_length_mm, radial_, internal_);
  centre_mm += 1e-3 * m.tip_error_um(centre_mm, t);
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
