// Device policies: each clips as documented, brakes never drive a joint.
#include <doctest/doctest.h>

#include <cmath>
#include <limits>
#include <random>

#include <grip/pipeline/device_policy.hpp>

#include "support/allocation_counter.hpp"
#include "support/random.hpp"

// Named, not anonymous: the unity build puts several test files in one translation unit.
namespace device_policy_tests {
using namespace grip;

namespace {
using Iso = Eigen::Transform<double, 3, Eigen::Isometry>;

HandPosture<double> open_hand() {
  HandPosture<double> h;
  REQUIRE(forward_kinematics(HandDimensions<double>::standard(), Iso::Identity(), HandJoints<double>::Zero(), h) ==
          Status::Ok);
  return h;
}

// Random felt forces (N) at random points of random postures.
FeltForces<double> random_felt(std::mt19937& g, const HandPosture<double>& h, double scale) {
  const grip_test::Uniform u(-scale, scale), t(0, 1);
  FeltForces<double> in;
  for (std::size_t k = 0; k < 14; ++k) {
    const Eigen::Vector3d f = grip_test::draw3(g, u);
    const double s = t(g);
    in.add(static_cast<int>(k), f, h.phalanges[k].base + s * (h.phalanges[k].tip - h.phalanges[k].base));
  }
  in.finish(h);
  return in;
}

HandPosture<double> random_posture(std::mt19937& g) {
  const HandDimensions<double> d = HandDimensions<double>::standard();
  const grip_test::Uniform u(0, 1);
  HandJoints<double> q;
  for (int i = 0; i < 20; ++i) {
    const double s = u(g);
    q(i) = (1 - s) * d.limits.lower[detail::idx(i)] + s * d.limits.upper[detail::idx(i)];
  }
  HandPosture<double> h;
  REQUIRE(forward_kinematics(d, Iso::Identity(), q, h) == Status::Ok);
  return h;
}
}  // namespace

TEST_CASE("phalanx actuators push along extension only, up to their limit") {
  const HandPosture<double> h = open_hand();
  // The straight index finger (along +x, flexing about +y) is extended by pushes along +z.
  CHECK((actuation_direction(h, 3) - Eigen::Vector3d(0, 0, 1)).norm() <= 1e-15);
  PhalanxActuators<double> dev;
  dev.limit.fill(4);
  FeltForces<double> in;
  in.add(3, Eigen::Vector3d(1, 0, 3), h.phalanges[3].tip);   // within the limit: 3 N along +z
  in.add(4, Eigen::Vector3d(0, 0, 6), h.phalanges[4].tip);   // beyond: 4 N
  in.add(7, Eigen::Vector3d(0, 0, -2), h.phalanges[7].tip);  // pulling: 0
  in.finish(h);
  CHECK((in.direction[3] - Eigen::Vector3d(0, 0, 1)).norm() <= 1e-15);
  PhalanxActuators<double>::Command c;
  REQUIRE(dev.render(in, h, HandJoints<double>::Zero(), c) == Status::Ok);
  CHECK(c.force[3] == doctest::Approx(3));
  CHECK(c.force[4] == doctest::Approx(4));
  CHECK(c.force[7] == 0);
  CHECK(c.wanted[7] == doctest::Approx(-2));
  CHECK(c.clipped == 2);
}

TEST_CASE("vector forces saturate by norm, keeping the direction, and fingertips only") {
  std::mt19937 g(5);
  const HandPosture<double> h = random_posture(g);
  VectorForces<double> dev;
  dev.limit.fill(3);
  for (int trial = 0; trial < 20; ++trial) {
    const FeltForces<double> in = random_felt(g, h, 4);
    VectorForces<double>::Command c;
    REQUIRE(dev.render(in, h, HandJoints<double>::Zero(), c) == Status::Ok);
    int beyond = 0;
    for (std::size_t k = 0; k < 14; ++k) {
      const double n = in.force[k].norm();
      CHECK(c.force[k].norm() <= 3 * (1 + 1e-15));
      CHECK(c.force[k].cross(in.force[k]).norm() <= 1e-14 * n * n);  // parallel
      CHECK(c.force[k].dot(in.force[k]) >= 0);                       // same sense
      if (n <= 3)
        CHECK((c.force[k] - in.force[k]).norm() == 0);  // untouched below the limit
      else
        CHECK(c.force[k].norm() == doctest::Approx(3));  // by norm, not per component
      beyond += n > 3 ? 1 : 0;
    }
    CHECK(c.clipped == beyond);
  }
  dev.fingertips_only = true;
  const FeltForces<double> in = random_felt(g, h, 1);
  VectorForces<double>::Command c;
  REQUIRE(dev.render(in, h, HandJoints<double>::Zero(), c) == Status::Ok);
  for (int k = 0; k < 14; ++k) {
    if (phalanx_kind(k) == Phalanx::Distal)
      CHECK((c.force[detail::idx(k)] - in.force[detail::idx(k)]).norm() == 0);
    else
      CHECK(c.force[detail::idx(k)].norm() == 0);
  }
  CHECK(c.clipped == 9);  // the 9 proximal and middle phalanges render nothing
}

TEST_CASE("joint torques are J^T F summed over the phalanges, each clipped to its limit") {
  std::mt19937 g(6);
  JointTorques<double> dev;
  dev.limit.fill(0.05);
  for (int trial = 0; trial < 20; ++trial) {
    const HandPosture<double> h = random_posture(g);
    const FeltForces<double> in = random_felt(g, h, 3);
    // The reference: each phalanx's Jacobian, transposed, times its force.
    HandJoints<double> want = HandJoints<double>::Zero();
    for (int k = 0; k < 14; ++k) {
      PointJacobian<double> J;
      REQUIRE(point_jacobian(h, k, in.point[detail::idx(k)], J) == Status::Ok);
      want += J.transpose() * in.force[detail::idx(k)];
    }
    JointTorques<double>::Command c;
    REQUIRE(dev.render(in, h, HandJoints<double>::Zero(), c) == Status::Ok);
    CHECK((c.wanted - want).cwiseAbs().maxCoeff() <= 1e-14);
    int beyond = 0;
    for (int i = 0; i < 20; ++i) {
      CHECK(std::abs(c.torque(i)) <= 0.05);
      if (std::abs(want(i)) <= 0.05)
        CHECK(c.torque(i) == c.wanted(i));
      else
        CHECK(c.torque(i) == doctest::Approx(want(i) > 0 ? 0.05 : -0.05));
      beyond += std::abs(c.wanted(i)) > 0.05 ? 1 : 0;
    }
    CHECK(c.clipped == beyond);
  }
}

TEST_CASE("brakes only resist: the rendered torque never drives a joint along its velocity") {
  std::mt19937 g(7);
  const grip_test::Uniform v(-2, 2);
  JointBrakes<double> dev;
  dev.limit.fill(0.05);
  int resisting = 0, refused = 0;
  for (int trial = 0; trial < 50; ++trial) {
    const HandPosture<double> h = random_posture(g);
    const FeltForces<double> in = random_felt(g, h, 3);
    HandJoints<double> qdot;
    for (int i = 0; i < 20; ++i) qdot(i) = v(g);
    qdot(5) = 0;  // a joint at rest can be held either way
    JointBrakes<double>::Command c;
    REQUIRE(dev.render(in, h, qdot, c) == Status::Ok);
    for (int i = 0; i < 20; ++i) {
      CHECK(c.torque(i) * qdot(i) <= 0);  // dissipative: never pushes
      CHECK(std::abs(c.torque(i)) <= 0.05);
      if (c.wanted(i) * qdot(i) > 0) {
        CHECK(c.torque(i) == 0);
        ++refused;
      } else {
        CHECK(c.torque(i) == doctest::Approx(std::max(-0.05, std::min(0.05, c.wanted(i)))));
        ++resisting;
      }
    }
    CHECK(c.torque(5) == doctest::Approx(std::max(-0.05, std::min(0.05, c.wanted(5)))));
  }
  CHECK(resisting > 100);  // both cases were exercised
  CHECK(refused > 100);
}

namespace {
// The brake rule of device_policy.hpp, written from its comment: the wanted torque tau (J^T F)
// is rendered only where it resists the joint's motion, tau qdot <= 0 (at rest, qdot = 0, it is
// held either way), clipped to [-limit, limit]; where it would drive the joint along its
// velocity the brake renders 0. The wanted torques come from each phalanx's Jacobian, as in the
// joint-torque test above, not from the device.
HandJoints<double> wanted_torques(const HandPosture<double>& h, const FeltForces<double>& in) {
  HandJoints<double> want = HandJoints<double>::Zero();
  for (int k = 0; k < 14; ++k) {
    PointJacobian<double> J;
    REQUIRE(point_jacobian(h, k, in.point[detail::idx(k)], J) == Status::Ok);
    want += J.transpose() * in.force[detail::idx(k)];
  }
  return want;
}

// A brake of a different limit per joint, 0.02 .. 0.115 N m, so that a limit read from the
// wrong joint shows.
JointBrakes<double> graded_brakes() {
  JointBrakes<double> dev;
  for (std::size_t i = 0; i < 20; ++i) dev.limit[i] = 0.02 + 0.005 * double(i);
  return dev;
}

// Checks joint i of a brake's command against the rule for velocity v: 0 while the wanted
// torque would drive the joint along v; otherwise the wanted torque's sign (against v) and its
// size up to the limit, exactly the limit beyond it. Returns whether the brake changed it.
bool check_brake(const JointBrakes<double>::Command& c, const HandJoints<double>& want, const JointBrakes<double>& dev,
                 int i, double v) {
  CAPTURE(i);
  CAPTURE(v);
  const double w = want(i), l = dev.limit[detail::idx(i)], t = c.torque(i);
  REQUIRE(std::abs(c.wanted(i) - w) <= 1e-14);
  REQUIRE(std::abs(w) > 1e-6);  // the sign of the wanted torque is clear
  CHECK(std::abs(t) <= l);
  // By the signs: a product of a torque and a subnormal speed underflows to 0.
  const auto same_sign = [](double x, double y) { return (x > 0 && y > 0) || (x < 0 && y < 0); };
  CHECK_FALSE(same_sign(t, v));  // never drives the joint
  if (same_sign(w, v)) {
    CHECK(t == 0);
    return true;
  }
  CHECK((t > 0) == (w > 0));
  if (std::abs(w) > l) {
    CHECK(std::abs(t) == l);
    return true;
  }
  CHECK(std::abs(t - w) <= 1e-14);
  return false;
}
}  // namespace

TEST_CASE("brakes at rest hold either way, each up to its own limit") {
  std::mt19937 g(71);
  const JointBrakes<double> dev = graded_brakes();
  int positive = 0, negative = 0, at_limit = 0, within = 0;
  for (int trial = 0; trial < 20; ++trial) {
    const HandPosture<double> h = random_posture(g);
    const FeltForces<double> in = random_felt(g, h, 2);
    const HandJoints<double> want = wanted_torques(h, in);
    HandJoints<double> qdot = HandJoints<double>::Zero();
    for (int i = 0; i < 20; i += 2) qdot(i) = -0.0;  // a negative zero is at rest too
    JointBrakes<double>::Command c;
    REQUIRE(dev.render(in, h, qdot, c) == Status::Ok);
    int changed = 0;
    for (int i = 0; i < 20; ++i) {
      changed += check_brake(c, want, dev, i, qdot(i)) ? 1 : 0;
      CHECK(c.torque(i) != 0);  // held, whichever the sign
      positive += want(i) > 0 ? 1 : 0;
      negative += want(i) < 0 ? 1 : 0;
      at_limit += std::abs(want(i)) > dev.limit[detail::idx(i)] ? 1 : 0;
      within += std::abs(want(i)) <= dev.limit[detail::idx(i)] ? 1 : 0;
    }
    CHECK(c.clipped == changed);
  }
  // Both signs, and torques both within and beyond the limits, were held.
  CHECK(positive > 50);
  CHECK(negative > 50);
  CHECK(at_limit > 50);
  CHECK(within > 50);
}

TEST_CASE("brakes at speed resist with the torque's sign up to the limit, and never drive") {
  std::mt19937 g(72);
  const JointBrakes<double> dev = graded_brakes();
  int refused = 0, limited = 0;
  for (int trial = 0; trial < 20; ++trial) {
    const HandPosture<double> h = random_posture(g);
    const FeltForces<double> in = random_felt(g, h, 2);
    const HandJoints<double> want = wanted_torques(h, in);
    for (const double speed : {0.5, 3.0}) {
      // Every joint moving against its wanted torque: all rendered (clipped to the limits).
      HandJoints<double> against, along;
      for (int i = 0; i < 20; ++i) {
        against(i) = want(i) > 0 ? -speed : speed;
        along(i) = -against(i);
      }
      JointBrakes<double>::Command c;
      REQUIRE(dev.render(in, h, against, c) == Status::Ok);
      int changed = 0;
      for (int i = 0; i < 20; ++i) {
        const bool beyond = std::abs(want(i)) > dev.limit[detail::idx(i)];
        CHECK(check_brake(c, want, dev, i, against(i)) == beyond);
        limited += beyond ? 1 : 0;
        changed += beyond ? 1 : 0;
      }
      CHECK(c.clipped == changed);
      // Every joint moving along its wanted torque: nothing rendered, all 20 counted.
      REQUIRE(dev.render(in, h, along, c) == Status::Ok);
      for (int i = 0; i < 20; ++i) CHECK(check_brake(c, want, dev, i, along(i)));
      CHECK(c.torque.cwiseAbs().maxCoeff() == 0);
      CHECK(c.clipped == 20);
      refused += 20;
    }
  }
  CHECK(limited > 100);
  CHECK(refused > 100);
}

TEST_CASE("brakes at the velocity's sign change: off while driven, full resistance from rest on") {
  // Each joint's velocity crosses zero, from along its wanted torque to against it, through
  // the smallest normal and subnormal speeds (whose product with the torque underflows to 0)
  // and both zeros (and back): the brake renders nothing while the joint moves along the
  // torque, and from rest on the torque's sign, clipped to the limit, at once.
  const double tiny = std::numeric_limits<double>::min(), least = std::numeric_limits<double>::denorm_min();
  const double sweep[] = {2.0, 1e-3, 1e-300, tiny, least, 0.0, -0.0, -least, -tiny, -1e-300, -1e-3, -2.0};
  constexpr std::size_t steps = sizeof sweep / sizeof sweep[0];
  std::mt19937 g(73);
  const JointBrakes<double> dev = graded_brakes();
  for (int trial = 0; trial < 10; ++trial) {
    const HandPosture<double> h = random_posture(g);
    const FeltForces<double> in = random_felt(g, h, 2);
    const HandJoints<double> want = wanted_torques(h, in);
    for (const bool backwards : {false, true}) {
      for (std::size_t step = 0; step < steps; ++step) {
        const double s = sweep[backwards ? steps - 1 - step : step];  // > 0: along the wanted torque
        HandJoints<double> qdot;
        for (int i = 0; i < 20; ++i) qdot(i) = want(i) > 0 ? s : -s;
        JointBrakes<double>::Command c;
        REQUIRE(dev.render(in, h, qdot, c) == Status::Ok);
        for (int i = 0; i < 20; ++i) {
          check_brake(c, want, dev, i, qdot(i));
          const double l = dev.limit[detail::idx(i)];
          const double resisting = std::max(-l, std::min(l, want(i)));
          if (s > 0)
            CHECK(c.torque(i) == 0);
          else
            CHECK(std::abs(c.torque(i) - resisting) <= 1e-14);
        }
      }
    }
  }
}

TEST_CASE("device policies: bad input is InvalidInput with a zero command, nothing allocates") {
  std::mt19937 g(8);
  const HandPosture<double> h = random_posture(g);
  FeltForces<double> in = random_felt(g, h, 1);
  const HandJoints<double> qdot = HandJoints<double>::Constant(0.1);
  PhalanxActuators<double>::Command a;
  VectorForces<double>::Command b;
  JointTorques<double>::Command c;
  JointBrakes<double>::Command d;
  {
    grip_test::NoHeapScope scope;
    CHECK(PhalanxActuators<double>{}.render(in, h, qdot, a) == Status::Ok);
    CHECK(VectorForces<double>{}.render(in, h, qdot, b) == Status::Ok);
    CHECK(JointTorques<double>{}.render(in, h, qdot, c) == Status::Ok);
    CHECK(JointBrakes<double>{}.render(in, h, qdot, d) == Status::Ok);
    CHECK(scope.allocations() == 0);
  }
  in.force[6].x() = std::numeric_limits<double>::quiet_NaN();
  CHECK(PhalanxActuators<double>{}.render(in, h, qdot, a) == Status::InvalidInput);
  CHECK(VectorForces<double>{}.render(in, h, qdot, b) == Status::InvalidInput);
  CHECK(JointTorques<double>{}.render(in, h, qdot, c) == Status::InvalidInput);
  CHECK(JointBrakes<double>{}.render(in, h, qdot, d) == Status::InvalidInput);
  CHECK(a.force[0] == 0);
  CHECK(b.force[0].norm() == 0);
  CHECK(c.torque.norm() == 0);
  CHECK(d.torque.norm() == 0);
  in.force[6].x() = 0;
  JointTorques<double> negative;
  negative.limit[3] = -1;
  CHECK(negative.render(in, h, qdot, c) == Status::InvalidInput);
  CHECK(JointBrakes<double>{}.render(in, h, HandJoints<double>::Constant(std::numeric_limits<double>::infinity()), d) ==
        Status::InvalidInput);
}

}  // namespace device_policy_tests
