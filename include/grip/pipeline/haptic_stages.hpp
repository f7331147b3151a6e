#pragma once
/// \file
/// The stages of HapticPipeline's frame (haptic_pipeline.hpp declares them with their contracts
/// and includes this file; include that header instead): posing the hand, carrying the held
/// object, the contacts, the object's external wrench, the force solve with its cone monitor,
/// the object's motion and each phalanx's feedback (docs/pipeline.md).

#include "grip/pipeline/haptic_pipeline.hpp"

namespace grip {

template <class Scalar, class Scene, class Solver, class Device>
template <class Derived>
bool HapticPipeline<Scalar, Scene, Solver, Device>::pose_hand(const WristState<Scalar>& wrist,
                                                              const Eigen::MatrixBase<Derived>& angles) {
  if (!wrist.pose.matrix().allFinite() || !wrist.linear_velocity.allFinite() || !wrist.angular_velocity.allFinite() ||
      !wrist.linear_acceleration.allFinite() || !wrist.angular_acceleration.allFinite() || !angles.allFinite() ||
      validate(object_) != Status::Ok || !(settings_.dt > Scalar(0)))
    return false;
  if (forward_kinematics(settings_.hand, wrist.pose, angles, posture_) != Status::Ok) return false;
  HandJoints<Scalar> q = HandJoints<Scalar>::Zero();
  if constexpr (Derived::SizeAtCompileTime == hand_dof_count) {
    q = angles;
  } else {
    for (int k = 0; k < hand_joint_count; ++k) q(phalanx_joint(k)) = angles(k);
  }
  joint_velocity_ = first_frame_ ? HandJoints<Scalar>::Zero() : HandJoints<Scalar>((q - joints_) / settings_.dt);
  joints_ = q;
  first_frame_ = false;
  return true;
}

template <class Scalar, class Scene, class Solver, class Device>
void HapticPipeline<Scalar, Scene, Solver, Device>::carry_held_object(const WristState<Scalar>& wrist) {
  if (!held_) return;
  const Vector3<Scalar> wrist_origin = wrist.pose.translation();
  const Isometry pose = wrist.pose * offset_;
  object_.position = pose.translation();
  object_.orientation = Eigen::Quaternion<Scalar>(pose.linear()).normalized();
  object_.linear_velocity = wrist.linear_velocity + wrist.angular_velocity.cross(object_.position - wrist_origin);
  object_.angular_velocity = wrist.angular_velocity;
}

template <class Scalar, class Scene, class Solver, class Device>
void HapticPipeline<Scalar, Scene, Solver, Device>::find_contacts(HapticFrame<Scalar>& frame) {
  scene_.hand_contacts(posture_, object_, hand_);
  scene_.obstacle_contacts(object_, obstacles_);
  for (int i = 0; i < obstacles_.count; ++i) {
    PenaltyContact<Scalar>& c = obstacles_.items[detail::idx(i)];
    c.depth_rate = -c.normal.dot(object_.point_velocity(object_.position + c.point));
  }
  frame.contacts = hand_.count;
  frame.obstacles = obstacles_.count;
}

template <class Scalar, class Scene, class Solver, class Device>
bool HapticPipeline<Scalar, Scene, Solver, Device>::object_wrench(const WristState<Scalar>& wrist,
                                                                  HapticFrame<Scalar>& frame) {
  const Vector3<Scalar> wrist_origin = wrist.pose.translation();
  const Vector3<Scalar> r = object_.position - wrist_origin;
  const Vector3<Scalar>& w = wrist.angular_velocity;
  const Vector3<Scalar> a = wrist.linear_acceleration + wrist.angular_acceleration.cross(r) + w.cross(w.cross(r));
  RigidBody<Scalar> imposed = object_;
  imposed.angular_velocity = w;
  frame.external = external_wrench(imposed, settings_.gravity, a, wrist.angular_acceleration, obstacles_.items.data(),
                                   obstacles_.count, settings_.obstacle_material);
  if (frame.external.status != Status::Ok) return false;
  outputs_.w_ext = frame.external.total();
  return true;
}

template <class Scalar, class Scene, class Solver, class Device>
void HapticPipeline<Scalar, Scene, Solver, Device>::solve_forces(HapticFrame<Scalar>& frame) {
  std::array<bool, max_contacts> keep{};
  for (int i = 0; i < hand_.count; ++i) keep[detail::idx(i)] = true;
  outputs_.stable = false;
  const int rounds = std::max(0, settings_.max_resolves);
  for (int round = 0; round <= rounds; ++round) {
    build_grasp(keep);
    outputs_.transmitted.fill(Vector3<Scalar>::Zero());
    outputs_.sliding.fill(false);
    if (grasp_.size() == 0) {
      frame.solve_status = Status::Singular;
      return;
    }
    const Solution<GraspType> sol = solver_(grasp_, outputs_.w_ext);
    ++frame.solves;
    frame.iterations += sol.iterations;
    frame.solve_status = sol.status;
    const GraspState<GraspType> state = monitor_cones(sol, frame);
    if (state.status != Status::Ok) return;
    frame.separating += state.separating_count;
    // A solver that keeps forces in their cones answers a separating contact with the apex,
    // exactly zero, and the other forces are already the answer without it (zero is feasible
    // for that contact and costs F2 a constant): solving again would only repeat the solve.
    if (state.separating_count == 0 || round == rounds || Solver::enforces_cones) {  // the last solve
      outputs_.stable = sol.status == Status::Ok && state.sliding_count == 0 && state.sticking_count > 0 &&
                        (Solver::enforces_cones || state.separating_count == 0);
      const Resolution<GraspType> res = resolve(grasp_, sol.forces, state, outputs_.w_ext);
      for (int j = 0; j < grasp_.size(); ++j) {
        const auto i = detail::idx(index_[detail::idx(j)]);
        outputs_.transmitted[i] = res.status == Status::Ok ? Vector3<Scalar>(res.transmitted.template segment<3>(3 * j))
                                                           : Vector3<Scalar>::Zero();
        outputs_.sliding[i] = state.is_sliding(j);
      }
      return;
    }
    for (int j = 0; j < grasp_.size(); ++j)  // drop the separating contacts and solve again with the rest
      if (state.is_separating(j)) keep[detail::idx(index_[detail::idx(j)])] = false;
  }
}

template <class Scalar, class Scene, class Solver, class Device>
auto HapticPipeline<Scalar, Scene, Solver, Device>::monitor_cones(const Solution<GraspType>& sol,
                                                                  HapticFrame<Scalar>& frame) const
    -> GraspState<GraspType> {
  GraspState<GraspType> state = monitor_.evaluate(grasp_, sol.forces);
  if (state.status != Status::Ok) {
    frame.solve_status = Status::InvalidInput;
    return state;
  }
  frame.sliding = state.sliding_count;
  frame.min_margin = state.count > 0 && state.sticking_count + state.sliding_count > 0 ? state.min_margin : Scalar(0);
  return state;
}

template <class Scalar, class Scene, class Solver, class Device>
void HapticPipeline<Scalar, Scene, Solver, Device>::move_object(const WristState<Scalar>& wrist,
                                                                HapticFrame<Scalar>& frame) {
  Wrench<Scalar> transmitted = Wrench<Scalar>::Zero();
  for (int i = 0; i < hand_.count; ++i) {
    const Vector3<Scalar>& f = outputs_.transmitted[detail::idx(i)];
    const Vector3<Scalar> p = hand_.items[detail::idx(i)].point - object_.position;
    transmitted.template head<3>() += f;
    transmitted.template tail<3>() += p.cross(f);
  }
  if (outputs_.stable) {
    if (!held_) offset_ = wrist.pose.inverse() * object_pose();
    held_ = true;
  } else {
    held_ = false;
    frame.unbalanced = outputs_.w_ext + transmitted;
    (void)step_free(object_, Wrench<Scalar>(frame.external.applied() + transmitted), settings_.dt);
  }
  frame.held = held_;
}

template <class Scalar, class Scene, class Solver, class Device>
void HapticPipeline<Scalar, Scene, Solver, Device>::phalanx_feedback(HapticFrame<Scalar>& frame) {
  felt_ = FeltForces<Scalar>{};
  for (int i = 0; i < hand_.count; ++i) {
    const HandContact<Scalar>& hc = hand_.items[detail::idx(i)];
    const int k = phalanx_index(hc.finger, hc.phalanx);
    if (k < 0 || k >= hand_body_count) continue;
    const Vector3<Scalar>& f = outputs_.transmitted[detail::idx(i)];
    felt_.add(k, -f, hc.point);
    if (k >= hand_phalanx_count) {
      frame.palm_force -= f;
      continue;
    }
    PhalanxFeedback<Scalar>& fb = frame.phalanges[detail::idx(k)];
    fb.force -= f;
    fb.in_contact = true;
    fb.sliding = fb.sliding || outputs_.sliding[detail::idx(i)];
  }
  felt_.finish(posture_);
  for (int k = 0; k < hand_phalanx_count; ++k) {
    PhalanxFeedback<Scalar>& fb = frame.phalanges[detail::idx(k)];
    fb.actuation_direction = felt_.direction[detail::idx(k)];
    fb.actuated = fb.force.dot(fb.actuation_direction);
    if constexpr (!phalanx_device)  // else the device's own command (render_device)
      detail::set_phalanx_command(frame, k, detail::push_command(fb.actuated, settings_.device_limit[detail::idx(k)]));
  }
}

}  // namespace grip
