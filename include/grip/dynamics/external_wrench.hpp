#pragma once
/// \file
/// The external wrench of the paper's eq. 1-2 on a grasped object: gravity, the inertial
/// (d'Alembert) terms of the motion the hand imposes, and obstacle penalty contacts.

#include <Eigen/Geometry>

#include "grip/core/status.hpp"
#include "grip/core/types.hpp"
#include "grip/dynamics/penalty_contact.hpp"
#include "grip/dynamics/rigid_body.hpp"

namespace grip {

/// Gravity's wrench `[m g; 0]` (N; N m about the centre of mass). `g` in m/s^2, world
/// axes (e.g. (0, 0, -9.81)).
template <class Scalar>
Wrench<Scalar> gravity_wrench(Scalar mass, const Vector3<Scalar>& g) {
  Wrench<Scalar> w;
  w << mass * g, Vector3<Scalar>::Zero();
  return w;
}

/// The inertial (d'Alembert) wrench of a body whose motion is imposed: with the centre of
/// mass accelerating at `a` (m/s^2) and the body turning at `body.angular_velocity`
/// (rad/s) with angular acceleration `alpha` (rad/s^2), all world axes, it is
/// `[-m a; -(I alpha + omega x I omega)]`, I = body.world_inertia(). Adding it to the
/// real external wrench makes Newton-Euler a statics problem: the contacts must balance
/// the sum (docs/conventions.md: G f + w_ext = 0).
template <class Scalar>
Wrench<Scalar> inertial_wrench(const RigidBody<Scalar>& body, const Vector3<Scalar>& a, const Vector3<Scalar>& alpha) {
  const Matrix3<Scalar> inertia = body.world_inertia();
  const Vector3<Scalar>& omega = body.angular_velocity;
  Wrench<Scalar> w;  // fixed-size halves: see penalty_wrench()
  w.template head<3>() = -body.mass * a;
  w.template tail<3>() = -(inertia * alpha + omega.cross(inertia * omega));
  return w;
}

/// The terms of an object's external wrench, kept apart so that a user (or a plot) can
/// see what the hand feels and why. Each is `[force; moment about the centre of mass]`.
template <class Scalar>
struct ExternalWrench {
  Wrench<Scalar> gravity{Wrench<Scalar>::Zero()};    ///< [m g; 0]
  Wrench<Scalar> inertial{Wrench<Scalar>::Zero()};   ///< [-m a; -(I alpha + omega x I omega)]
  Wrench<Scalar> obstacles{Wrench<Scalar>::Zero()};  ///< sum of penalty_wrench()
  Status status{Status::InvalidInput};               ///< Ok, or InvalidInput (then every term is zero)

  /// The sum of the terms: the paper's (F_ext, N_ext), i.e. grip's w_ext.
  Wrench<Scalar> total() const { return gravity + inertial + obstacles; }
  /// The real (non-inertial) part, gravity + obstacles: what accelerates a free object.
  Wrench<Scalar> applied() const { return gravity + obstacles; }
};

/// Assembles the external wrench on `body` whose motion (centre-of-mass acceleration `a`,
/// angular acceleration `alpha`, world axes) the hand imposes, under gravity `g`, with
/// `count` obstacle contacts `obstacles[0..count)` of material `material`.
/// InvalidInput (all terms zero) for an invalid body, non-finite a/alpha/g, count < 0,
/// a null pointer with count > 0, or an invalid penalty contact.
template <class Scalar>
ExternalWrench<Scalar> external_wrench(const RigidBody<Scalar>& body, const Vector3<Scalar>& g,
                                       const Vector3<Scalar>& a, const Vector3<Scalar>& alpha,
                                       const PenaltyContact<Scalar>* obstacles, int count,
                                       const PenaltyMaterial<Scalar>& material) {
  ExternalWrench<Scalar> out;
  if (validate(body) != Status::Ok || !detail::all_in_range(g) || !detail::all_in_range(a) ||
      !detail::all_in_range(alpha) || count < 0 || (count > 0 && obstacles == nullptr))
    return out;
  Wrench<Scalar> sum = Wrench<Scalar>::Zero();
  for (int i = 0; i < count; ++i) {
    if (validate(obstacles[i], material) != Status::Ok) return out;
    sum += penalty_wrench(obstacles[i], material);
  }
  out.gravity = gravity_wrench(body.mass, g);
  out.inertial = inertial_wrench(body, a, alpha);
  out.obstacles = sum;
  out.status = validate(out.total());
  if (out.status != Status::Ok) out = ExternalWrench<Scalar>{};
  return out;
}

}  // namespace grip
