// `gearmc run`: Monte-Carlo batch, statistics table, output files (see run_command.h).
#include "engine/cli/run_command.h"

#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <vector>

#include "engine/mc/monte_carlo.h"
#include "engine/report/html_report.h"
#include "engine/report/output_files.h"
#include "engine/report/svg_plot.h"
#include "engine/scenario/input_error.h"
#include "engine/stats/distribution_fit.h"
#include "engine/stats/stats_json.h"

namespace gearmc {
namespace {

namespace fs = std::filesystem;
constexpr double kModeDisplayWidthUm = 0.1;

nlohmann::ordered_json side_pair(const ErrorStatistics stats[2]) {
  nlohmann::ordered_json j;
  j["left"] = stats_json(stats[0].moments, stats[0].histogram, kModeDisplayWidthUm);
  j["right"] = stats_json(stats[1].moments, stats[1].histogram, kModeDisplayWidthUm);
  return j;
}

std::string format_stat(double v) {
  if (std::isnan(v)) return "-";
  std::ostringstream s;
  s << std::fixed << std::setprecision(3) << v;
  return s.str();
}

void print_table(std::ostream& out, const RunResults& r) {
  out << "δRcomp (µm)        n        mean     std      min      mode     p95      p99.73   max\n";
  auto row = [&](const char* label, const ErrorStatistics& e) {
    const auto& m = e.moments;
    out << std::left << std::setw(18) << label << std::right << std::setw(8) << m.count();
    for (double v :
         {m.mean(), m.stddev(), m.min(), m.count() ? e.histogram.mode(kModeDisplayWidthUm) : NAN,
          m.count() ? e.histogram.quantile(0.95) : NAN,
          m.count() ? e.histogram.quantile(0.9973) : NAN, m.max()}) {
      out << std::setw(9) << format_stat(v);
    }
    out << '\n';
  };
  row("point L", r.point[0]);
  row("point R", r.point[1]);
  row("flank max L", r.flank_max[0]);
  row("flank max R", r.flank_max[1]);
  row("flank mean L", r.flank_mean[0]);
  row("flank mean R", r.flank_mean[1]);
}

// The error budget of a run with measurement effects: the radius-compensation normal error and
// each effect's change of the reading along n, with its share of the summed variances
// (covariances between sources are not split; they are small when the sources are independent).
struct BudgetLine {
  std::string source;
  const RunningStats* stats;
  double share;
  const RunningStats* alone = nullptr;  // the total with only this source on
};
std::vector<BudgetLine> error_budget(const Scenario& scenario, const RunResults& r) {
  std::vector<BudgetLine> lines;
  lines.push_back({"radius_compensation", &r.effects.radius_compensation, 0.0});
  for (std::size_t e = 0; e < r.effects.contribution.size(); ++e) {
    lines.push_back({std::string(scenario.effects->effect(e).name()), &r.effects.contribution[e],
                     0.0, &r.effects.alone[e]});
  }
  double sum = 0.0;
  for (const BudgetLine& l : lines) sum += l.stats->count() > 1 ? l.stats->variance() : 0.0;
  for (BudgetLine& l : lines) {
    l.share = sum > 0.0 && l.stats->count() > 1 ? l.stats->variance() / sum : 0.0;
  }
  return lines;
}

void print_effects(std::ostream& out, const Scenario& scenario, const RunResults& r) {
  out << "total error (µm)   n        mean     std      min      max      |e| p95  |e| p99.73\n";
  for (int s = 0; s < 2; ++s) {
    const RunningStats& m = r.effects.total_signed[s];
    out << std::left << std::setw(18) << (s == 0 ? "point L, along n" : "point R, along n")
        << std::right << std::setw(8) << m.count();
    for (double v : {m.mean(), m.stddev(), m.min(), m.max(),
                     m.count() ? r.total_abs[s].histogram.quantile(0.95) : NAN,
                     m.count() ? r.total_abs[s].histogram.quantile(0.9973) : NAN}) {
      out << std::setw(9) << format_stat(v);
    }
    out << '\n';
  }
  out << "error budget (µm)    mean     std      share of variance   total σ with it alone\n";
  for (const BudgetLine& l : error_budget(scenario, r)) {
    out << std::left << std::setw(20) << l.source << std::right << std::setw(8)
        << format_stat(l.stats->mean()) << std::setw(9) << format_stat(l.stats->stddev())
        << std::setw(9) << format_stat(100.0 * l.share) << " %" << std::setw(14)
        << (l.alone ? format_stat(l.alone->stddev()) : "") << "\n";
  }
}

// Histogram counts at the display width, one column per quantity.
std::string histogram_csv(const RunResults& r) {
  const std::size_t factor = r.point[0].histogram.rebin_factor(0.05);
  const Histogram* h[6] = {&r.point[0].histogram,      &r.point[1].histogram,
                           &r.flank_max[0].histogram,  &r.flank_max[1].histogram,
                           &r.flank_mean[0].histogram, &r.flank_mean[1].histogram};
  std::vector<Histogram> coarse;
  for (const Histogram* x : h) coarse.push_back(x->rebin(factor));
  // Last non-empty bin over all columns.
  std::size_t last = 0;
  for (const Histogram& c : coarse) {
    for (std::size_t i = 0; i < c.bin_count(); ++i) {
      if (c.count(i) > 0) last = std::max(last, i);
    }
  }
  std::ostringstream csv;
  csv << "bin_lo_um,bin_hi_um,point_L,point_R,flank_max_L,flank_max_R,flank_mean_L,flank_mean_R\n";
  for (std::size_t i = 0; i <= last; ++i) {
    csv << coarse[0].edge(i) << ',' << coarse[0].edge(i + 1);
    for (const Histogram& c : coarse) csv << ',' << c.count(i);
    csv << '\n';
  }
  return csv.str();
}

void write_point_row(std::ostream& f, const ProbedPoint& p, double R) {
  const ContactResult& c = p.contact;
  f << p.gear << ',' << p.tooth << ',' << side_letter(p.side) << ',' << p.i << ',' << p.j;
  auto v3 = [&](const Eigen::Vector3d& v) { f << ',' << v.x() << ',' << v.y() << ',' << v.z(); };
  v3(p.p);
  v3(p.n);
  if (c.status == ContactResult::Status::kOk) {
    v3(c.contact);
    v3(c.centre);
    v3(c.reported);
    f << ',' << c.delta_um << ',' << c.normal_error_um << ",ok\n";
  } else {
    f << ",,,,,,,,,,,";
    f << ','
      << (c.status == ContactResult::Status::kEdge        ? "edge"
          : c.status == ContactResult::Status::kCollision ? c.collision
          : *c.failure != '\0'                            ? c.failure
                                                          : "not_converged")
      << '\n';
  }
  (void)R;
}

// P1's set-up (sources.md, Table 1 and Fig. 4): the gear, the grid and the stylus. Only then
// is P1's Table 2 a fair comparison.
bool is_p1_setup(const Scenario& s) {
  const GearParameters& g = s.gear;
  return g.teeth == 24 && g.module_mm == 5.6 && g.pressure_angle_deg == 20.0 &&
         g.profile_shift == 0.90116 && g.face_width_mm == 78.89 && s.stylus_radius_mm == 0.5 &&
         s.probing.grid.points_along_profile == 10 && s.probing.grid.sections_across_face == 5;
}

constexpr double kP1ClaimUm = 4.0;  // P1: "the compensation error does not exceed 4 µm"

nlohmann::ordered_json fit_json(const DistributionFit& f) {
  nlohmann::ordered_json j;
  j["law"] = std::string(law_name(f.distribution.law));
  const auto names = f.distribution.parameter_names();
  j["parameters"] = {{std::string(names[0]), f.distribution.a},
                     {std::string(names[1]), f.distribution.b}};
  j["aic"] = f.aic;
  j["ks_distance"] = f.ks_distance;
  j["chi_square_p_value"] = f.chi_square_p_value;
  return j;
}

std::vector<std::string> stats_cells(const std::string& label, const ErrorStatistics& e) {
  const auto& m = e.moments;
  const bool any = m.count() > 0;
  return {label,
          std::to_string(m.count()),
          format_stat(m.mean()),
          format_stat(m.stddev()),
          format_stat(m.min()),
          format_stat(any ? e.histogram.mode(kModeDisplayWidthUm) : NAN),
          format_stat(any ? e.histogram.quantile(0.95) : NAN),
          format_stat(any ? e.histogram.quantile(0.9973) : NAN),
          format_stat(m.max())};
}

std::string report_html(const Scenario& scenario, const RunResults& r,
                        const std::vector<DistributionFit> fits[2],
                        const std::vector<std::pair<std::string, std::string>>& figures) {
  HtmlReport report("gearmc run: " + scenario.name);
  std::ostringstream intro;
  intro << r.gears << " gears, " << r.contacts << " contacts (failed " << r.failed_contacts
        << ", edge " << r.edge_contacts << ", collisions " << r.collisions << "), stylus R "
        << scenario.stylus_radius_mm << " mm, seed " << scenario.seed << ". δRcomp = |C − E|: "
        << "distance between the true contact point and the point the CMM reports.";
  report.paragraph(intro.str());
  for (const FlankMeshSurface& surface : scenario.surfaces) {
    std::ostringstream mesh;
    mesh << "Flank " << surface.tooth << side_letter(surface.side) << " is the mesh "
         << surface.mesh_path << " (" << surface.mesh->n_faces() << " triangles, "
         << (surface.contact == MeshContactPoint::kSmoothed ? "smoothed" : "facet")
         << " contact point) in every gear; its random deviations are not used.";
    report.paragraph(mesh.str());
  }
  HtmlTable table;
  table.caption =
      "δRcomp statistics (µm). Quantiles at 0.001 µm resolution; mode = centre of "
      "the fullest 0.1 µm bin.";
  table.header = {"quantity", "n", "mean", "std", "min", "mode", "p95", "p99.73", "max"};
  table.rows.push_back({stats_cells("per point, left", r.point[0])});
  table.rows.push_back({stats_cells("per point, right", r.point[1])});
  table.rows.push_back({stats_cells("per flank max, left", r.flank_max[0])});
  table.rows.push_back({stats_cells("per flank max, right", r.flank_max[1])});
  table.rows.push_back({stats_cells("per flank mean, left", r.flank_mean[0])});
  table.rows.push_back({stats_cells("per flank mean, right", r.flank_mean[1])});
  if (is_p1_setup(scenario)) {
    // P1 Table 2 (sources.md): per-flank value, 50 gears; E = most probable value.
    table.rows.push_back(
        {{"P1 Table 2, left", "1200", "", "0.6", "0.7", "1.6", "", "", "3.4"}, true});
    table.rows.push_back(
        {{"P1 Table 2, right", "1200", "", "0.6", "0.7", "1.6", "", "", "3.2"}, true});
  }
  report.table(table);
  if (!scenario.effects->empty()) {
    HtmlTable total;
    total.caption =
        "Total point error with the measurement effects on (µm): (E' − C)·n, E' the point "
        "reported from the recorded stylus centre, C the true contact point.";
    total.header = {"flank", "n", "mean", "std", "min", "max"};
    for (int s = 0; s < 2; ++s) {
      const RunningStats& m = r.effects.total_signed[s];
      total.rows.push_back(
          {{s == 0 ? "left" : "right", std::to_string(m.count()), format_stat(m.mean()),
            format_stat(m.stddev()), format_stat(m.min()), format_stat(m.max())}});
    }
    report.table(total);
    HtmlTable budget;
    budget.caption =
        "Error budget: each source's change of the reading along n (µm), its share of the "
        "summed variances, and the total error's σ with that effect alone on (besides δRcomp).";
    budget.header = {"source", "mean", "std", "share of variance", "total σ, alone"};
    for (const BudgetLine& l : error_budget(scenario, r)) {
      budget.rows.push_back(
          {{l.source, format_stat(l.stats->mean()), format_stat(l.stats->stddev()),
            format_stat(100.0 * l.share) + " %", l.alone ? format_stat(l.alone->stddev()) : ""}});
    }
    report.table(budget);
  }
  std::ostringstream claim;
  const double worst = std::max(r.flank_max[0].moments.max(), r.flank_max[1].moments.max());
  std::uint64_t above = 0, total = 0;
  for (int s = 0; s < 2; ++s) {
    const Histogram& h = r.flank_max[s].histogram;
    for (std::size_t i = 0; i < h.bin_count(); ++i) {
      if (h.edge(i) >= kP1ClaimUm) above += h.count(i);
    }
    above += h.overflow();
    total += h.total();
  }
  claim << "P1's claim \"δRcomp does not exceed 4 µm\": the largest per-flank value here is "
        << format_stat(worst) << " µm; " << above << " of " << total << " flanks exceed 4 µm.";
  report.paragraph(claim.str());
  for (const auto& [svg, caption] : figures) report.figure(svg, caption);
  HtmlTable fit_table;
  fit_table.caption =
      "Laws fitted to the per-flank maximum (binned maximum likelihood), best "
      "first by AIC";
  fit_table.header = {"flank", "law", "parameters", "AIC", "KS distance", "χ² p-value"};
  for (int s = 0; s < 2; ++s) {
    for (const DistributionFit& f : fits[s]) {
      if (!f.applicable) continue;
      const auto names = f.distribution.parameter_names();
      std::ostringstream params;
      params << names[0] << " " << format_stat(f.distribution.a) << ", " << names[1] << " "
             << format_stat(f.distribution.b);
      std::ostringstream aic, ks, p;
      aic << std::fixed << std::setprecision(1) << f.aic;
      ks << std::fixed << std::setprecision(4) << f.ks_distance;
      p << std::setprecision(3) << f.chi_square_p_value;
      fit_table.rows.push_back(
          {{s == 0 ? "left" : "right", std::string(law_name(f.distribution.law)), params.str(),
            aic.str(), ks.str(), p.str()},
           &f == &fits[s].front()});
    }
  }
  report.table(fit_table);
  report.preformatted(scenario.source_text, "Scenario (" + scenario.source_path + ")");
  return report.html();
}

}  // namespace

int run_command(const RunCommandOptions& o, std::ostream& out, std::ostream& err) {
  Scenario scenario =
      o.scenario_path.empty() ? reference_scenario() : load_scenario_file(o.scenario_path);
  if (o.seed) scenario.seed = *o.seed;
  if (o.gears) scenario.gears = *o.gears;
  const MonteCarloRun mc(scenario);
  if (o.only_gear && (*o.only_gear < 0 || *o.only_gear >= scenario.gears)) {
    throw InputError({}, "--only-gear", std::to_string(*o.only_gear),
                     "a gear index from 0 to " + std::to_string(scenario.gears - 1));
  }

  const fs::path dir =
      o.out_dir.empty() ? fs::path("results") / scenario.name : fs::path(o.out_dir);
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) throw InputError({dir.string(), 0, 0}, dir.string() + ": cannot create: " + ec.message());
  OutputFiles files(dir);

  std::ofstream points_file;
  if (o.points) {
    points_file = files.open("points.csv");
    points_file << std::setprecision(17);
    points_file << "gear,tooth,flank,i,j,px,py,pz,nx,ny,nz,cx,cy,cz,ox,oy,oz,ex,ey,ez,delta_um,"
                   "normal_err_um,status\n";
  }

  RunOptions run;
  run.gears = scenario.gears;
  run.seed = scenario.seed;
  run.threads = o.threads;
  run.only_gear = o.only_gear;
  run.record_points = o.points;
  if (o.points) {
    run.on_gear = [&](const GearOutcome& g) {
      for (const ProbedPoint& p : g.points)
        write_point_row(points_file, p, scenario.stylus_radius_mm);
    };
  }
  const bool show_progress = !o.quiet && isatty(STDERR_FILENO);
  const auto start = std::chrono::steady_clock::now();
  if (show_progress) {
    run.progress = [&](int done, int total) {
      const double t =
          std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      if (t < 1.0 && done < total) return;
      const double eta = done > 0 ? t * (total - done) / done : 0.0;
      const double rate = done * mc.points_per_flank() * mc.probed_teeth() * 2.0 / t;
      err << "\r  gears " << done << "/" << total << "  contacts/s " << std::scientific
          << std::setprecision(2) << rate << std::defaultfloat << "  ETA " << std::fixed
          << std::setprecision(0) << eta << " s   " << std::defaultfloat << std::flush;
      if (done == total) err << '\n';
    };
  }
  const RunResults r = mc.run(run);
  if (o.points) points_file.close();

  nlohmann::ordered_json summary;
  summary["scenario"] = scenario.name;
  summary["source"] = scenario.source_path;
  summary["gears"] = r.gears;
  summary["only_gear"] =
      o.only_gear ? nlohmann::ordered_json(*o.only_gear) : nlohmann::ordered_json();
  summary["teeth"] = mc.probed_teeth();
  summary["points_per_flank"] = mc.points_per_flank();
  summary["stylus_radius_mm"] = scenario.stylus_radius_mm;
  summary["seed"] = scenario.seed;
  summary["contacts"] = r.contacts;
  summary["failed_contacts"] = r.failed_contacts;
  summary["edge_contacts"] = r.edge_contacts;
  summary["collisions"] = r.collisions;
  summary["wall_s"] = r.wall_s;
  summary["contacts_per_s"] = r.wall_s > 0 ? static_cast<double>(r.contacts) / r.wall_s : 0.0;
  // Flanks probed on a mesh instead of the analytic perturbed flank (`surfaces:`).
  nlohmann::ordered_json mesh_surfaces = nlohmann::ordered_json::array();
  for (const FlankMeshSurface& surface : scenario.surfaces) {
    mesh_surfaces.push_back(
        {{"tooth", surface.tooth},
         {"flank", std::string(1, side_letter(surface.side))},
         {"mesh", surface.mesh_path},
         {"contact", surface.contact == MeshContactPoint::kSmoothed ? "smoothed" : "facets"},
         {"triangles", surface.mesh->n_faces()}});
  }
  summary["mesh_surfaces"] = mesh_surfaces;
  summary["quantile_resolution_um"] = r.point[0].histogram.width();
  summary["mode_display_width_um"] = kModeDisplayWidthUm;
  summary["delta_rcomp_um"] = {{"point", side_pair(r.point)},
                               {"flank_max", side_pair(r.flank_max)},
                               {"flank_mean", side_pair(r.flank_mean)}};
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
                                 {"abs", side_pair(r.total_abs)}};
    nlohmann::ordered_json budget = nlohmann::ordered_json::array();
    for (const BudgetLine& l : error_budget(scenario, r)) {
      nlohmann::ordered_json line = signed_stats(*l.stats);
      line["source"] = l.source;
      line["variance_share"] = l.share;
      if (l.alone) line["total_std_alone"] = l.alone->stddev();
      budget.push_back(line);
    }
    summary["error_budget_um"] = budget;
  }
  // Laws fitted to the per-flank maximum (P1 names a law for its per-flank values).
  std::vector<DistributionFit> fits[2];
  for (int s = 0; s < 2; ++s) {
    if (r.flank_max[s].moments.count() >= 2) fits[s] = fit_distributions(r.flank_max[s].histogram);
  }
  nlohmann::ordered_json fit_doc;
  for (int s = 0; s < 2; ++s) {
    fit_doc[s == 0 ? "left" : "right"] = fits[s].empty() || !fits[s].front().applicable
                                             ? nlohmann::ordered_json()
                                             : fit_json(fits[s].front());
  }
  summary["flank_max_best_law"] = fit_doc;
  files.write("summary.json", summary.dump(2) + "\n");
  files.write("histograms.csv", histogram_csv(r));

  // Pictures: per-point and per-flank-max histograms, left and right (P1 Fig. 5).
  std::vector<std::pair<std::string, std::string>> figures;
  const char* side_name[2] = {"left", "right"};
  for (int s = 0; s < 2; ++s) {
    for (int kind = 0; kind < 2; ++kind) {
      const ErrorStatistics& e = kind == 0 ? r.flank_max[s] : r.point[s];
      if (e.moments.count() == 0) continue;
      HistogramPlotOptions plot;
      const std::string what = kind == 0 ? "per-flank maximum" : "per point";
      plot.title = std::string("δRcomp ") + what + ", " + side_name[s] +
                   " flanks (n = " + std::to_string(e.moments.count()) + ")";
      std::ostringstream p9973;
      p9973 << "p99.73 = " << format_stat(e.histogram.quantile(0.9973)) << " µm";
      plot.markers.push_back({e.histogram.quantile(0.9973), p9973.str(), "", true});
      if (kind == 0) {
        plot.markers.push_back({kP1ClaimUm, "P1's claim 4 µm", "", true});
        if (!fits[s].empty() && fits[s].front().applicable) {
          const Distribution law = fits[s].front().distribution;
          plot.overlay_pdf = [law](double x) { return law.pdf(x); };
          plot.overlay_label = "best fit: " + std::string(law_name(law.law));
        }
      }
      const Histogram display = e.histogram.rebin(e.histogram.rebin_factor(kModeDisplayWidthUm));
      const std::string svg = histogram_svg(display, plot);
      const std::string name = std::string(kind == 0 ? "flank_max_" : "point_") + side_name[s];
      files.write(name + ".svg", svg);
      figures.emplace_back(svg, plot.title + " — " + name + ".svg");
    }
  }
  files.write("report.html", report_html(scenario, r, fits, figures));
  files.commit();

  out << "gearmc run: " << scenario.name << ", " << r.gears << " gears, " << mc.probed_teeth()
      << " teeth, " << mc.points_per_flank() << " points per flank, R " << scenario.stylus_radius_mm
      << " mm, seed " << scenario.seed << "\n";
  out << "contacts " << r.contacts << " (failed " << r.failed_contacts << ", edge "
      << r.edge_contacts << ", collisions " << r.collisions << ") in " << std::fixed
      << std::setprecision(2) << r.wall_s << " s\n"
      << std::defaultfloat;
  for (const FlankMeshSurface& surface : scenario.surfaces) {
    out << "flank " << surface.tooth << side_letter(surface.side) << " is the mesh "
        << surface.mesh_path << " (" << surface.mesh->n_faces() << " triangles, "
        << (surface.contact == MeshContactPoint::kSmoothed ? "smoothed" : "facet")
        << " contact point) in every gear\n";
  }
  print_table(out, r);
  if (!scenario.effects->empty()) print_effects(out, scenario, r);
  out << "report: " << dir.string() << "/report.html\n";
  return 0;
}

}  // namespace gearmc
