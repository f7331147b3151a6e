// The hand's Jacobians and joint torques: finite differences, virtual work, a hand-solved case.
#include <doctest/doctest.h>

#include <cmath>
#include <limits>
#include <random>

#include <grip/hand/hand_jacobian.hpp>

#include "support/allocation_counter.hpp"
#include "support/random.hpp"

// Named, not anonymous: the unity build puts several test files in one translation unit.
namespace hand_jacobian_tests {
using namespace grip;

namespace {
using Iso = Eigen::Transform<double, 3, Eigen::Isometry>;

// A point fixed to phalanx k, by coordinates in the phalanx's own frame: along its axis (a
// fraction of its length), along its joint axis, and along their cross product (m).
struct BodyPoint {
  int k;
  double along, lateral, normal;
  Eigen::Vector3d at(const HandPosture<double>& h) const {
    const PhalanxCapsule<double>& c = h.phalanges[detail::idx(k)];
    if (phalanx_joint(k) < 0) return c.base + along * (c.tip - c.base);  // a finger's metacarpal: fixed
    const Eigen::Vector3d a = h.joints[detail::idx(phalanx_joint(k))].axis;
    const Eigen::Vector3d u = (c.tip - c.base).normalized();
    return c.base + along * (c.tip - c.base) + lateral * a + normal * a.cross(u);
  }
};

HandJoints<double> random_joints(std::mt19937& g, const JointLimits<double>& l) {
  const grip_test::Uniform u(0, 1);
  HandJoints<double> q;
  for (int i = 0; i < hand_dof_count; ++i) {
    const double t = u(g);
    q(i) = (1 - t) * l.lower[detail::idx(i)] + t * l.upper[detail::idx(i)];
  }
  return q;
}

Iso random_wrist(std::mt19937& g) {
  const grip_test::Uniform u(-1, 1);
  Iso T = Iso::Identity();
  const Eigen::Vector3d axis = grip_test::draw3(g, u).normalized();
  const double angle = 3 * u(g);
  T.linear() = Eigen::AngleAxisd(angle, axis).toRotationMatrix();
  T.translation() = grip_test::draw3(g, u);
  return T;
}

HandPosture<double> pose(const HandDimensions<double>& d, const Iso& T, const HandJoints<double>& q) {
  HandPosture<double> h;
  REQUIRE(forward_kinematics(d, T, q, h) == Status::Ok);
  return h;
}
}  // namespace

TEST_CASE("point Jacobians match central differences at random postures of both hands") {
  std::mt19937 g(2020);
  const grip_test::Uniform frac(0, 1), off(-0.01, 0.01);
  for (Side side : {Side::Right, Side::Left}) {
    const HandDimensions<double> d = HandDimensions<double>::standard(0.19, side);
    for (int trial = 0; trial < 20; ++trial) {
      const HandJoints<double> q = random_joints(g, d.limits);
      const Iso T = random_wrist(g);
      const HandPosture<double> h = pose(d, T, q);
      for (int k = 0; k < hand_body_count; ++k) {  // the phalanges and the palm's metacarpals
        const double along = frac(g), lateral = off(g), normal = off(g);
        const BodyPoint b{k, along, lateral, normal};
        PointJacobian<double> J;
        REQUIRE(point_jacobian(h, k, b.at(h), J) == Status::Ok);
        // Central differences: truncation h^2 |p'''| / 6 with |p'''| below the hand's reach
        // (0.2 m), about 1e-11 for h = 1e-5, and round-off u |p| / h, about 1e-11 (|p| <= 2 m).
        const double step = 1e-5;
        PointJacobian<double> fd;
        for (int i = 0; i < hand_dof_count; ++i) {
          HandJoints<double> qp = q, qm = q;
          qp(i) += step;
          qm(i) -= step;
          fd.col(i) = (b.at(pose(d, T, qp)) - b.at(pose(d, T, qm))) / (2 * step);
        }
        CHECK((J - fd).cwiseAbs().maxCoeff() <= 1e-9);
        // Columns of the joints that do not move phalanx k are exactly zero.
        for (int i = 0; i < hand_dof_count; ++i)
          if (i / 4 != static_cast<int>(phalanx_finger(k)) || i > phalanx_joint(k)) CHECK(J.col(i).isZero(0));
      }
    }
  }
}

TEST_CASE("joint torques do the virtual work of the contact forces (tau = J^T f)") {
  std::mt19937 g(4242);
  const grip_test::Uniform frac(0, 1), off(-0.01, 0.01), force(-5, 5), dq(-1e-6, 1e-6);
  const HandDimensions<double> d = HandDimensions<double>::standard();
  for (int trial = 0; trial < 30; ++trial) {
    const HandJoints<double> q = random_joints(g, d.limits);
    const Iso T = random_wrist(g);
    const HandPosture<double> h = pose(d, T, q);
    // Forces on five random phalanges at random points of them.
    BodyPoint points[5];
    Eigen::Vector3d forces[5];
    HandJoints<double> tau = HandJoints<double>::Zero();
    for (int c = 0; c < 5; ++c) {
      const int k = static_cast<int>(frac(g) * hand_body_count);
      const double along = frac(g), lateral = off(g), normal = off(g);
      points[c] = BodyPoint{k, along, lateral, normal};
      forces[c] = grip_test::draw3(g, force);
      REQUIRE(add_joint_torques(h, k, points[c].at(h), forces[c], tau) == Status::Ok);
    }
    // A small joint displacement: the forces' work on the points' displacements (central
    // difference, second order) equals tau . delta.
    HandJoints<double> delta;
    for (int i = 0; i < hand_dof_count; ++i) delta(i) = dq(g);
    const HandPosture<double> hp = pose(d, T, q + delta), hm = pose(d, T, q - delta);
    double work = 0;
    for (int c = 0; c < 5; ++c) work += forces[c].dot(points[c].at(hp) - points[c].at(hm)) / 2;
    // Work is about |f| |J| |delta| ~ 5e-7 J; the difference's round-off u |p| |f| / 1 ~ 1e-15.
    CHECK(std::abs(work - tau.dot(delta)) <= 1e-13);
    // Holding the hand still: joint torques -tau and the forces do no net work (statics).
    CHECK(std::abs(work + (-tau).dot(delta)) <= 1e-13);
  }
}

TEST_CASE("a hand-solved case: an upward push on the straight index fingertip") {
  const HandDimensions<double> d = HandDimensions<double>::standard();
  const HandPosture<double> h = pose(d, Iso::Identity(), HandJoints<double>::Zero());
  // Finger along +x, flexion about +y: F = (0, 0, 2) N at the tip, at distances l_p + l_m + l_d,
  // l_m + l_d and l_d from the MCP, PIP and DIP: tau = y . (r x F) = -2 r (it extends the finger);
  // about the abduction axis +z the moment is 0.
  const double lp = 0.265 * 0.19, lm = 0.143 * 0.19, ld = 0.097 * 0.19;
  HandJoints<double> tau = HandJoints<double>::Zero();
  REQUIRE(add_joint_torques(h, 4, h.phalanges[4].tip, Eigen::Vector3d(0, 0, 2), tau) == Status::Ok);
  CHECK(tau(4) == doctest::Approx(0).epsilon(1e-12));
  CHECK(tau(5) == doctest::Approx(-2 * (lp + lm + ld)));
  CHECK(tau(6) == doctest::Approx(-2 * (lm + ld)));
  CHECK(tau(7) == doctest::Approx(-2 * ld));
  for (int i : {0, 1, 2, 3, 8, 12, 16}) CHECK(tau(i) == 0);
  // A sideways push (-y, ulnar) abducts it back: about +z, r x F = (L, 0, 0) x (0, -1, 0) = -L z.
  HandJoints<double> side = HandJoints<double>::Zero();
  REQUIRE(add_joint_torques(h, 4, h.phalanges[4].tip, Eigen::Vector3d(0, -1, 0), side) == Status::Ok);
  CHECK(side(4) == doctest::Approx(-(lp + lm + ld)));
}

TEST_CASE("Jacobian and torques: bad input is InvalidInput, nothing allocates") {
  const HandDimensions<double> d = HandDimensions<double>::standard();
  const HandPosture<double> h = pose(d, Iso::Identity(), HandJoints<double>::Constant(0.2));
  PointJacobian<double> J = PointJacobian<double>::Constant(7);
  HandJoints<double> tau = HandJoints<double>::Zero();
  {
    grip_test::NoHeapScope scope;
    CHECK(point_jacobian(h, 3, h.phalanges[3].tip, J) == Status::Ok);
    CHECK(add_joint_torques(h, 3, h.phalanges[3].tip, Eigen::Vector3d(1, 2, 3), tau) == Status::Ok);
    CHECK(scope.allocations() == 0);
  }
  const PointJacobian<double> J0 = J;
  const HandJoints<double> tau0 = tau;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  CHECK(point_jacobian(h, 19, h.phalanges[3].tip, J) == Status::InvalidInput);
  CHECK(point_jacobian(h, -1, h.phalanges[3].tip, J) == Status::InvalidInput);
  CHECK(point_jacobian(h, 3, Eigen::Vector3d(nan, 0, 0), J) == Status::InvalidInput);
  CHECK(add_joint_torques(h, 3, h.phalanges[3].tip, Eigen::Vector3d(nan, 0, 0), tau) == Status::InvalidInput);
  CHECK(J == J0);
  CHECK(tau == tau0);
}

}  // namespace hand_jacobian_tests
