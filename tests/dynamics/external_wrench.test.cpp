// The external wrench of eq. 1-2: gravity, inertial (d'Alembert) terms, penalty contacts.
#include <doctest/doctest.h>

#include <cmath>
#include <limits>

#include <grip/dynamics/external_wrench.hpp>

#include "support/allocation_counter.hpp"
#include "support/fixtures.hpp"

using namespace grip;

template struct grip::ExternalWrench<double>;
template struct grip::ExternalWrench<float>;
template struct grip::PenaltyContact<float>;

TEST_CASE_TEMPLATE("gravity and inertial terms match a hand derivation", S, double, float) {
  RigidBody<S> b;
  b.mass = S(2);
  b.principal_inertia << S(1), S(2), S(3);
  // Body turned +90 deg about world z: body x -> world y, body y -> world -x.
  b.orientation = Eigen::Quaternion<S>(Eigen::AngleAxis<S>(S(EIGEN_PI / 2), Vector3<S>::UnitZ()));
  b.angular_velocity << S(1), S(0), S(1);
  const Vector3<S> g(S(0), S(0), S(-9.81)), a(S(0.5), S(-1), S(2)), alpha(S(0), S(0), S(1));

  // Hand derivation. I_world = R diag(1,2,3) R^T = diag(2,1,3) (x and y swap).
  // I alpha = (0,0,3); I omega = (2,0,3); omega x I omega = (1,0,1) x (2,0,3)
  //   = (0*3 - 1*0, 1*2 - 1*3, 1*0 - 0*2) = (0,-1,0).  Moment = -((0,0,3) + (0,-1,0)) = (0,1,-3).
  // Force = -m a = (-1, 2, -4). Gravity = (0, 0, -19.62; 0, 0, 0).
  const S tol = grip_test::tight<S>();
  CHECK((b.world_inertia() - Vector3<S>(S(2), S(1), S(3)).asDiagonal().toDenseMatrix()).norm() <= tol);
  const Wrench<S> gi = inertial_wrench(b, a, alpha);
  Wrench<S> expected;
  expected << S(-1), S(2), S(-4), S(0), S(1), S(-3);
  CHECK((gi - expected).norm() <= tol);
  const Wrench<S> gg = gravity_wrench(b.mass, g);
  CHECK((gg.template head<3>() - Vector3<S>(S(0), S(0), S(-19.62))).norm() <= tol);
  CHECK(gg.template tail<3>().norm() == S(0));

  const ExternalWrench<S> e = external_wrench<S>(b, g, a, alpha, nullptr, 0, PenaltyMaterial<S>{});
  REQUIRE(e.status == Status::Ok);
  CHECK((e.total() - (expected + gg)).norm() <= tol);
  CHECK((e.applied() - gg).norm() <= tol);
}

TEST_CASE_TEMPLATE("penalty contacts: spring-damper along the normal, no pull", S, double, float) {
  const PenaltyMaterial<S> m{S(1e4), S(100)};
  PenaltyContact<S> c;
  c.point << S(0.1), S(0), S(-0.05);
  c.normal << S(0), S(0), S(1);
  c.depth = S(0.002);
  c.depth_rate = S(0.1);
  // f = k d + c d' = 1e4 * 0.002 + 100 * 0.1 = 20 + 10 = 30 N along +z;
  // moment r x f = (0.1, 0, -0.05) x (0, 0, 30) = (0*30 - (-0.05)*0, (-0.05)*0 - 0.1*30, 0) = (0, -3, 0).
  CHECK(penalty_force(c, m) == doctest::Approx(30).epsilon(1e-5));
  Wrench<S> expected;
  expected << S(0), S(0), S(30), S(0), S(-3), S(0);
  CHECK((penalty_wrench(c, m) - expected).norm() <= S(1e-4));
  c.depth_rate = S(-1);  // separating fast: 20 - 100 < 0 -> clamped to 0
  CHECK(penalty_force(c, m) == S(0));
  c.depth = S(-0.001);
  c.depth_rate = S(1);  // apart: no force whatever the rate
  CHECK(penalty_force(c, m) == S(0));

  // Two contacts summed by external_wrench(), with zero gravity and no imposed motion.
  PenaltyContact<S> cs[2] = {c, c};
  cs[0].depth = S(0.001);
  cs[0].depth_rate = S(0);  // 10 N
  cs[1].point << S(-0.1), S(0), S(-0.05);
  cs[1].depth = S(0.001);
  cs[1].depth_rate = S(0);  // 10 N: the moments (0, -1, 0) and (0, +1, 0) cancel
  RigidBody<S> b;
  const Vector3<S> z = Vector3<S>::Zero();
  const ExternalWrench<S> e = external_wrench<S>(b, z, z, z, cs, 2, m);
  REQUIRE(e.status == Status::Ok);
  Wrench<S> sum;
  sum << S(0), S(0), S(20), S(0), S(0), S(0);
  CHECK((e.obstacles - sum).norm() <= S(1e-4));
  CHECK((e.total() - sum).norm() <= S(1e-4));
}

TEST_CASE_TEMPLATE("external_wrench rejects bad input with zero terms", S, double, float) {
  RigidBody<S> b;
  const Vector3<S> z = Vector3<S>::Zero();
  const PenaltyMaterial<S> m{};
  PenaltyContact<S> c;
  c.normal << S(0), S(0), S(2);  // not unit
  c.depth = S(0.01);
  CHECK(external_wrench<S>(b, z, z, z, &c, 1, m).status == Status::InvalidInput);
  c.normal << S(0), S(0), S(1);
  CHECK(external_wrench<S>(b, z, z, z, &c, 1, m).status == Status::Ok);
  CHECK(external_wrench<S>(b, z, z, z, &c, 1, PenaltyMaterial<S>{S(-1), S(0)}).status == Status::InvalidInput);
  CHECK(external_wrench<S>(b, z, z, z, nullptr, 1, m).status == Status::InvalidInput);
  CHECK(external_wrench<S>(b, z, z, z, &c, -1, m).status == Status::InvalidInput);
  Vector3<S> nan = z;
  nan(1) = std::numeric_limits<S>::quiet_NaN();
  const ExternalWrench<S> e = external_wrench<S>(b, z, nan, z, &c, 1, m);
  CHECK(e.status == Status::InvalidInput);
  CHECK(e.total().norm() == S(0));
  b.mass = S(-1);
  CHECK(external_wrench<S>(b, z, z, z, &c, 1, m).status == Status::InvalidInput);
}

TEST_CASE_TEMPLATE("from_inertia_tensor recovers principal moments and axes", S, double, float) {
  const Matrix3<S> rot = Eigen::AngleAxis<S>(S(0.7), Vector3<S>(S(1), S(2), S(-1)).normalized()).toRotationMatrix();
  const Vector3<S> moments(S(0.5), S(0.8), S(1.1));
  const Matrix3<S> tensor = rot * moments.asDiagonal() * rot.transpose();
  const PrincipalInertia<S> p = from_inertia_tensor(tensor);
  REQUIRE(p.status == Status::Ok);
  CHECK((p.moments - moments).norm() <= S(10) * grip_test::tight<S>());
  const Matrix3<S> a = p.axes.toRotationMatrix();
  CHECK((a * p.moments.asDiagonal() * a.transpose() - tensor).norm() <= S(10) * grip_test::tight<S>());
  Matrix3<S> bad = tensor;
  bad(0, 1) += S(0.1);
  CHECK(from_inertia_tensor(bad).status == Status::InvalidInput);
  CHECK(from_inertia_tensor<S>(-tensor).status == Status::InvalidInput);
}

TEST_CASE_TEMPLATE("assembling the external wrench does not touch the heap", S, double, float) {
  RigidBody<S> b;
  PenaltyContact<S> c;
  c.normal << S(0), S(0), S(1);
  c.depth = S(0.001);
  const Vector3<S> g(S(0), S(0), S(-9.81));
  grip_test::NoHeapScope scope;
  const ExternalWrench<S> e = external_wrench<S>(b, g, g, g, &c, 1, PenaltyMaterial<S>{});
  CHECK(e.status == Status::Ok);
  CHECK(scope.allocations() == 0);
}
