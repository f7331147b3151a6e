// The whole hand's 20 joints: layout, limits, DIP coupling.
#include <doctest/doctest.h>

#include <cmath>
#include <limits>

#include <grip/hand/hand_joints.hpp>
#include <grip/hand/hand_model.hpp>

// Named, not anonymous: the unity build puts several test files in one translation unit.
namespace hand_joints_tests {
using namespace grip;

TEST_CASE("joint layout: four per digit, phalanx k moved by its digit's joints up to its own") {
  static_assert(hand_dof_count == 20, "20 joints");
  // The layout of hand_joints.hpp, written out: phalanx k's own (innermost) joint.
  const int own[14] = {2, 3, 5, 6, 7, 9, 10, 11, 13, 14, 15, 17, 18, 19};
  for (int k = 0; k < 14; ++k) CHECK(phalanx_joint(k) == own[k]);
  CHECK(joint_index(Finger::Thumb, 0) == static_cast<int>(HandJoint::ThumbCmcFlexion));
  CHECK(joint_index(Finger::Thumb, 1) == static_cast<int>(HandJoint::ThumbCmcAbduction));
  CHECK(joint_index(Finger::Ring, 0) == static_cast<int>(HandJoint::RingAbduction));
  CHECK(joint_index(Finger::Little, 3) == static_cast<int>(HandJoint::LittleDip));
  CHECK(static_cast<int>(HandJoint::LongPip) == 10);
}

TEST_CASE_TEMPLATE("joint limits: the documented ranges, contains and clamp", S, double, float) {
  const JointLimits<S> l = JointLimits<S>::standard();
  const double deg = 3.141592653589793 / 180.0;
  // Ranges typed from the documentation (degrees), not from the code.
  const double lo[20] = {-15, 0, -10, -15, -20, -20, 0, 0, -20, -20, 0, 0, -20, -20, 0, 0, -20, -20, 0, 0};
  const double hi[20] = {45, 60, 80, 90, 20, 90, 110, 90, 20, 90, 110, 90, 20, 90, 110, 90, 20, 90, 110, 90};
  for (std::size_t i = 0; i < 20; ++i) {
    CHECK(std::abs(double(l.lower[i]) - lo[i] * deg) <= 4 * double(std::numeric_limits<S>::epsilon()));
    CHECK(std::abs(double(l.upper[i]) - hi[i] * deg) <= 4 * double(std::numeric_limits<S>::epsilon()) * 2);
  }
  HandJoints<S> q = HandJoints<S>::Zero();
  CHECK(l.contains(q));
  q(6) = S(2.5);                               // index PIP beyond 110 deg
  q(4) = S(-1);                                // index abduction below -20 deg
  q(0) = std::numeric_limits<S>::quiet_NaN();  // NaN: outside
  CHECK(!l.contains(q));
  CHECK(l.clamp(q) == 3);
  CHECK(q(6) == l.upper[6]);
  CHECK(q(4) == l.lower[4]);
  CHECK(q(0) == l.lower[0]);
  CHECK(l.contains(q));
  CHECK(l.clamp(q) == 0);
}

TEST_CASE_TEMPLATE("couple_dip sets each finger's DIP to 2/3 of its PIP, not the thumb's IP", S, double, float) {
  HandJoints<S> q = HandJoints<S>::Constant(S(0.3));
  q(6) = S(0.9);
  q(18) = S(1.2);
  couple_dip(q);
  CHECK(q(7) == doctest::Approx(0.6));
  CHECK(q(19) == doctest::Approx(0.8));
  CHECK(q(11) == doctest::Approx(0.2));
  CHECK(q(3) == S(0.3));  // the thumb's IP is no DIP
}

}  // namespace hand_joints_tests
