// Free-phase Newton-Euler integration: free fall, energy and momentum in free flight.
#include <doctest/doctest.h>

#include <cmath>

#include <grip/dynamics/integrator.hpp>

#include "support/allocation_counter.hpp"
#include "support/fixtures.hpp"

using namespace grip;

template struct grip::RigidBody<double>;
template struct grip::RigidBody<float>;

namespace {
template <class S>
RigidBody<S> box_body() {
  // A 0.4 kg box 0.1 x 0.06 x 0.03 m: I_x = m (b^2 + c^2) / 12, etc. (all distinct).
  RigidBody<S> b;
  b.mass = S(0.4);
  const double m = 0.4, a = 0.1, bb = 0.06, c = 0.03;
  b.principal_inertia << S(m * (bb * bb + c * c) / 12), S(m * (a * a + c * c) / 12), S(m * (a * a + bb * bb) / 12);
  return b;
}
template <class S>
S rel_tol(double d, double f) {
  return std::is_same<S, float>::value ? S(f) : S(d);
}
}  // namespace

TEST_CASE_TEMPLATE("a falling object follows x0 + v0 t + g t^2 / 2 at every step", S, double, float) {
  RigidBody<S> b = box_body<S>();
  b.position << S(0.1), S(-0.2), S(1.5);
  b.linear_velocity << S(0.3), S(0), S(1);
  const Vector3<S> g(S(0), S(0), S(-9.81));
  const Wrench<S> w = [&] { Wrench<S> x; x << b.mass * g, Vector3<S>::Zero(); return x; }();
  const S dt = S(1e-3);
  for (int k = 1; k <= 500; ++k) {
    REQUIRE(step_free<S>(b, w, dt) == Status::Ok);
    // Hand derivation: kick-drift-kick with a constant acceleration g is exact:
    // v_k = v0 + g t_k, x_k = x0 + v0 t_k + g t_k^2 / 2 with t_k = k dt.
    const double t = k * 1e-3;
    const Eigen::Vector3d x(0.1 + 0.3 * t, -0.2, 1.5 + t - 0.5 * 9.81 * t * t);
    const Eigen::Vector3d v(0.3, 0, 1 - 9.81 * t);
    CHECK((b.position.template cast<double>() - x).norm() <= double(rel_tol<S>(1e-12, 2e-4)));
    CHECK((b.linear_velocity.template cast<double>() - v).norm() <= double(rel_tol<S>(1e-12, 2e-4)));
  }
}

TEST_CASE_TEMPLATE("a constant spin about a principal axis turns the body by omega t", S, double, float) {
  RigidBody<S> b = box_body<S>();
  b.angular_velocity << S(0), S(0), S(2);  // rad/s about the body (= world) z axis
  for (int k = 0; k < 1000; ++k) REQUIRE(step_free<S>(b, Wrench<S>::Zero(), S(1e-3)) == Status::Ok);
  // After 1 s the body has turned 2 rad about z: q = (cos 1, 0, 0, sin 1).
  CHECK(std::abs(b.orientation.w() - S(std::cos(1.0))) <= rel_tol<S>(1e-10, 1e-3));
  CHECK(std::abs(b.orientation.z() - S(std::sin(1.0))) <= rel_tol<S>(1e-10, 1e-3));
  CHECK((b.angular_velocity - Vector3<S>(S(0), S(0), S(2))).norm() <= rel_tol<S>(1e-12, 1e-5));
}

TEST_CASE_TEMPLATE("energy does not grow in free flight over 10 s (fall and tumble)", S, double, float) {
  // Asymmetric box thrown upwards spinning mostly about its intermediate axis (the unstable
  // one: it flips over and over, the hardest case for an integrator), 10 000 steps of 1 ms.
  RigidBody<S> b = box_body<S>();
  b.linear_velocity << S(1), S(0.5), S(8);
  b.orientation = Eigen::Quaternion<S>(S(0.9), S(0.1), S(-0.3), S(0.2)).normalized();
  b.angular_velocity = b.orientation * Vector3<S>(S(0.05), S(20), S(0.05));
  const Vector3<S> g(S(0), S(0), S(-9.81));
  const Wrench<S> w = [&] { Wrench<S> x; x << b.mass * g, Vector3<S>::Zero(); return x; }();
  auto energy = [&](const RigidBody<S>& x) { return x.kinetic_energy() - x.mass * g.dot(x.position); };
  const S e0 = energy(b), rot0 = b.kinetic_energy() - S(0.5) * b.mass * b.linear_velocity.squaredNorm();
  const Vector3<S> l0 = b.angular_momentum();
  S worst_e = S(0), worst_rot = S(0), worst_l = S(0), scale = e0;
  S min_wy = S(1e9), max_wy = S(-1e9);
  for (int k = 0; k < 10000; ++k) {
    REQUIRE(step_free<S>(b, w, S(1e-3)) == Status::Ok);
    const S rot = b.kinetic_energy() - S(0.5) * b.mass * b.linear_velocity.squaredNorm();
    scale = std::max(scale, b.kinetic_energy());  // energy terms grow to ~2 kJ as it falls
    worst_e = std::max(worst_e, (energy(b) - e0) / scale);
    worst_rot = std::max(worst_rot, (rot - rot0) / rot0);
    worst_l = std::max(worst_l, (b.angular_momentum() - l0).norm() / l0.norm());
    const S wy = (b.orientation.conjugate() * b.angular_velocity).y();
    min_wy = std::min(min_wy, wy);
    max_wy = std::max(max_wy, wy);
  }
  // The body really tumbles: its body-y rate changes sign (the intermediate-axis flip).
  CHECK(min_wy < S(-10));
  CHECK(max_wy > S(10));
  // Energy never rises above its start by more than the splitting's bounded O(dt^2) error
  // (omega dt = 0.02 rad: 1e-3 relative is generous) or float round-off, relative to the
  // size of the energy terms (kinetic and potential energy reach ~2 kJ, 150 times E0).
  CHECK(worst_e <= rel_tol<S>(1e-5, 1e-3));
  CHECK(worst_rot <= rel_tol<S>(1e-3, 5e-3));
  // Torque-free: the world angular momentum is conserved to round-off.
  CHECK(worst_l <= rel_tol<S>(1e-10, 1e-2));
  CHECK(b.orientation.norm() == doctest::Approx(1).epsilon(double(rel_tol<S>(1e-12, 1e-5))));
}

TEST_CASE_TEMPLATE("a torque changes the angular momentum by tau dt", S, double, float) {
  RigidBody<S> b = box_body<S>();
  b.orientation = Eigen::Quaternion<S>(S(0.5), S(0.5), S(-0.5), S(0.5));
  b.angular_velocity << S(1), S(-2), S(3);
  Wrench<S> w = Wrench<S>::Zero();
  w.template tail<3>() << S(0.01), S(0.02), S(-0.03);
  const Vector3<S> l0 = b.angular_momentum();
  for (int k = 0; k < 100; ++k) REQUIRE(step_free<S>(b, w, S(1e-3)) == Status::Ok);
  // dL/dt = tau in world axes (the free rotation conserves L): L(0.1 s) = L0 + 0.1 tau.
  const Vector3<S> expected = l0 + S(0.1) * w.template tail<3>();
  CHECK((b.angular_momentum() - expected).norm() <= rel_tol<S>(1e-12, 1e-6));
}

TEST_CASE_TEMPLATE("step_free rejects bad input and leaves the body unchanged", S, double, float) {
  RigidBody<S> b = box_body<S>();
  const RigidBody<S> before = b;
  CHECK(step_free<S>(b, Wrench<S>::Zero(), S(0)) == Status::InvalidInput);
  CHECK(step_free<S>(b, Wrench<S>::Zero(), S(-1e-3)) == Status::InvalidInput);
  CHECK(step_free<S>(b, Wrench<S>::Zero(), std::numeric_limits<S>::quiet_NaN()) == Status::InvalidInput);
  Wrench<S> bad = Wrench<S>::Zero();
  bad(4) = std::numeric_limits<S>::infinity();
  CHECK(step_free<S>(b, bad, S(1e-3)) == Status::InvalidInput);
  CHECK(b.position == before.position);
  RigidBody<S> c = b;
  c.mass = S(0);
  CHECK(step_free<S>(c, Wrench<S>::Zero(), S(1e-3)) == Status::InvalidInput);
  c = b;
  c.principal_inertia << S(1), S(1), S(3);  // violates I_z <= I_x + I_y
  CHECK(step_free<S>(c, Wrench<S>::Zero(), S(1e-3)) == Status::InvalidInput);
  c = b;
  c.orientation.coeffs() << S(1), S(1), S(0), S(0);  // not unit
  CHECK(step_free<S>(c, Wrench<S>::Zero(), S(1e-3)) == Status::InvalidInput);
}

TEST_CASE_TEMPLATE("a free step does not touch the heap", S, double, float) {
  RigidBody<S> b = box_body<S>();
  b.angular_velocity << S(1), S(2), S(3);
  int ok = 0;
  grip_test::NoHeapScope scope;
  for (int k = 0; k < 10; ++k) ok += step_free<S>(b, Wrench<S>::Zero(), S(1e-3)) == Status::Ok ? 1 : 0;
  CHECK(scope.allocations() == 0);
  CHECK(ok == 10);
}

TEST_CASE_TEMPLATE("momenta: m v, and the step changes m v by F dt", S, double, float) {
  RigidBody<S> b = box_body<S>();
  b.mass = S(2);
  b.linear_velocity << S(0.5), S(-1), S(3);
  CHECK((b.linear_momentum() - Vector3<S>(S(1), S(-2), S(6))).norm() <= S(1e-6));  // by hand
  Wrench<S> w = Wrench<S>::Zero();
  w.template head<3>() << S(4), S(0), S(-2);
  const Vector3<S> before = b.linear_momentum();
  REQUIRE(step_free<S>(b, w, S(0.01)) == Status::Ok);
  CHECK((b.linear_momentum() - before - Vector3<S>(S(0.04), S(0), S(-0.02))).norm() <= rel_tol<S>(1e-12, 1e-6));
}
