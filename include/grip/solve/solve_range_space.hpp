#pragma once
/// \file
/// The structure-exploiting O(n) solver of min F2 s.t. G x + w_ext = 0.

#include <algorithm>
#include <cmath>

#include "grip/contact/contact.hpp"
#include "grip/contact/contact_model.hpp"
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
  using M = typename GraspT::ModelType;
  constexpr int d = GraspT::dim;
  for (int i = 0; i < grasp.size(); ++i) {
    const auto& c = grasp.contact(i);
    sol.forces.template segment<d>(i * d) = M::target(c) + grasp.inverse_weight(i) * M::wrench_transpose(c, lambda);
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
    k_sum += grasp.inverse_weight(i);
    kr2_sum += c.position.squaredNorm() * grasp.inverse_weight(i);
  }
  return lever_arm(k_sum, kr2_sum);
}

/// Solves (sum k G_i G_i^T) y = r from the sums of `acc` when the force block is k0 I
/// (models with identity_force_block: `extra` touches only the moment block). With
/// M = [[k0 I, -[s1]x], [[s1]x, S]] the force rows give y_f = (r_f + s1 x y_m) / k0 and leave
/// the 3x3 Schur complement C y_m = r_m - s1 x r_f / k0, C = S + (s1 s1^T - |s1|^2 I) / k0: the
/// weighted second moment of the contact points about their centroid s1 / k0, factored by
/// SmallLdlt. This is the elimination the 6x6 factorisation would do, on the same
/// unit-free scale (rank tolerance against max(k0, max diag S / L^2)); the multipliers it
/// implies are bounded by |s1 / k0| / L <= 1, so it is as rank revealing as diagonal pivoting.
/// One step of iterative refinement follows (the residual from the sums, one more pair of
/// substitutions). Returns false when C is numerically rank deficient, k0 or L is not
/// positive, or the result is not finite: the caller then falls back to solve_symmetric_6x6
/// on acc.matrix().
/// On success `residual` = M y - r, evaluated from the sums as well.
template <class S>
bool solve_gram_by_schur(const GramAccumulator<S>& acc, const Wrench<S>& r, S length, Wrench<S>& y,
                         Wrench<S>& residual) {
  const S tol = ScalarTraits<S>::rank_tolerance;
  if (!(acc.k0 > S(0)) || !(length > S(0)) || !std::isfinite(length)) return false;
  const S inv_k0 = S(1) / acc.k0;
  const Vector3<S> c = acc.s1;
  Matrix3<S> sm = acc.s2;  // s2 holds its upper triangle only
  sm(1, 0) = sm(0, 1);
  sm(2, 0) = sm(0, 2);
  sm(2, 1) = sm(1, 2);
  sm += acc.extra.template bottomRightCorner<3, 3>();
  S a[3][3];
  S diag_max(0);
  for (int i = 0; i < 3; ++i) {
    diag_max = std::max(diag_max, sm(i, i));
    for (int k = 0; k < 3; ++k) a[i][k] = sm(i, k) + c(i) * c(k) * inv_k0;
    a[i][i] -= c.squaredNorm() * inv_k0;
  }
  const S l2 = length * length;
  const S ref = std::max(acc.k0, diag_max / l2);
  if (!std::isfinite(ref) || !(acc.k0 > tol * ref)) return false;
  SmallLdlt<3, S> ldlt;
  if (!ldlt.factor(a, ref * l2, tol)) return false;
  // y = M^-1 r by the block elimination; then one step of iterative refinement with the
  // residual formed from the sums themselves, which recovers what forming C lost to
  // cancellation when the contacts sit far from the reference point.
  const auto eliminate = [&](const Wrench<S>& b) {
    const Vector3<S> bf = b.template head<3>();
    const Vector3<S> bm = b.template tail<3>() - inv_k0 * c.cross(bf);
    S x[3] = {bm.x(), bm.y(), bm.z()};
    ldlt.solve(x);
    const Vector3<S> zm(x[0], x[1], x[2]);
    Wrench<S> z;
    z << inv_k0 * (bf + c.cross(zm)), zm;
    return z;
  };
  const auto times = [&](const Wrench<S>& z) {  // M z
    const Vector3<S> zf = z.template head<3>(), zm = z.template tail<3>();
    Wrench<S> out;
    out << acc.k0 * zf - c.cross(zm), c.cross(zf) + sm * zm;
    return out;
  };
  y = eliminate(r);
  y -= eliminate(Wrench<S>(times(y) - r));
  residual = times(y) - r;
  return y.allFinite() && residual.allFinite();
}

/// solve_range_space() into `sol`, also giving the system's right-hand side
/// rhs = -(w_ext + G t) and residual vector res = M lambda - rhs = G x + w_ext (up to the
/// round-off of the recovery pass): with them F2(x) = lambda.(rhs + res) / 2 needs no other pass.
/// Returns false (sol InvalidInput) for invalid input.
template <class GraspT>
bool range_space_solve(const GraspT& grasp, const Wrench<typename GraspT::ScalarType>& w_ext, Solution<GraspT>& sol,
                       Wrench<typename GraspT::ScalarType>& rhs, Wrench<typename GraspT::ScalarType>& res) {
  using S = typename GraspT::ScalarType;
  using M = typename GraspT::ModelType;
  rhs.setZero();
  res.setZero();
  if (!check_inputs(grasp, w_ext, sol)) return false;
  GramAccumulator<S> acc;
  rhs = -w_ext;
  S k_sum(0), kr2_sum(0);
  for (int i = 0; i < grasp.size(); ++i) {
    const auto& c = grasp.contact(i);
    const S k = grasp.inverse_weight(i);
    M::accumulate(acc, c, k);
    k_sum += k;
    kr2_sum += k * c.position.squaredNorm();
    rhs -= M::wrench(c, M::target(c));
  }
  Wrench<S> lambda;
  const S length = lever_arm(k_sum, kr2_sum);
  bool done = false;
  if constexpr (M::identity_force_block) {
    done = solve_gram_by_schur(acc, rhs, length, lambda, res);
    if (done) sol.status = Status::Ok;
  }
  if (!done) {
    const Matrix6<S> gram = acc.matrix();
    sol.status = solve_symmetric_6x6(gram, rhs, lambda, length);
    res = gram * lambda - rhs;
  }
  forces_from_multipliers(grasp, lambda, sol);
  // G x + w_ext = G t + M lambda + w_ext = M lambda - rhs: the residual without another pass.
  sol.residual = res.norm();
  return true;
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
    GraspT::ModelType::accumulate(acc, c, grasp.inverse_weight(i));
  }
  return acc.matrix();
}

/// Solves min F2 = 1/2 sum w_i |x_i - t_i|^2 subject to G x + w_ext = 0 (the paper's
/// section 5 problem) by eliminating x: x = t + W^-1 G^T lambda with
/// (G W^-1 G^T) lambda = -(w_ext + G t). Cost O(n): one pass to accumulate the 6x6 matrix
/// and G t in closed form, one small factorisation (hard and soft fingers: the force rows are
/// eliminated in closed form and a 3x3 Schur complement is factored, see
/// detail::solve_gram_by_schur; frictionless points and rank-deficient grasps: the 6x6
/// solve_symmetric_6x6), one pass to recover the forces. No heap. `residual` is
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
  Solution<GraspT> sol;
  Wrench<typename GraspT::ScalarType> rhs, res;
  detail::range_space_solve(grasp, w_ext, sol, rhs, res);
  return sol;
}

}  // namespace grip
