// The artefact's profile and helix form as Legendre terms on the flank (see artefact_form.h).
#include "engine/effects/artefact_form.h"

#include <algorithm>
#include <cmath>

namespace gearmc {
namespace {

// P₂ and P₃ at t (Abramowitz & Stegun 22.3.8).
double legendre_2(double t) { return 0.5 * (3.0 * t * t - 1.0); }
double legendre_3(double t) { return 0.5 * (5.0 * t * t * t - 3.0 * t); }

double normalised(double v, double from, double to) { return 2.0 * (v - from) / (to - from) - 1.0; }

}  // namespace

const std::vector<std::string>& ArtefactFormEffect::parameter_names() {
  static const std::vector<std::string> names = {
      "left_profile_2_um",  "left_profile_3_um",  "left_helix_2_um",  "left_helix_3_um",
      "right_profile_2_um", "right_profile_3_um", "right_helix_2_um", "right_helix_3_um"};
  return names;
}

ArtefactFormEffect::ArtefactFormEffect(std::vector<EffectParameter> parameters, FormRanges ranges)
    : MeasurementEffect([&] {
        parameters.resize(kArtefactFormParameters);
        for (int k = 0; k < kArtefactFormParameters; ++k) {
          parameters[k].name = parameter_names()[k];
          parameters[k].unit = "µm";
        }
        return std::move(parameters);
      }()),
      ranges_(ranges) {}

double ArtefactFormEffect::roll_length_mm(const PointContext& point) {
  const double r2 = point.p.x() * point.p.x() + point.p.y() * point.p.y();
  const double rb = point.base_radius_mm;
  return std::sqrt(std::max(0.0, r2 - rb * rb));
}

void ArtefactFormEffect::signature(const PointContext& point, std::span<const double>,
                                   std::span<double> out) const {
  std::fill(out.begin(), out.end(), 0.0);
  const double x =
      normalised(roll_length_mm(point), ranges_.profile_from_mm, ranges_.profile_to_mm);
  const double y = normalised(point.p.z(), ranges_.face_from_mm, ranges_.face_to_mm);
  const int first = point.side == FlankSide::kLeft ? 0 : 4;
  out[first + 0] = legendre_2(x);
  out[first + 1] = legendre_3(x);
  out[first + 2] = legendre_2(y);
  out[first + 3] = legendre_3(y);
}

void ArtefactFormEffect::apply(const PointContext& point, std::span<const double> values,
                               Eigen::Vector3d& c, RandomStream&) const {
  double s[kArtefactFormParameters];
  signature(point, values, s);
  double f_um = 0.0;
  for (int k = 0; k < kArtefactFormParameters; ++k) f_um += values[k] * s[k];
  c += 1e-3 * f_um * point.n;
}

}  // namespace gearmc
