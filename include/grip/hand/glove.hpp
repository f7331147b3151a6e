#pragma once
/// \file
/// Data gloves to the whole hand's 20 joints (hand_joints.hpp): per-sensor calibration, the
/// paper's glove of 14 flexion sensors and a 22-sensor layout with abduction, thumb rotation,
/// palm arch and wrist. Small value types, no heap; map() is real-time safe.
///
/// Calibration of sensor i: angle_i = gain_i (raw_i - offset_i) (rad), for readings within
/// [raw_min_i, raw_max_i]; a reading outside is clamped to the range and the mapping answers
/// Status::OutOfRange, as it does when a mapped joint leaves its JointLimits (it is clamped).
///
/// 22-sensor layout (the grouping of common instrumented gloves):
///   0 thumb rotation (CMC flexion), 1 thumb MCP, 2 thumb IP, 3 thumb abduction (CMC),
///   4 index MCP, 5 index PIP, 6 index DIP, 7 index-long abduction,
///   8 long MCP, 9 long PIP, 10 long DIP,
///   11 ring MCP, 12 ring PIP, 13 ring DIP, 14 long-ring abduction,
///   15 little MCP, 16 little PIP, 17 little DIP, 18 ring-little abduction,
///   19 palm arch, 20 wrist flexion, 21 wrist abduction (radial deviation).
/// An abduction sensor measures the spread between two neighbours (positive apart); the long
/// finger is the reference (its abduction 0), so index = s7, ring = -s14, little = ring - s18.
/// The model has no palm-arch or wrist joint (the tracker gives the wrist): those readings are
/// returned calibrated, beside the joints.

#include <array>
#include <cmath>
#include <limits>

#include <Eigen/Core>

#include "grip/core/index.hpp"
#include "grip/core/status.hpp"
#include "grip/hand/hand_joints.hpp"
#include "grip/hand/hand_model.hpp"

namespace grip {

/// Offset, gain and valid range of each of N sensors. Defaults: offset 0, gain 1 (readings
/// already in radians), any finite reading valid.
template <class Scalar, int N>
struct GloveCalibration {
  using Readings = Eigen::Matrix<Scalar, N, 1>;  ///< One value per sensor.
  std::array<Scalar, N> offset{};                ///< Raw reading at angle 0.
  std::array<Scalar, N> gain{};                  ///< Radians per raw unit, finite and nonzero.
  std::array<Scalar, N> raw_min{};               ///< Least valid raw reading.
  std::array<Scalar, N> raw_max{};               ///< Largest valid raw reading.

  GloveCalibration() {
    gain.fill(Scalar(1));
    raw_min.fill(std::numeric_limits<Scalar>::lowest());
    raw_max.fill(std::numeric_limits<Scalar>::max());
  }

  /// Calibrated angles of raw readings. InvalidInput (angles unchanged) if a reading is not
  /// finite or a gain is zero or not finite; OutOfRange if a reading was clamped; Ok otherwise.
  Status angles(const Readings& raw, Readings& out) const {
    for (int i = 0; i < N; ++i)
      if (!std::isfinite(raw(i)) || !std::isfinite(gain[detail::idx(i)]) || gain[detail::idx(i)] == Scalar(0))
        return Status::InvalidInput;
    bool clamped = false;
    for (int i = 0; i < N; ++i) {
      const Scalar lo = raw_min[detail::idx(i)], hi = raw_max[detail::idx(i)];
      const Scalar r = raw(i) < lo ? lo : (raw(i) > hi ? hi : raw(i));
      clamped = clamped || r != raw(i);
      out(i) = gain[detail::idx(i)] * (r - offset[detail::idx(i)]);
    }
    return clamped ? Status::OutOfRange : Status::Ok;
  }

  /// The raw readings that calibrate to `a` (the inverse, for simulated gloves and tests).
  Readings raw(const Readings& a) const {
    Readings r;
    for (int i = 0; i < N; ++i) r(i) = offset[detail::idx(i)] + a(i) / gain[detail::idx(i)];
    return r;
  }
};

/// The paper's glove: 14 flexion sensors in the joint order of hand_model.hpp. The thumb's
/// CMC is not measured: it follows the thumb's MCP, from open (0, 0) at MCP 0 to `opposition`
/// at the MCP's upper limit (the thumb closes across the palm as it flexes; a model choice).
/// Finger abductions are 0.
template <class Scalar>
struct Glove14 {
  static constexpr int sensors = 14;                   ///< Readings per frame.
  using Readings = Eigen::Matrix<Scalar, sensors, 1>;  ///< Raw readings.
  GloveCalibration<Scalar, sensors> calibration{};     ///< Per sensor.
  /// CMC flexion and abduction (rad) at full thumb MCP flexion: 30 and 45 deg.
  std::array<Scalar, 2> opposition{{Scalar(30) * Scalar(3.14159265358979323846) / Scalar(180),
                                    Scalar(45) * Scalar(3.14159265358979323846) / Scalar(180)}};
  bool couple_dip{false};  ///< Ignore the DIP sensors: DIP = 2/3 PIP (couple_dip()).

  /// Joints of raw readings, clamped to `limits`. InvalidInput (q unchanged) on a non-finite
  /// reading or a bad gain; OutOfRange if a reading or a joint was clamped; Ok otherwise.
  Status map(const Readings& raw, const JointLimits<Scalar>& limits, HandJoints<Scalar>& q) const;
  /// Raw readings that map to q (q's CMC and abductions are ignored: they follow).
  Readings readings(const HandJoints<Scalar>& q) const;
};

/// What a 22-sensor glove measures beyond the 20 joints (rad, calibrated).
template <class Scalar>
struct GloveExtras {
  Scalar palm_arch{0};        ///< Sensor 19.
  Scalar wrist_flexion{0};    ///< Sensor 20.
  Scalar wrist_abduction{0};  ///< Sensor 21.
};

/// A 22-sensor glove, in the layout of this file's header.
template <class Scalar>
struct Glove22 {
  static constexpr int sensors = 22;                   ///< Readings per frame.
  using Readings = Eigen::Matrix<Scalar, sensors, 1>;  ///< Raw readings.
  GloveCalibration<Scalar, sensors> calibration{};     ///< Per sensor.
  bool couple_dip{false};                              ///< Ignore the DIP sensors: DIP = 2/3 PIP (couple_dip()).

  /// Joints (and the extras) of raw readings, joints clamped to `limits`. Statuses as
  /// Glove14::map; `extras` may be null.
  Status map(const Readings& raw, const JointLimits<Scalar>& limits, HandJoints<Scalar>& q,
             GloveExtras<Scalar>* extras = nullptr) const;
  /// Raw readings that map to q and `extras` (the long finger's abduction is the reference:
  /// the others are read relative to it).
  Readings readings(const HandJoints<Scalar>& q, const GloveExtras<Scalar>& extras = {}) const;
};

// ---------------------------------------------------------------------------------------------

namespace detail {
/// Sensor of the 22-glove for joint i of the 20, or -1 for a finger abduction (relative).
constexpr int glove22_sensor(int i) {
  constexpr int table[hand_dof_count] = {0, 3, 1, 2, -1, 4, 5, 6, -1, 8, 9, 10, -1, 11, 12, 13, -1, 15, 16, 17};
  return table[i];
}

template <class Scalar>
Status finish_glove(Status status, bool couple, const JointLimits<Scalar>& limits, HandJoints<Scalar>& q) {
  if (couple) couple_dip(q);
  return limits.clamp(q) > 0 ? Status::OutOfRange : status;
}
}  // namespace detail

template <class Scalar>
Status Glove14<Scalar>::map(const Readings& raw, const JointLimits<Scalar>& limits, HandJoints<Scalar>& q) const {
  Readings a;
  const Status s = calibration.angles(raw, a);
  if (s == Status::InvalidInput) return s;
  HandJoints<Scalar> out = HandJoints<Scalar>::Zero();
  for (int k = 0; k < hand_joint_count; ++k) out(phalanx_joint(k)) = a(k);
  const Scalar mcp_max = limits.upper[detail::idx(HandJoint::ThumbMcp)];
  const Scalar mcp = out(static_cast<int>(HandJoint::ThumbMcp));
  const Scalar share =
      mcp_max > Scalar(0) ? (mcp <= Scalar(0) ? Scalar(0) : (mcp >= mcp_max ? Scalar(1) : mcp / mcp_max)) : Scalar(0);
  out(0) = share * opposition[0];
  out(1) = share * opposition[1];
  q = out;
  return detail::finish_glove(s, couple_dip, limits, q);
}

template <class Scalar>
typename Glove14<Scalar>::Readings Glove14<Scalar>::readings(const HandJoints<Scalar>& q) const {
  Readings a;
  for (int k = 0; k < hand_joint_count; ++k) a(k) = q(phalanx_joint(k));
  return calibration.raw(a);
}

template <class Scalar>
Status Glove22<Scalar>::map(const Readings& raw, const JointLimits<Scalar>& limits, HandJoints<Scalar>& q,
                            GloveExtras<Scalar>* extras) const {
  Readings a;
  const Status s = calibration.angles(raw, a);
  if (s == Status::InvalidInput) return s;
  HandJoints<Scalar> out;
  for (int i = 0; i < hand_dof_count; ++i)
    out(i) = detail::glove22_sensor(i) >= 0 ? a(detail::glove22_sensor(i)) : Scalar(0);
  out(static_cast<int>(HandJoint::IndexAbduction)) = a(7);
  out(static_cast<int>(HandJoint::RingAbduction)) = -a(14);
  out(static_cast<int>(HandJoint::LittleAbduction)) = -a(14) - a(18);
  if (extras) *extras = GloveExtras<Scalar>{a(19), a(20), a(21)};
  q = out;
  return detail::finish_glove(s, couple_dip, limits, q);
}

template <class Scalar>
typename Glove22<Scalar>::Readings Glove22<Scalar>::readings(const HandJoints<Scalar>& q,
                                                             const GloveExtras<Scalar>& extras) const {
  Readings a;
  for (int i = 0; i < hand_dof_count; ++i)
    if (detail::glove22_sensor(i) >= 0) a(detail::glove22_sensor(i)) = q(i);
  const Scalar ref = q(static_cast<int>(HandJoint::LongAbduction));
  a(7) = q(static_cast<int>(HandJoint::IndexAbduction)) - ref;
  a(14) = ref - q(static_cast<int>(HandJoint::RingAbduction));
  a(18) = q(static_cast<int>(HandJoint::RingAbduction)) - q(static_cast<int>(HandJoint::LittleAbduction));
  a(19) = extras.palm_arch;
  a(20) = extras.wrist_flexion;
  a(21) = extras.wrist_abduction;
  return calibration.raw(a);
}

}  // namespace grip
