#pragma once
/// \file
/// The haptic pipeline's contact source built on geometry/: the hand's sphere hierarchy
/// against the object's spherical octree (the paper's section 3 detection), and box
/// obstacles against sample points of a cylindrical object.

#include "grip/core/types.hpp"
#include "grip/dynamics/rigid_body.hpp"
#include "grip/geometry/collision.hpp"
#include "grip/geometry/hand_collision_model.hpp"
#include "grip/geometry/spherical_octree.hpp"
#include "grip/hand/hand_kinematics.hpp"
#include "grip/pipeline/cylinder_scene.hpp"
#include "grip/pipeline/obstacle_contacts.hpp"

namespace grip {

/// Hand contacts from detect_contacts() (two-stage recursive sphere-tree descent) between
/// the posed hand (Samples sample spheres per phalanx) and the object's octree, placed in the
/// world by the object's pose (body frame = the octree's frame, origin at the centre of mass).
/// Obstacle contacts from `obstacles` (CylinderScene's rim samples against its boxes).
///
/// The octree is not copied: `octree` points to one the user built (it can be large: keep
/// it in static storage) and must outlive the scene. With a null or empty octree
/// hand_contacts() reports none.
template <class Scalar, int Capacity, int Samples = 8, int MaxBoxes = 4>
struct OctreeScene {
  const SphericalOctree<Scalar, Capacity>* octree{nullptr};  ///< the object's octree (body frame)
  CylinderScene<Scalar, MaxBoxes> obstacles{};                ///< obstacle boxes and rim sampling
  mutable HandCollisionModel<Scalar, Samples> model{};       ///< per-frame hand spheres (scratch)

  /// Contacts between the posed hand and the object. Returns their count.
  int hand_contacts(const HandPosture<Scalar>& posture, const RigidBody<Scalar>& object,
                    HandContacts<Scalar>& out) const {
    out.count = 0;
    if (octree == nullptr || model.set_posture(posture) != Status::Ok) return 0;
    Eigen::Transform<Scalar, 3, Eigen::Isometry> pose = Eigen::Transform<Scalar, 3, Eigen::Isometry>::Identity();
    pose.linear() = object.rotation();
    pose.translation() = object.position;
    if (detect_contacts(model, *octree, pose, out) != Status::Ok) out.count = 0;
    return out.count;
  }

  /// Obstacle contacts of the object (see CylinderScene::obstacle_contacts).
  int obstacle_contacts(const RigidBody<Scalar>& object, ObstacleContactSet<Scalar>& out) const {
    return obstacles.obstacle_contacts(object, out);
  }
};

}  // namespace grip
