// The pipeline with the whole hand (20 joints, palm) and with each device policy.
#include <doctest/doctest.h>

#include <cmath>

#include <grip/hand/hand_jacobian.hpp>
#include <grip/pipeline/close_hand.hpp>
#include <grip/pipeline/cylinder_scene.hpp>
#include <grip/pipeline/haptic_pipeline.hpp>

#include "pipeline/pipeline_fixture.hpp"
#include "support/allocation_counter.hpp"

// Named, not anonymous: the unity build puts several test files in one translation unit.
namespace whole_hand_tests {
using namespace grip;

namespace {
using Iso = Eigen::Transform<double, 3, Eigen::Isometry>;
constexpr double mass = 0.4, radius = 0.035, half_length = 0.08, L = 0.19;

// A 0.4 kg cylinder lying across the open palm of a hand held palm up (whole hand, 20
// joints at zero), 1 mm into the palm's surface at x = 0.34 L: on the index, long and ring
// metacarpals, clear of the thenar and of the straight fingers. (A cylinder on a flat palm
// touches it along a line; it rests only with its centre above its contacts.)
struct PalmUp {
  HapticSettings<double> settings;
  CylinderScene<double> scene;
  RigidBody<double> object;
  WristState<double> wrist;

  PalmUp() {
    settings.palm_stiffness = 1.5e4;
    scene.radius = radius;
    scene.half_length = half_length;
    object.mass = mass;
    object.principal_inertia = solid_cylinder_inertia<double>(mass, radius, half_length);
    wrist.pose = Iso::Identity();
    // Palm up, tilted by 0.02 rad so that the object leans on the metacarpal heads: lying on
    // the flat palm alone, a cylinder touches it along one line, a grasp matrix of rank 5.
    wrist.pose.linear() = Eigen::AngleAxisd(3.141592653589793, Eigen::Vector3d::UnitX()).toRotationMatrix() *
                          Eigen::AngleAxisd(0.02, Eigen::Vector3d::UnitY()).toRotationMatrix();
    wrist.pose.translation() = Eigen::Vector3d(0.1, 0.2, 0.5);
    const Eigen::Vector3d in_hand(0.34 * L, 0.0, -(radius + 0.055 * L - 0.001));
    object.position = wrist.pose * in_hand;
    object.orientation =
        Eigen::Quaterniond(wrist.pose.linear() * Eigen::AngleAxisd(3.141592653589793 / 2, Eigen::Vector3d::UnitX()));
  }
};
}  // namespace

TEST_CASE("whole hand, palm up: an object resting in the open palm, the palm carries its weight") {
  PalmUp s;
  HapticPipeline<double, CylinderScene<double>> p(s.settings, s.scene, s.object);
  HapticFrame<double> f;
  for (int i = 0; i < 5; ++i) REQUIRE(p.step(s.wrist, HandJoints<double>::Zero(), f) == Status::Ok);
  CHECK(f.held);
  int palm = 0;
  for (int i = 0; i < p.hand_contacts().count; ++i) palm += p.hand_contacts()[i].phalanx == Phalanx::Metacarpal;
  CHECK(palm >= 3);
  CHECK(palm == f.contacts);  // the straight fingers are above the palm's surface: only it touches
  // Held at rest: what the palm feels is the weight, m g downwards (the solve's equilibrium,
  // to the frame's round-off), and the phalanges feel nothing.
  CHECK((f.palm_force - Eigen::Vector3d(0, 0, -mass * 9.81)).norm() <=
        grip_test::roundoff<double>(64, grip_test::grasp_condition(p.grasp()), 2 * mass * 9.81));
  CHECK(grip_test::total_feedback(f).norm() == 0);
  // The same scene with the paper's hand (no palm): nothing holds the object.
  HapticPipeline<double, CylinderScene<double>> paper(s.settings, s.scene, s.object);
  REQUIRE(paper.step(s.wrist, JointAngles<double>::Zero(), f) == Status::Ok);
  CHECK_FALSE(f.held);
  CHECK(f.palm_force.norm() == 0);
}

TEST_CASE("the open whole hand lets an object under it fall untouched, the paper hand's thumb catches it") {
  HapticSettings<double> settings;
  CylinderScene<double> scene;
  scene.radius = 0.03;
  scene.half_length = 0.05;
  RigidBody<double> ball;  // a cylinder along y, 2 mm under the open hand's palm
  ball.mass = 0.2;
  ball.principal_inertia = solid_cylinder_inertia<double>(0.2, 0.03, 0.05);
  ball.orientation = Eigen::Quaterniond(Eigen::AngleAxisd(3.141592653589793 / 2, Eigen::Vector3d::UnitX()));
  ball.position = Eigen::Vector3d(0.06, 0.03, -(0.065 * L + 0.002 + 0.03));
  WristState<double> wrist;
  {
    HapticPipeline<double, CylinderScene<double>> p(settings, scene, ball);
    HapticFrame<double> f;
    for (int i = 0; i < 100; ++i) {
      REQUIRE(p.step(wrist, HandJoints<double>::Zero(), f) == Status::Ok);
      CHECK(f.contacts == 0);
      CHECK_FALSE(f.held);
    }
    // 0.1 s of free fall: g t^2 / 2 = 49 mm (the integrator's exact law, integrator.test.cpp).
    CHECK(p.object().position.z() == doctest::Approx(ball.position.z() - 0.5 * 9.81 * 0.1 * 0.1).epsilon(1e-9));
  }
  HapticPipeline<double, CylinderScene<double>> paper(settings, scene, ball);
  HapticFrame<double> f;
  REQUIRE(paper.step(wrist, JointAngles<double>::Zero(), f) == Status::Ok);
  CHECK(f.contacts > 0);  // the thumb held in opposition reaches into it
  CHECK(f.phalanges[1].in_contact);
}

TEST_CASE("the joint-torque device renders sum J^T F of what each phalanx feels") {
  grip_test::HeldCylinder<double> h;
  using P = HapticPipeline<double, CylinderScene<double>, RangeSpaceFrameSolver, JointTorques<double>>;
  P p(h.settings, h.scene, h.object);
  p.device().limit.fill(0.2);
  HapticFrame<double> f;
  REQUIRE(p.step(h.wrist, h.closed, f) == Status::Ok);
  REQUIRE(f.held);
  // The reference: each contact's Jacobian at its point (one contact per phalanx), transposed,
  // times the force the phalanx feels.
  HandJoints<double> want = HandJoints<double>::Zero();
  for (int i = 0; i < p.hand_contacts().count; ++i) {
    const HandContact<double>& c = p.hand_contacts()[i];
    const int k = phalanx_index(c.finger, c.phalanx);
    PointJacobian<double> J;
    REQUIRE(point_jacobian(p.posture(), k, c.point, J) == Status::Ok);
    want += J.transpose() * f.phalanges[detail::idx(k)].force;
  }
  const JointTorques<double>::Command& cmd = p.device_command();
  REQUIRE(cmd.status == Status::Ok);
  CHECK((cmd.wanted - want).cwiseAbs().maxCoeff() <= 1e-12);
  CHECK(want.cwiseAbs().maxCoeff() > 0.01);  // the grasp loads the joints
  for (int i = 0; i < hand_dof_count; ++i) CHECK(std::abs(cmd.torque(i)) <= 0.2);
  // The paper's hand holds its CMC and abductions fixed: no torque there.
  for (int i : {0, 1, 4, 8, 12, 16}) CHECK(cmd.wanted(i) == 0);
}

TEST_CASE("brakes in the loop: while the hand closes they never push, at rest they hold") {
  grip_test::HeldCylinder<double> h;
  using P = HapticPipeline<double, CylinderScene<double>, RangeSpaceFrameSolver, JointBrakes<double>>;
  P p(h.settings, h.scene, h.object);
  HapticFrame<double> f;
  int refused = 0;
  for (int i = 0; i <= 40; ++i) {  // the hand closes onto the object, then squeezes past it
    const double t = 0.8 + 0.01 * i;
    {
      grip_test::NoHeapScope scope;
      REQUIRE(p.step(h.wrist, t * h.closed, f) == Status::Ok);
      CHECK(scope.allocations() == 0);
    }
    const auto& cmd = p.device_command();
    for (int j = 0; j < hand_dof_count; ++j) {
      CHECK(cmd.torque(j) * p.joint_velocity()(j) <= 0);
      refused += cmd.wanted(j) * p.joint_velocity()(j) > 0 ? 1 : 0;
    }
  }
  // The hand stops: every joint at rest, the brakes hold what the object pushes back.
  REQUIRE(p.step(h.wrist, 1.2 * h.closed, f) == Status::Ok);
  REQUIRE(p.step(h.wrist, 1.2 * h.closed, f) == Status::Ok);
  CHECK(p.joint_velocity().isZero(0));
  const auto& cmd = p.device_command();
  for (int j = 0; j < hand_dof_count; ++j)
    CHECK(cmd.torque(j) == doctest::Approx(std::max(-0.5, std::min(0.5, cmd.wanted(j)))));
  CHECK(cmd.wanted.cwiseAbs().maxCoeff() > 0.01);
  (void)refused;
}

}  // namespace whole_hand_tests
