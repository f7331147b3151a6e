#pragma once
/// \file
/// The closed haptic loop, one frame at a time: hand pose and joint angles in, per-phalanx
/// feedback forces out, the grasped object simulated in between. Fixed-size, heap-free.
/// step() runs a frame as named stages, private members declared with their contracts in the
/// class and defined in haptic_stages.hpp. A frame's inputs and outputs are in haptic_frame.hpp,
/// the frame solvers in frame_solver.hpp.

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <limits>
#include <type_traits>

#include <Eigen/Geometry>

#include "grip/contact/contact.hpp"
#include "grip/contact/contact_model.hpp"
#include "grip/core/index.hpp"
#include "grip/core/status.hpp"
#include "grip/core/types.hpp"
#include "grip/dynamics/external_wrench.hpp"
#include "grip/dynamics/integrator.hpp"
#include "grip/dynamics/rigid_body.hpp"
#include "grip/collision/collision.hpp"
#include "grip/grasp/grasp.hpp"
#include "grip/hand/hand_joints.hpp"
#include "grip/hand/hand_kinematics.hpp"
#include "grip/hand/hand_model.hpp"
#include "grip/hand/squeeze.hpp"
#include "grip/monitor/grasp_state.hpp"
#include "grip/monitor/resolution.hpp"
#include "grip/monitor/stability_monitor.hpp"
#include "grip/pipeline/device_policy.hpp"
#include "grip/pipeline/frame_solver.hpp"
#include "grip/pipeline/haptic_frame.hpp"
#include "grip/pipeline/obstacle_contacts.hpp"
#include "grip/pipeline/scene.hpp"

namespace grip {

/// The per-frame haptic pipeline. step() runs the stages of docs/pipeline.md in order, each a
/// private member: pose_hand, carry_held_object, find_contacts, object_wrench, solve_forces
/// (build_grasp, `Solver`, monitor_cones, resolve()), move_object, phalanx_feedback,
/// render_device.
///
/// - `Scene`: the contact source (scene.hpp: CylinderScene, OctreeScene, or your own). A
///   phalanx with several contacts feels their sum, each contact's squeeze eq. 8's with its
///   own depth.
/// - `Solver`: a frame solver policy (frame_solver.hpp: RangeSpaceFrameSolver, ...).
/// - `Device`: a device policy (device_policy.hpp: PhalanxActuators, the paper's glove and the
///   default, whose limits start as settings.device_limit, then device().limit, and whose
///   command is each PhalanxFeedback::command; VectorForces, JointTorques, JointBrakes). Its
///   command of the last frame is device_command().
/// - The hand: step() takes the paper's 14 flexion angles (a hand without a palm) or the
///   whole hand's 20 joints (hand_joints.hpp; the palm and the thenar then touch objects too).
///
/// The object is held (rigidly attached to the wrist with the pose it had when the grasp
/// became stable; the contacts must balance w_ext) while the solve is Ok and every contact
/// kept is inside its exact cone. Otherwise it is free: it moves by Newton-Euler (step_free)
/// under gravity, obstacles and the forces the fingers can transmit (each force projected
/// onto its cone, separating ones zero), so a slipping grasp lets the unbalanced wrench move it.
template <class Scalar, class Scene, class Solver = RangeSpaceFrameSolver, class Device = PhalanxActuators<Scalar>>
class HapticPipeline {
 public:
  /// Most hand contacts of one phalanx (the scene's contacts_per_phalanx).
  static constexpr int contacts_per_phalanx = detail::scene_contacts_per_phalanx<Scene>::value;
  /// Most hand contacts of one frame.
  static constexpr int max_contacts = hand_body_count * contacts_per_phalanx;
  /// The grasp type of one frame: up to contacts_per_phalanx hard-finger contacts per phalanx.
  using GraspType = Grasp<Dynamic, HardFinger, Scalar, max_contacts>;
  /// A rigid transform (rotation and translation): the poses of the wrist and the object.
  using Isometry = Eigen::Transform<Scalar, 3, Eigen::Isometry>;

  /// A pipeline over `scene` with `settings`, the object starting in state `object` (free).
  HapticPipeline(const HapticSettings<Scalar>& settings, const Scene& scene, const RigidBody<Scalar>& object)
      : settings_(settings), scene_(scene), object_(object) {
    if constexpr (phalanx_device) device_.limit = settings.device_limit;
  }

  /// Runs one frame. `angles`: the 14 flexion angles (JointAngles) or the 20 joints
  /// (HandJoints), rad. `fresh`: whether the glove and tracker gave new data for this frame
  /// (false: the last data again), read by the command guard's stale-input watchdog
  /// (settings.guard_commands). InvalidInput (object unchanged, frame zeroed but for the status
  /// and, with the guard, each phalanx's command, the guard's on its way to zero) for a
  /// non-finite wrist state or angles, a non-orthonormal wrist rotation, invalid hand
  /// dimensions or an invalid object; Ok otherwise (whether the object is held or not:
  /// see HapticFrame).
  template <class Derived>
  Status step(const WristState<Scalar>& wrist, const Eigen::MatrixBase<Derived>& angles, HapticFrame<Scalar>& frame,
              bool fresh = true) {
    frame = HapticFrame<Scalar>{};
    frame.status = Status::InvalidInput;
    const Scalar now = Scalar(frames_++) * settings_.dt;
    if (!pose_hand(wrist, angles) || !object_wrench_ready(wrist, frame)) {
      guard_commands(now, nullptr, fresh, frame);
      return frame.status;
    }
    solve_forces(frame);
    move_object(wrist, frame);
    phalanx_feedback(frame);
    render_device(frame);
    guard_commands(now, &command_, fresh, frame);
    frame.status = Status::Ok;
    return frame.status;
  }

  /// The simulated object.
  const RigidBody<Scalar>& object() const { return object_; }
  /// Replaces the object's state (it becomes free). InvalidInput (unchanged) if invalid.
  Status set_object(const RigidBody<Scalar>& object) {
    if (validate(object) != Status::Ok) return Status::InvalidInput;
    object_ = object;
    held_ = false;
    return Status::Ok;
  }
  /// True while the grasp holds the object (it moves with the wrist).
  bool held() const { return held_; }
  /// The frame solver, e.g. to set a ConstrainedFrameSolver's settings before the first step or
  /// between steps.
  Solver& solver() { return solver_; }
  /// The frame solver.
  const Solver& solver() const { return solver_; }
  /// The hand posture of the last frame (world capsules).
  const HandPosture<Scalar>& posture() const { return posture_; }
  /// The hand contacts of the last frame.
  const HandContacts<Scalar, contacts_per_phalanx>& hand_contacts() const { return hand_; }
  /// The grasp solved last (the contacts kept in the last solve).
  const GraspType& grasp() const { return grasp_; }
  /// The settings.
  const HapticSettings<Scalar>& settings() const { return settings_; }
  /// The device policy, e.g. to set its limits before the first step or between steps.
  Device& device() { return device_; }
  /// The device policy's command of the last frame.
  const typename Device::Command& device_command() const { return command_; }
  /// The guard of the default device's commands (settings.guard_commands; at rest otherwise).
  const ChannelGuard<Scalar, hand_phalanx_count>& guard() const { return guard_; }
  /// What every body of the hand felt in the last frame (the device policy's input): forces,
  /// points and contacts per body, actuation directions per phalanx.
  const FeltForces<Scalar>& felt() const { return felt_; }
  /// The joint velocities of the last frame (rad/s): the difference of the last two frames'
  /// joints over dt (zero at the first frame; the 14 angles fill the 20 joints' flexions).
  const HandJoints<Scalar>& joint_velocity() const { return joint_velocity_; }
  /// The scene (mutable: obstacles may move between frames).
  Scene& scene() { return scene_; }

 private:
  /// What the later stages of a frame read from the earlier ones, rewritten every frame.
  struct StageOutputs {
    Wrench<Scalar> w_ext{Wrench<Scalar>::Zero()};  ///< by object_wrench: the external wrench
    /// By solve_forces, per hand contact (hand_'s order): the force it transmits to the
    /// object (N, world; zero if dropped as separating or if resolve() failed).
    std::array<Vector3<Scalar>, max_contacts> transmitted{};
    std::array<bool, max_contacts> sliding{};  ///< by solve_forces: the contact left its cone
    bool stable{false};                        ///< by solve_forces: the last solve Ok and every contact kept sticks
  };

  // The stages, in step()'s order.

  /// 1. Inputs: false for an input step() rejects (see step()). Reads `wrist`, `angles`,
  /// settings_, object_; writes posture_ (forward kinematics), joints_, joint_velocity_.
  template <class Derived>
  bool pose_hand(const WristState<Scalar>& wrist, const Eigen::MatrixBase<Derived>& angles);
  /// 2. Held object: if held_, object_ takes the pose wrist.pose * offset_, the wrist's angular
  /// velocity and the velocity v_w + omega_w x r. Reads `wrist`, held_, offset_; writes object_.
  void carry_held_object(const WristState<Scalar>& wrist);
  /// 3. Contacts: reads posture_, object_, scene_; writes hand_, obstacles_ (each obstacle
  /// contact's depth_rate from object_'s twist), frame.contacts and frame.obstacles.
  void find_contacts(HapticFrame<Scalar>& frame);
  /// 4. External wrench: gravity, obstacles, and the inertial terms of the motion the wrist
  /// would impose on object_. Reads `wrist`, object_, obstacles_, settings_; writes
  /// frame.external and outputs_.w_ext. False if external_wrench() fails.
  bool object_wrench(const WristState<Scalar>& wrist, HapticFrame<Scalar>& frame);
  /// 5-6. Forces: build_grasp() of the contacts kept, solved by solver_, checked by
  /// monitor_cones(); separating contacts dropped and the rest solved again, up to
  /// max_resolves times (never when Solver::enforces_cones: its separating forces are exactly
  /// zero and the rest are the reduced problem's answer, so one solve per frame, within its
  /// deadline); the last solve resolve()d into what the fingers transmit. Reads
  /// hand_, object_, outputs_.w_ext; writes grasp_, index_, outputs_'s other fields, and
  /// frame.solve_status, solves, iterations, sliding, separating and min_margin.
  void solve_forces(HapticFrame<Scalar>& frame);
  /// 6. Monitor: the state of grasp_ under `sol`'s forces (StabilityMonitor, exact cones).
  /// Writes frame.sliding and frame.min_margin; frame.solve_status = InvalidInput if the
  /// monitor rejects its input (the state's status says so).
  GraspState<GraspType> monitor_cones(const Solution<GraspType>& sol, HapticFrame<Scalar>& frame) const;
  /// 7. Object: stable, it becomes (or stays) held; else frame.unbalanced = w_ext + G f' and
  /// step_free moves object_ by dt. Reads outputs_, hand_, `wrist`; writes held_, offset_,
  /// object_, frame.unbalanced and frame.held.
  void move_object(const WristState<Scalar>& wrist, HapticFrame<Scalar>& frame);
  /// 8. Feedback: each phalanx feels -f_i summed over its contacts (command: see Device), the
  /// palm frame.palm_force. Reads outputs_, hand_, posture_, settings_; writes frame, felt_.
  void phalanx_feedback(HapticFrame<Scalar>& frame);
  /// 9. Device: device_ renders felt_ (posture_, joint_velocity_) into command_; writes
  /// frame.device_clipped (PhalanxActuators: each phalanx's command and frame.clamped).
  void render_device(HapticFrame<Scalar>& frame) {
    (void)device_.render(felt_, posture_, joint_velocity_, command_);
    frame.device_clipped = command_.clipped;
    if constexpr (phalanx_device)
      for (int k = 0; k < hand_phalanx_count; ++k)
        detail::set_phalanx_command(frame, k, command_.force[detail::idx(k)]);
  }
  /// 2-4 of a frame whose inputs pose_hand accepted: carry_held_object, find_contacts and
  /// object_wrench; false if object_wrench fails.
  bool object_wrench_ready(const WristState<Scalar>& wrist, HapticFrame<Scalar>& frame) {
    carry_held_object(wrist);
    find_contacts(frame);
    return object_wrench(wrist, frame);
  }
  /// 10. Guard (settings_.guard_commands, PhalanxActuators only): guard_ takes `command`'s
  /// forces at time `now` (nullptr: the frame's input was bad, every target 0) and each
  /// phalanx's command becomes the guard's.
  void guard_commands(Scalar now, const typename Device::Command* command, bool fresh, HapticFrame<Scalar>& frame) {
    if constexpr (phalanx_device) {
      if (!settings_.guard_commands) return;
      if (command != nullptr)
        (void)guard_.update(now, command->force, fresh);
      else
        (void)guard_.reject(now);
      for (int k = 0; k < hand_phalanx_count; ++k)
        frame.phalanges[detail::idx(k)].command = guard_.command()[detail::idx(k)];
    } else {
      (void)now, (void)command, (void)fresh, (void)frame;
    }
  }
  /// Whether Device is the default PhalanxActuators, whose command is PhalanxFeedback::command.
  static constexpr bool phalanx_device = std::is_same<Device, PhalanxActuators<Scalar>>::value;

  Isometry object_pose() const {
    Isometry t = Isometry::Identity();
    t.linear() = object_.rotation();
    t.translation() = object_.position;
    return t;
  }

  /// The contact share d of phalanx k, from settings_.contribution (thumb included).
  Scalar share(int k) const { return settings_.contribution(phalanx_finger(k), phalanx_kind(k)); }

  /// 5. Grasp: one Contact per hand contact kept (r_i from the centre of mass, friction,
  /// squeeze of eq. 8, weight, and with bound_by_device a bound: device_share). Reads hand_,
  /// object_, settings_; writes grasp_ and index_ (index_[j]: the hand contact of grasp_'s
  /// contact j).
  void build_grasp(const std::array<bool, max_contacts>& keep) {
    grasp_.clear();
    std::array<int, hand_body_count> per_body{};
    for (int i = 0; i < hand_.count; ++i) {
      const HandContact<Scalar>& h = hand_.items[detail::idx(i)];
      const int k = phalanx_index(h.finger, h.phalanx);
      if (keep[detail::idx(i)] && k >= 0 && k < hand_body_count) ++per_body[detail::idx(k)];
    }
    for (int i = 0; i < hand_.count; ++i) {
      if (!keep[detail::idx(i)]) continue;
      const HandContact<Scalar>& h = hand_.items[detail::idx(i)];
      Contact<Scalar> c;
      c.position = h.point - object_.position;
      c.normal = h.normal;
      c.friction = settings_.friction;
      const int k = phalanx_index(h.finger, h.phalanx);
      if (k < 0 || k >= hand_body_count) continue;  // not a body of the model
      const Scalar stiffness = k < hand_phalanx_count ? settings_.stiffness[detail::idx(k)] : settings_.palm_stiffness;
      c.squeeze = squeeze(share(k), stiffness, h.depth);
      if (settings_.weight_by_squeeze) c.weight = Scalar(1) / std::max(c.squeeze, settings_.weight_floor);
      c.max_normal_force = device_share(k, per_body[detail::idx(k)]);
      if (!(c.max_normal_force > Scalar(0))) continue;  // the channel renders nothing
      if (grasp_.add(c) == Status::Ok) index_[detail::idx(grasp_.size() - 1)] = i;
    }
  }
  /// The bound on the normal force of each of the `count` contacts of body k: with
  /// bound_by_device and a solver that enforces the cones, phalanx k's device limit over count;
  /// infinity otherwise (and for the palm's bodies).
  Scalar device_share(int k, int count) const {
    if (!Solver::enforces_cones || !settings_.bound_by_device || k >= hand_phalanx_count || count < 1)
      return std::numeric_limits<Scalar>::infinity();
    Scalar limit = settings_.device_limit[detail::idx(k)];
    if constexpr (phalanx_device) limit = device_.limit[detail::idx(k)];
    return std::isfinite(limit) ? std::max(limit, Scalar(0)) / Scalar(count) : std::numeric_limits<Scalar>::infinity();
  }

  HapticSettings<Scalar> settings_;
  Scene scene_;
  Solver solver_{};
  StabilityMonitor<GraspType> monitor_{};
  RigidBody<Scalar> object_;
  bool held_{false};
  Isometry offset_{Isometry::Identity()};
  HandPosture<Scalar> posture_{};
  HandJoints<Scalar> joints_{HandJoints<Scalar>::Zero()};
  HandJoints<Scalar> joint_velocity_{HandJoints<Scalar>::Zero()};
  bool first_frame_{true};
  Device device_{};
  typename Device::Command command_{};
  FeltForces<Scalar> felt_{};
  ChannelGuard<Scalar, hand_phalanx_count> guard_{settings_.guard};  ///< settings_.guard_commands
  long long frames_{0};                                              ///< frames stepped (the guard's clock)
  HandContacts<Scalar, contacts_per_phalanx> hand_{};
  ObstacleContactSet<Scalar> obstacles_{};
  GraspType grasp_{};
  std::array<int, max_contacts> index_{};
  StageOutputs outputs_{};
};

}  // namespace grip

#include "grip/pipeline/haptic_stages.hpp"
