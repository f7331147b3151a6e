#pragma once
/// \file
/// The whole hand's 20 joints: their order, the joint vector, joint limits and the usual
/// DIP-PIP coupling. Forward kinematics over them is in hand_kinematics.hpp, their Jacobians
/// in hand_jacobian.hpp, glove readings to them in glove.hpp.
///
/// Joint order, four per digit, proximal first: joint j of digit f is index 4 f + j.
///   thumb  0 CMC flexion, 1 CMC abduction, 2 MCP flexion, 3 IP flexion;
///   finger f = 1 (index) .. 4 (little): 4 f MCP abduction, 4 f + 1 MCP flexion,
///          4 f + 2 PIP flexion, 4 f + 3 DIP flexion.
/// Signs (both hands, see hand_model.hpp): flexion positive closes the hand; finger abduction
/// positive turns the finger radially (towards the thumb); thumb CMC flexion positive carries
/// the metacarpal across the palm (ulnarly), CMC abduction positive lifts it away from the
/// palm (palmar abduction). All zeros is the open rest pose: fingers straight, thumb in the
/// palm plane.

#include <array>

#include <Eigen/Core>

#include "grip/core/index.hpp"
#include "grip/hand/squeeze.hpp"

namespace grip {

/// Number of joints of the whole hand model.
constexpr int hand_dof_count = 20;

/// The 20 joints by name, valued as their index in the joint vector.
enum class HandJoint {
  ThumbCmcFlexion = 0,
  ThumbCmcAbduction,
  ThumbMcp,
  ThumbIp,
  IndexAbduction,
  IndexMcp,
  IndexPip,
  IndexDip,
  LongAbduction,
  LongMcp,
  LongPip,
  LongDip,
  RingAbduction,
  RingMcp,
  RingPip,
  RingDip,
  LittleAbduction,
  LittleMcp,
  LittlePip,
  LittleDip,
};

/// The joint vector of the whole hand (rad), in the order of this file.
template <class Scalar>
using HandJoints = Eigen::Matrix<Scalar, hand_dof_count, 1>;

/// Index of joint j (0 .. 3, proximal first) of digit f.
constexpr int joint_index(Finger f, int j) { return 4 * static_cast<int>(f) + j; }

/// The innermost joint of the 20 that moves body k (order of hand_model.hpp) about its own
/// proximal end: a finger's MCP, PIP or DIP flexion, the thumb's MCP or IP; for the thumb's
/// metacarpal (k = 14) its CMC abduction; -1 for a finger's metacarpal (k = 15 .. 18), which
/// no joint moves. Body k is moved by every joint of its digit from 4 f up to this one.
constexpr int phalanx_joint(int k) {
  return k >= 15 ? -1 : k == 14 ? 1 : k < 2 ? 2 + k : 4 * (1 + (k - 2) / 3) + 1 + (k - 2) % 3;
}

/// Lower and upper limit of every joint (rad): the range a mapping or a closing helper keeps
/// the hand in. Invariant: lower <= upper, zero within (the rest pose is reachable).
template <class Scalar>
struct JointLimits {
  std::array<Scalar, hand_dof_count> lower{};  ///< Least angle of each joint (rad).
  std::array<Scalar, hand_dof_count> upper{};  ///< Largest angle of each joint (rad).

  /// The model's ranges (degrees; typical active ranges of motion, rounded; model choices):
  /// thumb CMC flexion -15 .. 45, CMC abduction 0 .. 60, MCP -10 .. 80, IP -15 .. 90;
  /// fingers MCP abduction -20 .. 20, MCP flexion -20 .. 90, PIP 0 .. 110, DIP 0 .. 90.
  static JointLimits standard() {
    const Scalar deg = Scalar(3.14159265358979323846) / Scalar(180);
    JointLimits l;
    const Scalar thumb[4][2] = {{-15, 45}, {0, 60}, {-10, 80}, {-15, 90}};
    const Scalar finger[4][2] = {{-20, 20}, {-20, 90}, {0, 110}, {0, 90}};
    for (int i = 0; i < hand_dof_count; ++i) {
      const Scalar* r = i < 4 ? thumb[i] : finger[i % 4];
      l.lower[detail::idx(i)] = r[0] * deg;
      l.upper[detail::idx(i)] = r[1] * deg;
    }
    return l;
  }

  /// True if every joint of q lies within its range (a NaN is outside).
  bool contains(const HandJoints<Scalar>& q) const {
    for (int i = 0; i < hand_dof_count; ++i)
      if (!(q(i) >= lower[detail::idx(i)] && q(i) <= upper[detail::idx(i)])) return false;
    return true;
  }

  /// Clamps q into the ranges; returns the number of joints moved. A NaN joint becomes its
  /// lower limit (and counts).
  int clamp(HandJoints<Scalar>& q) const {
    int moved = 0;
    for (int i = 0; i < hand_dof_count; ++i) {
      const Scalar lo = lower[detail::idx(i)], hi = upper[detail::idx(i)];
      const Scalar v = q(i) >= lo ? (q(i) <= hi ? q(i) : hi) : lo;
      moved += v != q(i) ? 1 : 0;
      q(i) = v;
    }
    return moved;
  }
};

/// The coupling of most hand models and of the tendons: each finger's DIP flexion set to
/// 2/3 of its PIP flexion (the thumb is left alone).
template <class Scalar>
void couple_dip(HandJoints<Scalar>& q) {
  for (int f = 1; f < 5; ++f) q(4 * f + 3) = Scalar(2) / Scalar(3) * q(4 * f + 2);
}

}  // namespace grip
