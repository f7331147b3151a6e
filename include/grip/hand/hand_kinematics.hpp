#pragma once
/// \file
/// Forward kinematics of the hand model: wrist pose (tracker) and 14 joint angles (glove)
/// to the pose of every phalanx, each a capsule (segment and radius).

#include <array>
#include <cmath>

#include <Eigen/Geometry>

#include "grip/core/index.hpp"
#include "grip/core/status.hpp"
#include "grip/core/types.hpp"
#include "grip/hand/hand_model.hpp"

namespace grip {

/// One phalanx posed in the world: the capsule of points within `radius` of the segment
/// [base, tip]. base is the proximal joint centre, tip the distal joint (or fingertip).
template <class Scalar>
struct PhalanxCapsule {
  Vector3<Scalar> base{Vector3<Scalar>::Zero()};  ///< Proximal joint centre (m), world.
  Vector3<Scalar> tip{Vector3<Scalar>::Zero()};   ///< Distal end of the segment (m), world.
  Scalar radius{0};                               ///< Capsule radius (m).
  Finger finger{Finger::Thumb};                   ///< Which digit.
  Phalanx phalanx{Phalanx::Proximal};             ///< Which phalanx of it.
};

/// The posed hand: the 14 phalanges in the order of hand_model.hpp.
template <class Scalar>
struct HandPosture {
  std::array<PhalanxCapsule<Scalar>, hand_phalanx_count> phalanges{};  ///< World-frame capsules.
};

/// Forward kinematics. `wrist` maps hand-frame points to world points (rigid: rotation and
/// translation, the tracker's pose); `angles` are the 14 flexion angles (rad) in the joint
/// order of hand_model.hpp. Within a digit each joint rotates every phalanx distal to it
/// about the digit's flexion axis, so phalanx j of a digit points along
/// Rot(axis, angle_1 + ... + angle_j) rest_direction, and starts where the previous ends.
///
/// Statuses: InvalidInput if the dimensions fail validate(), an angle or the pose is not
/// finite, or the pose's rotation is not orthonormal (within 1e-3); `out` is then left
/// unchanged. Ok otherwise.
/// (Scalar is deduced from `dims` only, so expressions such as JointAngles<S>::Zero() bind.)
template <class Scalar>
Status forward_kinematics(const HandDimensions<Scalar>& dims,
                          const typename HandDimensions<Scalar>::Transform& wrist,
                          const typename HandDimensions<Scalar>::Angles& angles, HandPosture<Scalar>& out) {
  if (validate(dims) != Status::Ok || !angles.allFinite() || !wrist.matrix().allFinite())
    return Status::InvalidInput;
  const Matrix3<Scalar> R = wrist.linear();
  if (!((R.transpose() * R - Matrix3<Scalar>::Identity()).cwiseAbs().maxCoeff() <= Scalar(1e-3)))
    return Status::InvalidInput;
  const Vector3<Scalar> t = wrist.translation();
  for (int f = 0; f < 5; ++f) {
    const int first = f == 0 ? 0 : 2 + 3 * (f - 1);
    const int count = f == 0 ? 2 : 3;
    Vector3<Scalar> p = dims.base[detail::idx(f)];
    Scalar sum = Scalar(0);
    for (int j = 0; j < count; ++j) {
      const int k = first + j;
      sum += angles(k);
      const Vector3<Scalar> dir =
          Eigen::AngleAxis<Scalar>(sum, dims.flexion_axis[detail::idx(f)]) * dims.rest_direction[detail::idx(f)];
      const Vector3<Scalar> q = p + dims.length[detail::idx(k)] * dir;
      PhalanxCapsule<Scalar>& c = out.phalanges[detail::idx(k)];
      c.base = R * p + t;
      c.tip = R * q + t;
      c.radius = dims.radius[detail::idx(k)];
      c.finger = phalanx_finger(k);
      c.phalanx = phalanx_kind(k);
      p = q;
    }
  }
  return Status::Ok;
}

}  // namespace grip
