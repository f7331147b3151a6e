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
///
/// Where G has rank < 6 (one contact, two hard fingers, contacts on a line), a load with a part
/// outside G's range has a certificate in closed form: any y with G^T y = 0 (so every G_i^T y is
/// in K_i^*) and y.w_ext > 0 (range_certificate).

#include <algorithm>
#include <cmath>
#include <limits>

#include "grip/contact/contact_model.hpp"
#include "grip/contact/exact_cone.hpp"
#include "grip/core/scalar_traits.hpp"
#include "grip/core/types.hpp"
#include "grip/solve/detail/equilibrium_norm.hpp"
#include "grip/solve/solve_range_space.hpp"
#include "grip/solve/symmetric_solve.hpp"

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
/// `y_unit` receives y / |y|_L*. O(1) where y . w_ext <= 0 (no certificate), else one O(n) pass.
template <class GraspT>
bool is_infeasibility_certificate(const GraspT& grasp, const Wrench<typename GraspT::ScalarType>& w_ext,
                                  const Wrench<typename GraspT::ScalarType>& y, typename GraspT::ScalarType tol,
                                  Wrench<typename GraspT::ScalarType>& y_unit) {
  using S = typename GraspT::ScalarType;
  using M = typename GraspT::ModelType;
  using Cone = ExactConeT<M, S>;
  if (!(y.dot(w_ext) > S(0))) return false;
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

/// True when the part of `w_ext` outside G's range (see the file comment) certifies infeasibility
/// to `tol` as is_infeasibility_certificate tests it, with the certificate of dual norm 1 in
/// `y_unit`; false where G has rank 6 or w_ext lies in G's range to within round-off.
/// The method: M = D G W^-1 G^T D (D = T of the equilibrium norm, equilibrium_norm.hpp) is
/// factored by diagonally pivoted LDL^T up to its numerical rank r (pivots above
/// ScalarTraits::rank_tolerance times its largest diagonal entry). Each of the 6 - r columns of
/// the permuted M's null space, n = P (-L11^-T l, e), gives y = D n with G^T y = 0 to round-off;
/// their sum weighted by n.(D w_ext) has y.w_ext = sum (n.(D w_ext))^2 >= 0, which must stand
/// above its round-off (rho |y| |D w_ext|, rho = min(tol, 64 eps / tol)). O(n) and a 6x6
/// factorisation; no heap.
template <class GraspT>
bool range_certificate(const GraspT& grasp, const Wrench<typename GraspT::ScalarType>& w_ext,
                       typename GraspT::ScalarType tol, Wrench<typename GraspT::ScalarType>& y_unit) {
  using S = typename GraspT::ScalarType;
  const Wrench<S> d = EquilibriumNorm<S>::of(grasp).weights();
  const Matrix6<S> m = weighted_gram(grasp);
  S a[6][6], inv_d[6], largest(0);
  int perm[6] = {0, 1, 2, 3, 4, 5};
  for (int i = 0; i < 6; ++i) {
    for (int k = 0; k < 6; ++k) a[i][k] = d(i) * m(i, k) * d(k);
    largest = std::max(largest, a[i][i]);
  }
  const S floor = S(ScalarTraits<S>::rank_tolerance) * largest;
  if (!(floor > S(0)) || ldlt_factor<true>(a, inv_d, perm, floor)) return false;
  int r = 0;  // the numerical rank: the pivots taken before the factorisation stopped
  while (r < 6 && a[r][r] > floor) ++r;
  const Wrench<S> dw = d.cwiseProduct(w_ext);
  Wrench<S> y = Wrench<S>::Zero();
  for (int c = r; c < 6; ++c) {
    S z[6] = {};
    z[c] = S(1);
    for (int i = r - 1; i >= 0; --i) {  // L11^T u = -l_c, l_c = row c of L21
      S v = -a[c][i];
      for (int k = i + 1; k < r; ++k) v -= a[k][i] * z[k];
      z[i] = v;
    }
    Wrench<S> n;
    for (int i = 0; i < 6; ++i) n(perm[i]) = z[i];
    y += n.dot(dw) * n;
  }
  // y.(D w_ext) = sum (n.(D w_ext))^2 must stand above its round-off, as the interior-point
  // method's certificates must (interior_point.hpp): at least rho |y| |D w_ext|.
  const S rho = std::min(tol, S(64) * std::numeric_limits<S>::epsilon() / tol);
  if (!(y.dot(dw) >= rho * y.norm() * dw.norm())) return false;
  return is_infeasibility_certificate(grasp, w_ext, Wrench<S>(d.cwiseProduct(y)), tol, y_unit);
}

}  // namespace detail
}  // namespace grip
