#pragma once
/// \file
/// An analytic contact source for the haptic pipeline: a solid cylinder, the hand, and
/// obstacles of any shape. No trees: the cylinder's exact distance is cheap, so every sample
/// of every phalanx near it is evaluated (collision.hpp's detect_contacts_direct), side,
/// end caps and rims alike.

#include <array>
#include <cmath>

#include <Eigen/Geometry>

#include "grip/core/types.hpp"
#include "grip/dynamics/rigid_body.hpp"
#include "grip/collision/collision.hpp"
#include "grip/collision/hand_collision_model.hpp"
#include "grip/geometry/shape.hpp"
#include "grip/hand/hand_kinematics.hpp"
#include "grip/pipeline/obstacle_contacts.hpp"

namespace grip {

/// A solid cylinder (the grasped object, its axis along the body z axis through the centre
/// of mass) among up to MaxObstacles obstacles; at most PerPhalanx contacts per phalanx.
///
/// - Hand contacts: the exact narrow phase of collision.hpp on the cylinder's distance field,
///   each phalanx sampled by `Samples` spheres: with PerPhalanx = 1, a contact is its capsule's
///   deepest point on the side, an end cap or a rim, its depth within
///   `contact_settings.refine_tolerance` and its point and normal within the bounds that
///   collision.hpp states for convex fields. The cylinder is
///   convex, so even 2 samples find it; where the deepest points form a line (a phalanx lying
///   along the side) the samples decide which of them is reported: the first, from the base.
/// - Obstacle contacts: `rim_points` points on each end-cap rim (2 rim_points in all) against
///   the obstacles (Obstacles::contacts).
template <class Scalar, int MaxObstacles = 4, int PerPhalanx = 1, int Samples = 8>
struct CylinderScene {
  static constexpr int contacts_per_phalanx = PerPhalanx;  ///< most hand contacts per phalanx
  Scalar radius{Scalar(0.035)};                            ///< cylinder radius (m)
  Scalar half_length{Scalar(0.06)};                        ///< half of the cylinder's length (m)
  int rim_points{8};                                       ///< sample points per rim, in [1, max_obstacle_contacts / 2]
  Obstacles<Scalar, MaxObstacles> obstacles{};             ///< obstacles in the world (e.g. a table: add_box)
  ContactSettings<Scalar> contact_settings{};              ///< the narrow phase's settings
  mutable HandCollisionModel<Scalar, Samples> model{};     ///< per-frame hand spheres (scratch)

  /// The hand contacts of `posture` with the cylinder posed as `object`. Returns their count
  /// (0 also when the posture, the object or the settings are invalid).
  int hand_contacts(const HandPosture<Scalar>& posture, const RigidBody<Scalar>& object,
                    HandContacts<Scalar, PerPhalanx>& out) const {
    out.count = 0;
    const Shape<Scalar, 1> cylinder(make_cylinder<Scalar>(radius, half_length));
    if (model.set_posture(posture) != Status::Ok) return 0;
    Isometry3<Scalar> pose = Isometry3<Scalar>::Identity();
    pose.linear() = object.rotation();
    pose.translation() = object.position;
    if (detect_contacts_direct(model, cylinder, pose, out, contact_settings) != Status::Ok) out.count = 0;
    return out.count;
  }

  /// The obstacle contacts of the cylinder posed as `object`; points are relative to its
  /// centre of mass, depth_rate is left 0. Returns their count.
  int obstacle_contacts(const RigidBody<Scalar>& object, ObstacleContactSet<Scalar>& out) const {
    SurfacePoints<Scalar, max_obstacle_contacts> rims;
    const int n = rim_points < 1 ? 1 : rim_points > max_obstacle_contacts / 2 ? max_obstacle_contacts / 2 : rim_points;
    add_rim_points(rims, radius, half_length, n);
    return obstacles.contacts(object, rims, out);
  }
};

}  // namespace grip
