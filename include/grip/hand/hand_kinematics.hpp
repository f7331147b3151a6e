#pragma once
/// \file
/// Forward kinematics of the hand model: wrist pose (tracker) and joint angles (glove: the
/// paper's 14 flexions, or the whole hand's 20 joints) to the pose of every phalanx, each a
/// capsule (segment and radius), and of every joint axis (for the Jacobians).

#include <array>
#include <cmath>
#include <cstdint>

#include <Eigen/Geometry>

#include "grip/core/index.hpp"
#include "grip/core/status.hpp"
#include "grip/core/types.hpp"
#include "grip/hand/hand_joints.hpp"
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

/// A joint posed in the world: a point of its axis and the axis's unit direction (a positive
/// angle turns the distal bodies counter-clockwise about it). A joint the model holds fixed
/// (the thumb's CMC and the finger abductions of the 14-joint hand) has a zero axis.
template <class Scalar>
struct JointFrame {
  Vector3<Scalar> point{Vector3<Scalar>::Zero()};  ///< On the axis (m), world.
  Vector3<Scalar> axis{Vector3<Scalar>::Zero()};   ///< Unit, world; zero if fixed.
};

/// The posed hand: its 19 bodies (the 14 phalanges, then the 5 metacarpals of the palm) in
/// the order of hand_model.hpp and the 20 joints in the order of hand_joints.hpp. Invariant:
/// body k's base lies on joints[phalanx_joint(k)]'s axis (it is that joint's point) when
/// phalanx_joint(k) >= 0.
template <class Scalar>
struct HandPosture {
  std::array<PhalanxCapsule<Scalar>, hand_body_count> phalanges{};  ///< World-frame capsules.
  std::array<JointFrame<Scalar>, hand_dof_count> joints{};          ///< World-frame joint axes.
  /// Bit k set if body k belongs to the model: the paper's hand (14 angles) is its phalanges,
  /// the whole hand (20 joints) has the palm too. Collision detection skips the others.
  std::uint32_t bodies{(1u << hand_phalanx_count) - 1u};
};

/// Forward kinematics of either hand model. `wrist` maps hand-frame points to world points
/// (rigid: the tracker's pose); `q` is either
/// - the 14 flexion angles of the paper's glove (rad, order of hand_model.hpp): the thumb's CMC
///   holds the fixed opposed posture of HandDimensions (rest_direction[0], flexion_axis[0]) and
///   the fingers do not spread; the posture's CMC and abduction joints are then fixed (zero
///   axis); or
/// - the 20 joints of the whole hand (rad, order of hand_joints.hpp), the thumb opening flat
///   at zero (open_thumb_direction).
/// Within a digit, after the digit's base rotation B (finger: abduction about
/// abduction_axis[f]; thumb: CMC flexion about cmc_flexion_axis, then abduction about
/// abduction_axis[0] turned by the flexion), phalanx j points along
/// B Rot(e, q_1 + ... + q_j) d, with d and e the digit's rest direction and flexion axis, and
/// starts where the previous ends. Joint limits are not enforced (see JointLimits).
///
/// Statuses: InvalidInput if the dimensions fail validate(), an angle or the pose is not
/// finite, or the pose's rotation is not orthonormal (within 1e-3); `out` is then left
/// unchanged. Ok otherwise. Scalar is deduced from `dims` only, so expressions such as
/// JointAngles<S>::Zero() bind; a vector of another size does not compile.
template <class Scalar, class Derived>
Status forward_kinematics(const HandDimensions<Scalar>& dims, const typename HandDimensions<Scalar>::Transform& wrist,
                          const Eigen::MatrixBase<Derived>& q, HandPosture<Scalar>& out);

// ---------------------------------------------------------------------------------------------

template <class Scalar, class Derived>
Status forward_kinematics(const HandDimensions<Scalar>& dims, const typename HandDimensions<Scalar>::Transform& wrist,
                          const Eigen::MatrixBase<Derived>& q, HandPosture<Scalar>& out) {
  constexpr int n = Derived::SizeAtCompileTime;
  static_assert(n == hand_joint_count || n == hand_dof_count, "14 flexion angles or the 20 joints");
  constexpr bool whole = n == hand_dof_count;
  if (validate(dims) != Status::Ok || !q.allFinite() || !wrist.matrix().allFinite()) return Status::InvalidInput;
  const Matrix3<Scalar> R = wrist.linear();
  if (!((R.transpose() * R - Matrix3<Scalar>::Identity()).cwiseAbs().maxCoeff() <= Scalar(1e-3)))
    return Status::InvalidInput;
  const Vector3<Scalar> t = wrist.translation();
  out.bodies = whole ? (1u << hand_body_count) - 1u : (1u << hand_phalanx_count) - 1u;
  using AngleAxis = Eigen::AngleAxis<Scalar>;
  for (int f = 0; f < 5; ++f) {
    const int first = f == 0 ? 0 : 2 + 3 * (f - 1);
    const int count = f == 0 ? 2 : 3;
    // Base rotation B of the digit and the frames of the joints before its first phalanx.
    Matrix3<Scalar> B = Matrix3<Scalar>::Identity();
    Vector3<Scalar> d = dims.rest_direction[detail::idx(f)];
    Vector3<Scalar> e = dims.flexion_axis[detail::idx(f)];
    Vector3<Scalar> p = dims.base[detail::idx(f)];
    JointFrame<Scalar>* joint = &out.joints[detail::idx(4 * f)];
    if (f == 0) {
      joint[0].point = joint[1].point = R * dims.thumb_cmc + t;
      joint[0].axis = joint[1].axis = Vector3<Scalar>::Zero();
      if (whole) {
        const Matrix3<Scalar> flex = AngleAxis(q(0), dims.cmc_flexion_axis).toRotationMatrix();
        B = flex * AngleAxis(q(1), dims.abduction_axis[0]).toRotationMatrix();
        joint[0].axis = R * dims.cmc_flexion_axis;
        joint[1].axis = R * (flex * dims.abduction_axis[0]);
        d = dims.open_thumb_direction;
        e = dims.open_thumb_flexion_axis;
        p = dims.thumb_cmc + dims.thumb_metacarpal * (B * d);
      }
      joint += 2;
    } else {
      joint[0].point = R * p + t;
      joint[0].axis = Vector3<Scalar>::Zero();
      if (whole) {
        B = AngleAxis(q(4 * f), dims.abduction_axis[detail::idx(f)]).toRotationMatrix();
        joint[0].axis = R * dims.abduction_axis[detail::idx(f)];
      }
      joint += 1;
    }
    const Vector3<Scalar> axis = R * (B * e);
    Scalar sum = Scalar(0);
    for (int j = 0; j < count; ++j) {
      const int k = first + j;
      sum += q(whole ? phalanx_joint(k) : k);
      const Vector3<Scalar> dir = B * (AngleAxis(sum, e) * d);
      const Vector3<Scalar> next = p + dims.length[detail::idx(k)] * dir;
      PhalanxCapsule<Scalar>& c = out.phalanges[detail::idx(k)];
      c.base = R * p + t;
      c.tip = R * next + t;
      c.radius = dims.radius[detail::idx(k)];
      c.finger = phalanx_finger(k);
      c.phalanx = phalanx_kind(k);
      joint[j].point = c.base;
      joint[j].axis = axis;
      p = next;
    }
    PhalanxCapsule<Scalar>& m = out.phalanges[detail::idx(hand_phalanx_count + f)];
    m.base = f == 0 ? out.joints[0].point : Vector3<Scalar>(R * dims.palm_base[detail::idx(f - 1)] + t);
    m.tip = out.phalanges[detail::idx(first)].base;
    m.radius = dims.metacarpal_radius[detail::idx(f)];
    m.finger = static_cast<Finger>(f);
    m.phalanx = Phalanx::Metacarpal;
  }
  return Status::Ok;
}

}  // namespace grip
