// Sphere sweep against triangle meshes (MeshFlankContact) against hand-computed and analytic
// answers:
//  * a tilted plane: the sphere moving along n touches a plane of normal m (angle theta to n)
//    at t = (R - (p - q).m) / (n.m), C = O - R m, and the compensation error of the reported
//    point E = O - R n is |C - E| = R |m - n| = 2 R sin(theta/2) (docs/sources.md, P1);
//  * an edge contact and a vertex contact whose t solves |O(t) - X|^2 = R^2 by hand;
//  * the search window [t_min, t_max] and a sphere already touching at t_max;
//  * the AABB-tree traversal gives exactly the answer of testing every triangle;
//  * convergence: meshes of a real perturbed flank (P1's gear and tolerances), refined, converge
//    to the analytic first contact (an independent nested grid search of the contact height);
//    the centre O converges with order 2, within the interpolation bound derived below;
//  * on a whole-gear mesh a flank probe gives the flank mesh's answer, and a stylus too big for
//    the tooth space touches something other than the planned flank.
#include "surfaces/mesh_contact.h"
#include "tests/support/p1_fixtures.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <cstdio>
#include <limits>
#include <random>
#include <vector>

#include "gears/tolerances.h"

namespace gearmc {
namespace {

using testing_support::p1_gear;
using testing_support::p1_gear_parameters;

TriangleMesh mesh_of(const std::vector<Eigen::Vector3d>& points,
                     const std::vector<std::array<int, 3>>& faces) {
  TriangleMesh mesh;
  std::vector<TriangleMesh::VertexHandle> v;
  for (const auto& x : points) v.push_back(mesh.add_vertex({x.x(), x.y(), x.z()}));
  for (const auto& f : faces) mesh.add_face(v[f[0]], v[f[1]], v[f[2]]);
  return mesh;
}

// A square of side 2 s centred at q in the plane of unit normal m (two triangles).
TriangleMesh square(const Eigen::Vector3d& q, const Eigen::Vector3d& m, double s) {
  const Eigen::Vector3d u = m.unitOrthogonal(), v = m.cross(u);
  return mesh_of({q - s * u - s * v, q + s * u - s * v, q + s * u + s * v, q - s * u + s * v},
                 {{0, 1, 2}, {0, 2, 3}});
}

TEST(MeshContact, TiltedPlaneGivesTwoRSinHalfTheta) {
  const Eigen::Vector3d n = Eigen::Vector3d(0.3, -0.5, 0.8).normalized();
  const Eigen::Vector3d axis = n.unitOrthogonal();
  const Eigen::Vector3d q(1.0, 2.0, -0.5);
  for (double theta : {0.0, 1e-3, 2e-3, 0.1, 0.5, 1.0}) {
    const Eigen::Vector3d m = Eigen::AngleAxisd(theta, axis) * n;
    const MeshFlankContact mesh(square(q, m, 100.0));  // large enough for theta = 1 rad
    for (double R : {0.5, 1.0, 2.5}) {
      for (const Eigen::Vector3d& offset :
           {Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(1.5, -0.7, 0.2), Eigen::Vector3d(-2, 3, 1)}) {
        SCOPED_TRACE(testing::Message() << "theta " << theta << " R " << R);
        const Eigen::Vector3d p = q + offset;
        const MeshContactResult r = mesh.first_contact(p, n, R, -20.0, 20.0);
        ASSERT_TRUE(r.found);
        const double t = (R - (p - q).dot(m)) / n.dot(m);
        EXPECT_NEAR(r.t, t, 1e-9);
        EXPECT_LT((r.centre - (p + t * n)).norm(), 1e-9);
        EXPECT_LT((r.contact - (r.centre - R * m)).norm(), 1e-9);
        const Eigen::Vector3d E = r.centre - R * n;
        EXPECT_NEAR((r.contact - E).norm(), 2 * R * std::sin(theta / 2), 1e-9);
        EXPECT_NEAR((r.contact - r.centre).norm(), R, 1e-9);
      }
    }
  }
}

TEST(MeshContact, EdgeContactByHand) {
  // Triangle in z = 0 on the y <= 0 side of its edge along the x axis.
  const MeshFlankContact mesh(mesh_of({{-5, 0, 0}, {5, 0, 0}, {0, -5, 0}}, {{0, 1, 2}}));
  // Straight down at y = 0.3 beside the edge: 0.3^2 + t^2 = 0.5^2, t = 0.4, C = (1, 0, 0).
  MeshContactResult r = mesh.first_contact({1, 0.3, 0}, {0, 0, 1}, 0.5, -5, 5);
  ASSERT_TRUE(r.found);
  EXPECT_NEAR(r.t, 0.4, 1e-12);
  EXPECT_LT((r.contact - Eigen::Vector3d(1, 0, 0)).norm(), 1e-12);
  // Obliquely, n = (0, 0.6, 0.8): |O - (1, 0, 0)|^2 = (0.3 + 0.6 t)^2 + (0.8 t)^2 = 0.25,
  // t^2 + 0.36 t - 0.16 = 0, t = (-0.36 + sqrt(0.7696)) / 2.
  r = mesh.first_contact({1, 0.3, 0}, {0, 0.6, 0.8}, 0.5, -5, 5);
  ASSERT_TRUE(r.found);
  EXPECT_NEAR(r.t, (-0.36 + std::sqrt(0.7696)) / 2, 1e-12);
  EXPECT_LT((r.contact - Eigen::Vector3d(1, 0, 0)).norm(), 1e-12);
  EXPECT_EQ(r.face, 0);
}

TEST(MeshContact, VertexContactByHand) {
  // A sharp corner at the origin pointing towards -x.
  const MeshFlankContact mesh(mesh_of({{0, 0, 0}, {5, -1, 0}, {5, 1, 0}}, {{0, 1, 2}}));
  MeshContactResult r = mesh.first_contact({-0.3, 0, 0}, {0, 0, 1}, 0.5, -5, 5);
  ASSERT_TRUE(r.found);
  EXPECT_NEAR(r.t, 0.4, 1e-12);  // 0.3^2 + t^2 = 0.5^2
  EXPECT_LT(r.contact.norm(), 1e-12);
  // n = (-0.6, 0, 0.8): |O|^2 = (0.3 + 0.6 t)^2 + (0.8 t)^2 = 0.25, as in the edge case.
  r = mesh.first_contact({-0.3, 0, 0}, {-0.6, 0, 0.8}, 0.5, -5, 5);
  ASSERT_TRUE(r.found);
  EXPECT_NEAR(r.t, (-0.36 + std::sqrt(0.7696)) / 2, 1e-12);
  EXPECT_LT(r.contact.norm(), 1e-12);
  // The single-triangle function agrees, and a line passing farther than R finds nothing.
  EXPECT_NEAR(
      *sphere_triangle_last_contact({0, 0, 0}, {5, -1, 0}, {5, 1, 0}, {-0.3, 0, 0}, {0, 0, 1}, 0.5),
      0.4, 1e-12);
  EXPECT_FALSE(
      sphere_triangle_last_contact({0, 0, 0}, {5, -1, 0}, {5, 1, 0}, {-0.6, 0, 0}, {0, 0, 1}, 0.5));
}

TEST(MeshContact, SearchWindow) {
  const MeshFlankContact mesh(square({0, 0, 0}, {0, 0, 1}, 5.0));
  const Eigen::Vector3d p(0.5, 0.2, 0), n(0, 0, 1);
  MeshContactResult r = mesh.first_contact(p, n, 0.5, -1.0, 2.0);
  EXPECT_TRUE(r.found);
  EXPECT_NEAR(r.t, 0.5, 1e-12);
  r = mesh.first_contact(p, n, 0.5, 0.6, 2.0);  // the contact lies below the window
  EXPECT_FALSE(r.found);
  EXPECT_FALSE(r.touching_at_t_max);
  r = mesh.first_contact(p, n, 0.5, -1.0, 0.3);  // at t_max the sphere already cuts the plane
  EXPECT_FALSE(r.found);
  EXPECT_TRUE(r.touching_at_t_max);
  EXPECT_NEAR(r.t, 0.5, 1e-12);
  r = mesh.first_contact({9, 0, 0}, n, 0.5, -1.0, 2.0);  // passes beside the square
  EXPECT_FALSE(r.found);
}

TEST(MeshContact, TreeTraversalEqualsTestingEveryTriangle) {
  const InvoluteGear gear = p1_gear();
  const GearSampler sampler(gear, testing_support::p1_tolerance_set(), DeviationModel{}, 7);
  const PerturbedGear g = sampler.draw(2);
  const AnalyticFlank flank(gear, 4, FlankSide::kLeft, g.flank(4, FlankSide::kLeft),
                            g.eccentricity_mm);
  const MeshFlankContact mesh(mesh_flank(flank, whole_flank_spec(gear, 1.0, 1.0)));
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> U(0.0, 1.0);
  int found = 0;
  for (int i = 0; i < 400; ++i) {
    const double L = 21.0 + 24.0 * U(rng), z = -2.0 + 83.0 * U(rng);
    const FlankPoint fp = gear.flank_point(4, FlankSide::kLeft, L, z);
    const Eigen::Vector3d tilt(U(rng) - 0.5, U(rng) - 0.5, U(rng) - 0.5);
    const Eigen::Vector3d n = (fp.normal + 1.2 * tilt).normalized();
    const double R = 0.1 + 3.0 * U(rng);
    const double t_min = -2.0 * U(rng), t_max = 4.0 * U(rng);
    const MeshContactResult a = mesh.first_contact(fp.point, n, R, t_min, t_max);
    const MeshContactResult b = mesh.first_contact_linear_scan(fp.point, n, R, t_min, t_max);
    ASSERT_EQ(a.found, b.found) << i;
    ASSERT_EQ(a.touching_at_t_max, b.touching_at_t_max) << i;
    if (!a.found) continue;
    ++found;
    EXPECT_EQ(a.t, b.t) << i;
    EXPECT_LT((a.contact - b.contact).norm(), 1e-12) << i;
    EXPECT_NEAR((a.contact - a.centre).norm(), R, 1e-12) << i;
  }
  EXPECT_GT(found, 100);
}

// The analytic first contact comes from testing_support::brute_force_contact (nested grid
// search of the contact height, tests/support/p1_fixtures.h), independent of the Newton solver.

// Convergence of the mesh contact to the analytic one. The mesh is the piecewise-linear
// interpolant of S on the (L, z) grid; along the normal it misses the surface by at most
//   e = (dL^2 max|S_LL.n| + dz^2 max|S_zz.n|) / 8
// (linear interpolation error on the grid's right triangles; S_Lz.n = 0 for the separable
// deviation field), with S_LL.n = d_LL - (L + d)/r_b^2 (involute curvature plus the profile
// form's) and S_zz.n = d_zz. A sphere resting on a surface moved along the normal by at most e
// moves by at most e (to first order in the tilt), so |O_mesh - O| <= e: order 2 in h.
// The contact point C follows the facet normal, which differs from the surface normal by up to
// ~h kappa: C converges with order 1 only (measured below), and so does delta = |C - E|.
//
// Measured (P1 gear, gear 1 of seed 2024, flanks 6L and 6R, P1's 10 x 5 grid with 5 % margins,
// R = 0.5 mm, max over the 100 points; mesh steps h in L and z; order = log2 of the ratio to
// the previous row; C_s = smoothed_contact):
//   h mm   max|dO| nm order  max|dC| nm order  max|dC_s| nm order  max e nm
//   2.00      4335.3     -      6787.9     -        5003.8     -     5027.2
//   1.00       992.1  2.13      2284.7  1.57         992.1  2.33     1358.0
//   0.50       336.3  1.56      1871.2  0.29         336.3  1.56      351.5
//   0.25        78.9  2.09       765.2  1.29          79.0  2.09       89.2
// O: order 1.93 over the three halvings; C: 1.06; C_s: 2.00. (The test prints this table.)
// (C_s with nu taken at the facet point, before the fixed-point passes of mesh_contact.cpp:
// 5017.3 / 992.3 / 336.3 / 79.0 nm, order 2.02 here; the passes matter below h ~ 0.1 mm.)
TEST(MeshContact, RefinedFlankMeshesConvergeToTheAnalyticContact) {
  const InvoluteGear gear = p1_gear();
  const GearSampler sampler(gear, testing_support::p1_tolerance_set(), DeviationModel{}, 2024);
  const PerturbedGear g = sampler.draw(1);
  const double R = 0.5, r_b = gear.base_diameter_mm() / 2;
  const double L0 = gear.form_roll_length_mm(), L1 = gear.tip_roll_length_mm();
  const double b = gear.face_width_mm();
  struct Probe {
    const AnalyticFlank* flank;
    Eigen::Vector3d p, n, O, C;
    double L, z;
  };
  const AnalyticFlank flanks[2] = {
      AnalyticFlank(gear, 6, FlankSide::kLeft, g.flank(6, FlankSide::kLeft), g.eccentricity_mm),
      AnalyticFlank(gear, 6, FlankSide::kRight, g.flank(6, FlankSide::kRight), g.eccentricity_mm)};
  std::vector<Probe> probes;
  for (const AnalyticFlank& flank : flanks) {
    for (int i = 0; i < 10; ++i) {
      for (int j = 0; j < 5; ++j) {  // P1's grid: N = 10, M = 5, 5 % margins
        const double L = L0 + (L1 - L0) * (0.05 + 0.9 * i / 9), z = b * (0.05 + 0.9 * j / 4);
        const FlankPoint fp = gear.flank_point(6, flank.side(), L, z);
        const Eigen::Vector2d x =
            testing_support::brute_force_contact(flank, fp.point, fp.normal, R, L, z, 18);
        Probe pr{&flank, fp.point, fp.normal, {}, {}, x[0], x[1]};
        pr.C = flank.point(x[0], x[1]);
        pr.O = fp.point + testing_support::brute_force_contact_height(flank, fp.point, fp.normal, R,
                                                                      x[0], x[1]) *
                              fp.normal;
        probes.push_back(pr);
      }
    }
  }
  // The interpolation bound e near a contact (over the patch the sphere can reach).
  auto bound = [&](const Probe& pr, double dL, double dz) {
    double kL = 0, kz = 0;
    for (int a = -10; a <= 10; ++a) {
      const double L = std::clamp(pr.L + (dL + R) * a / 10, L0, L1);
      const double z = std::clamp(pr.z + (dz + R) * a / 10, 0.0, b);
      const FlankDeviation& d =
          pr.flank == &flanks[0] ? g.flank(6, FlankSide::kLeft) : g.flank(6, FlankSide::kRight);
      kL = std::max(kL,
                    std::abs(1e-3 * d.d2_dL2(L) - (L + 1e-3 * d.normal_um(L, pr.z)) / (r_b * r_b)));
      kz = std::max(kz, std::abs(1e-3 * d.d2_dz2(z)));
    }
    return (dL * dL * kL + dz * dz * kz) / 8;
  };

  const double steps[] = {2.0, 1.0, 0.5, 0.25};
  double max_dO[4], max_dC[4], max_dS[4], max_e[4];
  for (int s = 0; s < 4; ++s) {
    const double h = steps[s];
    const FlankMeshSpec spec = whole_flank_spec(gear, h, h);
    const double dL = (L1 - L0) / (spec.roll_length_samples - 1), dz = b / (spec.z_samples - 1);
    const MeshFlankContact meshes[2] = {MeshFlankContact(mesh_flank(flanks[0], spec)),
                                        MeshFlankContact(mesh_flank(flanks[1], spec))};
    max_dO[s] = max_dC[s] = max_dS[s] = max_e[s] = 0;
    for (const Probe& pr : probes) {
      const MeshFlankContact& mesh = meshes[pr.flank == &flanks[0] ? 0 : 1];
      const MeshContactResult r = mesh.first_contact(pr.p, pr.n, R, -1.0, 2.0);
      ASSERT_TRUE(r.found);
      const double dO = (r.centre - pr.O).norm(), e = bound(pr, dL, dz);
      // The bound holds point by point at every resolution (1 % for the first-order tilt
      // terms, 1e-9 mm for the reference's own accuracy).
      EXPECT_LE(dO, 1.01 * e + 1e-9) << "h " << h << " L " << pr.L << " z " << pr.z;
      max_dO[s] = std::max(max_dO[s], dO);
      max_dC[s] = std::max(max_dC[s], (r.contact - pr.C).norm());
      max_dS[s] = std::max(max_dS[s], (r.smoothed_contact - pr.C).norm());
      max_e[s] = std::max(max_e[s], e);
    }
  }
  std::printf("  h mm   max|dO| nm order  max|dC| nm order  max|dCs| nm order  max e nm\n");
  for (int s = 0; s < 4; ++s) {
    auto order = [s](const double* v) { return s ? std::log2(v[s - 1] / v[s]) : 0.0; };
    std::printf("  %4.2f  %10.1f %5.2f  %10.1f %5.2f  %11.1f %5.2f  %8.1f\n", steps[s],
                1e6 * max_dO[s], order(max_dO), 1e6 * max_dC[s], order(max_dC), 1e6 * max_dS[s],
                order(max_dS), 1e6 * max_e[s]);
  }
  // Order 2 for the centre over the last three halvings (the max over 100 points smooths the
  // dependence on where each contact falls within its facet).
  const double order_O = std::log2(max_dO[0] / max_dO[3]) / 3;
  EXPECT_GT(order_O, 1.7);
  EXPECT_LT(order_O, 2.3);
  // At h = 0.25 mm (dL = 0.2491 mm, dz = 0.2497 mm) the bound e is
  // dL^2/8 (max (L+d)/r_b^2 + max|d_LL|) + dz^2/8 max|d_zz| <= 89 nm over the probed points:
  // the involute part is 0.2491^2/8 * 44.3/63.15^2 = 86 nm at the last profile point
  // (L = 44.3 mm), the form fields add about 3 nm. Asserted with a margin:
  EXPECT_LT(max_dO[3], 100e-6);  // 100 nm
  // The smoothed contact point converges like O (order 2); the exact mesh contact point C, which
  // follows the facet normals, only with order ~1 and is several times worse at h = 0.25 mm.
  const double order_S = std::log2(max_dS[0] / max_dS[3]) / 3;
  EXPECT_GT(order_S, 1.7);
  EXPECT_LT(order_S, 2.3);
  EXPECT_LT(max_dS[3], 100e-6);
  const double order_C = std::log2(max_dC[0] / max_dC[3]) / 3;
  EXPECT_LT(order_C, 1.5);
  EXPECT_GT(max_dC[3], 4 * max_dS[3]);
}

TEST(MeshContact, WholeGearMeshMatchesTheFlankMeshAndSeesCollisions) {
  const InvoluteGear gear = p1_gear();
  const GearSampler sampler(gear, testing_support::p1_tolerance_set(), DeviationModel{}, 3);
  const PerturbedGear g = sampler.draw(0);
  const GearMeshSpec spec{30, 6, 12, 60};
  const GearMesh gm = mesh_gear(gear, g, spec);
  const MeshFlankContact whole(gm.mesh);
  const FlankMeshSpec flank_spec{
      gear.form_roll_length_mm(), gear.tip_roll_length_mm(), 0.0,
      gear.face_width_mm(),       spec.profile_samples,      spec.face_samples};
  for (int tooth : {1, 9, 24}) {
    for (FlankSide side : {FlankSide::kLeft, FlankSide::kRight}) {
      const AnalyticFlank flank(gear, tooth, side, g.flank(tooth, side), g.eccentricity_mm);
      const MeshFlankContact single(mesh_flank(flank, flank_spec));
      for (double L : {24.0, 33.0, 43.0}) {
        for (double z : {5.0, 40.0, 74.0}) {
          const FlankPoint fp = gear.flank_point(tooth, side, L, z);
          const MeshContactResult a = whole.first_contact(fp.point, fp.normal, 0.5, -1.0, 1.5);
          const MeshContactResult b = single.first_contact(fp.point, fp.normal, 0.5, -1.0, 1.5);
          ASSERT_TRUE(a.found);
          ASSERT_TRUE(b.found);
          EXPECT_NEAR(a.t, b.t, 1e-12);
          EXPECT_LT((a.contact - b.contact).norm(), 1e-12);
          const GearMeshFace& label = gm.faces[a.face];
          EXPECT_EQ(label.region, GearMeshFace::Region::kFlank);
          EXPECT_EQ(label.tooth, tooth);
          EXPECT_EQ(label.side, side);
        }
      }
    }
  }
  // A 2 mm stylus sent to the bottom of flank 5R (0.5 mm of roll length above the form
  // circle): the root lies 1.4 mm below the form circle and the sphere reaches it first. The
  // flank alone would have been touched later (smaller t); the whole-gear mesh says what was
  // touched instead: a collision, not a flank point.
  const double L = gear.form_roll_length_mm() + 0.5;
  const FlankPoint fp = gear.flank_point(5, FlankSide::kRight, L, 40.0);
  const MeshContactResult r = whole.first_contact(fp.point, fp.normal, 2.0, -1.0, 2.5);
  ASSERT_TRUE(r.found);
  const GearMeshFace& label = gm.faces[r.face];
  EXPECT_EQ(label.region, GearMeshFace::Region::kRoot);
  EXPECT_EQ(label.tooth, 5);
  const AnalyticFlank flank(gear, 5, FlankSide::kRight, g.flank(5, FlankSide::kRight),
                            g.eccentricity_mm);
  const MeshContactResult alone = MeshFlankContact(mesh_flank(flank, flank_spec))
                                      .first_contact(fp.point, fp.normal, 2.0, -1.0, 2.5);
  ASSERT_TRUE(alone.found);
  EXPECT_LT(alone.t, r.t - 1e-3);
}

}  // namespace
}  // namespace gearmc
