#pragma once
/// \file
/// Solid shapes given by signed distance functions (SDF): sphere, box, cylinder, capsule,
/// and the union of a few of those. Small value types: no heap, no virtual functions.
///
/// Sign convention: distance < 0 inside, > 0 outside; the gradient is the unit OUTWARD
/// normal of the nearest surface. Each primitive's SDF is exact (the Euclidean distance to
/// its surface, with sign). The union's SDF is the minimum over primitives: exact outside,
/// and inside a lower bound in magnitude (|min| <= true depth), which is conservative.

#include <algorithm>
#include <array>
#include <cmath>

#include "grip/core/index.hpp"
#include "grip/core/status.hpp"
#include "grip/core/types.hpp"

namespace grip {

/// Kind of a shape primitive.
enum class PrimitiveKind { Sphere, Box, Cylinder, Capsule };

/// One primitive in the object frame. Local axes are the columns of `rotation`; the
/// cylinder and the capsule have their axis along local z.
template <class Scalar>
struct ShapePrimitive {
  PrimitiveKind kind{PrimitiveKind::Sphere};              ///< Which SDF.
  Vector3<Scalar> center{Vector3<Scalar>::Zero()};        ///< Centre (m), object frame.
  Matrix3<Scalar> rotation{Matrix3<Scalar>::Identity()};  ///< Local-to-object rotation.
  Vector3<Scalar> half_extents{Vector3<Scalar>::Zero()};  ///< Box half sizes (m).
  Scalar radius{0};                                       ///< Sphere, cylinder, capsule radius (m).
  Scalar half_length{0};  ///< Cylinder: half height; capsule: half the segment length (m).

  /// Signed distance (m) from object-frame point p; writes the unit outward gradient to
  /// `normal` (an arbitrary unit vector where the gradient is undefined, e.g. the centre).
  Scalar distance(const Vector3<Scalar>& p, Vector3<Scalar>& normal) const {
    const Vector3<Scalar> q = rotation.transpose() * (p - center);
    Vector3<Scalar> g_local = Vector3<Scalar>::UnitZ();
    Scalar d = Scalar(0);
    switch (kind) {
      case PrimitiveKind::Sphere: {
        const Scalar n = q.norm();
        if (n > Scalar(0)) g_local = q / n;
        d = n - radius;
        break;
      }
      case PrimitiveKind::Capsule: {
        const Scalar z = std::min(std::max(q.z(), -half_length), half_length);
        const Vector3<Scalar> v(q.x(), q.y(), q.z() - z);
        const Scalar n = v.norm();
        if (n > Scalar(0))
          g_local = v / n;
        else
          g_local = Vector3<Scalar>::UnitX();
        d = n - radius;
        break;
      }
      case PrimitiveKind::Box: {
        const Vector3<Scalar> e = q.cwiseAbs() - half_extents;
        const Vector3<Scalar> outside = e.cwiseMax(Scalar(0));
        const Scalar no = outside.norm();
        if (no > Scalar(0)) {
          g_local = outside / no;
          d = no;
        } else {
          int axis = 0;
          d = e.maxCoeff(&axis);
          g_local = Vector3<Scalar>::Zero();
          g_local(axis) = Scalar(1);
        }
        for (int i = 0; i < 3; ++i)
          if (q(i) < Scalar(0)) g_local(i) = -g_local(i);
        break;
      }
      case PrimitiveKind::Cylinder: {
        const Scalar rho = std::sqrt(q.x() * q.x() + q.y() * q.y());
        const Vector3<Scalar> radial =
            rho > Scalar(0) ? Vector3<Scalar>(q.x() / rho, q.y() / rho, Scalar(0)) : Vector3<Scalar>::UnitX();
        const Scalar axial_sign = q.z() < Scalar(0) ? Scalar(-1) : Scalar(1);
        const Scalar er = rho - radius;
        const Scalar ez = std::abs(q.z()) - half_length;
        if (er > Scalar(0) || ez > Scalar(0)) {
          const Scalar a = std::max(er, Scalar(0));
          const Scalar b = std::max(ez, Scalar(0));
          d = std::sqrt(a * a + b * b);
          g_local = (a * radial + b * axial_sign * Vector3<Scalar>::UnitZ()) / d;
        } else if (er > ez) {
          d = er;
          g_local = radial;
        } else {
          d = ez;
          g_local = axial_sign * Vector3<Scalar>::UnitZ();
        }
        break;
      }
    }
    normal = rotation * g_local;
    return d;
  }

  /// Half sizes of the object-frame axis-aligned box bounding this primitive (m).
  Vector3<Scalar> bounding_half_extents() const {
    Vector3<Scalar> local = Vector3<Scalar>::Zero();
    switch (kind) {
      case PrimitiveKind::Sphere: local.setConstant(radius); break;
      case PrimitiveKind::Box: local = half_extents; break;
      case PrimitiveKind::Cylinder: local = Vector3<Scalar>(radius, radius, half_length); break;
      case PrimitiveKind::Capsule: local = Vector3<Scalar>(radius, radius, half_length + radius); break;
    }
    return rotation.cwiseAbs() * local;
  }

  /// Volume (m^3), for tests and mass properties.
  Scalar volume() const {
    const Scalar pi = Scalar(3.14159265358979323846);
    switch (kind) {
      case PrimitiveKind::Sphere: return Scalar(4) / Scalar(3) * pi * radius * radius * radius;
      case PrimitiveKind::Box: return Scalar(8) * half_extents.prod();
      case PrimitiveKind::Cylinder: return pi * radius * radius * Scalar(2) * half_length;
      case PrimitiveKind::Capsule:
        return pi * radius * radius * (Scalar(2) * half_length + Scalar(4) / Scalar(3) * radius);
    }
    return Scalar(0);
  }
};

namespace detail {

/// The part the makers below share: a primitive of `kind` placed at `center`, turned by
/// `rotation`, its sizes zero for the maker to set.
template <class Scalar>
ShapePrimitive<Scalar> placed_primitive(PrimitiveKind kind, const Vector3<Scalar>& center,
                                        const Matrix3<Scalar>& rotation = Matrix3<Scalar>::Identity()) {
  ShapePrimitive<Scalar> s;
  s.kind = kind;
  s.center = center;
  s.rotation = rotation;
  return s;
}

}  // namespace detail

/// A sphere of `radius` (m) at `center`.
template <class Scalar>
ShapePrimitive<Scalar> make_sphere(Scalar radius, const Vector3<Scalar>& center = Vector3<Scalar>::Zero()) {
  ShapePrimitive<Scalar> s = detail::placed_primitive(PrimitiveKind::Sphere, center);
  s.radius = radius;
  return s;
}

/// A box of half sizes `half_extents` (m) along the columns of `rotation`.
template <class Scalar>
ShapePrimitive<Scalar> make_box(const Vector3<Scalar>& half_extents,
                                const Vector3<Scalar>& center = Vector3<Scalar>::Zero(),
                                const Matrix3<Scalar>& rotation = Matrix3<Scalar>::Identity()) {
  ShapePrimitive<Scalar> s = detail::placed_primitive(PrimitiveKind::Box, center, rotation);
  s.half_extents = half_extents;
  return s;
}

/// A solid circular cylinder of `radius` and height 2 `half_length` (m), axis along the
/// third column of `rotation` (object z by default).
template <class Scalar>
ShapePrimitive<Scalar> make_cylinder(Scalar radius, Scalar half_length,
                                     const Vector3<Scalar>& center = Vector3<Scalar>::Zero(),
                                     const Matrix3<Scalar>& rotation = Matrix3<Scalar>::Identity()) {
  ShapePrimitive<Scalar> s = detail::placed_primitive(PrimitiveKind::Cylinder, center, rotation);
  s.radius = radius;
  s.half_length = half_length;
  return s;
}

/// A capsule: points within `radius` of the segment of half length `half_length` along the
/// third column of `rotation` through `center`.
template <class Scalar>
ShapePrimitive<Scalar> make_capsule(Scalar radius, Scalar half_length,
                                    const Vector3<Scalar>& center = Vector3<Scalar>::Zero(),
                                    const Matrix3<Scalar>& rotation = Matrix3<Scalar>::Identity()) {
  ShapePrimitive<Scalar> s = make_cylinder(radius, half_length, center, rotation);
  s.kind = PrimitiveKind::Capsule;
  return s;
}

/// Ok if all numbers are finite, sizes positive (half_length >= 0 for a capsule) and the
/// rotation orthonormal within 1e-3; InvalidInput otherwise.
template <class Scalar>
Status validate(const ShapePrimitive<Scalar>& s) {
  if (!s.center.allFinite() || !s.rotation.allFinite() || !s.half_extents.allFinite() || !std::isfinite(s.radius) ||
      !std::isfinite(s.half_length))
    return Status::InvalidInput;
  if (!((s.rotation.transpose() * s.rotation - Matrix3<Scalar>::Identity()).cwiseAbs().maxCoeff() <= Scalar(1e-3)))
    return Status::InvalidInput;
  switch (s.kind) {
    case PrimitiveKind::Sphere: return s.radius > Scalar(0) ? Status::Ok : Status::InvalidInput;
    case PrimitiveKind::Box: return s.half_extents.minCoeff() > Scalar(0) ? Status::Ok : Status::InvalidInput;
    case PrimitiveKind::Cylinder:
      return s.radius > Scalar(0) && s.half_length > Scalar(0) ? Status::Ok : Status::InvalidInput;
    case PrimitiveKind::Capsule:
      return s.radius > Scalar(0) && s.half_length >= Scalar(0) ? Status::Ok : Status::InvalidInput;
  }
  return Status::InvalidInput;
}

/// The union of up to MaxPrimitives primitives (an obstacle such as a table is one box).
template <class Scalar, int MaxPrimitives = 4>
class Shape {
  static_assert(MaxPrimitives >= 1, "a shape holds at least one primitive");

 public:
  static constexpr int capacity = MaxPrimitives;  ///< Most primitives held.

  Shape() = default;
  /// A shape of one primitive (check validate() or use add() to be told about bad input).
  explicit Shape(const ShapePrimitive<Scalar>& p) { add(p); }

  /// Adds a primitive: InvalidInput (shape unchanged) if it fails validate() or the shape is full.
  Status add(const ShapePrimitive<Scalar>& p) {
    if (count_ >= MaxPrimitives || validate(p) != Status::Ok) return Status::InvalidInput;
    prims_[detail::idx(count_++)] = p;
    return Status::Ok;
  }
  /// Number of primitives.
  int size() const { return count_; }
  /// Primitive i. Precondition (GRIP_ASSERT): 0 <= i < size().
  const ShapePrimitive<Scalar>& primitive(int i) const {
    GRIP_ASSERT(i < count_);
    return prims_[detail::idx(i)];
  }

  /// The parts of the field (collision.hpp's multi-contact narrow phase): the primitives.
  static constexpr int max_parts = MaxPrimitives;
  /// Number of parts: size().
  int part_count() const { return count_; }
  /// Signed distance (m) of p from part i (primitive i, 0 <= i < size()), its outward normal.
  Scalar part_distance(int i, const Vector3<Scalar>& p, Vector3<Scalar>& normal) const {
    GRIP_ASSERT(i < count_);
    return prims_[detail::idx(i)].distance(p, normal);
  }

  /// Signed distance (m) of object-frame point p (min over primitives; +max_magnitude for an
  /// empty shape); `normal` receives the unit outward gradient of the nearest primitive.
  Scalar distance(const Vector3<Scalar>& p, Vector3<Scalar>& normal) const {
    Scalar best = Scalar(1e9);
    normal = Vector3<Scalar>::UnitZ();
    Vector3<Scalar> g = Vector3<Scalar>::UnitZ();
    for (int i = 0; i < count_; ++i) {
      const Scalar d = prims_[detail::idx(i)].distance(p, g);
      if (d < best) {
        best = d;
        normal = g;
      }
    }
    return best;
  }
  /// Signed distance (m) of object-frame point p.
  Scalar distance(const Vector3<Scalar>& p) const {
    Vector3<Scalar> g = Vector3<Scalar>::UnitZ();
    return distance(p, g);
  }

  /// Object-frame axis-aligned bounding box: writes its corners; false for an empty shape.
  bool bounding_box(Vector3<Scalar>& lo, Vector3<Scalar>& hi) const {
    if (count_ == 0) return false;
    for (int i = 0; i < count_; ++i) {
      const ShapePrimitive<Scalar>& p = prims_[detail::idx(i)];
      const Vector3<Scalar> h = p.bounding_half_extents();
      if (i == 0) {
        lo = p.center - h;
        hi = p.center + h;
      } else {
        lo = lo.cwiseMin(p.center - h);
        hi = hi.cwiseMax(p.center + h);
      }
    }
    return true;
  }

 private:
  std::array<ShapePrimitive<Scalar>, MaxPrimitives> prims_{};
  int count_{0};
};

}  // namespace grip
