#pragma once
/// \file
/// Settings of solve_constrained: tolerances and bounds, and every tuning constant of its
/// Newton iteration, its infeasibility decision and its least-residual problem, each with the
/// reason for its default. The per-scalar defaults come from ScalarTraits.

#include <cmath>
#include <limits>

#include "grip/core/scalar_traits.hpp"

namespace grip {

/// Tolerances, bounds and tuning constants of solve_constrained for scalar type Scalar.
///
/// The defaults depend on Scalar through ScalarTraits<Scalar>::is_single_precision (double:
/// tolerance 1e-12; float: 1e-5) and are what the tests hold the solver to. Every real member
/// must be finite and positive, counts >= 1 (infeasible_grace and stall_growth_allowance
/// >= 0), armijo < 1,
/// certificate_retry_factor <= 1 and least_residual_continuation > 1, or the solver answers
/// InvalidInput. An aggregate: set members by name after default construction.
template <class Scalar>
struct ConstrainedSettings {
  /// Relative equilibrium tolerance: Ok when |G x + w_ext|_L <= tolerance * (|w_ext|_L + |x|)
  /// (|(f, m)|_L = |(f, m / L)|, L the grasp's longest lever arm: see solve_constrained)
  /// and the duality gap |lambda.(G x + w_ext)| <= gap_tolerance * F2(x) (or the residual is at
  /// round-off, 16 eps times that scale).
  Scalar tolerance{ScalarTraits<Scalar>::is_single_precision ? Scalar(1e-5f) : Scalar(1e-12)};
  /// Relative duality-gap tolerance (see tolerance); the objective is then within about this
  /// relative error of the optimum.
  Scalar gap_tolerance{ScalarTraits<Scalar>::is_single_precision ? Scalar(1e-5f) : Scalar(1e-10)};
  /// Smallest Levenberg-Marquardt regularisation of the Jacobi-scaled 6x6 Newton matrix (the
  /// regularisation follows the residual down to it near the optimum).
  Scalar regularisation{ScalarTraits<Scalar>::is_single_precision ? Scalar(1e-6f) : Scalar(1e-13)};
  /// Relative slack of the infeasibility certificate: a y of dual norm |(y_f, L y_m)| = 1 is
  /// accepted when every G_i^T y lies in the dual cone up to certificate_tolerance *
  /// (1 + |r_i| / L) and y.w_ext exceeds certificate_guard * certificate_tolerance * |w_ext|_L.
  Scalar certificate_tolerance{ScalarTraits<Scalar>::is_single_precision ? Scalar(2e-3f) : Scalar(1e-5)};
  /// Weight delta (relative to the largest diagonal entry of G W^-1 G^T, moment entries over
  /// L^2) of F2 in the least-residual problem min |G x + w_ext|_L^2/2 + delta F2(x)/2 over the cones, solved when
  /// the Newton iteration stalls, to decide infeasibility and give the closest forces.
  Scalar least_residual_weight{ScalarTraits<Scalar>::is_single_precision ? Scalar(1e-6f) : Scalar(1e-12)};
  /// Bound on Newton iterations (each O(n)); the worst-case time is proportional to it.
  int max_iterations{60};
  /// Bound on step halvings per line search (each one more O(n) pass).
  int max_line_search{30};
  /// Deadline: bound on the O(n) passes over the contacts after the fast path, counting the
  /// Newton iteration's and the least-residual problem's alike (ConstrainedSolution::passes).
  /// When it is reached the solver stops and answers IterationLimit with the least-residual
  /// iterate it has met (forces in their cones), or Infeasible if a certificate was already
  /// found. The worst-case time of a solve is then about the fast path plus max_passes times
  /// (one pass + one 6x6 solve): docs/solve.md gives both per contact count. Default: the
  /// largest int, no deadline (the iteration bounds govern).
  int max_passes{std::numeric_limits<int>::max()};

  // The Newton iteration.

  /// Armijo constant c of both line searches (Newton's on the dual q, the least-residual
  /// problem's on its dual): a step alpha d is accepted when the objective rises by at least
  /// c alpha times its slope along d (less 16 eps of round-off slack). Small, the textbook
  /// value, so that the full semi-smooth Newton step is taken near the optimum (quadratic
  /// convergence) and a cut step only where the model is poor. The default is the float
  /// literal 1e-4f in both precisions (in double 9.99999975e-5).
  Scalar armijo{Scalar(1e-4f)};
  /// Floor of the Jacobi scaling D of the Levenberg-Marquardt term, relative to its largest
  /// entry, both taken in the units of the equilibrium norm (moment entries over L^2, L the
  /// longest lever arm): each diagonal entry of G W^-1 G^T below jacobi_floor times the
  /// largest is raised to it. It keeps D^-1/2 finite when a diagonal entry vanishes (every
  /// normal through the reference point, rank < 6), the same in every unit of length.
  /// Float literal 1e-6f in both precisions.
  Scalar jacobi_floor{Scalar(1e-6f)};
  /// Newton iterations in a row that fail to halve the residual after which infeasibility is
  /// suspected and decided once by the least-residual problem. Halving is measured against
  /// the residual of the last iteration that halved it or grew the dual (a growth step of
  /// stall_growth_allowance; not the previous iteration's), and an iteration whose rise of the
  /// dual is at most half that of the last one that reset the count is no stall either (a
  /// zig-zag across a kink that converges), so that
  /// a residual that swings up and down by orders of magnitude (a diverging iteration on an
  /// infeasible grasp) is seen to stall. Not 3: feasible instances whose active set is still
  /// settling (nearly infeasible ones, with forces of 1000 N for a 5 N load) stall for 3 to 15
  /// and then converge, and the least-residual solve spent on them costs 30 to 100 passes.
  /// Double 16: most slipping grasps are sent to the least-residual problem sooner, by
  /// certificate_check_growth, so a longer wait costs them nothing. Float 8: without that
  /// trigger, every slipping grasp pays the wait.
  int stall_limit{ScalarTraits<Scalar>::is_single_precision ? 8 : 16};
  /// Full Newton steps (no step halved) that at least double a positive dual q are not
  /// counted as stalls, up to this many per solve: the multipliers of a nearly infeasible
  /// grasp grow about tenfold per step toward an optimum far away, and the least-residual
  /// problem that a stall starts would cost more than the few steps left. 8: beyond it a
  /// growth that goes on is taken for divergence (an infeasible grasp). >= 0; 0 counts every
  /// step that fails to halve.
  int stall_growth_allowance{8};
  /// From this many growth steps on (full steps that double the dual, see
  /// stall_growth_allowance), each one tests the direction -lambda of the growing multipliers
  /// as an infeasibility certificate (one O(n) loop, no pass), and one that checks out starts
  /// the least-residual problem at once: an infeasible grasp's multipliers grow tenfold per
  /// step along a certificate, and waiting for the stall costs 10 to 20 passes. Only a
  /// trigger: the verdict is the least-residual problem's, as after a stall. Double 3 (the
  /// growth has settled on its direction by then); float never (the largest int): its
  /// certificate_tolerance of 2e-3 passes the growth direction of nearly infeasible grasps
  /// that hold, and its least-residual solve then confirms them. >= 1.
  int certificate_check_growth{ScalarTraits<Scalar>::is_single_precision ? std::numeric_limits<int>::max() : 3};
  /// Newton iterations still allowed after an infeasibility certificate was found on a stall:
  /// Infeasible is answered only if Newton has not converged within them. Float 12: a nearly
  /// infeasible feasible instance can stall early and pass the float certificate tolerance
  /// (2e-3), then converge. Double 0: the verdict is immediate (its certificates are tight).
  int infeasible_grace{ScalarTraits<Scalar>::is_single_precision ? 12 : 0};

  // The infeasibility decision.

  /// Smallest least residual, in units of tolerance * |w_ext|_L, that may be taken for
  /// infeasibility (below it the residual is round-off of a feasible problem and its
  /// direction is not tried as a certificate). Double 1000; float 10 (1e-4 relative): there
  /// least residuals of 1e-3 |w_ext| are genuine (cvxopt reference instances) while round-off
  /// stays near 1e-6 |w_ext|.
  Scalar infeasibility_bar{ScalarTraits<Scalar>::is_single_precision ? Scalar(10) : Scalar(1000)};
  /// Least-residual solves tried for a certificate, each with delta certificate_retry_factor
  /// times the previous one (all within one budget of max_iterations). The certificate's error
  /// is delta w_i |x_i - t_i| / |y|, and nearly infeasible grasps need large least-residual
  /// forces: float 3 (delta 1e-6, then 100 and 10^4 times smaller); double 1.
  int certificate_attempts{ScalarTraits<Scalar>::is_single_precision ? 3 : 1};
  /// Factor of delta from one certificate attempt to the next (see certificate_attempts).
  Scalar certificate_retry_factor{Scalar(0.01)};
  /// Factor of the guard y.w_ext > certificate_guard * certificate_tolerance * |w_ext| that
  /// keeps directions of round-off out of certificates. Double 1; float 0.1 (2e-4 |w_ext|,
  /// still 1000 times float round-off): a nearly feasible grasp (cvxopt reference instance 195:
  /// least residual 8e-4 |w_ext|) has a genuine certificate with y.w_ext of 7.5e-4 |w_ext|,
  /// below the float certificate_tolerance of 2e-3.
  Scalar certificate_guard{ScalarTraits<Scalar>::is_single_precision ? Scalar(0.1) : Scalar(1)};
  /// Let Ok accept a residual at the multipliers' own resolution, 16 eps times
  /// sum_k |H e_k|_L |lambda_k|, where that is coarser than `tolerance` (a soft finger's torsion
  /// on a grasp of micrometres: its moment multiplier is large and the residual steps in units
  /// of its last place), once the duality gap has closed. Double only by default: float's gap
  /// tolerance (1e-5 of F2) is too loose to guard it, and nearly infeasible float grasps, whose
  /// multipliers grow, would stop with residuals of 1e-3 of their scale.
  bool resolution_bar{!ScalarTraits<Scalar>::is_single_precision};
  /// When the least-residual certificates fail, also test the direction -lambda of the diverging
  /// Newton multipliers (x_i(lambda) is a projection, so -G_i^T lambda lies in K_i^* up to
  /// w_i |x_i - t_i| / |lambda|). Float only by default: float least-residual solves can stop
  /// short of the tolerance; double results are validated by the least-residual certificate alone.
  bool multiplier_certificate{ScalarTraits<Scalar>::is_single_precision};

  // The least-residual problem (continuation on delta).

  /// Relative gradient tolerance of each intermediate stage of the continuation (the last
  /// stage is solved to `tolerance`): an intermediate stage only warm-starts the next, so
  /// 1e-3 of the scale suffices. Float literal 1e-3f in both precisions.
  Scalar least_residual_stage_tolerance{Scalar(1e-3f)};
  /// Ratio of delta from one stage of the continuation to the next: it starts at
  /// delta / least_residual_weight (a well-scaled problem) and drops by this factor, down to
  /// the requested delta. 100: each stage's answer is a good start for the next (a few Newton
  /// iterations each), and double's least_residual_weight of 1e-12 takes about six drops.
  Scalar least_residual_continuation{Scalar(100)};
};

namespace detail {

/// True when every member of `s` is in its documented range (see ConstrainedSettings).
template <class Scalar>
bool valid_settings(const ConstrainedSettings<Scalar>& s) {
  const auto pos = [](Scalar v) { return std::isfinite(v) && v > Scalar(0); };
  return pos(s.tolerance) && pos(s.gap_tolerance) && pos(s.regularisation) && pos(s.certificate_tolerance) &&
         pos(s.least_residual_weight) && s.max_iterations >= 1 && s.max_line_search >= 1 && s.max_passes >= 1 && pos(s.armijo) &&
         s.armijo < Scalar(1) && pos(s.jacobi_floor) && s.stall_limit >= 1 && s.stall_growth_allowance >= 0 &&
         s.certificate_check_growth >= 1 && s.infeasible_grace >= 0 &&
         pos(s.infeasibility_bar) && s.certificate_attempts >= 1 && pos(s.certificate_retry_factor) &&
         s.certificate_retry_factor <= Scalar(1) && pos(s.certificate_guard) &&
         pos(s.least_residual_stage_tolerance) && pos(s.least_residual_continuation) &&
         s.least_residual_continuation > Scalar(1);
}

}  // namespace detail

}  // namespace grip
