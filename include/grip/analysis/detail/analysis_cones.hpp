#pragma once
/// \file
/// The exact friction cones as the conic analyses see them (internal to conic_dual.hpp,
/// force_closure.hpp and max_wrench.hpp): each contact's cone K_i in its unknown space
/// (dim = 1, 3 or 4), its axis e_i, the margin of a force inside it, and the linear map that
/// takes its dual cone K_i^* onto the standard second-order cone; the units' balancing of G;
/// contacts cast to the scalar the analyses compute in.
/// - HardFinger: the Coulomb cone {|f_t| <= mu f_n} (eq. 4-5); mu = 0 leaves the ray f = f_n a;
/// - SoftFinger: the elliptic cone {|f_t|^2 / mu^2 + m^2 / mu_t^2 <= f_n^2} (mu_t in m);
///   a zero coefficient removes that direction;
/// - FrictionlessPoint: {x >= 0}.
/// The dual cone is K_i^* = {v : v_n >= sqrt(sum mu_k^2 v_k^2)} (the Coulomb cone with 1/mu).

#include <algorithm>
#include <cmath>
#include <type_traits>

#include <Eigen/Core>

#include "grip/contact/cone_support.hpp"
#include "grip/contact/contact.hpp"
#include "grip/core/types.hpp"

namespace grip {
namespace detail {

/// The exact cone of one contact: its axis, quadratic form and span.
template <class S, int D>
struct ExactConeData {
  Eigen::Matrix<S, D, 1> axis;  ///< e_i, unit.
  Eigen::Matrix<S, D, D> quad;  ///< A: v^T A v = v_n^2 - sum mu_k^2 v_k^2.
  Eigen::Matrix<S, D, D> span;  ///< orthogonal projector onto the linear span of K_i.
  bool halfspace{false};        ///< K_i is the ray along axis: K_i^* = {axis . v >= 0}.
};

/// The axis e_i of contact c's exact cone: the unit normal (padded with 0 for a soft finger's
/// torsion), or 1 for a frictionless point.
template <class Model, class S>
Eigen::Matrix<S, Model::dim, 1> cone_axis(const Contact<S>& c) {
  Eigen::Matrix<S, Model::dim, 1> e;
  if constexpr (Model::dim == 1) {
    e.setConstant(S(1));
  } else {
    e.setZero();
    e.template head<3>() = c.normal / c.normal.norm();
  }
  return e;
}

/// The orthogonal projector onto the linear span of contact c's exact cone: the identity,
/// less the directions whose friction coefficient is zero.
template <class Model, class S>
Eigen::Matrix<S, Model::dim, Model::dim> cone_span(const Contact<S>& c) {
  using Span = Eigen::Matrix<S, Model::dim, Model::dim>;
  Span p = Span::Identity();
  if constexpr (Model::dim > 1) {
    if (!(c.friction > S(0))) {
      const Vector3<S> a = c.normal / c.normal.norm();
      p.template topLeftCorner<3, 3>() = a * a.transpose();
    }
    if constexpr (Model::dim == 4) p(3, 3) = c.torsional_friction > S(0) ? S(1) : S(0);
  }
  return p;
}

/// True when cone_span<Model>(c) is the identity (every friction coefficient > 0).
template <class Model, class S>
bool full_span(const Contact<S>& c) {
  if constexpr (Model::dim == 1)
    return true;
  else if constexpr (Model::dim == 4)
    return c.friction > S(0) && c.torsional_friction > S(0);
  else
    return c.friction > S(0);
}

/// The exact cone of contact c for contact model Model.
template <class Model, class S>
ExactConeData<S, Model::dim> exact_cone(const Contact<S>& c) {
  constexpr int D = Model::dim;
  ExactConeData<S, D> k;
  k.axis = cone_axis<Model>(c);
  k.span = cone_span<Model>(c);
  if constexpr (D == 1) {
    k.quad.setConstant(S(1));
    k.halfspace = true;
  } else {
    const Vector3<S> a = k.axis.template head<3>();
    const Matrix3<S> aa = a * a.transpose();
    k.quad.setZero();
    k.quad.template topLeftCorner<3, 3>() = aa - (c.friction * c.friction) * (Matrix3<S>::Identity() - aa);
    bool ray = !(c.friction > S(0));
    if constexpr (D == 4) {
      k.quad(3, 3) = -(c.torsional_friction * c.torsional_friction);
      ray = ray && !(c.torsional_friction > S(0));
    }
    k.halfspace = ray;
  }
  return k;
}

/// The largest t with x - t e in K (e the cone's axis), for a force x of contact c: x_n - |x_t|/mu
/// (hard finger), x_n - sqrt(|x_t|^2/mu^2 + m^2/mu_t^2) (soft finger), x (frictionless). Terms
/// with a zero coefficient are left out (the span projection has removed those components).
template <class Model, class S>
S normal_margin(const Contact<S>& c, const Eigen::Matrix<S, Model::dim, 1>& x) {
  if constexpr (Model::dim == 1) {
    return x(0);
  } else {
    const Vector3<S> a = c.normal / c.normal.norm();
    const S xn = a.dot(x.template head<3>());
    S q(0);
    if (c.friction > S(0)) q += (x.template head<3>() - xn * a).squaredNorm() / (c.friction * c.friction);
    if constexpr (Model::dim == 4)
      if (c.torsional_friction > S(0)) q += x(3) * x(3) / (c.torsional_friction * c.torsional_friction);
    return xn - std::sqrt(q);
  }
}

/// The linear map L_i of contact c that takes its dual cone onto the standard second-order
/// cone: K_i^* = {v : L_i v in Q}, rows a, mu t1, mu t2 (and mu_t for the torsion of a soft
/// finger), with (t1, t2) the TangentBasis of a; so v^T A v = (L v)^T J (L v). A zero
/// coefficient leaves a zero row (that component is then free in K_i^*). Its transpose
/// takes Q onto K_i: x = L_i^T z.
template <class Model, class S>
Eigen::Matrix<S, Model::dim, Model::dim> cone_map(const Contact<S>& c) {
  constexpr int D = Model::dim;
  Eigen::Matrix<S, D, D> m = Eigen::Matrix<S, D, D>::Zero();
  if constexpr (D == 1) {
    m(0, 0) = S(1);
  } else {
    const Vector3<S> a = c.normal / c.normal.norm();
    const TangentBasis<S> t = TangentBasis<S>::from_normal(a);
    m.template block<1, 3>(0, 0) = a.transpose();
    m.template block<1, 3>(1, 0) = c.friction * t.t1.transpose();
    m.template block<1, 3>(2, 0) = c.friction * t.t2.transpose();
    if constexpr (D == 4) m(3, 3) = c.torsional_friction;
  }
  return m;
}

/// The torque scale used internally: the largest |r_i|, or 1 when all are 0.
template <class GraspT>
typename GraspT::ScalarType internal_torque_scale(const GraspT& grasp) {
  using S = typename GraspT::ScalarType;
  S rho(0);
  for (int i = 0; i < grasp.size(); ++i) rho = std::max(rho, grasp.contact(i).position.norm());
  return rho > S(0) ? rho : S(1);
}

/// diag(1, 1, 1, 1/rho x 3).
template <class S>
Wrench<S> row_scaling(S rho) {
  Wrench<S> d;
  d << S(1), S(1), S(1), S(1) / rho, S(1) / rho, S(1) / rho;
  return d;
}

/// Contact c in the scalar To, field by field (exact when To is at least as wide as S, as
/// ScalarTraits<S>::Wide is).
template <class To, class S>
Contact<To> cast_contact(const Contact<S>& c) {
  Contact<To> w;
  w.position = c.position.template cast<To>();
  w.normal = c.normal.template cast<To>();
  w.friction = To(c.friction);
  w.torsional_friction = To(c.torsional_friction);
  w.squeeze = To(c.squeeze);
  w.weight = To(c.weight);
  w.max_normal_force = To(c.max_normal_force);
  return w;
}

/// Contact c in the scalar To: c itself (a reference, no copy) when To is its scalar, else
/// cast_contact<To>(c) (a value).
template <class To, class S>
decltype(auto) wide_contact(const Contact<S>& c) {
  if constexpr (std::is_same<To, S>::value)
    return (c);
  else
    return cast_contact<To>(c);
}

}  // namespace detail
}  // namespace grip
