// Glove mappings: calibration, 14 and 22 sensors to the 20 joints, statuses.
#include <doctest/doctest.h>

#include <cmath>
#include <limits>
#include <random>
#include <string>

#include <grip/hand/glove.hpp>

#include "support/allocation_counter.hpp"
#include "support/random.hpp"

// Named, not anonymous: the unity build puts several test files in one translation unit.
namespace glove_tests {
using namespace grip;

namespace {
// A random calibration: offsets in raw units, gains of either sign, a generous valid range.
template <class S, int N>
GloveCalibration<S, N> random_calibration(std::mt19937& g) {
  GloveCalibration<S, N> c;
  const grip_test::Uniform offset(-500, 500), gain(0.002, 0.02), sign(0, 1);
  for (std::size_t i = 0; i < std::size_t(N); ++i) {
    c.offset[i] = S(offset(g));
    const double m = gain(g);
    c.gain[i] = S(sign(g) < 0.5 ? -m : m);
    c.raw_min[i] = S(-1e5);
    c.raw_max[i] = S(1e5);
  }
  return c;
}
// Joints drawn within the limits, shrunk by 1 % so that round-off cannot cross a limit.
template <class S>
HandJoints<S> random_joints(std::mt19937& g, const JointLimits<S>& l) {
  HandJoints<S> q;
  const grip_test::Uniform u(0.01, 0.99);
  for (int i = 0; i < hand_dof_count; ++i) {
    const double t = u(g);
    q(i) = S((1 - t) * double(l.lower[std::size_t(i)]) + t * double(l.upper[std::size_t(i)]));
  }
  return q;
}
}  // namespace

TEST_CASE_TEMPLATE("calibration: angle = gain (raw - offset), clamped readings say OutOfRange", S, double, float) {
  GloveCalibration<S, 2> c;
  c.offset = {S(100), S(-20)};
  c.gain = {S(0.01), S(-0.5)};
  c.raw_min = {S(0), S(-40)};
  c.raw_max = {S(300), S(0)};
  Eigen::Matrix<S, 2, 1> a;
  CHECK(c.angles(Eigen::Matrix<S, 2, 1>(S(150), S(-22)), a) == Status::Ok);
  CHECK(a(0) == doctest::Approx(0.5));  // 0.01 (150 - 100)
  CHECK(a(1) == doctest::Approx(1.0));  // -0.5 (-22 + 20)
  CHECK(c.angles(Eigen::Matrix<S, 2, 1>(S(400), S(-22)), a) == Status::OutOfRange);
  CHECK(std::string(to_string(Status::OutOfRange)) == "out of range");
  CHECK(a(0) == doctest::Approx(2.0));  // clamped to 300
  const Eigen::Matrix<S, 2, 1> before = a;
  CHECK(c.angles(Eigen::Matrix<S, 2, 1>(std::numeric_limits<S>::quiet_NaN(), S(0)), a) == Status::InvalidInput);
  CHECK(a == before);
  c.gain[1] = S(0);
  CHECK(c.angles(Eigen::Matrix<S, 2, 1>(S(1), S(0)), a) == Status::InvalidInput);
}

TEST_CASE_TEMPLATE("22-sensor glove: readings round-trip through any calibration", S, double, float) {
  std::mt19937 g(2211);
  const JointLimits<S> limits = JointLimits<S>::standard();
  for (int trial = 0; trial < 50; ++trial) {
    Glove22<S> glove;
    glove.calibration = random_calibration<S, 22>(g);
    HandJoints<S> q = random_joints(g, limits);
    q(static_cast<int>(HandJoint::LongAbduction)) = S(0);  // the reference the glove reads against
    const GloveExtras<S> extras{S(0.1), S(-0.2), S(0.15)};
    const typename Glove22<S>::Readings raw = glove.readings(q, extras);
    HandJoints<S> back;
    GloveExtras<S> got;
    REQUIRE(glove.map(raw, limits, back, &got) == Status::Ok);
    // Each joint passes through raw = offset + a / gain and back: a few roundings of the raw
    // reading's size (|offset| + |a / gain|, up to 2000) times the gain.
    const double tol = 8 * double(std::numeric_limits<S>::epsilon()) * 2000 * 0.02;
    CHECK(double((back - q).cwiseAbs().maxCoeff()) <= tol);
    CHECK(std::abs(double(got.wrist_flexion) + 0.2) <= tol);
    CHECK(std::abs(double(got.palm_arch) - 0.1) <= tol);
  }
}

TEST_CASE_TEMPLATE("22-sensor glove: abductions are relative to the long finger", S, double, float) {
  Glove22<S> glove;  // identity calibration: readings are angles
  typename Glove22<S>::Readings raw = Glove22<S>::Readings::Zero();
  raw(7) = S(0.1);    // index and long 0.1 apart
  raw(14) = S(0.05);  // long and ring
  raw(18) = S(0.08);  // ring and little
  HandJoints<S> q;
  REQUIRE(glove.map(raw, JointLimits<S>::standard(), q) == Status::Ok);
  CHECK(q(static_cast<int>(HandJoint::IndexAbduction)) == doctest::Approx(0.1));
  CHECK(q(static_cast<int>(HandJoint::LongAbduction)) == S(0));
  CHECK(q(static_cast<int>(HandJoint::RingAbduction)) == doctest::Approx(-0.05));
  CHECK(q(static_cast<int>(HandJoint::LittleAbduction)) == doctest::Approx(-0.13));
  // A spread beyond the little finger's 20 degrees is clamped and reported.
  raw(18) = S(0.5);
  CHECK(glove.map(raw, JointLimits<S>::standard(), q) == Status::OutOfRange);
  CHECK(q(static_cast<int>(HandJoint::LittleAbduction)) == JointLimits<S>::standard().lower[16]);
}

TEST_CASE_TEMPLATE("14-sensor glove: round trip, the thumb's CMC follows its MCP, DIP coupling", S, double, float) {
  std::mt19937 g(1414);
  const JointLimits<S> limits = JointLimits<S>::standard();
  for (int trial = 0; trial < 50; ++trial) {
    Glove14<S> glove;
    glove.calibration = random_calibration<S, 14>(g);
    const HandJoints<S> q = random_joints(g, limits);
    HandJoints<S> back;
    REQUIRE(glove.map(glove.readings(q), limits, back) == Status::Ok);
    const double tol = 8 * double(std::numeric_limits<S>::epsilon()) * 2000 * 0.02;
    for (int k = 0; k < 14; ++k) CHECK(std::abs(double(back(phalanx_joint(k)) - q(phalanx_joint(k)))) <= tol);
    for (int f = 1; f < 5; ++f) CHECK(back(4 * f) == S(0));  // no abduction sensors
    // CMC: the thumb MCP's fraction of its upper limit, times the opposition posture.
    const double share = std::max(0.0, double(q(2)) / double(limits.upper[2]));
    CHECK(std::abs(double(back(0)) - share * double(glove.opposition[0])) <= 8 * tol);
    CHECK(std::abs(double(back(1)) - share * double(glove.opposition[1])) <= 8 * tol);
  }
  Glove14<S> glove;
  glove.couple_dip = true;
  typename Glove14<S>::Readings raw = Glove14<S>::Readings::Zero();
  raw(3) = S(0.9);  // index PIP
  raw(4) = S(0.1);  // index DIP: ignored when coupled
  HandJoints<S> q;
  {
    grip_test::NoHeapScope scope;
    CHECK(glove.map(raw, JointLimits<S>::standard(), q) == Status::Ok);
    CHECK(scope.allocations() == 0);
  }
  CHECK(q(static_cast<int>(HandJoint::IndexDip)) == doctest::Approx(0.6));
  CHECK(q(0) == S(0));  // the open thumb stays flat: MCP 0
  raw(5) = std::numeric_limits<S>::infinity();
  const HandJoints<S> before = q;
  CHECK(glove.map(raw, JointLimits<S>::standard(), q) == Status::InvalidInput);
  CHECK(q == before);
}

}  // namespace glove_tests
