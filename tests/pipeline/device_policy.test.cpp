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
      if (n <= 3) CHECK((c.force[k] - in.force[k]).norm() == 0);       // untouched below the limit
      else CHECK(c.force[k].norm() == doctest::Approx(3));             // by norm, not per component
      beyond += n > 3 ? 1 : 0;
    }
    CHECK(c.clipped == beyond);
  }
  dev.fingertips_only = true;
  const FeltForces<double> in = random_felt(g, h, 1);
  VectorForces<double>::Command c;
  REQUIRE(dev.render(in, h, HandJoints<double>::Zero(), c) == Status::Ok);
  for (int k = 0; k < 14; ++k) {
    if (phalanx_kind(k) == Phalanx::Distal) CHECK((c.force[detail::idx(k)] - in.force[detail::idx(k)]).norm() == 0);
    else CHECK(c.force[detail::idx(k)].norm() == 0);
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
      if (std::abs(want(i)) <= 0.05) CHECK(c.torque(i) == c.wanted(i));
      else CHECK(c.torque(i) == doctest::Approx(want(i) > 0 ? 0.05 : -0.05));
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
