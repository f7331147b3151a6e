#pragma once
/// \file
/// What solve_constrained (solve_constrained.hpp) returns: its status, forces and multipliers
/// (Solution), and the numbers that certify them: the infeasibility certificate, the primal and
/// dual objectives, and how the answer was reached. And what the next frame's solve may start
/// from (ConstrainedWarmStart).

#include "grip/core/types.hpp"
#include "grip/solve/solution.hpp"

namespace grip {

/// What solve_constrained returns: a Solution plus the numbers that certify it.
///
/// Every number is finite whatever the status; `forces` always lie inside their cones and below
/// their contacts' max_normal_force, except under InvalidInput, where everything is zero.
template <class GraspT>
struct ConstrainedSolution : Solution<GraspT> {
  /// The grasp's scalar type (float or double).
  using Scalar = typename GraspT::ScalarType;
  /// Infeasible: a 6-vector y of dual norm |(y_f, L y_m)| = 1 (L the longest lever arm) with
  /// y.w_ext > 0 and every G_i^T y in the dual cone K_i^* to within
  /// ConstrainedSettings::certificate_tolerance (y.w_ext) / |w_ext|_L (for a contact with a
  /// bound: G_i^T y + tau_i a_i in K_i^* for some tau_i >= 0 with sum_i tau_i c_i < y.w_ext). It
  /// proves that no forces in the cones balance w_ext: for x_i in K_i, y.(G x) >= 0, so
  /// y.(G x + w_ext) > 0 (with bounds, y.(G x) >= -sum_i tau_i c_i). Zero otherwise.
  Wrench<Scalar> certificate{Wrench<Scalar>::Zero()};
  /// F2 at `forces`: 1/2 sum_i w_i |x_i - t_i|^2.
  Scalar objective{0};
  /// Ok: the dual function q at `multipliers`, F2(x) - lambda.(G x + w_ext) (the optimum lies
  /// between it and `objective`). Otherwise 0.
  Scalar dual_objective{0};
  /// True when the unconstrained optimum was inside every cone (f_n > 0, below its bound) and was
  /// returned at once.
  bool fast_path{false};
  /// Ok: true when `forces` are the projections x_i(lambda) of `multipliers` (the fast path, or
  /// Newton's refinement converged) and meet ConstrainedSettings::tolerance: every contact's KKT
  /// conditions then hold exactly; false when they meet only ScalarTraits::interior_tolerance (the
  /// residual, and the duality gap relative to F2): Newton's least-residual iterate, or the
  /// interior-point method's answer, strictly inside the cones. False otherwise.
  bool refined{false};
  /// O(n) passes over the contacts after the fast path: three per interior-point iteration, one
  /// more per interior-point run, one per Newton trial.
  int passes{0};
};

/// What a solve may start from: the previous frame's answer (solve_constrained's warm start).
/// Both are 6-vectors, so the contacts may change between frames.
template <class Scalar>
struct ConstrainedWarmStart {
  Wrench<Scalar> multipliers{Wrench<Scalar>::Zero()};  ///< an Ok or IterationLimit answer's multipliers
  bool has_multipliers{false};                         ///< whether `multipliers` is given
  Wrench<Scalar> certificate{Wrench<Scalar>::Zero()};  ///< an Infeasible answer's certificate
  bool has_certificate{false};                         ///< whether `certificate` is given
};

}  // namespace grip
