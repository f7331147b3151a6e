#pragma once
/// \file
/// Grasp quality measures from the singular values of the grasp matrix G.
///
/// G maps contact unknowns to wrenches; the set {G x : |x|_2 <= 1} is an ellipsoid in
/// wrench space (the "wrench ellipsoid" or manipulability ellipsoid of the grasp) whose
/// semi-axes are the singular values sigma_1 >= ... >= sigma_6 of G.
/// - Smallest singular value sigma_6 (Li & Sastry, "Task-oriented optimal grasping by
///   multifingered robot hands", IEEE J. Robot. Autom. 4(1), 1988): the smallest wrench
///   produced by a unit contact force vector; 0 when some wrench direction cannot be
///   produced at all. Survey: Roa & Suarez, "Grasp quality measures: review and
///   performance", Autonomous Robots 38(1), 2015, section 4.1 ("Q_MSV").
/// - Volume of the wrench ellipsoid: V_6 * prod sigma_k with V_6 = pi^3 / 6 the volume of
///   the unit ball of R^6 (Li & Sastry 1988; Roa & Suarez 2015 "Q_VEW", who drop V_6).
///   Units mix N and N m unless a torque scale is given (below).
/// - Isotropy index sigma_6 / sigma_1 in [0, 1] (Kim, Oh et al. 2001; Roa & Suarez
///   2015 "Q_IIG"): 1 when every wrench direction is equally easy.
///
/// Lever length L (m): the moment rows of G are divided by L, so moments are compared
/// with forces as "force at lever arm L" (L = 1 m leaves G as is). The same convention
/// is used by the Ferrari-Canny epsilon (see epsilon.hpp).
///
/// The singular values come from a fixed-size 6x6 self-adjoint eigen-decomposition of
/// G G^T (no heap), accumulated contact by contact in closed form.

#include <cmath>

#include "grip/contact/contact_model.hpp"
#include "grip/core/scalar_traits.hpp"
#include "grip/core/status.hpp"
#include "grip/core/types.hpp"
#include "grip/grasp/grasp.hpp"
#include "grip/solve/symmetric_solve.hpp"

namespace grip {

/// Singular-value quality measures of a grasp.
///
/// Ok: computed. InvalidInput: incomplete grasp or lever_length not finite and > 0; every
/// number is 0 then. A rank-deficient G is not an error: sigma_min (and volume, isotropy)
/// are then 0 up to round-off.
template <class Scalar>
struct GraspQuality {
  Wrench<Scalar> singular_values{Wrench<Scalar>::Zero()};  ///< sigma_1 >= ... >= sigma_6 >= 0.
  Scalar sigma_min{0};                                     ///< sigma_6 (N per N, with the torque scale).
  Scalar sigma_max{0};                                     ///< sigma_1.
  Scalar volume{0};                     ///< pi^3 / 6 * prod sigma_k: the 6-D volume of {G x : |x| <= 1}.
  Scalar isotropy{0};                   ///< sigma_6 / sigma_1 in [0, 1] (0 if G = 0).
  Status status{Status::InvalidInput};  ///< Ok or InvalidInput.
};

/// The volume of the unit ball in R^6, pi^3 / 6.
template <class Scalar>
constexpr Scalar unit_ball_volume_6() {
  return Scalar(3.14159265358979323846L * 3.14159265358979323846L * 3.14159265358979323846L / 6.0L);
}

/// G G^T with G's moment rows divided by L: D (G G^T) D, D = diag(1, 1, 1, 1/L x 3).
template <class GraspT>
Matrix6<typename GraspT::ScalarType> scaled_gram(const GraspT& grasp, typename GraspT::ScalarType lever) {
  using S = typename GraspT::ScalarType;
  GramAccumulator<S> acc;
  for (int i = 0; i < grasp.size(); ++i) GraspT::ModelType::accumulate(acc, grasp.contact(i), S(1));
  Wrench<S> d;
  d << S(1), S(1), S(1), S(1) / lever, S(1) / lever, S(1) / lever;
  return d.asDiagonal() * acc.matrix() * d.asDiagonal();
}

/// Singular values of G (moment rows scaled by 1/lever_length) and the measures derived
/// from them. O(n) plus one 6x6 eigen-decomposition. No heap.
template <class GraspT>
GraspQuality<typename GraspT::ScalarType> grasp_quality(
    const GraspT& grasp, typename GraspT::ScalarType lever_length = typename GraspT::ScalarType(1)) {
  using S = typename GraspT::ScalarType;
  GraspQuality<S> q;
  if (!grasp.complete() || !std::isfinite(lever_length) || !(lever_length > S(0))) return q;
  const Matrix6<S> m = scaled_gram(grasp, lever_length);
  if (!m.allFinite()) return q;
  Wrench<S> evs;
  Matrix6<S> vecs;
  detail::symmetric_eigen_6x6_sorted(m, evs, vecs);  // grip's Jacobi: cheap to compile, no heap
  // eigenvalues ascending; singular values descending.
  for (int k = 0; k < 6; ++k) {
    const S ev = evs(5 - k);
    q.singular_values(k) = ev > S(0) ? std::sqrt(ev) : S(0);
  }
  q.sigma_max = q.singular_values(0);
  q.sigma_min = q.singular_values(5);
  q.volume = unit_ball_volume_6<S>() * q.singular_values.prod();
  q.isotropy = q.sigma_max > S(0) ? q.sigma_min / q.sigma_max : S(0);
  q.status = Status::Ok;
  return q;
}

}  // namespace grip
