#pragma once
/// \file
/// The haptic pipeline's contact source for objects of any shape: the paper's section 3
/// detection (the hand's sphere hierarchy against the object's spherical octree) with the
/// exact narrow phase of the object's distance field (a Shape, a mesh's MeshShape, ...), or
/// the paper mode (octree leaves only); obstacles of any shape against points of the
/// object's surface.

#include <type_traits>

#include "grip/core/types.hpp"
#include "grip/dynamics/rigid_body.hpp"
#include "grip/collision/collision.hpp"
#include "grip/collision/hand_collision_model.hpp"
#include "grip/geometry/spherical_octree.hpp"
#include "grip/hand/hand_kinematics.hpp"
#include "grip/pipeline/obstacle_contacts.hpp"

namespace grip {

/// OctreeScene's Field for the paper mode: depths from the octree leaves alone.
struct PaperMode {};

/// Hand contacts between the posed hand (Samples sample spheres per phalanx) and an object
/// given by its spherical octree and its distance field, both in the body frame (origin at
/// the centre of mass), placed in the world by the object's pose: detect_contacts() of
/// collision.hpp, at most PerPhalanx contacts per phalanx. With Field = PaperMode the
/// paper mode (PerPhalanx must be 1). Obstacle contacts: `surface` points against
/// `obstacles`.
///
/// The octree and the field are not copied: they can be large (keep them in static
/// storage) and must outlive the scene. With a null or empty octree, or a null field,
/// hand_contacts() reports none.
template <class Scalar, int Capacity, class Field = PaperMode, int Samples = 8, int PerPhalanx = 1,
          int MaxObstacles = 4>
struct OctreeScene {
  static_assert(PerPhalanx == 1 || !std::is_same<Field, PaperMode>::value,
                "the paper mode gives one contact per phalanx");
  static constexpr int contacts_per_phalanx = PerPhalanx;    ///< most hand contacts per phalanx
  const SphericalOctree<Scalar, Capacity>* octree{nullptr};  ///< the object's octree (body frame)
  const Field* field{nullptr};                  ///< the object's distance field (body frame; unused in the paper mode)
  Obstacles<Scalar, MaxObstacles> obstacles{};  ///< obstacles in the world
  SurfacePoints<Scalar, max_obstacle_contacts> surface{};  ///< where the object meets obstacles (body frame)
  ContactSettings<Scalar> contact_settings{};              ///< the narrow phase's settings
  mutable HandCollisionModel<Scalar, Samples> model{};     ///< per-frame hand spheres (scratch)

  /// Contacts between the posed hand and the object. Returns their count.
  int hand_contacts(const HandPosture<Scalar>& posture, const RigidBody<Scalar>& object,
                    HandContacts<Scalar, PerPhalanx>& out) const {
    out.count = 0;
    if (octree == nullptr || model.set_posture(posture) != Status::Ok) return 0;
    Isometry3<Scalar> pose = Isometry3<Scalar>::Identity();
    pose.linear() = object.rotation();
    pose.translation() = object.position;
    Status s = Status::InvalidInput;
    if constexpr (std::is_same<Field, PaperMode>::value) {
      s = detect_contacts(model, *octree, pose, out);
    } else {
      if (field != nullptr) s = detect_contacts(model, *octree, *field, pose, out, contact_settings);
    }
    if (s != Status::Ok) out.count = 0;
    return out.count;
  }

  /// Obstacle contacts of the object: `surface` against `obstacles` (Obstacles::contacts).
  int obstacle_contacts(const RigidBody<Scalar>& object, ObstacleContactSet<Scalar>& out) const {
    return obstacles.contacts(object, surface, out);
  }
};

}  // namespace grip
