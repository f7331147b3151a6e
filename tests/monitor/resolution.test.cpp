// Resolution step: transmitted forces (kinetic friction = projection, zero when separating),
// the unbalanced wrench, and re-solving on the sticking contacts.
#include <doctest/doctest.h>

#include <random>

#include <grip/monitor/resolution.hpp>
#include <grip/solve/solve_range_space.hpp>

#include "support/allocation_counter.hpp"
#include "support/cone_sampling.hpp"
#include "support/fixtures.hpp"

using grip_test::pi;

using namespace grip;

template struct grip::Resolution<Grasp<4, HardFinger, double>>;
template struct grip::StickingGrasp<Grasp<Dynamic, SoftFinger, float, 6>>;

TEST_CASE_TEMPLATE("Resolution: transmitted forces and the unbalanced wrench", S, double, float) {
  using G = Grasp<Dynamic, HardFinger, S, 16>;
  std::mt19937 rng(81);
  int kinds[3] = {0, 0, 0};
  for (int trial = 0; trial < 200; ++trial) {
    const G g = grip_test::random_grasp<G>(rng, 4 + trial % 12);
    const Wrench<S> w = grip_test::random_wrench<S>(rng);
    typename G::ForceVector x(g.unknowns());
    for (int i = 0; i < g.size(); ++i)
      x.template segment<3>(3 * i) =
          grip_test::random_force(rng, g.contact(i).normal.template cast<double>(), -2.0, 5.0, 4.0).template cast<S>();
    grip_test::NoHeapScope scope;
    const auto st = monitor_grasp(g, x);
    const auto r = resolve(g, x, st, w);
    CHECK(scope.allocations() == 0);
    REQUIRE(r.ok());
    Wrench<S> released = Wrench<S>::Zero();
    for (int i = 0; i < g.size(); ++i) {
      const auto cone = CoulombCone<S>::from_contact(g.contact(i));
      const Vector3<S> f = x.template segment<3>(3 * i), y = r.transmitted.template segment<3>(3 * i);
      ++kinds[static_cast<int>(st.mode(i))];
      if (st.is_sticking(i)) CHECK(y == f);
      if (st.is_separating(i)) CHECK(y == Vector3<S>::Zero());
      if (st.is_sliding(i)) {
        // Kinetic friction: on the cone's boundary, and the nearest such point (Moreau).
        CHECK(std::abs(cone.margin(y)) <= S(20) * grip_test::rel_tol<S>() * (S(1) + f.norm()));
        CHECK(std::abs(y.dot(f - y)) <= S(20) * grip_test::rel_tol<S>() * (S(1) + f.squaredNorm()));
        released.template head<3>() += y;
        released.template tail<3>() += g.contact(i).position.cross(y);
      }
    }
    // Independent: unbalanced = G y + w_ext with G from grasp_matrix().
    const Wrench<S> expect = g.grasp_matrix() * r.transmitted + w;
    CHECK((r.unbalanced - expect).norm() <= S(20) * grip_test::rel_tol<S>() * (S(1) + expect.norm() + x.norm()));
    CHECK((r.released_wrench - released).norm() <= S(20) * grip_test::rel_tol<S>() * (S(1) + x.norm()));
  }
  CHECK(kinds[0] > 100);
  CHECK(kinds[1] > 100);
  CHECK(kinds[2] > 100);
}

TEST_CASE_TEMPLATE("Resolution: a stable balanced grasp leaves nothing unbalanced", S, double, float) {
  using G = Grasp<Dynamic, HardFinger, S, 8>;
  std::mt19937 rng(82);
  G g;
  for (int i = 0; i < 6; ++i)
    REQUIRE(g.add(grip_test::sphere_contact<S>(pi / 2, i * pi / 3, 0.05, 0.9, 8.0)) == Status::Ok);
  Wrench<S> w = Wrench<S>::Zero();
  w(2) = S(-2);
  const auto sol = solve_range_space(g, w);
  const auto st = monitor_grasp(g, sol.forces);
  REQUIRE(st.stable);
  const auto r = resolve(g, sol.forces, st, w);
  CHECK(r.unbalanced.norm() <= S(10) * grip_test::rel_tol<S>() * S(10));
  CHECK(r.released_wrench.norm() == S(0));
}

TEST_CASE_TEMPLATE("Resolution: re-solve on the sticking contacts balances the load", S, double, float) {
  // Six fingers round a sphere; two of them have almost no friction and slip under a sideways
  // load. After resolution the four sticking fingers are re-solved against w_ext plus the
  // kinetic friction of the slipping ones; the combined forces balance the object again.
  using G = Grasp<Dynamic, HardFinger, S, 8>;
  G g;
  for (int i = 0; i < 6; ++i)
    REQUIRE(g.add(grip_test::sphere_contact<S>(pi / 2 + 0.3 * (i % 2), i * pi / 3, 0.05, i < 2 ? 0.01 : 1.0, 4.0)) ==
            Status::Ok);
  Wrench<S> w = Wrench<S>::Zero();
  w(2) = S(-3);
  const auto sol = solve_range_space(g, w);
  const auto st = monitor_grasp(g, sol.forces);
  REQUIRE(st.ok());
  REQUIRE(st.sliding_count == 2);
  CHECK(st.is_sliding(0));
  CHECK(st.is_sliding(1));
  const auto r = resolve(g, sol.forces, st, w);
  // The slipping fingers drop load: since G x + w_ext = 0, the unbalanced wrench is G (y - x),
  // only the two sliding contacts' changes, and it is not small (the object would move).
  const Wrench<S> drop = g.grasp_matrix() * (r.transmitted - sol.forces);
  CHECK((r.unbalanced - drop).norm() <= S(100) * grip_test::rel_tol<S>());
  CHECK(r.unbalanced.norm() > S(0.05));
  grip_test::NoHeapScope scope;
  const auto sub = sticking_grasp(g, st);
  CHECK(scope.allocations() == 0);
  REQUIRE(sub.ok());
  REQUIRE(sub.grasp.size() == 4);
  for (int k = 0; k < 4; ++k) CHECK(sub.original_index[static_cast<std::size_t>(k)] == k + 2);
  CHECK(sub.original_index[4] == -1);
  const auto again = solve_range_space(sub.grasp, Wrench<S>(w + r.released_wrench));
  REQUIRE(again.ok());
  typename G::ForceVector x2 = r.transmitted;
  sub.scatter(again.forces, x2);
  for (int k = 0; k < 2; ++k) CHECK(x2.template segment<3>(3 * k) == r.transmitted.template segment<3>(3 * k));
  CHECK((g.grasp_matrix() * x2 + w).norm() <= S(100) * grip_test::rel_tol<S>() * S(10));
}

TEST_CASE_TEMPLATE("Resolution: bad input", S, double, float) {
  using G = Grasp<Dynamic, HardFinger, S, 4>;
  std::mt19937 rng(83);
  const G g = grip_test::random_grasp<G>(rng, 3);
  const typename G::ForceVector x = G::ForceVector::Ones(9);
  const auto st = monitor_grasp(g, x);
  Wrench<S> w = Wrench<S>::Zero();
  CHECK(resolve(g, x, st, w).ok());
  w(0) = std::numeric_limits<S>::quiet_NaN();
  const auto bad = resolve(g, x, st, w);
  CHECK(bad.status == Status::InvalidInput);
  CHECK(bad.transmitted.size() == 9);
  CHECK(bad.transmitted.isZero());
  GraspState<G> invalid;  // default: InvalidInput
  CHECK(resolve(g, x, invalid, Wrench<S>::Zero()).status == Status::InvalidInput);
  CHECK(sticking_grasp(g, invalid).status == Status::InvalidInput);
}
