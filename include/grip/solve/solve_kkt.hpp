#pragma once
/// \file
/// The paper's method (section 5, eq. 9): Gaussian elimination on the KKT matrix H.

#include <cmath>

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
  h.block(3, 0, 3, m) /= length;
  b.template segment<3>(3) /= length;
  h.block(0, n + 3, m, 3) /= length;
  const S eq_scale = h.topRows(6).cwiseAbs().maxCoeff();
  if (!(eq_scale > S(0))) return solve_range_space(grasp, w_ext);
  h.topRows(6) /= eq_scale;
  b.template head<6>() /= eq_scale;
  for (int i = 6; i < m; ++i) {
    const S s = h.row(i).cwiseAbs().maxCoeff();  // >= the contact's weight > 0
    h.row(i) /= s;
    b(i) /= s;
  }
  const S tol = ScalarTraits<S>::rank_tolerance;
  for (int k = 0; k < m; ++k) {
    Eigen::Index p = 0;
    const S pivot = h.col(k).tail(m - k).cwiseAbs().maxCoeff(&p);
    p += k;
    if (!(pivot > tol)) return solve_range_space(grasp, w_ext);  // Singular, least squares
    if (p != k) {
      h.row(k).swap(h.row(p));
      std::swap(b(k), b(p));
    }
    const int rest = m - k - 1;
    if (rest == 0) break;
    h.col(k).tail(rest) /= h(k, k);
    h.bottomRightCorner(rest, rest).noalias() -= h.col(k).tail(rest) * h.row(k).tail(rest);
    b.tail(rest).noalias() -= h.col(k).tail(rest) * b(k);
  }
  for (int i = m - 1; i >= 0; --i) {  // back substitution
    const int rest = m - i - 1;
    S v = b(i);
    if (rest > 0) v -= h.row(i).tail(rest).dot(b.tail(rest));
    b(i) = v / h(i, i);
  }
  if (!b.allFinite()) return solve_range_space(grasp, w_ext);
  sol.forces = b.head(n);
  sol.multipliers = b.tail(6);
  sol.multipliers.template tail<3>() /= length;  // undo the column scaling of lambda_M
  sol.residual = (grasp.wrench(sol.forces) + w_ext).norm();
  sol.status = Status::Ok;
  return sol;
}

}  // namespace grip
