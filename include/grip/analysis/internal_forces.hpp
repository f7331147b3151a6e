#pragma once
/// \file
/// Internal and external contact forces (the paper's section 4): the part of a contact
/// force vector that balances a wrench, the part that only squeezes the object, a basis of
/// the internal forces, and how much of the squeeze F2 asked for survives equilibrium.
///
/// Definitions (W = diag(w_i I_dim), the weights of F2; M = G W^-1 G^T, 6x6):
/// - the external part of x is its W-orthogonal projection onto range(W^-1 G^T):
///   `x_ext = W^-1 G^T lambda` with `M lambda = G x`;
/// - the internal part is `x_int = x - x_ext`; then `G x_int = 0` (it lies in null(G): it
///   squeezes the object without moving it) and `x_ext^T W n = 0` for every n in null(G).
/// With unit weights this is the classical split of Murray, Li & Sastry, "A Mathematical
/// Introduction to Robotic Manipulation" (1994), section 5.3, and Yoshikawa & Nagai,
/// "Manipulating and grasping forces in manipulation by multifingered robot hands",
/// IEEE Trans. Robot. Autom. 7(1), 1991.

#include <algorithm>
#include <cmath>
#include <utility>

#include "grip/core/scalar_traits.hpp"
#include "grip/core/status.hpp"
#include "grip/core/types.hpp"
#include "grip/grasp/grasp.hpp"
#include "grip/solve/solve_range_space.hpp"
#include "grip/solve/symmetric_solve.hpp"

namespace grip {

/// The split x = external + internal of one contact force vector.
///
/// Invariant: all numbers finite. Status Ok: G has rank 6. Singular: rank < 6; the split
/// is still exact (M^+ is used: G x is always in range(M)). InvalidInput: incomplete grasp
/// or non-finite x (or x of the wrong size); both parts are zero then.
template <class GraspT>
struct ForceDecomposition {
  typename GraspT::ForceVector external;  ///< x_ext = W^-1 G^T lambda (grasp.unknowns()).
  typename GraspT::ForceVector internal;  ///< x_int = x - x_ext, in null(G).
  Wrench<typename GraspT::ScalarType> multipliers{Wrench<typename GraspT::ScalarType>::Zero()};  ///< lambda.
  Status status{Status::InvalidInput};                                                           ///< See above.
};

/// Splits the contact force vector `x` (grasp.unknowns() values, in grip's order: docs/conventions.md) into
/// its external part (balances the wrench G x, W-orthogonal to every internal force) and
/// its internal part (G x_int = 0). Cost O(n): one closed-form 6x6 Gram, one 6x6 solve.
/// No heap.
template <class GraspT, class Derived>
ForceDecomposition<GraspT> decompose_forces(const GraspT& grasp, const Eigen::MatrixBase<Derived>& x) {
  using S = typename GraspT::ScalarType;
  using M = typename GraspT::ModelType;
  constexpr int d = GraspT::dim;
  ForceDecomposition<GraspT> out;
  out.external.setZero(grasp.unknowns());
  out.internal.setZero(grasp.unknowns());
  if (!grasp.complete() || x.size() != grasp.unknowns() || !detail::all_in_range(x)) return out;
  const Wrench<S> gx = grasp.wrench(x);
  Wrench<S> lambda;
  // Unit-balanced rank test (moment rows scaled by the lever arm), as in solve_range_space.
  const Status st = solve_symmetric_6x6(weighted_gram(grasp), gx, lambda, detail::lever_arm(grasp));
  for (int i = 0; i < grasp.size(); ++i) {
    const auto& c = grasp.contact(i);
    const typename GraspT::ContactVector xe = grasp.inverse_weight(i) * M::wrench_transpose(c, lambda);
    out.external.template segment<d>(i * d) = xe;
    out.internal.template segment<d>(i * d) = x.template segment<d>(i * d) - xe;
  }
  out.multipliers = lambda;
  out.status = st;
  return out;
}

/// The W-weighted squared norm sum_i w_i |x_i|^2 of a contact force vector.
template <class GraspT, class Derived>
typename GraspT::ScalarType weighted_squared_norm(const GraspT& grasp, const Eigen::MatrixBase<Derived>& x) {
  using S = typename GraspT::ScalarType;
  constexpr int d = GraspT::dim;
  S sum(0);
  for (int i = 0; i < grasp.size(); ++i) sum += grasp.contact(i).weight * x.template segment<d>(i * d).squaredNorm();
  return sum;
}

/// An orthonormal (Euclidean) basis of the internal forces null(G).
template <class GraspT>
struct InternalForceBasis {
  /// unknowns x (unknowns - rank) matrix, columns orthonormal, G * basis = 0. At most
  /// max_unknowns columns (bounded storage, no heap); unknowns - 6 when G has rank 6.
  using Matrix = Eigen::Matrix<typename GraspT::ScalarType, GraspT::unknowns_at_compile_time, Dynamic, Eigen::ColMajor,
                               GraspT::max_unknowns, GraspT::max_unknowns>;
  Matrix basis;  ///< unknowns() - rank columns spanning null(G); none under InvalidInput.
  int rank{0};   ///< rank of G (numerical, relative tolerance rank_tolerance).
  Status status{
      Status::InvalidInput};  ///< Ok (rank 6), Singular (rank < 6; basis still exact), InvalidInput (0 columns).
};

/// A basis of null(G) from a column-pivoted Householder QR of G^T (unknowns x 6): the last
/// unknowns - rank columns of Q. Rank decided with ScalarTraits::rank_tolerance relative to
/// the largest pivot (as Eigen's ColPivHouseholderQR::rank()). No heap (all storage bounded by
/// GraspT::max_unknowns). The factorisation is written out in scalar loops rather than taken
/// from Eigen's ColPivHouseholderQR: the same arithmetic, at a fraction of the compile cost per
/// grasp type.
template <class GraspT>
InternalForceBasis<GraspT> internal_force_basis(const GraspT& grasp) {
  using S = typename GraspT::ScalarType;
  using Gt = Eigen::Matrix<S, GraspT::unknowns_at_compile_time, 6, Eigen::ColMajor, GraspT::max_unknowns, 6>;
  InternalForceBasis<GraspT> out;
  const int m = grasp.unknowns();
  out.basis.setZero(m, 0);
  if (!grasp.complete() || m == 0) return out;
  Gt a = grasp.grasp_matrix().transpose();
  const int steps = m < 6 ? m : 6;
  S tau[6] = {S(0), S(0), S(0), S(0), S(0), S(0)};
  S max_pivot(0);
  int nonzero = 0;
  for (int k = 0; k < steps; ++k) {
    // Pivot: the remaining column of largest norm over rows k..m-1 (recomputed, no downdating).
    int p = k;
    S best(-1);
    for (int j = k; j < 6; ++j) {
      S n2(0);
      for (int i = k; i < m; ++i) n2 += a(i, j) * a(i, j);
      if (n2 > best) {
        best = n2;
        p = j;
      }
    }
    if (!(best > S(0))) break;  // the rest is exactly zero
    if (p != k)
      for (int i = 0; i < m; ++i) std::swap(a(i, k), a(i, p));
    // Householder reflector H = I - tau v v^T with v(k) = 1 that maps a(k.., k) to (alpha, 0..).
    const S norm = std::sqrt(best);
    const S alpha = a(k, k) > S(0) ? -norm : norm;
    const S v0 = a(k, k) - alpha;
    for (int i = k + 1; i < m; ++i) a(i, k) /= v0;
    tau[k] = (alpha - a(k, k)) / alpha;
    a(k, k) = alpha;  // R(k, k)
    for (int j = k + 1; j < 6; ++j) {
      S dot = a(k, j);
      for (int i = k + 1; i < m; ++i) dot += a(i, k) * a(i, j);
      dot *= tau[k];
      a(k, j) -= dot;
      for (int i = k + 1; i < m; ++i) a(i, j) -= dot * a(i, k);
    }
    max_pivot = std::max(max_pivot, norm);
    nonzero = k + 1;
  }
  int r = 0;
  for (int k = 0; k < nonzero; ++k) r += int(std::abs(a(k, k)) > ScalarTraits<S>::rank_tolerance * max_pivot);
  // Columns r..m-1 of Q = H_0 H_1 ... : apply the reflectors, last first, to e_r .. e_{m-1}.
  out.basis.setZero(m, m - r);
  for (int c = 0; c < m - r; ++c) {
    out.basis(r + c, c) = S(1);
    for (int k = nonzero - 1; k >= 0; --k) {
      S dot = out.basis(k, c);
      for (int i = k + 1; i < m; ++i) dot += a(i, k) * out.basis(i, c);
      dot *= tau[k];
      out.basis(k, c) -= dot;
      for (int i = k + 1; i < m; ++i) out.basis(i, c) -= dot * a(i, k);
    }
  }
  out.rank = r;
  out.status = r == 6 ? Status::Ok : Status::Singular;
  return out;
}

/// The squeeze that F2 asks for (the targets t, eq. 7) split into what equilibrium keeps
/// (its internal part) and what it cancels (its external part).
///
/// The F2 optimum for any w_ext is x* = t + W^-1 G^T lambda*, whose internal part is exactly
/// the internal part of t: whatever the load, the optimum squeezes with `kept` and never
/// with `lost`. `kept_fraction` = |t_int|_w / |t|_w (W-norms) in [0, 1] (1 when t is all internal,
/// e.g. equal squeezes at contacts whose normals sum to zero with zero moment; 0 when t = 0).
template <class GraspT>
struct SqueezeSplit {
  typename GraspT::ForceVector asked;            ///< t (grasp.unknowns()).
  typename GraspT::ForceVector kept;             ///< t_int, in null(G).
  typename GraspT::ForceVector lost;             ///< t_ext = t - t_int.
  typename GraspT::ScalarType kept_fraction{0};  ///< |t_int|_w / |t|_w, 0 if t = 0.
  Status status{Status::InvalidInput};           ///< as decompose_forces.
};

/// Splits the targets of F2 into their internal (kept) and external (lost) parts. No heap.
template <class GraspT>
SqueezeSplit<GraspT> squeeze_split(const GraspT& grasp) {
  using S = typename GraspT::ScalarType;
  SqueezeSplit<GraspT> out;
  out.asked.setZero(grasp.unknowns());
  out.kept.setZero(grasp.unknowns());
  out.lost.setZero(grasp.unknowns());
  if (!grasp.complete()) return out;
  out.asked = grasp.target();
  const ForceDecomposition<GraspT> dec = decompose_forces(grasp, out.asked);
  out.status = dec.status;
  if (dec.status == Status::InvalidInput) return out;
  out.kept = dec.internal;
  out.lost = dec.external;
  const S total = weighted_squared_norm(grasp, out.asked);
  if (total > S(0)) {
    const S f = std::sqrt(weighted_squared_norm(grasp, out.kept) / total);
    out.kept_fraction = f > S(1) ? S(1) : f;
  }
  return out;
}

}  // namespace grip
