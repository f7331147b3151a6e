// One triangle: closest points against hand-derived answers, points built inside each feature's
// normal cone, and a brute-force barycentric search; degenerate triangles; solid angles.
#include <doctest/doctest.h>

#include <cmath>
#include <limits>
#include <random>

#include <grip/geometry/triangle.hpp>

#include "geometry/mesh_test_support.hpp"
#include "support/constants.hpp"
#include "support/tolerance.hpp"

namespace triangle_test {

using namespace grip;
using grip_mesh_test::uniform;
using grip_mesh_test::V3;
using grip_test::pi;

namespace {

/// Brute-force squared distance from p to triangle abc: the least over a barycentric grid,
/// then grids of a quarter the step around the best point until the step is below 1e-12
/// (plain doubles; independent of the region logic).
double brute_distance2(const V3& p, const V3& a, const V3& b, const V3& c) {
  const double px = p.x() - a.x(), py = p.y() - a.y(), pz = p.z() - a.z();
  const double ux = b.x() - a.x(), uy = b.y() - a.y(), uz = b.z() - a.z();
  const double vx = c.x() - a.x(), vy = c.y() - a.y(), vz = c.z() - a.z();
  double best = 1e300, bu = 0, bv = 0, h = 1.0 / 32;
  int n = 32;
  double u0 = 0, v0 = 0;
  while (true) {
    for (int i = 0; i <= n; ++i)
      for (int j = 0; j <= n; ++j) {
        double u = std::min(std::max(u0 + h * i, 0.0), 1.0), v = std::min(std::max(v0 + h * j, 0.0), 1.0);
        if (u + v > 1) {  // onto the edge u + v = 1
          const double s = u + v;
          u /= s, v /= s;
        }
        const double dx = px - u * ux - v * vx, dy = py - u * uy - v * vy, dz = pz - u * uz - v * vz;
        const double d = dx * dx + dy * dy + dz * dz;
        if (d < best) best = d, bu = u, bv = v;
      }
    if (h < 1e-12) return best;
    u0 = bu - 2 * h, v0 = bv - 2 * h, h /= 4, n = 16;  // a window of +-2 old steps
  }
}

template <class S>
Vector3<S> cv(const V3& x) {
  return x.cast<S>();
}

}  // namespace

TEST_CASE_TEMPLATE("closest point on a triangle: hand-derived cases for every feature", S, double, float) {
  const Vector3<S> a(S(0), S(0), S(0)), b(S(1), S(0), S(0)), c(S(0), S(1), S(0));
  struct Case {
    Vector3<S> p, q;
    S d2;
    TriangleFeature f;
  };
  const Case cases[] = {
      {Vector3<S>(S(0.25), S(0.25), S(1)), Vector3<S>(S(0.25), S(0.25), S(0)), S(1), TriangleFeature::Face},
      {Vector3<S>(S(0.25), S(0.25), S(-2)), Vector3<S>(S(0.25), S(0.25), S(0)), S(4), TriangleFeature::Face},
      {Vector3<S>(S(-1), S(-1), S(0.5)), a, S(2.25), TriangleFeature::VertexA},
      {Vector3<S>(S(2), S(-1), S(0)), b, S(2), TriangleFeature::VertexB},
      {Vector3<S>(S(-1), S(2), S(0)), c, S(2), TriangleFeature::VertexC},
      {Vector3<S>(S(0.5), S(-1), S(0)), Vector3<S>(S(0.5), S(0), S(0)), S(1), TriangleFeature::EdgeAB},
      {Vector3<S>(S(1), S(1), S(0)), Vector3<S>(S(0.5), S(0.5), S(0)), S(0.5), TriangleFeature::EdgeBC},
      {Vector3<S>(S(-1), S(0.5), S(1)), Vector3<S>(S(0), S(0.5), S(0)), S(2), TriangleFeature::EdgeCA},
  };
  for (const Case& k : cases) {
    Vector3<S> q = Vector3<S>::Zero();
    TriangleFeature f = TriangleFeature::Face;
    const S d2 = closest_point_on_triangle(k.p, a, b, c, q, f);
    // The data are exact in both types (multiples of 1/4, |p| < 2.5): q = a + v ab + w ac and
    // |p - q|^2 take a few roundings each, on coordinates up to 2.5 and d2 up to 4.25. k = 8
    // roundings of the largest value, scale 4.25 for d2 and 2.5 for q.
    const double tol_d2 = grip_test::roundoff<S>(8, 1, 4.25), tol_q = grip_test::roundoff<S>(8, 1, 2.5);
    CHECK(double(std::abs(d2 - k.d2)) <= tol_d2);
    CHECK(double((q - k.q).norm()) <= tol_q);
    CHECK(f == k.f);
  }
  CHECK(feature_edge(TriangleFeature::EdgeBC) == 1);
  CHECK(feature_vertex(TriangleFeature::VertexC) == 2);
  CHECK(feature_edge(TriangleFeature::Face) == -1);
  CHECK(feature_vertex(TriangleFeature::EdgeAB) == -1);
}

TEST_CASE_TEMPLATE("closest point on a triangle: points in every feature's normal cone", S, double, float) {
  // p = q0 + t dir with dir in the normal cone of the feature holding q0: then q0 is the
  // closest point (the cone is exactly that feature's Voronoi region).
  std::mt19937 g(11);
  int checked[7] = {0, 0, 0, 0, 0, 0, 0};
  for (int trial = 0; trial < 300; ++trial) {
    V3 v[3];
    for (V3& x : v) x = V3(uniform(g, -1, 1), uniform(g, -1, 1), uniform(g, -1, 1));
    const V3 n = (v[1] - v[0]).cross(v[2] - v[0]);
    if (n.norm() < 0.2) continue;
    const V3 nh = n.normalized();
    V3 m[3];  // outward in-plane edge normals, edge e from v[e] to v[e + 1]
    for (int e = 0; e < 3; ++e) m[e] = (v[(e + 1) % 3] - v[e]).cross(nh).normalized();
    const int kind = trial % 7;
    V3 q0, dir;
    TriangleFeature expect;
    if (kind == 0) {
      double u = 1, w = 1;
      while (u + w > 0.9) u = uniform(g, 0.05, 0.85), w = uniform(g, 0.05, 0.85);
      q0 = v[0] + u * (v[1] - v[0]) + w * (v[2] - v[0]);
      dir = (g() & 1) ? nh : V3(-nh);
      expect = TriangleFeature::Face;
    } else if (kind <= 3) {
      const int e = kind - 1;
      q0 = v[e] + uniform(g, 0.05, 0.95) * (v[(e + 1) % 3] - v[e]);
      const double th = uniform(g, -1.4, 1.4);
      dir = std::cos(th) * m[e] + std::sin(th) * nh;
      expect = static_cast<TriangleFeature>(1 + e);
    } else {
      const int k = kind - 4;  // vertex k: edges k (leaving) and k - 1 (arriving)
      q0 = v[k];
      const double al = uniform(g, 0.05, 1), be = uniform(g, 0.05, 1), ga = uniform(g, -1, 1);
      dir = (al * m[k] + be * m[(k + 2) % 3]).normalized() * std::sqrt(1 - ga * ga) + ga * nh;
      expect = static_cast<TriangleFeature>(4 + k);
    }
    const V3 p = q0 + uniform(g, 0.01, 2) * dir.normalized();
    Vector3<S> q = Vector3<S>::Zero();
    TriangleFeature f = TriangleFeature::Face;
    const S d2 = closest_point_on_triangle(cv<S>(p), cv<S>(v[0]), cv<S>(v[1]), cv<S>(v[2]), q, f);
    // Tolerances from round-off (support/tolerance.hpp), M the largest |coordinate vector|.
    // d2: rounding p and the vertices to S moves |p - q| (at most 2 M) by up to 2 u M, so d2 by
    // 8 u M^2; |p - q|^2 itself takes 5 roundings of up to 4 M^2 (20 u M^2); the reference
    // p = q0 + t dir is rounded in double: k = 32 u M^2 in all. d2 is of first order only in
    // the part of q's error along p - q; the solve's error in q lies in the feature, across it.
    // q: the barycentric numerators va, vb, vc are differences of products of dot products,
    // of size L^2 R^2 (L the longest edge, R the farthest vertex from p), whose exact values
    // are n . (bp x cp) and the like (Binet-Cauchy), divided by |n|^2, n = ab x ac: the
    // condition (L R / |n|)^2 (1 plus it, for the input rounding), k = 8 roundings of M.
    double M = p.norm(), L = 0, R = 0;
    for (int e = 0; e < 3; ++e)
      M = std::max(M, v[e].norm()), L = std::max(L, (v[(e + 1) % 3] - v[e]).norm()), R = std::max(R, (p - v[e]).norm());
    const double cond = 1 + L * L * R * R / n.squaredNorm();
    CHECK(std::abs(double(d2) - (p - q0).squaredNorm()) <= grip_test::roundoff<S>(32, 1, M * M));
    CHECK((q.template cast<double>() - q0).norm() <= grip_test::roundoff<S>(8, cond, M));
    CHECK(f == expect);
    ++checked[kind];
  }
  for (int k = 0; k < 7; ++k) CHECK(checked[k] > 20);
}

TEST_CASE_TEMPLATE("closest point on a triangle against a brute-force barycentric search", S, double, float) {
  std::mt19937 g(12);
  int regions[7] = {0, 0, 0, 0, 0, 0, 0};
  for (int trial = 0; trial < 120; ++trial) {
    V3 v[3];
    for (V3& x : v) x = V3(uniform(g, -1, 1), uniform(g, -1, 1), uniform(g, -1, 1));
    if ((v[1] - v[0]).cross(v[2] - v[0]).norm() < 0.05) continue;
    const V3 p(uniform(g, -2, 2), uniform(g, -2, 2), uniform(g, -2, 2));
    Vector3<S> q = Vector3<S>::Zero();
    TriangleFeature f = TriangleFeature::Face;
    const S d2 = closest_point_on_triangle(cv<S>(p), cv<S>(v[0]), cv<S>(v[1]), cv<S>(v[2]), q, f);
    const double brute = brute_distance2(p, v[0], v[1], v[2]);
    // The d2 tolerance of the normal-cone test, k = 32 u M^2: the search is in double, its grid
    // reaches each feature exactly (clamped to the edges) and refines to steps below 1e-12,
    // whose error is of second order there (1e-24 M^2). |p - q|^2 recomputed from q: the same
    // input rounding and squared norm.
    double M = p.norm();
    for (const V3& x : v) M = std::max(M, x.norm());
    const double tol = grip_test::roundoff<S>(32, 1, M * M);
    CHECK(std::abs(double(d2) - brute) <= tol);
    CHECK(std::abs((p - q.template cast<double>()).squaredNorm() - double(d2)) <= tol);
    ++regions[static_cast<int>(f)];
  }
  for (int k = 0; k < 7; ++k) CHECK(regions[k] > 0);  // random points reach every region
}

TEST_CASE_TEMPLATE("segment and triangle: the closed form against a search along the segment", S, double, float) {
  // The squared distance from p0 + t (p1 - p0) to the triangle is convex in t (a convex set's
  // distance along a line), so a ternary search in double over t with the point distance
  // (checked above) finds its least value independently of the closed form's case analysis.
  std::mt19937 g(31);
  int ends = 0, inner = 0, crossing = 0;
  for (int trial = 0; trial < 300; ++trial) {
    V3 v[3];
    for (V3& x : v) x = V3(uniform(g, -1, 1), uniform(g, -1, 1), uniform(g, -1, 1));
    if ((v[1] - v[0]).cross(v[2] - v[0]).norm() < 0.05) continue;
    V3 p0(uniform(g, -2, 2), uniform(g, -2, 2), uniform(g, -2, 2)),
        p1(uniform(g, -2, 2), uniform(g, -2, 2), uniform(g, -2, 2));
    const int kind = trial % 5;
    if (kind == 3) {  // parallel to the plane, above the face
      const V3 n = (v[1] - v[0]).cross(v[2] - v[0]).normalized(), in = (v[0] + v[1] + v[2]) / 3;
      const V3 along = (p1 - p0 - n * n.dot(p1 - p0)).normalized();
      p0 = in + 0.3 * n - 0.2 * along;
      p1 = in + 0.3 * n + 0.2 * along;
    } else if (kind == 4) {  // through the triangle
      const double w0 = grip_mesh_test::u01(g), w1 = (1 - w0) * grip_mesh_test::u01(g);
      const V3 in = w0 * v[0] + w1 * v[1] + (1 - w0 - w1) * v[2];
      p1 = in + 0.7 * (in - p0);
    }
    auto point_d2 = [&](double t) {
      V3 q;
      TriangleFeature f = TriangleFeature::Face;
      return closest_point_on_triangle<double>(p0 + t * (p1 - p0), v[0], v[1], v[2], q, f);
    };
    double lo = 0, hi = 1;
    for (int it = 0; it < 200; ++it) {
      const double m1 = lo + (hi - lo) / 3, m2 = hi - (hi - lo) / 3;
      if (point_d2(m1) < point_d2(m2))
        hi = m2;
      else
        lo = m1;
    }
    const double search = std::min({point_d2(0), point_d2(1), point_d2(0.5 * (lo + hi))});
    S u = S(-1);
    const S d2 = segment_triangle_distance2(cv<S>(p0), cv<S>(p1), cv<S>(v[0]), cv<S>(v[1]), cv<S>(v[2]), u);
    // 64 roundings of values of size M^2 (the endpoint and edge cases' dot products); the
    // search's own error is of second order at the minimum.
    double M = std::max(p0.norm(), p1.norm());
    for (const V3& x : v) M = std::max(M, x.norm());
    const double tol = grip_test::roundoff<S>(64, 1, M * M);
    CHECK(std::abs(double(d2) - search) <= tol);
    REQUIRE(u >= S(0));
    REQUIRE(u <= S(1));
    CHECK(std::abs(point_d2(double(u)) - double(d2)) <= tol);  // u attains it
    if (kind == 4) CHECK(d2 == S(0));
    if (d2 == S(0))
      ++crossing;
    else if (u == S(0) || u == S(1))
      ++ends;
    else
      ++inner;
  }
  CHECK(ends > 20);  // an end nearest, an edge nearest, and crossings all occur
  CHECK(inner > 20);
  CHECK(crossing > 20);
  // A segment of zero length is a point.
  const Vector3<S> a(S(0), S(0), S(0)), b(S(1), S(0), S(0)), c(S(0), S(1), S(0)), p(S(0.2), S(0.2), S(0.5));
  S u = S(-1);
  CHECK(segment_triangle_distance2(p, p, a, b, c, u) == doctest::Approx(0.25));
  CHECK(u == S(0));
}

TEST_CASE_TEMPLATE("closest point on degenerate triangles: finite, the nearest segment point", S, double, float) {
  const Vector3<S> a(S(0), S(0), S(0)), b(S(1), S(0), S(0)), mid(S(0.5), S(0), S(0));
  Vector3<S> q = Vector3<S>::Zero();
  TriangleFeature f = TriangleFeature::Face;
  // Collinear: the "triangle" is segment [0, 1] on x.
  // Exact data but 0.3, which p and the expected q round alike: t = 0.3 / 1, q = t ab and
  // |p - q|^2 = 4 take a few roundings of up to 4 (q: of 1). k = 4 (support/tolerance.hpp).
  const double tol_d2 = grip_test::roundoff<S>(4, 1, 4), tol_q = grip_test::roundoff<S>(4, 1, 1);
  S d2 = closest_point_on_triangle(Vector3<S>(S(0.3), S(2), S(0)), a, b, mid, q, f);
  CHECK(std::abs(double(d2) - 4.0) <= tol_d2);
  CHECK(double((q - Vector3<S>(S(0.3), S(0), S(0))).norm()) <= tol_q);
  CHECK(f != TriangleFeature::Face);
  // All three vertices equal.
  d2 = closest_point_on_triangle(Vector3<S>(S(1), S(2), S(2)), a, a, a, q, f);
  CHECK(std::abs(double(d2) - 9.0) <= grip_test::roundoff<S>(4, 1, 9));
  CHECK(q == a);
  // Two equal vertices: a segment.
  d2 = closest_point_on_triangle(Vector3<S>(S(2), S(1), S(0)), a, b, b, q, f);
  CHECK(std::abs(double(d2) - 2.0) <= tol_d2);
  CHECK(q == b);
  // A needle of zero area to rounding far from the query point: finite.
  const Vector3<S> far_a(S(1000), S(1000), S(1000));
  d2 = closest_point_on_triangle(Vector3<S>(S(0), S(0), S(0)), far_a, Vector3<S>(far_a + Vector3<S>(S(1), S(0), S(0))),
                                 Vector3<S>(far_a + Vector3<S>(S(2), S(0), S(0))), q, f);
  CHECK(std::isfinite(d2));
  CHECK(q.allFinite());
}

TEST_CASE_TEMPLATE("solid angles: octant pi/2, and a closed mesh sums to 4 pi inside and 0 outside", S, double, float) {
  const Vector3<S> o = Vector3<S>::Zero(), x = Vector3<S>::UnitX(), y = Vector3<S>::UnitY(), z = Vector3<S>::UnitZ();
  // The data are exact small integers; the angle, of size up to 2 pi, is 2 atan2(num, den) with
  // num and den a few roundings from exact (sqrt(3) on the tetrahedron), and is compared with
  // pi rounded to S: k = 4 roundings of 2 pi (support/tolerance.hpp).
  const S tol = S(grip_test::roundoff<S>(4, 1, 2 * pi));
  // Seen from the origin, the octant triangle covers 1/8 of the sphere; the origin is behind it.
  CHECK(std::abs(triangle_solid_angle(o, x, y, z) - S(pi / 2)) <= tol);
  CHECK(std::abs(triangle_solid_angle(o, x, z, y) + S(pi / 2)) <= tol);
  // A point in the triangle's plane outside it sees nothing; a vertex gives 0, not NaN.
  CHECK(std::abs(triangle_solid_angle(Vector3<S>(S(2), S(0), S(-1)), x, y, Vector3<S>(S(1), S(1), S(-1)))) <= tol);
  CHECK(triangle_solid_angle(x, x, y, z) == S(0));
  // The regular tetrahedron seen from its centre: pi per face.
  const grip_mesh_test::Soup tet = [] {
    grip_mesh_test::Soup s;
    s.v = {V3(1, 1, 1), V3(1, -1, -1), V3(-1, 1, -1), V3(-1, -1, 1)};
    s.t = {{0, 1, 2}, {0, 3, 1}, {0, 2, 3}, {1, 3, 2}};
    return s;
  }();
  for (const auto& t : tet.t) {
    const S w = triangle_solid_angle(o, cv<S>(tet.v[static_cast<std::size_t>(t[0])]),
                                     cv<S>(tet.v[static_cast<std::size_t>(t[1])]),
                                     cv<S>(tet.v[static_cast<std::size_t>(t[2])]));
    CHECK(std::abs(w - S(pi)) <= tol);
  }
  // A closed icosphere (outward): 4 pi at random inside points, 0 outside.
  const grip_mesh_test::Soup sph = grip_mesh_test::icosphere(2);
  std::mt19937 g(13);
  for (int k = 0; k < 40; ++k) {
    const V3 dir = grip_mesh_test::unit_vector(g);
    const V3 p = dir * (k % 2 == 0 ? uniform(g, 0, 0.9) : uniform(g, 1.1, 3));
    S sum = S(0);
    for (const auto& t : sph.t)
      sum += triangle_solid_angle(cv<S>(p), cv<S>(sph.v[static_cast<std::size_t>(t[0])]),
                                  cv<S>(sph.v[static_cast<std::size_t>(t[1])]),
                                  cv<S>(sph.v[static_cast<std::size_t>(t[2])]));
    // The rounded vertices still close the mesh, so the exact sum stays 4 pi or 0. Each of the
    // n terms is within a few u of its value (num's and den's errors are u |x||y||z|, den about
    // 4 |x||y||z| or more), and the running sum adds up to (n - 1) u 4 pi: k = 2 per term of
    // 2 pi, scale n 2 pi.
    const double n_tri = double(sph.t.size());
    CHECK(double(std::abs(sum - (k % 2 == 0 ? S(4 * pi) : S(0)))) <= grip_test::roundoff<S>(2, 1, n_tri * 2 * pi));
  }
}

}  // namespace triangle_test
