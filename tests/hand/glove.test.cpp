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

namespace {
// The 22-sensor layout as glove.hpp's header documents it, written out here channel by channel
// (not read from the glove's table): the linear map from the 22 calibrated readings to the 20
// joints (rows 0 .. 19, hand_joints.hpp's order) and the three extras (rows 20 .. 22: palm
// arch, wrist flexion, wrist abduction). Flexion and thumb sensors read one joint each; the
// abduction sensors read spreads relative to the long finger (its abduction 0): index = s7,
// ring = -s14, little = ring - s18 = -s14 - s18.
Eigen::Matrix<double, 23, 22> documented_glove22_layout() {
  Eigen::Matrix<double, 23, 22> m = Eigen::Matrix<double, 23, 22>::Zero();
  const auto set = [&m](HandJoint j, int sensor, double sign) { m(static_cast<int>(j), sensor) = sign; };
  set(HandJoint::ThumbCmcFlexion, 0, 1);    // thumb rotation (CMC flexion)
  set(HandJoint::ThumbMcp, 1, 1);           // thumb MCP
  set(HandJoint::ThumbIp, 2, 1);            // thumb IP
  set(HandJoint::ThumbCmcAbduction, 3, 1);  // thumb abduction (CMC)
  set(HandJoint::IndexMcp, 4, 1);
  set(HandJoint::IndexPip, 5, 1);
  set(HandJoint::IndexDip, 6, 1);
  set(HandJoint::IndexAbduction, 7, 1);  // index-long spread
  set(HandJoint::LongMcp, 8, 1);
  set(HandJoint::LongPip, 9, 1);
  set(HandJoint::LongDip, 10, 1);
  set(HandJoint::RingMcp, 11, 1);
  set(HandJoint::RingPip, 12, 1);
  set(HandJoint::RingDip, 13, 1);
  set(HandJoint::RingAbduction, 14, -1);  // long-ring spread
  set(HandJoint::LittleAbduction, 14, -1);
  set(HandJoint::LittleMcp, 15, 1);
  set(HandJoint::LittlePip, 16, 1);
  set(HandJoint::LittleDip, 17, 1);
  set(HandJoint::LittleAbduction, 18, -1);  // ring-little spread
  m(20, 19) = 1;                            // palm arch
  m(21, 20) = 1;                            // wrist flexion
  m(22, 21) = 1;                            // wrist abduction (radial deviation)
  return m;
}

// A calibration whose offset and gain differ from channel to channel (gains of both signs), so
// that every channel's raw reading is distinct too.
template <class S>
GloveCalibration<S, 22> distinct_calibration() {
  GloveCalibration<S, 22> c;
  for (std::size_t i = 0; i < 22; ++i) {
    c.offset[i] = S(100 + 37 * double(i));
    c.gain[i] = S((i % 2 == 0 ? 1 : -1) * 0.001 * (1 + 0.1 * double(i)));
  }
  return c;
}

// The calibrated angle read on channel i in the tests below: distinct per channel, and small
// enough that all 22 at once keep every joint within JointLimits::standard() (the little
// finger's abduction, -(a14 + a18), is the largest at -0.284 rad against -20 deg).
double channel_angle(int i) { return 0.03 + 0.007 * double(i); }

// Round-off of a reading's angle: raw = offset + a / gain and back, raw readings below 1200
// units and gains up to 0.0031 rad a unit, a few roundings each, two readings summed at most.
template <class S>
double layout_tolerance() {
  return 16 * double(std::numeric_limits<S>::epsilon()) * 1200 * 0.0031;
}

template <class S>
Eigen::Matrix<double, 23, 1> mapped(const HandJoints<S>& q, const GloveExtras<S>& e) {
  Eigen::Matrix<double, 23, 1> out;
  out.template head<20>() = q.template cast<double>();
  out(20) = double(e.palm_arch);
  out(21) = double(e.wrist_flexion);
  out(22) = double(e.wrist_abduction);
  return out;
}
}  // namespace

TEST_CASE_TEMPLATE("22-sensor glove: each raw channel moves the joint its documented layout names", S, double, float) {
  const Eigen::Matrix<double, 23, 22> layout = documented_glove22_layout();
  const JointLimits<S> limits = JointLimits<S>::standard();
  Glove22<S> glove;
  glove.calibration = distinct_calibration<S>();
  const double tol = layout_tolerance<S>();
  // One channel at a time: every other channel reads its offset (angle 0), so channel i alone
  // must produce layout column i times its angle, and nothing anywhere else.
  for (int i = 0; i < 22; ++i) {
    CAPTURE(i);
    typename Glove22<S>::Readings raw;
    for (int j = 0; j < 22; ++j) raw(j) = glove.calibration.offset[std::size_t(j)];
    const double a = channel_angle(i);
    raw(i) = S(double(glove.calibration.offset[std::size_t(i)]) + a / double(glove.calibration.gain[std::size_t(i)]));
    HandJoints<S> q;
    GloveExtras<S> extras;
    REQUIRE(glove.map(raw, limits, q, &extras) == Status::Ok);
    const Eigen::Matrix<double, 23, 1> want = layout.col(i) * a;
    const Eigen::Matrix<double, 23, 1> got = mapped(q, extras);
    for (int r = 0; r < 23; ++r) {
      CAPTURE(r);
      CHECK(std::abs(got(r) - want(r)) <= tol);
    }
  }
  // All 22 at once, each with its own angle: the whole layout.
  Eigen::Matrix<double, 22, 1> angles;
  typename Glove22<S>::Readings raw;
  for (int i = 0; i < 22; ++i) {
    angles(i) = channel_angle(i);
    raw(i) = S(double(glove.calibration.offset[std::size_t(i)]) +
               angles(i) / double(glove.calibration.gain[std::size_t(i)]));
  }
  HandJoints<S> q;
  GloveExtras<S> extras;
  REQUIRE(glove.map(raw, limits, q, &extras) == Status::Ok);
  const Eigen::Matrix<double, 23, 1> want = layout * angles;
  const Eigen::Matrix<double, 23, 1> got = mapped(q, extras);
  for (int r = 0; r < 23; ++r) {
    CAPTURE(r);
    CHECK(std::abs(got(r) - want(r)) <= 2 * tol);
  }
}

TEST_CASE_TEMPLATE("22-sensor glove: readings put each joint on its documented channel", S, double, float) {
  // The inverse direction: the raw reading of every channel, from distinct joints and extras,
  // is offset + a / gain of the angle the documented layout gives that channel: a joint's own
  // angle, or for an abduction sensor the spread of its two neighbours (positive apart:
  // index - long, long - ring, ring - little), the long finger's abduction not being zero.
  Glove22<S> glove;
  glove.calibration = distinct_calibration<S>();
  HandJoints<S> q;
  for (int i = 0; i < hand_dof_count; ++i) q(i) = S(0.1 + 0.03 * i);  // flexions, distinct
  q(static_cast<int>(HandJoint::IndexAbduction)) = S(0.15);
  q(static_cast<int>(HandJoint::LongAbduction)) = S(0.05);
  q(static_cast<int>(HandJoint::RingAbduction)) = S(-0.07);
  q(static_cast<int>(HandJoint::LittleAbduction)) = S(-0.2);
  const GloveExtras<S> extras{S(0.33), S(-0.41), S(0.27)};
  const auto j = [&q](HandJoint h) { return double(q(static_cast<int>(h))); };
  const double expected[22] = {j(HandJoint::ThumbCmcFlexion),
                               j(HandJoint::ThumbMcp),
                               j(HandJoint::ThumbIp),
                               j(HandJoint::ThumbCmcAbduction),
                               j(HandJoint::IndexMcp),
                               j(HandJoint::IndexPip),
                               j(HandJoint::IndexDip),
                               j(HandJoint::IndexAbduction) - j(HandJoint::LongAbduction),
                               j(HandJoint::LongMcp),
                               j(HandJoint::LongPip),
                               j(HandJoint::LongDip),
                               j(HandJoint::RingMcp),
                               j(HandJoint::RingPip),
                               j(HandJoint::RingDip),
                               j(HandJoint::LongAbduction) - j(HandJoint::RingAbduction),
                               j(HandJoint::LittleMcp),
                               j(HandJoint::LittlePip),
                               j(HandJoint::LittleDip),
                               j(HandJoint::RingAbduction) - j(HandJoint::LittleAbduction),
                               double(extras.palm_arch),
                               double(extras.wrist_flexion),
                               double(extras.wrist_abduction)};
  const typename Glove22<S>::Readings raw = glove.readings(q, extras);
  for (int i = 0; i < 22; ++i) {
    CAPTURE(i);
    const double offset = double(glove.calibration.offset[std::size_t(i)]);
    const double gain = double(glove.calibration.gain[std::size_t(i)]);
    // The rounding of the raw reading, times the gain (layout_tolerance).
    CHECK(std::abs((double(raw(i)) - offset) * gain - expected[i]) <= layout_tolerance<S>());
  }
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
