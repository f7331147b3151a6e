#pragma once
/// \file
/// The virtual hand's topology and dimensions (paper section 3): five digits, 14 phalanges,
/// 14 measured joints, and anthropometric defaults scaled by hand length; the whole hand adds
/// the palm (five metacarpal bodies) and 20 joints (hand_joints.hpp).
///
/// Hand frame (right hand; the wrist pose of the tracker maps it to the world):
/// - origin at the wrist (centre of the distal wrist crease);
/// - +x distal, along the long finger's metacarpal; +y radial (towards the thumb);
///   +z dorsal (the back of the hand), so the palm faces -z.
///
/// The order of the phalanges, joints and bodies, and their names: phalanx.hpp.

#include <array>
#include <cmath>

#include <Eigen/Geometry>

#include "grip/core/index.hpp"
#include "grip/core/status.hpp"
#include "grip/core/types.hpp"
#include "grip/hand/hand_joints.hpp"
#include "grip/hand/phalanx.hpp"
#include "grip/hand/squeeze.hpp"

namespace grip {

/// Which hand a model is. A left hand is the mirror image of the right in the hand frame's
/// x-z plane (y -> -y): its radial side is -y; every joint angle keeps its anatomical sign.
enum class Side { Right, Left };

/// The 14 joint flexion angles (rad) in the order of this file. Positive flexes (closes the
/// hand); all zero is the rest pose (fingers straight in the palm plane).
template <class Scalar>
using JointAngles = Eigen::Matrix<Scalar, hand_joint_count, 1>;

/// Segment lengths as fractions of hand length, from Buchholz, Armstrong and Goldstein
/// (1992), "Anthropometric data for describing the kinematics of the human hand",
/// Ergonomics 35(3), segment-length coefficients (joint centre to joint centre; distal:
/// joint centre to fingertip). Rows thumb..little; columns metacarpal, proximal, middle,
/// distal (the thumb has no middle: 0).
template <class Scalar>
constexpr std::array<std::array<Scalar, 4>, 5> buchholz_segment_fractions() {
  return {{{Scalar(0.251), Scalar(0.196), Scalar(0), Scalar(0.158)},
           {Scalar(0.374), Scalar(0.265), Scalar(0.143), Scalar(0.097)},
           {Scalar(0.373), Scalar(0.277), Scalar(0.170), Scalar(0.108)},
           {Scalar(0.336), Scalar(0.259), Scalar(0.165), Scalar(0.107)},
           {Scalar(0.295), Scalar(0.206), Scalar(0.117), Scalar(0.093)}}};
}

/// Dimensions and joint layout of the hand model, in the hand frame (m, rad).
///
/// standard(L) fills it from hand length L:
/// - segment lengths: buchholz_segment_fractions() times L;
/// - finger MCP joints at x = (metacarpal fraction) L, z = 0, y = +0.105 L (index), 0 (long),
///   -0.10 L (ring), -0.20 L (little): a model choice (about one finger breadth apart);
/// - radii (a phalanx is a capsule): proximal 0.045 L, middle 0.040 L, distal 0.036 L;
///   thumb proximal 0.050 L, distal 0.045 L (model choices, about half a segment breadth);
/// - fingers at rest point along +x and flex about +y (towards the palm, -z);
/// - the thumb's CMC joint sits at (0.05 L, 0.22 L, 0); its metacarpal (0.251 L, rigid, not a
///   collision body) points palmar-distally along (sin 25 deg, 0, -cos 25 deg), which is also
///   the rest direction of its phalanges; the thumb flexes about -y (towards +x, wrapping
///   under an object held against the fingers).
/// - joint limits: finger MCP 90 deg, PIP 110 deg, DIP 90 deg; thumb MCP 80, IP 90 deg
///   (upper limits; lower limits 0), used by helpers that close the hand, not enforced by
///   forward kinematics.
///
/// The whole hand of 20 joints (hand_joints.hpp) shares the fingers and adds (model choices):
/// - finger MCP abduction about the palm normal +z through the MCP;
/// - a thumb that opens flat: at all-zero joints its metacarpal and phalanges point along
///   open_thumb_direction = (cos 40 deg, sin 40 deg, 0) in the palm plane, flexing (MCP, IP)
///   about open_thumb_flexion_axis, chosen so that flexion moves the tip as much ulnarly as
///   palmarly (45 deg between the palm plane and the path);
/// - thumb CMC flexion about cmc_flexion_axis = -z and then CMC abduction about
///   abduction_axis[0] = (-cos 10 deg, 0, -sin 10 deg), both through thumb_cmc: 80 deg apart,
///   not perpendicular, as Hollister et al. (1992, J. Orthop. Res. 10(3)) found the joint's
///   axes to be (the angle is a model choice, and these axes meet, which theirs do not);
/// - limits: JointLimits::standard().
/// - the palm: each finger's metacarpal a capsule from palm_base (x = 0.10 L; y = 0.07 L,
///   0, -0.06 L, -0.12 L index to little, converging towards the wrist) to its MCP, radius
///   0.055 L; the thumb's from thumb_cmc to its MCP, radius 0.065 L (the thenar eminence).
///   Model choices: neighbours overlap, so the palm's surface is continuous, about 0.055 L
///   palmar of the joint centres (the phalanges' is 0.036 .. 0.045 L).
/// standard(L, Side::Left) mirrors every point and direction (y -> -y) and every axis as an
/// axis (a -> -(a_x, -a_y, a_z)), so that positive angles keep their meaning.
template <class Scalar>
struct HandDimensions {
  using Angles = JointAngles<Scalar>;                              ///< The 14 joint angles.
  using Transform = Eigen::Transform<Scalar, 3, Eigen::Isometry>;  ///< A rigid pose (hand -> world).

  Scalar hand_length{Scalar(0.19)};                 ///< L (m), wrist crease to long fingertip.
  std::array<Scalar, hand_phalanx_count> length{};  ///< Segment length of phalanx k (m).
  std::array<Scalar, hand_phalanx_count> radius{};  ///< Capsule radius of phalanx k (m).
  std::array<Vector3<Scalar>, 5> base{};            ///< First joint of each digit (finger MCP, thumb MCP), hand frame.
  std::array<Vector3<Scalar>, 5> rest_direction{};  ///< Unit direction of each digit's phalanges at rest.
  std::array<Vector3<Scalar>, 5> flexion_axis{};    ///< Unit axis about which a positive angle flexes.
  std::array<Scalar, hand_joint_count> joint_upper_limit{};  ///< Largest flexion (rad) for closing helpers.
  Vector3<Scalar> thumb_cmc{Vector3<Scalar>::Zero()};        ///< Thumb CMC joint, hand frame.
  Scalar thumb_metacarpal{0};                                ///< Thumb CMC to MCP (m).
  Side side{Side::Right};                                    ///< Which hand.
  /// Fingers: MCP abduction axis; [0]: the thumb's CMC abduction axis (zero pose).
  std::array<Vector3<Scalar>, 5> abduction_axis{};
  Vector3<Scalar> cmc_flexion_axis{Vector3<Scalar>::Zero()};         ///< Thumb CMC flexion axis.
  Vector3<Scalar> open_thumb_direction{Vector3<Scalar>::Zero()};     ///< Thumb at all-zero 20 joints.
  Vector3<Scalar> open_thumb_flexion_axis{Vector3<Scalar>::Zero()};  ///< Its MCP and IP axis there.
  JointLimits<Scalar> limits{JointLimits<Scalar>::standard()};       ///< Ranges of the 20 joints.
  /// Proximal end of finger f's metacarpal body at [f - 1] (the thumb's is thumb_cmc).
  std::array<Vector3<Scalar>, 4> palm_base{};
  std::array<Scalar, 5> metacarpal_radius{};  ///< Radius of digit f's metacarpal body (m).

  /// The anthropometric defaults described above for hand length L (m). A non-finite or
  /// non-positive L gives dimensions that validate() rejects.
  static HandDimensions standard(Scalar L = Scalar(0.19), Side side = Side::Right) {
    HandDimensions d;
    d.hand_length = L;
    const auto frac = buchholz_segment_fractions<Scalar>();
    const Scalar deg = Scalar(3.14159265358979323846) / Scalar(180);
    const Scalar y_mcp[5] = {Scalar(0), Scalar(0.105), Scalar(0), Scalar(-0.10), Scalar(-0.20)};
    const Scalar r_finger[3] = {Scalar(0.045), Scalar(0.040), Scalar(0.036)};
    for (int f = 1; f < 5; ++f) {
      d.base[detail::idx(f)] = Vector3<Scalar>(frac[detail::idx(f)][0] * L, y_mcp[f] * L, Scalar(0));
      d.rest_direction[detail::idx(f)] = Vector3<Scalar>::UnitX();
      d.flexion_axis[detail::idx(f)] = Vector3<Scalar>::UnitY();
      d.abduction_axis[detail::idx(f)] = Vector3<Scalar>::UnitZ();
      const Scalar y_base[5] = {Scalar(0), Scalar(0.07), Scalar(0), Scalar(-0.06), Scalar(-0.12)};
      d.palm_base[detail::idx(f - 1)] = Vector3<Scalar>(Scalar(0.10) * L, y_base[f] * L, Scalar(0));
      d.metacarpal_radius[detail::idx(f)] = Scalar(0.055) * L;
      for (int p = 0; p < 3; ++p) {
        const int k = phalanx_index(static_cast<Finger>(f), static_cast<Phalanx>(p));
        d.length[detail::idx(k)] = frac[detail::idx(f)][detail::idx(1 + p)] * L;
        d.radius[detail::idx(k)] = r_finger[p] * L;
        d.joint_upper_limit[detail::idx(k)] = (p == 1 ? Scalar(110) : Scalar(90)) * deg;
      }
    }
    const Scalar beta = Scalar(25) * deg;
    d.thumb_cmc = Vector3<Scalar>(Scalar(0.05) * L, Scalar(0.22) * L, Scalar(0));
    d.rest_direction[0] = Vector3<Scalar>(std::sin(beta), Scalar(0), -std::cos(beta));
    d.flexion_axis[0] = -Vector3<Scalar>::UnitY();
    d.thumb_metacarpal = frac[0][0] * L;
    d.metacarpal_radius[0] = Scalar(0.065) * L;
    d.base[0] = d.thumb_cmc + d.thumb_metacarpal * d.rest_direction[0];
    d.length[0] = frac[0][1] * L;
    d.length[1] = frac[0][3] * L;
    d.radius[0] = Scalar(0.050) * L;
    d.radius[1] = Scalar(0.045) * L;
    d.joint_upper_limit[0] = Scalar(80) * deg;
    d.joint_upper_limit[1] = Scalar(90) * deg;
    const Scalar open = Scalar(40) * deg, tilt = Scalar(10) * deg, path = Scalar(45) * deg;
    d.open_thumb_direction = Vector3<Scalar>(std::cos(open), std::sin(open), Scalar(0));
    const Vector3<Scalar> ulnar(std::sin(open), -std::cos(open), Scalar(0));
    const Vector3<Scalar> moves = std::cos(path) * ulnar - std::sin(path) * Vector3<Scalar>::UnitZ();
    d.open_thumb_flexion_axis = d.open_thumb_direction.cross(moves);  // axis x direction = moves
    d.cmc_flexion_axis = -Vector3<Scalar>::UnitZ();
    d.abduction_axis[0] = Vector3<Scalar>(-std::cos(tilt), Scalar(0), -std::sin(tilt));
    if (side == Side::Left) d.mirror();
    return d;
  }

  /// Mirrors the model into the other hand (y -> -y for points and directions, a ->
  /// -(a_x, -a_y, a_z) for axes) and flips `side`.
  void mirror() {
    const auto point = [](Vector3<Scalar>& v) { v.y() = -v.y(); };
    const auto axis = [](Vector3<Scalar>& v) { v = Vector3<Scalar>(-v.x(), v.y(), -v.z()); };
    for (int f = 0; f < 5; ++f) {
      point(base[detail::idx(f)]);
      point(rest_direction[detail::idx(f)]);
      axis(flexion_axis[detail::idx(f)]);
      axis(abduction_axis[detail::idx(f)]);
    }
    point(thumb_cmc);
    for (Vector3<Scalar>& p : palm_base) point(p);
    point(open_thumb_direction);
    axis(open_thumb_flexion_axis);
    axis(cmc_flexion_axis);
    side = side == Side::Right ? Side::Left : Side::Right;
  }
};

/// Ok if every number is finite, lengths and radii are positive, the directions and axes are
/// unit (within 1e-3), each digit's rest direction perpendicular to its flexion axis (|dot| <=
/// 1e-3, and the open thumb's likewise), and every joint range holds zero; InvalidInput
/// otherwise.
template <class Scalar>
Status validate(const HandDimensions<Scalar>& d) {
  const Scalar tol = Scalar(1e-3);
  if (!std::isfinite(d.hand_length) || !(d.hand_length > Scalar(0))) return Status::InvalidInput;
  for (int k = 0; k < hand_phalanx_count; ++k) {
    if (!std::isfinite(d.length[detail::idx(k)]) || !(d.length[detail::idx(k)] > Scalar(0)))
      return Status::InvalidInput;
    if (!std::isfinite(d.radius[detail::idx(k)]) || !(d.radius[detail::idx(k)] > Scalar(0)))
      return Status::InvalidInput;
    if (!std::isfinite(d.joint_upper_limit[detail::idx(k)])) return Status::InvalidInput;
  }
  if (!d.thumb_cmc.allFinite() || !std::isfinite(d.thumb_metacarpal) || !(d.thumb_metacarpal > Scalar(0)))
    return Status::InvalidInput;
  // | |v| - 1 | <= tol, without a square root (validate runs in every forward kinematics).
  const Scalar lo = (Scalar(1) - tol) * (Scalar(1) - tol), hi = (Scalar(1) + tol) * (Scalar(1) + tol);
  const auto unit = [lo, hi](const Vector3<Scalar>& v) {
    const Scalar n2 = v.squaredNorm();
    return n2 >= lo && n2 <= hi;  // false for NaN; an infinite component gives n2 = inf
  };
  for (int f = 0; f < 5; ++f) {
    if (!d.base[detail::idx(f)].allFinite() || !unit(d.rest_direction[detail::idx(f)]) ||
        !unit(d.flexion_axis[detail::idx(f)]) ||
        !(std::abs(d.rest_direction[detail::idx(f)].dot(d.flexion_axis[detail::idx(f)])) <= tol))
      return Status::InvalidInput;
  }
  for (int f = 0; f < 5; ++f)
    if (!unit(d.abduction_axis[detail::idx(f)]) || !std::isfinite(d.metacarpal_radius[detail::idx(f)]) ||
        !(d.metacarpal_radius[detail::idx(f)] > Scalar(0)) || (f > 0 && !d.palm_base[detail::idx(f - 1)].allFinite()))
      return Status::InvalidInput;
  if (!unit(d.cmc_flexion_axis) || !unit(d.open_thumb_direction) || !unit(d.open_thumb_flexion_axis) ||
      !(std::abs(d.open_thumb_direction.dot(d.open_thumb_flexion_axis)) <= tol))
    return Status::InvalidInput;
  for (int i = 0; i < hand_dof_count; ++i)
    if (!(d.limits.lower[detail::idx(i)] <= Scalar(0) && d.limits.upper[detail::idx(i)] >= Scalar(0)))
      return Status::InvalidInput;
  return Status::Ok;
}

}  // namespace grip
