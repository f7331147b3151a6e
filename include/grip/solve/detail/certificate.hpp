#pragma once
/// \file
/// The test of an infeasibility certificate (namespace grip::detail): a wrench direction y that
/// proves that no forces inside the contacts' cones (and below their bounds) balance w_ext.
///
/// For x_i in the exact cone K_i, (G_i^T y) . x_i >= 0 when G_i^T y lies in the dual cone K_i^*;
/// then y.(G x + w_ext) >= y.w_ext > 0 for every such x. A contact with a bound c_i on its normal
/// force needs less: over the truncated cone, (G_i^T y) . x_i >= c_i min(0, phi_i) with
/// phi_i = min over x in K_i with f_n(x) = 1 of (G_i^T y) . x (v_n - mu |v_t| for a hard finger,
/// v_n - sqrt(mu^2 |v_t|^2 + mu_t^2 m^2) for a soft finger, v for a frictionless point, v = G_i^T y).
/// So y is a certificate to tolerance tol when, with |y|_L* = 1 (equilibrium_norm.hpp),
///     y.w_ext - sum_i c_i max(0, -phi_i)  >  0      (bounded contacts)
///     dist(G_i^T y, K_i^*) <= tol (y.w_ext) / |w_ext|_L   (the others),
/// which rules out balancing forces of total magnitude below about |w_ext|_L / tol.

#include <cmath>
#include <limits>

#include "grip/contact/contact_model.hpp"
#include "grip/contact/exact_cone.hpp"
#include "grip/core/types.hpp"
#include "grip/solve/detail/equilibrium_norm.hpp"

namespace grip {
namespace detail {

/// phi_i of a contact of model M for v = G_i^T y (see the file comment): the least value of v.x
/// over the contact's cone at unit normal force.
template <class Model, class S, class V>
S unit_normal_minimum(const Contact<S>& c, const V& v) {
  if constexpr (Model::dim == 1) {
    return v(0);
  } else {
    const Vector3<S> f = v.template head<3>();
    const S vn = f.dot(c.normal);
    const S vt2 = (f - vn * c.normal).squaredNorm();
    S q = c.friction * c.friction * vt2;
    if constexpr (Model::dim == 4) q += c.torsional_friction * c.torsional_friction * v(3) * v(3);
    return vn - std::sqrt(q);
  }
}

/// True when `y` (any nonzero scale) certifies infeasibility to `tol` (see the file comment);
/// `y_unit` receives y / |y|_L*.
template <class GraspT>
bool is_infeasibility_certificate(const GraspT& grasp, const Wrench<typename GraspT::ScalarType>& w_ext,
                                  const Wrench<typename GraspT::ScalarType>& y, typename GraspT::ScalarType tol,
                                  Wrench<typename GraspT::ScalarType>& y_unit) {
  using S = typename GraspT::ScalarType;
  using M = typename GraspT::ModelType;
  using Cone = ExactConeT<M, S>;
  const EquilibriumNorm<S> norm = EquilibriumNorm<S>::of(grasp);
  const S yn = norm.dual(y);
  if (!(yn > S(0)) || !std::isfinite(yn)) return false;
  y_unit = y / yn;
  const S yw = y_unit.dot(w_ext);
  const S wn = norm(w_ext);
  if (!(yw > S(0)) || !(wn > S(0))) return false;
  const S slack = tol * yw / wn;
  S deficit(0);
  for (int i = 0; i < grasp.size(); ++i) {
    const auto& c = grasp.contact(i);
    const typename GraspT::ContactVector v = M::wrench_transpose(c, y_unit);
    if (c.max_normal_force < std::numeric_limits<S>::infinity()) {
      const S phi = unit_normal_minimum<M>(c, v);
      if (phi < S(0)) deficit += c.max_normal_force * -phi;
    } else {
      const auto dual = Cone::from_contact(c).dual();
      if (!((v - dual.project(v)).norm() <= slack)) return false;
    }
  }
  return deficit < yw;
}

}  // namespace detail
}  // namespace grip
