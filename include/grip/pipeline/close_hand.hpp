#pragma once
/// \file
/// Scripted grasping: the joint angles at which a hand closing on an object stops, for
/// sessions and tests that stand in for a glove.

#include <algorithm>
#include <cstddef>

#include "grip/core/index.hpp"
#include "grip/core/status.hpp"
#include "grip/core/types.hpp"
#include "grip/dynamics/rigid_body.hpp"
#include "grip/collision/collision.hpp"
#include "grip/collision/hand_closure.hpp"
#include "grip/hand/hand_kinematics.hpp"
#include "grip/hand/hand_model.hpp"
#include "grip/pipeline/scene.hpp"

namespace grip {

/// Result of close_hand_in_scene(): `Joints` the paper's 14 flexions or the 20 joints.
template <class Scalar, class Joints = JointAngles<Scalar>>
struct ClosedHand {
  Joints angles{Joints::Zero()};        ///< the closed posture (rad)
  int touching{0};                      ///< phalanges in contact in the closed posture
  Status status{Status::InvalidInput};  ///< Ok, or InvalidInput (angles zero)
};

/// Closes the hand posed at `wrist` on `object` the way a grasping hand does: digit by digit,
/// joint by joint from the palm outwards, each joint flexes (in steps of `step` rad, then
/// bisection) until some phalanx distal to it penetrates the object by `target_depth` (m),
/// or the joint reaches its upper limit. Uses `scene.hand_contacts` (see HapticPipeline); the
/// procedure of collision's close_hand() (detail::close_digits), for any scene. `start`: the posture closing
/// begins from, zero by default; with the whole hand's 20 joints (HandJoints) only the
/// flexions close (the thumb's CMC and the abductions stay as in `start`), and the palm's
/// contacts do not stop a digit. InvalidInput for invalid dimensions, pose, non-positive step
/// or negative depth. Set-up cost: a few thousand forward kinematics; no heap.
template <class Scalar, class Scene, class Joints = JointAngles<Scalar>>
ClosedHand<Scalar, Joints> close_hand_in_scene(const Scene& scene, const HandDimensions<Scalar>& dims,
                                               const Eigen::Transform<Scalar, 3, Eigen::Isometry>& wrist,
                                               const RigidBody<Scalar>& object, Scalar target_depth,
                                               Scalar step = Scalar(0.01), const Joints& start = Joints::Zero()) {
  ClosedHand<Scalar, Joints> out;
  if (validate(dims) != Status::Ok || !(step > Scalar(0)) || !(target_depth >= Scalar(0)) ||
      validate(object) != Status::Ok || !start.allFinite())
    return out;
  HandPosture<Scalar> posture;
  HandContacts<Scalar, detail::scene_contacts_per_phalanx<Scene>::value> contacts;
  Joints q = start;
  // Deepest penetration among phalanges [first, last] for angles a (-1 if none touch).
  auto deepest = [&](const Joints& a, int first, int last) {
    if (forward_kinematics(dims, wrist, a, posture) != Status::Ok) return Scalar(-2);
    scene.hand_contacts(posture, object, contacts);
    Scalar d = Scalar(-1);
    for (int i = 0; i < contacts.count; ++i) {
      const HandContact<Scalar>& c = contacts.items[detail::idx(i)];
      const int k = phalanx_index(c.finger, c.phalanx);
      if (k >= first && k <= last) d = std::max(d, c.depth);
    }
    return d;
  };
  if (deepest(q, 0, hand_phalanx_count - 1) < Scalar(-1)) return out;
  detail::close_digits(dims, target_depth, step, 30, q,
                       [&](const Joints& trial, int k, int end) { return deepest(trial, k, end - 1); });
  out.angles = q;
  (void)deepest(q, 0, hand_phalanx_count - 1);
  out.touching = contacts.count;
  out.status = Status::Ok;
  return out;
}

}  // namespace grip
