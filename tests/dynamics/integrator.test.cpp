// Free-phase Newton-Euler integration: free fall, energy and momentum in free flight.
#include <doctest/doctest.h>

#include <cmath>

#include <grip/dynamics/integrator.hpp>

#include "support/allocation_counter.hpp"
#include "support/fixtures.hpp"
#include "support/tolerance.hpp"

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
}  // namespace

TEST_CASE_TEMPLATE("a falling object follows x0 + v0 t + g t^2 / 2 at every step", S, double, float) {
  RigidBody<S> b = box_body<S>();
  b.position << S(0.1), S(-0.2), S(1.5);
  b.linear_velocity << S(0.3), S(0), S(1);
  const Vector3<S> g(S(0), S(0), S(-9.81));
  const Wrench<S> w = [&] {
    Wrench<S> x;
    x << b.mass * g, Vector3<S>::Zero();
    return x;
  }();
  const S dt = S(1e-3);
  // Round-off (support/tolerance.hpp), accumulated step by step, condition 1. Velocity: the two
  // half kicks round v_j twice (2 u sum |v_j|); a = (m g) / m and half a carry 3 u g, and dt's
  // rounding to S puts t off by u t (u g t): 4 u g t. Position: x += dt v rounds the sum and the
  // product (u sum (|x_j| + dt |v_j|)), the drift carries each step's velocity error (dt times
  // tol_v), and dt's rounding u t |v|.
  double sum_v = 0, sum_x = 0, carried = 0;
  for (int k = 1; k <= 500; ++k) {
    REQUIRE(step_free<S>(b, w, dt) == Status::Ok);
    // Hand derivation: kick-drift-kick with a constant acceleration g is exact:
    // v_k = v0 + g t_k, x_k = x0 + v0 t_k + g t_k^2 / 2 with t_k = k dt.
    const double t = k * 1e-3;
    const Eigen::Vector3d x(0.1 + 0.3 * t, -0.2, 1.5 + t - 0.5 * 9.81 * t * t);
    const Eigen::Vector3d v(0.3, 0, 1 - 9.81 * t);
    sum_v += v.norm();
    sum_x += x.norm();
    const double tol_v = grip_test::roundoff<S>(2, 1, sum_v) + grip_test::roundoff<S>(4, 1, 9.81 * t);
    carried += 1e-3 * tol_v;
    const double tol_x = grip_test::roundoff<S>(1, 1, sum_x + 1e-3 * sum_v + t * v.norm()) + carried;
    CHECK((b.position.template cast<double>() - x).norm() <= tol_x);
    CHECK((b.linear_velocity.template cast<double>() - v).norm() <= tol_v);
  }
}

TEST_CASE_TEMPLATE("a constant spin about a principal axis turns the body by omega t", S, double, float) {
  RigidBody<S> b = box_body<S>();
  b.angular_velocity << S(0), S(0), S(2);  // rad/s about the body (= world) z axis
  for (int k = 0; k < 1000; ++k) REQUIRE(step_free<S>(b, Wrench<S>::Zero(), S(1e-3)) == Status::Ok);
  // After 1 s the body has turned 2 rad about z: q = (cos 1, 0, 0, sin 1). The splitting is
  // exact about a principal axis (the axis-0 and axis-1 flows are the identity), so round-off
  // only (support/tolerance.hpp), 1000 steps of: q * r (r with 2 non-zero parts: 3 roundings
  // of |q| = 1 per part), the renormalisation (4), the half-angle's cos and sin (1): k = 8 per
  // step; and the reference's rounding to S (1).
  const double tol_q = grip_test::roundoff<S>(8 * 1000 + 1, 1, 1);
  CHECK(std::abs(double(b.orientation.w()) - std::cos(1.0)) <= tol_q);
  CHECK(std::abs(double(b.orientation.z()) - std::sin(1.0)) <= tol_q);
  // omega = 2: about z, I_world's z row is (0, 0, I_z) exactly (R's z row is (0, 0, 1)), so
  // L = I_z omega is exact (doubling) and L / I_z returns omega exactly each step: at most the
  // last step's product and quotient (k = 2 of |omega|).
  CHECK(double((b.angular_velocity - Vector3<S>(S(0), S(0), S(2))).norm()) <= grip_test::roundoff<S>(2, 1, 2));
}

TEST_CASE_TEMPLATE("energy does not grow in free flight over 10 s (fall and tumble)", S, double, float) {
  // Asymmetric box thrown upwards spinning mostly about its intermediate axis (the unstable
  // one: it flips over and over, the hardest case for an integrator), 10 000 steps of 1 ms.
  RigidBody<S> b = box_body<S>();
  b.linear_velocity << S(1), S(0.5), S(8);
  b.orientation = Eigen::Quaternion<S>(S(0.9), S(0.1), S(-0.3), S(0.2)).normalized();
  b.angular_velocity = b.orientation * Vector3<S>(S(0.05), S(20), S(0.05));
  const Vector3<S> g(S(0), S(0), S(-9.81));
  const Wrench<S> w = [&] {
    Wrench<S> x;
    x << b.mass * g, Vector3<S>::Zero();
    return x;
  }();
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
  // Energy never rises above its start by more than the splitting's bounded O(dt^2) error or
  // round-off, relative to the size of the energy terms (kinetic and potential energy reach
  // ~2 kJ, 150 times E0). Not round-off: integrator.hpp documents a bounded O(dt^2) energy
  // error without a constant; omega dt = 0.02 rad, and this check's own allowances for it are
  // 1e-5 of the energy terms and 1e-3 of the rotational energy (as before, in both types;
  // observed 1.2e-8 and 2.1e-6 in double).
  // Round-off (support/tolerance.hpp), linear in the 10 000 steps n: the world angular
  // momentum's round trip each step (omega -> I_world omega, about 12 roundings times the
  // inertia's anisotropy I_max / I_min = 3; to body axes 6; five axis rotations 15; back to
  // omega 7): k_L = 64 per step of |L|. The energy: the kicks and the drift round v and x
  // twice each per step, 4 u of the energy terms. The rotational energy: twice L's relative
  // error (it is quadratic in L), and its difference of kinetic energies cancels 4 roundings
  // of the energy terms (scale) against rot0.
  const double n = 10000, k_l = 64 * n;
  CHECK(double(worst_e) <= 1e-5 + grip_test::roundoff<S>(4 * n, 1, 1));
  CHECK(double(worst_rot) <=
        1e-3 + grip_test::roundoff<S>(2 * k_l, 1, 1) + grip_test::roundoff<S>(4, double(scale / rot0), 1));
  // Torque-free: the world angular momentum is conserved to round-off: k_L per step, relative.
  CHECK(double(worst_l) <= grip_test::roundoff<S>(k_l, 1, 1));
  // Renormalised every step: |q| = 1 to the norm's and the division's roundings (k = 4 of 1).
  CHECK(std::abs(double(b.orientation.norm()) - 1) <= grip_test::roundoff<S>(4, 1, 1));
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
  // Round-off (support/tolerance.hpp): k_L = 64 roundings of |L| per step as in the tumbling
  // test, 100 steps, and the kicks' 0.1 tau (2 per step of dt |tau|): on |L0| + 0.1 |tau|.
  const double l_scale = double(l0.norm()) + 0.1 * double(w.template tail<3>().norm());
  CHECK(double((b.angular_momentum() - expected).norm()) <= grip_test::roundoff<S>(64 * 100 + 2 * 100, 1, l_scale));
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
  // By hand: m v, one rounding of |m v| (support/tolerance.hpp; here exact in binary).
  CHECK(double((b.linear_momentum() - Vector3<S>(S(1), S(-2), S(6))).norm()) <=
        grip_test::roundoff<S>(1, 1, std::sqrt(41.0)));
  Wrench<S> w = Wrench<S>::Zero();
  w.template head<3>() << S(4), S(0), S(-2);
  const Vector3<S> before = b.linear_momentum();
  REQUIRE(step_free<S>(b, w, S(0.01)) == Status::Ok);
  // F / m, the half step's product and the two kicks' sums (4 roundings of |v|, times m), m v
  // twice and their difference (3 of |m v|), the reference's rounding (1): k = 8 of |m v|.
  CHECK(double((b.linear_momentum() - before - Vector3<S>(S(0.04), S(0), S(-0.02))).norm()) <=
        grip_test::roundoff<S>(8, 1, double(b.linear_momentum().norm())));
}
