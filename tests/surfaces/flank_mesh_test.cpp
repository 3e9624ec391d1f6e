// Flank and whole-gear meshes and their files:
//  * a flank mesh has its vertices on the real surface S(L_i, z_j) and its faces oriented like
//    the outward normal, on either flank;
//  * the whole-gear mesh is, for CGAL, a valid, closed, outward-oriented triangle mesh without
//    self-intersections, its face labels count what the construction says, and its enclosed
//    volume is b times the analytic transverse area (involute flanks, tip arcs, the documented
//    root blend) within the chord (sagitta) error of the sampling, computed here;
//  * STL (binary and ASCII), PLY (binary and ASCII), OBJ and OFF files written and read back
//    through OpenMesh keep the vertex and face counts, the connectivity and every coordinate to
//    the format's precision: OpenMesh 9 passes coordinates through 32-bit floats in every
//    format, so a coordinate x comes back within |x| 2^-24 (round to nearest float: half an
//    ulp, ulp <= 2^-23 |x|); no temporary file is left behind;
//  * an unreadable file, an unknown extension, a garbage file and an unwritable place all give
//    MeshIoError.
#include "surfaces/flank_mesh.h"
#include "tests/support/p1_fixtures.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <string>
#include <vector>

#include "surfaces/mesh_contact.h"
#include "tests/support/temp_paths.h"

using ::gearmc::testing_support::fresh_temp_path;

namespace gearmc {
namespace {

using testing_support::p1_gear;
using testing_support::p1_gear_parameters;
using testing_support::wavy_deviation;

constexpr double kPi = std::numbers::pi;

Eigen::Vector3d to_eigen(const TriangleMesh::Point& x) { return {x[0], x[1], x[2]}; }

Eigen::Vector3d face_normal(const TriangleMesh& mesh, TriangleMesh::FaceHandle f) {
  std::vector<Eigen::Vector3d> v;
  for (auto vh : mesh.fv_range(f)) v.push_back(to_eigen(mesh.point(vh)));
  return (v[1] - v[0]).cross(v[2] - v[0]).normalized();
}

// This process's folder for mesh files, made once (other tests write beside it in parallel).
const std::filesystem::path& mesh_folder() {
  static const std::filesystem::path folder = [] {
    const std::filesystem::path p = fresh_temp_path("mesh");
    std::filesystem::create_directories(p);
    return p;
  }();
  return folder;
}

std::string temp_path(const std::string& name) { return (mesh_folder() / name).string(); }

PerturbedGear nominal_perturbed(const InvoluteGear& gear) {
  PerturbedGear g;
  g.flanks.resize(2 * gear.teeth());
  return g;
}

TEST(FlankMesh, VerticesOnTheSurfaceAndFacesOrientedOutwards) {
  const InvoluteGear gear = p1_gear();
  const FlankDeviation dev = wavy_deviation();
  for (FlankSide side : {FlankSide::kLeft, FlankSide::kRight}) {
    const AnalyticFlank flank(gear, 5, side, dev, {0.012, -0.007});
    const FlankMeshSpec spec{22.0, 44.0, 3.0, 75.0, 12, 9};
    const TriangleMesh mesh = mesh_flank(flank, spec);
    ASSERT_EQ(mesh.n_vertices(), 12u * 9u);
    ASSERT_EQ(mesh.n_faces(), 2u * 11u * 8u);
    const MeshCheck check = check_mesh(mesh);  // an open sheet: valid, not closed, no volume
    EXPECT_TRUE(check.valid);
    EXPECT_TRUE(check.triangles);
    EXPECT_FALSE(check.closed);
    EXPECT_EQ(check.volume_mm3, 0.0);
    EXPECT_GT(check.area_mm2, 0.9 * 72.0 * (44.0 * 44.0 - 22.0 * 22.0) / (2 * 63.15));
    for (int j = 0; j < 9; ++j) {
      for (int i = 0; i < 12; ++i) {
        const double L = 22.0 + 22.0 * i / 11, z = 3.0 + 72.0 * j / 8;
        const Eigen::Vector3d x = to_eigen(mesh.point(TriangleMesh::VertexHandle(j * 12 + i)));
        EXPECT_LT((x - flank.point(L, z)).norm(), 1e-12);
      }
    }
    // Every face normal within a few degrees of the nominal outward normal at its centroid.
    for (auto f : mesh.faces()) {
      Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
      for (auto vh : mesh.fv_range(f)) centroid += to_eigen(mesh.point(vh)) / 3.0;
      const double phi = std::atan2(centroid.y(), centroid.x());
      // Nominal normal of this flank near the centroid: the flank's own at the closest L.
      double best = 1e9, L_best = 22.0;
      for (double L = 22.0; L <= 44.0; L += 0.05) {
        const double d = (gear.flank_point(5, side, L, centroid.z()).point - centroid).norm();
        if (d < best) best = d, L_best = L;
      }
      const Eigen::Vector3d n = gear.flank_point(5, side, L_best, centroid.z()).normal;
      EXPECT_GT(face_normal(mesh, f).dot(n), std::cos(0.1)) << "phi " << phi;
    }
  }
}

// Analytic transverse area of the nominal gear as mesh_gear shapes it (flank_mesh.h): per
// tooth, the involute part between the form and the tip circle, 2 ∫ psi(r) r dr with the half
// tooth angle psi = theta_b - inv(alpha_r) (ISO 21771); in roll length (r dr = L dL,
// inv = L/r_b - atan(L/r_b)) the primitive is
//   G(L) = theta_b L^2/2 - L^3/(3 r_b) + (L^2 + r_b^2) atan(L/r_b)/2 - r_b L/2;
// the sector under the tooth below the form circle, psi_F r_Ff^2; the root blend
// r(u) = r_f + a |2u-1|^3 (a = r_Ff - r_f) over the space angle D = tau - 2 psi_F:
// (D/2) ∫ r^2 du = (D/2)(r_f^2 + r_f a/2 + a^2/7).
double analytic_section_area(const InvoluteGear& gear) {
  const double r_b = gear.base_diameter_mm() / 2, theta_b = gear.base_half_angle_rad();
  const double L_F = gear.form_roll_length_mm(), L_a = gear.tip_roll_length_mm();
  auto G = [&](double L) {
    return theta_b * L * L / 2 - L * L * L / (3 * r_b) +
           (L * L + r_b * r_b) * std::atan(L / r_b) / 2 - r_b * L / 2;
  };
  const double psi_F = theta_b - (L_F / r_b - std::atan(L_F / r_b));
  const double r_F = gear.form_diameter_mm() / 2, r_f = gear.root_diameter_mm() / 2;
  const double a = r_F - r_f, D = gear.angular_pitch_rad() - 2 * psi_F;
  const double per_tooth =
      2 * (G(L_a) - G(L_F)) + psi_F * r_F * r_F + D / 2 * (r_f * r_f + r_f * a / 2 + a * a / 7);
  return gear.teeth() * per_tooth;
}

// Upper bound of |analytic area - inscribed polygon area| for the sampling `spec`: each chord
// of a curve cuts off at most (2/3) c s, s = c^2 kappa / 8 the sagitta (c^3 kappa / 12). The
// involute chord from L_i to L_i+1 is at most its arc length (L_i+1^2 - L_i^2)/(2 r_b), its
// curvature at most 1/L_i; the tip chords cut exact circular segments r_a^2 (phi - sin phi)/2;
// the root chords' segments are integrated numerically (polar area minus the fan triangle).
double chord_error_bound(const InvoluteGear& gear, const GearMeshSpec& spec) {
  const double r_b = gear.base_diameter_mm() / 2, theta_b = gear.base_half_angle_rad();
  const double L_F = gear.form_roll_length_mm(), L_a = gear.tip_roll_length_mm();
  double involute = 0;
  for (int i = 0; i + 1 < spec.profile_samples; ++i) {
    const double L0 = L_F + (L_a - L_F) * i / (spec.profile_samples - 1);
    const double L1 = L_F + (L_a - L_F) * (i + 1) / (spec.profile_samples - 1);
    const double c = (L1 * L1 - L0 * L0) / (2 * r_b);
    involute += c * c * c / (12 * L0);
  }
  const double r_a = gear.tip_diameter_mm() / 2;
  const double psi_a = theta_b - (L_a / r_b - std::atan(L_a / r_b));
  const double phi = 2 * psi_a / (spec.tip_samples + 1);
  const double tip = (spec.tip_samples + 1) * r_a * r_a * (phi - std::sin(phi)) / 2;
  const double psi_F = theta_b - (L_F / r_b - std::atan(L_F / r_b));
  const double r_F = gear.form_diameter_mm() / 2, r_f = gear.root_diameter_mm() / 2;
  const double D = gear.angular_pitch_rad() - 2 * psi_F;
  auto r = [&](double u) { return r_f + (r_F - r_f) * std::pow(std::abs(2 * u - 1), 3); };
  double root = 0;
  const int n = spec.root_samples + 1;
  for (int m = 0; m < n; ++m) {
    const double u0 = static_cast<double>(m) / n, u1 = static_cast<double>(m + 1) / n;
    double polar = 0;  // (1/2) ∫ r^2 dtheta, Simpson with 200 intervals
    for (int q = 0; q <= 200; ++q) {
      const double u = u0 + (u1 - u0) * q / 200, w = (q == 0 || q == 200) ? 1 : (q % 2 ? 4 : 2);
      polar += w * r(u) * r(u);
    }
    polar *= 0.5 * D * (u1 - u0) / 600;
    root += std::abs(polar - 0.5 * r(u0) * r(u1) * std::sin(D * (u1 - u0)));
  }
  return gear.teeth() * (2 * involute + tip + root);
}

TEST(GearMesh, NominalGearIsAClosedOutwardSolidWithTheAnalyticVolume) {
  const InvoluteGear gear = p1_gear();
  GearMeshSpec spec;      // 25 profile, 6 tip, 12 root samples (the defaults) ...
  spec.face_samples = 5;  // ... few sections: the nominal gear is a prism (and the test fast)
  const GearMesh gm = mesh_gear(gear, nominal_perturbed(gear), spec);
  const int M = gear.teeth() * (2 * spec.profile_samples + spec.tip_samples + spec.root_samples);
  // F sections and an inner ring per end face; 2 (F - 1) M walls and 3 M - 2 per end face (an
  // annulus of 2 M, the inner polygon's M - 2), flank_mesh.h.
  ASSERT_EQ(gm.mesh.n_vertices(), static_cast<size_t>((spec.face_samples + 2) * M));
  ASSERT_EQ(gm.mesh.n_faces(),
            static_cast<size_t>(2 * (spec.face_samples - 1) * M + 2 * (3 * M - 2)));
  ASSERT_EQ(gm.faces.size(), gm.mesh.n_faces());

  const MeshCheck check = check_mesh(gm.mesh, /*check_self_intersection=*/true);
  EXPECT_TRUE(check.valid);
  EXPECT_TRUE(check.triangles);
  EXPECT_TRUE(check.closed);
  EXPECT_TRUE(check.outward_oriented);
  EXPECT_FALSE(check.self_intersecting);

  const double b = gear.face_width_mm();
  const double expected = analytic_section_area(gear) * b;
  const double tolerance = chord_error_bound(gear, spec) * b;
  // Analytic 1.26388e6 mm^3; the bound is 107 mm^3 (8.5e-5 relative; the mesh is 34 mm^3 low).
  // A missing fan, a flipped wall or a wrong root shape would be off by orders of magnitude more.
  EXPECT_GT(check.volume_mm3, 0.0);
  EXPECT_NEAR(check.volume_mm3, expected, tolerance);
  EXPECT_LT(tolerance, 1e-4 * expected);
  // Refining the profile sampling moves the volume towards the analytic value (O(h^2)).
  GearMeshSpec fine = spec;
  fine.profile_samples = 100, fine.tip_samples = 24, fine.root_samples = 48, fine.face_samples = 2;
  const double fine_volume =
      check_mesh(mesh_gear(gear, nominal_perturbed(gear), fine).mesh).volume_mm3;
  EXPECT_LT(std::abs(fine_volume - expected), std::abs(check.volume_mm3 - expected) / 8);

  // Face labels: per tooth 2 flanks x (profile_samples - 1) edges, tip_samples + 1 tip edges,
  // root_samples + 1 root edges, each giving 2 (face_samples - 1) wall triangles; 2 M fans.
  int flank = 0, tip = 0, root = 0, end = 0;
  for (const GearMeshFace& f : gm.faces) {
    switch (f.region) {
      case GearMeshFace::Region::kFlank:
        ++flank;
        break;
      case GearMeshFace::Region::kTip:
        ++tip;
        break;
      case GearMeshFace::Region::kRoot:
        ++root;
        break;
      case GearMeshFace::Region::kEndFace:
        ++end;
        break;
      case GearMeshFace::Region::kRim:
        ADD_FAILURE() << "an external gear has no rim";
        break;
    }
  }
  const int wall = 2 * (spec.face_samples - 1) * gear.teeth();
  EXPECT_EQ(flank, wall * 2 * (spec.profile_samples - 1));
  EXPECT_EQ(tip, wall * (spec.tip_samples + 1));
  EXPECT_EQ(root, wall * (spec.root_samples + 1));
  EXPECT_EQ(end, 2 * (3 * M - 2));
  // No vertex with more than a few neighbours, whatever M (a fan made one centre vertex the
  // neighbour of all M, and building such a vertex costs OpenMesh O(M^2)): a wall vertex has 6,
  // an inner-ring vertex 4 in the annulus and at most 2 strip diagonals, a section vertex on an
  // end 4 along the wall and 2 on the inner ring.
  size_t max_valence = 0;
  for (const auto vh : gm.mesh.vertices()) {
    max_valence = std::max(max_valence, static_cast<size_t>(gm.mesh.valence(vh)));
  }
  EXPECT_LE(max_valence, 8u);
}

TEST(GearMesh, PerturbedGearIsClosedAndFlankFacesLieOnTheirFlanks) {
  const InvoluteGear gear = p1_gear();
  PerturbedGear g = nominal_perturbed(gear);
  g.eccentricity_mm = {0.02, -0.015};
  double max_deviation_um = 0;
  for (int k = 1; k <= gear.teeth(); ++k) {
    for (FlankSide side : {FlankSide::kLeft, FlankSide::kRight}) {
      FlankDeviation d = wavy_deviation();
      d.offset_um = -40.0 + 3.0 * k * side_sign(side);  // every flank different
      g.flank(k, side) = d;
      for (double L = 21.0; L <= 45.0; L += 0.5) {
        for (double z = 0; z <= 79.0; z += 1.0) {
          max_deviation_um = std::max(max_deviation_um, std::abs(d.normal_um(L, z)));
        }
      }
    }
  }
  const GearMeshSpec spec{20, 5, 10, 12};
  const GearMesh gm = mesh_gear(gear, g, spec);
  const MeshCheck check = check_mesh(gm.mesh, true);
  EXPECT_TRUE(check.valid);
  EXPECT_TRUE(check.closed);
  EXPECT_TRUE(check.outward_oriented);
  EXPECT_FALSE(check.self_intersecting);
  // Volume: the nominal mesh's, changed by at most (perimeter x b x max |d|): every section
  // vertex moves by at most max |d| relative to the gear centre (eccentricity is a translation).
  const double nominal = check_mesh(mesh_gear(gear, nominal_perturbed(gear), spec).mesh).volume_mm3;
  const double perimeter = 2 * kPi * gear.tip_diameter_mm() / 2 * 3;  // generous: 3 x tip circle
  EXPECT_NEAR(check.volume_mm3, nominal,
              perimeter * gear.face_width_mm() * 1e-3 * max_deviation_um);
  EXPECT_NE(check.volume_mm3, nominal);
  // Every vertex of every flank face lies on its real flank (S(L, z) for some L, z, found by
  // projecting: in the transverse plane, distance from the nominal involute = the deviation).
  int checked = 0;
  for (auto f : gm.mesh.faces()) {
    const GearMeshFace& label = gm.faces[f.idx()];
    if (label.region != GearMeshFace::Region::kFlank || f.idx() % 97 != 0) continue;
    const AnalyticFlank flank(gear, label.tooth, label.side, g.flank(label.tooth, label.side),
                              g.eccentricity_mm);
    for (auto vh : gm.mesh.fv_range(f)) {
      const Eigen::Vector3d x = to_eigen(gm.mesh.point(vh));
      double best = 1e9;
      for (int i = 0; i < spec.profile_samples; ++i) {
        const double L =
            gear.form_roll_length_mm() + (gear.tip_roll_length_mm() - gear.form_roll_length_mm()) *
                                             i / (spec.profile_samples - 1);
        best = std::min(best, (flank.point(L, x.z()) - x).norm());
      }
      EXPECT_LT(best, 1e-9);
      ++checked;
    }
  }
  EXPECT_GT(checked, 100);
}

TEST(MeshFiles, RoundTripKeepsCountsConnectivityAndCoordinatesToFloatPrecision) {
  const InvoluteGear gear = p1_gear();
  const FlankDeviation dev = wavy_deviation();
  const AnalyticFlank flank(gear, 3, FlankSide::kRight, dev, {0.01, 0.02});
  const TriangleMesh mesh = mesh_flank(flank, whole_flank_spec(gear, 1.0, 2.0));
  struct Case {
    std::string name;
    bool binary;
  };
  for (const Case& c : std::vector<Case>{{"flank_b.stl", true},
                                         {"flank_a.stl", false},
                                         {"flank_b.ply", true},
                                         {"flank_a.ply", false},
                                         {"flank.obj", false},
                                         {"flank.OFF", false}}) {
    SCOPED_TRACE(c.name);
    const std::string path = temp_path(c.name);
    write_mesh_file(mesh, path, {c.binary});
    const TriangleMesh back = read_mesh_file(path);
    ASSERT_EQ(back.n_vertices(), mesh.n_vertices());
    ASSERT_EQ(back.n_faces(), mesh.n_faces());
    auto close = [](const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
      for (int k = 0; k < 3; ++k) {
        if (std::abs(a[k] - b[k]) > std::abs(b[k]) * std::ldexp(1.0, -24)) return false;
      }
      return true;
    };
    const bool is_stl = mesh_format_of(path) == MeshFormat::kStl;
    if (!is_stl) {  // PLY, OBJ, OFF keep the vertex order and the faces' vertex indices
      for (auto v : mesh.vertices()) {
        ASSERT_TRUE(close(to_eigen(back.point(v)), to_eigen(mesh.point(v)))) << v.idx();
      }
    }
    // Faces in file order with the same vertices in the same cyclic order (STL stores each
    // triangle's three points; the reader merges equal points into shared vertices).
    for (auto f : mesh.faces()) {
      std::vector<Eigen::Vector3d> a, b;
      std::vector<int> ia, ib;
      for (auto vh : mesh.fv_range(f))
        a.push_back(to_eigen(mesh.point(vh))), ia.push_back(vh.idx());
      const TriangleMesh::FaceHandle fb(f.idx());
      for (auto vh : back.fv_range(fb))
        b.push_back(to_eigen(back.point(vh))), ib.push_back(vh.idx());
      ASSERT_EQ(b.size(), 3u);
      int shift = 0;
      while (shift < 3 && !close(b[shift], a[0])) ++shift;
      ASSERT_LT(shift, 3) << "face " << f.idx();
      for (int k = 0; k < 3; ++k) {
        EXPECT_TRUE(close(b[(k + shift) % 3], a[k])) << "face " << f.idx();
        if (!is_stl) {
          EXPECT_EQ(ib[(k + shift) % 3], ia[k]);
        }
      }
    }
    std::filesystem::remove(path);
  }
  // Nothing but the files themselves was ever left in the directory.
  for (const auto& entry : std::filesystem::directory_iterator(mesh_folder())) {
    EXPECT_EQ(entry.path().string().find(".partial-"), std::string::npos) << entry.path();
  }
}

TEST(MeshFiles, ExportedGearReadsBackClosed) {
  const InvoluteGear gear = p1_gear();
  const GearMesh gm = mesh_gear(gear, nominal_perturbed(gear), GearMeshSpec{12, 3, 6, 6});
  for (std::string name : {"gear.stl", "gear.ply", "gear.obj", "gear.off"}) {
    SCOPED_TRACE(name);
    const std::string path = temp_path(name);
    write_mesh_file(gm.mesh, path);
    const TriangleMesh back = read_mesh_file(path);
    EXPECT_EQ(back.n_vertices(), gm.mesh.n_vertices());
    const MeshCheck check = check_mesh(back);
    EXPECT_TRUE(check.valid);
    EXPECT_TRUE(check.closed);
    EXPECT_TRUE(check.outward_oriented);
    EXPECT_NEAR(check.volume_mm3, check_mesh(gm.mesh).volume_mm3, 1e-5 * check.volume_mm3);
    std::filesystem::remove(path);
  }
}

TEST(MeshFiles, ErrorsAreMeshIoErrors) {
  const std::string missing = temp_path("does_not_exist.stl");
  EXPECT_THROW(read_mesh_file(missing), MeshIoError);
  try {
    read_mesh_file(missing);
  } catch (const MeshIoError& e) {
    EXPECT_NE(std::string(e.what()).find("does_not_exist.stl"), std::string::npos);
  }
  const std::string text = temp_path("points.xyz");
  std::ofstream(text) << "1 2 3\n";
  EXPECT_THROW(read_mesh_file(text), MeshIoError);
  EXPECT_THROW(mesh_format_of("flank.step"), MeshIoError);
  EXPECT_THROW(mesh_format_of("flank"), MeshIoError);
  const std::string garbage = temp_path("garbage.off");
  std::ofstream(garbage) << "this is not an OFF file\n";
  EXPECT_THROW(read_mesh_file(garbage), MeshIoError);
  EXPECT_THROW(read_mesh_file(mesh_folder().string()), MeshIoError);  // a directory
  std::filesystem::remove(text);
  std::filesystem::remove(garbage);

  const InvoluteGear gear = p1_gear();
  const FlankDeviation none;
  const TriangleMesh mesh =
      mesh_flank(AnalyticFlank(gear, 1, FlankSide::kLeft, none, {0, 0}), {22, 40, 0, 10, 3, 3});
  EXPECT_THROW(write_mesh_file(mesh, temp_path("flank.xyz")), MeshIoError);
  EXPECT_THROW(write_mesh_file(mesh, temp_path("no_such_dir/flank.stl")), MeshIoError);
  EXPECT_FALSE(std::filesystem::exists(temp_path("no_such_dir")));
  // A MeshIoError is a std::runtime_error (the engine reports it as bad input).
  EXPECT_THROW(read_mesh_file(missing), std::runtime_error);
}

// An internal (ring) gear's mesh: a closed solid oriented outward (its flank walls facing the
// axis), without self-intersections, whose volume is the rim's prism (the outer ring polygon, a
// convex polygon read from the mesh, times b) minus the bore bounded by the teeth, analytic: the
// disk inside the tip circle, pi r_a^2, plus per space the part between the tip and the form
// circle, ∫ (tau - 2 psi(r)) r dr with the internal tooth's half angle psi = theta_b + inv(alpha_r)
// (DIN 3960; in roll length r dr = L dL, Simpson), plus the root blend over the space angle
// D = tau - 2 psi_F beyond the form circle, (D/2)(r_f^2 + r_f a/2 + a^2/7) - (D/2) r_Ff^2.
TEST(GearMesh, InternalGearIsAClosedOutwardRingWithTheAnalyticVolume) {
  GearParameters p;
  p.teeth = 60;
  p.internal = true;
  p.module_mm = 2.0;
  p.face_width_mm = 20.0;
  ASSERT_EQ(validate_gear_parameters(p), "");
  const InvoluteGear gear(p);
  GearMeshSpec spec;
  spec.face_samples = 3;
  const GearMesh gm = mesh_gear(gear, nominal_perturbed(gear), spec);
  const int M = gear.teeth() * (2 * spec.profile_samples + spec.tip_samples + spec.root_samples);
  // F sections and an outer ring per end face; 2 (F - 1) M walls, 2 M rim and 2 M per end face.
  ASSERT_EQ(gm.mesh.n_vertices(), static_cast<size_t>((spec.face_samples + 2) * M));
  ASSERT_EQ(gm.mesh.n_faces(), static_cast<size_t>(2 * (spec.face_samples - 1) * M + 6 * M));
  const MeshCheck check = check_mesh(gm.mesh, /*check_self_intersection=*/true);
  EXPECT_TRUE(check.valid);
  EXPECT_TRUE(check.closed);
  EXPECT_TRUE(check.outward_oriented);
  EXPECT_FALSE(check.self_intersecting);

  const double r_b = gear.base_diameter_mm() / 2, theta = gear.base_half_angle_rad();
  const double L_a = gear.tip_roll_length_mm(), L_F = gear.form_roll_length_mm();
  const double tau = 2 * std::numbers::pi / gear.teeth();
  const auto psi = [&](double L) { return theta + (L / r_b - std::atan(L / r_b)); };
  double space = 0;  // Simpson, 2000 intervals
  for (int q = 0; q <= 2000; ++q) {
    const double L = L_a + (L_F - L_a) * q / 2000, w = (q == 0 || q == 2000) ? 1 : (q % 2 ? 4 : 2);
    space += w * (tau - 2 * psi(L)) * L;
  }
  space *= (L_F - L_a) / 6000;
  const double r_a = gear.tip_diameter_mm() / 2, r_F = gear.form_diameter_mm() / 2;
  const double r_f = gear.root_diameter_mm() / 2, a = r_F - r_f, D = tau - 2 * psi(L_F);
  const double blend = 0.5 * D * (r_f * r_f + r_f * a / 2 + a * a / 7) - 0.5 * D * r_F * r_F;
  const double bore = std::numbers::pi * r_a * r_a + gear.teeth() * (space + blend);
  double rim = 0;  // shoelace of the bottom outer ring
  const int ring = spec.face_samples * M;
  for (int i = 0; i < M; ++i) {
    const auto x = gm.mesh.point(TriangleMesh::VertexHandle(ring + i));
    const auto y = gm.mesh.point(TriangleMesh::VertexHandle(ring + (i + 1) % M));
    rim += 0.5 * (x[0] * y[1] - y[0] * x[1]);
  }
  const double expected = (rim - bore) * p.face_width_mm;
  // Measured: 4.4 of 70166 mm^3 (6.3e-5 relative) too much: the chords of the tip arcs and the
  // root blends cut into the bore. A flipped wall or a missing rim is off by the whole volume.
  EXPECT_NEAR(check.volume_mm3, expected, 1e-4 * expected);
  EXPECT_GT(check.volume_mm3, expected);
  // Finer sampling shrinks the difference (chord error ~ h^2; the involute's chords, 25 samples
  // per flank, account for about 1.7 mm^3 of it: c^3 / (12 L) per chord).
  GearMeshSpec fine = spec;
  fine.profile_samples = 100, fine.tip_samples = 24, fine.root_samples = 48, fine.face_samples = 2;
  const GearMesh fine_mesh = mesh_gear(gear, nominal_perturbed(gear), fine);
  double fine_rim = 0;
  const int fine_M =
      gear.teeth() * (2 * fine.profile_samples + fine.tip_samples + fine.root_samples);
  for (int i = 0; i < fine_M; ++i) {
    const auto x = fine_mesh.mesh.point(TriangleMesh::VertexHandle(2 * fine_M + i));
    const auto y = fine_mesh.mesh.point(TriangleMesh::VertexHandle(2 * fine_M + (i + 1) % fine_M));
    fine_rim += 0.5 * (x[0] * y[1] - y[0] * x[1]);
  }
  const double fine_expected = (fine_rim - bore) * p.face_width_mm;
  EXPECT_LT(std::abs(check_mesh(fine_mesh.mesh).volume_mm3 - fine_expected),
            std::abs(check.volume_mm3 - expected) / 4);
  int rim_faces = 0;
  for (const GearMeshFace& f : gm.faces) rim_faces += f.region == GearMeshFace::Region::kRim;
  EXPECT_EQ(rim_faces, 2 * M);
}

}  // namespace
}  // namespace gearmc
