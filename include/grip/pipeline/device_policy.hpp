#pragma once
/// \file
/// Device policies: what a force-feedback device can render of the forces the hand should
/// feel. The haptic pipeline takes one as a template parameter (haptic_pipeline.hpp) and
/// calls render() at the end of every frame; each policy clips to what its hardware can do
/// and reports what it clipped. No heap, no exceptions.
///
///   PhalanxActuators  one actuator per phalanx pushing along its actuation direction (the
///                     paper's glove): a force in [0, limit] along it.
///   VectorForces      a 3-D force per phalanx, or per fingertip only: saturated by norm (the
///                     direction is kept), never per component.
///   JointTorques      an exoskeleton or tendon glove: one torque per joint, tau = sum J^T F
///                     over the phalanges, each clipped to [-limit, limit].
///   JointBrakes       passive brakes on the joints: a brake can only resist the joint's
///                     motion, so a torque that would drive the joint along its velocity is
///                     not rendered (0); a resisting one is clipped to the brake's limit.
///
/// Every policy: `Command` (its output, with `clipped`, the number of outputs it changed, and
/// `status`), and `Status render(const FeltForces<S>&, const HandPosture<S>&, const
/// HandJoints<S>& joint_velocity, Command&) const`: InvalidInput (command zeroed) on a
/// non-finite input or a negative limit; Ok otherwise.

#include <array>
#include <cmath>

#include "grip/core/index.hpp"
#include "grip/core/status.hpp"
#include "grip/core/types.hpp"
#include "grip/hand/hand_jacobian.hpp"
#include "grip/hand/hand_joints.hpp"
#include "grip/hand/hand_kinematics.hpp"
#include "grip/hand/hand_model.hpp"
#include "grip/pipeline/net_wrench_command.hpp"
#include "grip/pipeline/net_wrench_vector.hpp"

namespace grip {

/// What the hand should feel, per body (the phalanges, then the palm's metacarpals; order of
/// hand_model.hpp), world frame: the sum of -f_i over the body's contacts and the point it
/// acts at (the contacts' points weighted by their force; the body's tip when it has none).
/// Phalanx devices render the phalanges; joint devices take the thenar's torques too.
template <class Scalar>
struct FeltForces {
  std::array<Vector3<Scalar>, hand_body_count> force{};  ///< N
  std::array<Vector3<Scalar>, hand_body_count> point{};  ///< m
  std::array<bool, hand_body_count> in_contact{};        ///< the body touches the object
  std::array<Scalar, hand_body_count> weight{};          ///< sum of |force| of add()'s contacts (N)
  /// Per phalanx, actuation_direction() of the posture (set by finish()).
  std::array<Vector3<Scalar>, hand_phalanx_count> direction{};
  FeltForces() {
    force.fill(Vector3<Scalar>::Zero());
    point.fill(Vector3<Scalar>::Zero());
    direction.fill(Vector3<Scalar>::Zero());
  }
  /// Adds a contact of body k: the hand feels `felt` (N) at `at` (m). Call finish() after the
  /// last one.
  void add(int k, const Vector3<Scalar>& felt, const Vector3<Scalar>& at) {
    const auto i = detail::idx(k);
    const Scalar w = felt.norm();
    force[i] += felt;
    point[i] += w * at;
    weight[i] += w;
    in_contact[i] = true;
  }
  /// Turns the weighted sums of add() into points (a body without force acts at its tip) and
  /// sets each phalanx's actuation direction: call it once the contacts are added.
  void finish(const HandPosture<Scalar>& posture);
};

/// The direction in which phalanx k's actuator pushes: extension, u x e for the phalanx's
/// unit direction u and its flexion axis e (an object pressing on the palmar side pushes
/// along it). Zero for a degenerate phalanx.
template <class Scalar>
Vector3<Scalar> actuation_direction(const HandPosture<Scalar>& posture, int k) {
  const PhalanxCapsule<Scalar>& c = posture.phalanges[detail::idx(k)];
  const Vector3<Scalar> d = (c.tip - c.base).cross(posture.joints[detail::idx(phalanx_joint(k))].axis);
  const Scalar n = d.norm();
  return n > Scalar(0) ? Vector3<Scalar>(d / n) : Vector3<Scalar>::Zero();
}

template <class Scalar>
void FeltForces<Scalar>::finish(const HandPosture<Scalar>& posture) {
  for (int k = 0; k < hand_body_count; ++k) {
    const auto i = detail::idx(k);
    point[i] = weight[i] > Scalar(0) ? Vector3<Scalar>(point[i] / weight[i]) : posture.phalanges[i].tip;
  }
  for (int k = 0; k < hand_phalanx_count; ++k) direction[detail::idx(k)] = actuation_direction(posture, k);
}

namespace detail {
/// True if every phalanx's felt force is finite and every limit >= 0 (a NaN limit is not).
template <class Scalar>
bool phalanx_inputs_ok(const FeltForces<Scalar>& in, const std::array<Scalar, hand_phalanx_count>& limit) {
  for (int k = 0; k < hand_phalanx_count; ++k)
    if (!in.force[idx(k)].allFinite() || !(limit[idx(k)] >= Scalar(0))) return false;
  return true;
}

/// A pushing actuator's command for a wanted force along its direction: in [0, limit].
template <class Scalar>
Scalar push_command(Scalar wanted, Scalar limit) {
  return std::fmin(limit, std::fmax(Scalar(0), wanted));
}
}  // namespace detail

/// (a) One actuator per phalanx along its actuation direction (FeltForces::direction),
/// pushing only: command in [0, limit]. By default each phalanx is clipped on its own; with
/// net_wrench, the pushes are net_wrench_command's: those whose net wrench on the hand comes
/// closest to the felt one (net_wrench_command.hpp). Clipped: phalanges in contact whose push
/// differs from their own F . direction.
template <class Scalar>
struct PhalanxActuators {
  std::array<Scalar, hand_phalanx_count> limit{};  ///< Largest push (N) per phalanx, >= 0.
  bool net_wrench{false};                          ///< render the closest net wrench, not clips
  PhalanxActuators() { limit.fill(Scalar(10)); }

  /// What the actuators render in one frame.
  struct Command {
    std::array<Scalar, hand_phalanx_count> wanted{};  ///< F . direction (N)
    std::array<Scalar, hand_phalanx_count> force{};   ///< rendered (N)
    /// The felt net wrench that the pushes do not render (N; N m about `point`, the mean of the
    /// contact bodies' points): the palm's share, pulls, and what the limits cut.
    Wrench<Scalar> unrendered{Wrench<Scalar>::Zero()};
    Vector3<Scalar> point{Vector3<Scalar>::Zero()};  ///< unrendered's moment point (m, world)
    int clipped{0};                                  ///< phalanges in contact whose force != wanted
    /// Ok, or InvalidInput (command zeroed); with net_wrench, IterationLimit if its bound was met.
    Status status{Status::InvalidInput};
  };

  /// Renders `in` (its force and direction per phalanx) into `out`; see the file comment.
  Status render(const FeltForces<Scalar>& in, const HandPosture<Scalar>&, const HandJoints<Scalar>&,
                Command& out) const {
    out = Command{};
    if (!detail::phalanx_inputs_ok(in, limit)) return out.status;
    NetWrenchCommand<Scalar> best;
    if (net_wrench) {
      best = net_wrench_command(in.force, in.point, in.in_contact, in.direction, limit);
      if (best.status == Status::InvalidInput) return out.status;
    }
    for (int k = 0; k < hand_phalanx_count; ++k) {
      const auto i = detail::idx(k);
      out.wanted[i] = in.force[i].dot(in.direction[i]);
      out.force[i] = net_wrench ? best.force[i] : detail::push_command(out.wanted[i], limit[i]);
      out.clipped += in.in_contact[i] && out.force[i] != out.wanted[i] ? 1 : 0;
    }
    if (net_wrench) {  // net_wrench_command reported what its pushes leave unrendered
      out.unrendered = best.unrendered;
      out.point = best.point;
    } else {
      const FeltNetWrench<Scalar> felt = felt_net_wrench(in.force, in.point, in.in_contact);
      std::array<Scalar, hand_phalanx_count> rendered = out.force;  // a phalanx out of contact renders nothing
      for (int k = 0; k < hand_phalanx_count; ++k)
        if (!in.in_contact[detail::idx(k)]) rendered[detail::idx(k)] = Scalar(0);
      out.unrendered = unrendered_wrench(felt, in.point, in.direction, rendered);
      out.point = felt.point;
    }
    out.status = net_wrench ? best.status : Status::Ok;
    return out.status;
  }
};

/// (b) A 3-D force per phalanx (fingertips_only: per distal phalanx, the others rendering
/// nothing), at most `limit` in norm: each phalanx's own force scaled down as a whole (the
/// default), or with net_wrench the forces whose net wrench on the hand comes closest to the felt
/// one (net_wrench_vector.hpp).
template <class Scalar>
struct VectorForces {
  std::array<Scalar, hand_phalanx_count> limit{};  ///< Largest |force| (N) per phalanx, >= 0.
  bool fingertips_only{false};                     ///< Only the distal phalanges have a device.
  bool net_wrench{false};  ///< Render the closest net wrench (net_wrench_vector_command), not each phalanx scaled.
  VectorForces() { limit.fill(Scalar(10)); }

  /// What the device renders in one frame.
  struct Command {
    std::array<Vector3<Scalar>, hand_phalanx_count> force{};  ///< rendered (N, world)
    /// |rendered| / |wanted|: in [0, 1] when scaling; with net_wrench a phalanx may render more
    /// than its own (0 where nothing is wanted).
    std::array<Scalar, hand_phalanx_count> scale{};
    int clipped{0};  ///< phalanges whose rendered force differs from their own
    /// The felt net wrench that the forces do not render (N; N m about `point`, the mean of the
    /// contact bodies' points): the palm's share and what the limits cut.
    Wrench<Scalar> unrendered{Wrench<Scalar>::Zero()};
    Vector3<Scalar> point{Vector3<Scalar>::Zero()};  ///< unrendered's moment point (m, world)
    /// Ok, or InvalidInput (command zeroed); with net_wrench, IterationLimit if its bound was met.
    Status status{Status::InvalidInput};
    Command() { force.fill(Vector3<Scalar>::Zero()); }
  };

  /// Renders `in` (its force per phalanx) into `out`; see the file comment.
  Status render(const FeltForces<Scalar>& in, const HandPosture<Scalar>&, const HandJoints<Scalar>&,
                Command& out) const {
    out = Command{};
    if (!detail::phalanx_inputs_ok(in, limit)) return out.status;
    std::array<Scalar, hand_phalanx_count> reach = limit;  // the devices' limits, 0 where none
    for (int k = 0; k < hand_phalanx_count; ++k)
      if (fingertips_only && phalanx_kind(k) != Phalanx::Distal) reach[detail::idx(k)] = Scalar(0);
    NetWrenchVectorCommand<Scalar> best;
    if (net_wrench) {
      best = net_wrench_vector_command(in.force, in.point, in.in_contact, reach);
      if (best.status == Status::InvalidInput) return out.status;
    }
    for (int k = 0; k < hand_phalanx_count; ++k) {
      const auto i = detail::idx(k);
      const Scalar n = in.force[i].norm();
      if (net_wrench) {
        out.force[i] = best.force[i];
        out.scale[i] = n > Scalar(0) ? best.force[i].norm() / n : Scalar(0);
        out.clipped += in.in_contact[i] && best.force[i] != in.force[i] ? 1 : 0;
      } else {
        const Scalar s = n > reach[i] ? reach[i] / n : Scalar(1);
        out.scale[i] = s;
        out.force[i] = s * in.force[i];
        out.clipped += n > Scalar(0) && s < Scalar(1) ? 1 : 0;
      }
    }
    if (net_wrench) {
      out.unrendered = best.unrendered;
      out.point = best.point;
    } else {
      const FeltNetWrench<Scalar> felt = felt_net_wrench(in.force, in.point, in.in_contact);
      out.unrendered = felt.wrench;
      for (int k = 0; k < hand_phalanx_count; ++k) {
        const auto i = detail::idx(k);
        const Vector3<Scalar> f = in.in_contact[i] ? out.force[i] : Vector3<Scalar>(Vector3<Scalar>::Zero());
        out.unrendered.template head<3>() -= f;
        out.unrendered.template tail<3>() -= (in.point[i] - felt.point).cross(f);
      }
      out.point = felt.point;
    }
    out.status = net_wrench ? best.status : Status::Ok;
    return out.status;
  }
};

namespace detail {
/// tau = sum over phalanges of J^T F at each felt force's point. False on non-finite input.
template <class Scalar>
bool felt_torques(const FeltForces<Scalar>& in, const HandPosture<Scalar>& posture, HandJoints<Scalar>& tau) {
  tau.setZero();
  for (int k = 0; k < hand_body_count; ++k)
    if (add_joint_torques(posture, k, in.point[idx(k)], in.force[idx(k)], tau) != Status::Ok) return false;
  return true;
}
}  // namespace detail

namespace detail {
/// The command of the joint devices: per joint the torque wanted and the one rendered.
template <class Scalar>
struct JointCommand {
  HandJoints<Scalar> wanted{HandJoints<Scalar>::Zero()};  ///< J^T F (N m)
  HandJoints<Scalar> torque{HandJoints<Scalar>::Zero()};  ///< rendered (N m)
  int clipped{0};                                         ///< joints where torque != wanted
  Status status{Status::InvalidInput};                    ///< Ok, or InvalidInput (command zeroed)
};

/// J^T F clipped to [-limit, limit]; with `velocity`, a torque that would drive its joint
/// along the velocity (tau qdot > 0) renders 0 (a brake).
template <class Scalar>
Status render_joints(const std::array<Scalar, hand_dof_count>& limit, const FeltForces<Scalar>& in,
                     const HandPosture<Scalar>& posture, const HandJoints<Scalar>* velocity,
                     JointCommand<Scalar>& out) {
  out = JointCommand<Scalar>{};
  if (velocity != nullptr && !velocity->allFinite()) return out.status;
  for (int i = 0; i < hand_dof_count; ++i)
    if (!(limit[idx(i)] >= Scalar(0))) return out.status;
  if (!felt_torques(in, posture, out.wanted)) {
    out.wanted.setZero();
    return out.status;
  }
  for (int i = 0; i < hand_dof_count; ++i) {
    const Scalar l = limit[idx(i)];
    // tau qdot > 0 by the signs (their product underflows to 0 at the smallest speeds).
    const Scalar tau = out.wanted(i), qdot = velocity == nullptr ? Scalar(0) : (*velocity)(i);
    const bool renders = !((tau > Scalar(0) && qdot > Scalar(0)) || (tau < Scalar(0) && qdot < Scalar(0)));
    out.torque(i) = renders ? std::fmin(l, std::fmax(-l, out.wanted(i))) : Scalar(0);
    out.clipped += out.torque(i) != out.wanted(i) ? 1 : 0;
  }
  out.status = Status::Ok;
  return out.status;
}
}  // namespace detail

/// (c) One torque per joint: the torques J^T F of the felt forces summed over the bodies
/// (hand_jacobian.hpp), each clipped to [-limit, limit]. Joints the posture holds fixed get 0.
template <class Scalar>
struct JointTorques {
  std::array<Scalar, hand_dof_count> limit{};  ///< Largest |torque| (N m) per joint, >= 0.
  JointTorques() { limit.fill(Scalar(0.5)); }

  using Command = detail::JointCommand<Scalar>;  ///< wanted, torque, clipped, status

  /// Renders the torques of `in` at the joints of `posture` into `out`; see the file comment.
  Status render(const FeltForces<Scalar>& in, const HandPosture<Scalar>& posture, const HandJoints<Scalar>&,
                Command& out) const {
    return detail::render_joints(limit, in, posture, static_cast<const HandJoints<Scalar>*>(nullptr), out);
  }
};

/// (d) Passive brakes on the joints. The torque a joint should feel, J^T F as for
/// JointTorques, is rendered only where it resists the joint's motion (tau qdot <= 0; a joint
/// at rest can be held either way), clipped to [-limit, limit]; where it would drive the
/// joint along its velocity the brake renders 0 and counts it clipped.
template <class Scalar>
struct JointBrakes {
  std::array<Scalar, hand_dof_count> limit{};  ///< Largest braking torque (N m) per joint, >= 0.
  JointBrakes() { limit.fill(Scalar(0.5)); }

  using Command = detail::JointCommand<Scalar>;  ///< wanted, torque (resisting only), clipped, status

  /// Renders the resisting part of the torques of `in` at the joints of `posture`, given the
  /// joints' velocities (rad/s), into `out`; see the file comment.
  Status render(const FeltForces<Scalar>& in, const HandPosture<Scalar>& posture,
                const HandJoints<Scalar>& joint_velocity, Command& out) const {
    return detail::render_joints(limit, in, posture, &joint_velocity, out);
  }
};

}  // namespace grip
