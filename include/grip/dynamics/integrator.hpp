#pragma once
/// \file
/// Free-phase Newton-Euler integration of a rigid body (no stable grasp holds it).

#include <cmath>

#include <Eigen/Geometry>

#include "grip/core/status.hpp"
#include "grip/core/types.hpp"
#include "grip/dynamics/rigid_body.hpp"

namespace grip {

namespace detail {

/// Exact flow of the free-body sub-Hamiltonian L_k^2 / (2 I_k) for time h: the body turns
/// about its principal axis k at the constant rate L_k / I_k; in body axes the angular
/// momentum turns the other way (Euler's equation dL/dt = L x omega).
template <class Scalar>
void rotate_about_principal_axis(int k, Scalar h, const Vector3<Scalar>& moments, Vector3<Scalar>& l_body,
                                 Eigen::Quaternion<Scalar>& q) {
  const Scalar theta = h * l_body(k) / moments(k);
  const Scalar c = std::cos(theta), s = std::sin(theta);
  const int i = (k + 1) % 3, j = (k + 2) % 3;
  // l <- Rot_k(-theta) l
  const Scalar li = l_body(i), lj = l_body(j);
  l_body(i) = c * li + s * lj;
  l_body(j) = -s * li + c * lj;
  // q <- q * Rot_k(theta)
  const Scalar ch = std::cos(theta / Scalar(2)), sh = std::sin(theta / Scalar(2));
  Eigen::Quaternion<Scalar> r(ch, Scalar(0), Scalar(0), Scalar(0));
  r.vec()(k) = sh;
  q = q * r;
}

}  // namespace detail

/// Advances a free body by one step `dt` (s) under a real applied wrench `w` (N; N m about
/// the centre of mass, world axes; NOT including inertial terms), held constant over the step.
///
/// Integrator (a symmetric splitting, second order, symplectic for conservative loads):
/// 1. half kick:  v += dt/2 F/m;  L += dt/2 tau   (L = world angular momentum)
/// 2. drift:      x += dt v; the torque-free rotation for dt by the splitting of Dullweber,
///    Leimkuhler and McLachlan (1997): the free-body energy is a sum over principal axes of
///    L_k^2 / (2 I_k), each flowing exactly (a rotation about axis k), composed as
///    axis 0 (dt/2), axis 1 (dt/2), axis 2 (dt), axis 1 (dt/2), axis 0 (dt/2)
/// 3. half kick:  v += dt/2 F/m;  L += dt/2 tau;  omega = I_world^-1 L.
///
/// Properties: exact for a constant force (free fall: x = x0 + v0 t + g t^2 / 2 at every
/// step); torque-free, |L| and the world angular momentum are conserved to round-off and
/// the kinetic energy has a bounded O(dt^2) error with no drift (it cannot grow over time
/// as explicit Euler's does); the quaternion is renormalised every step.
///
/// InvalidInput (body unchanged) for an invalid body, a non-finite wrench or dt <= 0 / NaN.
template <class Scalar>
Status step_free(RigidBody<Scalar>& body, const Wrench<Scalar>& w, Scalar dt) {
  if (validate(body) != Status::Ok || validate(w) != Status::Ok || !detail::in_range(dt) || !(dt > Scalar(0)))
    return Status::InvalidInput;
  const Scalar half = Scalar(0.5) * dt;
  const Vector3<Scalar> accel = w.template head<3>() / body.mass;
  const Vector3<Scalar> tau = w.template tail<3>();
  const Vector3<Scalar>& moments = body.principal_inertia;

  RigidBody<Scalar> b = body;
  b.linear_velocity += half * accel;
  Vector3<Scalar> l_world = b.angular_momentum() + half * tau;

  b.position += dt * b.linear_velocity;
  Vector3<Scalar> l_body = b.orientation.conjugate() * l_world;
  Eigen::Quaternion<Scalar> q = b.orientation;
  detail::rotate_about_principal_axis(0, half, moments, l_body, q);
  detail::rotate_about_principal_axis(1, half, moments, l_body, q);
  detail::rotate_about_principal_axis(2, dt, moments, l_body, q);
  detail::rotate_about_principal_axis(1, half, moments, l_body, q);
  detail::rotate_about_principal_axis(0, half, moments, l_body, q);
  q.normalize();
  b.orientation = q;

  b.linear_velocity += half * accel;
  l_body += half * (q.conjugate() * tau);
  b.angular_velocity = q * l_body.cwiseQuotient(moments);
  if (validate(b) != Status::Ok) return Status::InvalidInput;
  body = b;
  return Status::Ok;
}

}  // namespace grip
