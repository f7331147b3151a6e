#pragma once
/// \file
/// solve_constrained's iteration after the fast path (namespace grip::detail): semi-smooth
/// Newton ascent on the 6-dimensional dual, with the infeasibility decision by phase 1
/// (least_residual.hpp). Included by solve_constrained.hpp, which defines ConstrainedSolution.
///
/// For multipliers lambda the Lagrangian L(x, lambda) = F2(x) - lambda.(G x + w_ext) is
/// minimised over the cones by x_i(lambda) = P_i(v_i), v_i = t_i + w_i^-1 G_i^T lambda (P_i:
/// Euclidean projection onto K_i; the weight is a scalar, so the weighted projection is the
/// Euclidean one). The dual function q(lambda) = L(x(lambda), lambda) is concave and C^1 with
/// gradient -(G x(lambda) + w_ext); its generalised Hessian is -sum_i w_i^-1 G_i J_i G_i^T with
/// J_i a generalised Jacobian of P_i (projection_jacobian.hpp). Each iteration: a regularised
/// 6x6 solve for the direction (the matrix comes from the previous pass), and an Armijo line
/// search on q (one pass per trial, constrained_passes.hpp). Every x(lambda) lies in the cones
/// and satisfies stationarity and complementarity exactly; only the equilibrium residual is
/// driven to zero.

#include <algorithm>
#include <cmath>
#include <limits>

#include <Eigen/Core>

#include "grip/contact/contact_model.hpp"
#include "grip/core/status.hpp"
#include "grip/core/types.hpp"
#include "grip/solve/constrained_settings.hpp"
#include "grip/solve/detail/constrained_passes.hpp"
#include "grip/solve/detail/equilibrium_norm.hpp"
#include "grip/solve/detail/least_residual.hpp"
#include "grip/solve/symmetric_solve.hpp"

namespace grip {

template <class GraspT>
struct ConstrainedSolution;  // solve_constrained.hpp

namespace detail {

/// `sol` as InvalidInput: zero forces (`unknowns` of them) and multipliers, the largest residual.
template <class GraspT>
void fill_invalid(ConstrainedSolution<GraspT>& sol, int unknowns) {
  sol.forces.setZero(unknowns);
  sol.multipliers.setZero();
  sol.status = Status::InvalidInput;
  sol.residual = std::numeric_limits<typename GraspT::ScalarType>::max();
  sol.iterations = 0;
}

/// The semi-smooth Newton iteration of solve_constrained (see the file comment), with its state
/// in members: the iterate (lambda_, its forces x_ and pass sums cur_, the Hessian sums cur_h_),
/// the Levenberg-Marquardt damping, the stall count, and phase 1's verdict, kept pending in the
/// p_* members until apply_infeasible(). Entry: run().
template <class GraspT>
class SemismoothNewton {
 public:
  using S = typename GraspT::ScalarType;
  using Passes = ConstrainedPasses<GraspT>;
  using Forces = typename Passes::Forces;

  /// Runs the iteration after the fast path failed: `lambda` and `gram_diagonal` as
  /// constrained_fast_path left them (the start, unless `warm` is given), every field of `sol`
  /// written. Out of line, so that the fast path (a real-time loop's common case) skips its frame.
  static EIGEN_DONT_INLINE void run(const GraspT& grasp, const Wrench<S>& w_ext, const ConstrainedSettings<S>& settings,
                                    const Wrench<S>* warm, const Wrench<S>& lambda, const Wrench<S>& gram_diagonal,
                                    ConstrainedSolution<GraspT>& sol) {
    fill_invalid(sol, grasp.unknowns());
    SemismoothNewton newton(grasp, w_ext, settings, sol,
                            warm != nullptr ? *warm : (lambda.allFinite() ? lambda : Wrench<S>::Zero()), gram_diagonal);
    newton.iterate();
    newton.finish();
  }

 private:
  SemismoothNewton(const GraspT& grasp, const Wrench<S>& w_ext, const ConstrainedSettings<S>& settings,
                   ConstrainedSolution<GraspT>& sol, const Wrench<S>& lambda, const Wrench<S>& gram_diagonal)
      : grasp_(grasp), w_ext_(w_ext), settings_(settings), sol_(sol), m_(grasp.unknowns()), lambda_(lambda),
        passes_(grasp), x_(passes_.make_forces()), xt_(passes_.make_forces()), best_x_(passes_.make_forces()),
        p_x_(passes_.make_forces()), budget_{settings.max_passes}, grace_(settings.infeasible_grace),
        norm_(EquilibriumNorm<S>::of(grasp)), w_norm_l_(norm_(w_ext)), scale_shift_(w_norm_l_ - w_ext.norm()) {
    // Jacobi scaling D of the Levenberg-Marquardt term: the unconstrained Gram diagonal, floored
    // in the equilibrium norm's units (moments per lever arm L), the same floor in every unit.
    const Wrench<S> t2 = norm_.weights().cwiseAbs2();  // (1, 1 / L^2)
    const Wrench<S> scaled = gram_diagonal.cwiseProduct(t2);
    jacobi_max_ = scaled.maxCoeff();
    const S floor = settings_.jacobi_floor * jacobi_max_;
    for (int k = 0; k < 6; ++k) jacobi_(k) = (scaled(k) > floor ? scaled(k) : floor) / t2(k);
    dinv_ = jacobi_.cwiseSqrt().cwiseInverse();
    cur_ = budget_.run(passes_, w_ext_, lambda_, x_, cur_h_);  // always allowed: max_passes >= 1
    keep_best();
    stall_ref_ = rn_;
    last_dual_ = cur_.dual;
  }

  /// Keeps the iterate if its residual is the least met so far: the answer under IterationLimit.
  void keep_best() {
    rn_ = norm_(cur_.residual);
    if (rn_ < best_rn_) {
      best_rn_ = rn_;
      best_lambda_ = lambda_;
      best_x_ = x_;
      best_ = cur_;
    }
  }

  /// The iteration until convergence, the bound, the end of ascent or an infeasibility verdict;
  /// at the bound, infeasibility is decided (or the pending verdict applied) once more.
  void iterate() {
    for (;; ++it_) {
      const S rn = rn_;
      const S scale = scale_of(cur_);
      const S floor = S(constrained_roundoff) * eps() * scale;
      // The tolerance, or the multipliers' own resolution where that is coarser (see
      // multiplier_resolution; evaluated only once the gap has closed and the last step
      // failed to halve the residual: a converging iteration never pays for it), with the
      // duality gap closed either way.
      const bool tolerance_met = rn <= settings_.tolerance * scale;
      const bool try_resolution = settings_.resolution_bar && stall_ > 0;
      if (rn <= floor || ((tolerance_met || try_resolution) &&
                          std::abs(lambda_.dot(cur_.residual)) <= settings_.gap_tolerance * cur_.f2 &&
                          (tolerance_met || rn <= S(constrained_roundoff) * eps() * multiplier_resolution()))) {
        status_ = Status::Ok;
        break;
      }
      if (it_ >= settings_.max_iterations) break;
      if (!newton_step(rn)) break;
      if (!watch_stall()) break;
    }
    if (status_ == Status::IterationLimit) {
      if (pending_ || (!phase1_done_ && decide_infeasible())) apply_infeasible();
      else restore_best();
    }
  }

  /// Under IterationLimit: the least-residual iterate met becomes the answer.
  void restore_best() {
    lambda_ = best_lambda_;
    x_ = best_x_;
    cur_ = best_;
    rn_ = best_rn_;
  }

  /// One Newton step from lambda_ (residual norm `rn`): the direction from
  /// (H + mu D) d = -r, H = sum w^-1 G J G^T, solved Jacobi-scaled, with
  /// mu = min(damping, |r|/scale) + regularisation (quadratic convergence near the optimum, and
  /// steps that grow geometrically along a direction of unbounded ascent: infeasible problems),
  /// then the Armijo line search on q (its second trial at q's first kink, first_break, if
  /// nearer than half; where q's rounding, `noise` (lambda.(G x + w_ext) sums terms of
  /// |lambda|_L* scale: multipliers of 1e6 to 1e8 on a nearly infeasible grasp), hides the rise
  /// Armijo asks, a point that keeps q within it and cuts the residual by the Armijo fraction).
  /// Its point becomes the iterate; false if none is accepted (Ok if in tolerance).
  bool newton_step(S rn) {
    const S reg = settings_.regularisation;
    Matrix6<S> h = cur_h_;
    const S scale = scale_of(cur_);
    const S rel = scale > S(0) ? rn / scale : S(1);
    const S mu = (damping_ < rel ? damping_ : rel) + reg;
    h.diagonal() += mu * jacobi_;
    scale_symmetric(h, dinv_);  // Jacobi-scaled in place
    const Wrench<S> dir = dinv_.cwiseProduct(solve_newton_6x6(h, Wrench<S>(-dinv_.cwiseProduct(cur_.residual)), mu));
    const S slope = -cur_.residual.dot(dir);  // q'(0) along dir, > 0
    bool accepted = false;
    ConstrainedPass<S> trial;
    Wrench<S> lt;
    int cuts = 0;
    const S noise = S(constrained_roundoff) * eps() * (std::abs(cur_.f2) + norm_.dual(lambda_) * scale);
    if (slope > S(0) && dir.allFinite()) {
      S alpha = S(1);
      for (; cuts < settings_.max_line_search && budget_.left(); ++cuts, alpha *= S(0.5)) {
        if (cuts == 1) alpha = second_trial(passes_, lambda_, dir, lambda_, dir, alpha);  // q's first kink
        lt = lambda_ + alpha * dir;
        if (lt == lambda_) break;  // a step below lambda's resolution (at round-off Armijo takes it)
        trial = budget_.run(passes_, w_ext_, lt, xt_, trial_h_);
        const S slack = S(constrained_roundoff) * eps() * (std::abs(trial.dual) + std::abs(cur_.dual) + std::abs(cur_.f2));
        const S rise = settings_.armijo * alpha * slope;
        accepted = trial.dual >= cur_.dual + rise - slack ||
                   (rise <= noise && trial.dual >= cur_.dual - noise &&
                    norm_(trial.residual) <= (S(1) - settings_.armijo * alpha) * rn);
        if (accepted) break;
      }
    }
    if (!accepted) {
      // No step left at round-off, unless the deadline cut the line search short.
      const bool deadline = !budget_.left() && cuts < settings_.max_line_search;
      if (!deadline && rn <= settings_.tolerance * scale) status_ = Status::Ok;
      return false;
    }
    // Levenberg-Marquardt: /10 after a full step, *4 (up to 1) after a cut one.
    damping_ = cuts == 0 ? damping_ * S(0.1) : (damping_ * S(4) < S(1) ? damping_ * S(4) : S(1));
    if (damping_ < reg) damping_ = reg;
    growing_ = cuts == 0 && cur_.dual > S(0) && trial.dual >= S(2) * cur_.dual;
    lambda_ = lt;
    x_ = xt_;
    cur_h_ = trial_h_;
    cur_ = trial;
    keep_best();
    return true;
  }

  /// After a step: settings.stall_limit steps in a row that fail to halve stall_ref_ (growth
  /// steps, settings.stall_growth_allowance of them, excepted: each resets it) and q's rise of
  /// the last step that did either (rise_ref_: a zig-zag converging on a kink), or sooner a
  /// growth step (certificate_check_growth on) whose -lambda is a certificate, suggest that no
  /// forces in the cones balance w_ext: decided once by phase 1. A verdict of infeasibility
  /// waits settings.infeasible_grace iterations for Newton to converge. False: stop now.
  bool watch_stall() {
    const S rise = cur_.dual - last_dual_;
    last_dual_ = cur_.dual;
    if (rn_ <= S(0.5) * stall_ref_) {
      stall_ref_ = rn_;
      rise_ref_ = rise;
      stall_ = 0;
    } else if (!growing_ && rise > S(0) && rise <= S(0.5) * rise_ref_) {
      rise_ref_ = rise;
      stall_ = 0;
    } else if (growing_ && growth_ < settings_.stall_growth_allowance) {
      stall_ref_ = rn_;  // the settling after a growth is measured from where it ended
      ++growth_;
    } else {
      ++stall_;
    }
    Wrench<S> y;  // -lambda_ / |lambda_|_L*, tested on growth steps only
    const bool diverging = growing_ && growth_ >= settings_.certificate_check_growth && !phase1_done_ &&
                           multiplier_direction_certificate(grasp_, w_ext_, lambda_, norm_, settings_, y);
    if ((diverging || stall_ >= settings_.stall_limit) && !phase1_done_) {
      phase1_done_ = true;
      if (decide_infeasible()) {
        pending_ = true;
        if (grace_ <= 0) return false;
      } else if (p_lambda_.allFinite()) {
        restart_from_phase1();
      }
    } else if (pending_ && --grace_ <= 0) {
      return false;
    }
    return true;
  }

  /// Feasible after all: the least-residual solve is a penalty approximation of this problem,
  /// so -y/delta (p_lambda_) estimates the multipliers; continue from it if the dual is higher
  /// there. Only where every projection input is in range: a small delta makes the estimate
  /// large, and the passes project an input beyond max_magnitude to zero, so that their dual
  /// there is not q (it can exceed the optimum, and Newton would stay on it).
  void restart_from_phase1() {
    if (!projection_inputs_in_range(grasp_, p_lambda_) || !budget_.left()) return;
    ConstrainedPass<S> alt = budget_.run(passes_, w_ext_, p_lambda_, xt_, trial_h_);
    if (alt.dual > cur_.dual && std::isfinite(alt.dual)) {
      lambda_ = p_lambda_;
      x_ = xt_;
      cur_h_ = trial_h_;
      cur_ = alt;
      stall_ = 0;
      stall_ref_ = norm_(alt.residual);
      keep_best();
    }
  }

  /// Phase 1: the least-residual forces; true (the verdict pending: its forces in p_x_, its
  /// multipliers and certificate in sol_, which finish() clears of them unless the answer is
  /// Infeasible) if the direction of its multipliers, or in float that of the diverging Newton
  /// multipliers, checks out as an infeasibility certificate.
  bool decide_infeasible() {
    Wrench<S>& y = sol_.multipliers;  // finish() writes lambda_ over it
    S f2 = S(0);
    const int passes_before = budget_.used;
    S delta = settings_.least_residual_weight * jacobi_max_;
    // y is (to delta) the least residual, in the units of the norm: a feasible problem leaves
    // only round-off there, below settings.infeasibility_bar tolerance |w_ext|_L.
    const S bar = settings_.infeasibility_bar * settings_.tolerance * w_norm_l_;
    bool ok = false;
    // The certificate's error is delta w_i |x_i - t_i| / |y|: nearly infeasible grasps need
    // large least-residual forces, so the solve may be retried with smaller delta
    // (settings.certificate_attempts) when the first certificate misses the tolerance.
    phase1_iterations_ = 0;
    // The tries share one budget of settings.max_iterations iterations (and the solve's passes);
    // xt_ and trial_h_ are free until Newton's next line search.
    for (int k = 0; k < settings_.certificate_attempts && !ok && phase1_iterations_ < settings_.max_iterations && budget_.left();
         ++k, delta *= settings_.certificate_retry_factor) {
      phase1_iterations_ += least_residual(passes_, w_ext_, norm_, scale_shift_, delta, settings_,
                                           settings_.max_iterations - phase1_iterations_, budget_, p_x_, y, f2,
                                           xt_, trial_h_);
      // y is in the norm's units; T y is the direction of physical multipliers.
      p_lambda_ = -norm_.to_units(y) / delta;  // the penalty estimate of the multipliers (x(p_lambda_) = p_x_)
      const S rn = y.norm();
      if (rn > bar) {
        sol_.certificate = norm_.to_units(y) / rn;  // |certificate|_L* = 1
        ok = is_infeasibility_certificate(grasp_, w_ext_, sol_.certificate, norm_, settings_.certificate_tolerance,
                                          settings_.certificate_guard);
      }
    }
    // Second candidate (settings.multiplier_certificate, float by default): the direction
    // -lambda of the diverging Newton multipliers (multiplier_direction_certificate). Neither
    // without a least-residual solve (the deadline left no pass for it): an Infeasible answer
    // carries its forces.
    const bool solved = budget_.used > passes_before;
    if (settings_.multiplier_certificate && solved && !ok)
      ok = multiplier_direction_certificate(grasp_, w_ext_, lambda_, norm_, settings_, sol_.certificate);
    if (!ok) {
      sol_.certificate.setZero();
      return false;
    }
    y = norm_.to_units(y);  // the multipliers of an Infeasible answer: T y, physical
    p_f2_ = f2;
    return true;
  }

  /// The pending verdict becomes the answer: Infeasible, phase 1's forces, multipliers, certificate.
  void apply_infeasible() {
    status_ = Status::Infeasible;
    x_ = p_x_;
    lambda_ = sol_.multipliers;  // T y, from decide_infeasible
    passes_.store(p_x_, sol_.forces);  // sized by run(); finish() writes the same forces
    cur_.residual = grasp_.wrench(sol_.forces) + w_ext_;
    cur_.f2 = p_f2_;
    cur_.dual = p_f2_ - lambda_.dot(cur_.residual);
  }

  /// Writes the iterate into the solution; anything not finite becomes zero forces and
  /// multipliers (an Ok verdict then IterationLimit).
  void finish() {
    ConstrainedSolution<GraspT>& sol = sol_;
    passes_.store(x_, sol.forces);
    sol.multipliers = lambda_;
    sol.residual = stable_norm(cur_.residual);
    sol.objective = cur_.f2;
    sol.dual_objective = cur_.dual;
    sol.iterations = it_ + phase1_iterations_;
    sol.passes = budget_.used;
    sol.status = status_;
    if (status_ != Status::Infeasible) sol.certificate.setZero();  // a verdict dropped in grace
    if (!sol.forces.allFinite() || !sol.multipliers.allFinite() || !std::isfinite(sol.dual_objective)) {
      sol.forces.setZero(m_);
      sol.multipliers.setZero();
      sol.residual = stable_norm(w_ext_);
      sol.objective = S(0);
      sol.dual_objective = S(0);
      if (sol.status == Status::Ok) sol.status = Status::IterationLimit;
    }
  }

  static S eps() { return std::numeric_limits<S>::epsilon(); }
  /// sum_k |H e_k|_L |lambda_k|: the residual's move (over eps) when each multiplier moves by its
  /// rounding, eps |lambda_k|; no iteration resolves it below eps times this (it matters where a
  /// channel is far stiffer than the lever arms suggest: a soft finger's torsion at micrometres).
  S multiplier_resolution() const {
    const Matrix6<S>& h = cur_h_;
    S sum = S(0);
    for (int k = 0; k < 6; ++k) sum += norm_(Wrench<S>(h.col(k))) * std::abs(lambda_(k));
    return sum;
  }
  /// The scale of a pass's tests in the units of the norm: |w_ext|_L + |x| (the pass's own
  /// scale is |w_ext| + |x|).
  S scale_of(const ConstrainedPass<S>& p) const { return p.scale + scale_shift_; }

  // The problem.
  const GraspT& grasp_;
  const Wrench<S>& w_ext_;
  const ConstrainedSettings<S>& settings_;
  ConstrainedSolution<GraspT>& sol_;
  const int m_;  ///< unknowns
  // The iterate.
  Wrench<S> lambda_;
  Wrench<S> jacobi_;  ///< D: the Gram diagonal, floored at settings.jacobi_floor of its largest entry (in L units)
  S jacobi_max_{0};   ///< the largest entry of the Gram diagonal in the norm's units (1, 1 / L^2)
  Wrench<S> dinv_;    ///< D^-1/2
  const Passes passes_;  ///< hard fingers: the grasp copied into columns once
  Forces x_, xt_;        ///< the forces at lambda_ and at the line-search point
  Forces best_x_;        ///< the forces of the least-residual iterate met (best_lambda_)
  Matrix6<S> cur_h_, trial_h_;  ///< the Hessians (sum w^-1 G J G^T) at lambda_ and at the line-search point
  ConstrainedPass<S> cur_;              ///< the pass sums at lambda_
  ConstrainedPass<S> best_;             ///< the pass sums at best_lambda_
  Wrench<S> best_lambda_{Wrench<S>::Zero()};
  S best_rn_{std::numeric_limits<S>::infinity()};  ///< |residual|_L at best_lambda_
  S rn_{0};  ///< |residual|_L at lambda_ (set by keep_best with every new iterate)
  S damping_{1};  ///< Levenberg-Marquardt state: /10 after a full step, *4 after a cut one
  Status status_{Status::IterationLimit};
  int it_{0};
  int stall_{0};         ///< steps in a row that did not halve stall_ref_
  S stall_ref_{0};       ///< the residual of the last step that halved it (or of the start)
  S last_dual_{0};       ///< q at the previous iterate (set by each step)
  S rise_ref_{std::numeric_limits<S>::infinity()};  ///< q's rise at the last step that reset stall_
  int growth_{0};        ///< full steps that doubled the dual, not counted as stalls
  bool growing_{false};  ///< the last step was one (a growth step)
  int phase1_iterations_{0};  ///< counted apart: the Newton budget stays max_iterations
  bool phase1_done_{false};
  // Phase 1's verdict, pending until apply_infeasible() (multipliers, certificate: in sol_).
  S p_f2_{0};
  Forces p_x_;
  Wrench<S> p_lambda_{Wrench<S>::Zero()};
  bool pending_{false};  ///< an infeasibility verdict awaits the grace iterations
  PassBudget budget_;    ///< settings.max_passes, and the passes made
  int grace_{0};         ///< iterations left for Newton to converge before the verdict stands
  // The norm of the tests (last: the iterate's members keep the layout of the hot loop).
  const EquilibriumNorm<S> norm_;  ///< |.|_L, in which residuals are measured
  const S w_norm_l_;               ///< |w_ext|_L
  const S scale_shift_;            ///< |w_ext|_L - |w_ext|: a pass's scale into the norm's units
};

}  // namespace detail
}  // namespace grip
