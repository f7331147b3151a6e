// The inner polytope of the epsilon search (analysis/detail/epsilon_polytope.hpp): facet
// normals against an SVD's null vector, the horizon against a count of every ridge, the scan
// against a plain loop over the facets.
#include <doctest/doctest.h>

#include <algorithm>
#include <array>
#include <map>
#include <memory>
#include <random>
#include <vector>

#include <Eigen/SVD>

#include <grip/analysis/epsilon.hpp>

#include "support/random.hpp"
#include "support/tolerance.hpp"

using namespace grip;

namespace {

using Ws = EpsilonWorkspace<double, 64, 256>;

// Random sorted 6-subsets of 0 .. range - 1 (a small range makes ridges repeat).
std::array<int, 6> random_facet(std::mt19937& rng, int range) {
  std::vector<int> all(static_cast<std::size_t>(range));
  for (int i = 0; i < range; ++i) all[static_cast<std::size_t>(i)] = i;
  std::shuffle(all.begin(), all.end(), rng);
  std::array<int, 6> f{};
  std::copy(all.begin(), all.begin() + 6, f.begin());
  std::sort(f.begin(), f.end());
  return f;
}

}  // namespace

TEST_CASE_TEMPLATE("facet normals: unit, normal to every edge, the SVD's null vector", S, double, float) {
  std::mt19937 rng(41);
  grip_test::Normal n01(0.0, 1.0);
  auto ws = std::make_unique<EpsilonWorkspace<S, 64, 256>>();
  for (int v = 0; v < 64; ++v)
    for (int i = 0; i < 6; ++i) ws->vertices[static_cast<std::size_t>(v)][i] = S(n01(rng));
  // Some simplices nearly flat in one direction: vertices 48 .. 63 copy vertex 0 but for a
  // step of 1e-3 (relative) along a random direction, so their edges span a thin simplex.
  for (int v = 48; v < 64; ++v)
    ws->vertices[static_cast<std::size_t>(v)] =
        ws->vertices[0] + S(1e-3) * ws->vertices[static_cast<std::size_t>(v - 40)];
  // Every count from 1 to 40 (partial batches of 16 lanes), from a nonzero first index.
  for (int count = 1; count <= 40; ++count) {
    const int first = count % 5;
    for (int f = first; f < first + count; ++f)
      ws->facet_vertices[static_cast<std::size_t>(f)] = random_facet(rng, f % 2 ? 64 : 48);
    detail::facet_normals<16>(ws->vertices.data(), ws->facet_vertices, first, count, ws->normals);
    for (int f = first; f < first + count; ++f) {
      const auto fi = static_cast<std::size_t>(f);
      const std::array<int, 6>& fv = ws->facet_vertices[fi];
      Eigen::Matrix<double, 5, 6> e;
      Wrench<double> n;
      for (int i = 0; i < 6; ++i) n[i] = double(ws->normals[static_cast<std::size_t>(i)][fi]);
      double longest = 0;
      for (int k = 1; k < 6; ++k) {
        e.row(k - 1) = (ws->vertices[static_cast<std::size_t>(fv[static_cast<std::size_t>(k)])] -
                        ws->vertices[static_cast<std::size_t>(fv[0])])
                           .template cast<double>()
                           .transpose();
        longest = std::max(longest, e.row(k - 1).norm());
      }
      // Unit to k = 8 roundings; normal to each edge to the edge's length times the
      // projections' round-off (two passes over five directions of six components: k = 64).
      // Observed at most 1.3 u (double) and 2.1 u (float) relative.
      CHECK(std::abs(n.norm() - 1.0) <= grip_test::roundoff<S>(8, 1, 1));
      for (int k = 0; k < 5; ++k) CHECK(std::abs(e.row(k).dot(n)) <= grip_test::roundoff<S>(64, 1, longest));
      // The SVD's null vector (the right singular vector of the least singular value), when
      // the simplex is not flat: n is it up to sign, to the round-off over the gap between
      // the two least singular values (k = 64).
      Eigen::JacobiSVD<Eigen::Matrix<double, 5, 6>> svd(e, Eigen::ComputeFullV);
      const double gap = svd.singularValues()(4) / svd.singularValues()(0);
      if (gap > 1e-2) {
        const Wrench<double> ref = svd.matrixV().col(5);
        CHECK(1.0 - std::abs(ref.dot(n)) <= grip_test::roundoff<S>(64, 1, 1.0 / gap));
      }
    }
  }
}

TEST_CASE("epsilon polytope: the horizon is every ridge one visible facet has") {
  std::mt19937 rng(43);
  auto ws = std::make_unique<Ws>();
  detail::PolytopeFacets<double, Ws> facets(*ws, Wrench<double>::Zero(), 0.0);
  for (int trial = 0; trial < 200; ++trial) {
    const int nvis = 1 + trial % 40;  // up to 40 facets: 480 ridge slots of the table's 512
    const int range = 7 + trial % 9;  // few vertices: ridges repeat, twice and more
    std::map<std::uint64_t, int> met;
    for (int a = 0; a < nvis; ++a) {
      // The visible facets: every other slot, so the scan's list is not 0 .. nvis - 1.
      const std::array<int, 6> f = random_facet(rng, range);
      ws->facet_vertices[static_cast<std::size_t>(2 * a + 1)] = f;
      ws->visible[static_cast<std::size_t>(a)] = 2 * a + 1;
      for (int drop = 0; drop < 6; ++drop) {
        std::array<int, 5> r{};
        for (int k = 0, j = 0; k < 6; ++k)
          if (k != drop) r[static_cast<std::size_t>(j++)] = f[static_cast<std::size_t>(k)];
        std::uint64_t key = 0;  // the ridge's five indices, base 4096 (independent of ridge_key)
        for (int m = 0; m < 5; ++m) key = key * 4096 + static_cast<std::uint64_t>(r[static_cast<std::size_t>(m)]);
        ++met[key];
      }
    }
    std::vector<std::uint64_t> expect;
    for (const auto& [key, times] : met)
      if (times == 1) expect.push_back(key);
    const int nh = facets.horizon(nvis);
    REQUIRE(nh == static_cast<int>(expect.size()));
    std::vector<std::uint64_t> got(ws->ridges.begin(), ws->ridges.begin() + nh);
    std::sort(got.begin(), got.end());
    CHECK(got == expect);
    for (int k = 0; k < nh; ++k) {  // and the keys decode to the ridges' sorted indices
      const std::array<int, 5> r = detail::ridge_vertices(got[static_cast<std::size_t>(k)]);
      CHECK(std::is_sorted(r.begin(), r.end()));
      CHECK(std::adjacent_find(r.begin(), r.end()) == r.end());
    }
  }
  // 43 visible facets need a table of 1 024 slots: more than the scratch holds.
  for (int a = 0; a < 43; ++a) ws->visible[static_cast<std::size_t>(a)] = a;
  CHECK(facets.horizon(43) == -1);
}

TEST_CASE_TEMPLATE("epsilon polytope: the scan finds the facets a point sees, and the nearest other", S, double,
                   float) {
  std::mt19937 rng(47);
  grip_test::Normal n01(0.0, 1.0);
  auto ws = std::make_unique<EpsilonWorkspace<S, 64, 256>>();
  for (int trial = 0; trial < 50; ++trial) {
    // A simplex about the origin: vertex k at e_k (k < 6), vertex 6 at -(1, ..., 1) / 6,
    // jittered; the centre is their mean.
    Wrench<S> centre = Wrench<S>::Zero();
    for (int v = 0; v < 7; ++v) {
      Wrench<S> x = v < 6 ? Wrench<S>(Wrench<S>::Unit(v)) : Wrench<S>(Wrench<S>::Constant(S(-1) / S(6)));
      for (int i = 0; i < 6; ++i) x[i] += S(0.1) * S(n01(rng));
      ws->vertices[static_cast<std::size_t>(v)] = x;
      centre += x / S(7);
    }
    detail::PolytopeFacets<S, EpsilonWorkspace<S, 64, 256>> facets(*ws, centre, S(0));
    REQUIRE(facets.simplex());
    REQUIRE(facets.count() == 7);
    for (int f = 0; f < 7; ++f) CHECK(facets.normal(f).dot(centre) < facets.offset(f));  // outward
    Wrench<S> p;
    for (int i = 0; i < 6; ++i) p[i] = S(2 * n01(rng));
    const S threshold = S(0.01);
    int best = -2;
    const int nvis = facets.scan(p, threshold, best);
    std::vector<int> expect;
    int expect_best = -1;
    for (int f = 0; f < 7; ++f) {
      if (facets.normal(f).dot(p) - facets.offset(f) > threshold) expect.push_back(f);
      else if (expect_best < 0 || facets.offset(f) < facets.offset(expect_best)) expect_best = f;
    }
    REQUIRE(nvis == static_cast<int>(expect.size()));
    for (int a = 0; a < nvis; ++a) CHECK(ws->visible[static_cast<std::size_t>(a)] == expect[static_cast<std::size_t>(a)]);
    CHECK(best == expect_best);
  }
}
