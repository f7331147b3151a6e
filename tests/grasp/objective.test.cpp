// F1 (eq. 6) and F2 (eq. 7) with weights, against sums written out by hand.
#include <doctest/doctest.h>

#include <grip/grasp/objective.hpp>

#include "support/fixtures.hpp"

using namespace grip;

TEST_CASE_TEMPLATE("F1 and F2 of a two-contact grasp, by hand", S, double, float) {
  // Contact 1: a = z, s = 2, w = 1; contact 2: a = -x, s = 1, w = 3.
  // x = (1, 0, 2 | 0, 1, 0): F1 = 1/2 (1 (1 + 4) + 3 (1)) = 4;
  // F2 = 1/2 (1 |(1, 0, 0)|^2 + 3 |(1, 1, 0)|^2) = 1/2 (1 + 6) = 3.5.
  Grasp<2, HardFinger, S> g;
  Contact<S> c1, c2;
  c1.normal << S(0), S(0), S(1);
  c1.squeeze = S(2);
  c2.normal << S(-1), S(0), S(0);
  c2.squeeze = S(1);
  c2.weight = S(3);
  REQUIRE(g.set(0, c1) == Status::Ok);
  REQUIRE(g.set(1, c2) == Status::Ok);
  Eigen::Matrix<S, 6, 1> x;
  x << S(1), S(0), S(2), S(0), S(1), S(0);
  CHECK(objective_f1(g, x) == doctest::Approx(4.0));
  CHECK(objective_f2(g, x) == doctest::Approx(3.5));
  CHECK(objective_f2(g, g.target()) == S(0));
}

TEST_CASE("soft finger targets ask for no torsion, frictionless targets are s_i") {
  Grasp<1, SoftFinger> soft;
  Contact<double> c;
  c.normal << 0, 1, 0;
  c.squeeze = 5;
  REQUIRE(soft.set(0, c) == Status::Ok);
  const Eigen::Vector4d t = soft.target();
  CHECK(t == Eigen::Vector4d(0, 5, 0, 0));
  Eigen::Vector4d x(0, 5, 0, 2);  // a torsion of 2 N m costs 1/2 * 2^2
  CHECK(objective_f2(soft, x) == doctest::Approx(2.0));
  Grasp<1, FrictionlessPoint> point;
  REQUIRE(point.set(0, c) == Status::Ok);
  CHECK(point.target()(0) == 5.0);
}
