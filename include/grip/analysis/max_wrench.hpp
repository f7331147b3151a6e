#pragma once
/// \file
/// The largest external wrench of a given direction that a grasp can resist with forces
/// inside its exact cones and a total normal-force budget.
///
///     scale* = max s  s.t.  G x + s d = 0,  x_i in K_i,  sum_i e_i . x_i <= budget
/// (e_i the unit normal direction: the budget bounds the sum of normal forces, N). The
/// grasp resists w_ext = s d for every 0 <= s <= scale*. This is the "task-oriented" view
/// of Li & Sastry 1988 and the wrench-direction quality of Roa & Suarez 2015 (section
/// 4.2); with the L1 budget it is the radius of the grasp wrench set along d.
/// Solved exactly (to the tolerance) through its dual
///     min budget * zeta  s.t.  d . y = -1,  zeta e_i - G_i^T y in K_i^*,  zeta >= 0,
/// by the interior-point solver of conic_dual.hpp. No heap.

#include <algorithm>
#include <cmath>
#include <limits>

#include "grip/analysis/conic_dual.hpp"
#include "grip/analysis/force_closure.hpp"
#include "grip/contact/contact.hpp"
#include "grip/core/status.hpp"
#include "grip/core/types.hpp"
#include "grip/grasp/grasp.hpp"

namespace grip {

/// The outcome of max_resistible_wrench().
///
/// Ok: `scale` is the optimum within settings.tolerance (relative). IterationLimit: the
/// iteration bound was hit; `scale` is an upper bound. InvalidInput: incomplete or empty
/// grasp, direction zero/non-finite, budget not finite and > 0, bad settings; zeros.
template <class GraspT>
struct ResistibleWrench {
  using Scalar = typename GraspT::ScalarType;  ///< The grasp's scalar type.
  Scalar scale{0};  ///< s*: w_ext = s* d is the largest resisted wrench along d (0: none).
  /// Contact forces that resist about -G x ~ scale * d within the cones and the budget.
  typename GraspT::ForceVector forces;
  Scalar residual{0};  ///< |G forces + scale d| (N and N m): the gap of the estimate.
  int iterations{0};   ///< interior-point iterations used.
  Status status{Status::InvalidInput};  ///< Ok, IterationLimit or InvalidInput (see above).
};

/// Largest s such that the external wrench s * direction can be balanced by contact forces
/// inside the exact cones whose normal components sum to at most `budget` (N).
template <class GraspT>
ResistibleWrench<GraspT> max_resistible_wrench(const GraspT& grasp,
                                               const Wrench<typename GraspT::ScalarType>& direction,
                                               typename GraspT::ScalarType budget,
                                               const ConicAnalysisSettings<typename GraspT::ScalarType>& settings = {}) {
  using S = typename GraspT::ScalarType;
  using M = typename GraspT::ModelType;
  constexpr int D = GraspT::dim;
  ResistibleWrench<GraspT> out;
  out.forces.setZero(grasp.unknowns());
  const int n = grasp.size();
  if (!grasp.complete() || n == 0 || validate(direction) != Status::Ok || !(direction.norm() > S(0)) ||
      !detail::in_range(budget) || !(budget > S(0)) || !valid_settings(settings))
    return out;
  const S rho = detail::internal_torque_scale(grasp);
  const Wrench<S> dsc = detail::row_scaling(rho);
  const Wrench<S> ds = dsc.cwiseProduct(direction);

  Eigen::Matrix<S, 7, 1> c = Eigen::Matrix<S, 7, 1>::Zero(), a = Eigen::Matrix<S, 7, 1>::Zero(), q0;
  c(6) = S(1);
  a.template head<6>() = -ds;
  q0.template head<6>() = -ds / ds.squaredNorm();
  // A strictly feasible zeta: zeta e_i - v_i in int K_i^* needs zeta > v_n + sqrt(Q(v_t)).
  S zeta(0);
  const Wrench<S> y0 = dsc.cwiseProduct(q0.template head<6>());
  for (int i = 0; i < n; ++i) {
    const auto k = detail::exact_cone<M>(grasp.contact(i));
    const Eigen::Matrix<S, D, 1> v = M::wrench_transpose(grasp.contact(i), y0);
    const S vn = k.axis.dot(v);
    const Eigen::Matrix<S, D, 1> u = v - vn * k.axis;
    const S q = k.halfspace ? S(0) : -u.dot(k.quad * u);
    zeta = std::max(zeta, vn + std::sqrt(std::max(q, S(0))));
  }
  q0(6) = zeta + S(1) + std::abs(zeta);
  // zeta >= 0 bounds the objective below by 0: no floor is reached.
  const auto r = detail::solve_conic_dual(grasp, rho, c, a, q0, true, settings.tolerance, settings.max_newton_steps,
                                          -std::numeric_limits<S>::infinity());
  out.iterations = r.iterations;
  out.status = r.status == Status::Ok ? Status::Ok : Status::IterationLimit;
  out.scale = std::max(S(0), budget * r.objective);
  out.forces = budget * r.primal;
  out.residual = (grasp.wrench(out.forces) + out.scale * direction).norm();
  return out;
}

}  // namespace grip
