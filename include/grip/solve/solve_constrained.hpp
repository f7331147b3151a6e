#pragma once
/// \file
/// solve_constrained: the exact optimum of F2 with every contact force inside its exact cone
/// (the paper's section 4 problem, eq. 3-5 with eq. 7), O(n) per iteration. The API and its
/// result type first, with their contract; the definitions at the end. The method lives in
/// detail/: semi-smooth Newton on the 6-dimensional dual (semismooth_newton.hpp), its passes
/// over the contacts (constrained_passes.hpp) and the least-residual problem that decides
/// infeasibility (least_residual.hpp).

#include <type_traits>

#include "grip/contact/coulomb_cone.hpp"
#include "grip/contact/coulomb_kernel.hpp"
#include "grip/contact/exact_cone.hpp"
#include "grip/core/status.hpp"
#include "grip/core/types.hpp"
#include "grip/grasp/grasp.hpp"
#include "grip/solve/constrained_settings.hpp"
#include "grip/solve/detail/constrained_passes.hpp"
#include "grip/solve/detail/least_residual.hpp"
#include "grip/solve/detail/semismooth_newton.hpp"
#include "grip/solve/solution.hpp"
#include "grip/solve/solve_range_space.hpp"

namespace grip {

/// What solve_constrained returns: a Solution plus the numbers that certify it.
///
/// Every number is finite whatever the status; `forces` always lie inside their cones
/// (they are projections), except under InvalidInput, where everything is zero.
template <class GraspT>
struct ConstrainedSolution : Solution<GraspT> {
  /// The grasp's scalar type (float or double).
  using Scalar = typename GraspT::ScalarType;
  /// Infeasible: a 6-vector y of dual norm |(y_f, L y_m)| = 1 (L the longest lever arm, see
  /// solve_constrained) with G_i^T y in the dual cone K_i^* for every contact (its distance to
  /// K_i^* at most ConstrainedSettings::certificate_tolerance (1 + |r_i| / L)) and
  /// y.w_ext > 0. It proves that no forces in
  /// the cones balance w_ext: for x_i in K_i, y.(G x) >= 0, so y.(G x + w_ext) > 0. Zero otherwise.
  Wrench<Scalar> certificate{Wrench<Scalar>::Zero()};
  /// F2 at `forces`: 1/2 sum_i w_i |x_i - t_i|^2.
  Scalar objective{0};
  /// The dual function q at `multipliers`, F2(x) - lambda.(G x + w_ext): a lower bound on the
  /// optimum whenever the problem is feasible.
  Scalar dual_objective{0};
  /// True when the unconstrained optimum was inside every cone (f_n > 0) and was returned at once.
  bool fast_path{false};
  /// O(n) passes over the contacts after the fast path (0 on it): the Newton iteration's and
  /// the least-residual problem's projections, the unit of ConstrainedSettings::max_passes.
  int passes{0};
};

/// The exact optimum of min 1/2 sum_i w_i |x_i - t_i|^2 s.t. G x + w_ext = 0, x_i in K_i
/// (K_i = ExactConeT<Model, Scalar>, see exact_cone.hpp), for any Grasp (fixed or Dynamic,
/// any model, float or double). No heap, no exceptions; at most settings.max_iterations
/// Newton iterations of O(n) each, each with at most settings.max_line_search O(n) passes, plus
/// (only when infeasibility is suspected) as many again for the least-residual problem;
/// `iterations` counts both, `passes` the passes, and settings.max_passes bounds them (the
/// deadline of a real-time caller: the solve then costs at most about the fast path plus
/// max_passes times one pass and one 6x6 solve).
///
/// Fast path, always tried first: solve_range_space's unconstrained optimum; if every force is
/// in its cone with f_n > 0 it is the answer (status Ok, iterations 0, fast_path true).
/// Otherwise the iteration starts from that optimum's multipliers (cold start), or from the
/// previous frame's `multipliers` when given (warm start: a 6-vector, so the contact count may
/// change between frames). A grasp matrix of rank < 6 or close to it (one that
/// solve_range_space's first factorisation does not accept) skips the fast path: the cold
/// start is then zero multipliers (detail::RankFallback::decline).
///
/// Wrenches are measured in the equilibrium norm |(f, m)|_L = |(f, m / L)|, L = max_i |r_i| the
/// grasp's longest lever arm (1 m if every contact is at the reference point), so that every
/// verdict is the same in every unit of length (docs/solve.md); `residual` still reports the
/// plain |G x + w_ext|.
///
/// Statuses and numbers:
/// - Ok: |G x + w_ext|_L <= tolerance (|w_ext|_L + |x|) (or, where coarser and
///   settings.resolution_bar, 16 eps times the residual's step when each multiplier moves by its
///   last place: sum_k |H e_k|_L |lambda_k|, H the Newton matrix) with duality gap |lambda.(G x + w_ext)| <=
///   gap_tolerance F2 (or the residual is at round-off). `forces` are in their cones, the KKT
///   conditions of every contact hold exactly (x_i is a projection), `objective` is F2.
/// - Infeasible: no forces in the cones balance w_ext (the grasp slips). `certificate` holds y
///   (see ConstrainedSolution). `forces` come closest: the best point, by the least-residual
///   objective |G x + w_ext|_L^2/2 + delta F2(x), that its solve over the cones meets (delta =
///   least_residual_weight times the largest diagonal entry of G W^-1 G^T in the norm's units,
///   moment entries over L^2), i.e. about the smallest equilibrium residual in |.|_L, ties
///   broken by F2; within 1e-5 (double) and 1e-2 (float) of the forces' scale of it on the
///   cvxopt reference instances.
///   `multipliers` are then that problem's (y = multipliers / |(multipliers_f, L multipliers_m)|).
///   Decided when the Newton iteration stalls (stall_limit = 8 steps in a row fail to halve
///   the residual of the last step that did: ConstrainedSettings), at its iteration bound,
///   or (double) once its growing multipliers point along a certificate
///   (certificate_check_growth); the least-residual solve has its own
///   max_iterations bound. In float (the defaults of ConstrainedSettings) the least-residual
///   solve is retried with a 100 and 10^4 times smaller delta (within that one bound) if its
///   certificate misses the tolerance, the direction of the diverging Newton multipliers is
///   tried as a second certificate, and a certificate found on a stall is used only if Newton
///   has not converged within 12 more iterations (infeasible_grace).
/// - IterationLimit: an iteration bound or the deadline (max_passes) was reached, or the line
///   search stalled, before the tolerance; `forces` = x(lambda) of the iterate with the least
///   residual met (in the cones), `multipliers` its lambda, `residual` what is left.
/// - InvalidInput: incomplete grasp, bad w_ext, bad settings or a non-finite warm start: zeros.
/// A grasp matrix of rank < 6 is not an error here: the answer is Ok if the wrench can still be
/// balanced inside the cones, Infeasible (with a certificate) otherwise.
template <class GraspT>
ConstrainedSolution<GraspT> solve_constrained(
    const GraspT& grasp, const Wrench<typename GraspT::ScalarType>& w_ext,
    const ConstrainedSettings<typename GraspT::ScalarType>& settings = ConstrainedSettings<typename GraspT::ScalarType>{});

/// As above, warm-started from `warm_multipliers` (the previous frame's solution.multipliers).
template <class GraspT>
ConstrainedSolution<GraspT> solve_constrained(const GraspT& grasp, const Wrench<typename GraspT::ScalarType>& w_ext,
                                              const ConstrainedSettings<typename GraspT::ScalarType>& settings,
                                              const Wrench<typename GraspT::ScalarType>& warm_multipliers);

// ---------------------------------------------------------------------------------------------
// Definitions.

namespace detail {

/// The fast path: the unconstrained optimum (solve_range_space's first factorisation only:
/// RankFallback::decline leaves Singular with zero multipliers), returned as the answer when
/// every force is in its cone with f_n > 0 (a feasible minimiser of the relaxed problem solves
/// the constrained one). Writes it into `sol` and its multipliers into `lambda`; returns true
/// if it is the answer (status Ok, fast_path true). One solve_range_space plus one
/// square-root-free cone test per contact (Cone::slips with zero slack; for hard fingers all
/// contacts at once by detail::coulomb_all_inside, vectorised where compiled in). The diagonal
/// of G W^-1 G^T goes to `gram_diagonal` (see range_space_solve).
template <class GraspT>
EIGEN_DONT_INLINE bool constrained_fast_path(const GraspT& grasp, const Wrench<typename GraspT::ScalarType>& w_ext,
                           ConstrainedSolution<GraspT>& sol, Wrench<typename GraspT::ScalarType>& lambda,
                           Wrench<typename GraspT::ScalarType>& gram_diagonal) {
  using S = typename GraspT::ScalarType;
  using Cone = ExactConeT<typename GraspT::ModelType, S>;
  constexpr int d = GraspT::dim;
  Wrench<S> rhs, res;
  // solve_constrained_impl has checked the grasp and w_ext.
  if (!range_space_solve<RankFallback::decline>(grasp, w_ext, sol, rhs, res, &gram_diagonal, true)) return false;
  lambda = sol.multipliers;
  bool inside = sol.status == Status::Ok;
  if constexpr (std::is_same<Cone, CoulombCone<S>>::value) {
    // All contacts at once (SIMD where compiled in; see coulomb_kernel.hpp), zero slack.
    inside = inside && detail::coulomb_all_inside_grasp(grasp, sol.forces);
  } else {
    for (int i = 0; i < grasp.size() && inside; ++i) {
      const Cone cone = Cone::from_contact(grasp.contact(i));
      const typename Cone::Vector x = sol.forces.template segment<d>(i * d);
      inside = cone.normal_part(x) > S(0) && !cone.slips(x, S(0));
    }
  }
  if (!inside) return false;
  // F2(x) = 1/2 lambda^T M lambda = 1/2 lambda.(rhs + res); the dual is F2 - lambda.res.
  const S l_rhs = lambda.dot(rhs), l_res = lambda.dot(res);
  sol.objective = S(0.5) * (l_rhs + l_res);
  sol.dual_objective = S(0.5) * (l_rhs - l_res);
  sol.iterations = 0;
  sol.fast_path = true;
  return true;
}

template <class GraspT>
ConstrainedSolution<GraspT> solve_constrained_impl(const GraspT& grasp,
                                                   const Wrench<typename GraspT::ScalarType>& w_ext,
                                                   const ConstrainedSettings<typename GraspT::ScalarType>& settings,
                                                   const Wrench<typename GraspT::ScalarType>* warm) {
  using S = typename GraspT::ScalarType;
  const int m = grasp.unknowns();
  ConstrainedSolution<GraspT> sol;
  if (!grasp.complete() || validate(w_ext) != Status::Ok || !valid_settings(settings) ||
      (warm != nullptr && !(detail::all_in_range(*warm)))) {
    fill_invalid(sol, m);
    return sol;
  }

  if (grasp.size() == 0) {  // nothing can push: feasible only for w_ext = 0
    fill_invalid(sol, m);
    sol.residual = detail::stable_norm(w_ext);
    if (sol.residual == S(0)) {
      sol.status = Status::Ok;
    } else {
      sol.status = Status::Infeasible;
      // Scaled by its largest component first: a denormal wrench's norm keeps too few bits to
      // divide by (w = (1, 0, 0, 0, 21, 0) units of the least float gave a norm of 21 units).
      const Wrench<S> unit = w_ext / w_ext.cwiseAbs().maxCoeff();
      sol.certificate = unit / unit.norm();
    }
    return sol;
  }

  // Start: the unconstrained optimum (returned at once if strictly inside), or the warm start.
  // The fast path writes every field of sol that an Ok answer documents (the rest keep their
  // constructed values); SemismoothNewton::run resets it for any other outcome.
  Wrench<S> lambda = Wrench<S>::Zero();
  Wrench<S> gram_diagonal = Wrench<S>::Zero();  // of G W^-1 G^T, from the fast path's solve
  if (constrained_fast_path(grasp, w_ext, sol, lambda, gram_diagonal)) return sol;
  SemismoothNewton<GraspT>::run(grasp, w_ext, settings, warm, lambda, gram_diagonal, sol);
  return sol;
}

}  // namespace detail

template <class GraspT>
ConstrainedSolution<GraspT> solve_constrained(const GraspT& grasp, const Wrench<typename GraspT::ScalarType>& w_ext,
                                              const ConstrainedSettings<typename GraspT::ScalarType>& settings) {
  return detail::solve_constrained_impl(grasp, w_ext, settings, nullptr);
}

template <class GraspT>
ConstrainedSolution<GraspT> solve_constrained(const GraspT& grasp, const Wrench<typename GraspT::ScalarType>& w_ext,
                                              const ConstrainedSettings<typename GraspT::ScalarType>& settings,
                                              const Wrench<typename GraspT::ScalarType>& warm_multipliers) {
  return detail::solve_constrained_impl(grasp, w_ext, settings, &warm_multipliers);
}

}  // namespace grip
