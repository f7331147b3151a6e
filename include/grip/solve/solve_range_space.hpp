#pragma once
/// \file
/// The structure-exploiting O(n) solver of min F2 s.t. G x + w_ext = 0. Where G W^-1 G^T is
/// numerically rank deficient, its least-squares refinement is detail/least_squares.hpp.

#include <algorithm>
#include <cmath>
#include <limits>

#include "grip/contact/contact.hpp"
#include "grip/contact/contact_model.hpp"
#include "grip/grasp/grasp.hpp"
#include "grip/solve/detail/least_squares.hpp"
#include "grip/solve/solution.hpp"
#include "grip/solve/symmetric_solve.hpp"

namespace grip {

namespace detail {

/// Ok if the grasp is complete and w_ext valid; otherwise fills `sol` for InvalidInput.
template <class GraspT>
bool check_inputs(const GraspT& grasp, const Wrench<typename GraspT::ScalarType>& w_ext, Solution<GraspT>& sol) {
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

/// lever_arm() of a grasp whose sums k_sum and kr2_sum are given. Where the squares of the
/// coordinates may have underflowed (kr2_sum below k_sum min / eps: lever arms under about
/// 3e-16 m in float), it is computed again from the positions scaled by their largest
/// coordinate, so that a grasp at any representable scale gets its true lever arm.
template <class GraspT>
typename GraspT::ScalarType lever_arm(const GraspT& grasp, typename GraspT::ScalarType k_sum,
                                      typename GraspT::ScalarType kr2_sum) {
  using S = typename GraspT::ScalarType;
  if (!(kr2_sum < k_sum * (std::numeric_limits<S>::min() / std::numeric_limits<S>::epsilon())))
    return lever_arm(k_sum, kr2_sum);
  S big(0), scaled(0);
  for (int i = 0; i < grasp.size(); ++i) big = std::max(big, grasp.contact(i).position.cwiseAbs().maxCoeff());
  if (!(big > S(0))) return S(0);
  for (int i = 0; i < grasp.size(); ++i)
    scaled += (grasp.contact(i).position / big).squaredNorm() * grasp.inverse_weight(i);
  return big * lever_arm(k_sum, scaled);
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
  return lever_arm(grasp, k_sum, kr2_sum);
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
/// on acc.matrix(). With `Ldlt` false, C is solved by its adjugate only: a C whose determinant
/// (on the rank test's scale) is not above rank_tolerance returns false without factoring.
/// On success `residual` = M y - r, evaluated from the sums as well.
template <bool Ldlt = true, class S>
bool solve_gram_by_schur(const GramAccumulator<S>& acc, const Wrench<S>& r, S length, Wrench<S>& y,
                         Wrench<S>& residual) {
  const S tol = ScalarTraits<S>::rank_tolerance;
  const S k0 = acc.k0;
  if (!(k0 > S(0)) || !(length > S(0)) || !std::isfinite(length)) return false;
  const S inv_k0 = S(1) / k0;
  const S cx = acc.s1.x(), cy = acc.s1.y(), cz = acc.s1.z();
  // S (s2 keeps its upper triangle; extra may add to the moment block).
  const S m00 = acc.s2(0, 0) + acc.extra(3, 3), m01 = acc.s2(0, 1) + acc.extra(3, 4),
          m02 = acc.s2(0, 2) + acc.extra(3, 5), m11 = acc.s2(1, 1) + acc.extra(4, 4),
          m12 = acc.s2(1, 2) + acc.extra(4, 5), m22 = acc.s2(2, 2) + acc.extra(5, 5);
  const S l2 = length * length;
  const S ref = std::max(k0, std::max(m00, std::max(m11, m22)) / l2);  // largest diagonal of D M D
  if (!std::isfinite(ref) || !(k0 > tol * ref)) return false;
  // C / (ref L^2): the Schur complement on the scale of the rank test, entries <= 1.
  const S u = S(1) / (ref * l2);
  const S c2 = cx * cx + cy * cy + cz * cz;
  const S a00 = (m00 + (cx * cx - c2) * inv_k0) * u, a01 = (m01 + cx * cy * inv_k0) * u,
          a02 = (m02 + cx * cz * inv_k0) * u, a11 = (m11 + (cy * cy - c2) * inv_k0) * u,
          a12 = (m12 + cy * cz * inv_k0) * u, a22 = (m22 + (cz * cz - c2) * inv_k0) * u;
  // Straight-line solve by the adjugate when det > tol: as for SmallLdlt, the product of the
  // pivots (det) then proves that diagonally pivoted LDL^T would accept; else SmallLdlt decides.
  const Adjugate3<S> adj = adjugate3(a00, a01, a02, a11, a12, a22);
  const S b00 = adj.c00, b01 = adj.c01, b02 = adj.c02, b11 = adj.c11, b12 = adj.c12, b22 = adj.c22;
  const S det = adj.det;
  const bool by_adjugate = det > tol;
  SmallLdlt<3, S> ldlt;
  if (!by_adjugate) {
    if constexpr (!Ldlt) return false;
    const S a[3][3] = {{a00, a01, a02}, {a01, a11, a12}, {a02, a12, a22}};
    if (!ldlt.factor(a, S(1), tol)) return false;
  }
  const S inv_det = by_adjugate ? S(1) / det : S(0);
  // z = M^-1 b by the block elimination: z_m = C^-1 (b_m - c x b_f / k0), z_f = (b_f + c x z_m) / k0.
  const auto eliminate = [&](const Wrench<S>& b, Wrench<S>& z) {
    const S fx = b(0), fy = b(1), fz = b(2);
    S x0 = (b(3) - (cy * fz - cz * fy) * inv_k0) * u, x1 = (b(4) - (cz * fx - cx * fz) * inv_k0) * u,
      x2 = (b(5) - (cx * fy - cy * fx) * inv_k0) * u;
    if (by_adjugate) {
      const S y0 = (b00 * x0 + b01 * x1 + b02 * x2) * inv_det, y1 = (b01 * x0 + b11 * x1 + b12 * x2) * inv_det,
              y2 = (b02 * x0 + b12 * x1 + b22 * x2) * inv_det;
      x0 = y0;
      x1 = y1;
      x2 = y2;
    } else {
      S x[3] = {x0, x1, x2};
      ldlt.solve(x);
      x0 = x[0];
      x1 = x[1];
      x2 = x[2];
    }
    z(3) = x0;
    z(4) = x1;
    z(5) = x2;
    z(0) = (fx + (cy * x2 - cz * x1)) * inv_k0;
    z(1) = (fy + (cz * x0 - cx * x2)) * inv_k0;
    z(2) = (fz + (cx * x1 - cy * x0)) * inv_k0;
  };
  // residual = M z - b, from the sums: M = [[k0 I, -[c]x], [[c]x, S]].
  const auto residual_of = [&](const Wrench<S>& z, const Wrench<S>& b, Wrench<S>& out) {
    out(0) = k0 * z(0) - (cy * z(5) - cz * z(4)) - b(0);
    out(1) = k0 * z(1) - (cz * z(3) - cx * z(5)) - b(1);
    out(2) = k0 * z(2) - (cx * z(4) - cy * z(3)) - b(2);
    out(3) = (cy * z(2) - cz * z(1)) + m00 * z(3) + m01 * z(4) + m02 * z(5) - b(3);
    out(4) = (cz * z(0) - cx * z(2)) + m01 * z(3) + m11 * z(4) + m12 * z(5) - b(4);
    out(5) = (cx * z(1) - cy * z(0)) + m02 * z(3) + m12 * z(4) + m22 * z(5) - b(5);
  };
  // One step of iterative refinement, with the residual formed from the sums themselves: it
  // recovers what forming C lost to cancellation when the contacts sit far from the origin.
  Wrench<S> dz;
  eliminate(r, y);
  residual_of(y, r, residual);
  eliminate(residual, dz);
  y -= dz;
  residual_of(y, r, residual);
  return y.allFinite() && residual.allFinite();
}

/// What range_space_solve does with a grasp matrix its first factorisation does not accept.
enum class RankFallback {
  /// Factor again (pivoted LDL^T, then an eigen-decomposition) and repair the residual:
  /// solve_range_space's least-squares contract.
  least_squares,
  /// Report Singular with zero multipliers at once, without further factorisation: for a
  /// caller that handles every rank itself (solve_constrained's fast path, whose iteration then
  /// starts from zero multipliers). Hard and soft fingers accept only the Schur complement's
  /// straight-line solve by its adjugate; an answer worse than x = 0 is declined too.
  decline
};

/// solve_range_space() into `sol`, also giving the system's right-hand side
/// rhs = -(w_ext + G t) and residual vector res = M lambda - rhs = G x + w_ext (up to the
/// round-off of the recovery pass): with them F2(x) = lambda.(rhs + res) / 2 needs no other pass.
/// With `gram_diagonal` given, also writes the diagonal of G W^-1 G^T there. Returns false (sol
/// InvalidInput, rhs and res zero, `gram_diagonal` untouched) for invalid input.
/// `inputs_checked`: the caller has already found the grasp complete and w_ext valid (as
/// check_inputs would), so they are not checked again. `Fallback`: see RankFallback (declined:
/// status Singular, zero multipliers, the forces t and res = -rhs).
template <RankFallback Fallback = RankFallback::least_squares, class GraspT>
bool range_space_solve(const GraspT& grasp, const Wrench<typename GraspT::ScalarType>& w_ext, Solution<GraspT>& sol,
                       Wrench<typename GraspT::ScalarType>& rhs, Wrench<typename GraspT::ScalarType>& res,
                       Wrench<typename GraspT::ScalarType>* gram_diagonal = nullptr, bool inputs_checked = false) {
  using S = typename GraspT::ScalarType;
  using M = typename GraspT::ModelType;
  if (!inputs_checked && !check_inputs(grasp, w_ext, sol)) {
    rhs.setZero();
    res.setZero();
    return false;
  }
  sol.forces.resize(grasp.unknowns());  // every entry is written by forces_from_multipliers
  sol.iterations = 0;
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
  if (gram_diagonal != nullptr) *gram_diagonal = acc.diagonal();
  Wrench<S> lambda;
  const S length = lever_arm(grasp, k_sum, kr2_sum);
  bool done = false;
  constexpr bool least_squares = Fallback == RankFallback::least_squares;
  if constexpr (M::identity_force_block) {
    done = solve_gram_by_schur<least_squares>(acc, rhs, length, lambda, res);
    if (done) sol.status = Status::Ok;
  }
  if (!done) {
    if constexpr (least_squares || !M::identity_force_block) {
      const Matrix6<S> gram = acc.matrix();
      sol.status = solve_symmetric_6x6(gram, rhs, lambda, length);
      res = gram * lambda - rhs;
    } else {  // declined: no multipliers were computed
      sol.status = Status::Singular;
      lambda.setZero();
      res = -rhs;
    }
  }
  forces_from_multipliers(grasp, lambda, sol);
  // |D (G x + w_ext)| clearly above its value at x = 0 (beyond the round-off of the terms, and
  // sqrt-free: |D res|^2 > 2 |D w_ext|^2 + 2 slack^2): possible only where directions of
  // round-off rank were cut (or float cancels at extreme scales); refine_least_squares then
  // repairs it. The test costs three 6-vector dot products.
  const Wrench<S> balance = unit_balance(length);
  const S eps64 = S(64) * std::numeric_limits<S>::epsilon();
  const S floor2 =
      S(2) * balance.cwiseProduct(w_ext).squaredNorm() + S(2) * eps64 * eps64 * balance.cwiseProduct(rhs).squaredNorm();
  const auto worse_than_zero = [&] { return balance.cwiseProduct(res).squaredNorm() > floor2; };
  if constexpr (!least_squares) {
    if (sol.status != Status::Ok || worse_than_zero()) {
      sol.status = Status::Singular;
      lambda.setZero();
      forces_from_multipliers(grasp, lambda, sol);
      res = -rhs;
    }
  } else if ((sol.status == Status::Singular && residual_reducible(grasp, length, res)) || worse_than_zero()) {
    // Directions of round-off rank keep the residual of the starting point; when that is
    // still worse than x = 0, start again from x = 0.
    refine_least_squares(grasp, w_ext, length, sol, res);
    if (worse_than_zero()) {
      sol.forces.setZero();
      refine_least_squares(grasp, w_ext, length, sol, res);
    }
  }
  // G x + w_ext = G t + M lambda + w_ext = M lambda - rhs: the residual without another pass.
  sol.residual = stable_norm(res);
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
///   is smallest. `residual` (unscaled) tells what is left unbalanced. The least residual holds
///   at every valid scale: where weights spread beyond 1 / rank_tolerance, soft-finger torsion
///   meets lever arms far from 1 m, or one contact lies far beyond L, G W^-1 G^T looks rank
///   deficient although G need not be; the answer is then refined on G's own columns
///   (detail::refine_least_squares: three more passes and a 6x6 eigen-decomposition), F2
///   smallest only to within that refinement, and the status stays Singular.
/// - InvalidInput: incomplete grasp or non-finite/out-of-range w_ext; zeros.
template <class GraspT>
Solution<GraspT> solve_range_space(const GraspT& grasp, const Wrench<typename GraspT::ScalarType>& w_ext) {
  Solution<GraspT> sol;
  Wrench<typename GraspT::ScalarType> rhs, res;
  detail::range_space_solve(grasp, w_ext, sol, rhs, res);
  return sol;
}

}  // namespace grip
