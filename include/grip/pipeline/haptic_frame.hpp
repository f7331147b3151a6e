#pragma once
/// \file
/// What one frame of the haptic pipeline (haptic_pipeline.hpp) takes and gives: the wrist's
/// state in, the settings, the per-phalanx feedback and the frame's report out. Fixed-size.

#include <array>

#include <Eigen/Geometry>

#include "grip/core/index.hpp"
#include "grip/core/status.hpp"
#include "grip/core/types.hpp"
#include "grip/dynamics/external_wrench.hpp"
#include "grip/dynamics/penalty_contact.hpp"
#include "grip/hand/hand_model.hpp"
#include "grip/hand/grasp_type.hpp"
#include "grip/pipeline/channel_guard.hpp"

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
  /// Contribution d_i of each phalanx, thumb included (eq. 8); default the cylindrical power
  /// grip (Table 1 for the fingers); contribution_table(GraspType) gives the other types.
  ContributionTable<Scalar> contribution{cylindrical_power_grip<Scalar>()};
  /// Contact stiffness K_i per phalanx (N/m) of eq. 8.
  std::array<Scalar, hand_phalanx_count> stiffness{};
  /// K_i of the palm's bodies (N/m): the metacarpals and the thenar, which touch objects when
  /// the pipeline runs the whole hand (20 joints).
  Scalar palm_stiffness{Scalar(3e4)};
  Scalar friction{Scalar(0.8)};                                  ///< Coulomb mu of every hand contact
  Vector3<Scalar> gravity{Scalar(0), Scalar(0), Scalar(-9.81)};  ///< g (m/s^2)
  PenaltyMaterial<Scalar> obstacle_material{};                   ///< object-obstacle spring-damper
  /// The largest force per phalanx along its actuation direction (N): the default device
  /// policy's (PhalanxActuators) limits when the pipeline is built (then device().limit), and
  /// the limits of PhalanxFeedback::command under the other device policies.
  std::array<Scalar, hand_phalanx_count> device_limit{};
  /// With a frame solver that enforces the cones (ConstrainedFrameSolver): true bounds every hand
  /// contact's normal force by its phalanx's limit (the default device's device().limit, else
  /// device_limit) shared equally among that phalanx's contacts of the frame, so that the solver
  /// returns the best forces the device can render, or Infeasible when even those cannot hold the
  /// object (a phalanx whose limit is <= 0 then touches nothing; the palm's bodies have no
  /// actuator: unbounded). False: no bounds, and the device clips what it cannot render.
  bool bound_by_device{true};
  Scalar dt{Scalar(1e-3)};  ///< frame period (s)
  /// Re-solves per frame after dropping separating contacts, >= 0 (none with a solver that
  /// enforces the cones: its separating forces are zero and the rest already the answer).
  int max_resolves{4};
  /// Weight of contact i in F2: 1 (the paper's F2) when false; when true
  /// `w_i = 1 / max(s_i, weight_floor)` (1/N), so that each contact's share of the
  /// equilibrium correction grows with its squeeze: strongly pressed phalanges, which have
  /// the most friction to spare, carry the load (the grip's Table 1 distribution).
  bool weight_by_squeeze{true};
  Scalar weight_floor{Scalar(0.5)};  ///< s floor (N) of weight_by_squeeze, > 0
  /// With the default device (PhalanxActuators): true passes its 14 commands through a
  /// ChannelGuard (channel_guard.hpp) with `guard`, whose output is then each
  /// PhalanxFeedback::command; frame k's time is k dt. False: the device's command as it is.
  bool guard_commands{false};
  ChannelGuardSettings<Scalar> guard{};  ///< the guard's settings (guard_commands)

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
  Scalar actuated{0};      ///< force . actuation_direction (N)
  Scalar command{0};       ///< actuated clamped to [0, device_limit] (N): what the device renders
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
  int contacts{0};                            ///< hand contacts detected
  int obstacles{0};                           ///< obstacle contacts
  int sliding{0};                             ///< contacts outside their cone (after re-solves)
  int separating{0};                          ///< contacts dropped as separating (f . a <= 0)
  int clamped{0};                             ///< phalanges whose command was clamped
  /// -f summed over the palm's contacts (N, world): what the palm feels (whole hand only).
  Vector3<Scalar> palm_force{Vector3<Scalar>::Zero()};
  int device_clipped{0};  ///< outputs the device policy clipped (its Command::clipped)
  int solves{0};          ///< solver calls this frame
  int iterations{0};      ///< solver iterations this frame (0 for direct solvers)
  bool held{false};       ///< the grasp is stable: the object moves with the hand
  Scalar min_margin{0};   ///< smallest Coulomb margin (N) over the contacts of the last solve
};

namespace detail {

/// Sets phalanx k's command (N) in `frame`, and whether it differs from the force the phalanx
/// should feel (PhalanxFeedback::clamped, counted in HapticFrame::clamped).
template <class Scalar>
void set_phalanx_command(HapticFrame<Scalar>& frame, int k, Scalar command) {
  PhalanxFeedback<Scalar>& fb = frame.phalanges[idx(k)];
  fb.command = command;
  fb.clamped = fb.in_contact && fb.command != fb.actuated;
  if (fb.clamped) ++frame.clamped;
}

}  // namespace detail

}  // namespace grip
