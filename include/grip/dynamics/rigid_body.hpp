#pragma once
/// \file
/// A rigid object's mass properties and state: mass, principal inertia, pose, twist.

#include <cmath>

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>

#include "grip/contact/contact.hpp"
#include "grip/core/scalar_traits.hpp"
#include "grip/core/status.hpp"
#include "grip/core/types.hpp"

namespace grip {

/// A rigid object, in grip's conventions (docs/conventions.md: SI units, one world-aligned frame).
///
/// - The body frame has its origin at the centre of mass and its axes along the principal
///   axes of inertia, so the body-frame inertia tensor is `diag(principal_inertia)`
///   (kg m^2). from_inertia_tensor() turns any symmetric tensor into this form.
/// - `orientation` (unit quaternion) rotates body coordinates into world coordinates:
///   `v_world = R v_body`, `R = orientation.toRotationMatrix()`.
/// - The twist is world-frame: `linear_velocity` of the centre of mass (m/s) and
///   `angular_velocity` (rad/s).
///
/// Invariants checked by validate(): all finite and within ScalarTraits::max_magnitude,
/// mass > 0, principal moments > 0 and satisfying the triangle inequality
/// (I_a <= I_b + I_c, with a relative slack of normal_tolerance), |orientation| = 1 within
/// ScalarTraits::normal_tolerance.
template <class Scalar>
struct RigidBody {
  Scalar mass{1};                                                                ///< m (kg)
  Vector3<Scalar> principal_inertia{Vector3<Scalar>::Ones()};                    ///< body-frame I (kg m^2)
  Vector3<Scalar> position{Vector3<Scalar>::Zero()};                             ///< centre of mass (m)
  Eigen::Quaternion<Scalar> orientation{Eigen::Quaternion<Scalar>::Identity()};  ///< body to world
  Vector3<Scalar> linear_velocity{Vector3<Scalar>::Zero()};                      ///< v (m/s), world
  Vector3<Scalar> angular_velocity{Vector3<Scalar>::Zero()};                     ///< omega (rad/s), world

  /// The rotation matrix R of `orientation` (body to world).
  Matrix3<Scalar> rotation() const { return orientation.toRotationMatrix(); }

  /// The inertia tensor about the centre of mass in world axes, `R diag(I) R^T` (kg m^2).
  Matrix3<Scalar> world_inertia() const {
    const Matrix3<Scalar> r = rotation();
    return r * principal_inertia.asDiagonal() * r.transpose();
  }

  /// Linear momentum m v (kg m/s).
  Vector3<Scalar> linear_momentum() const { return mass * linear_velocity; }

  /// Angular momentum about the centre of mass, world axes: `I_world omega` (kg m^2/s).
  Vector3<Scalar> angular_momentum() const { return world_inertia() * angular_velocity; }

  /// Kinetic energy `1/2 m |v|^2 + 1/2 omega^T I_world omega` (J).
  Scalar kinetic_energy() const {
    const Vector3<Scalar> wb = orientation.conjugate() * angular_velocity;  // body axes
    return Scalar(0.5) * mass * linear_velocity.squaredNorm() +
           Scalar(0.5) * wb.dot(principal_inertia.cwiseProduct(wb));
  }

  /// Velocity (m/s, world) of the material point at world position `p`: v + omega x (p - x).
  Vector3<Scalar> point_velocity(const Vector3<Scalar>& p) const {
    return linear_velocity + angular_velocity.cross(p - position);
  }
};

/// Ok if `b` satisfies the invariants of RigidBody, InvalidInput otherwise.
template <class Scalar>
Status validate(const RigidBody<Scalar>& b) {
  using T = ScalarTraits<Scalar>;
  if (!detail::in_range(b.mass) || !detail::all_in_range(b.principal_inertia) || !detail::all_in_range(b.position) ||
      !detail::all_in_range(b.orientation.coeffs()) || !detail::all_in_range(b.linear_velocity) ||
      !detail::all_in_range(b.angular_velocity))
    return Status::InvalidInput;
  if (!(b.mass > Scalar(0))) return Status::InvalidInput;
  const Vector3<Scalar>& i = b.principal_inertia;
  if (!(i.minCoeff() > Scalar(0))) return Status::InvalidInput;
  const Scalar slack = T::normal_tolerance * i.sum();
  if (i.x() > i.y() + i.z() + slack || i.y() > i.x() + i.z() + slack || i.z() > i.x() + i.y() + slack)
    return Status::InvalidInput;
  if (!(std::abs(b.orientation.squaredNorm() - Scalar(1)) <= Scalar(2) * T::normal_tolerance))
    return Status::InvalidInput;
  return Status::Ok;
}

/// Result of from_inertia_tensor().
template <class Scalar>
struct PrincipalInertia {
  Vector3<Scalar> moments{Vector3<Scalar>::Ones()};  ///< principal moments (kg m^2), ascending
  /// Rotation from principal axes to the axes the tensor was given in (columns: the axes).
  Eigen::Quaternion<Scalar> axes{Eigen::Quaternion<Scalar>::Identity()};
  Status status{Status::InvalidInput};  ///< Ok, or InvalidInput (moments 1, axes identity)
};

/// Diagonalises a symmetric inertia tensor `tensor` (kg m^2, about the centre of mass, in
/// some frame F): `tensor = A diag(moments) A^T` with A = axes (a proper rotation). A body
/// whose orientation was `q` (F to world) gets `principal_inertia = moments` and
/// `orientation = q * axes`. InvalidInput for a non-finite, non-symmetric (relative
/// 1e3 rank_tolerance) or non-positive-definite tensor. Closed form, no heap.
template <class Scalar>
PrincipalInertia<Scalar> from_inertia_tensor(const Matrix3<Scalar>& tensor) {
  PrincipalInertia<Scalar> out;
  if (!detail::all_in_range(tensor)) return out;
  const Scalar scale = tensor.cwiseAbs().maxCoeff();
  if (!(scale > Scalar(0))) return out;
  if ((tensor - tensor.transpose()).cwiseAbs().maxCoeff() > Scalar(1000) * ScalarTraits<Scalar>::rank_tolerance * scale)
    return out;
  Eigen::SelfAdjointEigenSolver<Matrix3<Scalar>> eig;
  eig.computeDirect(tensor);
  if (!(eig.eigenvalues().minCoeff() > Scalar(0))) return out;
  Matrix3<Scalar> a = eig.eigenvectors();
  if (a.determinant() < Scalar(0)) a.col(2) = -a.col(2);
  out.moments = eig.eigenvalues();
  out.axes = Eigen::Quaternion<Scalar>(a).normalized();
  out.status = Status::Ok;
  return out;
}

/// Mass properties of a solid cylinder of mass m, radius r, half-length h about its axis z:
/// I_z = m r^2 / 2, I_x = I_y = m (3 r^2 + (2h)^2) / 12 (kg m^2).
template <class Scalar>
Vector3<Scalar> solid_cylinder_inertia(Scalar m, Scalar r, Scalar h) {
  const Scalar ixy = m * (Scalar(3) * r * r + Scalar(4) * h * h) / Scalar(12);
  return Vector3<Scalar>(ixy, ixy, m * r * r / Scalar(2));
}

/// Mass properties of a solid box of mass m and half sizes h about its principal axes:
/// I_x = m (h_y^2 + h_z^2) / 3, and so on (kg m^2).
template <class Scalar>
Vector3<Scalar> solid_box_inertia(Scalar m, const Vector3<Scalar>& h) {
  return Vector3<Scalar>(m * (h.y() * h.y() + h.z() * h.z()) / Scalar(3),
                         m * (h.x() * h.x() + h.z() * h.z()) / Scalar(3),
                         m * (h.x() * h.x() + h.y() * h.y()) / Scalar(3));
}

}  // namespace grip
