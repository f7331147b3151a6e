// grip's hand written as MJCF (grip/mujoco/hand_mjcf.hpp): loaded by MuJoCo, its bodies,
// capsules and joint axes at random postures are grip's forward kinematics (computed by
// MuJoCo from the text, not by grip), for both hands; the options' checks.
#include <doctest/doctest.h>

#include <grip/hand/hand_kinematics.hpp>
#include <grip/mujoco/body_names.hpp>
#include <grip/mujoco/hand_mjcf.hpp>

#include "mujoco/mujoco_support.hpp"
#include "support/random.hpp"

using namespace grip;
using grip::mujoco::HandMjcf;

namespace {

Eigen::Vector3d at3(const mjtNum* p) { return Eigen::Vector3d(p[0], p[1], p[2]); }

Eigen::Isometry3d random_pose(std::mt19937& rng) {
  const grip_test::Uniform u(-1, 1);
  Eigen::Vector4d q;
  for (int i = 0; i < 4; ++i) q(i) = u(rng);
  Eigen::Isometry3d x = Eigen::Isometry3d::Identity();
  x.linear() = Eigen::Quaterniond(q(0), q(1), q(2), q(3)).normalized().toRotationMatrix();
  for (int i = 0; i < 3; ++i) x.translation()(i) = 0.3 * u(rng);
  return x;
}

// The largest distance between MuJoCo's and grip's bodies, capsule ends and joint axes over
// `trials` random postures within the joint limits and random wrist poses.
double worst_difference(Side side, int trials) {
  const HandDimensions<double> dims = HandDimensions<double>::standard(0.19, side);
  HandMjcf options;
  std::string xml;
  REQUIRE(grip::mujoco::hand_mjcf(dims, options, xml) == Status::Ok);
  std::string error;
  const grip_test::ModelPtr m = grip_test::load_mjcf(xml, &error);
  INFO(error);
  REQUIRE(m != nullptr);
  const grip_test::DataPtr d(mj_makeData(m.get()));
  CHECK(m->nq == 7 + hand_dof_count);  // the hand's free joint, then the 20 joints
  CHECK(m->nu == hand_dof_count);
  const int hand = mj_name2id(m.get(), mjOBJ_BODY, "hand");
  REQUIRE(hand > 0);
  const int mocap = m->body_mocapid[mj_name2id(m.get(), mjOBJ_BODY, "hand_target")];
  REQUIRE(mocap >= 0);
  CHECK(m->body_jntnum[hand] == 1);
  std::mt19937 rng(2024);
  double worst = 0;
  for (int t = 0; t < trials; ++t) {
    const Eigen::Isometry3d wrist = random_pose(rng);
    HandJoints<double> q;
    for (int i = 0; i < hand_dof_count; ++i) {
      const double lo = dims.limits.lower[detail::idx(i)], hi = dims.limits.upper[detail::idx(i)];
      const double draw = grip_test::Uniform(lo, hi)(rng);
      q(i) = draw;
      const int j = mj_name2id(m.get(), mjOBJ_JOINT, grip::mujoco::hand_joint_name(i));
      REQUIRE(j >= 0);
      CHECK(m->jnt_qposadr[j] == 7 + i);  // grip's order in qpos
      d->qpos[m->jnt_qposadr[j]] = q(i);
    }
    const Eigen::Quaterniond wq(wrist.linear());
    for (int k = 0; k < 3; ++k) d->mocap_pos[3 * mocap + k] = wrist.translation()(k);
    d->mocap_quat[4 * mocap] = wq.w();
    d->mocap_quat[4 * mocap + 1] = wq.x();
    d->mocap_quat[4 * mocap + 2] = wq.y();
    d->mocap_quat[4 * mocap + 3] = wq.z();
    for (int k = 0; k < 7; ++k) d->qpos[k] = k < 3 ? d->mocap_pos[3 * mocap + k] : d->mocap_quat[4 * mocap + k - 3];
    mj_kinematics(m.get(), d.get());
    HandPosture<double> posture;
    REQUIRE(forward_kinematics(dims, wrist, q, posture) == Status::Ok);
    for (int k = 0; k < hand_body_count; ++k) {
      const int b = mj_name2id(m.get(), mjOBJ_BODY, grip::mujoco::hand_body_name(k));
      REQUIRE(b > 0);
      REQUIRE(m->body_geomnum[b] == 1);
      const int g = m->body_geomadr[b];
      const PhalanxCapsule<double>& c = posture.phalanges[detail::idx(k)];
      // The capsule's axis is the geom frame's z (either way round), its half-length size[1].
      const Eigen::Vector3d z(d->geom_xmat[9 * g + 2], d->geom_xmat[9 * g + 5], d->geom_xmat[9 * g + 8]);
      const Eigen::Vector3d centre = at3(d->geom_xpos + 3 * g);
      const double half = m->geom_size[3 * g + 1];
      worst = std::max(worst, (at3(d->xpos + 3 * b) - c.base).norm());
      const Eigen::Vector3d e1 = centre - half * z, e2 = centre + half * z;
      worst = std::max(worst, std::min(std::max((e1 - c.base).norm(), (e2 - c.tip).norm()),
                                       std::max((e2 - c.base).norm(), (e1 - c.tip).norm())));
      worst = std::max(worst, std::abs(m->geom_size[3 * g] - c.radius));
    }
    for (int i = 0; i < hand_dof_count; ++i) {
      const int j = mj_name2id(m.get(), mjOBJ_JOINT, grip::mujoco::hand_joint_name(i));
      worst = std::max(worst, (at3(d->xaxis + 3 * j) - posture.joints[detail::idx(i)].axis).norm());
      // Any point of the axis will do: the anchor's offset from grip's point along the axis.
      const Eigen::Vector3d off = at3(d->xanchor + 3 * j) - posture.joints[detail::idx(i)].point;
      worst = std::max(
          worst, (off - off.dot(posture.joints[detail::idx(i)].axis) * posture.joints[detail::idx(i)].axis).norm());
    }
  }
  return worst;
}

}  // namespace

TEST_CASE("hand_mjcf: MuJoCo's kinematics of the written hand is grip's, right and left hands") {
  CHECK(worst_difference(Side::Right, 50) <= 1e-12);
  CHECK(worst_difference(Side::Left, 50) <= 1e-12);
}

TEST_CASE("hand_mjcf: joint ranges, actuators and the prefix") {
  const HandDimensions<double> dims = HandDimensions<double>::standard();
  HandMjcf options;
  options.prefix = "left_";
  options.servo_gain = 3;
  std::string xml;
  REQUIRE(grip::mujoco::hand_mjcf(dims, options, xml) == Status::Ok);
  const grip_test::ModelPtr m = grip_test::load_mjcf(xml);
  REQUIRE(m != nullptr);
  for (int i = 0; i < hand_dof_count; ++i) {
    const std::string name = std::string("left_") + grip::mujoco::hand_joint_name(i);
    const int j = mj_name2id(m.get(), mjOBJ_JOINT, name.c_str());
    REQUIRE(j >= 0);
    CHECK(m->jnt_limited[j] == 1);
    CHECK(m->jnt_range[2 * j] == dims.limits.lower[detail::idx(i)]);
    CHECK(m->jnt_range[2 * j + 1] == dims.limits.upper[detail::idx(i)]);
    const int a = mj_name2id(m.get(), mjOBJ_ACTUATOR, name.c_str());
    REQUIRE(a == i);
    CHECK(m->actuator_trnid[2 * a] == j);
    CHECK(m->actuator_gainprm[mjNGAIN * a] == 3.0);
  }
  options.servo_gain = 0;
  REQUIRE(grip::mujoco::hand_mjcf(dims, options, xml) == Status::Ok);
  const grip_test::ModelPtr bare = grip_test::load_mjcf(xml);
  REQUIRE(bare != nullptr);
  CHECK(bare->nu == 0);
}

TEST_CASE("hand_mjcf: bad dimensions or options give InvalidInput and no text") {
  const HandDimensions<double> good = HandDimensions<double>::standard();
  std::string xml = "stale";
  HandDimensions<double> bad = good;
  bad.length[3] = std::numeric_limits<double>::quiet_NaN();
  CHECK(grip::mujoco::hand_mjcf(bad, HandMjcf{}, xml) == Status::InvalidInput);
  CHECK(xml.empty());
  const auto rejects = [&](auto change) {
    HandMjcf o;
    change(o);
    std::string out = "stale";
    return grip::mujoco::hand_mjcf(good, o, out) == Status::InvalidInput && out.empty();
  };
  CHECK(rejects([](HandMjcf& o) { o.servo_gain = -1; }));
  CHECK(rejects([](HandMjcf& o) { o.density = 0; }));
  CHECK(rejects([](HandMjcf& o) { o.timestep = std::numeric_limits<double>::infinity(); }));
  CHECK(rejects([](HandMjcf& o) { o.friction = std::numeric_limits<double>::quiet_NaN(); }));
  CHECK(rejects([](HandMjcf& o) { o.condim = 2; }));
  CHECK(rejects([](HandMjcf& o) { o.prefix = "a\"b"; }));
  CHECK(rejects([](HandMjcf& o) { o.wrist.linear() *= 2.0; }));
  CHECK(rejects([](HandMjcf& o) { o.wrist.linear().col(0) *= -1.0; }));  // a reflection
}
