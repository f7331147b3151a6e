#pragma once
/// \file
/// The exact friction cones as the conic analyses see them (internal to force_closure.hpp,
/// max_wrench.hpp and detail/conic_analysis.hpp): each contact's cone K_i in its unknown space
/// (dim = 1, 3 or 4), its axis e_i, its linear span, and the margin of a force inside it;
/// contacts cast to the scalar the analyses compute in.
/// - HardFinger: the Coulomb cone {|f_t| <= mu f_n} (eq. 4-5); mu = 0 leaves the ray f = f_n a;
/// - SoftFinger: the elliptic cone {|f_t|^2 / mu^2 + m^2 / mu_t^2 <= f_n^2} (mu_t in m);
///   a zero coefficient removes that direction;
/// - FrictionlessPoint: {x >= 0}.

#include <cmath>
#include <type_traits>

#include <Eigen/Core>

#include "grip/contact/contact.hpp"
#include "grip/core/types.hpp"

namespace grip {
namespace detail {

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
