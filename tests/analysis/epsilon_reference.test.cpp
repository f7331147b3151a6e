// Ferrari-Canny epsilon on random grasps against an independent expanding-polytope search in
// double: facets kept in a plain list, every facet tested for visibility, the horizon counted
// in a map, each normal from a QR factorisation. Also the adjacency the search leaves in its
// workspace, and bounds when the workspace fills.
#include <doctest/doctest.h>

#include <algorithm>
#include <array>
#include <map>
#include <memory>
#include <random>
#include <vector>

#include <Eigen/QR>

#include <grip/analysis/epsilon.hpp>

#include "support/fixtures.hpp"
#include "support/random.hpp"
#include "support/tolerance.hpp"

namespace epsilon_reference_test {

using namespace grip;
using Vec6 = Eigen::Matrix<double, 6, 1>;

// The primitive wrenches of each contact, in double, and their largest norm.
struct Primitives {
  std::vector<std::vector<Vec6>> contact;
  double scale = 0;
};

template <int K, class GraspT>
Primitives primitives(const GraspT& g, double rho) {
  using S = typename GraspT::ScalarType;
  constexpr int P = detail::primitives_per_contact<typename GraspT::ModelType, K>();
  Primitives out;
  for (int i = 0; i < g.size(); ++i) {
    std::array<Wrench<S>, P> w;
    detail::contact_primitives<typename GraspT::ModelType, K>(g.contact(i), S(rho), w.data());
    out.contact.emplace_back();
    for (const auto& x : w) {
      out.contact.back().push_back(x.template cast<double>());
      out.scale = std::max(out.scale, x.template cast<double>().norm());
    }
  }
  return out;
}

// Support point and value of W along u (L1: the best primitive or 0; L-infinity: the sum of
// each contact's best primitive or 0).
double support(const Primitives& pr, bool linf, const Vec6& u, Vec6& p) {
  p.setZero();
  double h = 0;
  for (const auto& c : pr.contact) {
    double best = 0;
    const Vec6* arg = nullptr;
    for (const auto& w : c)
      if (u.dot(w) > best) best = u.dot(w), arg = &w;
    if (arg == nullptr) continue;
    if (linf) {
      h += best;
      p += *arg;
    } else if (best > h) {
      h = best;
      p = *arg;
    }
  }
  return h;
}

struct Facet {
  std::array<int, 6> v;
  Vec6 n;
  double b;
};

// The independent search: epsilon to stop * scale, or -1 if W is flat (no closure).
double reference_epsilon(const Primitives& pr, bool linf, double stop) {
  const double tol = stop * pr.scale, visible = 1e-12 * pr.scale;
  std::vector<Vec6> pts;
  std::mt19937 rng(7);
  grip_test::Normal n01(0.0, 1.0);
  // Seven affinely independent support points: along the axes, then random directions.
  auto independent = [&pts](const Vec6& p) {
    Eigen::MatrixXd e(6, static_cast<Eigen::Index>(pts.size()));
    for (std::size_t k = 1; k < pts.size(); ++k) e.col(static_cast<Eigen::Index>(k) - 1) = pts[k] - pts[0];
    e.col(e.cols() - 1) = p - pts[0];
    Eigen::FullPivLU<Eigen::MatrixXd> lu(e);
    lu.setThreshold(1e-9);
    return lu.rank() == e.cols();
  };
  for (int t = 0; t < 400 && pts.size() < 7; ++t) {
    Vec6 u = Vec6::Zero();
    if (t < 12)
      u(t / 2) = t % 2 ? -1.0 : 1.0;
    else
      for (int k = 0; k < 6; ++k) u(k) = n01(rng);
    Vec6 p;
    support(pr, linf, u.normalized(), p);
    if (pts.empty() || independent(p)) pts.push_back(p);
  }
  if (pts.size() < 7) return -1;
  Vec6 centre = Vec6::Zero();
  for (const auto& p : pts) centre += p / 7.0;
  auto make = [&](const std::array<int, 6>& v, Facet& f) {
    Eigen::Matrix<double, 6, 5> e;
    for (int k = 1; k < 6; ++k)
      e.col(k - 1) =
          pts[static_cast<std::size_t>(v[static_cast<std::size_t>(k)])] - pts[static_cast<std::size_t>(v[0])];
    Eigen::HouseholderQR<Eigen::Matrix<double, 6, 5>> qr(e);
    f.v = v;
    f.n = qr.householderQ() * Vec6::Unit(5);
    f.b = f.n.dot(pts[static_cast<std::size_t>(v[0])]);
    if (f.n.dot(centre) > f.b) f.n = -f.n, f.b = -f.b;
  };
  std::vector<Facet> facets;
  for (int skip = 0; skip < 7; ++skip) {
    std::array<int, 6> v{};
    for (int k = 0, j = 0; k < 7; ++k)
      if (k != skip) v[static_cast<std::size_t>(j++)] = k;
    facets.emplace_back();
    make(v, facets.back());
  }
  for (int step = 0; step < 4000; ++step) {
    const auto best =
        std::min_element(facets.begin(), facets.end(), [](const Facet& a, const Facet& b) { return a.b < b.b; });
    Vec6 p;
    const double h = support(pr, linf, best->n, p);
    if (h - best->b <= tol) return std::max(best->b, 0.0);
    const int np = static_cast<int>(pts.size());
    pts.push_back(p);
    std::map<std::array<int, 5>, int> ridges;
    std::vector<Facet> kept;
    for (const auto& f : facets) {
      if (f.n.dot(p) - f.b <= visible) {
        kept.push_back(f);
        continue;
      }
      for (int drop = 0; drop < 6; ++drop) {
        std::array<int, 5> r{};
        for (int k = 0, j = 0; k < 6; ++k)
          if (k != drop) r[static_cast<std::size_t>(j++)] = f.v[static_cast<std::size_t>(k)];
        ++ridges[r];
      }
    }
    for (const auto& [r, times] : ridges) {
      if (times != 1) continue;
      std::array<int, 6> v{};
      std::copy(r.begin(), r.end(), v.begin());
      v[5] = np;
      kept.emplace_back();
      make(v, kept.back());
    }
    facets.swap(kept);
  }
  return -2;  // did not converge
}

// Every live facet's neighbour across ridge r exists, has that ridge, and points back; every
// facet's plane passes through its own vertices.
template <class Ws>
void check_adjacency(const Ws& ws, int count) {
  int bad = 0;
  for (int f = 0; f < count; ++f) {
    const auto fi = static_cast<std::size_t>(f);
    for (int r = 0; r < 6; ++r) {
      const int g = ws.neighbours[fi][static_cast<std::size_t>(r)];
      if (g < 0 || g >= count || g == f) {
        ++bad;
        continue;
      }
      const std::uint64_t key = detail::ridge_key(ws.facet_vertices[fi], r);
      int back = 0;
      for (int s = 0; s < 6; ++s)
        if (ws.neighbours[static_cast<std::size_t>(g)][static_cast<std::size_t>(s)] == f &&
            detail::ridge_key(ws.facet_vertices[static_cast<std::size_t>(g)], s) == key)
          ++back;
      if (back != 1) ++bad;
    }
  }
  CHECK(bad == 0);
}

template <class S, class GraspT, int K>
void compare_random(std::mt19937& rng, int n, int& closures) {
  const double rho = 0.05;
  auto ws = std::make_unique<EpsilonWorkspace<S>>();
  const auto g = grip_test::random_grasp<GraspT>(rng, n);
  const Primitives pr = primitives<K>(g, rho);
  const S stop = ScalarTraits<S>::default_tolerance;
  for (const bool linf : {false, true}) {
    CAPTURE(n);
    CAPTURE(linf);
    const auto e = ferrari_canny_epsilon<K>(g, linf ? EpsilonNorm::LInfinity : EpsilonNorm::L1, S(rho), *ws, stop);
    REQUIRE(e.status == Status::Ok);
    const double ref = reference_epsilon(pr, linf, double(stop));
    REQUIRE(ref > -2);
    if (ref < 0) {  // W flat: no closure
      CHECK_FALSE(e.closure);
      continue;
    }
    // Both are exact to their stop (stop * scale above the exact value at most) and to a
    // facet's round-off below it: k = 48 of scale in S (L-infinity's, as in epsilon.test.cpp)
    // and k = 48 in double. Observed at most 1.0e-16 (double) and 1.1e-7 (float) apart.
    const double ro = grip_test::roundoff<S>(48, 1, pr.scale) + grip_test::roundoff<double>(48, 1, pr.scale);
    const double got = e.closure ? double(e.epsilon) : 0.0;
    CHECK(std::abs(got - ref) <= double(stop) * pr.scale + ro);
    closures += e.closure ? 1 : 0;
    check_adjacency(*ws, e.facets);
  }
}

TEST_CASE_TEMPLATE("epsilon on random grasps equals an independent search, L1 and L-infinity, hard and soft", S, double,
                   float) {
  std::mt19937 rng(59);
  int closures = 0;  // of 40 searches
  for (int n = 3; n <= 12; ++n) {
    compare_random<S, Grasp<Dynamic, HardFinger, S, 12>, 4>(rng, n, closures);
    compare_random<S, Grasp<Dynamic, SoftFinger, S, 12>, 4>(rng, n, closures);
  }
  CHECK(closures > 20);
}

TEST_CASE_TEMPLATE("epsilon: a full workspace gives IterationLimit and bounds on random grasps", S, double, float) {
  std::mt19937 rng(61);
  auto ws = std::make_unique<EpsilonWorkspace<S>>();
  auto small = std::make_unique<EpsilonWorkspace<S, 24, 600>>();
  int limited = 0;
  for (int rep = 0; rep < 8; ++rep) {
    const auto g = grip_test::random_grasp<Grasp<Dynamic, HardFinger, S, 8>>(rng, 4 + rep % 5);
    for (const EpsilonNorm norm : {EpsilonNorm::L1, EpsilonNorm::LInfinity}) {
      const auto full = ferrari_canny_epsilon<4>(g, norm, S(0.05), *ws);
      REQUIRE(full.status == Status::Ok);
      const auto cut = ferrari_canny_epsilon<4>(g, norm, S(0.05), *small);
      if (cut.status == Status::Ok) continue;
      REQUIRE(cut.status == Status::IterationLimit);
      ++limited;
      // The exact value lies within the full search's stop of its epsilon; the cut search's
      // epsilon is below it and its upper above, to a facet's round-off (k = 48 of the
      // primitives' largest norm, here below 2: mu <= 1.2, lever <= 6 cm / rho).
      const double ro = grip_test::roundoff<S>(48, 1, 4.0);
      const double stop = double(ScalarTraits<S>::default_tolerance) * 4.0;
      CHECK(double(cut.epsilon) <= double(full.epsilon) + stop + ro);
      CHECK(double(cut.upper) >= double(full.epsilon) - ro);
      CHECK(cut.epsilon <= cut.upper);
      CHECK(cut.facets <= 600);
      check_adjacency(*small, cut.facets);
    }
  }
  CHECK(limited > 0);
}

}  // namespace epsilon_reference_test
