#pragma once
/// \file
/// The closed haptic loop, one frame at a time: hand pose and joint angles in, per-phalanx
/// feedback forces out, the grasped object simulated in between. Fixed-size, heap-free.

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>

#include <Eigen/Geometry>

#include "grip/contact/contact.hpp"
#include "grip/contact/contact_model.hpp"
#include "grip/core/status.hpp"
#include "grip/core/types.hpp"
#include "grip/dynamics/external_wrench.hpp"
#include "grip/dynamics/integrator.hpp"
#include "grip/dynamics/rigid_body.hpp"
#include "grip/grasp/grasp.hpp"
#include "grip/hand/hand_kinematics.hpp"
#include "grip/hand/hand_model.hpp"
#include "grip/hand/squeeze.hpp"
#include "grip/monitor/grasp_state.hpp"
#include "grip/monitor/resolution.hpp"
#include "grip/monitor/stability_monitor.hpp"
#include "grip/pipeline/frame_solver.hpp"
#include "grip/geometry/collision.hpp"
#include "grip/pipeline/obstacle_contacts.hpp"
#include "grip/pipeline/scene.hpp"

namespace grip {

/// The tracker's reading for one frame: the wrist pose (hand frame to world) and the
/// wrist origin's velocity and acceleration, world axes (m, m/s, m/s^2, rad/s, rad/s^2).
/// The accelerations set the inertial terms the hand imposes on a held object; a real
/// tracker needs a filter to supply them (left to the user).
template <class Scalar>
struct WristState {
  /// Hand frame to world: rotation orthonormal, translation the wrist origin (m).
  Eigen::Transform<Scalar, 3, Eigen::Isometry> pose{Eigen::Transform<Scalar, 3, Eigen::Isometry>::Identity()};
  Vector3<Scalar> linear_velocity{Vector3<Scalar>::Zero()};       ///< of the wrist origin (m/s)
  Vector3<Scalar> angular_velocity{Vector3<Scalar>::Zero()};      ///< of the hand (rad/s)
  Vector3<Scalar> linear_acceleration{Vector3<Scalar>::Zero()};   ///< of the wrist origin (m/s^2)
  Vector3<Scalar> angular_acceleration{Vector3<Scalar>::Zero()};  ///< of the hand (rad/s^2)
};

/// Settings of a HapticPipeline (SI units).
template <class Scalar>
struct HapticSettings {
  HandDimensions<Scalar> hand{HandDimensions<Scalar>::standard()};  ///< the hand model
  /// Contribution d_i of each phalanx (eq. 8); default Table 1 (cylindrical power grip).
  ContributionTable<Scalar> contribution{cylindrical_power_grip<Scalar>()};
  /// Thumb proximal and distal shares (Table 1 has no thumb row; the thumb opposes the
  /// fingers, so it gets a share of its own).
  std::array<Scalar, 2> thumb_contribution{{Scalar(0.15), Scalar(0.25)}};
  /// Contact stiffness K_i per phalanx (N/m) of eq. 8.
  std::array<Scalar, hand_phalanx_count> stiffness{};
  Scalar friction{Scalar(0.8)};                              ///< Coulomb mu of every hand contact
  Vector3<Scalar> gravity{Scalar(0), Scalar(0), Scalar(-9.81)};  ///< g (m/s^2)
  PenaltyMaterial<Scalar> obstacle_material{};               ///< object-obstacle spring-damper
  /// The device's largest force per phalanx along its actuation direction (N).
  std::array<Scalar, hand_phalanx_count> device_limit{};
  Scalar dt{Scalar(1e-3)};                                   ///< frame period (s)
  int max_resolves{4};  ///< re-solves per frame after dropping separating contacts, >= 0
  /// Weight of contact i in F2: 1 (the paper's F2) when false; when true
  /// `w_i = 1 / max(s_i, weight_floor)` (1/N), so that each contact's share of the
  /// equilibrium correction grows with its squeeze: strongly pressed phalanges, which have
  /// the most friction to spare, carry the load (the grip's Table 1 distribution).
  bool weight_by_squeeze{true};
  Scalar weight_floor{Scalar(0.5)};  ///< s floor (N) of weight_by_squeeze, > 0

  HapticSettings() {
    stiffness.fill(Scalar(3e4));
    device_limit.fill(Scalar(10));
  }
};

/// What one phalanx feels in one frame.
template <class Scalar>
struct PhalanxFeedback {
  Vector3<Scalar> force{Vector3<Scalar>::Zero()};  ///< -f_i summed over the phalanx's contacts (N, world)
  /// Unit direction in which the device pushes the phalanx: extension, d x e for phalanx
  /// direction d and flexion axis e (world); the object pressing on the palmar side pushes
  /// along it.
  Vector3<Scalar> actuation_direction{Vector3<Scalar>::Zero()};
  Scalar actuated{0};    ///< force . actuation_direction (N)
  Scalar command{0};     ///< actuated clamped to [0, device_limit] (N): what the device renders
  bool in_contact{false};  ///< the phalanx touches the object
  bool clamped{false};     ///< command != actuated (beyond the limit, or pulling)
  bool sliding{false};     ///< its contact force left the friction cone
};

/// Everything the pipeline computed in one frame.
template <class Scalar>
struct HapticFrame {
  std::array<PhalanxFeedback<Scalar>, hand_phalanx_count> phalanges{};  ///< order of hand_model.hpp
  ExternalWrench<Scalar> external{};  ///< w_ext's terms (gravity, inertial, obstacles)
  /// Wrench left unbalanced, w_ext + G f' with f' the transmitted forces (zero when held).
  Wrench<Scalar> unbalanced{Wrench<Scalar>::Zero()};
  Status solve_status{Status::InvalidInput};  ///< status of the last solve of the frame
  Status status{Status::InvalidInput};        ///< Ok, or InvalidInput (bad wrist/angles/state)
  int contacts{0};      ///< hand contacts detected
  int obstacles{0};     ///< obstacle contacts
  int sliding{0};       ///< contacts outside their cone (after re-solves)
  int separating{0};    ///< contacts dropped as separating (f . a <= 0)
  int clamped{0};       ///< phalanges whose command was clamped
  int solves{0};        ///< solver calls this frame
  int iterations{0};    ///< solver iterations this frame (0 for direct solvers)
  bool held{false};     ///< the grasp is stable: the object moves with the hand
  Scalar min_margin{0};  ///< smallest Coulomb margin (N) over the contacts of the last solve
};

/// The per-frame haptic pipeline: hand pose and joint angles in; contacts from `Scene`;
/// squeeze s_i = d_i K_i dr_i (eq. 8); external wrench (gravity, inertial terms of the
/// motion the hand imposes, obstacle penalty contacts); optimal forces from `Solver`;
/// friction-cone monitor (StabilityMonitor, exact cones; resolve() for what slides or
/// separates); per-phalanx feedback -f_i out, clamped to the device's limits.
///
/// - `Scene`: the contact source (scene.hpp: CylinderScene, OctreeScene, or your own). A
///   phalanx with several contacts feels their sum; each contact's squeeze is eq. 8's with
///   its own depth.
/// - `Solver`: a frame solver policy (RangeSpaceFrameSolver, KktFrameSolver, ...).
///
/// The object's state machine. Held: the object is rigidly attached to the wrist with the
/// pose it had when the grasp became stable, and the contacts must balance w_ext. Free:
/// it moves by Newton-Euler (step_free) under gravity, obstacles and the forces the fingers
/// can transmit (each force projected onto its cone; separating ones zero). Each frame the
/// pipeline asks whether the hand could impose its own motion on the object (w_ext with the
/// inertial terms of the wrist's motion at the object's centre of mass): the object is held
/// when the solve is Ok and every contact kept is inside its cone. A grasp the monitor finds
/// slipping therefore lets the unbalanced wrench move the object.
template <class Scalar, class Scene, class Solver = RangeSpaceFrameSolver>
class HapticPipeline {
 public:
  /// Most hand contacts of one phalanx (the scene's contacts_per_phalanx).
  static constexpr int contacts_per_phalanx = detail::scene_contacts_per_phalanx<Scene>::value;
  /// Most hand contacts of one frame.
  static constexpr int max_contacts = hand_phalanx_count * contacts_per_phalanx;
  /// The grasp type of one frame: up to contacts_per_phalanx hard-finger contacts per phalanx.
  using GraspType = Grasp<Dynamic, HardFinger, Scalar, max_contacts>;
  /// A rigid transform (rotation and translation): the poses of the wrist and the object.
  using Isometry = Eigen::Transform<Scalar, 3, Eigen::Isometry>;

  /// A pipeline over `scene` with `settings`, the object starting in state `object` (free).
  HapticPipeline(const HapticSettings<Scalar>& settings, const Scene& scene, const RigidBody<Scalar>& object)
      : settings_(settings), scene_(scene), object_(object) {}

  /// Runs one frame. InvalidInput (object unchanged, frame zeroed but for the status) for a
  /// non-finite wrist state or angles, a non-orthonormal wrist rotation, invalid hand
  /// dimensions or an invalid object; Ok otherwise (whether the object is held or not:
  /// see HapticFrame).
  Status step(const WristState<Scalar>& wrist, const JointAngles<Scalar>& angles, HapticFrame<Scalar>& frame) {
    frame = HapticFrame<Scalar>{};
    frame.status = Status::InvalidInput;
    if (!wrist.pose.matrix().allFinite() || !wrist.linear_velocity.allFinite() ||
        !wrist.angular_velocity.allFinite() || !wrist.linear_acceleration.allFinite() ||
        !wrist.angular_acceleration.allFinite() || !angles.allFinite() || validate(object_) != Status::Ok ||
        !(settings_.dt > Scalar(0)))
      return frame.status;
    if (forward_kinematics(settings_.hand, wrist.pose, angles, posture_) != Status::Ok) return frame.status;

    // 1. A held object moves with the wrist.
    const Vector3<Scalar> wrist_origin = wrist.pose.translation();
    if (held_) {
      const Isometry pose = wrist.pose * offset_;
      object_.position = pose.translation();
      object_.orientation = Eigen::Quaternion<Scalar>(pose.linear()).normalized();
      object_.linear_velocity = wrist.linear_velocity + wrist.angular_velocity.cross(object_.position - wrist_origin);
      object_.angular_velocity = wrist.angular_velocity;
    }

    // 2. Contacts.
    scene_.hand_contacts(posture_, object_, hand_);
    scene_.obstacle_contacts(object_, obstacles_);
    for (int i = 0; i < obstacles_.count; ++i) {
      PenaltyContact<Scalar>& c = obstacles_.items[static_cast<std::size_t>(i)];
      c.depth_rate = -c.normal.dot(object_.point_velocity(object_.position + c.point));
    }
    frame.contacts = hand_.count;
    frame.obstacles = obstacles_.count;

    // 3. External wrench with the inertial terms of the motion the wrist would impose.
    const Vector3<Scalar> r = object_.position - wrist_origin;
    const Vector3<Scalar>& w = wrist.angular_velocity;
    const Vector3<Scalar> a = wrist.linear_acceleration + wrist.angular_acceleration.cross(r) + w.cross(w.cross(r));
    RigidBody<Scalar> imposed = object_;
    imposed.angular_velocity = w;
    frame.external = external_wrench(imposed, settings_.gravity, a, wrist.angular_acceleration,
                                     obstacles_.items.data(), obstacles_.count, settings_.obstacle_material);
    if (frame.external.status != Status::Ok) return frame.status;
    const Wrench<Scalar> w_ext = frame.external.total();

    // 4. Optimal forces, monitored (StabilityMonitor, exact cones); separating contacts are
    //    dropped and the rest re-solved; what slides or separates is resolved (resolve()).
    std::array<bool, max_contacts> keep{};
    for (int i = 0; i < hand_.count; ++i) keep[static_cast<std::size_t>(i)] = true;
    std::array<Vector3<Scalar>, max_contacts> force{};
    std::array<bool, max_contacts> slide{};
    bool stable = false;
    const int rounds = std::max(0, settings_.max_resolves);
    for (int round = 0; round <= rounds; ++round) {
      build_grasp(keep);
      force.fill(Vector3<Scalar>::Zero());
      slide.fill(false);
      if (grasp_.size() == 0) {
        frame.solve_status = Status::Singular;
        break;
      }
      const Solution<GraspType> sol = solver_(grasp_, w_ext);
      ++frame.solves;
      frame.iterations += sol.iterations;
      frame.solve_status = sol.status;
      const GraspState<GraspType> state = monitor_.evaluate(grasp_, sol.forces);
      if (state.status != Status::Ok) {
        frame.solve_status = Status::InvalidInput;
        break;
      }
      frame.sliding = state.sliding_count;
      frame.min_margin = state.count > 0 && state.sticking_count + state.sliding_count > 0 ? state.min_margin : Scalar(0);
      const bool last = state.separating_count == 0 || round == rounds;
      if (!last) {  // drop the separating contacts and solve again with the rest
        frame.separating += state.separating_count;
        for (int j = 0; j < grasp_.size(); ++j)
          if (state.is_separating(j)) keep[static_cast<std::size_t>(index_[static_cast<std::size_t>(j)])] = false;
        continue;
      }
      frame.separating += state.separating_count;
      stable = sol.status == Status::Ok && state.stable;
      const Resolution<GraspType> res = resolve(grasp_, sol.forces, state, w_ext);
      for (int j = 0; j < grasp_.size(); ++j) {
        const auto i = static_cast<std::size_t>(index_[static_cast<std::size_t>(j)]);
        force[i] = res.status == Status::Ok ? Vector3<Scalar>(res.transmitted.template segment<3>(3 * j))
                                            : Vector3<Scalar>::Zero();
        slide[i] = state.is_sliding(j);
      }
      break;
    }

    // 5. The object: held, or moved by what is left unbalanced.
    Wrench<Scalar> transmitted = Wrench<Scalar>::Zero();
    for (int i = 0; i < hand_.count; ++i) {
      const Vector3<Scalar>& f = force[static_cast<std::size_t>(i)];
      const Vector3<Scalar> p = hand_.items[static_cast<std::size_t>(i)].point - object_.position;
      transmitted.template head<3>() += f;
      transmitted.template tail<3>() += p.cross(f);
    }
    if (stable) {
      if (!held_) offset_ = wrist.pose.inverse() * object_pose();
      held_ = true;
    } else {
      held_ = false;
      frame.unbalanced = w_ext + transmitted;
      (void)step_free(object_, Wrench<Scalar>(frame.external.applied() + transmitted), settings_.dt);
    }
    frame.held = held_;

    // 6. Feedback per phalanx.
    const Matrix3<Scalar> rw = wrist.pose.linear();
    for (int i = 0; i < hand_.count; ++i) {
      const HandContact<Scalar>& hc = hand_.items[static_cast<std::size_t>(i)];
      const int k = phalanx_index(hc.finger, hc.phalanx);
      if (k < 0 || k >= hand_phalanx_count) continue;
      PhalanxFeedback<Scalar>& fb = frame.phalanges[static_cast<std::size_t>(k)];
      fb.force -= force[static_cast<std::size_t>(i)];
      fb.in_contact = true;
      fb.sliding = fb.sliding || slide[static_cast<std::size_t>(i)];
    }
    for (int k = 0; k < hand_phalanx_count; ++k) {
      PhalanxFeedback<Scalar>& fb = frame.phalanges[static_cast<std::size_t>(k)];
      const PhalanxCapsule<Scalar>& c = posture_.phalanges[static_cast<std::size_t>(k)];
      const Vector3<Scalar> d = (c.tip - c.base).normalized();
      const Vector3<Scalar> e = rw * settings_.hand.flexion_axis[static_cast<std::size_t>(phalanx_finger(k))];
      fb.actuation_direction = d.cross(e).normalized();
      fb.actuated = fb.force.dot(fb.actuation_direction);
      const Scalar limit = settings_.device_limit[static_cast<std::size_t>(k)];
      fb.command = std::min(limit, std::max(Scalar(0), fb.actuated));
      fb.clamped = fb.in_contact && fb.command != fb.actuated;
      if (fb.clamped) ++frame.clamped;
    }
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
  /// The hand posture of the last frame (world capsules).
  const HandPosture<Scalar>& posture() const { return posture_; }
  /// The hand contacts of the last frame.
  const HandContacts<Scalar, contacts_per_phalanx>& hand_contacts() const { return hand_; }
  /// The grasp solved last (the contacts kept in the last solve).
  const GraspType& grasp() const { return grasp_; }
  /// The settings.
  const HapticSettings<Scalar>& settings() const { return settings_; }
  /// The scene (mutable: obstacles may move between frames).
  Scene& scene() { return scene_; }

 private:
  Isometry object_pose() const {
    Isometry t = Isometry::Identity();
    t.linear() = object_.rotation();
    t.translation() = object_.position;
    return t;
  }

  /// The contact share d of phalanx k: Table 1 for fingers, thumb_contribution for the thumb.
  Scalar share(int k) const {
    if (k < 2) return settings_.thumb_contribution[static_cast<std::size_t>(k)];
    return settings_.contribution(phalanx_finger(k), phalanx_kind(k));
  }

  void build_grasp(const std::array<bool, max_contacts>& keep) {
    grasp_.clear();
    for (int i = 0; i < hand_.count; ++i) {
      if (!keep[static_cast<std::size_t>(i)]) continue;
      const HandContact<Scalar>& h = hand_.items[static_cast<std::size_t>(i)];
      Contact<Scalar> c;
      c.position = h.point - object_.position;
      c.normal = h.normal;
      c.friction = settings_.friction;
      const int k = phalanx_index(h.finger, h.phalanx);
      if (k < 0 || k >= hand_phalanx_count) continue;  // not a phalanx of the model
      c.squeeze = squeeze(share(k), settings_.stiffness[static_cast<std::size_t>(k)], h.depth);
      if (settings_.weight_by_squeeze) c.weight = Scalar(1) / std::max(c.squeeze, settings_.weight_floor);
      if (grasp_.add(c) == Status::Ok) index_[static_cast<std::size_t>(grasp_.size() - 1)] = i;
    }
  }

  HapticSettings<Scalar> settings_;
  Scene scene_;
  Solver solver_{};
  StabilityMonitor<GraspType> monitor_{};
  RigidBody<Scalar> object_;
  bool held_{false};
  Isometry offset_{Isometry::Identity()};
  HandPosture<Scalar> posture_{};
  HandContacts<Scalar, contacts_per_phalanx> hand_{};
  ObstacleContactSet<Scalar> obstacles_{};
  GraspType grasp_{};
  std::array<int, max_contacts> index_{};
};

}  // namespace grip
