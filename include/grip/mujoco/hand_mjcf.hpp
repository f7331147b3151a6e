#pragma once
/// \file
/// grip's whole hand (20 joints, 19 capsule bodies: hand/hand_model.hpp) written as MJCF, so
/// that a MuJoCo model moves exactly as grip's forward kinematics: the same joint axes, order
/// and limits, the same capsules. Offline (builds a std::string on the heap); text only, no
/// MuJoCo call, so it serves the Python package too. Part of grip::mujoco.
///
/// What it writes (all names prefixed by HandMjcf::prefix):
/// - a body "hand" at the wrist pose: with mocap on, a free body (the palm's mass and inertia)
///   welded to a mocap body "hand_target" that a tracker drives (mocap_pos, mocap_quat): the
///   weld makes the hand move with real velocities, so that its contacts carry friction (a mocap
///   body itself only teleports); with mocap off, fixed in the world;
/// - per digit, bodies named hand_body_name(k) (body_map.hpp), each with its origin at its
///   phalanx's base (the proximal joint centre) and the hand frame's axes at zero angles, and a
///   capsule geom from the origin along the rest direction (length and radius of HandDimensions);
///   the finger metacarpals as bodies fixed in the hand;
/// - the 20 hinge joints named hand_joint_name(i) in grip's order (hand_joints.hpp), with grip's
///   axes and JointLimits as ranges: in qpos consecutively in that order, after the hand's free
///   joint (7 numbers) when mocap is on, when the hand is the first body with joints in the model;
/// - with a servo gain, one position actuator per joint (named as the joint) whose control is
///   the joint's target angle (rad), in the joints' order.
/// Hand geoms do not collide with each other (contype 2, conaffinity 1): the palm's capsules
/// overlap by design. Everything else is the caller's: the scene's bodies (HandMjcf::worldbody)
/// and any top-level elements (HandMjcf::extra: assets, options, contacts).

#include <cmath>
#include <cstdio>
#include <string>

#include <Eigen/Geometry>

#include "grip/core/index.hpp"
#include "grip/core/status.hpp"
#include "grip/hand/hand_joints.hpp"
#include "grip/hand/hand_model.hpp"
#include "grip/mujoco/body_names.hpp"

namespace grip {
namespace mujoco {

/// Options of hand_mjcf(); one line each.
struct HandMjcf {
  std::string model{"grip_hand"};  ///< The `<mujoco model=...>` name.
  std::string prefix{};            ///< Prepended to every name the hand writes (two hands in one scene).
  Eigen::Isometry3d wrist{Eigen::Isometry3d::Identity()};  ///< The hand frame's initial pose (m; world).
  bool mocap{true};                  ///< The hand welded to a mocap target (tracker-driven); false: fixed.
  double palm_mass{0.4};             ///< The hand body's mass (kg) with mocap on; a box's inertia of 10 x 8 x 3 cm.
  double servo_gain{2.0};            ///< Position actuators' kp (N m/rad); 0 writes no actuator.
  double joint_damping{0.05};        ///< Joint damping (N m s/rad).
  double armature{1e-4};             ///< Joint armature (kg m^2), steadies the light phalanges.
  double density{1000.0};            ///< Capsule density (kg/m^3), for the bodies' masses.
  double friction{0.8};              ///< The hand geoms' sliding friction coefficient.
  double torsional_friction{0.005};  ///< Their torsional coefficient (m), used with condim 4 and 6.
  int condim{3};                     ///< The hand geoms' contact dimension (1, 3, 4 or 6).
  double timestep{0.001};            ///< The model's timestep (s).
  std::string worldbody{};           ///< XML placed in `<worldbody>` after the hand (a table, an object).
  std::string extra{};               ///< XML placed in `<mujoco>` after the worldbody (assets, contacts).
};

/// Writes grip's whole hand of dimensions `dims` as a complete MJCF document into `out`.
/// InvalidInput (out cleared) when dims fail validate(), an option is not finite or out of
/// range (gain, damping, armature, friction < 0; density, palm mass, timestep <= 0; condim not 1, 3, 4
/// or 6; a wrist that is not rigid within 1e-9), or the prefix holds a character outside
/// [A-Za-z0-9_-.]; Ok otherwise.
Status hand_mjcf(const HandDimensions<double>& dims, const HandMjcf& options, std::string& out);

// ---------------------------------------------------------------------------------------------

namespace detail {
inline std::string mjcf_number(double x) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.17g", x);
  return buf;
}
inline std::string mjcf_vector(const Eigen::Vector3d& v) {
  return mjcf_number(v.x()) + " " + mjcf_number(v.y()) + " " + mjcf_number(v.z());
}
inline bool mjcf_name_ok(const std::string& s) {
  for (const char c : s)
    if (!((c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_' || c == '-' ||
          c == '.'))
      return false;
  return true;
}
}  // namespace detail

inline Status hand_mjcf(const HandDimensions<double>& dims, const HandMjcf& o, std::string& out) {
  using detail::mjcf_number;
  using detail::mjcf_vector;
  using V = Eigen::Vector3d;
  out.clear();
  const Eigen::Matrix3d R = o.wrist.linear();
  const bool options_ok =
      std::isfinite(o.servo_gain) && o.servo_gain >= 0 && std::isfinite(o.joint_damping) && o.joint_damping >= 0 &&
      std::isfinite(o.armature) && o.armature >= 0 && std::isfinite(o.density) && o.density > 0 &&
      std::isfinite(o.palm_mass) && o.palm_mass > 0 && std::isfinite(o.friction) && o.friction >= 0 &&
      std::isfinite(o.torsional_friction) && o.torsional_friction >= 0 && std::isfinite(o.timestep) && o.timestep > 0 &&
      (o.condim == 1 || o.condim == 3 || o.condim == 4 || o.condim == 6) && o.wrist.matrix().allFinite() &&
      (R.transpose() * R - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff() <= 1e-9 && R.determinant() > 0 &&
      detail::mjcf_name_ok(o.prefix) && detail::mjcf_name_ok(o.model);
  if (validate(dims) != Status::Ok || !options_ok) return Status::InvalidInput;
  const std::string& pre = o.prefix;
  const auto joint = [&](int i, const V& axis) {
    return "<joint name=\"" + pre + hand_joint_name(i) + "\" type=\"hinge\" axis=\"" + mjcf_vector(axis) +
           "\" limited=\"true\" range=\"" + mjcf_number(dims.limits.lower[grip::detail::idx(i)]) + " " +
           mjcf_number(dims.limits.upper[grip::detail::idx(i)]) + "\"/>";
  };
  const auto capsule = [&](const V& to, double radius) {
    return "<geom type=\"capsule\" fromto=\"0 0 0 " + mjcf_vector(to) + "\" size=\"" + mjcf_number(radius) + "\"/>";
  };
  const auto open_body = [&](int k, const V& pos) {
    return "<body name=\"" + pre + hand_body_name(k) + "\" pos=\"" + mjcf_vector(pos) + "\">";
  };
  std::string b;  // the hand's bodies
  // The thumb: its metacarpal turns about the CMC's two axes; MCP and IP about the open
  // thumb's flexion axis.
  const V od = dims.open_thumb_direction;
  b += open_body(14, dims.thumb_cmc) + joint(0, dims.cmc_flexion_axis) + joint(1, dims.abduction_axis[0]) +
       capsule(dims.thumb_metacarpal * od, dims.metacarpal_radius[0]);
  b += open_body(0, dims.thumb_metacarpal * od) + joint(2, dims.open_thumb_flexion_axis) +
       capsule(dims.length[0] * od, dims.radius[0]);
  b += open_body(1, dims.length[0] * od) + joint(3, dims.open_thumb_flexion_axis) +
       capsule(dims.length[1] * od, dims.radius[1]) + "</body></body></body>";
  for (int f = 1; f < 5; ++f) {
    const auto fi = grip::detail::idx(f);
    const V d = dims.rest_direction[fi];
    const V e = dims.flexion_axis[fi];
    const int k0 = phalanx_index(static_cast<Finger>(f), Phalanx::Proximal);
    V pos = dims.base[fi];
    for (int j = 0; j < 3; ++j) {
      const int k = k0 + j;
      b += open_body(k, pos);
      if (j == 0) b += joint(4 * f, dims.abduction_axis[fi]);
      b += joint(4 * f + 1 + j, e) + capsule(dims.length[grip::detail::idx(k)] * d, dims.radius[grip::detail::idx(k)]);
      pos = dims.length[grip::detail::idx(k)] * d;
    }
    b += "</body></body></body>";
  }
  for (int f = 1; f < 5; ++f) {
    const V base = dims.palm_base[grip::detail::idx(f - 1)];
    b += open_body(hand_phalanx_count + f, base) +
         capsule(dims.base[grip::detail::idx(f)] - base, dims.metacarpal_radius[grip::detail::idx(f)]) + "</body>";
  }
  const Eigen::Quaterniond q(R);
  std::string s = "<mujoco model=\"" + o.model + "\">\n";
  s += "<compiler angle=\"radian\"/>\n<option timestep=\"" + mjcf_number(o.timestep) + "\"/>\n";
  s += "<default><default class=\"" + pre + "grip_hand\"><geom contype=\"2\" conaffinity=\"1\" condim=\"" +
       std::to_string(o.condim) + "\" friction=\"" + mjcf_number(o.friction) + " " + mjcf_number(o.torsional_friction) +
       " 0.0001\" density=\"" + mjcf_number(o.density) + "\"/><joint damping=\"" + mjcf_number(o.joint_damping) +
       "\" armature=\"" + mjcf_number(o.armature) + "\"/></default></default>\n";
  const std::string pose = "pos=\"" + mjcf_vector(o.wrist.translation()) + "\" quat=\"" + mjcf_number(q.w()) + " " +
                           mjcf_number(q.x()) + " " + mjcf_number(q.y()) + " " + mjcf_number(q.z()) + "\"";
  s += "<worldbody>\n";
  if (o.mocap) s += "<body name=\"" + pre + "hand_target\" mocap=\"true\" " + pose + "/>\n";
  s += "<body name=\"" + pre + "hand\" childclass=\"" + pre + "grip_hand\" " + pose + ">\n";
  if (o.mocap) {
    // The palm's inertia as a uniform box of 10 x 8 x 3 cm about its centre, 5 cm distal.
    const double a = 0.10, w = 0.08, h = 0.03, k = o.palm_mass / 12;
    s += "<freejoint name=\"" + pre + "hand_free\"/><inertial pos=\"0.05 0 0\" mass=\"" + mjcf_number(o.palm_mass) +
         "\" diaginertia=\"" + mjcf_number(k * (w * w + h * h)) + " " + mjcf_number(k * (a * a + h * h)) + " " +
         mjcf_number(k * (a * a + w * w)) + "\"/>\n";
  }
  s += b + "\n</body>\n" + o.worldbody + "\n</worldbody>\n";
  if (o.mocap)
    s += "<equality><weld body1=\"" + pre + "hand_target\" body2=\"" + pre + "hand\" solref=\"0.01 1\"/></equality>\n";
  if (o.servo_gain > 0) {
    s += "<actuator>\n";
    for (int i = 0; i < hand_dof_count; ++i)
      s += "<position name=\"" + pre + hand_joint_name(i) + "\" joint=\"" + pre + hand_joint_name(i) + "\" kp=\"" +
           mjcf_number(o.servo_gain) + "\" ctrllimited=\"true\" ctrlrange=\"" +
           mjcf_number(dims.limits.lower[grip::detail::idx(i)]) + " " +
           mjcf_number(dims.limits.upper[grip::detail::idx(i)]) + "\"/>\n";
    s += "</actuator>\n";
  }
  s += o.extra + "\n</mujoco>\n";
  out = std::move(s);
  return Status::Ok;
}

}  // namespace mujoco
}  // namespace grip
