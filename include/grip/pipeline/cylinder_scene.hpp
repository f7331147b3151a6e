#pragma once
/// \file
/// An analytic contact source for the haptic pipeline: a cylindrical object, the hand's
/// capsules, and axis-aligned box obstacles (a table). Closed-form distances, no trees: a
/// reference for the tree-based detection of geometry/, and a fast stand-in for it.

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <limits>

#include "grip/core/types.hpp"
#include "grip/dynamics/rigid_body.hpp"
#include "grip/hand/hand_kinematics.hpp"
#include "grip/geometry/collision.hpp"
#include "grip/pipeline/obstacle_contacts.hpp"

namespace grip {

/// An axis-aligned box obstacle [lower, upper] (m, world).
template <class Scalar>
struct BoxObstacle {
  Vector3<Scalar> lower{Vector3<Scalar>::Zero()};  ///< smallest corner (m)
  Vector3<Scalar> upper{Vector3<Scalar>::Zero()};  ///< largest corner (m)
};

namespace detail {

/// Parameters (s, t) in [0, 1]^2 of the closest points p0 + s d1 and q0 + t d2 of two
/// segments (degenerate segments handled). Standard clamped minimisation of |P(s) - Q(t)|^2.
template <class Scalar>
void closest_segment_parameters(const Vector3<Scalar>& p0, const Vector3<Scalar>& d1, const Vector3<Scalar>& q0,
                                const Vector3<Scalar>& d2, Scalar& s, Scalar& t) {
  const Vector3<Scalar> r = p0 - q0;
  const Scalar a = d1.squaredNorm(), e = d2.squaredNorm(), f = d2.dot(r);
  const Scalar tiny = Scalar(1e-12);
  auto clamp01 = [](Scalar x) { return std::min(Scalar(1), std::max(Scalar(0), x)); };
  if (a <= tiny && e <= tiny) {
    s = t = Scalar(0);
    return;
  }
  if (a <= tiny) {
    s = Scalar(0);
    t = clamp01(f / e);
    return;
  }
  const Scalar c = d1.dot(r);
  if (e <= tiny) {
    t = Scalar(0);
    s = clamp01(-c / a);
    return;
  }
  const Scalar b = d1.dot(d2), denom = a * e - b * b;
  s = denom > tiny * a * e ? clamp01((b * f - c * e) / denom) : Scalar(0);
  t = (b * s + f) / e;
  if (t < Scalar(0)) {
    t = Scalar(0);
    s = clamp01(-c / a);
  } else if (t > Scalar(1)) {
    t = Scalar(1);
    s = clamp01((b - c) / a);
  }
}

}  // namespace detail

/// A solid cylinder (the grasped object, its axis along the body z axis through the centre
/// of mass) among up to MaxBoxes box obstacles.
///
/// - Hand contacts: a phalanx capsule (segment, radius r) touches the cylinder's side when
///   the closest points of its segment and the cylinder's axis segment are closer than
///   radius + r with the axis point strictly inside the axis segment; the contact point is
///   the cylinder surface point towards the phalanx, the normal points from the phalanx
///   to the axis (into the object), depth = radius + r - distance. Contacts with the flat
///   end caps are not modelled (a power grip holds the side).
/// - Obstacle contacts: `rim_points` points on each end-cap rim (2 rim_points in all) are
///   tested against each box; a point inside a box gives a penalty contact through the
///   nearest box face (depth: distance to that face; normal: the face's outward normal,
///   which points into the object).
template <class Scalar, int MaxBoxes = 4>
struct CylinderScene {
  Scalar radius{Scalar(0.035)};       ///< cylinder radius (m)
  Scalar half_length{Scalar(0.06)};   ///< half of the cylinder's length (m)
  int rim_points{8};                  ///< sample points per rim, in [3, max_obstacle_contacts / 2]
  std::array<BoxObstacle<Scalar>, MaxBoxes> boxes{};  ///< boxes[0..box_count)
  int box_count{0};                   ///< number of obstacles

  /// The hand contacts of `posture` with the cylinder posed as `object`. Returns their count.
  int hand_contacts(const HandPosture<Scalar>& posture, const RigidBody<Scalar>& object,
                    HandContacts<Scalar>& out) const {
    out.count = 0;
    const Vector3<Scalar> axis = object.orientation * Vector3<Scalar>::UnitZ();
    const Vector3<Scalar> q0 = object.position - half_length * axis;
    const Vector3<Scalar> d2 = (Scalar(2) * half_length) * axis;
    for (int k = 0; k < hand_phalanx_count; ++k) {
      const PhalanxCapsule<Scalar>& c = posture.phalanges[static_cast<std::size_t>(k)];
      Scalar s, t;
      detail::closest_segment_parameters<Scalar>(c.base, c.tip - c.base, q0, d2, s, t);
      if (!(t > Scalar(0) && t < Scalar(1))) continue;
      const Vector3<Scalar> p = c.base + s * (c.tip - c.base);
      const Vector3<Scalar> q = q0 + t * d2;
      const Vector3<Scalar> diff = p - q;
      const Scalar dist = diff.norm();
      const Scalar depth = radius + c.radius - dist;
      if (!(depth > Scalar(0)) || !(dist > Scalar(1e-9))) continue;
      const Vector3<Scalar> u = diff / dist;
      HandContact<Scalar>& h = out.items[static_cast<std::size_t>(out.count++)];
      h.finger = phalanx_finger(k);
      h.phalanx = phalanx_kind(k);
      h.samples = 1;
      h.point = q + radius * u;
      h.normal = -u;
      h.depth = depth;
    }
    return out.count;
  }

  /// The obstacle contacts of the cylinder posed as `object`; points are relative to its
  /// centre of mass, depth_rate is left 0. Returns their count.
  int obstacle_contacts(const RigidBody<Scalar>& object, ObstacleContactSet<Scalar>& out) const {
    out.count = 0;
    const Matrix3<Scalar> rot = object.rotation();
    const int n = std::max(3, std::min(rim_points, max_obstacle_contacts / 2));
    const Scalar two_pi = Scalar(6.283185307179586);
    for (int end = 0; end < 2; ++end) {
      const Scalar z = end == 0 ? -half_length : half_length;
      for (int j = 0; j < n; ++j) {
        const Scalar phi = two_pi * Scalar(j) / Scalar(n);
        const Vector3<Scalar> r = rot * Vector3<Scalar>(radius * std::cos(phi), radius * std::sin(phi), z);
        const Vector3<Scalar> p = object.position + r;
        for (int b = 0; b < box_count; ++b) {
          const BoxObstacle<Scalar>& box = boxes[static_cast<std::size_t>(b)];
          if ((p.array() <= box.lower.array()).any() || (p.array() >= box.upper.array()).any()) continue;
          Scalar depth = std::numeric_limits<Scalar>::max();
          Vector3<Scalar> normal = Vector3<Scalar>::Zero();
          for (int axis_i = 0; axis_i < 3; ++axis_i) {
            const Scalar lo = p(axis_i) - box.lower(axis_i), hi = box.upper(axis_i) - p(axis_i);
            if (lo < depth) {
              depth = lo;
              normal = -Vector3<Scalar>::Unit(axis_i);
            }
            if (hi < depth) {
              depth = hi;
              normal = Vector3<Scalar>::Unit(axis_i);
            }
          }
          if (out.count >= max_obstacle_contacts) return out.count;
          PenaltyContact<Scalar>& c = out.items[static_cast<std::size_t>(out.count++)];
          c.point = r;
          c.normal = normal;
          c.depth = depth;
          c.depth_rate = Scalar(0);
        }
      }
    }
    return out.count;
  }
};

/// Mass properties of a solid cylinder of mass m, radius r, half-length h about its axis z:
/// I_z = m r^2 / 2, I_x = I_y = m (3 r^2 + (2h)^2) / 12 (kg m^2).
template <class Scalar>
Vector3<Scalar> solid_cylinder_inertia(Scalar m, Scalar r, Scalar h) {
  const Scalar ixy = m * (Scalar(3) * r * r + Scalar(4) * h * h) / Scalar(12);
  return Vector3<Scalar>(ixy, ixy, m * r * r / Scalar(2));
}

}  // namespace grip
