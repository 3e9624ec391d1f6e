// Sphere sweep against a triangle mesh through a CGAL AABB tree, and CGAL mesh checks (see
// mesh_contact.h). The only translation unit of gearmc that includes CGAL: the tree works
// directly on the OpenMesh mesh through CGAL's graph traits for TriMesh_ArrayKernelT, and a
// custom traversal (CGAL's AABB_tree::traversal_with_priority with our own traits: a node is
// entered when the swept line, grown by R, reaches its box above the best contact found so far,
// the child reaching higher first) gives a branch-and-bound for the largest contact t.
//
// Per triangle (the exact part), with the triangle's Minkowski sum with the ball of radius R
// written as the union of the slab prism over its interior, the three edge cylinders (lateral
// surface, 0 <= u <= 1) and the three vertex balls (Ericson, Real-Time Collision Detection,
// 2005, §5.3 for line-vs-slab/cylinder/sphere tests): the last t is the largest exit over these
// pieces. Quadratics use the cancellation-free root form (Press et al., Numerical Recipes,
// §5.6). The contact point C is the point of the triangle closest to O(t) (Ericson §5.1.5).
// Cheap exits keep a query at a few µs: a triangle is skipped when the sphere cannot touch its
// bounding ball, or its plane's slab (|distance| <= R, which holds the whole Minkowski sum),
// above the best t so far; and a line leaving the prism through the slab face above the
// interior has found the exit of the convex Minkowski sum, so the edge and corner pieces are
// not needed. The smoothed contact uses angle-weighted vertex normals (Thuermer & Wuethrich,
// "Computing vertex normals from polygonal facets", J. Graphics Tools 3(1), 1998).
#include "surfaces/mesh_contact.h"

#include <CGAL/AABB_face_graph_triangle_primitive.h>
#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/measure.h>
#include <CGAL/Polygon_mesh_processing/orientation.h>
#include <CGAL/Polygon_mesh_processing/self_intersections.h>
#include <CGAL/boost/graph/graph_traits_TriMesh_ArrayKernelT.h>
#include <CGAL/boost/graph/helpers.h>
#include <Eigen/Geometry>
#include <array>
#include <cmath>
#include <limits>
#include <utility>
#include <vector>

namespace gearmc {
namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;  // OpenMesh's point map
using Primitive = CGAL::AABB_face_graph_triangle_primitive<TriangleMesh>;
using AabbTraits = CGAL::AABB_traits<Kernel, Primitive>;
using Tree = CGAL::AABB_tree<AabbTraits>;
namespace PMP = CGAL::Polygon_mesh_processing;

constexpr double kInfinity = std::numeric_limits<double>::infinity();

using Corners = std::array<Eigen::Vector3d, 3>;

// A triangle with what the sweep test needs precomputed.
struct Triangle {
  Corners v;
  Eigen::Vector3d normal;  // unit, (v1 - v0) x (v2 - v0) direction; zero for a needle
  Eigen::Vector3d centre;  // bounding ball: centroid ...
  double radius = 0.0;     // ... and the largest corner distance (plus a rounding margin)
};

Triangle make_triangle(const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                       const Eigen::Vector3d& c) {
  Triangle tri;
  tri.v = {a, b, c};
  const Eigen::Vector3d cross = (b - a).cross(c - a);
  const double max_edge2 =
      std::max({(b - a).squaredNorm(), (c - b).squaredNorm(), (a - c).squaredNorm()});
  // A needle (area below 1e-14 of the longest edge squared) has no interior prism: its edge
  // capsules hold its whole Minkowski sum (to 1e-14 of its size).
  tri.normal = cross.squaredNorm() > 1e-28 * max_edge2 * max_edge2 ? cross.normalized()
                                                                   : Eigen::Vector3d::Zero();
  tri.centre = (a + b + c) / 3.0;
  tri.radius = std::sqrt(std::max({(a - tri.centre).squaredNorm(), (b - tri.centre).squaredNorm(),
                                   (c - tri.centre).squaredNorm()})) *
               (1.0 + 1e-12);
  return tri;
}

// Largest root of a t^2 + 2 h t + c = 0 (a > 0), or nothing; cancellation-free.
std::optional<double> largest_root(double a, double h, double c) {
  const double disc = h * h - a * c;
  if (disc < 0.0) return std::nullopt;
  const double s = std::sqrt(disc);
  return h <= 0.0 ? (-h + s) / a : c / (-h - s);
}

// Clips [lo, hi] by the constraint g0 + t g1 >= 0.
void clip(double g0, double g1, double* lo, double* hi) {
  if (g1 > 0.0) {
    *lo = std::max(*lo, -g0 / g1);
  } else if (g1 < 0.0) {
    *hi = std::min(*hi, -g0 / g1);
  } else if (g0 < 0.0) {
    *lo = kInfinity;
  }
}

// The largest t with dist(p + t n, triangle) <= R if it exceeds `floor`; -infinity otherwise
// (also when the line never comes within R).
double last_contact(const Triangle& tri, const Eigen::Vector3d& p, const Eigen::Vector3d& n,
                    double R, double floor) {
  double best = -kInfinity;
  const Eigen::Vector3d edge[3] = {tri.v[1] - tri.v[0], tri.v[2] - tri.v[1], tri.v[0] - tri.v[2]};
  if (tri.normal.squaredNorm() > 0.0) {
    // The whole Minkowski sum lies in the slab |(O - v0).m| <= R: its exit bounds every piece.
    const Eigen::Vector3d& m = tri.normal;
    const double s0 = (p - tri.v[0]).dot(m), sn = n.dot(m);
    double lo = -kInfinity, hi = kInfinity;
    clip(R + s0, sn, &lo, &hi);
    clip(R - s0, -sn, &lo, &hi);
    if (lo > hi || hi <= floor) return -kInfinity;
    const double slab_exit = hi;
    // Prism over the interior: O also projects into the triangle (inward edge normals m x e_k,
    // the corners being counter-clockwise about m).
    for (int k = 0; k < 3 && lo <= hi; ++k) {
      const Eigen::Vector3d q = m.cross(edge[k]);
      clip((p - tri.v[k]).dot(q), n.dot(q), &lo, &hi);
    }
    if (lo <= hi) {
      // Leaving through the slab's face above the interior is leaving the (convex) Minkowski
      // sum: that is the answer. Otherwise the line leaves through an edge's or corner's part.
      if (hi == slab_exit) return hi;
      best = hi;
    }
  }
  // Edge cylinders: |(w + t n)_perp|^2 = R^2, w = p - u0, perp = component normal to the edge;
  // valid where the closest edge point is inside the edge (0 <= u <= 1).
  for (int k = 0; k < 3; ++k) {
    const Eigen::Vector3d& d = edge[k];
    const double dd = d.squaredNorm();
    if (dd == 0.0) continue;
    const Eigen::Vector3d w = p - tri.v[k];
    const double wd = w.dot(d), nd = n.dot(d);
    const Eigen::Vector3d w_perp = w - (wd / dd) * d;
    const Eigen::Vector3d n_perp = n - (nd / dd) * d;
    const double a = n_perp.squaredNorm();
    if (a < 1e-24) continue;  // line parallel to the edge: the balls hold its last contact
    if (const auto t = largest_root(a, w_perp.dot(n_perp), w_perp.squaredNorm() - R * R)) {
      const double u = (wd + *t * nd) / dd;
      if (u >= 0.0 && u <= 1.0) best = std::max(best, *t);
    }
  }
  // Corner balls: |w + t n|^2 = R^2.
  for (int k = 0; k < 3; ++k) {
    const Eigen::Vector3d w = p - tri.v[k];
    if (const auto t = largest_root(1.0, w.dot(n), w.squaredNorm() - R * R)) {
      best = std::max(best, *t);
    }
  }
  return best > floor ? best : -kInfinity;
}

// Point of the triangle closest to x (Ericson, Real-Time Collision Detection, §5.1.5).
Eigen::Vector3d closest_point(const Corners& tri, const Eigen::Vector3d& x) {
  const Eigen::Vector3d &a = tri[0], &b = tri[1], &c = tri[2];
  const Eigen::Vector3d ab = b - a, ac = c - a, ap = x - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0.0 && d2 <= 0.0) return a;
  const Eigen::Vector3d bp = x - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0.0 && d4 <= d3) return b;
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) return a + (d1 / (d1 - d3)) * ab;
  const Eigen::Vector3d cp = x - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0.0 && d5 <= d6) return c;
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) return a + (d2 / (d2 - d6)) * ac;
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0) {
    return b + ((d4 - d3) / ((d4 - d3) + (d5 - d6))) * (c - b);
  }
  const double denominator = 1.0 / (va + vb + vc);
  return a + ab * (vb * denominator) + ac * (vc * denominator);
}

struct Sweep {
  Eigen::Vector3d p, n;
  double R, t_min, t_max;
};

// Best contact so far, and the test of one triangle. A triangle whose contact interval lies
// wholly above t_max is outside the window; one that the sphere touches at t_max is kept (it
// makes the result touching_at_t_max).
struct Best {
  double t = -kInfinity;
  int face = -1;
  void consider(const std::vector<Triangle>& triangles, int face_index, const Sweep& s) {
    const Triangle& tri = triangles[face_index];
    // Cheap rejection: the sphere cannot touch the triangle above t if it cannot touch the
    // triangle's bounding ball above t.
    const Eigen::Vector3d w = s.p - tri.centre;
    const double reach = tri.radius + s.R;
    const auto t_ball = largest_root(1.0, w.dot(s.n), w.squaredNorm() - reach * reach);
    if (!t_ball || !(*t_ball > t)) return;
    const double t_face = last_contact(tri, s.p, s.n, s.R, t);
    if (!(t_face > t)) return;
    if (t_face > s.t_max) {
      const Eigen::Vector3d o = s.p + s.t_max * s.n;
      if ((closest_point(tri.v, o) - o).norm() > s.R) return;
    }
    t = t_face, face = face_index;
  }
};

// Traversal traits for AABB_tree::traversal_with_priority (the interface of CGAL's own
// traits in CGAL/AABB_tree/internal/AABB_traversal_traits.h).
class SweepTraversal {
 public:
  using Priority = double;
  explicit SweepTraversal(const std::vector<Triangle>& triangles) : triangles_(triangles) {}

  bool go_further() const { return true; }
  void intersection(const Sweep& s, const Primitive& primitive) {
    best_.consider(triangles_, static_cast<int>(primitive.id().idx()), s);
  }
  template <class Node>
  bool do_intersect(const Sweep& s, const Node& node) const {
    return do_intersect_with_priority(s, node).first;
  }
  // Does O(t) for t in [max(t_min, best), t_max] come within R of the node's box (slab test on
  // the box grown by R, which contains the Minkowski sum of every triangle in it with the
  // ball)? Priority: the largest such t.
  template <class Node>
  std::pair<bool, double> do_intersect_with_priority(const Sweep& s, const Node& node) const {
    const CGAL::Bbox_3& box = node.bbox();
    double lo = std::max(s.t_min, best_.t), hi = s.t_max;
    for (int axis = 0; axis < 3 && lo <= hi; ++axis) {
      const double low = box.min(axis) - s.R, high = box.max(axis) + s.R;
      const double p = s.p[axis], n = s.n[axis];
      if (n == 0.0) {
        if (p < low || p > high) return {false, 0.0};
        continue;
      }
      double t0 = (low - p) / n, t1 = (high - p) / n;
      if (t0 > t1) std::swap(t0, t1);
      lo = std::max(lo, t0);
      hi = std::min(hi, t1);
    }
    return {lo <= hi, hi};
  }
  const Best& best() const { return best_; }

 private:
  const std::vector<Triangle>& triangles_;
  Best best_;
};

// Barycentric coordinates of x (a point of the triangle's plane) in the triangle.
Eigen::Vector3d barycentric(const Corners& tri, const Eigen::Vector3d& x) {
  const Eigen::Vector3d v0 = tri[1] - tri[0], v1 = tri[2] - tri[0], v2 = x - tri[0];
  const double d00 = v0.dot(v0), d01 = v0.dot(v1), d11 = v1.dot(v1);
  const double d20 = v2.dot(v0), d21 = v2.dot(v1);
  const double det = d00 * d11 - d01 * d01;
  if (det <= 0.0) return {1.0 / 3, 1.0 / 3, 1.0 / 3};  // degenerate: the mean normal
  const double b1 = (d11 * d20 - d01 * d21) / det, b2 = (d00 * d21 - d01 * d20) / det;
  return {1.0 - b1 - b2, b1, b2};
}

struct VertexNormals {
  std::vector<std::array<int, 3>> face_vertices;
  std::vector<Eigen::Vector3d> normals;
};

MeshContactResult make_result(const std::vector<Triangle>& triangles, const VertexNormals& vn,
                              const Best& best, const Sweep& s) {
  MeshContactResult r;
  if (best.face < 0 || best.t < s.t_min) return r;
  r.t = best.t;
  r.face = best.face;
  r.centre = s.p + best.t * s.n;
  const Corners& tri = triangles[best.face].v;
  r.contact = closest_point(tri, r.centre);
  // The smoothed contact X = O - R nu(X), nu interpolated where X itself lies. Taking nu at the
  // facet point instead (one pass) leaves an error first order in h: the facet point sits
  // R |m_facet - n| = O(R kappa h) away from the contact along the surface, and nu there is off
  // by kappa times that, an O(R^2 kappa^2 h) error in X (1.7 nm at h = 0.025 mm on P1's flanks
  // with R = 0.5 mm, where it is larger than the O(h^2) part). Each further pass multiplies that
  // offset by ~R kappa << 1. X stays within a fraction of a micrometre of the facet's plane, so
  // the barycentric coordinates of its projection may step slightly outside the triangle: nu's
  // linear field is then extended (the neighbour's differs by O(h^2) there); farther out (sharp
  // creases of coarse meshes) X is clamped to the triangle.
  const std::array<int, 3>& fv = vn.face_vertices[best.face];
  Eigen::Vector3d x = r.contact;
  for (int pass = 0; pass < 3; ++pass) {
    Eigen::Vector3d w = barycentric(tri, x);
    if (w.minCoeff() < -0.25) w = barycentric(tri, closest_point(tri, x));
    Eigen::Vector3d nu =
        w[0] * vn.normals[fv[0]] + w[1] * vn.normals[fv[1]] + w[2] * vn.normals[fv[2]];
    if (nu.dot(r.centre - r.contact) < 0.0) nu = -nu;
    x = r.centre - s.R * nu.normalized();
  }
  r.smoothed_contact = x;
  r.touching_at_t_max = best.t > s.t_max;
  r.found = !r.touching_at_t_max;
  return r;
}

}  // namespace

struct MeshFlankContact::Impl {
  TriangleMesh mesh;  // the tree's primitives refer to it
  std::vector<Triangle> triangles;
  VertexNormals vertex_normals;
  Tree tree;

  explicit Impl(const TriangleMesh& input) : mesh(input) {
    triangles.resize(mesh.n_faces());
    vertex_normals.face_vertices.resize(mesh.n_faces());
    vertex_normals.normals.assign(mesh.n_vertices(), Eigen::Vector3d::Zero());
    for (const TriangleMesh::FaceHandle f : mesh.faces()) {
      Corners corners;
      int k = 0;
      for (const TriangleMesh::VertexHandle v : mesh.fv_range(f)) {
        if (k < 3) {
          const TriangleMesh::Point& x = mesh.point(v);
          corners[k] = Eigen::Vector3d(x[0], x[1], x[2]);
          vertex_normals.face_vertices[f.idx()][k] = v.idx();
        }
        ++k;
      }
      const Triangle& tri = triangles[f.idx()] = make_triangle(corners[0], corners[1], corners[2]);
      // Angle-weighted vertex normals (Thuermer & Wuethrich, J. Graphics Tools 3(1), 1998).
      if (tri.normal.squaredNorm() == 0.0) continue;
      for (int c = 0; c < 3; ++c) {
        const Eigen::Vector3d a = corners[(c + 1) % 3] - corners[c];
        const Eigen::Vector3d b = corners[(c + 2) % 3] - corners[c];
        const double angle = std::atan2(a.cross(b).norm(), a.dot(b));
        vertex_normals.normals[vertex_normals.face_vertices[f.idx()][c]] += angle * tri.normal;
      }
    }
    for (Eigen::Vector3d& nu : vertex_normals.normals) {
      if (nu.squaredNorm() > 0.0) nu.normalize();
    }
    tree.insert(faces(mesh).first, faces(mesh).second, mesh);
    tree.build();
  }
};

MeshFlankContact::MeshFlankContact(const TriangleMesh& mesh)
    : impl_(std::make_unique<Impl>(mesh)) {}
MeshFlankContact::~MeshFlankContact() = default;
MeshFlankContact::MeshFlankContact(MeshFlankContact&&) noexcept = default;
MeshFlankContact& MeshFlankContact::operator=(MeshFlankContact&&) noexcept = default;

int MeshFlankContact::triangle_count() const { return static_cast<int>(impl_->triangles.size()); }

MeshContactResult MeshFlankContact::first_contact(const Eigen::Vector3d& p,
                                                  const Eigen::Vector3d& n, double R, double t_min,
                                                  double t_max) const {
  const Sweep sweep{p, n.normalized(), R, t_min, t_max};
  SweepTraversal traversal(impl_->triangles);
  impl_->tree.traversal_with_priority(sweep, traversal);
  return make_result(impl_->triangles, impl_->vertex_normals, traversal.best(), sweep);
}

MeshContactResult MeshFlankContact::first_contact_linear_scan(const Eigen::Vector3d& p,
                                                              const Eigen::Vector3d& n, double R,
                                                              double t_min, double t_max) const {
  const Sweep sweep{p, n.normalized(), R, t_min, t_max};
  Best best;
  for (int f = 0; f < static_cast<int>(impl_->triangles.size()); ++f) {
    best.consider(impl_->triangles, f, sweep);
  }
  return make_result(impl_->triangles, impl_->vertex_normals, best, sweep);
}

std::optional<double> sphere_triangle_last_contact(const Eigen::Vector3d& a,
                                                   const Eigen::Vector3d& b,
                                                   const Eigen::Vector3d& c,
                                                   const Eigen::Vector3d& p,
                                                   const Eigen::Vector3d& n, double R) {
  const double t = last_contact(make_triangle(a, b, c), p, n.normalized(), R, -kInfinity);
  if (t == -kInfinity) return std::nullopt;
  return t;
}

MeshCheck check_mesh(const TriangleMesh& mesh, bool check_self_intersection) {
  MeshCheck check;
  check.valid = CGAL::is_valid_polygon_mesh(mesh);
  if (!check.valid) return check;
  check.triangles = CGAL::is_triangle_mesh(mesh);
  check.closed = CGAL::is_closed(mesh);
  if (check.triangles) {
    check.area_mm2 = PMP::area(mesh);
    if (check.closed) {
      check.volume_mm3 = PMP::volume(mesh);
      check.outward_oriented = PMP::is_outward_oriented(mesh);
    }
    if (check_self_intersection) check.self_intersecting = PMP::does_self_intersect(mesh);
  }
  return check;
}

}  // namespace gearmc
