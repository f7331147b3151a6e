// Grasp: storage, statuses, the grasp matrix G (eq. 3) and the KKT system H, b (eq. 9).
#include <doctest/doctest.h>

#include <cmath>
#include <limits>
#include <random>

#include <grip/grasp/grasp.hpp>

#include "support/allocation_counter.hpp"
#include "support/fixtures.hpp"
#include "support/tolerance.hpp"

using namespace grip;

// Explicit instantiations: every member compiles for each model, scalar and size kind.
template class grip::Grasp<3, HardFinger, double>;
template class grip::Grasp<4, SoftFinger, float>;
template class grip::Grasp<6, FrictionlessPoint, double>;
template class grip::Grasp<Dynamic, HardFinger, float, 8>;
template class grip::Grasp<Dynamic, SoftFinger, double, 5>;
template class grip::Grasp<Dynamic, FrictionlessPoint, float, 7>;

TEST_CASE_TEMPLATE("G and H match the paper's eq. 3 and eq. 9 block by block", S, double, float) {
  // Worked example: two hard fingers at r1 = (1, 2, 3) cm and r2 = (-2, 0, 1) cm.
  Grasp<2, HardFinger, S> g;
  Contact<S> c1, c2;
  c1.position << S(0.01), S(0.02), S(0.03);
  c1.normal << S(0), S(0), S(-1);
  c1.squeeze = S(2);
  c2.position << S(-0.02), S(0), S(0.01);
  c2.normal << S(1), S(0), S(0);
  c2.squeeze = S(3);
  REQUIRE(g.set(0, c1) == Status::Ok);
  REQUIRE(g.set(1, c2) == Status::Ok);

  // R_i written out as in eq. 3: [0 -z y; z 0 -x; -y x 0].
  auto paper_r = [](const Vector3<S>& r) {
    Matrix3<S> m;
    m << S(0), -r(2), r(1), r(2), S(0), -r(0), -r(1), r(0), S(0);
    return m;
  };
  const auto G = g.grasp_matrix();
  REQUIRE(G.rows() == 6);
  REQUIRE(G.cols() == 6);
  CHECK(G.template block<3, 3>(0, 0) == Matrix3<S>::Identity());
  CHECK(G.template block<3, 3>(0, 3) == Matrix3<S>::Identity());
  CHECK(G.template block<3, 3>(3, 0) == paper_r(c1.position));
  CHECK(G.template block<3, 3>(3, 3) == paper_r(c2.position));

  const auto H = g.kkt_matrix();
  REQUIRE(H.rows() == 12);
  CHECK(H.template block<6, 6>(0, 0) == G);  // [G | 0]
  CHECK(H.template block<6, 6>(0, 6) == Matrix6<S>::Zero());
  CHECK(H.template block<6, 6>(6, 0) == Matrix6<S>::Identity());   // [I_3n | ...]
  CHECK(H.template block<3, 3>(6, 6) == -Matrix3<S>::Identity());  // row block i: [-I3  R_i]
  CHECK(H.template block<3, 3>(6, 9) == paper_r(c1.position));
  CHECK(H.template block<3, 3>(9, 6) == -Matrix3<S>::Identity());
  CHECK(H.template block<3, 3>(9, 9) == paper_r(c2.position));

  // The matrix-free product G x, by hand: f1 = (1, 0, 0) at r1 gives r1 x f1 = (0, 0.03, -0.02);
  // f2 = (0, 1, 0) at r2 gives r2 x f2 = (-0.01, 0, -0.02).
  typename Grasp<2, HardFinger, S>::ForceVector x;
  x << S(1), S(0), S(0), S(0), S(1), S(0);
  Wrench<S> gx_hand;
  gx_hand << S(1), S(1), S(0), S(-0.01), S(0.03), S(-0.04);
  // Round-off (support/tolerance.hpp): each row of G x takes 2 products and 1 sum of its terms
  // (here products with 0 and 1 and a doubling: exact), the hand values their rounding to S:
  // k = 4 of sum (1 + |r_i|) |x_i|.
  const double gx_scale = 2 + double(c1.position.norm() + c2.position.norm());
  CHECK(double((g.wrench(x) - gx_hand).norm()) <= grip_test::roundoff<S>(4, 1, gx_scale));
  CHECK(double((G * x - gx_hand).norm()) <= grip_test::roundoff<S>(4, 1, gx_scale));
  // G^T l, by hand: l = (l_f, l_m) gives f-block l_f + l_m x r_i (= l_f - r_i x l_m).
  Wrench<S> l;
  l << S(1), S(2), S(3), S(4), S(5), S(6);
  const Vector3<S> lf = l.template head<3>(), lm = l.template tail<3>();
  // Both sides: the cross product (2 products and a difference) and the sum, 4 roundings of
  // |l_f| + |l_m| |r| each: k = 8.
  const double l1 = double(lf.norm() + lm.norm() * c1.position.norm()),
               l2 = double(lf.norm() + lm.norm() * c2.position.norm());
  CHECK(double((HardFinger::wrench_transpose(c1, l) - (lf + lm.cross(c1.position))).norm()) <=
        grip_test::roundoff<S>(8, 1, l1));
  CHECK(double((HardFinger::wrench_transpose(c2, l) - (lf + lm.cross(c2.position))).norm()) <=
        grip_test::roundoff<S>(8, 1, l2));

  Wrench<S> w_ext;
  w_ext << S(1), S(2), S(3), S(4), S(5), S(6);
  const auto b = g.kkt_rhs(w_ext);
  REQUIRE(b.size() == 12);
  CHECK(b.template head<6>() == -w_ext);  // (-F_ext, -N_ext)
  CHECK(b.template segment<3>(6) == S(2) * c1.normal);
  CHECK(b.template segment<3>(9) == S(3) * c2.normal);
}

TEST_CASE_TEMPLATE("soft and frictionless grasp matrices have the documented columns", S, double, float) {
  std::mt19937 rng(7);
  const Contact<S> c = grip_test::random_contact<S>(rng);
  Grasp<Dynamic, SoftFinger, S, 2> soft;
  REQUIRE(soft.add(c) == Status::Ok);
  const auto Gs = soft.grasp_matrix();
  CHECK(Gs.col(3).template head<3>().norm() == S(0));
  CHECK((Gs.col(3).template tail<3>() - c.normal).norm() == S(0));
  Grasp<Dynamic, FrictionlessPoint, S, 2> point;
  REQUIRE(point.add(c) == Status::Ok);
  const auto Gp = point.grasp_matrix();
  REQUIRE(Gp.cols() == 1);
  CHECK((Gp.col(0).template head<3>() - c.normal).norm() == S(0));
  // Two evaluations of r x a, 3 roundings each of |r| |a| (support/tolerance.hpp): k = 6.
  CHECK(double((Gp.col(0).template tail<3>() - c.position.cross(c.normal)).norm()) <=
        grip_test::roundoff<S>(6, 1, double(c.position.norm() * c.normal.norm())));
}

TEST_CASE_TEMPLATE("bad contacts are refused with InvalidInput and leave the grasp unchanged", S, double, float) {
  Grasp<Dynamic, HardFinger, S, 2> g;
  Contact<S> good;
  good.normal << S(0), S(1), S(0);
  const S nan = std::numeric_limits<S>::quiet_NaN(), inf = std::numeric_limits<S>::infinity();
  auto bad = [&](auto mutate) {
    Contact<S> c = good;
    mutate(c);
    return g.add(c);
  };
  CHECK(bad([&](Contact<S>& c) { c.position.x() = nan; }) == Status::InvalidInput);
  CHECK(bad([&](Contact<S>& c) { c.position.z() = inf; }) == Status::InvalidInput);
  CHECK(bad([&](Contact<S>& c) { c.position.z() = S(2) * ScalarTraits<S>::max_magnitude; }) == Status::InvalidInput);
  CHECK(bad([&](Contact<S>& c) { c.normal.setZero(); }) == Status::InvalidInput);
  CHECK(bad([&](Contact<S>& c) { c.normal *= S(1.01); }) == Status::InvalidInput);
  CHECK(bad([&](Contact<S>& c) { c.normal.x() = nan; }) == Status::InvalidInput);
  CHECK(bad([&](Contact<S>& c) { c.friction = S(-0.1); }) == Status::InvalidInput);
  CHECK(bad([&](Contact<S>& c) { c.friction = nan; }) == Status::InvalidInput);
  CHECK(bad([&](Contact<S>& c) { c.torsional_friction = S(-1); }) == Status::InvalidInput);
  CHECK(bad([&](Contact<S>& c) { c.squeeze = S(-1); }) == Status::InvalidInput);
  CHECK(bad([&](Contact<S>& c) { c.squeeze = inf; }) == Status::InvalidInput);
  CHECK(bad([&](Contact<S>& c) { c.weight = S(0); }) == Status::InvalidInput);
  CHECK(bad([&](Contact<S>& c) { c.weight = S(-2); }) == Status::InvalidInput);
  CHECK(g.size() == 0);
  CHECK(g.add(good) == Status::Ok);
  CHECK(g.add(good) == Status::Ok);
  CHECK(g.add(good) == Status::InvalidInput);  // past MaxN
  CHECK(g.size() == 2);
  CHECK(g.set(2, good) == Status::InvalidInput);
  CHECK(g.set(-1, good) == Status::InvalidInput);
  g.clear();
  CHECK(g.size() == 0);
}

TEST_CASE("a fixed grasp is complete only when every slot is set") {
  Grasp<3> g;
  CHECK_FALSE(g.complete());
  std::mt19937 rng(3);
  for (int i = 0; i < 3; ++i) {
    CHECK_FALSE(g.complete());
    REQUIRE(g.set(i, grip_test::random_contact<double>(rng)) == Status::Ok);
  }
  CHECK(g.complete());
}

TEST_CASE("building G, H and b allocates nothing, fixed or bounded") {
  std::mt19937 rng(11);
  const auto fixed = grip_test::random_grasp<Grasp<5, SoftFinger, double>>(rng, 5);
  const auto bounded = grip_test::random_grasp<Grasp<Dynamic, HardFinger, float, 12>>(rng, 9);
  const Wrench<double> w = grip_test::random_wrench<double>(rng);
  grip_test::NoHeapScope scope;
  const auto g1 = fixed.grasp_matrix();
  const auto h1 = fixed.kkt_matrix();
  const auto b1 = fixed.kkt_rhs(w);
  const auto g2 = bounded.grasp_matrix();
  const auto h2 = bounded.kkt_matrix();
  const auto b2 = bounded.kkt_rhs(w.cast<float>());
  const long n = scope.allocations();
  CHECK(n == 0);
  CHECK(g1.cols() + h1.cols() + b1.size() + g2.cols() + h2.cols() + b2.size() == 20 + 26 + 26 + 27 + 33 + 33);
}

TEST_CASE_TEMPLATE("contacts() is the array of the stored contacts, kept in step", S, double, float) {
  using G = Grasp<Dynamic, HardFinger, S, 11>;
  std::mt19937 rng(5);
  G g;
  const auto mirrors = [](const G& grasp) {
    bool ok = true;
    for (int i = 0; i < grasp.size(); ++i) ok = ok && grasp.contacts() + i == &grasp.contact(i);
    return ok;
  };
  for (int i = 0; i < 11; ++i) {
    const Contact<S> c = grip_test::random_contact<S>(rng);
    REQUIRE(g.add(c) == Status::Ok);
    CHECK(mirrors(g));
    CHECK(g.contacts()[i].friction == c.friction);
  }
  // A rejected contact changes nothing; set() replaces in place.
  Contact<S> bad = grip_test::random_contact<S>(rng);
  bad.friction = S(-1);
  const S before = g.contacts()[3].friction;
  CHECK(g.set(3, bad) == Status::InvalidInput);
  CHECK(g.contacts()[3].friction == before);
  const Contact<S> c = grip_test::random_contact<S>(rng);
  REQUIRE(g.set(3, c) == Status::Ok);
  CHECK(g.contacts()[3].friction == c.friction);
  CHECK(mirrors(g));
}

TEST_CASE_TEMPLATE("a normal within its tolerance is stored unit, a unit one bit for bit", S, double, float) {
  // validate() accepts |a|^2 within 2 normal_tolerance of 1; the cones need a unit axis, so
  // the grasp scales such a normal to unit length. One already unit to round-off is kept as
  // given (so a grasp built from unit normals is exactly the caller's).
  std::mt19937 rng(6);
  const double tol = double(ScalarTraits<S>::normal_tolerance), eps = double(std::numeric_limits<S>::epsilon());
  Grasp<Dynamic, HardFinger, S, 8> g;
  for (int i = 0; i < 8; ++i) {
    Contact<S> c = grip_test::random_contact<S>(rng);
    const Vector3<S> unit = c.normal;
    if (i % 2 == 1) c.normal *= S(i % 4 == 1 ? 1 - 0.9 * tol : 1 + 0.9 * tol);
    REQUIRE(g.add(c) == Status::Ok);
    const Vector3<double> stored = g.contact(i).normal.template cast<double>();
    CHECK(std::abs(stored.norm() - 1) <= 4 * eps);
    if (i % 2 == 0) CHECK(g.contact(i).normal == unit);
    // The direction is the caller's: the part across it is round-off.
    CHECK(stored.cross(c.normal.template cast<double>().normalized()).norm() <= 4 * eps);
  }
}
