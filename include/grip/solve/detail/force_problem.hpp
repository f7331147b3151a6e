#pragma once
/// \file
/// A grasp's force problem as the interior-point method sees it (namespace grip::detail): each
/// contact's exact cone mapped onto the standard second-order cone, the data normalised, and the
/// way back to forces, multipliers and certificates.
///
/// Cone coordinates u_i of a contact (its unknowns x_i = M_i u_i, x_i in K_i iff u_i in Q):
/// - hard finger: x = u_0 a + mu (u_1 t_1 + u_2 t_2) (t_1, t_2 the TangentBasis of the normal a);
/// - soft finger: the same force, and the torsional moment m = mu_t u_3;
/// - frictionless point: x = u_0.
/// So u_0 is the normal force, M_i^T M_i = diag(1, mu^2, mu^2, mu_t^2) and M_i^T t_i = s_i e. A zero
/// coefficient leaves its coordinates free in Q with no effect on x (the cone is then the ray or
/// the hard finger's cone, as it should be).
///
/// Normalised: forces by F0 = max(|w_ext|_L, max_i s_i) (1 if both are 0), weights by
/// W0 = max_i w_i, moments by the lever length L (EquilibriumNorm, T = diag(1, 1, 1, 1/L, 1/L, 1/L)):
///     P_i = (w_i / W0) M_i^T M_i,   q_i = -(w_i s_i / (W0 F0)) e,   A_i = T G_i M_i,   b = -T w_ext / F0,
/// the bound on u_i0 is c_i / F0. Then F2(x) = W0 F0^2 (1/2 u^T P u + q^T u) + const and
/// G x + w_ext = 0 iff A u = b. The soft form (the least-residual problem) minimises
/// 1/2 |A u - b|^2 + delta_n (1/2 u^T P u + q^T u), i.e. 1/2 |G x + w_ext|_L^2 + delta F2(x) over
/// F0^2 with delta_n = delta W0.

#include <algorithm>
#include <cmath>
#include <limits>
#include <type_traits>

#include <Eigen/Core>

#include "grip/contact/cone_support.hpp"
#include "grip/contact/contact.hpp"
#include "grip/contact/contact_model.hpp"
#include "grip/core/types.hpp"
#include "grip/solve/detail/conic_lanes.hpp"
#include "grip/solve/detail/equilibrium_norm.hpp"

namespace grip {
namespace detail {

/// The map M_i from contact c's cone coordinates to its unknowns (see the file comment).
template <class Model, class S>
Eigen::Matrix<S, Model::dim, Model::dim> cone_coordinates(const Contact<S>& c) {
  constexpr int D = Model::dim;
  Eigen::Matrix<S, D, D> m = Eigen::Matrix<S, D, D>::Zero();
  if constexpr (D == 1) {
    m(0, 0) = S(1);
  } else {
    const TangentBasis<S> t = TangentBasis<S>::from_normal(c.normal);
    m.col(0).template head<3>() = c.normal;
    m.col(1).template head<3>() = c.friction * t.t1;
    m.col(2).template head<3>() = c.friction * t.t2;
    if constexpr (D == 4) m(3, 3) = c.torsional_friction;
  }
  return m;
}

/// The scales of a grasp's normalised force problem, and the maps between it and the grasp.
template <class GraspT>
struct ForceProblem {
  using S = typename GraspT::ScalarType;
  using M = typename GraspT::ModelType;
  static constexpr int D = GraspT::dim;
  using Lanes = ConicLanes<S, D, GraspT::capacity>;

  EquilibriumNorm<S> norm;  ///< the lever length L of the residuals' units
  S force{1};               ///< F0 (N)
  S weight{1};              ///< W0
  Wrench<S> b;              ///< -T w_ext / F0
  /// The load's size in the problem's units, |b|, clamped to [sqrt(eps), 1]: at most 1 (F0 is at
  /// least the load), below 1 when the squeezing forces outweigh the load.
  S load_scale{1};
  S q_norm{0};  ///< |q|
  /// Set by fill: every contact's q_i - A_i^T b lies in Q, so u = 0 minimises the soft form
  /// (its gradient there is q - A^T b, and u = 0 is optimal over the cones iff that lies in
  /// their dual, Q itself). Meaningful for the soft form only.
  bool origin_optimal{false};

  /// The scales of `grasp` and `w_ext` (norm, force, weight) and b, without the contacts' data.
  void scale(const GraspT& grasp, const Wrench<S>& w_ext) {
    norm = EquilibriumNorm<S>::of(grasp);
    S f0 = norm(w_ext), w0(0);
    for (int i = 0; i < grasp.size(); ++i) {
      f0 = std::max(f0, grasp.contact(i).squeeze);
      w0 = std::max(w0, grasp.contact(i).weight);
    }
    force = f0 > S(0) && std::isfinite(f0) ? f0 : S(1);
    weight = w0 > S(0) ? w0 : S(1);
    b = -norm.to_units(w_ext) / force;
    load_scale = std::min(S(1), std::max(b.norm(), std::sqrt(std::numeric_limits<S>::epsilon())));
  }

  /// The problem of `grasp` and `w_ext` written into `k` (every contact set), the scales and
  /// origin_optimal into this; the soft form's weight `delta_n` multiplies P and q (1 for the
  /// hard form). Each contact's bound on its normal force is its max_normal_force.
  void fill(const GraspT& grasp, const Wrench<S>& w_ext, Lanes& k, S delta_n) {
    scale(grasp, w_ext);
    S qq(0);
    origin_optimal = true;
    for (int i = 0; i < grasp.size(); ++i) {
      const auto& c = grasp.contact(i);
      const Eigen::Matrix<S, D, D> m = cone_coordinates<M>(c);
      Eigen::Matrix<S, 6, D> a;
      for (int j = 0; j < D; ++j) {
        const typename GraspT::ContactVector col = m.col(j);
        a.col(j) = norm.to_units(M::wrench(c, col));
      }
      const S w = c.weight / weight;
      Eigen::Matrix<S, D, 1> p, q = Eigen::Matrix<S, D, 1>::Zero(), metric;
      for (int j = 0; j < D; ++j) {
        metric(j) = m.col(j).squaredNorm();
        p(j) = delta_n * w * metric(j);
      }
      q(0) = -delta_n * w * c.squeeze / force;
      qq += q(0) * q(0);
      const Eigen::Matrix<S, D, 1> g = q - a.transpose() * b;  // the soft form's gradient at u = 0
      if constexpr (D == 1) {
        origin_optimal = origin_optimal && g(0) >= S(0);
      } else {
        origin_optimal = origin_optimal && g(0) >= g.template tail<D - 1>().norm();
      }
      const S bound = c.max_normal_force;
      k.set(i, a, p, q, bound < std::numeric_limits<S>::infinity() ? bound / force : bound, metric);
    }
    q_norm = std::sqrt(qq);
  }

  /// The unknowns x_i = F0 M_i u_i / tau of the iterate in `k`.
  template <class Vec>
  void forces(const GraspT& grasp, const Lanes& k, S tau, Vec& x) const {
    const S f = force / tau;
    for (int i = 0; i < grasp.size(); ++i)
      x.template segment<D>(i * D) = f * (cone_coordinates<M>(grasp.contact(i)) * k.u(i));
  }
  /// The multipliers lambda (W (x - t) = G^T lambda + the cones' normal part) of the rows' y.
  Wrench<S> multipliers(const Wrench<S>& y, S tau) const { return -norm.to_units(y) * (weight * force / tau); }
  /// F2's constant in the problem's units, sum_i w_i s_i^2 / (2 W0 F0^2) (left out of q^T u).
  S cost_offset(const GraspT& grasp) const {
    S c(0);
    for (int i = 0; i < grasp.size(); ++i) {
      const auto& ci = grasp.contact(i);
      const S s = ci.squeeze / force;
      c += ci.weight / weight * s * s;
    }
    return S(0.5) * c;
  }
  /// max_i s_i / F0: the squeezing forces' part of the residuals' scale, in the problem's units.
  S squeeze_scale(const GraspT& grasp) const {
    S s(0);
    for (int i = 0; i < grasp.size(); ++i) s = std::max(s, grasp.contact(i).squeeze);
    return s / force;
  }
  /// A cost of the problem's units in F2's: W0 F0^2 cost.
  S in_f2_units(S cost) const { return weight * force * force * cost; }
  /// The certificate T y / |T y|_L* (= T y / |y|) of the rows' y.
  Wrench<S> certificate(const Wrench<S>& y) const { return norm.to_units(y) / y.norm(); }
};

}  // namespace detail
}  // namespace grip
