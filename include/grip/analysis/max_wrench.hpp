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
/// Solved through its homogeneous form
///     c* = min sum_i e_i . x_i  s.t.  G x = -d,  x_i in K_i,
/// scale* = budget / c* (the optimal x scaled by budget / c*), or 0 when no forces inside the cones
/// give G x = -d (the problem is infeasible: no positive multiple of d is resisted), by the
/// interior-point method of solve_constrained (a homogeneous embedding with Nesterov-Todd
/// scaling and Mehrotra steps, solve/detail/interior_point.hpp; the rows in
/// detail/conic_analysis.hpp). Any wrench direction u bounds it: with zeta the least value such
/// that G_i^T u + zeta e_i lies in K_i^* for every contact, scale* <= zeta budget / (d . u) when
/// d . u > 0 (0 when zeta <= 0 too); the multipliers of the rows give the bound reported at
/// IterationLimit. No heap.

#include <algorithm>
#include <cmath>
#include <limits>

#include "grip/analysis/detail/conic_analysis.hpp"
#include "grip/analysis/force_closure.hpp"
#include "grip/contact/contact.hpp"
#include "grip/core/status.hpp"
#include "grip/core/types.hpp"
#include "grip/grasp/grasp.hpp"
#include "grip/solve/detail/interior_point.hpp"

namespace grip {

/// The outcome of max_resistible_wrench().
///
/// Ok: `scale` is the optimum within settings.tolerance (relative), or 0 when no forces inside
/// the cones resist any positive multiple of d (a certificate: forces zero). IterationLimit: the
/// iteration bound was hit; `scale` is an upper bound on the optimum, and `forces` the last
/// iterate, inside the cones with normal forces summing to the budget but not balancing
/// scale * d. InvalidInput: incomplete or empty grasp, direction zero/non-finite, budget not
/// finite and > 0, bad settings; zeros.
template <class GraspT>
struct ResistibleWrench {
  using Scalar = typename GraspT::ScalarType;  ///< The grasp's scalar type.
  Scalar scale{0};                             ///< s*: w_ext = s* d is the largest resisted wrench along d (0: none).
  /// Contact forces inside the cones, normal forces summing to the budget, that resist
  /// -G forces ~ scale * d (zero when scale is 0 by a certificate).
  typename GraspT::ForceVector forces;
  Scalar residual{0};                   ///< |G forces + scale d| (N and N m): the gap of the estimate.
  int iterations{0};                    ///< interior-point iterations used.
  Status status{Status::InvalidInput};  ///< Ok, IterationLimit or InvalidInput (see above).
};

/// Largest s such that the external wrench s * direction can be balanced by contact forces
/// inside the exact cones whose normal components sum to at most `budget` (N).
template <class GraspT>
ResistibleWrench<GraspT> max_resistible_wrench(
    const GraspT& grasp, const Wrench<typename GraspT::ScalarType>& direction, typename GraspT::ScalarType budget,
    const ConicAnalysisSettings<typename GraspT::ScalarType>& settings = {}) {
  using S = typename GraspT::ScalarType;
  using Analysis = detail::ConicAnalysis<GraspT>;
  using W = typename Analysis::W;  // the scalar of the computation (ScalarTraits<S>::Wide)
  using XW = Eigen::Matrix<W, GraspT::unknowns_at_compile_time, 1, Eigen::ColMajor, GraspT::max_unknowns, 1>;
  constexpr int D = GraspT::dim;
  ResistibleWrench<GraspT> out;
  out.forces.setZero(grasp.unknowns());
  const int n = grasp.size();
  if (!grasp.complete() || n == 0 || validate(direction) != Status::Ok || !(direction.norm() > S(0)) ||
      !detail::in_range(budget) || !(budget > S(0)) || !valid_settings(settings))
    return out;
  Analysis problem(grasp);
  const Wrench<W> d = direction.template cast<W>();
  typename Analysis::Lanes k(n);
  const Wrench<W> b = problem.wrench_problem(grasp, d, k);
  const auto st = Analysis::settings(W(settings.tolerance), settings.max_iterations, W(0), W(0));
  const detail::InteriorPointResult<W> r = detail::interior_point(k, b, std::sqrt(W(n)), st);
  out.iterations = r.iterations;
  if (r.status == Status::Infeasible) {  // nothing along d: scale 0, no forces
    out.status = Status::Ok;
    out.residual = S(0);
    return out;
  }
  // x = M u / tau (G x = -d / |T d| to the tolerance) and its cost c = sum e.x = sum u_0 / tau.
  XW x(grasp.unknowns());
  W c(0);
  for (int i = 0; i < n; ++i) {
    x.template segment<D>(i * D) = problem.force(k, i) / r.tau;
    c += k.u(i)(0) / r.tau;
  }
  const W wb = W(budget), td = problem.norm().to_units(d).norm();
  const XW forces = (wb / c) * x;
  const bool ok = r.status == Status::Ok && forces.allFinite() && c > W(0);
  W scale = wb / (td * c);
  if (!ok) {
    // An upper bound: from the multipliers' direction T y, and from T^2 d (d . T^2 d > 0).
    const Wrench<W> dsc = problem.norm().weights();
    scale = wb * std::min(problem.scale_bound(grasp, d, dsc.cwiseProduct(r.y)),
                          problem.scale_bound(grasp, d, dsc.cwiseProduct(dsc.cwiseProduct(d))));
  }
  if (forces.allFinite()) out.forces = forces.template cast<S>();
  out.scale = S(std::min(scale, W(std::numeric_limits<S>::max())));  // finite (a tiny d's bound)
  out.residual = (grasp.wrench(out.forces) + out.scale * direction).norm();
  out.status = ok ? Status::Ok : Status::IterationLimit;
  return out;
}

}  // namespace grip
