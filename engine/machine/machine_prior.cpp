// The machines drawn for a data sheet (machine_prior.h).
#include "engine/machine/machine_prior.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

#include "core/random_stream.h"
#include "engine/machine/verification.h"

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
  // Scanned by hand in one bounded pass (no regular-expression library: its recursion overflowed
  // the stack on long inputs elsewhere in gearmc).
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

ProbePrior probe_prior_for(double mpe_p_um) {
  ProbePrior p;
  p.mpe_p_um = mpe_p_um;
  p.component_um = mpe_p_um / 6.0;
  p.noise_max_um = mpe_p_um / 4.0;
  return p;
}

CmmProbe draw_probe(const ProbePrior& prior, std::uint64_t seed, std::uint64_t index) {
  CmmProbe probe;
  if (!(prior.mpe_p_um > 0.0)) return probe;
  TrialStream rng(seed, index, TrialPurpose::kProbeDraw);
  for (std::size_t k = 0; k < 3; ++k) {
    probe.cos_um[k] = prior.component_um * rng.normal();
    probe.sin_um[k] = prior.component_um * rng.normal();
  }
  probe.noise_um = prior.noise_max_um * rng.uniform();
  return probe;
}

std::vector<LengthError> length_test_with_probe(const KinematicMachine& machine,
                                                const CmmProbe& probe,
                                                const LengthTestOptions& test) {
  std::vector<LengthError> errors = length_test(machine, test);
  const std::vector<LengthTestPosition> positions = length_test_positions(machine.travel_mm);
  for (LengthError& e : errors) {
    const Eigen::Vector3d& u = positions[static_cast<std::size_t>(e.position)].direction;
    // End A touched along +û moves its recorded centre +p(û) û, end B along −û by −p(−û) û.
    e.error_um -= probe.pretravel_um(u) + probe.pretravel_um(-u);
  }
  return errors;
}

ConstrainedMachines draw_constrained(const MachinePrior& prior, const LengthMpe& mpe, int wanted,
                                     int max_draws, std::uint64_t seed,
                                     const LengthTestOptions& test, const ProbePrior& probe,
                                     double min_acceptance, const MachinePosterior* posterior) {
  ConstrainedMachines out;
  const bool probing = probe.mpe_p_um > 0.0;
  for (int i = 0; i < max_draws && static_cast<int>(out.kept.size()) < wanted; ++i) {
    if (i >= 2000 && static_cast<double>(out.kept.size()) < min_acceptance * i) break;
    const auto index = static_cast<std::uint64_t>(i);
    KinematicMachine m;
    CmmProbe p;
    if (posterior != nullptr) {
      draw_from_posterior(prior, probe, *posterior, seed, index, m, p);
    } else {
      m = draw_machine(prior, seed, index);
      p = draw_probe(probe, seed, index);
    }
    ++out.drawn;
    double ratio = 0.0, largest = 0.0;
    for (const LengthError& e : length_test_with_probe(m, p, test)) {
      ratio = std::max(ratio, std::abs(e.error_um) / mpe.at(e.length_mm));
      largest = std::max(largest, std::abs(e.error_um));
    }
    const double form = probing ? probing_test_form_um(p, seed, index) : 0.0;
    if (ratio > 1.0) ++out.failed_length;
    if (probing && form > probe.mpe_p_um) ++out.failed_probing;
    if (ratio <= 1.0 && (!probing || form <= probe.mpe_p_um)) {
      out.kept.push_back(std::move(m));
      out.probes.push_back(p);
      out.length_ratio.push_back(ratio);
      out.probing_form_um.push_back(form);
      out.largest_ratio = std::max(out.largest_ratio, ratio);
      out.largest_error_um = std::max(out.largest_error_um, largest);
    }
  }
  out.acceptance_rate =
      out.drawn > 0 ? static_cast<double>(out.kept.size()) / static_cast<double>(out.drawn) : 0.0;
  if (static_cast<int>(out.kept.size()) < wanted) {
    out.refused = true;
    std::ostringstream why;
    why << "the machine prior cannot meet MPE_E = " << mpe.a_um << " + L/" << mpe.k_mm_per_um
        << " µm";
    if (probing) why << " and MPE_P = " << probe.mpe_p_um << " µm";
    why << ": " << out.kept.size() << " of " << out.drawn << " drawn machines passed ("
        << out.failed_length << " failed the ISO 10360-2 length test";
    if (probing) why << ", " << out.failed_probing << " the ISO 10360-5 probing test";
    why << "), an acceptance rate of " << 100.0 * out.acceptance_rate << " %";
    if (min_acceptance > 0.0) why << " (at least " << 100.0 * min_acceptance << " % is needed)";
    why << ", " << wanted
        << " wanted; the prior's scales follow A and K together, so a data sheet with a small A "
           "for its K (or a tight MPE_P) is beyond it — check the MPEs";
    out.why = why.str();
  }
  return out;
}

}  // namespace gearmc
