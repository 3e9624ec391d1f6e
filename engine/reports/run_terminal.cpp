// The run's header line, points.csv rows, terminal tables and summary (see run_terminal.h).
#include "engine/reports/run_terminal.h"

#include <iomanip>
#include <sstream>
#include <string_view>
#include <vector>

#include "engine/reports/cmm_summary.h"
#include "engine/reports/run_report_cells.h"
#include "surfaces/triangle_mesh_fwd.h"

namespace gearmc {
using namespace run_output;
namespace {

// The number of characters (UTF-8 code points) of `text`, its width on a terminal.
std::size_t display_width(std::string_view text) {
  std::size_t n = 0;
  for (char c : text) n += (static_cast<unsigned char>(c) & 0xC0) != 0x80;
  return n;
}
// `text` padded with spaces to `width` characters, on the left (right-aligned) or the right.
std::string pad(std::string_view text, std::size_t width, bool right_align) {
  const std::size_t w = display_width(text);
  const std::string fill(w < width ? width - w : 0, ' ');
  return right_align ? fill + std::string(text) : std::string(text) + fill;
}
// One terminal table line: the first cell left-aligned in `first` characters, the others
// right-aligned in `rest` each (headers and numbers line up the same way).
std::string table_line(const std::vector<std::string>& cells, std::size_t first, std::size_t second,
                       std::size_t rest) {
  std::string line;
  for (std::size_t c = 0; c < cells.size(); ++c) {
    line += c == 0 ? pad(cells[c], first, false) : pad(cells[c], c == 1 ? second : rest, true);
  }
  while (!line.empty() && line.back() == ' ') line.pop_back();
  return line + "\n";
}

}  // namespace

std::string run_header_line(const Scenario& scenario, const MonteCarloRun& mc,
                            const std::optional<int>& only_gear) {
  std::ostringstream line;
  line << "gearmc run: " << scenario.name << ", " << (only_gear ? 1 : scenario.gears)
       << (only_gear ? " gear (--only-gear " + std::to_string(*only_gear) + ")" : " gears") << ", "
       << mc.probed_teeth() << " teeth, " << mc.points_per_flank() << " points per flank, R "
       << scenario.stylus_radius_mm << " mm, seed " << scenario.seed;
  return line.str();
}

std::string points_csv_header() {
  return "gear,tooth,flank,i,j,px,py,pz,nx,ny,nz,cx,cy,cz,ox,oy,oz,ex,ey,ez,delta_um,"
         "normal_err_um,status\n";
}

void write_point_row(std::ostream& f, const ProbedPoint& p) {
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
      << (c.status == ContactResult::Status::kEdge        ? std::string_view("edge")
          : c.status == ContactResult::Status::kCollision ? spelling(c.collision)
          : c.failure != ContactFailure::kNone            ? spelling(c.failure)
                                                          : std::string_view("not_converged"))
      << '\n';
  }
}

std::string run_contacts_line(const RunResults& r) {
  std::ostringstream line;
  line << "contacts " << r.contacts << " (failed " << r.failed_contacts << ", edge "
       << r.edge_contacts << ", collisions " << r.collisions << ") in " << std::fixed
       << std::setprecision(2) << r.wall_s << " s";
  return line.str();
}

void print_run_tables(std::ostream& out, const Scenario& scenario, const RunResults& r,
                      const RunPresentation& view) {
  static const char* const kShortLabel[] = {"point L",     "point R",      "flank max L",
                                            "flank max R", "flank mean L", "flank mean R"};
  out << table_line({"δRcomp (µm)", "n", "mean", "std", "min", "mode", "p95", "p99.73", "max"}, 14,
                    8, 9);
  for (std::size_t k = 0; k < std::size(kDeltaRows); ++k) {
    const TableRow& row = kDeltaRows[k];
    out << table_line(
        stats_cells(kShortLabel[k], run_statistics(r, row.q, row.side), view.bins[row.q]), 14, 8,
        9);
  }
  if (scenario.effects->empty()) return;
  out << table_line({"total error (µm)", "n", "mean", "std", "min", "max", "|e| p95", "|e| p99.73"},
                    18, 8, 11);
  for (int s = 0; s < 2; ++s) {
    const RunningStats& m = r.effects.total_signed[s];
    out << table_line({s == 0 ? "point L, along n" : "point R, along n", std::to_string(m.count()),
                       format_stat(m.mean()), format_stat(m.stddev()), format_stat(m.min()),
                       format_stat(m.max()), quantile_cell(r.total_abs[s].histogram, 0.95),
                       quantile_cell(r.total_abs[s].histogram, 0.9973)},
                      18, 8, 11);
  }
  out << table_line({"error budget (µm)", "mean", "std", "share", "σ alone"}, 20, 9, 11);
  for (const BudgetLine& l : error_budget(scenario, r)) {
    out << table_line(
        {l.source, format_stat(l.stats->mean()), format_stat(l.stats->stddev()),
         format_stat(100.0 * l.share) + " %", l.alone ? format_stat(l.alone->stddev()) : ""},
        20, 9, 11);
  }
  if (scenario.cmm) out << cmm_summary_sentence(*scenario.cmm) << "\n";
}

void print_run_summary(std::ostream& out, const Scenario& scenario, const RunResults& r,
                       const RunPresentation& view) {
  for (const FlankMeshSurface& surface : scenario.surfaces) {
    out << "flank " << surface.tooth << side_letter(surface.side) << " is the mesh "
        << surface.mesh_path << " (" << triangle_count(*surface.mesh) << " triangles, "
        << (surface.contact == MeshContactPoint::kSmoothed ? "smoothed" : "facet")
        << " contact point) in every gear\n";
  }
  print_run_tables(out, scenario, r, view);
  for (int s = 0; s < 2; ++s) {
    out << "flank max " << (s == 0 ? "L" : "R") << " law: " << view.laws[s].sentence << "\n";
  }
}

}  // namespace gearmc
