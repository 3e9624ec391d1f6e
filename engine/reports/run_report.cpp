// Composition of what `gearmc run` writes and prints (see run_report.h).
// Here: the presentation of a run (bins, laws, warnings), summary.json and histograms.csv; the
// figures are drawn in run_figures.cpp, report.html in run_report_html.cpp and the terminal
// tables in run_terminal.cpp.
#include "engine/reports/run_report.h"

#include <cmath>
#include <iomanip>
#include <sstream>

#include "engine/effects/measurement_effect.h"
#include "engine/reports/cmm_summary.h"
#include "engine/reports/run_report_cells.h"
#include "engine/statistics/stats_json.h"

namespace gearmc {
using namespace run_output;
namespace {

nlohmann::ordered_json side_pair(const RunResults& r, RunQuantity q, const HistogramBins& bins) {
  nlohmann::ordered_json j;
  for (int s = 0; s < 2; ++s) {
    const ErrorStatistics& e = run_statistics(r, q, s);
    j[kSideName[s]] = stats_json(e.moments, e.histogram, bins);
  }
  return j;
}

LawVerdict judge_laws(const ErrorStatistics& e, const HistogramBins& bins) {
  LawVerdict v;
  if (e.moments.count() < 2) {
    v.sentence = "too few values to fit a law";
    return v;
  }
  // Fits on bins four times finer than the plotted ones (still at least one RelativeHistogram
  // bucket wide, histogram_bins.h); chi-square cells of the plotted width.
  const Histogram fine = e.histogram.to_histogram(bins.lo, bins.width / 4.0, bins.count * 4);
  FitOptions options;
  options.chi_square_cell_width_um = bins.width;
  v.fits = fit_distributions(fine, options);
  for (const DistributionFit& f : v.fits) {
    if (!f.applicable) continue;
    if (!v.closest) v.closest = f;
    const bool rejected = f.chi_square_p_value < kLawRejectionLevel;  // NaN: not testable
    if (!rejected && !v.accepted) v.accepted = f;
  }
  if (!v.closest) {
    v.sentence = "no law could be fitted";
  } else if (v.accepted) {
    const DistributionFit& a = *v.accepted;
    v.sentence =
        std::string(law_name(a.distribution.law)) +
        (std::isnan(a.chi_square_p_value) ? " (best AIC; too few cells for a χ² test)"
                                          : " (χ² p = " + format_p(a.chi_square_p_value) + ")");
  } else {
    v.sentence = "no law of the five fits at the 1 % level; closest: " +
                 std::string(law_name(v.closest->distribution.law)) +
                 ", χ² p = " + format_p(v.closest->chi_square_p_value);
  }
  return v;
}

nlohmann::ordered_json fit_json(const DistributionFit& f) {
  nlohmann::ordered_json j;
  j["law"] = std::string(law_name(f.distribution.law));
  const auto names = f.distribution.parameter_names();
  j["parameters"] = {{std::string(names[0]), f.distribution.a},
                     {std::string(names[1]), f.distribution.b}};
  j["aic"] = f.aic;
  j["ks_distance"] = f.ks_distance;
  j["chi_square_p_value"] =
      std::isfinite(f.chi_square_p_value) ? nlohmann::ordered_json(f.chi_square_p_value) : nullptr;
  return j;
}

nlohmann::ordered_json law_json(const LawVerdict& v) {
  if (!v.closest) return nullptr;
  nlohmann::ordered_json j = fit_json(v.accepted ? *v.accepted : *v.closest);
  j["accepted"] = v.accepted.has_value();
  j["rejection_level"] = kLawRejectionLevel;
  j["verdict"] = v.sentence;
  return j;
}

}  // namespace

const ErrorStatistics& run_statistics(const RunResults& r, RunQuantity q, int s) {
  switch (q) {
    case kPointDelta:
      return r.point[s];
    case kFlankMax:
      return r.flank_max[s];
    case kFlankMean:
      return r.flank_mean[s];
    default:
      return r.total_abs[s];
  }
}

RunPresentation present_run(const RunResults& r, Provenance provenance) {
  RunPresentation view;
  view.provenance = std::move(provenance);
  for (int q = 0; q < kRunQuantities; ++q) {
    const auto quantity = static_cast<RunQuantity>(q);
    view.bins[q] = freedman_diaconis_bins(
        {&run_statistics(r, quantity, 0).histogram, &run_statistics(r, quantity, 1).histogram});
  }
  for (int s = 0; s < 2; ++s) view.laws[s] = judge_laws(r.flank_max[s], view.bins[kFlankMax]);
  view.warnings = contact_warnings(r);
  return view;
}

std::vector<std::string> contact_warnings(const RunResults& r) {
  std::vector<std::string> warnings;
  const std::uint64_t bad = r.failed_contacts + r.edge_contacts + r.collisions;
  if (r.contacts > 0 && bad > 0 && 100 * bad > r.contacts) {
    std::ostringstream w;
    const double percent = 100.0 * static_cast<double>(bad) / static_cast<double>(r.contacts);
    w << (2 * bad > r.contacts ? "most contacts gave no value: " : "contacts without a value: ")
      << bad << " of " << r.contacts << " (" << std::fixed << std::setprecision(1) << percent
      << " %: failed " << r.failed_contacts << ", edge " << r.edge_contacts << ", collisions "
      << r.collisions
      << "); the statistics describe only the other points — check the stylus (radius, shaft) "
         "against the tooth space (`run --points` gives each point's status) and any normal_um "
         "expression";
    warnings.push_back(w.str());
  }
  if (r.runout_redrawn_gears > 0) {
    warnings.push_back(
        "F_r constrains the profile and helix shapes: " + std::to_string(r.runout_redrawn_gears) +
        " of " + std::to_string(r.gears) +
        " gears had shapes that alone broke F_r and were drawn again (" +
        std::to_string(r.runout_redraws) +
        " redraws in all), so the shapes follow the scenario's law conditioned on meeting F_r");
  }
  std::uint64_t non_finite = 0;
  for (int q = 0; q < kRunQuantities; ++q) {
    for (int s = 0; s < 2; ++s)
      non_finite += run_statistics(r, static_cast<RunQuantity>(q), s).non_finite;
  }
  if (non_finite > 0) {
    warnings.push_back(std::to_string(non_finite) +
                       " error values were not finite (left out of every statistic): an effect "
                       "parameter is probably far outside its physical range");
  }
  return warnings;
}

bool is_p1_setup(const Scenario& s) {
  // P1's set-up (Table 1 and Fig. 4 of P1): the gear, the grid and the stylus.
  const GearParameters& g = s.gear;
  return g.teeth == 24 && g.module_mm == 5.6 && g.pressure_angle_deg == 20.0 &&
         g.profile_shift == 0.90116 && g.face_width_mm == 78.89 && s.stylus_radius_mm == 0.5 &&
         s.probing.grid.points_along_profile == 10 && s.probing.grid.sections_across_face == 5;
}

nlohmann::ordered_json run_summary_json(const Scenario& scenario, const MonteCarloRun& mc,
                                        const RunResults& r, const RunPresentation& view,
                                        std::optional<int> only_gear) {
  nlohmann::ordered_json summary;
  summary["provenance"] = provenance_json(view.provenance);
  summary["scenario"] = scenario.name;
  summary["source"] = scenario.source_path;
  summary["gears"] = r.gears;
  summary["only_gear"] = only_gear ? nlohmann::ordered_json(*only_gear) : nlohmann::ordered_json();
  summary["teeth"] = mc.probed_teeth();
  summary["points_per_flank"] = mc.points_per_flank();
  summary["stylus_radius_mm"] = scenario.stylus_radius_mm;
  summary["seed"] = scenario.seed;
  summary["contacts"] = r.contacts;
  summary["failed_contacts"] = r.failed_contacts;
  summary["edge_contacts"] = r.edge_contacts;
  summary["collisions"] = r.collisions;
  summary["runout_redrawn_gears"] = r.runout_redrawn_gears;
  summary["wall_s"] = r.wall_s;
  summary["contacts_per_s"] = r.wall_s > 0 ? static_cast<double>(r.contacts) / r.wall_s : 0.0;
  summary["warnings"] = view.warnings;
  summary["input_warnings"] = scenario.warnings;
  // Flanks probed on a mesh instead of the analytic perturbed flank (`surfaces:`).
  nlohmann::ordered_json mesh_surfaces = nlohmann::ordered_json::array();
  for (const FlankMeshSurface& surface : scenario.surfaces) {
    mesh_surfaces.push_back(
        {{"tooth", surface.tooth},
         {"flank", std::string(1, side_letter(surface.side))},
         {"mesh", surface.mesh_path},
         {"contact", surface.contact == MeshContactPoint::kSmoothed ? "smoothed" : "facets"},
         {"triangles", triangle_count(*surface.mesh)}});
  }
  summary["mesh_surfaces"] = mesh_surfaces;
  summary["quantile_relative_resolution"] = RelativeHistogram::kRelativeResolution;
  summary["delta_rcomp_um"] = {{"point", side_pair(r, kPointDelta, view.bins[kPointDelta])},
                               {"flank_max", side_pair(r, kFlankMax, view.bins[kFlankMax])},
                               {"flank_mean", side_pair(r, kFlankMean, view.bins[kFlankMean])}};
  if (!scenario.effects->empty()) {
    nlohmann::ordered_json names = nlohmann::ordered_json::array();
    for (std::size_t e = 0; e < scenario.effects->size(); ++e) {
      names.push_back(std::string(scenario.effects->effect(e).name()));
    }
    summary["effects"] = names;
    auto signed_stats = [](const RunningStats& m) {
      nlohmann::ordered_json j;
      j["n"] = m.count();
      for (auto [key, v] : {std::pair{"mean", m.mean()}, std::pair{"std", m.stddev()},
                            std::pair{"min", m.min()}, std::pair{"max", m.max()}}) {
        j[key] = std::isfinite(v) ? nlohmann::ordered_json(v) : nlohmann::ordered_json();
      }
      return j;
    };
    summary["total_error_um"] = {{"signed",
                                  {{"left", signed_stats(r.effects.total_signed[0])},
                                   {"right", signed_stats(r.effects.total_signed[1])}}},
                                 {"abs", side_pair(r, kTotalAbs, view.bins[kTotalAbs])}};
    nlohmann::ordered_json budget = nlohmann::ordered_json::array();
    for (const BudgetLine& l : error_budget(scenario, r)) {
      nlohmann::ordered_json line = signed_stats(*l.stats);
      line["source"] = l.source;
      line["variance_share"] = l.share;
      if (l.alone) {
        const double alone = l.alone->stddev();
        line["total_std_alone"] = std::isfinite(alone) ? nlohmann::ordered_json(alone) : nullptr;
      }
      budget.push_back(line);
    }
    summary["error_budget_um"] = budget;
  }
  if (scenario.cmm) summary["cmm"] = cmm_summary_json(*scenario.cmm);
  // Laws fitted to the per-flank maximum (P1 names a law for its per-flank values).
  summary["flank_max_best_law"] = {{"left", law_json(view.laws[0])},
                                   {"right", law_json(view.laws[1])}};
  return summary;
}

std::string run_histograms_csv(const RunResults& r, const RunPresentation& view) {
  static const char* const kName[kRunQuantities] = {"point", "flank_max", "flank_mean",
                                                    "total_abs"};
  std::ostringstream csv;
  csv << std::setprecision(17);
  // The header first (read with any tool's defaults); the provenance is summary.json's.
  csv << "quantity,side,bin_lo_um,bin_hi_um,count\n";
  for (int q = 0; q < kRunQuantities; ++q) {
    for (int s = 0; s < 2; ++s) {
      const ErrorStatistics& e = run_statistics(r, static_cast<RunQuantity>(q), s);
      if (e.moments.count() == 0) continue;
      const Histogram h = view.bins[q].histogram_of(e.histogram);
      const char* side = s == 0 ? "L" : "R";
      if (h.underflow() > 0) {
        csv << kName[q] << ',' << side << ",-inf," << h.lo() << ',' << h.underflow() << '\n';
      }
      for (std::size_t i = 0; i < h.bin_count(); ++i) {
        csv << kName[q] << ',' << side << ',' << h.edge(i) << ',' << h.edge(i + 1) << ','
            << h.count(i) << '\n';
      }
      if (h.overflow() > 0) {
        csv << kName[q] << ',' << side << ',' << h.hi() << ",inf," << h.overflow() << '\n';
      }
    }
  }
  return csv.str();
}

}  // namespace gearmc
