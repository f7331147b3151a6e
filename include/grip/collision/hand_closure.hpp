#pragma once
/// \file
/// A set-up helper that closes the virtual hand on an object: for each digit, each joint
/// from the palm outwards flexes until a phalanx at or beyond it reaches a target depth
/// (or the joint's upper limit). Gives joint angles for a power grasp without a glove
/// (tests, examples, benchmarks). Not a per-frame routine: it runs collision detection a few
/// hundred times.

#include <algorithm>
#include <cmath>
#include <cstdint>

#include <Eigen/Geometry>

#include "grip/core/index.hpp"
#include "grip/core/status.hpp"
#include "grip/core/types.hpp"
#include "grip/collision/collision.hpp"
#include "grip/collision/hand_collision_model.hpp"
#include "grip/geometry/spherical_octree.hpp"
#include "grip/hand/hand_kinematics.hpp"
#include "grip/hand/hand_model.hpp"

namespace grip {

namespace detail {
// Deepest contact of the phalanges k_from .. k_end - 1 for `angles`, 0 if none: `detect`
// fills `contacts` for the posed model and a phalanx mask.
template <class Scalar, int Samples, class Joints, class Detect>
Scalar digit_depth(const HandDimensions<Scalar>& dims, const Eigen::Transform<Scalar, 3, Eigen::Isometry>& wrist,
                   const Joints& angles, int k_from, int k_end, HandCollisionModel<Scalar, Samples>& model,
                   HandContacts<Scalar>& contacts, const Detect& detect) {
  HandPosture<Scalar> posture;
  forward_kinematics(dims, wrist, angles, posture);
  model.set_posture(posture);
  std::uint32_t mask = 0;
  for (int k = k_from; k < k_end; ++k) mask |= 1u << k;
  detect(model, contacts, mask);
  Scalar d = Scalar(0);
  for (int i = 0; i < contacts.count; ++i) {
    const int k = phalanx_index(contacts[i].finger, contacts[i].phalanx);
    if (k >= k_from && k < k_end && contacts[i].depth > d) d = contacts[i].depth;
  }
  return d;
}

/// The loop that closes a hand, shared by close_hand() and close_hand_in_scene()
/// (pipeline/close_hand.hpp): digit by digit, joint by joint from the palm outwards, each joint
/// flexes from its value in `angles` in steps of `step` (rad), then by `bisections` halvings,
/// to the least angle at which depth(trial, k, end), the deepest penetration (m) of the digit's
/// phalanges k .. end - 1 for the joint angles `trial`, reaches `target_depth`; or to its upper
/// limit. A joint already blocked stays. Joints: the 14 flexion angles, or the 20 joints (whose
/// flexions close; the rest stay as given).
template <class Scalar, class Joints, class Depth>
void close_digits(const HandDimensions<Scalar>& dims, Scalar target_depth, Scalar step, int bisections, Joints& angles,
                  const Depth& depth) {
  constexpr bool whole = Joints::RowsAtCompileTime == hand_dof_count;
  static_assert(whole || Joints::RowsAtCompileTime == hand_joint_count, "14 flexion angles or the 20 joints");
  for (int f = 0; f < 5; ++f) {
    const int first = f == 0 ? 0 : 2 + 3 * (f - 1);  // the thumb's two phalanges, then three a finger
    const int end = f == 0 ? 2 : first + 3;
    for (int k = first; k < end; ++k) {
      const int j = whole ? phalanx_joint(k) : k;  // the joint at the phalanx's proximal end
      auto depth_at = [&](Scalar a) {
        Joints trial = angles;
        trial(j) = a;
        return depth(trial, k, end);
      };
      const Scalar limit = whole ? dims.limits.upper[detail::idx(j)] : dims.joint_upper_limit[detail::idx(k)];
      Scalar lo = angles(j);
      if (depth_at(lo) >= target_depth) continue;
      Scalar hi = lo;
      bool reached = false;
      while (hi < limit) {
        hi = std::min(hi + step, limit);
        if (depth_at(hi) >= target_depth) {
          reached = true;
          break;
        }
        lo = hi;
      }
      if (reached)
        for (int it = 0; it < bisections; ++it) {
          const Scalar mid = (lo + hi) / Scalar(2);
          if (depth_at(mid) >= target_depth)
            hi = mid;
          else
            lo = mid;
        }
      angles(j) = hi;
    }
  }
}

// close_hand's set-up and loop, contacts from `detect` (see digit_depth).
template <int Samples, class Scalar, class Joints, class Detect>
Status close_hand_with(const HandDimensions<Scalar>& dims, const Eigen::Transform<Scalar, 3, Eigen::Isometry>& wrist,
                       Scalar target_depth, Scalar step, Joints& angles, const Detect& detect) {
  HandPosture<Scalar> posture;
  if (!(target_depth > Scalar(0)) || !(step > Scalar(0)) || !std::isfinite(target_depth) || !std::isfinite(step) ||
      forward_kinematics(dims, wrist, angles, posture) != Status::Ok)
    return Status::InvalidInput;
  HandCollisionModel<Scalar, Samples> model;
  HandContacts<Scalar> contacts;
  close_digits(dims, target_depth, step, 10, angles, [&](const Joints& trial, int k, int end) {
    return digit_depth(dims, wrist, trial, k, end, model, contacts, detect);
  });
  return Status::Ok;
}
}  // namespace detail

/// Flexes `angles` (in: the starting posture, usually zeros; out: the closed posture) joint by
/// joint, digit by digit, in steps of `step` (rad) then by 10 bisections, until a phalanx
/// distal to the joint (of the same digit) penetrates by at least `target_depth` (m), or the
/// joint reaches its upper limit (dims.joint_upper_limit; for the 20 joints dims.limits).
/// `angles` is the paper's 14 flexions (JointAngles) or the whole hand's 20 joints
/// (HandJoints): then only the flexions close, the thumb's CMC and the abductions stay as
/// given, and the palm is part of the hand (it does not stop a digit). Contacts from detect_contacts() with the
/// object's octree and distance field `field` (exact narrow phase). Statuses: InvalidInput for bad dimensions, poses,
/// angles, a step <= 0 or target depth <= 0, or an empty octree; Ok otherwise. Uses a HandCollisionModel of `Samples`
/// samples per phalanx (no heap).
template <int Samples = 8, class Scalar, int Capacity, class Field, class Joints>
Status close_hand(const HandDimensions<Scalar>& dims, const Eigen::Transform<Scalar, 3, Eigen::Isometry>& wrist,
                  const SphericalOctree<Scalar, Capacity>& object, const Field& field,
                  const Eigen::Transform<Scalar, 3, Eigen::Isometry>& object_pose, Scalar target_depth, Scalar step,
                  Joints& angles) {
  if (object.tree().empty() || !detail::rigid_pose_ok(object_pose)) return Status::InvalidInput;
  return detail::close_hand_with<Samples>(
      dims, wrist, target_depth, step, angles,
      [&](const HandCollisionModel<Scalar, Samples>& m, HandContacts<Scalar>& c, std::uint32_t mask) {
        detect_contacts(m, object, field, object_pose, c, ContactSettings<Scalar>{}, mask);
      });
}

/// close_hand() with the paper mode's contacts (octree leaves only, collision.hpp).
template <int Samples = 8, class Scalar, int Capacity, class Joints>
Status close_hand(const HandDimensions<Scalar>& dims, const Eigen::Transform<Scalar, 3, Eigen::Isometry>& wrist,
                  const SphericalOctree<Scalar, Capacity>& object,
                  const Eigen::Transform<Scalar, 3, Eigen::Isometry>& object_pose, Scalar target_depth, Scalar step,
                  Joints& angles) {
  if (object.tree().empty() || !detail::rigid_pose_ok(object_pose)) return Status::InvalidInput;
  return detail::close_hand_with<Samples>(
      dims, wrist, target_depth, step, angles,
      [&](const HandCollisionModel<Scalar, Samples>& m, HandContacts<Scalar>& c, std::uint32_t mask) {
        detect_contacts(m, object, object_pose, c, mask);
      });
}

}  // namespace grip
