#pragma once
/// \file
/// The structure-exploiting O(n) solver of min F2 s.t. G x + w_ext = 0.

#include <cmath>

#include "grip/contact/contact.hpp"
#include "grip/grasp/grasp.hpp"
#include "grip/solve/solution.hpp"
#include "grip/solve/symmetric_solve.hpp"

namespace grip {

namespace detail {

/// Ok if the grasp is complete and w_ext valid; otherwise fills `sol` for InvalidInput.
template <class GraspT>
bool check_inputs(const GraspT& grasp, const Wrench<typename GraspT::ScalarType>& w_ext,
                  Solution<GraspT>& sol) {
  sol.forces.setZero(grasp.unknowns());
  sol.multipliers.setZero();
  sol.iterations = 0;
  sol.residual = std::numeric_limits<typename GraspT::ScalarType>::max();
  if (!grasp.complete() || validate(w_ext) != Status::Ok) {
    sol.status = Status::InvalidInput;
    return false;
  }
  return true;
}

/// Given multipliers lambda, writes x_i = t_i + W_i^-1 G_i^T lambda (the stationarity rows of
/// eq. 9) into `sol`. One pass over the contacts.
template <class GraspT>
void forces_from_multipliers(const GraspT& grasp, const Wrench<typename GraspT::ScalarType>& lambda,
                             Solution<GraspT>& sol) {
  using S = typename GraspT::ScalarType;
  using M = typename GraspT::ModelType;
  constexpr int d = GraspT::dim;
  for (int i = 0; i < grasp.size(); ++i) {
    const auto& c = grasp.contact(i);
    sol.forces.template segment<d>(i * d) = M::target(c) + (S(1) / c.weight) * M::wrench_transpose(c, lambda);
  }
  sol.multipliers = lambda;
}

/// The characteristic lever arm L = sqrt(sum k_i |r_i|^2 / sum k_i) (m) that balances force
/// and moment rows in rank tests; 0 when every contact sits at the reference point.
template <class S>
S lever_arm(S k_sum, S kr2_sum) {
  return k_sum > S(0) ? std::sqrt(kr2_sum / k_sum) : S(0);
}

/// lever_arm() of a grasp.
template <class GraspT>
typename GraspT::ScalarType lever_arm(const GraspT& grasp) {
  using S = typename GraspT::ScalarType;
  S k_sum(0), kr2_sum(0);
  for (int i = 0; i < grasp.size(); ++i) {
    const auto& c = grasp.contact(i);
    k_sum += S(1) / c.weight;
    kr2_sum += c.position.squaredNorm() / c.weight;
  }
  return lever_arm(k_sum, kr2_sum);
}

}  // namespace detail

/// The 6x6 matrix G W^-1 G^T of a grasp, accumulated contact by contact in closed form
/// (hard finger: from sum w_i^-1, sum w_i^-1 r_i, sum w_i^-1 (|r_i|^2 I - r_i r_i^T)).
template <class GraspT>
Matrix6<typename GraspT::ScalarType> weighted_gram(const GraspT& grasp) {
  using S = typename GraspT::ScalarType;
  GramAccumulator<S> acc;
  for (int i = 0; i < grasp.size(); ++i) {
    const auto& c = grasp.contact(i);
    GraspT::ModelType::accumulate(acc, c, S(1) / c.weight);
  }
  return acc.matrix();
}

/// Solves min F2 = 1/2 sum w_i |x_i - t_i|^2 subject to G x + w_ext = 0 (the paper's
/// section 5 problem) by eliminating x: x = t + W^-1 G^T lambda with
/// (G W^-1 G^T) lambda = -(w_ext + G t). Cost O(n): one pass to accumulate the 6x6 matrix
/// and G t, one 6x6 Cholesky, one pass to recover the forces. No heap. `residual` is
/// evaluated as |M lambda + w_ext + G t|, equal to |G x + w_ext| up to the round-off of the
/// recovery pass.
///
/// Statuses:
/// - Ok: the unique optimum; `residual` at round-off.
/// - Singular: G has rank < 6 (fewer than 3 hard fingers, all contacts on a line, normals all
///   through one point for frictionless contacts, ...). `forces` are the least-squares
///   forces: |D (G x + w_ext)| is as small as possible, D = diag(1, 1, 1, 1/L, 1/L, 1/L) with
///   L = detail::lever_arm(grasp) (m) putting N and N m on one footing, and among such x, F2
///   is smallest. `residual` (unscaled) tells what is left unbalanced.
/// - InvalidInput: incomplete grasp or non-finite/out-of-range w_ext; zeros.
template <class GraspT>
Solution<GraspT> solve_range_space(const GraspT& grasp, const Wrench<typename GraspT::ScalarType>& w_ext) {
  using S = typename GraspT::ScalarType;
  using M = typename GraspT::ModelType;
  Solution<GraspT> sol;
  if (!detail::check_inputs(grasp, w_ext, sol)) return sol;
  GramAccumulator<S> acc;
  Wrench<S> rhs = -w_ext;
  S k_sum(0), kr2_sum(0);
  for (int i = 0; i < grasp.size(); ++i) {
    const auto& c = grasp.contact(i);
    const S k = S(1) / c.weight;
    M::accumulate(acc, c, k);
    k_sum += k;
    kr2_sum += k * c.position.squaredNorm();
    rhs -= M::wrench(c, M::target(c));
  }
  Wrench<S> lambda;
  const Matrix6<S> gram = acc.matrix();
  sol.status = solve_symmetric_6x6(gram, rhs, lambda, detail::lever_arm(k_sum, kr2_sum));
  detail::forces_from_multipliers(grasp, lambda, sol);
  // G x + w_ext = G t + M lambda + w_ext = M lambda - rhs: the residual without another pass.
  sol.residual = (gram * lambda - rhs).norm();
  return sol;
}

}  // namespace grip
