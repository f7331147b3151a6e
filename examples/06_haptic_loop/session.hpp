#pragma once
// The scripted session of examples/06_haptic_loop, shared with bench/bench_haptic_loop.cpp:
// it stands in for a glove (14 joint angles) and a tracker (wrist pose and its derivatives)
// at 1 kHz. A cylinder lies on a table; the hand closes on it (Table 1 power grip), lifts
// it, holds it still, shakes it, swings it into the table's edge, and lets go above the table.
#include <cmath>

#include <grip/dynamics/rigid_body.hpp>
#include <grip/pipeline/close_hand.hpp>
#include <grip/pipeline/cylinder_scene.hpp>
#include <grip/pipeline/haptic_pipeline.hpp>

namespace haptic_session {

using S = double;
using Isometry = Eigen::Transform<S, 3, Eigen::Isometry>;
using V3 = grip::Vector3<S>;

constexpr S rate = 1000;     // frames per second
constexpr S duration = 6.5;  // s
constexpr S mass = 0.4;      // kg: a full 0.4 l bottle
constexpr S radius = 0.035;  // m
constexpr S half_length = 0.06;

struct Phase {
  const char* name;
  S begin, end;
};
// The script's phases (s).
constexpr Phase phases[] = {{"close", 0.0, 0.7},   {"lift", 0.7, 1.5},   {"hold", 1.5, 2.2}, {"shake", 2.2, 3.4},
                            {"to edge", 3.4, 4.3}, {"impact", 4.3, 4.9}, {"back", 4.9, 5.6}, {"let go", 5.6, 6.5}};
constexpr int phase_count = 8;

inline int phase_at(S t) {
  for (int i = 0; i < phase_count; ++i)
    if (t < phases[i].end) return i;
  return phase_count - 1;
}

// Smooth 0 -> 1 over [a, b] (minimum jerk: zero velocity and acceleration at both ends).
inline S ramp(S t, S a, S b) {
  if (t <= a) return 0;
  if (t >= b) return 1;
  const S u = (t - a) / (b - a);
  return u * u * u * (10 - 15 * u + 6 * u * u);
}

// The object's rest pose on the table: axis along world y, lying at x = -0.15.
inline V3 start_position() { return V3(-0.15, 0, radius); }

// Where the grasped object's centre should be at time t (the script moves the hand so).
inline V3 object_path(S t) {
  V3 p = start_position();
  p.z() += 0.15 * ramp(t, 0.7, 1.5);                              // lift 15 cm
  const S shake = ramp(t, 2.2, 2.45) * (1 - ramp(t, 3.15, 3.4));  // 4 Hz, 1.5 cm
  p.z() += 0.015 * shake * std::sin(S(2 * EIGEN_PI) * 4 * (t - 2.2));
  p.x() += 0.25 * ramp(t, 3.4, 3.85) - 0.25 * ramp(t, 5.15, 5.6);     // past the edge and back
  p.z() += -0.205 * ramp(t, 3.85, 4.3) + 0.205 * ramp(t, 4.9, 5.15);  // down beside the table
  p.x() += -0.068 * ramp(t, 4.3, 4.55) + 0.068 * ramp(t, 4.65, 4.9);  // into the edge, 3 mm deep
  return p;
}

// Hand opening: 1 = closed on the object, 0 = open.
inline S closure(S t) { return ramp(t, 0.15, 0.6) * (1 - ramp(t, 5.75, 6.0)); }

// The settings of the session: Table 1 plus a thumb, stiffness, device limits.
inline grip::HapticSettings<S> settings() {
  grip::HapticSettings<S> s;
  // Power-grip thumb posture: the thumb opposes the long finger (the model's default thumb
  // sits 4 cm radial of it, which would twist the cylinder out of the fingers).
  s.hand.thumb_cmc.y() = -0.005;
  s.hand.base[0].y() = -0.005;
  s.contribution(grip::Finger::Thumb, grip::Phalanx::Proximal) = 0.5;  // a firmer thumb than the
  s.contribution(grip::Finger::Thumb, grip::Phalanx::Distal) = 0.7;    // table's 0.15 and 0.25
  s.stiffness.fill(1.5e4);
  s.device_limit.fill(12);
  s.device_limit[0] = s.device_limit[1] = 25;
  s.obstacle_material.stiffness = 4000;  // per rim sample point
  s.obstacle_material.damping = 20;
  return s;
}

inline grip::CylinderScene<S> scene() {
  grip::CylinderScene<S> sc;
  sc.radius = radius;
  sc.half_length = half_length;
  sc.rim_points = 8;
  sc.obstacles.add_box(V3(-0.8, -0.5, -0.75), V3(0, 0.5, 0));  // the table: top at z = 0, edge at x = 0
  return sc;
}

inline grip::RigidBody<S> object() {
  grip::RigidBody<S> b;
  b.mass = mass;
  b.principal_inertia = grip::solid_cylinder_inertia<S>(mass, radius, half_length);
  b.position = start_position();
  grip::Matrix3<S> r;  // body z (the axis) -> world y; body x -> world z
  r.col(0) = V3::UnitZ();
  r.col(1) = V3::UnitX();
  r.col(2) = V3::UnitY();
  b.orientation = Eigen::Quaternion<S>(r);
  return b;
}

// The object's centre in the hand frame during the grasp: palm down, the cylinder under the
// proximal phalanges, 2 mm into them.
inline V3 grasp_offset(const grip::HandDimensions<S>& hand) {
  const S l = hand.hand_length;
  return V3(0.374 * l + 0.03, 0, -(radius + 0.045 * l - 0.002));
}

// The scripted glove and tracker.
struct Script {
  grip::HandDimensions<S> hand;
  V3 offset;
  grip::JointAngles<S> closed;
  int touching = 0;

  Script() : hand(settings().hand), offset(grasp_offset(hand)) {
    Isometry w = wrist_pose(0);
    const grip::ClosedHand<S> c = grip::close_hand_in_scene<S>(scene(), hand, w, object(), 0.002);
    closed = c.angles;
    touching = c.touching;
  }
  Isometry wrist_pose(S t) const {
    Isometry w = Isometry::Identity();  // palm down, fingers along +x
    w.translation() = object_path(t) - offset;
    return w;
  }
  grip::JointAngles<S> angles(S t) const { return closure(t) * closed; }
  // Wrist state with velocity and acceleration by central differences of the script.
  grip::WristState<S> wrist(S t) const {
    const S h = 1e-4;
    grip::WristState<S> s;
    s.pose = wrist_pose(t);
    const V3 p0 = wrist_pose(t - h).translation(), p1 = s.pose.translation(), p2 = wrist_pose(t + h).translation();
    s.linear_velocity = (p2 - p0) / (2 * h);
    s.linear_acceleration = (p2 - 2 * p1 + p0) / (h * h);
    return s;  // the script does not rotate the wrist: zero angular terms
  }
};

}  // namespace haptic_session
