// The whole hand's collision bodies: the palm's metacarpals and the thenar touch objects like
// the phalanges, only when the posture has them; the open hand keeps clear of the palm plane.
#include <doctest/doctest.h>

#include <cmath>

#include <Eigen/Geometry>

#include <grip/collision/collision.hpp>
#include <grip/collision/hand_closure.hpp>
#include <grip/geometry/shape.hpp>

#include "support/tolerance.hpp"

// Named, not anonymous: the unity build puts several test files in one translation unit.
namespace hand_collision_model_tests {
using namespace grip;

namespace {
using Iso = Eigen::Transform<double, 3, Eigen::Isometry>;
constexpr int octree_capacity = 16384;

// An object in the palm: its top 1 mm into the palm's surface (the metacarpal bodies' palmar
// side, 0.055 L below the joint centres), centred under the metacarpals at x = 0.27 L and at
// height y across the palm.
struct PalmScene {
  HandDimensions<double> dims{HandDimensions<double>::standard()};
  Shape<double> shape;
  SphericalOctree<double, octree_capacity> octree;
  Iso pose{Iso::Identity()};
  double radius;
  PalmScene(const Shape<double>& s, double r, bool across, double y) : shape(s), radius(r) {
    octree.build(shape, 5);
    if (across) pose.linear() = Eigen::AngleAxisd(3.141592653589793 / 2, Eigen::Vector3d::UnitX()).toRotationMatrix();
    pose.translation() = Eigen::Vector3d(0.27 * 0.19, y, -(r + 0.055 * 0.19 - 0.001));
  }
};

// Depth of capsule c in the exact field: r - min over its axis of the distance (dense).
double exact_depth(const Shape<double>& shape, const Iso& pose, const PhalanxCapsule<double>& c) {
  const Iso to_object = pose.inverse();
  const Eigen::Vector3d a = to_object * c.base, b = to_object * c.tip;
  double phi = 1;
  for (int t = 0; t <= 2000; ++t) phi = std::min(phi, shape.distance(Eigen::Vector3d(a + (b - a) * (t / 2000.0))));
  return c.radius - phi;
}

// Contacts of the whole hand closed on the scene's object (the thumb's CMC in opposition).
void grasp_with_palm(const PalmScene& sc, HandPosture<double>& posture, HandContacts<double>& contacts) {
  HandJoints<double> q = HandJoints<double>::Zero();
  q(static_cast<int>(HandJoint::ThumbCmcFlexion)) = 0.5;
  q(static_cast<int>(HandJoint::ThumbCmcAbduction)) = 0.6;
  REQUIRE(close_hand(sc.dims, Iso::Identity(), sc.octree, sc.shape, sc.pose, 0.002, 0.05, q) == Status::Ok);
  REQUIRE(forward_kinematics(sc.dims, Iso::Identity(), q, posture) == Status::Ok);
  HandCollisionModel<double> hand;
  REQUIRE(hand.set_posture(posture) == Status::Ok);
  REQUIRE(detect_contacts(hand, sc.octree, sc.shape, sc.pose, contacts) == Status::Ok);
}
}  // namespace

TEST_CASE("power grasps of a cylinder and a sphere: the palm touches, as collision finds it") {
  const PalmScene cylinder(Shape<double>(make_cylinder<double>(0.035, 0.07)), 0.035, true, -0.02);
  const PalmScene sphere(Shape<double>(make_sphere<double>(0.04)), 0.04, false, 0.01);
  for (const PalmScene* sc : {&cylinder, &sphere}) {
    HandPosture<double> posture;
    HandContacts<double> contacts;
    grasp_with_palm(*sc, posture, contacts);
    int palm = 0;
    for (int i = 0; i < contacts.count; ++i) {
      const HandContact<double>& c = contacts[i];
      const int k = phalanx_index(c.finger, c.phalanx);
      palm += c.phalanx == Phalanx::Metacarpal && c.finger != Finger::Thumb ? 1 : 0;
      // Every contact's depth is the capsule's true depth in the exact field (convex: the
      // narrow phase is exact to its refine tolerance, 1e-7 m; the reference's 2000 samples
      // miss at most L^2 / (2000^2 8 R) < 1e-9 m).
      CHECK(std::abs(c.depth - exact_depth(sc->shape, sc->pose, posture.phalanges[detail::idx(k)])) <= 2e-7);
    }
    // The palm's metacarpals under the object: all four under the cylinder lying across the
    // palm; under the ball, the one below its lowest point (the index's, at y = 10 mm). The
    // thenar, lowered by the CMC's opposition, touches both.
    if (sc == &cylinder) {
      CHECK(palm == 4);
    } else {
      CHECK(palm >= 1);
      CHECK(contacts.find(Finger::Index, Phalanx::Metacarpal) != nullptr);
    }
    CHECK(contacts.find(Finger::Thumb, Phalanx::Metacarpal) != nullptr);
    // The fingers close on it too, and the thumb opposes them.
    CHECK(contacts.find(Finger::Long, Phalanx::Distal) != nullptr);
    CHECK((contacts.find(Finger::Thumb, Phalanx::Distal) != nullptr ||
           contacts.find(Finger::Thumb, Phalanx::Proximal) != nullptr ||
           contacts.find(Finger::Thumb, Phalanx::Metacarpal) != nullptr));
    // The cylinder: every phalanx wraps it (each digit closes joint by joint until the
    // phalanges beyond touch), with the four metacarpals and the thenar, 19 contacts, as the
    // paper's 20-contact grasps; the ball, narrower than the hand, leaves some phalanges off.
    if (sc == &cylinder)
      CHECK(contacts.count == 19);
    else
      CHECK(contacts.count >= 12);
  }
}

TEST_CASE("the paper's hand has no palm: the same object, no metacarpal contact") {
  const PalmScene sc(Shape<double>(make_cylinder<double>(0.035, 0.07)), 0.035, true, -0.02);
  HandPosture<double> posture;
  REQUIRE(forward_kinematics(sc.dims, Iso::Identity(), JointAngles<double>::Zero(), posture) == Status::Ok);
  CHECK(posture.bodies == all_phalanges);
  HandCollisionModel<double> hand;
  REQUIRE(hand.set_posture(posture) == Status::Ok);
  HandContacts<double> contacts;
  REQUIRE(detect_contacts(hand, sc.octree, sc.shape, sc.pose, contacts) == Status::Ok);
  for (int i = 0; i < contacts.count; ++i) CHECK(contacts[i].phalanx != Phalanx::Metacarpal);
  // The whole hand's open pose on the same object: the palm is what touches.
  REQUIRE(forward_kinematics(sc.dims, Iso::Identity(), HandJoints<double>::Zero(), posture) == Status::Ok);
  CHECK(posture.bodies == all_hand_bodies);
  REQUIRE(hand.set_posture(posture) == Status::Ok);
  REQUIRE(detect_contacts(hand, sc.octree, sc.shape, sc.pose, contacts) == Status::Ok);
  CHECK(contacts.find(Finger::Long, Phalanx::Metacarpal) != nullptr);
  // A mask without the palm leaves it out.
  REQUIRE(detect_contacts(hand, sc.octree, sc.shape, sc.pose, contacts, ContactSettings<double>{}, all_phalanges) ==
          Status::Ok);
  for (int i = 0; i < contacts.count; ++i) CHECK(contacts[i].phalanx != Phalanx::Metacarpal);
}

TEST_CASE("the open hand: an object just under the palm touches nothing, the paper hand's thumb catches it") {
  // A sphere of 40 mm under the palm's centre, 2 mm below the lowest body of the open hand.
  const HandDimensions<double> dims = HandDimensions<double>::standard();
  const Shape<double> ball(make_sphere<double>(0.04));
  SphericalOctree<double, octree_capacity> octree;
  octree.build(ball, 5);
  HandPosture<double> open;
  REQUIRE(forward_kinematics(dims, Iso::Identity(), HandJoints<double>::Zero(), open) == Status::Ok);
  double lowest = 0;
  for (const PhalanxCapsule<double>& c : open.phalanges)
    lowest = std::min({lowest, c.base.z() - c.radius, c.tip.z() - c.radius});
  // Every body's lowest point is its radius below the palm plane: the open hand is flat.
  CHECK(lowest >= -0.065 * 0.19 - 1e-12);
  Iso pose = Iso::Identity();
  for (double x : {0.05, 0.08, 0.11}) {
    pose.translation() = Eigen::Vector3d(x, 0.02, lowest - 0.002 - 0.04);
    HandCollisionModel<double> hand;
    HandContacts<double> contacts;
    REQUIRE(hand.set_posture(open) == Status::Ok);
    REQUIRE(detect_contacts(hand, octree, ball, pose, contacts) == Status::Ok);
    CHECK(contacts.count == 0);
  }
  // The paper's hand holds its thumb in opposition, 40 mm and more below the palm: it reaches
  // into the same ball.
  HandPosture<double> paper;
  REQUIRE(forward_kinematics(dims, Iso::Identity(), JointAngles<double>::Zero(), paper) == Status::Ok);
  pose.translation() = Eigen::Vector3d(0.08, 0.02, lowest - 0.002 - 0.04);
  HandCollisionModel<double> hand;
  HandContacts<double> contacts;
  REQUIRE(hand.set_posture(paper) == Status::Ok);
  REQUIRE(detect_contacts(hand, octree, ball, pose, contacts) == Status::Ok);
  CHECK(contacts.find(Finger::Thumb, Phalanx::Distal) != nullptr);
}

TEST_CASE("the left hand's palm mirrors the right's") {
  const HandDimensions<double> right = HandDimensions<double>::standard();
  const HandDimensions<double> left = HandDimensions<double>::standard(0.19, Side::Left);
  HandJoints<double> q = HandJoints<double>::Constant(0.3);
  HandPosture<double> r, l;
  REQUIRE(forward_kinematics(right, Iso::Identity(), q, r) == Status::Ok);
  REQUIRE(forward_kinematics(left, Iso::Identity(), q, l) == Status::Ok);
  const Eigen::Vector3d m(1, -1, 1);
  for (int k = hand_phalanx_count; k < hand_body_count; ++k) {
    CHECK((l.phalanges[detail::idx(k)].base - r.phalanges[detail::idx(k)].base.cwiseProduct(m)).norm() <= 1e-15);
    CHECK((l.phalanges[detail::idx(k)].tip - r.phalanges[detail::idx(k)].tip.cwiseProduct(m)).norm() <= 1e-15);
    CHECK(l.phalanges[detail::idx(k)].phalanx == Phalanx::Metacarpal);
  }
}

}  // namespace hand_collision_model_tests
