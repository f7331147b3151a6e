#pragma once
/// \file
/// The least-squares refinement of the range-space solve (namespace grip::detail): where
/// G W^-1 G^T is numerically rank deficient, the forces' residual G x + w_ext is made the
/// smallest on G's own columns, each scaled to unit length (solve_range_space.hpp's Singular
/// answer; docs/solve.md).

#include <cmath>
#include <limits>

#include <Eigen/Core>

#include "grip/contact/contact.hpp"
#include "grip/core/types.hpp"
#include "grip/solve/solution.hpp"
#include "grip/solve/symmetric_solve.hpp"

namespace grip {
namespace detail {

/// The balanced columns b_j = D g_j of contact c's block of G (D = `balance`) as unit columns
/// q_j = b_j / |b_j| into `q`, and s_j = 1 / |b_j| into `s` (q_j = 0 and s_j = 0 for a column of
/// zero or non-finite length). Unit columns keep every product finite where |b_j|^2 would
/// overflow (a moment row scaled by 1 / L for a lever arm L of 1e-22 m in float).
template <class M, class S, int d>
void balanced_columns(const Contact<S>& c, const Wrench<S>& balance, Eigen::Matrix<S, 6, d>& q,
                      Eigen::Matrix<S, d, 1>& s) {
  q = balance.asDiagonal() * M::basis(c);
  for (int j = 0; j < d; ++j) {
    const S norm = stable_norm(q.col(j));
    const bool usable = norm > S(0) && std::isfinite(norm) && std::isfinite(S(1) / norm);
    s(j) = usable ? S(1) / norm : S(0);
    if (usable)
      q.col(j) *= s(j);
    else
      q.col(j).setZero();
  }
}

/// True when the residual `res` = G x + w_ext still has a component along some balanced column
/// of G: |b_j . D res| / |b_j| > sqrt(eps) |D res| for a column b_j = D g_j (the least residual
/// is reached exactly when there is none). One O(n) pass, no factorisation: it spares the
/// refinement to a Singular answer that the weighted solve already made least-squares.
template <class GraspT>
bool residual_reducible(const GraspT& grasp, typename GraspT::ScalarType length,
                        const Wrench<typename GraspT::ScalarType>& res) {
  using S = typename GraspT::ScalarType;
  constexpr int d = GraspT::dim;
  const Wrench<S> balance = unit_balance(length);
  const Wrench<S> r = balance.cwiseProduct(res);  // D res
  const S limit = std::sqrt(std::numeric_limits<S>::epsilon()) * stable_norm(r);
  for (int i = 0; i < grasp.size(); ++i) {
    const Eigen::Matrix<S, 6, d> b = balance.asDiagonal() * GraspT::ModelType::basis(grasp.contact(i));
    for (int j = 0; j < d; ++j)
      if (!(std::abs(b.col(j).dot(r)) <= limit * stable_norm(b.col(j)))) return true;
  }
  return false;
}

/// The least-squares refinement of an answer x whose residual G x + w_ext is not yet the
/// smallest. G W^-1 G^T can look rank deficient at the unit balance D when G is not: weights
/// that spread by more than 1 / rank_tolerance, soft-finger torsion columns (N m unknowns) on
/// lever arms far from 1 m, or one contact far beyond the lever arm L; the directions cut
/// there stay unbalanced. The correction is therefore taken on G's own columns, each scaled to
/// unit length (rank and the least residual do not depend on column scales): with
/// b_j = D g_j, s_j = 1 / |b_j|, q_j = s_j b_j and A1 = sum_j q_j q_j^T, x_j += s_j q_j^T u for
/// u = A1^+ D (-res). Then |D (G x + w_ext)| is the smallest whatever the weights and units (F2
/// is smallest among such x only to within that correction). Two steps, the residual taken from
/// the forces themselves each time (the one from the sums, M lambda - rhs, loses to
/// cancellation what huge multipliers carry): three O(n) passes and one 6x6
/// eigen-decomposition. `res` = G x + w_ext on return.
template <class GraspT>
void refine_least_squares(const GraspT& grasp, const Wrench<typename GraspT::ScalarType>& w_ext,
                          typename GraspT::ScalarType length, Solution<GraspT>& sol,
                          Wrench<typename GraspT::ScalarType>& res) {
  using S = typename GraspT::ScalarType;
  using M = typename GraspT::ModelType;
  constexpr int d = GraspT::dim;
  using Local = Eigen::Matrix<S, d, 1>;
  const Wrench<S> balance = unit_balance(length);
  Matrix6<S> a1 = Matrix6<S>::Zero();
  Eigen::Matrix<S, 6, d> q;
  Local s;
  res = w_ext;
  for (int i = 0; i < grasp.size(); ++i) {
    balanced_columns<M>(grasp.contact(i), balance, q, s);
    a1.noalias() += q * q.transpose();
    res += M::wrench(grasp.contact(i), Local(sol.forces.template segment<d>(i * d)));
  }
  const PseudoInverse6<S> pinv(a1);
  for (int step = 0; step < 2; ++step) {
    const Wrench<S> u = pinv.apply(Wrench<S>(-balance.cwiseProduct(res)));
    res = w_ext;
    for (int i = 0; i < grasp.size(); ++i) {
      balanced_columns<M>(grasp.contact(i), balance, q, s);
      auto xi = sol.forces.template segment<d>(i * d);
      xi += s.cwiseProduct(q.transpose() * u);  // s_j^2 b_j^T u
      res += M::wrench(grasp.contact(i), Local(xi));
    }
  }
}

}  // namespace detail
}  // namespace grip
