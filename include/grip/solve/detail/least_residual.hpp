#pragma once
/// \file
/// Phase 1 of solve_constrained (namespace grip::detail): the least-residual problem, solved
/// when the Newton iteration stalls, and the test of an infeasibility certificate.
///
/// The least-residual forces come closest to equilibrium inside the cones (ties broken by F2);
/// for any multipliers of its dual, the projections make their direction an infeasibility
/// certificate up to a term of order delta, so one solve both decides infeasibility and gives
/// the forces that an Infeasible answer returns.

#include <algorithm>
#include <cmath>
#include <limits>

#include "grip/contact/contact_model.hpp"
#include "grip/contact/exact_cone.hpp"
#include "grip/core/types.hpp"
#include "grip/solve/constrained_settings.hpp"
#include "grip/solve/detail/constrained_passes.hpp"
#include "grip/solve/detail/equilibrium_norm.hpp"
#include "grip/solve/symmetric_solve.hpp"

namespace grip {
namespace detail {

/// The Newton direction d of least_residual's dual: (T H T + delta I) d = delta g, H the
/// Hessian `h` (overwritten: each iteration reads its Hessian once), T = `norm`'s weights, solved
/// Jacobi-scaled with the floor of 16 eps. Out of line, so that its frame is not on the stack
/// under the passes.
template <class S>
EIGEN_DONT_INLINE Wrench<S> least_residual_direction(Matrix6<S>& h, const EquilibriumNorm<S>& norm, S delta,
                                                     const Wrench<S>& g) {
  scale_symmetric(h, norm.weights());  // T H T
  h.diagonal().array() += delta;
  const Wrench<S> e = h.diagonal().cwiseSqrt().cwiseInverse();
  scale_symmetric(h, e);  // Jacobi-scaled in place
  const S floor = S(constrained_roundoff) * std::numeric_limits<S>::epsilon();
  return e.cwiseProduct(solve_newton_6x6(h, Wrench<S>(delta * e.cwiseProduct(g)), floor));
}

/// Phase 1: forces in the cones that come closest to equilibrium. Solves
///   min over x in the cones of 1/2 |G x + w_ext|_L^2 + delta/2 sum_i w_i |x_i - t_i|^2
/// (|.|_L = |T .|, T = diag(1, 1, 1, 1/L, 1/L, 1/L): EquilibriumNorm; delta small: the least
/// residual, ties broken by F2) through its strongly concave dual
///   phi(l) = -1/2 |l|^2 + l.T(G x(l) + w_ext) + delta F2(x(l)), x_i(l) = P_i(t_i - G_i^T T l/(delta w_i)),
/// by the same semi-smooth Newton method (Hessian -(I + T sum G_i J_i G_i^T T/(delta w_i))). At its
/// maximiser l = T(G x + w_ext). For ANY l, x_i(l) is a projection, so G_i^T T l + delta w_i (x_i - t_i)
/// lies in K_i^* exactly: T l/|l| is an infeasibility certificate (|T l / |l||_L* = 1) up to
/// delta w_i |x_i - t_i| / |l|.
/// `scale_shift` = |w_ext|_L - |w_ext| turns a pass's scale |w_ext| + |x| into the norm's units.
/// Writes the forces into x, the multipliers l (in the norm's units) into lambda, and returns the iterations used (at
/// most `max_iterations`; the other bounds and constants from `settings`). Each pass is counted in `budget`; none is started once it is
/// spent (then the best point met so far is the answer; with no pass left at the start,
/// lambda = 0, f2 = 0 and x unchanged). `xt` and `trial_h` are scratch lent by the caller (each
/// pass's forces and the line search's Hessian; their contents on return are unspecified), so
/// that phase 1 adds no second copy of them to the stack.
template <class Passes>
int least_residual(const Passes& passes, const Wrench<typename Passes::Scalar>& w_ext,
                   const EquilibriumNorm<typename Passes::Scalar>& norm, typename Passes::Scalar scale_shift,
                   typename Passes::Scalar delta, const ConstrainedSettings<typename Passes::Scalar>& settings,
                   int max_iterations, PassBudget& budget, typename Passes::Forces& x,
                   Wrench<typename Passes::Scalar>& lambda, typename Passes::Scalar& f2,
                   typename Passes::Forces& xt, Matrix6<typename Passes::Scalar>& trial_h) {
  using S = typename Passes::Scalar;
  const S eps = std::numeric_limits<S>::epsilon();
  lambda.setZero();
  f2 = S(0);
  if (!budget.left()) return 0;
  // The Hessian at the current point (trial_h: at the line-search point), from their passes;
  // each iteration's direction consumes it (h_fresh: not yet consumed).
  Matrix6<S> cur_h;
  bool h_fresh = true;
  // Continuation: delta starts at delta_max (a well-scaled problem) and drops `drop`-fold (100)
  // each time the current problem is solved, down to the requested delta (each stage
  // warm-started from the last one's forces).
  S dl = delta;
  const S delta_max = delta / settings.least_residual_weight;
  const S drop = settings.least_residual_continuation;
  while (dl * drop <= delta_max) dl *= drop;
  const auto phi = [&](const ConstrainedPass<S>& p, const Wrench<S>& l) {
    return -S(0.5) * l.squaredNorm() + l.dot(norm.to_units(p.residual)) + dl * p.f2;
  };
  // The pass's multipliers for l: -T l / dl (physical).
  const auto input = [&](const Wrench<S>& l) { return Wrench<S>(-norm.to_units(l) / dl); };
  // Every pass writes its forces into xt.
  ConstrainedPass<S> cur = budget.run(passes, w_ext, input(lambda), xt, cur_h);
  S cur_phi = phi(cur, lambda);
  // The forces returned (into x) are the best point met by the requested problem's objective
  // |r|^2/2 + delta F2: at the last, tiny delta, x(l) is so sensitive to l that the last
  // iterate's forces can lie far from the least residual even though l itself is right.
  S best_objective = std::numeric_limits<S>::infinity(), best_f2 = S(0);
  const auto keep = [&]() {  // after each new iterate's pass, whose forces are in xt
    const S p = S(0.5) * norm.to_units(cur.residual).squaredNorm() + delta * cur.f2;
    if (p < best_objective) {
      best_objective = p;
      best_f2 = cur.f2;
      x = xt;
    }
  };
  keep();
  int it = 0;
  for (; it < max_iterations; ++it) {
    // True when this iteration ends the current stage of the continuation (solved, at
    // round-off, or no step accepted): the next one starts from the current l.
    bool stage_end = false;
    const Wrench<S> g = norm.to_units(cur.residual) - lambda;  // grad phi
    const S scale = cur.scale + scale_shift;  // |w_ext|_L + |x|
    if (g.norm() <= settings.tolerance * scale ||
        (dl > delta && g.norm() <= settings.least_residual_stage_tolerance * scale)) {
      stage_end = true;
    } else {
      const Wrench<S> dir = least_residual_direction(cur_h, norm, dl, g);
      h_fresh = false;
      const S slope = g.dot(dir);
      if (dir.norm() <= S(4) * eps * (lambda.norm() + scale) || !(slope > S(0))) {  // at round-off
        stage_end = true;
      } else {
        if (!dir.allFinite()) break;  // slope > 0 here: the branch above took the rest
        bool accepted = false;
        S alpha = S(1);
        Wrench<S> lt;
        ConstrainedPass<S> trial;
        S trial_phi = cur_phi;
        for (int ls = 0; ls < settings.max_line_search && budget.left(); ++ls, alpha *= S(0.5)) {
          // The full step failed: try the first kink of phi along dir if it comes before the half.
          if (ls == 1) alpha = second_trial(passes, input(lambda), input(dir), lambda, dir, alpha, false);
          // A step below l's resolution, 16 eps |l|, moves it by rounding alone, yet the
          // round-off slack of the Armijo test can accept it, and the next iteration would
          // take the same step again, to the iteration bound: it ends the stage instead.
          if (alpha * dir.norm() <= S(constrained_roundoff) * eps * lambda.norm()) break;
          lt = lambda + alpha * dir;
          if (lt == lambda) break;  // (l = 0: a step that rounds away entirely)
          trial = budget.run(passes, w_ext, input(lt), xt, trial_h);
          trial_phi = phi(trial, lt);
          const S slack =
              S(constrained_roundoff) * eps * (std::abs(cur_phi) + std::abs(trial_phi) + lt.squaredNorm());
          if (trial_phi >= cur_phi + settings.armijo * alpha * slope - slack) {
            accepted = true;
            break;
          }
        }
        if (accepted) {
          lambda = lt;
          cur_h = trial_h;
          h_fresh = true;
          cur = trial;
          cur_phi = trial_phi;
          keep();
        } else {
          stage_end = true;
        }
      }
    }
    if (stage_end) {  // the next stage; none after the last
      if (!(dl > delta) || !budget.left()) break;
      // It starts from this stage's forces: l scaled with delta keeps the pass's multipliers
      // -T l / delta, so x(l) too. Keeping l instead would scale them by the drop, and x(l),
      // which depends on l as 1 / delta, would jump far from the forces just found (each
      // stage then cost 20 to 40 passes; slipping grasps' p99 was 2.4 times today's).
      const S next = dl / drop < delta ? delta : dl / drop;
      lambda *= next / dl;
      dl = next;
      // Same pass input, so the same forces and sums: a stage solved to its tolerance keeps
      // them and its unconsumed Hessian (forces in xt: no trial since), and only phi changes.
      if (!h_fresh) {
        cur = budget.run(passes, w_ext, input(lambda), xt, cur_h);
        h_fresh = true;
      }
      cur_phi = phi(cur, lambda);
      keep();
    }
  }
  f2 = best_f2;
  return it;
}

/// True when y (|y|_L* = 1, see EquilibriumNorm) certifies infeasibility: y.w_ext > 0 and
/// G_i^T y in K_i^* for all i, up to `tol`: the distance from G_i^T y to K_i^* is at most
/// tol (1 + |r_i| / L) (the scale of G_i^T y for such a y), and y.w_ext > guard tol |w_ext|_L,
/// which keeps directions of round-off out (ConstrainedSettings::certificate_guard). Both
/// tests are the same in every unit of length.
template <class GraspT>
bool is_infeasibility_certificate(const GraspT& grasp, const Wrench<typename GraspT::ScalarType>& w_ext,
                                  const Wrench<typename GraspT::ScalarType>& y,
                                  const EquilibriumNorm<typename GraspT::ScalarType>& norm,
                                  typename GraspT::ScalarType tol, typename GraspT::ScalarType guard) {
  using S = typename GraspT::ScalarType;
  using M = typename GraspT::ModelType;
  using Cone = ExactConeT<M, S>;
  const S wtol = tol * guard;
  if (!(y.dot(w_ext) > wtol * norm(w_ext))) return false;
  for (int i = 0; i < grasp.size(); ++i) {
    const auto& c = grasp.contact(i);
    const typename GraspT::ContactVector z = M::wrench_transpose(c, y);
    const auto dual = Cone::from_contact(c).dual();
    if (!((z - dual.project(z)).norm() <= tol * (S(1) + c.position.norm() * norm.inverse))) return false;
  }
  return true;
}

/// The direction of diverging Newton multipliers as a certificate: y = -lambda / |lambda|_L*,
/// written into `y`; true if it checks out (is_infeasibility_certificate with the settings'
/// certificate_tolerance and certificate_guard). x_i(lambda) is a projection, so -G_i^T lambda
/// lies in K_i^* up to w_i |x_i - t_i| / |lambda|: a certificate once |lambda| has grown large
/// along it. False (y unspecified) for lambda = 0 or not finite.
template <class GraspT>
bool multiplier_direction_certificate(const GraspT& grasp, const Wrench<typename GraspT::ScalarType>& w_ext,
                                      const Wrench<typename GraspT::ScalarType>& lambda,
                                      const EquilibriumNorm<typename GraspT::ScalarType>& norm,
                                      const ConstrainedSettings<typename GraspT::ScalarType>& settings,
                                      Wrench<typename GraspT::ScalarType>& y) {
  using S = typename GraspT::ScalarType;
  const S ln = norm.dual(lambda);
  if (!(ln > S(0)) || !std::isfinite(ln)) return false;
  y = -lambda / ln;
  return is_infeasibility_certificate(grasp, w_ext, y, norm, settings.certificate_tolerance, settings.certificate_guard);
}

}  // namespace detail
}  // namespace grip
