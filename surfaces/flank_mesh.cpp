// Flank and whole-gear triangle meshes (OpenMesh) and mesh files (see flank_mesh.h).
// The gear mesh is a generalised prism: every transverse section z_j is the same closed polygon
// topology (M vertices, counter-clockwise seen from +Z), consecutive sections are joined by two
// triangles per polygon edge, and the end sections are closed by fans from the gear centre.
// With V = nz M + 2 vertices, E = (3 nz - 2) M edges and F = 2 nz M faces, V - E + F = 2: the
// mesh is a closed, orientable genus-0 surface; the side walls run counter-clockwise and the
// fans are ordered so that every face normal points out of the material.
#include "surfaces/flank_mesh.h"

#include <unistd.h>
#include <Eigen/Geometry>
#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <system_error>

#include "core/check.h"
#include "core/constants.h"
#include "core/input_file.h"

namespace gearmc {

std::size_t triangle_count(const TriangleMesh& mesh) { return mesh.n_faces(); }

namespace {

// The i-th of n equally spaced values from a to b, ends exact (so flank meshes and gear meshes
// with the same sampling have bit-identical vertices).
double grid_value(double a, double b, int i, int n) {
  return i == n - 1 ? b : a + (b - a) * i / (n - 1);
}

TriangleMesh::Point to_point(const Eigen::Vector3d& x) { return {x.x(), x.y(), x.z()}; }

// Adds triangle (a, b, c) of the vertex list; aborts if OpenMesh rejects it (a topological
// error would mean the construction above is wrong).
void add_triangle(TriangleMesh& mesh, const std::vector<TriangleMesh::VertexHandle>& v, int a,
                  int b, int c) {
  const TriangleMesh::FaceHandle f = mesh.add_face(v[a], v[b], v[c]);
  GEARMC_CHECK(f.is_valid(), "OpenMesh rejected a triangle (non-manifold construction)");
}

// Disables OpenMesh's informational log (e.g. "[STLWriter] : write binary file") for one call;
// its error stream is left on. OpenMesh's log is process-global: mesh I/O is not meant to run
// concurrently with other OpenMesh I/O.
class QuietOpenMeshLog {
 public:
  QuietOpenMeshLog() : was_enabled_(::omlog().is_enabled()) { ::omlog().disable(); }
  ~QuietOpenMeshLog() {
    if (was_enabled_) ::omlog().enable();
  }
  QuietOpenMeshLog(const QuietOpenMeshLog&) = delete;
  QuietOpenMeshLog& operator=(const QuietOpenMeshLog&) = delete;

 private:
  bool was_enabled_;
};

std::string lower_extension(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return ext;
}

const char* format_name(MeshFormat f) {
  switch (f) {
    case MeshFormat::kStl:
      return "STL";
    case MeshFormat::kPly:
      return "PLY";
    case MeshFormat::kObj:
      return "OBJ";
    case MeshFormat::kOff:
      return "OFF";
  }
  return "?";
}

const char* format_extension(MeshFormat f) {
  switch (f) {
    case MeshFormat::kStl:
      return ".stl";
    case MeshFormat::kPly:
      return ".ply";
    case MeshFormat::kObj:
      return ".obj";
    case MeshFormat::kOff:
      return ".off";
  }
  return "";
}

// Significant digits for text formats: OpenMesh writes floats; 9 digits round-trip a float,
// 17 are used so that nothing is lost should a writer ever pass doubles through.
constexpr std::streamsize kTextPrecision = 17;

}  // namespace

// ---------------------------------------------------------------------------------------------
// Meshing

FlankMeshSpec whole_flank_spec(const InvoluteGear& gear, double roll_length_step_mm,
                               double z_step_mm) {
  GEARMC_CHECK(roll_length_step_mm > 0.0 && z_step_mm > 0.0, "mesh steps must be > 0");
  FlankMeshSpec spec;
  spec.roll_length_min_mm = gear.active_roll_length_min_mm();
  spec.roll_length_max_mm = gear.active_roll_length_max_mm();
  spec.z_min_mm = 0.0;
  spec.z_max_mm = gear.face_width_mm();
  const double span_L = spec.roll_length_max_mm - spec.roll_length_min_mm;
  // 1e-9: a span that is an exact multiple of the step does not get an extra sample.
  spec.roll_length_samples =
      1 + std::max(1, static_cast<int>(std::ceil(span_L / roll_length_step_mm - 1e-9)));
  spec.z_samples = 1 + std::max(1, static_cast<int>(std::ceil(spec.z_max_mm / z_step_mm - 1e-9)));
  return spec;
}

TriangleMesh mesh_flank(const AnalyticFlank& flank, const FlankMeshSpec& spec) {
  const int nL = spec.roll_length_samples, nz = spec.z_samples;
  GEARMC_CHECK(nL >= 2 && nz >= 2, "a flank mesh needs at least 2 x 2 samples");
  TriangleMesh mesh;
  mesh.reserve(static_cast<size_t>(nL) * nz, 3 * static_cast<size_t>(nL) * nz,
               2 * static_cast<size_t>(nL) * nz);
  std::vector<TriangleMesh::VertexHandle> v;
  v.reserve(static_cast<size_t>(nL) * nz);
  for (int j = 0; j < nz; ++j) {
    const double z = grid_value(spec.z_min_mm, spec.z_max_mm, j, nz);
    for (int i = 0; i < nL; ++i) {
      const double L = grid_value(spec.roll_length_min_mm, spec.roll_length_max_mm, i, nL);
      v.push_back(mesh.add_vertex(to_point(flank.point(L, z))));
    }
  }
  // Orientation: S_L x S_z is +n on an L flank and -n on an R flank (gears/involute_gear.h
  // conventions); it is evaluated rather than assumed. With S_L x S_z along +n the cell
  // (00, 10, 11, 01) is split along 00-11 as (00, 10, 11) + (00, 11, 01); otherwise along 10-01
  // as (10, 00, 01) + (10, 01, 11), the mirror image. Both are what mesh_gear's side wall gives.
  const FlankSurfacePoint mid =
      flank.evaluate(0.5 * (spec.roll_length_min_mm + spec.roll_length_max_mm),
                     0.5 * (spec.z_min_mm + spec.z_max_mm));
  const bool along_n = mid.d_dL.cross(mid.d_dz).dot(mid.nominal_normal) > 0.0;
  for (int j = 0; j + 1 < nz; ++j) {
    for (int i = 0; i + 1 < nL; ++i) {
      const int c00 = j * nL + i, c10 = c00 + 1, c01 = c00 + nL, c11 = c01 + 1;
      if (along_n) {
        add_triangle(mesh, v, c00, c10, c11);
        add_triangle(mesh, v, c00, c11, c01);
      } else {
        add_triangle(mesh, v, c10, c00, c01);
        add_triangle(mesh, v, c10, c01, c11);
      }
    }
  }
  return mesh;
}

GearMesh mesh_gear(const InvoluteGear& gear, const PerturbedGear& perturbed,
                   const GearMeshSpec& spec, const NormalExpression* expression) {
  const int teeth = gear.teeth();
  const int nL = spec.profile_samples, nt = spec.tip_samples, nr = spec.root_samples;
  const int nz = spec.face_samples;
  GEARMC_CHECK(nL >= 2 && nt >= 0 && nr >= 0 && nz >= 2, "gear mesh sample counts out of range");
  GEARMC_CHECK(static_cast<int>(perturbed.flanks.size()) == 2 * teeth,
               "a perturbed gear needs two flanks per tooth");
  const int per_tooth = 2 * nL + nt + nr;
  const int M = teeth * per_tooth;  // vertices per section
  const double L_form = gear.form_roll_length_mm(), L_tip = gear.tip_roll_length_mm();
  const double r_root = 0.5 * gear.root_diameter_mm();
  const double b = gear.face_width_mm();
  const Eigen::Vector2d centre = perturbed.eccentricity_mm;

  // The real flanks: index 2 (k - 1) + (R ? 1 : 0), as PerturbedGear::flanks.
  std::vector<AnalyticFlank> flanks;
  flanks.reserve(2 * static_cast<size_t>(teeth));
  for (int k = 1; k <= teeth; ++k) {
    for (FlankSide side : {FlankSide::kLeft, FlankSide::kRight}) {
      flanks.emplace_back(gear, k, side, perturbed.flank(k, side), perturbed.eccentricity_mm,
                          expression);
    }
  }

  // What each section edge i -> i + 1 (mod M) belongs to.
  std::vector<GearMeshFace> edge_label(M);
  for (int k = 1; k <= teeth; ++k) {
    const int base = (k - 1) * per_tooth;
    int i = base;
    for (int s = 0; s + 1 < nL; ++s)
      edge_label[i++] = {GearMeshFace::Region::kFlank, k, FlankSide::kLeft};
    for (int s = 0; s <= nt; ++s)
      edge_label[i++] = {GearMeshFace::Region::kTip, k, FlankSide::kLeft};
    for (int s = 0; s + 1 < nL; ++s)
      edge_label[i++] = {GearMeshFace::Region::kFlank, k, FlankSide::kRight};
    for (int s = 0; s <= nr; ++s)
      edge_label[i++] = {GearMeshFace::Region::kRoot, k, FlankSide::kLeft};
    GEARMC_CHECK(i == base + per_tooth, "section edge count");
  }

  // Polar coordinates about the gear centre (which carries the eccentricity).
  auto polar = [&](const Eigen::Vector3d& x, double* angle, double* radius) {
    const Eigen::Vector2d d = x.head<2>() - centre;
    *angle = std::atan2(d.y(), d.x());
    *radius = d.norm();
  };
  // Interior points of the arc from a to b (counter-clockwise), radius given per u in (0, 1);
  // a and b by value: they may live in *out.
  int tooth_now = 0;  // the tooth whose section is being built, for messages
  auto arc = [&](const Eigen::Vector3d a, const Eigen::Vector3d bpt, int count, double z,
                 auto radius_at, std::vector<Eigen::Vector3d>* out) {
    double phi_a, rho_a, phi_b, rho_b;
    polar(a, &phi_a, &rho_a);
    polar(bpt, &phi_b, &rho_b);
    double sweep = std::remainder(phi_b - phi_a, 2.0 * kPi);
    if (!(sweep > 0.0)) {
      // Not a bug: a real gear whose perturbed flanks cross before the tip circle (a nearly
      // pointed tooth) has no closed section to mesh.
      throw MeshIoError(
          "tooth " + std::to_string(tooth_now) + " of this gear has flanks that " +
          "cross before its tip or root arc at z = " + std::to_string(z) +
          " mm (nominal tip thickness s_a = " + std::to_string(gear.tip_thickness_mm()) +
          " mm, less than its drawn deviations): a section that is not "
          "star-shaped has no closed mesh");
    }
    for (int m = 1; m <= count; ++m) {
      const double u = static_cast<double>(m) / (count + 1);
      const double phi = phi_a + u * sweep;
      const double rho = radius_at(u, (1.0 - u) * rho_a + u * rho_b);
      out->emplace_back(centre.x() + rho * std::cos(phi), centre.y() + rho * std::sin(phi), z);
    }
  };
  auto tip_radius = [](double, double interpolated) { return interpolated; };
  auto root_radius = [r_root](double u, double interpolated) {
    const double s = std::abs(2.0 * u - 1.0);
    return r_root + (interpolated - r_root) * s * s * s;
  };

  GearMesh out;
  TriangleMesh& mesh = out.mesh;
  mesh.reserve(static_cast<size_t>(nz + 2) * M, 3 * static_cast<size_t>(nz + 2) * M,
               2 * static_cast<size_t>(nz + 2) * M);
  std::vector<TriangleMesh::VertexHandle> v;
  v.reserve(static_cast<size_t>(nz + 2) * M);
  std::vector<Eigen::Vector3d> section;
  section.reserve(M);
  for (int j = 0; j < nz; ++j) {
    const double z = grid_value(0.0, b, j, nz);
    section.clear();
    for (int k = 1; k <= teeth; ++k) {
      tooth_now = k;
      const AnalyticFlank& left = flanks[2 * (k - 1)];
      const AnalyticFlank& right = flanks[2 * (k - 1) + 1];
      const AnalyticFlank& next_left = flanks[2 * (k % teeth)];
      for (int i = 0; i < nL; ++i)
        section.push_back(left.point(grid_value(L_form, L_tip, i, nL), z));
      const Eigen::Vector3d right_tip = right.point(L_tip, z);
      arc(section.back(), right_tip, nt, z, tip_radius, &section);
      for (int i = nL - 1; i >= 0; --i) {
        section.push_back(i == nL - 1 ? right_tip
                                      : right.point(grid_value(L_form, L_tip, i, nL), z));
      }
      arc(section.back(), next_left.point(L_form, z), nr, z, root_radius, &section);
    }
    GEARMC_CHECK(static_cast<int>(section.size()) == M, "section vertex count");
    for (const Eigen::Vector3d& x : section) v.push_back(mesh.add_vertex(to_point(x)));
  }
  // The inner rings of the end faces: section j's vertices projected radially (about the
  // centre) onto the circle of half the section's smallest radius, bottom then top. An internal
  // gear's ring: the outer rings, on the circle of 1.1 times the section's largest radius (the
  // rim), joined by the rim's cylinder.
  const bool internal = gear.internal();
  const int bottom = nz * M, top = bottom + M;
  for (const int j : {0, nz - 1}) {
    double smallest = kInf, largest = 0.0;
    for (int i = 0; i < M; ++i) {
      const TriangleMesh::Point& x = mesh.point(v[static_cast<size_t>(j * M + i)]);
      smallest = std::min(smallest, std::hypot(x[0] - centre.x(), x[1] - centre.y()));
      largest = std::max(largest, std::hypot(x[0] - centre.x(), x[1] - centre.y()));
    }
    const double r_in = internal ? 1.1 * largest : 0.5 * smallest;
    for (int i = 0; i < M; ++i) {
      const TriangleMesh::Point& x = mesh.point(v[static_cast<size_t>(j * M + i)]);
      const double dx = x[0] - centre.x(), dy = x[1] - centre.y(), rho = std::hypot(dx, dy);
      v.push_back(mesh.add_vertex(
          TriangleMesh::Point(centre.x() + r_in * dx / rho, centre.y() + r_in * dy / rho, x[2])));
    }
  }

  out.faces.reserve(2 * static_cast<size_t>(nz) * M);
  // Side walls: the section runs counter-clockwise, so (a, b, c) with a -> b along the section
  // and c above b has the normal (b - a) x e_z pointing outwards; an internal gear's material
  // lies outside its section, its walls face the axis: (a, c, b).
  for (int j = 0; j + 1 < nz; ++j) {
    for (int i = 0; i < M; ++i) {
      const int a = j * M + i, bb = j * M + (i + 1) % M, c = bb + M, d = a + M;
      if (internal) {
        add_triangle(mesh, v, a, c, bb);
        add_triangle(mesh, v, a, d, c);
      } else {
        add_triangle(mesh, v, a, bb, c);
        add_triangle(mesh, v, a, c, d);
      }
      out.faces.push_back(edge_label[i]);
      out.faces.push_back(edge_label[i]);
    }
  }
  if (internal) {  // the rim: the outer rings are convex and counter-clockwise, normals outward
    const GearMeshFace rim{GearMeshFace::Region::kRim, 0, FlankSide::kLeft};
    for (int i = 0; i < M; ++i) {
      const int a = bottom + i, bb = bottom + (i + 1) % M, c = top + (i + 1) % M, d = top + i;
      add_triangle(mesh, v, a, bb, c);
      add_triangle(mesh, v, a, c, d);
      out.faces.push_back(rim);
      out.faces.push_back(rim);
    }
  }
  // End faces, with no vertex in more than a few triangles (a fan from the centre would put one
  // vertex in M of them, and OpenMesh's cost of adding a face grows with its vertices' valence:
  // O(M^2) in all). Each is an annulus between the section (outer o_i) and its inner ring (n_i,
  // on the same ray) plus the inner polygon. The section is star-shaped about the centre (polar
  // angle phi strictly increasing along it), so each edge's quad (n_i, o_i, o_i+1, n_i+1) lies
  // in the edge's own sector [phi_i, phi_i+1] with two radial sides: its triangles (n_i, o_i,
  // o_i+1) and (n_i, o_i+1, n_i+1) are counter-clockwise seen from +z (cross products
  // (rho_i - r_in) rho_i+1 sin(dphi) and r_in (rho_i+1 - r_in) sin(dphi), both > 0) and the
  // sectors do not overlap. The inner polygon is convex (points on a circle, counter-clockwise):
  // a zigzag strip (q_l, q_l+1, q_r), (q_l, q_r-1, q_r) triangulates it with every triangle
  // counter-clockwise. Bottom faces -z (reversed), top +z.
  const GearMeshFace end_face{GearMeshFace::Region::kEndFace, 0, FlankSide::kLeft};
  for (const bool is_top : {false, true}) {
    const int o = is_top ? (nz - 1) * M : 0, n = is_top ? top : bottom;
    auto end_triangle = [&](int a, int bb, int c) {  // counter-clockwise seen from +z
      if (is_top) {
        add_triangle(mesh, v, a, bb, c);
      } else {
        add_triangle(mesh, v, a, c, bb);
      }
      out.faces.push_back(end_face);
    };
    for (int i = 0; i < M; ++i) {
      const int next = (i + 1) % M;
      if (internal) {  // the annulus between the section (inside) and the outer ring
        end_triangle(o + i, n + i, n + next);
        end_triangle(o + i, n + next, o + next);
      } else {
        end_triangle(n + i, o + i, o + next);
        end_triangle(n + i, o + next, n + next);
      }
    }
    if (internal) continue;  // a ring: no inner polygon
    int l = 0, r = M - 1;
    for (bool left = true; r - l >= 2; left = !left) {
      if (left) {
        end_triangle(n + l, n + l + 1, n + r);
        ++l;
      } else {
        end_triangle(n + l, n + r - 1, n + r);
        --r;
      }
    }
  }
  GEARMC_CHECK(out.faces.size() == mesh.n_faces(), "face labels");
  return out;
}

// ---------------------------------------------------------------------------------------------
// Files

MeshFormat mesh_format_of(const std::string& path) {
  const std::string ext = lower_extension(path);
  if (ext == ".stl") return MeshFormat::kStl;
  if (ext == ".ply") return MeshFormat::kPly;
  if (ext == ".obj") return MeshFormat::kObj;
  if (ext == ".off") return MeshFormat::kOff;
  throw MeshIoError("mesh file '" + path + "': unknown extension '" + ext +
                    "' (expected .stl, .ply, .obj or .off)");
}

void write_mesh_file(const TriangleMesh& mesh, const std::string& path,
                     const MeshWriteOptions& options) {
  const MeshFormat format = mesh_format_of(path);
  OpenMesh::IO::Options om_options = OpenMesh::IO::Options::Default;
  if (options.binary && (format == MeshFormat::kStl || format == MeshFormat::kPly)) {
    om_options += OpenMesh::IO::Options::Binary;
  }
  // OpenMesh picks the writer by the extension, so the temporary name keeps it.
  const std::string temporary =
      path + ".partial-" + std::to_string(::getpid()) + format_extension(format);
  bool written;
  {
    QuietOpenMeshLog quiet;
    written = OpenMesh::IO::write_mesh(mesh, temporary, om_options, kTextPrecision);
  }
  std::error_code ec;
  if (!written) {
    std::filesystem::remove(temporary, ec);
    throw MeshIoError("cannot write " + std::string(format_name(format)) + " file '" + path +
                      "' (is the directory there and writable?)");
  }
  std::filesystem::rename(temporary, path, ec);
  if (ec) {
    std::error_code ignored;
    std::filesystem::remove(temporary, ignored);
    throw MeshIoError("cannot write mesh file '" + path + "': " + ec.message());
  }
}

TriangleMesh read_mesh_file(const std::string& path) {
  const MeshFormat format = mesh_format_of(path);
  if (const auto reason = unreadable_input_reason(path, "mesh file", kMaxMeshFileBytes)) {
    throw MeshIoError("cannot read mesh file '" + path + "': " + *reason);
  }
  if (!std::ifstream(path, std::ios::binary).is_open()) {
    throw MeshIoError("cannot open mesh file '" + path + "' (missing or unreadable)");
  }
  TriangleMesh mesh;
  OpenMesh::IO::Options om_options;
  bool read;
  {
    QuietOpenMeshLog quiet;
    read = OpenMesh::IO::read_mesh(mesh, path, om_options);
  }
  if (!read) {
    throw MeshIoError("cannot read mesh file '" + path + "': not a valid " + format_name(format) +
                      " file");
  }
  if (mesh.n_faces() == 0) {
    throw MeshIoError("mesh file '" + path + "' contains no triangles");
  }
  return mesh;
}

}  // namespace gearmc
