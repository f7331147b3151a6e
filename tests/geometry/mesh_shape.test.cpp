// Mesh signed distance fields: a box mesh against grip's analytic box, an icosphere against the
// sphere within its sag, the hierarchy against a loop over all triangles, the pseudo-normal sign
// against the exact winding number, the fast winding number within its error, the winding
// view, no heap per query, and the shipped meshes' volumes against independent estimates.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include <grip/geometry/mesh_io.hpp>
#include <grip/geometry/mesh_shape.hpp>
#include <grip/geometry/shape.hpp>

#include "geometry/mesh_test_support.hpp"
#include "support/allocation_counter.hpp"
#include "support/constants.hpp"
#include "support/tolerance.hpp"

template class grip::MeshShape<double, 16, 32>;
template class grip::MeshShape<float, 16, 32>;

namespace mesh_shape_test {

using namespace grip;
using grip_mesh_test::load;
using grip_mesh_test::Soup;
using grip_mesh_test::u01;
using grip_mesh_test::uniform;
using grip_mesh_test::unit_vector;
using grip_mesh_test::V3;
using grip_test::pi;

namespace {
constexpr int max_v = 4096, max_t = 8192;
template <class S>
using Mesh = TriangleMesh<S, max_v, max_t>;
template <class S>
using Field = MeshShape<S, max_v, max_t>;

template <class S>
Mesh<S>& mesh_a() {
  static Mesh<S> m;  // large: static storage
  return m;
}
template <class S>
Field<S>& field_a() {
  static Field<S> f;
  return f;
}

/// A random point on a random triangle of m, with barycentrics pushed towards edges and
/// vertices one time in three each.
template <class S>
Vector3<S> surface_point(const Mesh<S>& m, std::mt19937& g, int& t) {
  t = static_cast<int>(u01(g) * m.triangle_count());
  double a = u01(g), b = u01(g);
  if (a + b > 1) a = 1 - a, b = 1 - b;
  const int mode = static_cast<int>(g() % 3);
  if (mode == 1) b = 1e-7 * u01(g);                     // near edge ab
  if (mode == 2) a = 1e-7 * u01(g), b = 1e-7 * u01(g);  // near vertex a
  const std::array<int, 3>& tri = m.triangle(t);
  const Vector3<double> p0 = m.vertex(tri[0]).template cast<double>(), p1 = m.vertex(tri[1]).template cast<double>(),
                        p2 = m.vertex(tri[2]).template cast<double>();
  return (p0 + a * (p1 - p0) + b * (p2 - p0)).template cast<S>();
}

/// Brute force: the least distance over all triangles, by the tests' own point-triangle
/// distance (plain doubles).
double brute_distance(const std::vector<std::array<double, 9>>& tris, const V3& p) {
  double best = std::numeric_limits<double>::infinity();
  for (const auto& c : tris) best = std::min(best, grip_mesh_test::triangle_distance2(p.data(), &c[0], &c[3], &c[6]));
  return std::sqrt(best);
}

/// The condition of the exact winding number at p: the sum over the triangles of 1 + L / d (L
/// the triangle's longest edge, d its distance from p), each solid angle's atan2 arguments'
/// condition (see the pyramid's case below). Times u, it bounds the sum's rounding (k = 1 per
/// triangle).
double winding_condition(const std::vector<std::array<double, 9>>& tris, const V3& p) {
  double sum = 0;
  for (const auto& c : tris) {
    const V3 a(c[0], c[1], c[2]), b(c[3], c[4], c[5]), d(c[6], c[7], c[8]);
    const double L = std::max({(b - a).norm(), (d - b).norm(), (a - d).norm()});
    sum += 1 + L / std::sqrt(grip_mesh_test::triangle_distance2(p.data(), &c[0], &c[3], &c[6]));
  }
  return sum;
}

/// The largest vertex norm: the mesh's size in the round-off of a distance.
double extent(const std::vector<std::array<double, 9>>& tris) {
  double m = 0;
  for (const auto& c : tris)
    for (std::size_t k = 0; k < 3; ++k) m = std::max(m, V3(c[3 * k], c[3 * k + 1], c[3 * k + 2]).norm());
  return m;
}
}  // namespace

TEST_CASE_TEMPLATE("a square pyramid (6 triangles: a padded block): hierarchy, far field and distance", S, double,
                   float) {
  // Base [-a, a]^2 at z = 0, apex (0, 0, h). Its triangle count is not a multiple of 4, so the
  // last block of the SIMD distance pass is padded.
  const double a = 0.02, h = 0.03;
  Soup soup;
  soup.v = {V3(-a, -a, 0), V3(a, -a, 0), V3(a, a, 0), V3(-a, a, 0), V3(0, 0, h)};
  soup.t = {{0, 2, 1}, {0, 3, 2}, {0, 1, 4}, {1, 2, 4}, {2, 3, 4}, {3, 0, 4}};  // outward
  static TriangleMesh<S, 16, 16> m;
  static MeshShape<S, 16, 16> f;
  REQUIRE(load(soup, m).ok());
  CHECK(f.mesh() == nullptr);
  REQUIRE(f.build(m) == Status::Ok);
  CHECK(f.mesh() == &m);
  REQUIRE(f.node_count() >= 1);
  CHECK(f.quad_count() >= 1);
  // The leaves hold the 6 triangles, 1 to 4 each; the root's box is the pyramid's.
  int held = 0;
  for (int i = 0; i < f.node_count(); ++i) {
    const auto& node = f.node(i);
    CHECK(node.count <= 4);
    held += node.count;
  }
  CHECK(held == 6);
  // Tolerances from round-off (support/tolerance.hpp). The root's box: each coordinate a
  // vertex's, rounded once to S: at most u |(a, a, h)| (k = 1).
  const double corner = V3(a, a, h).norm();
  CHECK((f.node(0).lo.template cast<double>() - V3(-a, -a, 0)).norm() <= grip_test::roundoff<S>(1, 1, corner));
  CHECK((f.node(0).hi.template cast<double>() - V3(a, a, h)).norm() <= grip_test::roundoff<S>(1, 1, corner));
  // Far field of the root, by hand: area 4 a^2 + 4 a sqrt(h^2 + a^2); a closed surface's
  // area-weighted normals sum to zero.
  const auto& root = f.winding_node(0);
  const double area = 4 * a * a + 4 * a * std::sqrt(h * h + a * a);
  // Each of the 6 triangles' |cross| / 2 and cross / 2 from coordinates rounded to S (2 u of
  // the area), the cross product's and the norm's roundings, then the sum: k = 16 of the area.
  CHECK(std::abs(double(root.area) - area) <= grip_test::roundoff<S>(16, 1, area));
  CHECK(double(root.normal_sum.norm()) <= grip_test::roundoff<S>(16, 1, area));
  // Distances against the tests' own point-triangle distance; the sign from the winding number.
  const std::vector<std::array<double, 9>> tris = grip_mesh_test::plain_triangles(m);
  const auto view = winding_signed(f, true);
  std::mt19937 g(57);
  int inside = 0;
  for (int i = 0; i < 200; ++i) {
    const V3 p(uniform(g, -0.03, 0.03), uniform(g, -0.03, 0.03), uniform(g, -0.01, 0.04));
    const double expect = brute_distance(tris, p);
    if (expect < 1e-4) continue;  // the sign is decided well away from the surface
    const bool in = p.z() > 0 && std::max(std::abs(p.x()), std::abs(p.y())) < a * (1 - p.z() / h);
    const Vector3<S> q = p.cast<S>();
    // The distance |p - q|: q's coordinates carry a couple of roundings of M, the largest
    // coordinate vector (p's and the vertices' rounding to S, the closest point's
    // interpolation), p - q and its norm a few of d <= 2 M: k = 8 u M (observed 1.5 u M).
    const double M = std::max(p.norm(), corner), tol_d = grip_test::roundoff<S>(8, 1, M);
    CHECK(std::abs(double(f.distance(q)) - (in ? -expect : expect)) <= tol_d);
    CHECK(std::abs(double(view.distance(q)) - (in ? -expect : expect)) <= tol_d);
    // The winding number: 6 solid angles (each within 2 u of 2 pi, as in triangle.test.cpp,
    // times the condition 1 + L / d of atan2's arguments at distance d from a triangle of
    // edges up to L = 2 sqrt(2) a) summed, over 4 pi: k = 1 per triangle.
    const double cond_w = 1 + 2 * std::sqrt(2.0) * a / expect;
    CHECK(std::abs(double(f.winding_number_exact(q)) - (in ? 1.0 : 0.0)) <= grip_test::roundoff<S>(1, cond_w, 6));
    inside += in ? 1 : 0;
  }
  CHECK(inside > 5);
}

TEST_CASE_TEMPLATE("a box mesh's signed distance is grip's analytic box SDF", S, double, float) {
  Mesh<S>& m = mesh_a<S>();
  Field<S>& f = field_a<S>();
  const V3 h(0.05, 0.04, 0.03), c(0.01, -0.02, 0.005);
  REQUIRE(load(grip_mesh_test::box_soup(h, c), m).ok());
  REQUIRE(f.build(m) == Status::Ok);
  const ShapePrimitive<S> box = make_box<S>(h.cast<S>(), c.cast<S>());
  std::mt19937 g(31);
  for (int i = 0; i < 1500; ++i) {
    V3 p;
    if (i % 3 == 0) {  // anywhere around the box
      p = c + V3(uniform(g, -2, 2) * h.x(), uniform(g, -2, 2) * h.y(), uniform(g, -2, 2) * h.z());
    } else {  // near a corner or an edge: a corner plus a small offset, one axis free on edges
      V3 corner = c;
      for (int k = 0; k < 3; ++k) corner(k) += (g() & 1) ? h(k) : -h(k);
      p = corner + V3(uniform(g, -4e-3, 4e-3), uniform(g, -4e-3, 4e-3), uniform(g, -4e-3, 4e-3));
      const int axis = static_cast<int>(g() % 3);
      if (i % 3 == 2) p(axis) = c(axis) + uniform(g, -0.02, 0.02);
    }
    const Vector3<S> ps = p.cast<S>();
    Vector3<S> nm = Vector3<S>::Zero(), nb = nm;
    const S dm = f.distance(ps, nm), db = box.distance(ps, nb);
    CAPTURE(i);
    // Both distances from the same point in S: p - c, the box's half sizes or the mesh's
    // vertices (c +- h rounded to S), a closest point and a norm, a couple of roundings of
    // M = |p - c| + |h| (k = 2). Observed at most 0.74 u M (double) and 0.72 u M (float).
    const double M = (p - c).norm() + h.norm();
    CHECK(double(std::abs(dm - db)) <= grip_test::roundoff<S>(2, 1, M));
    // A normalised vector: the norm's and the division's roundings (k = 6 of 1). Observed at
    // most 2 u in both types.
    CHECK(double(std::abs(nm.norm() - S(1))) <= grip_test::roundoff<S>(6, 1, 1));
    // Compare normals where the analytic gradient is unique (not on the inner medial planes).
    const Vector3<S> e = (ps - c.cast<S>()).cwiseAbs() - h.cast<S>();
    Vector3<S> sorted = e;
    std::sort(sorted.data(), sorted.data() + 3);
    // The mesh's normal is (p - q) / |d|, q its closest point, whose coordinates carry a few
    // roundings of M each: the direction's error is about u M / |d| across it, plus the
    // normalisation's few u: k = 8 of u (1 + M / |d|). One more term where the closest point
    // is not unique at round-off: outside, above a face and s0 inside one of its edges, the
    // neighbouring face's closest point (on that edge) is only s0^2 / (2 d) farther, and
    // where that is below the distances' round-off eps (k = 4 of u M: two distances of k = 2)
    // the search may take either; their normals differ by s0 / d <= sqrt(2 eps / d). The
    // float case met: 13 mm above the top face and 3.7 um inside its edge (5e-10 m farther,
    // normals 2.7e-4 apart). Observed at most 0.24 (double) and 0.28 (float) of the bound.
    if (db > S(0) || sorted(2) - sorted(1) > S(1e-4)) {
      const double dist = std::abs(double(db));
      double bound = grip_test::roundoff<S>(8, 1 + M / dist, 1);
      const Eigen::Vector3d ed = e.template cast<double>();
      if (db > S(0) && (ed.array() > 0.0).count() == 1) {  // the face region of a face
        double s0 = 1e300;
        for (int k = 0; k < 3; ++k)
          if (ed(k) <= 0.0) s0 = std::min(s0, -ed(k));
        const double eps_d = grip_test::roundoff<S>(4, 1, M);
        if (s0 * s0 <= 2 * dist * eps_d) bound += std::sqrt(2 * eps_d / dist);
      }
      CHECK(double((nm - nb).norm()) <= bound);
    }
  }
}

TEST_CASE_TEMPLATE("an icosphere's signed distance is the sphere's within the tessellation's sag", S, double, float) {
  Mesh<S>& m = mesh_a<S>();
  Field<S>& f = field_a<S>();
  const double R = 0.04;
  const Soup s = grip_mesh_test::sphere_soup(3, R);
  REQUIRE(load(s, m).ok());
  REQUIRE(f.build(m) == Status::Ok);
  // The polyhedron lies between the sphere and the ball of radius R - sag, sag = R - the least
  // distance from the centre to a face plane (all vertices on the sphere).
  double sag = 0;
  for (const auto& t : s.t) {
    const V3 n = (s.v[static_cast<std::size_t>(t[1])] - s.v[static_cast<std::size_t>(t[0])])
                     .cross(s.v[static_cast<std::size_t>(t[2])] - s.v[static_cast<std::size_t>(t[0])])
                     .normalized();
    sag = std::max(sag, R - std::abs(n.dot(s.v[static_cast<std::size_t>(t[0])])));
  }
  CHECK(sag < 1e-3);
  std::mt19937 g(32);
  for (int i = 0; i < 400; ++i) {
    const V3 p = unit_vector(g) * uniform(g, 0, 2.5 * R);
    const double exact = p.norm() - R;
    const double d = double(f.distance(p.cast<S>()));
    // The bracket holds exactly for the double vertices; p's and the vertices' rounding to S
    // and the distance's own few roundings move d by a few u of M = |p| + R: k = 8. Observed
    // at least 94 u M (float) and 5e10 u M (double) inside either side: the sag dominates,
    // and k = 8 only keeps the bracket from failing on rounding.
    const double tol = grip_test::roundoff<S>(8, 1, p.norm() + R);
    CHECK(d >= exact - tol);
    CHECK(d <= exact + sag + tol);
  }
  CHECK(m.volume() <= S(4.0 / 3 * pi * R * R * R));
  CHECK(m.volume() >= S(4.0 / 3 * pi * std::pow(R - sag, 3)));
}

TEST_CASE_TEMPLATE("the hierarchy's distance equals a loop over all triangles, its sign the winding number's", S,
                   double, float) {
  Mesh<S>& m = mesh_a<S>();
  Field<S>& f = field_a<S>();
  // A star-shaped blob with concave dents (320 triangles: the brute force is O(T) per point).
  REQUIRE(load(grip_mesh_test::sphere_soup(2, 0, V3::Zero(), true), m).ok());
  REQUIRE(f.build(m) == Status::Ok);
  std::mt19937 g(33);
  // Fewer points in float: a count of samples (each a brute-force loop over the triangles), not
  // a tolerance.
  const int n = std::is_same<S, double>::value ? 1500 : 500;
  const std::vector<std::array<double, 9>> tris = grip_mesh_test::plain_triangles(m);
  const double size = extent(tris);
  for (int i = 0; i < n; ++i) {
    Vector3<S> p;
    if (i % 2 == 0) {
      p = V3(uniform(g, -0.05, 0.05), uniform(g, -0.05, 0.05), uniform(g, -0.05, 0.05)).cast<S>();
    } else {
      int t = 0;
      p = surface_point(m, g, t) + (unit_vector(g) * uniform(g, 0, 0.01)).cast<S>();
    }
    const S d = f.distance(p);
    // Both from the same S vertices and point: the hierarchy's closest point, difference and
    // norm in S against the brute force in double, a few roundings of M = |p| + the mesh's
    // size: k = 4. Observed at most 1.25 u M (double) and 0.71 u M (float).
    const double M = double(p.norm()) + size;
    CHECK(std::abs(std::abs(double(d)) - brute_distance(tris, p.template cast<double>())) <=
          grip_test::roundoff<S>(4, 1, M));
  }
  // The sign against the exact winding number, at points within 1e-6 of the surface, near its
  // edges and vertices, and at random points (fewer in float: a count of samples).
  const double deltas[] = {1e-6, 1e-4, 3e-3};
  int inside = 0, outside = 0;
  for (int i = 0; i < (std::is_same<S, double>::value ? 300 : 150); ++i) {
    int t = 0;
    Vector3<S> p;
    if (i % 4 == 3) {
      p = V3(uniform(g, -0.05, 0.05), uniform(g, -0.05, 0.05), uniform(g, -0.05, 0.05)).cast<S>();
    } else {
      p = surface_point(m, g, t) + (unit_vector(g) * deltas[i % 3]).template cast<S>();
    }
    const S w = f.winding_number_exact(p);
    const S d = f.distance(p);
    // On the surface to rounding (the distance's k = 4 u M above): the sign is undecided there.
    const V3 pd = p.template cast<double>();
    if (double(std::abs(d)) <= grip_test::roundoff<S>(4, 1, pd.norm() + size)) continue;
    CAPTURE(i);
    CHECK((w > S(0.5)) == (d < S(0)));
    // The exact winding number's rounding: k = 1 per triangle times its condition 1 + L / d
    // (winding_condition). Observed at most 0.08 (double) and 0.053 (float) of it: the
    // condition is a worst case per triangle.
    CHECK(double(std::abs(w - std::round(w))) <= grip_test::roundoff<S>(1, winding_condition(tris, pd), 1));
    (d < S(0) ? inside : outside) += 1;
  }
  CHECK(inside > 30);
  CHECK(outside > 30);
}

TEST_CASE_TEMPLATE("a lane's closest point is closest_point_on_triangle's, to rounding, with its feature", S, double,
                   float) {
  // The hierarchy's closest point comes from the lane formulas of its leaf blocks
  // (TriangleBlock::closest); the reference is the region-by-region closest_point_on_triangle
  // (triangle.test.cpp). Points are drawn around each triangle, every region reached.
  std::mt19937 g(36);
  int features[7] = {0, 0, 0, 0, 0, 0, 0};
  for (int trial = 0; trial < 400; ++trial) {
    V3 v[3];
    for (V3& x : v) x = V3(uniform(g, -0.05, 0.05), uniform(g, -0.05, 0.05), uniform(g, -0.05, 0.05));
    if ((v[1] - v[0]).cross(v[2] - v[0]).norm() < 1e-4) continue;
    const Vector3<S> a = v[0].cast<S>(), b = v[1].cast<S>(), c = v[2].cast<S>();
    detail::TriangleBlock<S> block;
    block.set(0, a, b, c, 7);
    block.pad(1);
    const Vector3<S> p = V3(uniform(g, -0.08, 0.08), uniform(g, -0.08, 0.08), uniform(g, -0.08, 0.08)).cast<S>();
    Vector3<S> q, r;
    TriangleFeature f = TriangleFeature::Face, h = TriangleFeature::Face;
    const S d2 = block.closest(0, p, q, f);
    const S e2 = closest_point_on_triangle(p, a, b, c, r, h);
    // Both from the same data, k = 8 roundings of values of size M (the coordinates).
    const double M = 0.2, tol = grip_test::roundoff<S>(8, 1, M);
    CHECK((q - r).template cast<double>().norm() <= tol);
    CHECK(std::abs(double(d2) - double(e2)) <= tol * M);
    CHECK(std::abs(double((p - q).squaredNorm()) - double(d2)) <= tol * M);
    CHECK(f == h);  // random points lie off the regions' boundaries
    ++features[static_cast<int>(f)];
  }
  for (int k = 0; k < 7; ++k) CHECK(features[k] > 5);
  // On a vertex and on an edge: that feature, not the face (the sign needs its pseudo-normal).
  detail::TriangleBlock<S> block;
  const Vector3<S> a(S(0), S(0), S(0)), b(S(0.01), S(0), S(0)), c(S(0), S(0.01), S(0));
  block.set(0, a, b, c, 0);
  block.pad(1);
  Vector3<S> q;
  TriangleFeature f = TriangleFeature::Face;
  CHECK(block.closest(0, b, q, f) == S(0));
  CHECK(f == TriangleFeature::VertexB);
  CHECK(block.closest(0, Vector3<S>(S(0.005), S(0.005), S(0)), q, f) == doctest::Approx(0.0).epsilon(1e-12));
  CHECK(f == TriangleFeature::EdgeBC);
}

TEST_CASE_TEMPLATE("the narrow phase's queries: bounded distance with any hint, segment to a hinted triangle", S,
                   double, float) {
  Mesh<S>& m = mesh_a<S>();
  Field<S>& f = field_a<S>();
  REQUIRE(load(grip_mesh_test::sphere_soup(2, 0, V3::Zero(), true), m).ok());
  REQUIRE(f.build(m) == Status::Ok);
  std::mt19937 g(35);
  const std::vector<std::array<double, 9>> tris = grip_mesh_test::plain_triangles(m);
  const double size = extent(tris);
  int hits = 0, misses = 0;
  int hint = -1;
  for (int i = 0; i < 600; ++i) {
    int t = 0;
    const Vector3<S> p = surface_point(m, g, t) + (unit_vector(g) * uniform(g, 0, 0.02)).cast<S>();
    const double exact = brute_distance(tris, p.template cast<double>());
    const double limit = uniform(g, 0, 0.02);
    if (std::abs(limit - exact) < 1e-6) continue;  // too near the limit to say which side
    if (i % 3 == 0) hint = -1;                     // no hint, a stale one, or (every 7th) one naming no triangle
    if (i % 7 == 0) hint = 1 << 20;
    S phi = S(7);
    Vector3<S> n = Vector3<S>::Zero(), n_full;
    const bool found = f.distance_within(p, S(limit), phi, n, hint);
    CHECK(found == (exact < limit));  // the surface within the limit, whatever the hint
    if (!found) {
      CHECK(phi == S(7));  // untouched
      ++misses;
      continue;
    }
    ++hits;
    const double M = double(p.norm()) + size;
    CHECK(std::abs(double(phi) - double(f.distance(p, n_full))) <= grip_test::roundoff<S>(4, 1, M));
    CHECK(std::abs(std::abs(double(phi)) - exact) <= grip_test::roundoff<S>(4, 1, M));
    // The hint now names p's nearest triangle: the segment from p to a point 5 mm away starts
    // on p's distance, and its least squared distance to that triangle is no larger.
    REQUIRE(hint >= 0);
    const Vector3<S> q = p + (unit_vector(g) * 0.005).cast<S>();
    S u = S(-1);
    const S d2 = f.segment_distance2(hint, p, q, u);
    CHECK(double(d2) <= double(phi * phi) + grip_test::roundoff<S>(16, 1, M * M));
    CHECK(u >= S(0));
    CHECK(u <= S(1));
    CHECK(std::sqrt(double(d2)) >= brute_distance(tris, (p + u * (q - p)).template cast<double>()) -
                                       grip_test::roundoff<S>(16, 1, M));  // a triangle's distance bounds the mesh's
  }
  CHECK(hits > 100);
  CHECK(misses > 100);
  S u = S(3);
  CHECK(f.segment_distance2(-1, Vector3<S>::Zero(), Vector3<S>::UnitX(), u) == std::numeric_limits<S>::infinity());
  CHECK(u == S(0));
  CHECK(f.segment_distance2(m.triangle_count(), Vector3<S>::Zero(), Vector3<S>::UnitX(), u) ==
        std::numeric_limits<S>::infinity());
}

TEST_CASE_TEMPLATE("the fast winding number stays within its error bound, and the winding view agrees", S, double,
                   float) {
  Mesh<S>& m = mesh_a<S>();
  Field<S>& f = field_a<S>();
  REQUIRE(load(grip_mesh_test::sphere_soup(3, 0, V3::Zero(), true), m).ok());
  REQUIRE(f.build(m) == Status::Ok);
  CHECK(f.far_field() == S(2));
  CHECK(f.set_far_field(S(0.5)) == Status::InvalidInput);
  CHECK(f.set_far_field(std::numeric_limits<S>::quiet_NaN()) == Status::InvalidInput);
  std::mt19937 g(34);
  double worst = 0;
  const auto view = winding_signed(f);
  for (int i = 0; i < (std::is_same<S, double>::value ? 60 : 30); ++i) {  // a count of samples
    Vector3<S> p;
    int t = 0;
    if (i % 2 == 0)
      p = V3(uniform(g, -0.1, 0.1), uniform(g, -0.1, 0.1), uniform(g, -0.1, 0.1)).cast<S>();
    else
      p = surface_point(m, g, t) + (unit_vector(g) * uniform(g, 1e-4, 0.01)).cast<S>();
    S bound = S(0);
    const S fast = f.winding_number(p, bound);
    const S exact = f.winding_number_exact(p);
    CHECK(std::abs(fast - exact) <= bound + S(1e-4));
    CHECK(std::abs(fast - exact) <= S(0.1));  // docs/meshes.md: below 0.06 measured at beta = 2
    worst = std::max(worst, double(std::abs(fast - exact)));
    // The view: the same |d| as the shape, the winding number's side.
    Vector3<S> n1 = Vector3<S>::Zero(), n2 = n1;
    const S d1 = f.distance(p, n1), d2 = view.distance(p, n2);
    CHECK(std::abs(std::abs(d1) - std::abs(d2)) <= S(1e-12));
    CHECK((d2 < S(0)) == (fast >= S(0.5)));
    if (std::abs(d1) > S(1e-6)) {
      CHECK((d1 < S(0)) == (d2 < S(0)));
      CHECK((n1 - n2).norm() <= S(1e-5));
    }
  }
  MESSAGE("largest fast winding number error: " << worst);
  // An infinite far-field factor makes the hierarchy exact.
  REQUIRE(f.set_far_field(std::numeric_limits<S>::infinity()) == Status::Ok);
  const std::vector<std::array<double, 9>> tris = grip_mesh_test::plain_triangles(m);
  for (int i = 0; i < 20; ++i) {
    const Vector3<S> p = V3(uniform(g, -0.1, 0.1), uniform(g, -0.1, 0.1), uniform(g, -0.1, 0.1)).cast<S>();
    S bound = S(1);
    // The same solid angles summed in another order: each sum's rounding (k = 1 per triangle
    // times winding_condition), two of them. Observed 0 in both types (the same order here).
    CHECK(double(std::abs(f.winding_number(p, bound) - f.winding_number_exact(p))) <=
          grip_test::roundoff<S>(2, winding_condition(tris, p.template cast<double>()), 1));
    CHECK(bound == S(0));
  }
  REQUIRE(f.set_far_field(S(2)) == Status::Ok);
  Vector3<S> lo = Vector3<S>::Zero(), hi = lo, vlo = lo, vhi = lo;
  REQUIRE(f.bounding_box(lo, hi));
  REQUIRE(view.bounding_box(vlo, vhi));
  CHECK(lo == vlo);
  CHECK(hi == vhi);
  const auto exact_view = winding_signed(f, true);
  CHECK(exact_view.distance(Vector3<S>::Zero()) < S(0));
}

TEST_CASE_TEMPLATE("mesh distance: no heap per query, and bad points and unbuilt shapes give finite answers", S, double,
                   float) {
  Mesh<S>& m = mesh_a<S>();
  Field<S>& f = field_a<S>();
  REQUIRE(load(grip_mesh_test::sphere_soup(3, 0, V3::Zero(), true), m).ok());
  REQUIRE(f.build(m) == Status::Ok);
  std::mt19937 g(35);
  Vector3<S> pts[64];
  for (Vector3<S>& p : pts) p = V3(uniform(g, -0.06, 0.06), uniform(g, -0.06, 0.06), uniform(g, -0.06, 0.06)).cast<S>();
  S sum = S(0);
  {
    grip_test::NoHeapScope scope;
    for (const Vector3<S>& p : pts) {
      Vector3<S> n = Vector3<S>::Zero();
      sum += f.distance(p, n) + n.x();
    }
    CHECK(scope.allocations() == 0);
  }
  CHECK(std::isfinite(sum));
  // Points that are not finite or beyond max_magnitude: +max_magnitude, a unit normal.
  const S inf = std::numeric_limits<S>::infinity(), nan = std::numeric_limits<S>::quiet_NaN();
  for (const Vector3<S>& p : {Vector3<S>(nan, S(0), S(0)), Vector3<S>(S(0), inf, S(0)),
                              Vector3<S>(S(0), S(0), S(10) * ScalarTraits<S>::max_magnitude)}) {
    Vector3<S> n = Vector3<S>::Zero();
    CHECK(f.distance(p, n) == ScalarTraits<S>::max_magnitude);
    CHECK(std::abs(n.norm() - S(1)) <= S(1e-5));
    CHECK(f.winding_number(p) == S(0));
    CHECK(winding_signed(f).distance(p) == ScalarTraits<S>::max_magnitude);
  }
  // A point on the surface: distance 0 and the pseudo-normal.
  Vector3<S> n = Vector3<S>::Zero();
  const S d0 = f.distance(m.vertex(0), n);
  CHECK(d0 == S(0));
  CHECK((n - m.vertex_normal(0)).norm() <= S(1e-5));
  // Not built: refuses an unfinalized mesh, answers +max_magnitude.
  static Field<S> empty;
  CHECK(empty.distance(Vector3<S>::Zero()) == ScalarTraits<S>::max_magnitude);
  CHECK_FALSE(empty.built());
  Vector3<S> lo = Vector3<S>::Zero(), hi = lo;
  CHECK_FALSE(empty.bounding_box(lo, hi));
  REQUIRE(f.built());
  m.add_vertex(Vector3<S>(S(1), S(1), S(1)));  // changes the mesh: no longer finalized
  CHECK(empty.build(m) == Status::InvalidInput);
  CHECK(empty.mesh() == nullptr);
  // A shape whose mesh changed after build() answers as an unbuilt one.
  CHECK_FALSE(f.built());
  CHECK(f.distance(Vector3<S>::Zero()) == ScalarTraits<S>::max_magnitude);
  CHECK_FALSE(f.bounding_box(lo, hi));
  REQUIRE(m.finalize().ok());  // the extra vertex is unused: still Ok, but a new revision
  CHECK_FALSE(f.built());
  REQUIRE(f.build(m) == Status::Ok);
  CHECK(f.distance(Vector3<S>::Zero()) < S(0));
}

TEST_CASE_TEMPLATE("the shipped meshes: counts, closed, volumes against independent estimates", S, double, float) {
  Mesh<S>& m = mesh_a<S>();
  Field<S>& f = field_a<S>();
  static char buffer[1 << 19];
  const std::string dir = std::string(GRIP_TEST_DATA_DIR) + "/meshes/";
  // The tetrahedron: corners 0, a e_x, a e_y, a e_z with a = 0.05: volume a^3 / 6, and the
  // distance of a point inside from the three faces through the origin.
  MeshReport r = read_mesh_file((dir + "tetrahedron.stl").c_str(), buffer, sizeof buffer, m);
  REQUIRE(r.ok());
  CHECK(r.triangles == 4);
  CHECK(m.volume() == doctest::Approx(0.05 * 0.05 * 0.05 / 6).epsilon(1e-6).scale(0));
  REQUIRE(f.build(m) == Status::Ok);
  CHECK(f.distance(Vector3<S>(S(0.01), S(0.01), S(0.01))) == doctest::Approx(-0.01).epsilon(1e-5).scale(0));
  // The mug: closed, two components, and its volume within the tessellation error of the
  // shape it was made from (tests/data/meshes/make_meshes.py; keep the numbers in step): a
  // profile revolved about z, whose volume is pi |contour integral of r^2 dz| (Green's theorem,
  // Pappus), and a tube of radius 4 mm around an ellipse of semi-axes 10 and 18 mm, whose
  // volume is pi 4^2 times the ellipse's perimeter. The mesh's 40 sectors keep
  // 40 sin(2 pi / 40) / (2 pi) = 99.6% of the body and the 10-gon tube 93.5% of the handle
  // (about -0.8% in all); the rounded rim and bottom edges add less than that.
  r = read_mesh_file((dir + "mug.stl").c_str(), buffer, sizeof buffer, m);
  REQUIRE(r.ok());
  CHECK(r.triangles == 3600);
  CHECK(r.components == 2);
  CHECK_FALSE(r.flipped);
  {
    double contour = 0;  // contour integral of r^2 dz over the profile (mm^3)
    auto segment = [&contour](double r0, double z0, double r1, double z1) {
      contour += (z1 - z0) * (r0 * r0 + r0 * r1 + r1 * r1) / 3;  // exact for a straight segment
    };
    auto arc = [&segment](double cr, double cz, double radius, double a0, double a1) {
      const int n = 2000;
      for (int i = 0; i < n; ++i) {
        const double s0 = (a0 + (a1 - a0) * i / n) * pi / 180, s1 = (a0 + (a1 - a0) * (i + 1) / n) * pi / 180;
        segment(cr + radius * std::cos(s0), cz + radius * std::sin(s0), cr + radius * std::cos(s1),
                cz + radius * std::sin(s1));
      }
    };
    segment(0, 0, 36, 0);     // outer bottom
    arc(36, 4, 4, -90, 0);    // outer bottom edge
    segment(40, 4, 40, 58);   // outer wall
    arc(38, 58, 2, 0, 180);   // rim
    segment(36, 58, 36, 11);  // inner wall
    arc(31, 11, 5, 0, -90);   // inner bottom edge
    segment(31, 6, 0, 6);     // inner bottom; back down the axis (r = 0) adds nothing
    double perimeter = 0;
    for (int i = 0; i < 20000; ++i) {
      const double s0 = 2 * pi * i / 20000, s1 = 2 * pi * (i + 1) / 20000;
      perimeter += std::hypot(10 * (std::cos(s1) - std::cos(s0)), 18 * (std::sin(s1) - std::sin(s0)));
    }
    const double smooth = (pi * std::abs(contour) + pi * 16 * perimeter) * 1e-9;  // m^3
    const double ratio = double(m.volume()) / smooth;
    MESSAGE("mug: mesh volume / smooth shape's = " << ratio);
    CHECK(ratio <= 1.0);
    CHECK(ratio >= 0.98);
  }
  // The blob: closed, and its volume against an estimate of the winding-number inside test:
  // on vertical lines at stratified random (x, y) (one per cell of a grid over the box) the
  // winding number is 0 below the surface and changes by +-1 at each crossing (+1 entering
  // through a face whose normal points down); a line's inside length is where it is >= 1/2,
  // and the volume is the sum of lengths times the cell area. Exact along z, the estimate errs
  // only in the cells a silhouette crosses: about 0.5% here, 1.5% allowed.
  r = read_mesh_file((dir + "blob.obj").c_str(), buffer, sizeof buffer, m);
  REQUIRE(r.ok());
  CHECK(r.triangles == 5120);
  CHECK_FALSE(r.flipped);
  bool closed = true;
  for (int t = 0; t < m.triangle_count(); ++t)
    for (int e = 0; e < 3; ++e) closed = closed && m.neighbour(t, e) >= 0;
  CHECK(closed);
  REQUIRE(f.build(m) == Status::Ok);
  Vector3<S> lo = Vector3<S>::Zero(), hi = lo;
  REQUIRE(f.bounding_box(lo, hi));
  const std::vector<std::array<double, 9>> tri = grip_mesh_test::plain_triangles(m);
  const int cells = std::is_same<S, double>::value ? 32 : 16;  // a count of samples, not a tolerance
  const double dx = double(hi.x() - lo.x()) / cells, dy = double(hi.y() - lo.y()) / cells;
  double volume = 0;
  bool lines_closed = true;
  std::vector<std::pair<double, int>> crossings;
  std::mt19937 g(36);
  for (int i = 0; i < cells; ++i)
    for (int j = 0; j < cells; ++j) {
      const double x = double(lo.x()) + (i + u01(g)) * dx, y = double(lo.y()) + (j + u01(g)) * dy;
      crossings.clear();
      for (const auto& c : tri) {
        // Twice the signed areas of the sub-triangles opposite each vertex, seen from +z.
        const double wa = (c[3] - x) * (c[7] - y) - (c[4] - y) * (c[6] - x);
        const double wb = (c[6] - x) * (c[1] - y) - (c[7] - y) * (c[0] - x);
        const double wc = (c[0] - x) * (c[4] - y) - (c[1] - y) * (c[3] - x);
        const double area = wa + wb + wc;
        if (!((wa > 0 && wb > 0 && wc > 0) || (wa < 0 && wb < 0 && wc < 0))) continue;
        crossings.emplace_back((wa * c[2] + wb * c[5] + wc * c[8]) / area, area < 0 ? +1 : -1);
      }
      std::sort(crossings.begin(), crossings.end());
      int w = 0;
      for (std::size_t q = 0; q < crossings.size(); ++q) {
        w += crossings[q].second;
        if (w >= 1 && q + 1 < crossings.size()) volume += (crossings[q + 1].first - crossings[q].first) * dx * dy;
      }
      lines_closed = lines_closed && w == 0;  // closed: each line leaves as it came
    }
  CHECK(lines_closed);
  MESSAGE("blob: mesh volume / line estimate = " << double(m.volume()) / volume);
  CHECK(std::abs(double(m.volume()) - volume) <= 0.015 * volume);
}

}  // namespace mesh_shape_test
