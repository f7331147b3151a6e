#pragma once
/// \file
/// solve_constrained's answer for a grasp that slips (namespace grip::detail): its certificate
/// and the least-residual forces, the minimiser of |G x + w_ext|_L^2/2 + delta F2(x) over the
/// cones (and bounds): zero forces where the load pulls the object off every contact (checked in
/// closed form: the objective's gradient at zero lies in the cones' dual), else the interior-point
/// method on the problem's soft form (interior_point.hpp). Also the scaling of an iterate's
/// forces into their bounds, shared with the answer that the bound on iterations cuts.

#include <algorithm>
#include <cmath>
#include <limits>

#include "grip/core/scalar_traits.hpp"
#include "grip/core/types.hpp"
#include "grip/grasp/objective.hpp"
#include "grip/solve/constrained_settings.hpp"
#include "grip/solve/constrained_solution.hpp"
#include "grip/solve/detail/equilibrium_norm.hpp"
#include "grip/solve/detail/force_problem.hpp"
#include "grip/solve/detail/interior_point.hpp"

namespace grip {
namespace detail {

/// The interior-point iterate's forces, each scaled into its bound if the (infeasible-start)
/// iterate has not yet met it: the answer of a solve that the bound on iterations cuts.
template <class GraspT, class Vec>
void keep_within_bounds(const GraspT& grasp, Vec& x) {
  using S = typename GraspT::ScalarType;
  constexpr int d = GraspT::dim;
  for (int i = 0; i < grasp.size(); ++i) {
    const auto& c = grasp.contact(i);
    auto xi = x.template segment<d>(i * d);
    const S fn = d == 1 ? S(xi(0)) : c.normal.dot(xi.template head<3>());
    if (fn > c.max_normal_force) xi *= c.max_normal_force / fn;
  }
}

/// The least-residual problem's answer (solve_constrained's Infeasible forces) in `sol`: the
/// soft form of the problem in lanes `k` (cleared and refilled), by the interior-point method
/// with what is left of settings.max_iterations after `used`.
template <class GraspT, class Lanes>
void least_residual_forces(const GraspT& grasp, const Wrench<typename GraspT::ScalarType>& w_ext,
                           const ConstrainedSettings<typename GraspT::ScalarType>& settings,
                           const Wrench<typename GraspT::ScalarType>& gram_diagonal, int used, Lanes& k,
                           ForceProblem<GraspT>& problem, ConstrainedSolution<GraspT>& sol) {
  using S = typename GraspT::ScalarType;
  // delta = least_residual_weight times the largest diagonal entry of G W^-1 G^T in |.|_L's units.
  const EquilibriumNorm<S> norm = EquilibriumNorm<S>::of(grasp);
  const Wrench<S> t2 = norm.weights().cwiseAbs2();
  S gd(0);
  for (int j = 0; j < 6; ++j) gd = std::max(gd, gram_diagonal(j) * t2(j));
  problem.scale(grasp, w_ext);  // the scales first
  const S delta_n = settings.least_residual_weight * gd * problem.weight;
  k.clear(grasp.size());
  problem.fill(grasp, w_ext, k, delta_n);
  sol.multipliers.setZero();
  sol.status = Status::Infeasible;
  if (problem.origin_optimal) {
    // No force lowers the objective: the load pulls the object off every contact by more than
    // delta F2 pulls the forces toward the squeezing forces. Zero forces are the minimiser.
    sol.forces.setZero(grasp.unknowns());
    sol.passes += 1;
    return;
  }
  InteriorPointSettings<S> lr;
  lr.tolerance = std::max(S(ScalarTraits<S>::interior_tolerance), settings.tolerance);
  lr.feasibility_tolerance = lr.tolerance;  // the answer's accuracy is the interior-point method's
  lr.certificate_tolerance = settings.certificate_tolerance;
  lr.max_iterations = std::max(settings.max_iterations - used, 1);
  lr.soft = true;
  lr.cost_offset = problem.cost_offset(grasp) * delta_n;
  lr.residual_floor = problem.squeeze_scale(grasp);
  // The run starts at the load's size in the problem's units (ForceProblem::load_scale). Under
  // a load far below the squeezing forces the problem's data b, and with it the residuals and
  // multipliers, are small: from the cones' centres the method would first spend iterations
  // shrinking its iterate toward that scale.
  lr.start_scale = problem.load_scale;
  const InteriorPointResult<S> q = interior_point(k, problem.b, problem.q_norm, lr);
  sol.iterations += q.iterations;
  sol.passes += 3 * q.iterations + 1 - 2 * q.backtracks;
  problem.forces(grasp, k, q.tau, sol.forces);
  // A breakdown of the method (tau or an iterate not finite, in float at extreme scales): no
  // forces, whose residual is w_ext itself.
  if (!sol.forces.allFinite()) sol.forces.setZero(grasp.unknowns());
  keep_within_bounds(grasp, sol.forces);
}

/// An Infeasible answer in `sol`: `certificate` (of dual norm 1) and the least-residual forces,
/// with what is left of settings.max_iterations after `used`.
template <class GraspT, class Lanes>
void answer_slip(const GraspT& grasp, const Wrench<typename GraspT::ScalarType>& w_ext,
                 const ConstrainedSettings<typename GraspT::ScalarType>& settings,
                 const Wrench<typename GraspT::ScalarType>& gram_diagonal,
                 const Wrench<typename GraspT::ScalarType>& certificate, int used, Lanes& k,
                 ForceProblem<GraspT>& problem, ConstrainedSolution<GraspT>& sol) {
  using S = typename GraspT::ScalarType;
  sol.certificate = certificate;
  least_residual_forces(grasp, w_ext, settings, gram_diagonal, used, k, problem, sol);
  sol.residual = stable_norm(Wrench<S>(grasp.wrench(sol.forces) + w_ext));
  sol.objective = objective_f2(grasp, sol.forces);
}

}  // namespace detail
}  // namespace grip
