// summary.json's `cmm` block and its sentence (cmm_summary.h).
#include "engine/reports/cmm_summary.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "engine/effects/cmm_effects.h"
#include "engine/reports/svg_canvas.h"

namespace gearmc {
namespace {

// The q-quantile of `v` (nearest rank: the smallest value with at least q of them at or below it).
double quantile(std::vector<double> v, double q) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  const auto n = static_cast<double>(v.size());
  auto rank = static_cast<std::size_t>(std::max(1.0, std::ceil(q * n)));
  return v[std::min(rank, v.size()) - 1];
}

nlohmann::ordered_json spread(const std::vector<double>& v) {
  return {{"median", quantile(v, 0.5)}, {"p95", quantile(v, 0.95)}, {"max", quantile(v, 1.0)}};
}

}  // namespace

nlohmann::ordered_json cmm_summary_json(const CmmModel& cmm) {
  const ConstrainedMachines& k = cmm.kept;
  nlohmann::ordered_json j;
  j["layout"] = machine_layout_name(cmm.layout);
  j["mpe_e_um"] =
      cmm.mpe_from_table ? nlohmann::ordered_json() : nlohmann::ordered_json(cmm.mpe_e_text);
  if (cmm.mpe_from_table) {
    // The prior's scales chosen from the verification table (no MPE_E to pass).
    j["prior_scales_from_table"] = {{"A_um", cmm.mpe_e.a_um},
                                    {"K_mm_per_um", cmm.mpe_e.k_mm_per_um}};
  }
  j["mpe_p_um"] = cmm.mpe_p_um ? nlohmann::ordered_json(*cmm.mpe_p_um) : nlohmann::ordered_json();
  j["travel_mm"] = {cmm.travel_mm.x(), cmm.travel_mm.y(), cmm.travel_mm.z()};
  j["placement_mm"] = {cmm.placement_mm.x(), cmm.placement_mm.y(), cmm.placement_mm.z()};
  j["stylus_length_mm"] = cmm.stylus_length_mm;
  j["order"] = cmm.order;
  j["machines_seed"] = cmm.seed;
  j["machines_kept"] = k.kept.size();
  j["machines_drawn"] = k.drawn;
  j["acceptance_rate"] = k.acceptance_rate;
  j["failed_length_test"] = k.failed_length;
  j["failed_probing_test"] = k.failed_probing;
  j["test_error_max_um"] = k.largest_error_um;
  // Per kept machine: its largest |E| / MPE_E(L) over the 35 lengths, and its P_FTU.
  j["length_test_ratio"] = cmm.mpe_from_table ? nlohmann::ordered_json() : spread(k.length_ratio);
  j["probing_form_um"] = cmm.mpe_p_um ? spread(k.probing_form_um) : nlohmann::ordered_json();
  if (cmm.posterior) {
    const MachinePosterior& post = *cmm.posterior;
    double largest = 0.0, widest = 0.0;
    for (std::size_t i = 0; i < cmm.verification.size(); ++i) {
      largest = std::max(largest, std::abs(cmm.verification[i].error_um - post.predicted_um[i]));
      widest = std::max(widest, post.predicted_sd_um[i]);
    }
    j["verification"] = {{"file", cmm.verification_written}, {"rows", cmm.verification.size()},
                         {"largest_residual_um", largest},   {"predicted_sd_max_um", widest},
                         {"chi_square", post.chi_square},    {"p_value", post.p_value}};
  } else {
    j["verification"] = nullptr;
  }
  if (cmm.table) {
    double radial = 0.0, axial = 0.0, angular = 0.0;
    for (const RotaryTableErrors& t : cmm.tables) {
      radial = std::max(radial, t.radial_range_um());
      axial = std::max(axial, t.axial_range_um());
      angular = std::max(angular, t.angular_range_arcsec());
    }
    j["rotary_table"] = {{"radial_um", cmm.table->radial_um},
                         {"axial_um", cmm.table->axial_um},
                         {"angular_arcsec", cmm.table->angular_arcsec},
                         {"tables_kept", cmm.tables.size()},
                         {"tables_drawn", cmm.tables_drawn},
                         {"radial_range_max_um", radial},
                         {"axial_range_max_um", axial},
                         {"angular_range_max_arcsec", angular}};
  } else {
    j["rotary_table"] = nullptr;
  }
  j["coverage"] = {
      {"computed_in_this_run", false},
      {"validation",
       "docs/cmm.md, 'Validation': hidden machines drawn from the same prior and kept by the same "
       "tests; the fraction whose gear-parameter error lies within the stated U"}};
  return j;
}

std::string cmm_summary_sentence(const CmmModel& cmm) {
  const ConstrainedMachines& k = cmm.kept;
  std::string s = cmm.mpe_from_table
                      ? "CMM from its verification: the prior's scales from its table (A " +
                            fixed(cmm.mpe_e.a_um, 2) + " µm, K " + fixed(cmm.mpe_e.k_mm_per_um, 0) +
                            " mm/µm), no MPE_E"
                      : "CMM from its data sheet: MPE_E = " + cmm.mpe_e_text + " µm";
  if (cmm.mpe_p_um) s += ", MPE_P = " + fixed(*cmm.mpe_p_um, 2) + " µm";
  s += " (" + machine_layout_name(cmm.layout) + ", " + fixed(cmm.travel_mm.x(), 0) + " × " +
       fixed(cmm.travel_mm.y(), 0) + " × " + fixed(cmm.travel_mm.z(), 0) +
       " mm): " + std::to_string(k.kept.size()) + " machines kept of " + std::to_string(k.drawn) +
       " drawn (" + fixed(100.0 * k.acceptance_rate, 1) + " %)";
  if (!cmm.mpe_from_table) {
    s += "; their length tests reach " + fixed(100.0 * quantile(k.length_ratio, 1.0), 0) +
         " % of MPE_E (median " + fixed(100.0 * quantile(k.length_ratio, 0.5), 0) + " %)";
  }
  if (cmm.mpe_p_um) {
    s += ", their probing form " + fixed(quantile(k.probing_form_um, 1.0), 2) + " µm at most";
  }
  if (cmm.posterior) {
    s += "; drawn to agree with the " + std::to_string(cmm.verification.size()) +
         " measured length errors of " + cmm.verification_written;
  }
  if (cmm.table) {
    s += "; each gear turned on the machine's rotary table (radial " +
         fixed(cmm.table->radial_um, 2) + " µm, axial " + fixed(cmm.table->axial_um, 2) +
         " µm, angular " + fixed(cmm.table->angular_arcsec, 2) + "″; " +
         std::to_string(cmm.tables.size()) + " tables kept of " + std::to_string(cmm.tables_drawn) +
         ")";
  }
  return s + "; each gear is measured on one of them.";
}

}  // namespace gearmc
