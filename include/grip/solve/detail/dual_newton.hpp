#pragma once
/// \file
/// Newton's method on the 6-dimensional dual of the force problem (namespace grip::detail):
/// solve_constrained's refinement of the interior-point answer and its warm start, a bounded
/// number of passes each, with no stopping rule but the tolerance.
///
/// For multipliers lambda the Lagrangian F2(x) - lambda.(G x + w_ext) is minimised over the cones
/// contact by contact by x_i(lambda) = P_i(t_i + w_i^-1 G_i^T lambda) (P_i the Euclidean
/// projection onto K_i; constrained_passes.hpp). The dual q(lambda) is concave and C^1 with
/// gradient -(G x(lambda) + w_ext) and generalised Hessian -sum_i w_i^-1 G_i J_i G_i^T, J_i in
/// the projection's generalised Jacobian (projection_jacobian.hpp). Every x(lambda) lies in the
/// cones and satisfies stationarity and complementarity exactly, so lambda is optimal exactly
/// when the residual G x(lambda) + w_ext vanishes: the semismooth Newton step
///     (H + mu D) d = -(G x + w_ext),   mu = |G x + w_ext|_L / scale,
/// (D the Gram diagonal, floored, in the units of |.|_L: equilibrium_norm.hpp) converges
/// quadratically from multipliers near the optimum, where the projections' regions are settled:
/// the interior-point method's, or the previous frame's. A step is taken in full or halved until
/// the dual rises by the Armijo fraction of its slope or the residual falls by it; each trial
/// is one pass. Reference: L. Qi and J. Sun, "A nonsmooth version of Newton's method", Math.
/// Program. 58 (1993); X.-Y. Zhao, D. Sun and K.-C. Toh, "A Newton-CG augmented Lagrangian
/// method for semidefinite programming", SIAM J. Optim. 20(4), 2010 (the projection dual).

#include <algorithm>
#include <cmath>
#include <limits>

#include "grip/core/scalar_traits.hpp"
#include "grip/core/types.hpp"
#include "grip/solve/detail/constrained_passes.hpp"
#include "grip/solve/detail/equilibrium_norm.hpp"
#include "grip/solve/symmetric_solve.hpp"

namespace grip {
namespace detail {

/// Newton's method on the dual at one grasp (see the file comment). Keeps the iterate: its
/// multipliers, forces, pass sums and Hessian; and the iterate of least residual met.
template <class GraspT>
class DualNewton {
 public:
  using S = typename GraspT::ScalarType;
  using Passes = ConstrainedPasses<GraspT>;
  using Forces = typename Passes::Forces;

  /// For `grasp` and `w_ext`, with the Gram diagonal of G W^-1 G^T (the Levenberg-Marquardt
  /// scaling) and the relative `tolerance` of an Ok answer. With `bounded`, every projection is
  /// onto the cone truncated at the contact's max_normal_force (project_accumulate_bounded: one
  /// contact at a time; not for soft fingers).
  DualNewton(const GraspT& grasp, const Wrench<S>& w_ext, const Wrench<S>& gram_diagonal, S tolerance,
             bool bounded = false)
      : grasp_(grasp),
        w_ext_(w_ext),
        passes_(grasp),
        norm_(EquilibriumNorm<S>::of(grasp)),
        tolerance_(tolerance),
        bounded_(bounded),
        forces_(passes_.make_forces()),
        trial_forces_(passes_.make_forces()),
        best_forces_(passes_.make_forces()) {
    const Wrench<S> t2 = norm_.weights().cwiseAbs2();
    const Wrench<S> scaled = gram_diagonal.cwiseProduct(t2);
    const S floor = S(1e-6f) * scaled.maxCoeff();
    for (int k = 0; k < 6; ++k) gram_scale_(k) = (scaled(k) > floor ? scaled(k) : floor) / t2(k);
    if (!gram_scale_.allFinite() || !(gram_scale_.minCoeff() > S(0))) gram_scale_.setOnes();
    if (bounded_) stacked_.setZero(grasp.unknowns());
    load_norm_ = norm_(w_ext);
    for (int i = 0; i < grasp.size(); ++i) squeeze_ = std::max(squeeze_, grasp.contact(i).squeeze);
  }

  /// From `lambda`, until passes() reaches `max_passes` (counting earlier runs; one pass at least);
  /// true when the iterate meets the tolerance (converged() then holds and the iterate is the
  /// answer).
  bool run(const Wrench<S>& lambda, int max_passes) {
    lambda_ = lambda;
    current_ = pass(lambda_, forces_, hessian_);
    keep_best();
    while (!converged()) {
      if (passes_made_ >= max_passes) return false;
      if (!step(max_passes)) return converged();
    }
    return true;
  }

  /// True when the current iterate meets the tolerance: |G x + w_ext|_L <= tolerance scale, scale
  /// = |w_ext|_L + |x| + max_i s_i. The forces x(lambda) are projections, so they are then the exact optimum
  /// for the wrench w_ext - (G x + w_ext).
  bool converged() const { return meets(tolerance_); }

  /// True when the current iterate meets `tolerance` in place of the solve's: |G x + w_ext|_L <=
  /// tolerance scale (scale as in converged()).
  bool meets(S tolerance) const { return norm_(current_.residual) <= tolerance * scale_of(current_); }

  const Wrench<S>& lambda() const { return lambda_; }
  const Forces& forces() const { return forces_; }
  const ConstrainedPass<S>& sums() const { return current_; }
  int passes() const { return passes_made_; }
  const Passes& engine() const { return passes_; }

  /// The iterate of least residual met (in |.|_L) becomes the current one.
  void restore_best() {
    lambda_ = best_lambda_;
    forces_ = best_forces_;
    current_ = best_sums_;
  }

 private:
  ConstrainedPass<S> pass(const Wrench<S>& l, Forces& x, Matrix6<S>& h) {
    ++passes_made_;
    if constexpr (GraspT::dim != 4) {
      if (bounded_) {
        GramAccumulator<S> acc;
        const ConstrainedPass<S> p = constrained_pass(grasp_, w_ext_, l, stacked_, &acc, true);
        h = acc.matrix();
        passes_.load(stacked_, x);
        return p;
      }
    }
    return passes_.pass(w_ext_, l, x, h);
  }
  S scale_of(const ConstrainedPass<S>& p) const { return p.scale + load_norm_ - w_ext_.norm() + squeeze_; }
  void keep_best() {
    const S rn = norm_(current_.residual);
    if (rn < best_residual_) {
      best_residual_ = rn;
      best_lambda_ = lambda_;
      best_forces_ = forces_;
      best_sums_ = current_;
    }
  }

  /// One Newton step with its line search; false if no trial is accepted within the passes left.
  bool step(int max_passes) {
    const S scale = scale_of(current_);
    const S rn = norm_(current_.residual);
    const S rel = scale > S(0) ? std::min(rn / scale, S(1)) : S(1);
    const S mu = rel * rel + S(16) * std::numeric_limits<S>::epsilon();
    Matrix6<S> m = hessian_;
    m.diagonal() += mu * gram_scale_;
    Wrench<S> dinv;
    for (int k = 0; k < 6; ++k) dinv(k) = S(1) / std::sqrt(m(k, k));
    scale_symmetric(m, dinv);
    const Wrench<S> d = dinv.cwiseProduct(solve_newton_6x6(m, Wrench<S>(-dinv.cwiseProduct(current_.residual)), mu));
    const S slope = -current_.residual.dot(d);
    if (!(slope > S(0)) || !d.allFinite()) return false;
    const S c = S(1e-4f);
    int trial_count = 0;
    for (S alpha = S(1); passes_made_ < max_passes; alpha *= S(0.5), ++trial_count) {
      // The second trial: the dual's first kink along d (where a projection changes region), when
      // it comes before half the step, a relative sqrt(eps) past it (the pass then takes its
      // Hessian from the region entered).
      if (trial_count == 1) alpha = second_trial(passes_, lambda_, d, alpha);
      const Wrench<S> lt = lambda_ + alpha * d;
      if (lt == lambda_) return false;
      const ConstrainedPass<S> trial = pass(lt, trial_forces_, trial_hessian_);
      const S slack =
          S(16) * std::numeric_limits<S>::epsilon() * (std::abs(trial.dual) + std::abs(current_.dual) + current_.f2);
      if (trial.dual >= current_.dual + c * alpha * slope - slack || norm_(trial.residual) <= (S(1) - c * alpha) * rn) {
        lambda_ = lt;
        forces_ = trial_forces_;
        hessian_ = trial_hessian_;
        current_ = trial;
        keep_best();
        return true;
      }
    }
    return false;
  }

  const GraspT& grasp_;
  const Wrench<S>& w_ext_;
  const Passes passes_;
  const EquilibriumNorm<S> norm_;
  const S tolerance_;
  const bool bounded_;
  S load_norm_{0};                              ///< |w_ext|_L
  S squeeze_{0};                                ///< max_i s_i
  typename GraspT::ForceVector stacked_;        ///< the bounded pass's forces, stacked
  Wrench<S> gram_scale_{Wrench<S>::Ones()};     ///< the Levenberg-Marquardt scaling D (the Gram diagonal, floored)
  Wrench<S> lambda_{Wrench<S>::Zero()};         ///< the current multipliers
  Forces forces_, trial_forces_, best_forces_;  ///< x(lambda) at the current, trial and best iterates
  Matrix6<S> hessian_, trial_hessian_;          ///< minus the dual's generalised Hessian at current and trial
  ConstrainedPass<S> current_, best_sums_;      ///< the pass sums at the current and best iterates
  Wrench<S> best_lambda_{Wrench<S>::Zero()};    ///< the multipliers of least residual met
  S best_residual_{std::numeric_limits<S>::infinity()};  ///< their residual, |G x + w_ext|_L
  int passes_made_{0};
};

}  // namespace detail
}  // namespace grip
