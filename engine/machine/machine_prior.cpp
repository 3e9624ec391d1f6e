// The machines drawn for a data sheet (machine_prior.h).
#include "engine/machine/machine_prior.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

#include "core/random_stream.h"

namespace gearmc {

namespace {

// A non-negative decimal number "d+[.d*]" of at most 30 characters at `at` (advanced past it);
// false if none.
bool read_number(const std::string& text, std::size_t& at, double& value) {
  const std::size_t start = at;
  while (at < text.size() && text[at] >= '0' && text[at] <= '9') ++at;
  if (at == start) return false;
  if (at < text.size() && text[at] == '.') {
    ++at;
    while (at < text.size() && text[at] >= '0' && text[at] <= '9') ++at;
  }
  if (at - start > 30) return false;  // no MPE has 30 digits; std::stod would overflow
  value = std::stod(text.substr(start, at - start));
  return true;
}

void skip_spaces(const std::string& text, std::size_t& at) {
  while (at < text.size() && (text[at] == ' ' || text[at] == '\t')) ++at;
}

}  // namespace

LengthMpe parse_length_mpe(const std::string& text) {
  // Scanned by hand in one bounded pass (no std::regex: its recursion overflowed the stack on
  // long inputs elsewhere in gearmc).
  const auto refuse = [&](const std::string& what) {
    const std::string shown = text.size() > 60 ? text.substr(0, 60) + "…" : text;
    return std::invalid_argument("got '" + shown + "', expected " + what);
  };
  const std::string form = "MPE_E as \"A + L/K\" in µm with L in mm, e.g. \"1.8 + L/300\"";
  LengthMpe mpe;
  std::size_t at = 0;
  skip_spaces(text, at);
  if (!read_number(text, at, mpe.a_um)) throw refuse(form);
  skip_spaces(text, at);
  if (at >= text.size() || text[at] != '+') throw refuse(form);
  ++at;
  skip_spaces(text, at);
  if (at >= text.size() || text[at] != 'L') throw refuse(form);
  ++at;
  skip_spaces(text, at);
  if (at >= text.size() || text[at] != '/') throw refuse(form);
  ++at;
  skip_spaces(text, at);
  if (!read_number(text, at, mpe.k_mm_per_um)) throw refuse(form);
  skip_spaces(text, at);
  if (at != text.size()) throw refuse(form);
  if (!(mpe.k_mm_per_um > 0.0)) throw refuse("K > 0 in \"A + L/K\"");
  return mpe;
}

MachinePrior prior_for(const LengthMpe& mpe, MachineLayout layout,
                       const Eigen::Vector3d& travel_mm) {
  MachinePrior p;
  p.layout = layout;
  p.travel_mm = travel_mm;
  p.translation_um = 0.5 * travel_mm / mpe.k_mm_per_um;
  p.rotation_urad = 1e3 * mpe.a_um / (2.0 * 300.0);
  p.squareness_urad = 1e3 / mpe.k_mm_per_um;
  return p;
}

KinematicMachine draw_machine(const MachinePrior& prior, std::uint64_t seed, std::uint64_t index) {
  TrialStream rng(seed, index, TrialPurpose::kMachineDraw);
  KinematicMachine m;
  m.layout = prior.layout;
  m.travel_mm = prior.travel_mm;
  for (int a = 0; a < 3; ++a) {
    AxisErrors& f = m.axes[static_cast<std::size_t>(a)];
    for (int c = 0; c < 3; ++c) {
      auto& t = f.translation_um[static_cast<std::size_t>(c)];
      auto& r = f.rotation_urad[static_cast<std::size_t>(c)];
      t.assign(static_cast<std::size_t>(prior.order) + 1, 0.0);
      r.assign(static_cast<std::size_t>(prior.order) + 1, 0.0);
      for (int k = 1; k <= prior.order; ++k) {
        t[static_cast<std::size_t>(k)] = prior.translation_um[a] / k * rng.normal();
        r[static_cast<std::size_t>(k)] = prior.rotation_urad / k * rng.normal();
      }
    }
  }
  m.squareness_xy_urad = prior.squareness_urad * rng.normal();
  m.squareness_xz_urad = prior.squareness_urad * rng.normal();
  m.squareness_yz_urad = prior.squareness_urad * rng.normal();
  return m;
}

ConstrainedMachines draw_constrained(const MachinePrior& prior, const LengthMpe& mpe, int wanted,
                                     int max_draws, std::uint64_t seed,
                                     const LengthTestOptions& test) {
  ConstrainedMachines out;
  for (int i = 0; i < max_draws && static_cast<int>(out.kept.size()) < wanted; ++i) {
    KinematicMachine m = draw_machine(prior, seed, static_cast<std::uint64_t>(i));
    ++out.drawn;
    double ratio = 0.0;
    for (const LengthError& e : length_test(m, test)) {
      ratio = std::max(ratio, std::abs(e.error_um) / mpe.at(e.length_mm));
    }
    if (ratio <= 1.0) {
      out.kept.push_back(std::move(m));
      out.largest_ratio = std::max(out.largest_ratio, ratio);
    }
  }
  out.acceptance_rate =
      out.drawn > 0 ? static_cast<double>(out.kept.size()) / static_cast<double>(out.drawn) : 0.0;
  if (static_cast<int>(out.kept.size()) < wanted) {
    out.refused = true;
    std::ostringstream why;
    why << "the machine prior cannot meet MPE_E = " << mpe.a_um << " + L/" << mpe.k_mm_per_um
        << " µm: " << out.kept.size() << " of " << out.drawn
        << " drawn machines passed the ISO 10360-2 length test, " << wanted
        << " wanted (give the prior smaller scales, or check the MPE)";
    out.why = why.str();
  }
  return out;
}

}  // namespace gearmc
