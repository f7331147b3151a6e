// The inner polytope of the epsilon search (analysis/detail/epsilon_polytope.hpp): facet
// normals against an SVD's null vector; the breadth-first search for the facets a point sees
// against a plain loop over the facets, its horizon against a count of every ridge, and the
// adjacency, planes, convexity and nearest facet after each step of a growing hull.
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
  auto normals = std::make_unique<std::array<std::array<S, 256>, 6>>();  // normals[i][f]
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
    detail::facet_normals<16>(ws->vertices.data(), ws->facet_vertices, first, count, *normals);
    for (int f = first; f < first + count; ++f) {
      const auto fi = static_cast<std::size_t>(f);
      const std::array<int, 6>& fv = ws->facet_vertices[fi];
      Eigen::Matrix<double, 5, 6> e;
      Wrench<double> n;
      for (int i = 0; i < 6; ++i) n[i] = double((*normals)[static_cast<std::size_t>(i)][fi]);
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

TEST_CASE_TEMPLATE("epsilon polytope: a growing hull keeps its visible sets, horizon, adjacency and planes", S, double,
                   float) {
  using W = EpsilonWorkspace<S, 64, 16384>;
  std::mt19937 rng(43);
  grip_test::Normal n01(0.0, 1.0);
  auto ws = std::make_unique<W>();
  // Round-off of a plane through its vertices (norms below 3): k = 64 of 3 (the candidate
  // normals are kept within 4 u of each edge, facet_normals() within a few u). The visibility
  // threshold is that round-off, as in the search (a larger one leaves the hull non-convex
  // by more than itself: facets a point barely sees stay, and later cones fold over them).
  const double ro = grip_test::roundoff<S>(64, 1, 3.0);
  const S threshold = S(ro);
  int steps = 0, cone_facets = 0;
  for (int trial = 0; trial < 3; ++trial) {
    // A simplex about the origin (vertex k at e_k, vertex 6 at -(1, ..., 1) / 6, jittered),
    // then random points of norm 1 to 2.5, each added when some facet sees it.
    Wrench<S> centre = Wrench<S>::Zero();
    for (int v = 0; v < 7; ++v) {
      Wrench<S> x = v < 6 ? Wrench<S>(Wrench<S>::Unit(v)) : Wrench<S>(Wrench<S>::Constant(S(-1) / S(6)));
      for (int i = 0; i < 6; ++i) x[i] += S(0.1) * S(n01(rng));
      ws->vertices[static_cast<std::size_t>(v)] = x;
      centre += x / S(7);
    }
    detail::PolytopeFacets<S, W> facets(*ws, centre, S(0));
    REQUIRE(facets.simplex());
    int nv = 7;
    for (int attempt = 0; attempt < 400 && nv < W::max_vertices; ++attempt) {
      Wrench<S> p;
      for (int i = 0; i < 6; ++i) p[i] = S(n01(rng));
      p *= S(1 + 1.5 * (attempt % 7) / 6.0) / p.norm();
      // The plain loop: the facets that see p, and the one that sees it most (the start).
      std::vector<int> expect;
      int start = -1;
      for (int f = 0; f < facets.count(); ++f)
        if (facets.margin(f, p) > threshold) {
          expect.push_back(f);
          if (start < 0 || facets.margin(f, p) > facets.margin(start, p)) start = f;
        }
      if (expect.empty()) continue;
      ws->vertices[static_cast<std::size_t>(nv)] = p;
      const int nvis = facets.find_visible(p, threshold, start);
      REQUIRE(nvis >= 0);
      std::vector<int> got(ws->visible.begin(), ws->visible.begin() + nvis);
      std::sort(got.begin(), got.end());
      CHECK(got == expect);
      // The horizon: the ridges exactly one visible facet has, each with the facet across.
      std::map<std::uint64_t, int> met;
      for (const int f : expect)
        for (int drop = 0; drop < 6; ++drop)
          ++met[detail::ridge_key(ws->facet_vertices[static_cast<std::size_t>(f)], drop)];
      std::vector<std::uint64_t> once;
      for (const auto& [key, times] : met)
        if (times == 1) once.push_back(key);
      const int nh = facets.horizon_size();
      std::vector<std::uint64_t> horizon(ws->horizon.begin(), ws->horizon.begin() + nh);
      std::sort(horizon.begin(), horizon.end());
      CHECK(horizon == once);
      for (int k = 0; k < nh; ++k) {
        const int out = ws->outside[static_cast<std::size_t>(k)];
        REQUIRE(out >= 0);
        CHECK_FALSE(std::binary_search(expect.begin(), expect.end(), out / 8));
        CHECK(detail::ridge_key(ws->facet_vertices[static_cast<std::size_t>(out / 8)], out % 8) ==
              ws->horizon[static_cast<std::size_t>(k)]);
      }
      if (facets.count() - nvis + nh > W::max_facets) break;
      facets.replace_visible(nv++);
      ++steps;
      // Adjacency: every neighbour exists, has the ridge and points back across it.
      const int count = facets.count();
      int bad = 0;
      for (int f = 0; f < count; ++f)
        for (int r = 0; r < 6; ++r) {
          const auto fi = static_cast<std::size_t>(f);
          const int g = ws->neighbours[fi][static_cast<std::size_t>(r)];
          if (g < 0 || g >= count || g == f) {
            ++bad;
            continue;
          }
          int back = 0;
          for (int s = 0; s < 6; ++s)
            if (ws->neighbours[static_cast<std::size_t>(g)][static_cast<std::size_t>(s)] == f &&
                detail::ridge_key(ws->facet_vertices[static_cast<std::size_t>(g)], s) ==
                    detail::ridge_key(ws->facet_vertices[fi], r))
              ++back;
          bad += back == 1 ? 0 : 1;
        }
      CHECK(bad == 0);
      // Planes: unit, through the facet's vertices, every vertex on the inner side (convex);
      // nearest(): the least offset, the first of ties.
      int best = 0;
      for (int f = 0; f < count; ++f) {
        CHECK(std::abs(double(facets.normal(f).norm()) - 1.0) <= ro);
        for (const int v : ws->facet_vertices[static_cast<std::size_t>(f)])
          CHECK(std::abs(double(facets.margin(f, ws->vertices[static_cast<std::size_t>(v)]))) <= ro);
        for (int v = 0; v < nv; ++v)
          CHECK(double(facets.margin(f, ws->vertices[static_cast<std::size_t>(v)])) <= double(threshold) + ro);
        if (facets.offset(f) < facets.offset(best)) best = f;
        cone_facets += ws->facet_vertices[static_cast<std::size_t>(f)][5] == nv - 1 ? 1 : 0;
      }
      CHECK(facets.nearest() == best);
    }
  }
  CHECK(steps > 100);
  CHECK(cone_facets > 0);
}
