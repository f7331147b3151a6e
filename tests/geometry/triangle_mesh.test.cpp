// Triangle meshes: welding, the checks of finalize() (one mesh per refusal), derived normals,
// adjacency and volume against hand-derived values, capacities.
#include <doctest/doctest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <set>
#include <string>

#include <grip/geometry/triangle_mesh.hpp>

#include "geometry/mesh_test_support.hpp"
#include "support/tolerance.hpp"

template class grip::TriangleMesh<double, 16, 32>;
template class grip::TriangleMesh<float, 16, 32>;

namespace triangle_mesh_test {

using namespace grip;
using grip_mesh_test::append;
using grip_mesh_test::box_soup;
using grip_mesh_test::load;
using grip_mesh_test::Soup;
using grip_mesh_test::V3;

namespace {
template <class S>
using SmallMesh = TriangleMesh<S, 64, 128>;

template <class S>
SmallMesh<S>& small_mesh() {
  static SmallMesh<S> m;
  return m;
}

/// The tolerance of the volume of a closed mesh of `triangles` triangles whose vertices lie within
/// `r` of its bounding box's centre, from round-off (support/tolerance.hpp). finalize() sums
/// (a - c0) . ((b - c0) x (c - c0)) / 6 over the triangles: each term is at most r^3 / 6 and
/// takes 5 roundings of that size (the differences, the cross and dot products), the running
/// sum one more; rounding the data to S moves the exact volume by 3 u of itself at most, less
/// than the rest. k = 8, scale triangles r^3 / 6, condition 1.
template <class S>
double volume_tol(int triangles, double r) {
  return grip_test::roundoff<S>(8, 1, triangles * r * r * r / 6);
}
}  // namespace

TEST_CASE_TEMPLATE("mesh welding: exact duplicates share a vertex, +0 and -0 are equal", S, double, float) {
  SmallMesh<S>& m = small_mesh<S>();
  m.clear();
  const int a = m.add_vertex(Vector3<S>(S(1), S(2), S(3)));
  CHECK(a == 0);
  CHECK(m.add_vertex(Vector3<S>(S(1), S(2), S(3))) == a);
  CHECK(m.add_vertex(Vector3<S>(S(1), S(2), std::nextafter(S(3), S(4)))) == 1);  // one ulp apart: distinct
  CHECK(m.add_vertex(Vector3<S>(S(0), S(-0.0), S(0))) == 2);
  CHECK(m.add_vertex(Vector3<S>(S(-0.0), S(0), S(-0.0))) == 2);
  CHECK(m.vertex_count() == 3);
  // Non-finite or beyond max_magnitude: refused, nothing stored.
  CHECK(m.add_vertex(Vector3<S>(std::numeric_limits<S>::quiet_NaN(), S(0), S(0))) == -1);
  CHECK(m.add_vertex(Vector3<S>(S(0), std::numeric_limits<S>::infinity(), S(0))) == -1);
  CHECK(m.add_vertex(Vector3<S>(S(0), S(0), S(2) * ScalarTraits<S>::max_magnitude)) == -1);
  CHECK(m.vertex_count() == 3);
  // Source numbering: duplicates keep their own number and map to the shared vertex.
  m.clear();
  CHECK(m.add_source_vertex(Vector3<S>(S(1), S(0), S(0))) == 0);
  CHECK(m.add_source_vertex(Vector3<S>(S(0), S(1), S(0))) == 1);
  CHECK(m.add_source_vertex(Vector3<S>(S(1), S(0), S(0))) == 0);
  CHECK(m.source_vertex_count() == 3);
  CHECK(m.source_vertex(2) == 0);
  CHECK(m.source_vertex(3) == -1);
  CHECK(m.source_vertex(-1) == -1);
  // Triangles: indices must name vertices.
  CHECK(m.add_triangle(0, 1, 2) == -1);
  CHECK(m.add_triangle(0, 1, -1) == -1);
  CHECK(m.triangle_count() == 0);
}

TEST_CASE_TEMPLATE("mesh capacity: a full mesh refuses more and its counts stay within capacity", S, double, float) {
  TriangleMesh<S, 8, 4> m;  // small enough for the stack
  m.clear();
  for (int i = 0; i < 20; ++i) {
    const int v = m.add_vertex(Vector3<S>(S(i), S(0), S(0)));
    CHECK(v == (i < 8 ? i : -1));
  }
  CHECK(m.vertex_count() == 8);
  CHECK(m.add_vertex(Vector3<S>(S(3), S(0), S(0))) == 3);  // a duplicate is still found when full
  for (int i = 0; i < 6; ++i) CHECK(m.add_triangle(0, 1, 2 + i % 6) == (i < 4 ? i : -1));
  CHECK(m.triangle_count() == 4);
  for (int i = 0; i < 20; ++i) CHECK(m.add_source_vertex(Vector3<S>(S(i), S(1), S(0))) == -1);  // full
}

TEST_CASE_TEMPLATE("mesh of a box: normals, pseudo-normals, neighbours and volume by hand", S, double, float) {
  SmallMesh<S>& m = small_mesh<S>();
  const V3 h(0.05, 0.04, 0.03);
  const MeshReport r = load(box_soup(h), m);
  REQUIRE(r.ok());
  CHECK(r.issue == MeshIssue::None);
  CHECK(r.vertices == 8);
  CHECK(r.triangles == 12);
  CHECK(r.components == 1);
  CHECK_FALSE(r.flipped);
  CHECK(m.finalized());
  CHECK(std::abs(double(m.volume()) - 8 * h.prod()) <= volume_tol<S>(12, h.norm()));
  Vector3<S> lo = Vector3<S>::Zero(), hi = lo;
  REQUIRE(m.bounding_box(lo, hi));
  CHECK((hi - h.cast<S>()).norm() == S(0));
  CHECK((lo + h.cast<S>()).norm() == S(0));
  // Unit normals from round-off (support/tolerance.hpp), scale 1: a face normal is a cross
  // product of edges normalised (2 roundings in the product, the norm's and the division's:
  // k = 4); an edge's is the same sum of two unit normals normalised on both sides; a corner's
  // sums three faces weighted by angles of pi / 2 from atan2 (a few u each, relative),
  // normalised, against 1 / sqrt(3) rounded in S: k = 8.
  const S tol = S(grip_test::roundoff<S>(4, 1, 1)), tol_corner = S(grip_test::roundoff<S>(8, 1, 1));
  for (int t = 0; t < 12; ++t) {
    const Vector3<S>& n = m.face_normal(t);
    // Axis-aligned and outward: along the axis where the three vertices agree, with their sign.
    const std::array<int, 3>& tri = m.triangle(t);
    int axis = -1;
    for (int k = 0; k < 3; ++k)
      if (m.vertex(tri[0])(k) == m.vertex(tri[1])(k) && m.vertex(tri[1])(k) == m.vertex(tri[2])(k)) axis = k;
    REQUIRE(axis >= 0);
    Vector3<S> expect = Vector3<S>::Zero();
    expect(axis) = m.vertex(tri[0])(axis) > S(0) ? S(1) : S(-1);
    CHECK((n - expect).norm() <= tol);
    for (int e = 0; e < 3; ++e) {
      const int nb = m.neighbour(t, e);
      REQUIRE(nb >= 0);
      // The neighbour runs along the same edge in the other direction.
      const int u = tri[static_cast<std::size_t>(e)], v = tri[static_cast<std::size_t>((e + 1) % 3)];
      int found = 0;
      for (int k = 0; k < 3; ++k)
        found += m.triangle(nb)[static_cast<std::size_t>(k)] == v &&
                 m.triangle(nb)[static_cast<std::size_t>((k + 1) % 3)] == u;
      CHECK(found == 1);
      // Edge pseudo-normal: the normalised sum of the two faces' normals.
      CHECK((m.edge_normal(t, e) - (n + m.face_normal(nb)).normalized()).norm() <= tol);
    }
  }
  // A corner meets three faces at right angles: the pseudo-normal is (+-1, +-1, +-1) / sqrt(3).
  for (int v = 0; v < 8; ++v) {
    const Vector3<S> expect = m.vertex(v).cwiseSign() / std::sqrt(S(3));
    CHECK((m.vertex_normal(v) - expect).norm() <= tol_corner);
  }
}

TEST_CASE_TEMPLATE("finalize turns an inward mesh outward and says so", S, double, float) {
  SmallMesh<S>& m = small_mesh<S>();
  Soup inward;
  append(inward, box_soup(V3(0.02, 0.03, 0.04)), true);
  const MeshReport r = load(inward, m);
  REQUIRE(r.ok());
  CHECK(r.flipped);
  // The mesh keeps the report of its finalize: a box has 8 vertices, 12 triangles, one surface.
  CHECK(m.report().ok());
  CHECK(m.report().flipped);
  CHECK(m.report().vertices == 8);
  CHECK(m.report().triangles == 12);
  CHECK(m.report().components == 1);
  CHECK(std::abs(double(m.volume()) - 8 * 0.02 * 0.03 * 0.04) <= volume_tol<S>(12, V3(0.02, 0.03, 0.04).norm()));
  for (int t = 0; t < 12; ++t) {  // outward again: the normal points away from the centre
    const Vector3<S> c = (m.vertex(m.triangle(t)[0]) + m.vertex(m.triangle(t)[1]) + m.vertex(m.triangle(t)[2])) / S(3);
    CHECK(m.face_normal(t).dot(c) > S(0));
  }
}

TEST_CASE_TEMPLATE("finalize refuses each kind of bad mesh with its issue", S, double, float) {
  SmallMesh<S>& m = small_mesh<S>();
  const Soup box = box_soup(V3(0.05, 0.05, 0.05));
  // Empty: no triangles.
  m.clear();
  m.add_vertex(Vector3<S>::Zero());
  MeshReport r = m.finalize();
  CHECK(r.status == Status::InvalidInput);
  CHECK(r.issue == MeshIssue::Empty);
  CHECK_FALSE(m.finalized());
  // An open box: one triangle missing.
  Soup open = box;
  open.t.pop_back();
  r = load(open, m);
  CHECK(r.issue == MeshIssue::NotClosed);
  CHECK(r.element >= 0);
  // A repeated triangle: three triangles on its edges.
  Soup twice = box;
  twice.t.push_back(box.t[0]);
  CHECK(load(twice, m).issue == MeshIssue::NonManifold);
  // One triangle turned: its edges run the same way as its neighbours'.
  Soup turned = box;
  std::swap(turned.t[3][1], turned.t[3][2]);
  r = load(turned, m);
  CHECK(r.issue == MeshIssue::InconsistentOrientation);
  // A repeated vertex, then zero area (three collinear vertices).
  Soup repeat = box;
  repeat.t[5][2] = repeat.t[5][1];
  r = load(repeat, m);
  CHECK(r.issue == MeshIssue::DegenerateTriangle);
  CHECK(r.element == 5);
  Soup flat = box;
  flat.v.push_back(V3(0.0, 0.0, 0.05));
  flat.v.push_back(V3(0.01, 0.0, 0.05));
  flat.v.push_back(V3(0.02, 0.0, 0.05));
  flat.t.push_back({8, 9, 10});
  CHECK(load(flat, m).issue == MeshIssue::DegenerateTriangle);
  // Two boxes sharing one corner vertex: every edge is fine, the corner is two fans.
  Soup bowtie = box;
  Soup other = box_soup(V3(0.05, 0.05, 0.05), V3(0.1, 0.1, 0.1));
  append(bowtie, other);
  r = load(bowtie, m);  // welding merges the shared corner (0.05, 0.05, 0.05)
  CHECK(r.vertices == 15);
  CHECK(r.issue == MeshIssue::NonManifold);
  // Two boxes sharing an edge: that edge has four triangles.
  Soup edge_pair = box;
  append(edge_pair, box_soup(V3(0.05, 0.05, 0.05), V3(0.1, 0.1, 0.0)));
  CHECK(load(edge_pair, m).issue == MeshIssue::NonManifold);
  // A zero-thickness sheet: two triangles back to back.
  Soup sheet;
  sheet.v = {V3(0, 0, 0), V3(0.1, 0, 0), V3(0, 0.1, 0)};
  sheet.t = {{0, 1, 2}, {0, 2, 1}};
  CHECK(load(sheet, m).issue == MeshIssue::FoldedSurface);
  // A box inside a box, both outward: overlapping solids.
  Soup nested = box;
  append(nested, box_soup(V3(0.01, 0.01, 0.01)));
  CHECK(load(nested, m).issue == MeshIssue::Overlapping);
  // An inward box outside any solid: a cavity in nothing.
  Soup stray = box;
  append(stray, box_soup(V3(0.01, 0.01, 0.01), V3(0.5, 0, 0)), true);
  CHECK(load(stray, m).issue == MeshIssue::Overlapping);
  // After any refusal the mesh is not finalized and its derived data is not offered.
  Vector3<S> lo = Vector3<S>::Zero(), hi = lo;
  CHECK_FALSE(m.finalized());
  CHECK_FALSE(m.bounding_box(lo, hi));
  CHECK(m.volume() == S(0));
}

TEST_CASE_TEMPLATE("finalize accepts a cavity, separate components and unused vertices", S, double, float) {
  SmallMesh<S>& m = small_mesh<S>();
  // A hollow box: the outer box outward, the inner one inward.
  Soup hollow = box_soup(V3(0.05, 0.05, 0.05));
  append(hollow, box_soup(V3(0.02, 0.02, 0.02)), true);
  MeshReport r = load(hollow, m);
  REQUIRE(r.ok());
  CHECK(r.components == 2);
  CHECK_FALSE(r.flipped);
  const double hollow_tol = volume_tol<S>(24, V3(0.05, 0.05, 0.05).norm());  // about the centre
  CHECK(std::abs(double(m.volume()) - (0.001 - 0.000064)) <= hollow_tol);
  // The same, all turned inward: flipped as a whole, the cavity stays a cavity.
  Soup inverted;
  append(inverted, hollow, true);
  r = load(inverted, m);
  REQUIRE(r.ok());
  CHECK(r.flipped);
  CHECK(std::abs(double(m.volume()) - (0.001 - 0.000064)) <= hollow_tol);
  // Two separate boxes and an unused vertex far away (outside the bounding box).
  Soup two = box_soup(V3(0.01, 0.01, 0.01));
  append(two, box_soup(V3(0.01, 0.01, 0.01), V3(0.05, 0, 0)));
  two.v.push_back(V3(5, 5, 5));
  r = load(two, m);
  REQUIRE(r.ok());
  CHECK(r.components == 2);
  CHECK(r.vertices == 17);
  Vector3<S> lo = Vector3<S>::Zero(), hi = lo;
  REQUIRE(m.bounding_box(lo, hi));
  // The corner 0.05 + 0.01 is summed in double and rounded to S: k = 2 roundings of it
  // (support/tolerance.hpp).
  CHECK(std::abs(double(hi.x()) - 0.06) <= grip_test::roundoff<S>(2, 1, 0.06));
  CHECK(std::abs(double(hi.y()) - 0.01) <= grip_test::roundoff<S>(2, 1, 0.01));
  CHECK(m.vertex_normal(16) == Vector3<S>::Zero());
}

TEST_CASE("mesh issues have distinct names") {
  std::set<std::string> names;
  for (int i = 0; i <= static_cast<int>(MeshIssue::UnknownFormat); ++i) {
    const char* s = to_string(static_cast<MeshIssue>(i));
    CHECK(std::strlen(s) > 0);
    names.insert(s);
  }
  CHECK(names.size() == static_cast<std::size_t>(MeshIssue::UnknownFormat) + 1);
  MeshReport r;
  CHECK_FALSE(r.ok());
}

}  // namespace triangle_mesh_test
