#pragma once
/// \file
/// The paper's method (section 5, eq. 9): Gaussian elimination on the KKT matrix H.

#include <algorithm>
#include <cmath>
#include <utility>

#include "grip/grasp/grasp.hpp"
#include "grip/solve/solution.hpp"
#include "grip/solve/solve_range_space.hpp"

namespace grip {

/// Solves H c = b of eq. 9, c = (x, lambda), by Gaussian elimination with partial pivoting
/// on the (6 + n dim)-square H, in fixed-size (or bounded) storage: the paper's method,
/// O(n^3). H is first scaled so that the pivot test is unit-free (see the code).
///
/// Statuses and numbers as solve_range_space (same optimum, same multipliers):
/// - Ok: the unique optimum.
/// - Singular: a scaled pivot fell below ScalarTraits::rank_tolerance; the answer is then
///   the same least-squares forces solve_range_space documents (computed by it).
/// - InvalidInput: incomplete grasp or bad w_ext; zeros.
///
/// Stack use grows as (6 + n dim)^2: at n = 64 hard fingers, 310 KB in double, above Eigen's
/// default EIGEN_STACK_ALLOCATION_LIMIT (128 KB). Prefer solve_range_space beyond n = 20.
template <class GraspT>
Solution<GraspT> solve_kkt(const GraspT& grasp, const Wrench<typename GraspT::ScalarType>& w_ext) {
  using S = typename GraspT::ScalarType;
  Solution<GraspT> sol;
  if (!detail::check_inputs(grasp, w_ext, sol)) return sol;

  typename GraspT::KktMatrix h = grasp.kkt_matrix();
  typename GraspT::KktVector b = grasp.kkt_rhs(w_ext);
  const int m = static_cast<int>(h.rows());
  const int n = grasp.unknowns();
  // Unit-free scaling (see solve_symmetric_6x6): moment rows and the moment multipliers'
  // columns by the lever arm L, the six equilibrium rows by one common factor (scaling them
  // one by one would blow round-off in an all-but-zero row up to size one), and each
  // stationarity row by its weight.
  const S length = detail::lever_arm(grasp);
  if (!(length > S(0))) return solve_range_space(grasp, w_ext);  // no lever arm: no moments
  // The rank of G decides Ok or Singular, by the rank-revealing (diagonally pivoted) LDL^T of
  // the unit-balanced 6x6 Gram matrix, as in solve_range_space: O(n), against the
  // O((6 + n dim)^3) elimination below. Partial pivoting of the KKT matrix is not rank
  // revealing: in float an exactly singular G (two collinear hard fingers) can leave a last
  // pivot of round-off size above the tolerance and multipliers of 1e9.
  {
    Wrench<S> y;
    if (solve_symmetric_6x6(weighted_gram(grasp), w_ext, y, length) != Status::Ok)
      return solve_range_space(grasp, w_ext);
  }
  // Written in scalar loops over h(i, j), not Eigen block expressions: the same arithmetic at
  // a fraction of the compile cost per grasp type (h is column-major: inner loops run down
  // columns).
  for (int j = 0; j < m; ++j)
    for (int i = 3; i < 6; ++i) h(i, j) /= length;
  for (int i = 3; i < 6; ++i) b(i) /= length;
  for (int j = n + 3; j < n + 6; ++j)
    for (int i = 0; i < m; ++i) h(i, j) /= length;
  S eq_scale(0);
  for (int j = 0; j < m; ++j)
    for (int i = 0; i < 6; ++i) eq_scale = std::max(eq_scale, std::abs(h(i, j)));
  if (!(eq_scale > S(0))) return solve_range_space(grasp, w_ext);
  for (int j = 0; j < m; ++j)
    for (int i = 0; i < 6; ++i) h(i, j) /= eq_scale;
  for (int i = 0; i < 6; ++i) b(i) /= eq_scale;
  for (int i = 6; i < m; ++i) {
    S s(0);  // >= the contact's weight > 0
    for (int j = 0; j < m; ++j) s = std::max(s, std::abs(h(i, j)));
    for (int j = 0; j < m; ++j) h(i, j) /= s;
    b(i) /= s;
  }
  const S tol = ScalarTraits<S>::rank_tolerance;
  for (int k = 0; k < m; ++k) {
    int p = k;
    S pivot = std::abs(h(k, k));
    for (int i = k + 1; i < m; ++i) {
      const S v = std::abs(h(i, k));
      if (v > pivot) {
        pivot = v;
        p = i;
      }
    }
    if (!(pivot > tol)) return solve_range_space(grasp, w_ext);  // Singular, least squares
    if (p != k) {
      for (int j = 0; j < m; ++j) std::swap(h(k, j), h(p, j));
      std::swap(b(k), b(p));
    }
    if (k + 1 == m) break;
    const S inv = S(1) / h(k, k);
    for (int i = k + 1; i < m; ++i) h(i, k) *= inv;
    for (int j = k + 1; j < m; ++j) {
      const S hkj = h(k, j);
      for (int i = k + 1; i < m; ++i) h(i, j) -= h(i, k) * hkj;
    }
    const S bk = b(k);
    for (int i = k + 1; i < m; ++i) b(i) -= h(i, k) * bk;
  }
  for (int i = m - 1; i >= 0; --i) {  // back substitution
    S v = b(i);
    for (int j = i + 1; j < m; ++j) v -= h(i, j) * b(j);
    b(i) = v / h(i, i);
  }
  if (!b.allFinite()) return solve_range_space(grasp, w_ext);
  sol.forces = b.head(n);
  sol.multipliers = b.tail(6);
  sol.multipliers.template tail<3>() /= length;  // undo the column scaling of lambda_M
  sol.residual = detail::stable_norm(grasp.wrench(sol.forces) + w_ext);
  sol.status = Status::Ok;
  return sol;
}

}  // namespace grip
