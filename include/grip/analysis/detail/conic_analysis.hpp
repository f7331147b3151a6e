#pragma once
/// \file
/// The conic analyses (force_closure.hpp, max_wrench.hpp) as problems of the interior-point method
/// of solve_constrained (solve/detail/interior_point.hpp, namespace grip::detail): their rows, the
/// way back to forces and wrench directions, and the bounds that any row multipliers give.
///
/// Each contact's exact cone in its cone coordinates (solve/detail/force_problem.hpp): x_i = M_i u_i,
/// x_i in K_i iff u_i in Q, with M_i^T e_i = e = (1, 0, ...) for the cone's axis e_i (the unit normal,
/// padded with 0 for a soft finger's torsion, or 1) and, as M_i Q = K_i, v in K_i^* iff M_i^T v in Q.
/// The rows are those of G in the units of EquilibriumNorm (T = diag(1, 1, 1, 1/L, 1/L, 1/L), L the
/// longest lever arm); the objective has P = 0.
///
/// Margin problem (force closure): max t s.t. G x = 0, x_i - t e_i in K_i, sum_i e_i . x_i = n (the
/// forces scaled by n: normal forces of 1 on average). With s_i = x_i - t e_i = M_i u_i, t is
/// t = 1 - sum_i e_i . s_i / n, and the problem is
///     min sum_i (e / n) . u_i   s.t.   sum_i T (G_i - g_e e_i^T / n) M_i u_i = -T g_e,   u_i in Q,
/// g_e = sum_i G_i e_i, whose optimum is 1 - t*: the margin of force_closure (normal forces summing
/// to 1) is t* / n.
///
/// Largest resistible wrench along d: min sum_i e_i . x_i s.t. G x = -d / |T d|, x_i in K_i, i.e.
///     min sum_i e . u_i   s.t.   sum_i T G_i M_i u_i = -T d / |T d|,   u_i in Q,
/// with optimum c*: the budget B balances at most s* = B / (|T d| c*) times d (x scaled by
/// B / c*), and no multiple of d when the problem is infeasible.
///
/// Bounds from any wrench direction u (e.g. T y of the rows' multipliers y, T as in T G): with
/// zeta(u) = max_i (|v_i1| - v_i0), v_i = M_i^T G_i^T u, the least zeta with G_i^T u + zeta e_i in
/// K_i^* for every contact, and x feasible for either problem,
///     0 <= sum_i (G_i^T u + zeta e_i) . (x_i - t e_i) = u . G x + zeta sum_i e_i . x_i - t (g_e . u + n zeta).
/// Margin (G x = 0, sum e . x = 1): t (n zeta + g_e . u) <= zeta, so t <= zeta / (n zeta + g_e . u)
/// when the denominator is positive. Wrench (t = 0, G x = -s d, sum e . x <= B): s (d . u) <= zeta B,
/// so s <= zeta B / (d . u) when d . u > 0 (and s <= 0 when also zeta <= 0).

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <limits>

#include <Eigen/Core>

#include "grip/analysis/detail/analysis_cones.hpp"
#include "grip/contact/contact.hpp"
#include "grip/core/scalar_traits.hpp"
#include "grip/core/types.hpp"
#include "grip/solve/detail/conic_lanes.hpp"
#include "grip/solve/detail/equilibrium_norm.hpp"
#include "grip/solve/detail/force_problem.hpp"
#include "grip/solve/detail/interior_point.hpp"

namespace grip {
namespace detail {

/// A grasp's conic analyses in the scalar W = ScalarTraits<S>::Wide (see the file comment): the
/// norm's scale, each contact's cone coordinates, and the problems written into ConicLanes.
template <class GraspT>
class ConicAnalysis {
 public:
  using S = typename GraspT::ScalarType;
  using W = typename ScalarTraits<S>::Wide;
  using M = typename GraspT::ModelType;
  static constexpr int D = GraspT::dim;
  using Lanes = ConicLanes<W, D, GraspT::capacity>;
  using Coordinates = Eigen::Matrix<W, D, D>;
  using ConeVector = Eigen::Matrix<W, D, 1>;

  /// The scales and cone coordinates of `grasp` (complete, at least one contact).
  explicit ConicAnalysis(const GraspT& grasp) : n_(grasp.size()) {
    const EquilibriumNorm<S> norm = EquilibriumNorm<S>::of(grasp);
    norm_.length = W(norm.length);
    norm_.inverse = W(1) / norm_.length;
    for (int i = 0; i < n_; ++i) {
      Contact<W> c = cast_contact<W>(grasp.contact(i));
      if constexpr (D > 1) c.normal /= c.normal.norm();
      coordinates_[idx(i)] = cone_coordinates<M>(c);
    }
  }

  /// The norm whose units the rows take (T = norm.weights()).
  const EquilibriumNorm<W>& norm() const { return norm_; }
  /// M_i of contact i.
  const Coordinates& coordinates(int i) const { return coordinates_[idx(i)]; }

  /// The margin problem written into `k` (cleared first); returns its right-hand side b = -T g_e.
  Wrench<W> margin_problem(const GraspT& grasp, Lanes& k) {
    k.clear(n_);
    g_e_.setZero();
    for (int i = 0; i < n_; ++i) g_e_ += M::wrench(contact(grasp, i), cone_axis<M>(contact(grasp, i)));
    const Wrench<W> ge = norm_.to_units(g_e_);
    const W inv_n = W(1) / W(n_);
    for (int i = 0; i < n_; ++i) {
      Eigen::Matrix<W, 6, D> a = rows(grasp, i);
      a.col(0) -= inv_n * ge;  // T g_e e_i^T M_i / n = T g_e e^T / n
      ConeVector q = ConeVector::Zero();
      q(0) = inv_n;
      set(k, i, a, q);
    }
    return -ge;
  }

  /// The wrench problem along `d` (T d != 0) written into `k` (cleared first); returns its
  /// right-hand side b = -T d / |T d|.
  Wrench<W> wrench_problem(const GraspT& grasp, const Wrench<W>& d, Lanes& k) const {
    k.clear(n_);
    for (int i = 0; i < n_; ++i) {
      ConeVector q = ConeVector::Zero();
      q(0) = W(1);
      set(k, i, rows(grasp, i), q);
    }
    const Wrench<W> td = norm_.to_units(d);
    return -td / td.norm();
  }

  /// zeta(u) = max_i (|v_i1| - v_i0), v_i = M_i^T G_i^T u: the least zeta with G_i^T u + zeta e_i in
  /// K_i^* for every contact.
  W dual_shift(const GraspT& grasp, const Wrench<W>& u) const {
    W zeta = -std::numeric_limits<W>::infinity();
    for (int i = 0; i < n_; ++i) {
      const ConeVector v = coordinates_[idx(i)].transpose() * M::wrench_transpose(contact(grasp, i), u);
      const W tail = D > 1 ? W(v.template tail<D - 1>().norm()) : W(0);
      zeta = std::max(zeta, tail - v(0));
    }
    return zeta;
  }

  /// An upper bound on the margin (normal forces summing to 1) from the direction u: 1 / n, and
  /// zeta(u) / (n zeta(u) + g_e . u) where that denominator is positive (see the file comment).
  /// margin_problem must have run (it sets g_e).
  W margin_bound(const GraspT& grasp, const Wrench<W>& u) const {
    const W bound = W(1) / W(n_);
    const W zeta = dual_shift(grasp, u);
    const W den = W(n_) * zeta + g_e_.dot(u);
    if (!(den > W(0)) || !std::isfinite(zeta)) return bound;
    const W b = zeta / den;
    return std::isfinite(b) ? std::min(bound, b) : bound;
  }

  /// An upper bound on s* / B, the largest multiple of d per unit of budget, from the direction u:
  /// zeta(u) / (d . u) when d . u > 0 (0 when zeta(u) <= 0 too), infinity otherwise.
  W scale_bound(const GraspT& grasp, const Wrench<W>& d, const Wrench<W>& u) const {
    const W du = d.dot(u);
    if (!(du > W(0))) return std::numeric_limits<W>::infinity();
    const W zeta = dual_shift(grasp, u);
    if (!std::isfinite(zeta)) return std::numeric_limits<W>::infinity();
    return zeta > W(0) ? zeta / du : W(0);
  }

  /// The cone part M_i u_i of contact i at the iterate in `k`.
  ConeVector force(const Lanes& k, int i) const { return coordinates_[idx(i)] * k.u(i); }

  /// The interior-point settings of an analysis: `tolerance` for the gap, the residuals and the
  /// certificate, at most `max_iterations`, and the floors of the residuals' and the gap's scales.
  static InteriorPointSettings<W> settings(W tolerance, int max_iterations, W residual_floor, W objective_floor) {
    InteriorPointSettings<W> st;
    st.tolerance = tolerance;
    st.feasibility_tolerance = tolerance;
    st.certificate_tolerance = tolerance;
    st.max_iterations = max_iterations;
    st.residual_floor = residual_floor;
    st.objective_floor = objective_floor;
    return st;
  }

 private:
  static std::size_t idx(int i) { return static_cast<std::size_t>(i); }
  static decltype(auto) contact(const GraspT& grasp, int i) { return wide_contact<W>(grasp.contact(i)); }
  /// T G_i M_i.
  Eigen::Matrix<W, 6, D> rows(const GraspT& grasp, int i) const {
    const auto& c = contact(grasp, i);
    const Coordinates& m = coordinates_[idx(i)];
    Eigen::Matrix<W, 6, D> a;
    for (int j = 0; j < D; ++j) a.col(j) = norm_.to_units(M::wrench(c, ConeVector(m.col(j))));
    return a;
  }
  /// Contact i's rows `a`, P_i = 0, q_i, no bound, and the metric diag(M_i^T M_i).
  void set(Lanes& k, int i, const Eigen::Matrix<W, 6, D>& a, const ConeVector& q) const {
    const ConeVector metric = coordinates_[idx(i)].colwise().squaredNorm().transpose();
    k.set(i, a, ConeVector::Zero(), q, std::numeric_limits<W>::infinity(), metric);
  }

  int n_;
  EquilibriumNorm<W> norm_;
  Wrench<W> g_e_{Wrench<W>::Zero()};  ///< g_e = sum_i G_i e_i (margin_problem)
  std::array<Coordinates, static_cast<std::size_t>(GraspT::capacity)> coordinates_;
};

}  // namespace detail
}  // namespace grip
