// The run's header line, points.csv rows and terminal summary (see run_terminal.h).
#include "engine/report/run_terminal.h"

#include <iomanip>
#include <sstream>

#include "surfaces/triangle_mesh_fwd.h"

namespace gearmc {

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
      << (c.status == ContactResult::Status::kEdge        ? "edge"
          : c.status == ContactResult::Status::kCollision ? c.collision
          : *c.failure != '\0'                            ? c.failure
                                                          : "not_converged")
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
