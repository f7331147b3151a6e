#pragma once
/// \file
/// The hand's Jacobians and the joint torques of contact forces: what an exoskeleton or a
/// tendon glove commands. Both read a posture from forward_kinematics (hand_kinematics.hpp),
/// which holds every joint's world axis; no heap.
///
/// A point p carried by phalanx k moves, for joint rates qdot, at J(p) qdot with column i of
/// the 3 x 20 Jacobian J equal to a_i x (p - c_i) (a_i the joint's unit axis, c_i a point of
/// it, both world) for the joints that move the phalanx (those of its digit up to
/// phalanx_joint(k)), and zero for every other joint and for joints the model holds fixed.
/// A force f applied at p (on the hand) does virtual work f . J dq, so its generalized joint
/// torques are tau = J^T f, tau_i = a_i . ((p - c_i) x f): the moment of f about joint i's
/// axis. To hold the hand still against f, the joints must apply -tau.

#include <Eigen/Core>

#include "grip/core/index.hpp"
#include "grip/core/status.hpp"
#include "grip/core/types.hpp"
#include "grip/hand/hand_joints.hpp"
#include "grip/hand/hand_kinematics.hpp"

namespace grip {

/// Jacobian of a point's world position with respect to the 20 joints (m/rad).
template <class Scalar>
using PointJacobian = Eigen::Matrix<Scalar, 3, hand_dof_count>;

/// The Jacobian J of point p (world, m) carried by body k (a phalanx, or a metacarpal: the
/// thumb's moves with the CMC, the fingers' with nothing) of `posture`, into J.
/// InvalidInput (J unchanged) if k is outside [0, 19) or p is not finite; Ok otherwise.
template <class Scalar>
Status point_jacobian(const HandPosture<Scalar>& posture, int k, const Vector3<Scalar>& p, PointJacobian<Scalar>& J);

/// Adds tau = J^T f of force f (N, world, applied on the hand) at point p of phalanx k to
/// `tau` (N m, order of hand_joints.hpp): summed over a phalanx's or the hand's contacts it
/// is the torque of each joint. Only the joints of phalanx k's digit change, so a digit's
/// torques are tau.segment<4>(4 f). InvalidInput (tau unchanged) if k is outside [0, 19) or p
/// or f is not finite; Ok otherwise.
template <class Scalar>
Status add_joint_torques(const HandPosture<Scalar>& posture, int k, const Vector3<Scalar>& p, const Vector3<Scalar>& f,
                         HandJoints<Scalar>& tau);

// ---------------------------------------------------------------------------------------------

namespace detail {
/// The joints that move phalanx k: 4 f .. phalanx_joint(k), f its digit.
constexpr int first_joint_of(int k) { return 4 * static_cast<int>(phalanx_finger(k)); }
}  // namespace detail

template <class Scalar>
Status point_jacobian(const HandPosture<Scalar>& posture, int k, const Vector3<Scalar>& p, PointJacobian<Scalar>& J) {
  if (k < 0 || k >= hand_body_count || !p.allFinite()) return Status::InvalidInput;
  J.setZero();
  for (int i = detail::first_joint_of(k); i <= phalanx_joint(k); ++i) {
    const JointFrame<Scalar>& a = posture.joints[detail::idx(i)];
    J.col(i) = a.axis.cross(p - a.point);
  }
  return Status::Ok;
}

template <class Scalar>
Status add_joint_torques(const HandPosture<Scalar>& posture, int k, const Vector3<Scalar>& p, const Vector3<Scalar>& f,
                         HandJoints<Scalar>& tau) {
  if (k < 0 || k >= hand_body_count || !p.allFinite() || !f.allFinite()) return Status::InvalidInput;
  for (int i = detail::first_joint_of(k); i <= phalanx_joint(k); ++i) {
    const JointFrame<Scalar>& a = posture.joints[detail::idx(i)];
    tau(i) += a.axis.dot((p - a.point).cross(f));
  }
  return Status::Ok;
}

}  // namespace grip
