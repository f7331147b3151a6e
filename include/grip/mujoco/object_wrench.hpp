#pragma once
/// \file
/// A MuJoCo body's external wrench for grip (docs/conventions.md: G x + w_ext = 0): gravity,
/// the inertial (d'Alembert) terms of its motion, the forces applied to it, and the contacts
/// with bodies that are not the hand, read from MuJoCo's state. Part of grip::mujoco.
///
/// State: what mj_forward() computed, or what mj_step() computed before it integrated (the
/// contacts, accelerations, poses and velocities of one time; qpos and qvel may be a step
/// later). World axes; moments about the body's centre of mass (xipos). No heap.

#include <mujoco/mujoco.h>

#include "grip/core/types.hpp"

namespace grip {
namespace mujoco {

/// The terms of a free body's external wrench (N; N m about its centre of mass, world axes).
/// total() is what grip's solvers take as w_ext.
template <class Scalar>
struct ObjectWrench {
  Wrench<Scalar> gravity{Wrench<Scalar>::Zero()};    ///< [m g; 0], m the body's mass, g the model's gravity.
  Wrench<Scalar> inertial{Wrench<Scalar>::Zero()};   ///< [-m a; -(I alpha + omega x I omega)].
  Wrench<Scalar> applied{Wrench<Scalar>::Zero()};    ///< xfrc_applied of the body.
  Wrench<Scalar> obstacles{Wrench<Scalar>::Zero()};  ///< Contacts with bodies outside the hand.
  /// The sum of the four terms.
  Wrench<Scalar> total() const { return gravity + inertial + applied + obstacles; }
};

/// The force and moment (N; N m, world axes) that contact `i` of `d` applies to the body that
/// holds its geom2 (mj_contactForce turned out of the contact frame: the normal frame[0..2]
/// points from geom1 to geom2). The body of geom1 feels the opposite. The moment is the
/// contact's torsional and rolling torques only (about the contact point), zero for condim 1
/// and 3.
inline void contact_force_on_geom2(const mjModel* m, const mjData* d, int i, Vector3<double>& force,
                                   Vector3<double>& torque) {
  mjtNum local[6];
  mj_contactForce(m, d, i, local);
  const mjtNum* f = d->contact[i].frame;
  force = Vector3<double>(f[0], f[1], f[2]) * local[0] + Vector3<double>(f[3], f[4], f[5]) * local[1] +
          Vector3<double>(f[6], f[7], f[8]) * local[2];
  torque = Vector3<double>(f[0], f[1], f[2]) * local[3] + Vector3<double>(f[3], f[4], f[5]) * local[4] +
           Vector3<double>(f[6], f[7], f[8]) * local[5];
}

/// The wrench (world axes, moment about `about`) that contact `i` applies to `body`, one of
/// its two geoms' bodies; zero when neither geom belongs to it.
inline Wrench<double> contact_wrench_on(const mjModel* m, const mjData* d, int i, int body,
                                        const Vector3<double>& about) {
  const mjContact& c = d->contact[i];
  const int b1 = m->geom_bodyid[c.geom1], b2 = m->geom_bodyid[c.geom2];
  Wrench<double> w = Wrench<double>::Zero();
  if (b1 != body && b2 != body) return w;
  Vector3<double> f, t;
  contact_force_on_geom2(m, d, i, f, t);
  if (b2 != body) {
    f = -f;
    t = -t;
  }
  const Vector3<double> r = Vector3<double>(c.pos[0], c.pos[1], c.pos[2]) - about;
  w.head<3>() = f;
  w.tail<3>() = r.cross(f) + t;
  return w;
}

/// The gravity, inertial and applied terms of `body`'s wrench (its `obstacles` term zero: the
/// caller adds the contacts it classes as obstacles with contact_wrench_on()). The body must
/// have a free joint (its only joint) whose dofs start at `dof`: the centre of mass's
/// acceleration is a = a_o + alpha x r + omega x (omega x r), from the joint's qacc (the body
/// origin's acceleration, world; the angular acceleration, body axes), r = xipos - xpos; the
/// inertia is body_inertia in the inertial frame ximat. The result is finite whenever the
/// state is.
template <class Scalar>
ObjectWrench<Scalar> free_body_wrench(const mjModel* m, const mjData* d, int body, int dof) {
  using V = Vector3<double>;
  using M = Eigen::Matrix<double, 3, 3, Eigen::RowMajor>;
  const double mass = m->body_mass[body];
  const V g(m->opt.gravity[0], m->opt.gravity[1], m->opt.gravity[2]);
  const Eigen::Map<const M> R(d->xmat + 9 * body);    // body frame -> world
  const Eigen::Map<const M> Ri(d->ximat + 9 * body);  // inertial frame -> world
  const V r = V(d->xipos[3 * body], d->xipos[3 * body + 1], d->xipos[3 * body + 2]) -
              V(d->xpos[3 * body], d->xpos[3 * body + 1], d->xpos[3 * body + 2]);
  const V omega = V(d->cvel[6 * body], d->cvel[6 * body + 1], d->cvel[6 * body + 2]);  // world axes
  const V a_origin(d->qacc[dof], d->qacc[dof + 1], d->qacc[dof + 2]);
  const V alpha = R * V(d->qacc[dof + 3], d->qacc[dof + 4], d->qacc[dof + 5]);
  const V a = a_origin + alpha.cross(r) + omega.cross(omega.cross(r));
  const M I = Ri *
              V(m->body_inertia[3 * body], m->body_inertia[3 * body + 1], m->body_inertia[3 * body + 2]).asDiagonal() *
              Ri.transpose();
  Wrench<double> grav, inert, applied;
  grav << mass * g, V::Zero();
  inert << -mass * a, -(I * alpha + omega.cross(I * omega));
  for (int k = 0; k < 6; ++k) applied(k) = d->xfrc_applied[6 * body + k];
  ObjectWrench<Scalar> w;
  w.gravity = grav.cast<Scalar>();
  w.inertial = inert.cast<Scalar>();
  w.applied = applied.cast<Scalar>();
  return w;
}

}  // namespace mujoco
}  // namespace grip
