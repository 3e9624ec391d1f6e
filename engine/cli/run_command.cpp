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
#include "engine/scenario/input_error.h"
#include "engine/stats/stats_json.h"

namespace gearmc {
namespace {

namespace fs = std::filesystem;
constexpr double kModeDisplayWidthUm = 0.1;

// Files written under "<name>.partial" and renamed together at the end; on failure the
// partial files are removed (interface.md: nothing is half-written).
class OutputFiles {
 public:
  explicit OutputFiles(fs::path dir) : dir_(std::move(dir)) {}
  ~OutputFiles() {
    std::error_code ignored;
    for (const auto& name : pending_) fs::remove(partial(name), ignored);
  }
  std::ofstream open(const std::string& name) {
    pending_.push_back(name);
    std::ofstream f(partial(name), std::ios::binary);
    if (!f) throw InputError({dir_.string(), 0, 0}, dir_.string() + ": cannot write " + name);
    return f;
  }
  void write(const std::string& name, const std::string& content) {
    std::ofstream f = open(name);
    f << content;
  }
  void commit() {
    for (const auto& name : pending_) fs::rename(partial(name), dir_ / name);
    pending_.clear();
  }
  fs::path path(const std::string& name) const { return dir_ / name; }

 private:
  fs::path partial(const std::string& name) const { return dir_ / (name + ".partial"); }
  fs::path dir_;
  std::vector<std::string> pending_;
};

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
                                                          : "not_converged")
      << '\n';
  }
  (void)R;
}

}  // namespace

int run_command(const RunCommandOptions& o, std::ostream& out, std::ostream& err) {
  Scenario scenario =
      o.scenario_path.empty() ? reference_scenario() : load_scenario_file(o.scenario_path);
  if (o.seed) scenario.seed = *o.seed;
  if (o.gears) scenario.gears = *o.gears;
  const MonteCarloRun mc(scenario);
  if (o.only_gear && (*o.only_gear < 0 || *o.only_gear >= scenario.gears)) {
    throw InputError({"--only-gear", 0, 0}, "--only-gear", std::to_string(*o.only_gear),
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
  summary["quantile_resolution_um"] = r.point[0].histogram.width();
  summary["mode_display_width_um"] = kModeDisplayWidthUm;
  summary["delta_rcomp_um"] = {{"point", side_pair(r.point)},
                               {"flank_max", side_pair(r.flank_max)},
                               {"flank_mean", side_pair(r.flank_mean)}};
  files.write("summary.json", summary.dump(2) + "\n");
  files.write("histograms.csv", histogram_csv(r));
  files.commit();

  out << "gearmc run: " << scenario.name << ", " << r.gears << " gears, " << mc.probed_teeth()
      << " teeth, " << mc.points_per_flank() << " points per flank, R " << scenario.stylus_radius_mm
      << " mm, seed " << scenario.seed << "\n";
  out << "contacts " << r.contacts << " (failed " << r.failed_contacts << ", edge "
      << r.edge_contacts << ", collisions " << r.collisions << ") in " << std::fixed
      << std::setprecision(2) << r.wall_s << " s\n"
      << std::defaultfloat;
  print_table(out, r);
  out << "results: " << dir.string() << "/summary.json\n";
  return 0;
}

}  // namespace gearmc
