#pragma once
/// \file
/// The obstacle contacts a scene reports to the haptic pipeline each frame: obstacles of any
/// shape (unions of primitives, shape.hpp, placed in the world) against sample points of the
/// grasped object's surface, each point inside an obstacle a penalty contact.

#include <array>
#include <cmath>

#include "grip/core/index.hpp"
#include "grip/core/status.hpp"
#include "grip/core/types.hpp"
#include "grip/dynamics/penalty_contact.hpp"
#include "grip/dynamics/rigid_body.hpp"
#include "grip/geometry/shape.hpp"

namespace grip {

/// Most obstacle contacts one frame may report to the pipeline.
constexpr int max_obstacle_contacts = 32;

/// The obstacle contacts of one frame, in the conventions of PenaltyContact (points from the
/// object's centre of mass, normals into the object). The pipeline fills in depth_rate from
/// the object's twist; a scene may leave it 0.
template <class Scalar>
struct ObstacleContactSet {
  std::array<PenaltyContact<Scalar>, max_obstacle_contacts> items{};  ///< items[0..count)
  int count{0};                                                       ///< <= max_obstacle_contacts
};

/// Points of an object's surface, in its body frame (m, from the centre of mass), where it
/// may meet obstacles: a cylinder's rims, a box's corners and edges, a mesh's vertices.
template <class Scalar, int MaxPoints = max_obstacle_contacts>
struct SurfacePoints {
  using Point = Vector3<Scalar>;                   ///< A body-frame point (m).
  std::array<Vector3<Scalar>, MaxPoints> items{};  ///< items[0..count)
  int count{0};                                    ///< number of points

  /// Appends a point: InvalidInput (unchanged) if it is not finite or the set is full.
  Status add(const Vector3<Scalar>& body_point) {
    if (count >= MaxPoints || !body_point.allFinite()) return Status::InvalidInput;
    items[detail::idx(count++)] = body_point;
    return Status::Ok;
  }
};

/// Up to MaxObstacles obstacles, each a Shape given in the world frame (a table is one box).
template <class Scalar, int MaxObstacles = 4>
struct Obstacles {
  std::array<Shape<Scalar>, MaxObstacles> shapes{};  ///< shapes[0..count), world frame
  int count{0};                                      ///< number of obstacles

  /// Adds an obstacle: InvalidInput (unchanged) if it is empty or there is no room.
  Status add(const Shape<Scalar>& shape) {
    if (count >= MaxObstacles || shape.size() == 0) return Status::InvalidInput;
    shapes[detail::idx(count++)] = shape;
    return Status::Ok;
  }
  /// Adds the axis-aligned box [lower, upper] (m, world): InvalidInput if it is empty,
  /// not finite, or there is no room.
  Status add_box(const Vector3<Scalar>& lower, const Vector3<Scalar>& upper) {
    if (!lower.allFinite() || !upper.allFinite() || !((upper - lower).minCoeff() > Scalar(0)))
      return Status::InvalidInput;
    return add(Shape<Scalar>(make_box<Scalar>((upper - lower) / Scalar(2), (upper + lower) / Scalar(2))));
  }
  /// Removes every obstacle.
  void clear() { count = 0; }

  /// The penalty contacts of `points` (body frame) of `object`: a point p inside obstacle o
  /// (phi_o(p) < 0) gives a contact at p (relative to the centre of mass, world axes) of
  /// depth -phi_o(p) along o's outward normal at p (which points into the object). At most
  /// max_obstacle_contacts, in point order then obstacle order; depth_rate is left 0.
  /// Returns their count.
  template <int MaxPoints>
  int contacts(const RigidBody<Scalar>& object, const SurfacePoints<Scalar, MaxPoints>& points,
               ObstacleContactSet<Scalar>& out) const {
    out.count = 0;
    if (count == 0) return 0;
    const Matrix3<Scalar> rot = object.rotation();
    for (int i = 0; i < points.count; ++i) {
      const Vector3<Scalar> r = rot * points.items[detail::idx(i)];
      const Vector3<Scalar> p = object.position + r;
      for (int o = 0; o < count; ++o) {
        Vector3<Scalar> n;
        const Scalar d = shapes[detail::idx(o)].distance(p, n);
        if (!(d < Scalar(0))) continue;
        if (out.count >= max_obstacle_contacts) return out.count;
        PenaltyContact<Scalar>& c = out.items[detail::idx(out.count++)];
        c.point = r;
        c.normal = n;
        c.depth = -d;
        c.depth_rate = Scalar(0);
      }
    }
    return out.count;
  }
};

/// Appends `per_rim` points evenly spaced on each end rim of a solid cylinder (radius,
/// half_length, axis body z through the centre of mass): 2 per_rim points. InvalidInput if
/// they do not fit (those that fit are kept) or per_rim < 1.
template <class Scalar, int MaxPoints>
Status add_rim_points(SurfacePoints<Scalar, MaxPoints>& points,
                      typename SurfacePoints<Scalar, MaxPoints>::Point::Scalar radius,
                      typename SurfacePoints<Scalar, MaxPoints>::Point::Scalar half_length, int per_rim) {
  if (per_rim < 1) return Status::InvalidInput;
  const Scalar two_pi = Scalar(6.283185307179586);
  for (int end = 0; end < 2; ++end)
    for (int j = 0; j < per_rim; ++j) {
      const Scalar a = two_pi * Scalar(j) / Scalar(per_rim);
      const Vector3<Scalar> p(radius * std::cos(a), radius * std::sin(a), end == 0 ? -half_length : half_length);
      if (points.add(p) != Status::Ok) return Status::InvalidInput;
    }
  return Status::Ok;
}

/// Appends a box's 8 corners and 12 edge midpoints (half sizes along the columns of
/// `rotation`, centred at `center`, body frame). InvalidInput if they do not fit.
template <class Scalar, int MaxPoints>
Status add_box_points(SurfacePoints<Scalar, MaxPoints>& points,
                      const typename SurfacePoints<Scalar, MaxPoints>::Point& half_extents,
                      const typename SurfacePoints<Scalar, MaxPoints>::Point& center = Vector3<Scalar>::Zero(),
                      const Matrix3<Scalar>& rotation = Matrix3<Scalar>::Identity()) {
  // Each coordinate in {-1, 0, +1} times the half size, with at most one zero: 8 + 12 points.
  for (int code = 0; code < 27; ++code) {
    const int c[3] = {code % 3 - 1, (code / 3) % 3 - 1, code / 9 - 1};
    if ((c[0] == 0) + (c[1] == 0) + (c[2] == 0) > 1) continue;
    const Vector3<Scalar> local =
        Vector3<Scalar>(static_cast<Scalar>(c[0]), static_cast<Scalar>(c[1]), static_cast<Scalar>(c[2]))
            .cwiseProduct(half_extents);
    if (points.add(center + rotation * local) != Status::Ok) return Status::InvalidInput;
  }
  return Status::Ok;
}

}  // namespace grip
