// Ferrari-Canny epsilon: a symmetric grasp derived by hand, a brute-force facet enumeration.
#include <doctest/doctest.h>

#include <array>
#include <cstring>
#include <memory>
#include <vector>

#include <grip/analysis/epsilon.hpp>

#include "support/allocation_counter.hpp"
#include "support/fixtures.hpp"
#include "support/random.hpp"
#include "support/test_scale.hpp"
#include "support/tolerance.hpp"

using namespace grip;

namespace {

// Six soft fingers at the face centres of a cube (half side 3 cm), pushing in, mu = 0 and
// torsional coefficient mu_t = rho, torque scale rho. Each contact is on its own normal line
// (r x a = 0), so its primitive wrenches are [a; 0] and [a; +-a] (moment mu_t a / rho = +-a).
// Over the six faces: the twelve points +-e_fi +- e_mi. In the orthonormal basis
// p_i = (e_fi + e_mi)/sqrt2, q_i = (e_fi - e_mi)/sqrt2 they are +-sqrt2 p_i, +-sqrt2 q_i: a
// regular cross-polytope of circumradius sqrt2, whose facets are at distance sqrt2/sqrt6:
//   epsilon_L1 = 1/sqrt3.
// L-infinity: the two contacts on the x faces give, in the (f_x, m_x) plane, the sets
// conv{0, (-1,-1), (-1,1)} and conv{0, (1,1), (1,-1)}; the support of their sum along
// (cos t, sin t) is 0 + cos t + |sin t| >= 1 near t = 0, and by symmetry >= 1 everywhere:
// each plane's support is >= |u_plane|, so h(u) >= sum_k |u_k| >= 1, with equality for a
// pure force along an axis: epsilon_inf = 1.
template <class S>
Grasp<6, SoftFinger, S> cube_grasp(double rho) {
  Grasp<6, SoftFinger, S> g;
  for (int f = 0; f < 6; ++f) {
    Vector3<S> out = Vector3<S>::Zero();
    out(f / 2) = f % 2 ? S(-1) : S(1);
    Contact<S> c;
    c.position = S(0.03) * out;
    c.normal = -out;
    c.friction = S(0);
    c.torsional_friction = S(rho);
    REQUIRE(g.set(f, c) == Status::Ok);
  }
  return g;
}

// Independent method: every 6-subset of the points (and the origin) spans a hyperplane; the
// ones with all points on one side are the facet planes; epsilon = smallest facet distance.
double brute_force_epsilon(const std::vector<Eigen::Matrix<double, 6, 1>>& pts) {
  const std::size_t m = pts.size();
  double best = 1e300;
  std::array<std::size_t, 6> idx{0, 1, 2, 3, 4, 5};
  while (true) {
    Eigen::Matrix<double, 6, 5> e;
    for (std::size_t k = 1; k < 6; ++k) e.col(static_cast<Eigen::Index>(k) - 1) = pts[idx[k]] - pts[idx[0]];
    Eigen::FullPivLU<Eigen::Matrix<double, 6, 5>> lu(e);
    if (lu.rank() == 5) {
      Eigen::HouseholderQR<Eigen::Matrix<double, 6, 5>> qr(e);
      Eigen::Matrix<double, 6, 1> n = qr.householderQ() * Eigen::Matrix<double, 6, 1>::Unit(5);
      double b = n.dot(pts[idx[0]]);
      double lo = 1e300, hi = -1e300;
      for (const auto& p : pts) {
        lo = std::min(lo, n.dot(p) - b);
        hi = std::max(hi, n.dot(p) - b);
      }
      if (hi <= 1e-12)
        best = std::min(best, b);  // all on the negative side: normal outward
      else if (lo >= -1e-12)
        best = std::min(best, -b);  // flipped
    }
    std::size_t k = 6;
    while (k > 0 && idx[k - 1] == m - 7 + k) --k;
    if (k == 0) break;
    ++idx[k - 1];
    for (std::size_t j = k; j < 6; ++j) idx[j] = idx[j - 1] + 1;
  }
  return std::max(best, 0.0);
}

// Tolerances (support/tolerance.hpp). An Ok answer brackets the exact epsilon: `epsilon` is
// the offset of a facet of the inner polytope, whose vertices are support points of W (a lower
// bound), `upper` a support value h_W(u) (an upper bound), and the search stops once
// upper - epsilon <= tolerance * scale (the `tolerance` argument; scale = the largest primitive
// wrench norm). Both bounds hold to the round-off of a facet plane through six support points:
// k = 8 of scale for L1 (each point a primitive, rounded once per coordinate, the plane's
// orthogonal factorisation a few u), k = 48 for L-infinity (each point a sum of up to six
// per-contact supports, six roundings more per coordinate).
template <class S>
void check_brackets(const Epsilon<S>& e, double exact, double k, double stop, double scale) {
  const double ro = grip_test::roundoff<S>(k, 1, scale);
  CHECK(double(e.epsilon) <= exact + ro);
  CHECK(double(e.upper) >= exact - ro);
  CHECK(double(e.upper) - double(e.epsilon) <= stop * scale + ro);
}

// The largest norm of the primitive wrenches: the scale of ferrari_canny_epsilon's tolerance.
double largest_norm(const std::vector<Eigen::Matrix<double, 6, 1>>& pts) {
  double m = 0;
  for (const auto& p : pts) m = std::max(m, p.norm());
  return m;
}

}  // namespace

TEST_CASE_TEMPLATE("epsilon of the symmetric cube grasp, derived by hand", S, double, float) {
  const double rho = 0.02;
  const auto g = cube_grasp<S>(rho);
  auto ws = std::make_unique<EpsilonWorkspace<S>>();
  // The search's stopping tolerance: ScalarTraits' default relative tolerance, passed explicitly
  // so that the bound below can name it; the primitives' largest norm is sqrt(2) ([a; +-a]).
  const S stop = ScalarTraits<S>::default_tolerance;
  const double scale = std::sqrt(2.0);
  Epsilon<S> e1, einf;
  {
    grip_test::NoHeapScope scope;
    e1 = ferrari_canny_epsilon<4>(g, EpsilonNorm::L1, S(rho), *ws, stop);
    einf = ferrari_canny_epsilon<4>(g, EpsilonNorm::LInfinity, S(rho), *ws, stop);
    CHECK(scope.allocations() == 0);
  }
  REQUIRE(e1.status == Status::Ok);
  CHECK(e1.closure);
  // check_brackets: the cross-polytope is resolved to its facets, so epsilon and upper are
  // 1/sqrt(3) to round-off. Observed at most 2.1 u (double) and 1.3 u (float) of scale, k = 8.
  check_brackets(e1, 1.0 / std::sqrt(3.0), 8, double(stop), scale);
  REQUIRE(einf.status == Status::Ok);
  // Observed at most 7.1 u (double) and 17.7 u (float) of scale, k = 48.
  check_brackets(einf, 1.0, 48, double(stop), scale);
  // Without torsion (mu_t = 0, mu = 0) nothing resists a moment: epsilon = 0, no closure.
  const auto g0 = cube_grasp<S>(0.0);
  const auto e0 = ferrari_canny_epsilon<4>(g0, EpsilonNorm::L1, S(rho), *ws);
  CHECK(e0.status == Status::Ok);
  CHECK_FALSE(e0.closure);
  CHECK(e0.epsilon == S(0));
  // The weak direction is a moment: a unit facet normal whose force part is zero to a few
  // roundings (k = 8 of 1). Observed 0 in both types.
  CHECK(double(e0.direction.template head<3>().norm()) <= grip_test::roundoff<S>(8, 1, 1));
}

TEST_CASE_TEMPLATE("epsilon: IterationLimit when the workspace fills, bracketing the exact value", S, double, float) {
  // The cube grasp of the case above: epsilon_L1 = 1/sqrt(3) by hand.
  const double rho = 0.02, exact = 1.0 / std::sqrt(3.0);
  const auto g = cube_grasp<S>(rho);
  auto ws = std::make_unique<EpsilonWorkspace<S>>();
  const auto full = ferrari_canny_epsilon<4>(g, EpsilonNorm::L1, S(rho), *ws);
  REQUIRE(full.status == Status::Ok);
  constexpr int small_facets = 64;
  REQUIRE(full.facets > small_facets);  // so that the small workspace must fill up
  auto small = std::make_unique<EpsilonWorkspace<S, 32, small_facets>>();
  const auto cut = ferrari_canny_epsilon<4>(g, EpsilonNorm::L1, S(rho), *small);
  CHECK(cut.status == Status::IterationLimit);
  // A lower bound and an upper one, to the round-off of a facet (k = 8 of the primitives'
  // largest norm, sqrt(2), as in check_brackets). Observed 0.28 below and 0.20 above.
  const double ro = grip_test::roundoff<S>(8, 1, std::sqrt(2.0));
  CHECK(double(cut.epsilon) <= exact + ro);
  CHECK(double(cut.upper) >= exact - ro);
  CHECK(cut.epsilon <= cut.upper);
  CHECK(cut.facets <= small_facets);
}

TEST_CASE_TEMPLATE("epsilon L1 equals a brute-force facet enumeration, L-inf brackets", S, double, float) {
  std::mt19937 rng(31);
  auto ws = std::make_unique<EpsilonWorkspace<S>>();
  const double rho = 0.05;
  int closures = 0;
  const int reps = grip_test::scaled(12, 4);
  for (int rep = 0; rep < reps; ++rep) {
    const auto g = grip_test::random_grasp<Grasp<3, HardFinger, S>>(rng, 3);
    std::vector<Eigen::Matrix<double, 6, 1>> pts{Eigen::Matrix<double, 6, 1>::Zero()};
    for (int i = 0; i < 3; ++i) {
      Wrench<S> w[4];
      detail::contact_primitives<HardFinger, 4>(g.contact(i), S(rho), w);
      for (const auto& x : w) pts.push_back(x.template cast<double>());
    }
    const double expect = brute_force_epsilon(pts);
    // The stopping tolerance passed explicitly (ScalarTraits' default relative tolerance) so
    // that the bounds can name it; its scale is the primitives' largest norm.
    const S stop = ScalarTraits<S>::default_tolerance;
    const double scale = largest_norm(pts);
    const auto e1 = ferrari_canny_epsilon<4>(g, EpsilonNorm::L1, S(rho), *ws, stop);
    REQUIRE(e1.status == Status::Ok);
    // The brute force takes the same primitives (in double): the two differ by the search's
    // stop, stop * scale, and each one's facet round-off (k = 8 of scale in S, as in
    // check_brackets, and k = 8 in double). Observed at most 1.3e-16 (double) and 6.8e-8
    // (float), far inside the stop: the search resolves these hulls to their facets.
    const double ro1 = grip_test::roundoff<S>(8, 1, scale) + grip_test::roundoff<double>(8, 1, scale);
    CHECK(std::abs(double(e1.epsilon) - expect) <= double(stop) * scale + ro1);
    check_brackets(e1, expect, 16, double(stop), scale);
    closures += e1.closure ? 1 : 0;
    // L-infinity: W_1 in W_inf in 3 W_1, and epsilon <= h(u) for random unit u. Each epsilon
    // is a lower bound to its facet round-off (ro1, and k = 48 for L-infinity) and within the
    // stop of its exact value: epsilon_inf >= exact_inf - stop - ro >= exact_1 - stop - ro >=
    // epsilon_1 - stop - ro - ro1, and epsilon_inf <= exact_inf + ro <= 3 exact_1 + ro <=
    // 3 (epsilon_1 + stop + ro1) + ro. Observed: at least 0 and 0.085 inside.
    const auto ei = ferrari_canny_epsilon<4>(g, EpsilonNorm::LInfinity, S(rho), *ws, stop);
    REQUIRE(ei.status == Status::Ok);
    const double ro_inf = grip_test::roundoff<S>(48, 1, scale);
    CHECK(double(ei.epsilon) >= double(e1.epsilon) - double(stop) * scale - ro_inf - ro1);
    CHECK(double(ei.epsilon) <= 3 * (double(e1.epsilon) + double(stop) * scale + ro1) + ro_inf);
    grip_test::Normal n01(0.0, 1.0);
    for (int t = 0; t < 50; ++t) {
      Eigen::Matrix<double, 6, 1> u;
      for (int k = 0; k < 6; ++k) u(k) = n01(rng);
      u.normalize();
      double h = 0;
      for (int i = 0; i < 3; ++i) {
        double best = 0;
        for (int k = 0; k < 4; ++k) best = std::max(best, u.dot(pts[static_cast<std::size_t>(1 + 4 * i + k)]));
        h += best;
      }
      // A lower bound (ro_inf), h summed in double from the primitives (k = 8 of scale).
      CHECK(double(ei.epsilon) <= h + ro_inf + grip_test::roundoff<double>(8, 1, scale));
    }
  }
  CHECK(closures > 0);
}

TEST_CASE_TEMPLATE("epsilon L-infinity of 20 contacts: Ok in the default workspace, below every support value", S,
                   double, float) {
  // The largest grasps the analysis is sized for. Their Minkowski sums need up to about 50 000
  // facets and 550 vertices near the origin (measured on 64 such grasps), which the default
  // workspace holds: the answer is exact, not a bound.
  std::mt19937 rng(53);
  auto ws = std::make_unique<EpsilonWorkspace<S>>();
  const double rho = 0.05;
  const int reps = grip_test::scaled(3, 1);
  for (int rep = 0; rep < reps; ++rep) {
    const auto g = grip_test::random_grasp<Grasp<20, HardFinger, S>>(rng, 20);
    std::vector<Eigen::Matrix<double, 6, 1>> pts;
    for (int i = 0; i < 20; ++i) {
      Wrench<S> w[8];
      detail::contact_primitives<HardFinger, 8>(g.contact(i), S(rho), w);
      for (const auto& x : w) pts.push_back(x.template cast<double>());
    }
    const S stop = ScalarTraits<S>::default_tolerance;
    const double scale = largest_norm(pts);
    const auto e = ferrari_canny_epsilon<8>(g, EpsilonNorm::LInfinity, S(rho), *ws, stop);
    REQUIRE(e.status == Status::Ok);
    CHECK(e.facets <= EpsilonWorkspace<S>::max_facets);
    // Ok: upper is a support value and epsilon the offset of a facet of the inner polytope,
    // within the stop of each other. epsilon is below every support value h(u), here at 200
    // random directions and the six axes both ways, each summed in double from the primitives
    // (k = 8 of scale), to the facet round-off of L-infinity (k = 48, as in check_brackets).
    CHECK(double(e.upper) - double(e.epsilon) <= double(stop) * scale + grip_test::roundoff<S>(48, 1, scale));
    const double ro = grip_test::roundoff<S>(48, 1, scale) + grip_test::roundoff<double>(8, 1, scale);
    grip_test::Normal n01(0.0, 1.0);
    for (int t = 0; t < 212; ++t) {
      Eigen::Matrix<double, 6, 1> u = Eigen::Matrix<double, 6, 1>::Zero();
      if (t < 12)
        u(t / 2) = t % 2 ? -1.0 : 1.0;
      else
        for (int k = 0; k < 6; ++k) u(k) = n01(rng);
      u.normalize();
      double h = 0;
      for (int i = 0; i < 20; ++i) {
        double best = 0;
        for (int k = 0; k < 8; ++k) best = std::max(best, u.dot(pts[static_cast<std::size_t>(8 * i + k)]));
        h += best;
      }
      CHECK(double(e.epsilon) <= h + ro);
    }
  }
}

TEST_CASE_TEMPLATE("epsilon without a workspace: the same answer as with one, bit for bit", S, double, float) {
  // The convenience overload takes its workspace from the heap (never a 6 MB stack frame).
  std::mt19937 rng(37);
  auto ws = std::make_unique<EpsilonWorkspace<S>>();
  for (int rep = 0; rep < 3; ++rep) {
    const auto g = grip_test::random_grasp<Grasp<4, HardFinger, S>>(rng, 4);
    for (const EpsilonNorm norm : {EpsilonNorm::L1, EpsilonNorm::LInfinity}) {
      const auto with = ferrari_canny_epsilon<4>(g, norm, S(0.05), *ws);
      const auto without = ferrari_canny_epsilon<4>(g, norm, S(0.05));
      REQUIRE(with.status == Status::Ok);
      CHECK(without.status == with.status);
      CHECK(std::memcmp(&without.epsilon, &with.epsilon, sizeof(S)) == 0);
      CHECK(std::memcmp(&without.upper, &with.upper, sizeof(S)) == 0);
      CHECK(without.direction == with.direction);
      CHECK(without.facets == with.facets);
    }
  }
}

TEST_CASE_TEMPLATE("epsilon: bad input", S, double, float) {
  Grasp<3, HardFinger, S> g;
  CHECK(ferrari_canny_epsilon<4>(g, EpsilonNorm::L1, S(1)).status == Status::InvalidInput);
  std::mt19937 rng(2);
  g = grip_test::random_grasp<Grasp<3, HardFinger, S>>(rng, 3);
  CHECK(ferrari_canny_epsilon<4>(g, EpsilonNorm::L1, S(0)).status == Status::InvalidInput);
  CHECK(ferrari_canny_epsilon<4>(g, EpsilonNorm::L1, std::numeric_limits<S>::infinity()).status ==
        Status::InvalidInput);
}

template struct grip::Epsilon<float>;
template struct grip::EpsilonWorkspace<double, 64, 256>;
