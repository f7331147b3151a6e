#pragma once
/// \file
/// solve_constrained: the exact optimum of F2 with every contact force inside its exact cone
/// (the paper's section 4 problem, eq. 3-5 with eq. 7), and below its bound where the contact
/// has one. The API first, with its contract; the definitions at the end. Its settings are
/// constrained_settings.hpp, its result constrained_solution.hpp.
/// The method (docs/solve.md): a primal-dual interior-point method on a homogeneous embedding
/// (detail/interior_point.hpp, the contacts in SIMD lanes: detail/conic_lanes.hpp), refined by
/// Newton's method on the 6-dimensional dual (detail/dual_newton.hpp), which also takes a warm
/// start first.

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <type_traits>

#include "grip/contact/coulomb_cone.hpp"
#include "grip/contact/coulomb_kernel.hpp"
#include "grip/contact/exact_cone.hpp"
#include "grip/core/status.hpp"
#include "grip/core/types.hpp"
#include "grip/grasp/grasp.hpp"
#include "grip/grasp/objective.hpp"
#include "grip/solve/constrained_settings.hpp"
#include "grip/solve/constrained_solution.hpp"
#include "grip/solve/detail/certificate.hpp"
#include "grip/solve/detail/dual_newton.hpp"
#include "grip/solve/detail/equilibrium_norm.hpp"
#include "grip/solve/detail/force_problem.hpp"
#include "grip/solve/detail/interior_point.hpp"
#include "grip/solve/detail/slip_answer.hpp"
#include "grip/solve/solution.hpp"
#include "grip/solve/solve_range_space.hpp"

namespace grip {

/// The exact optimum of min 1/2 sum_i w_i |x_i - t_i|^2 s.t. G x + w_ext = 0, x_i in K_i and
/// f_n,i <= c_i (K_i = ExactConeT<Model, Scalar>, see exact_cone.hpp; c_i the contact's
/// max_normal_force), for any Grasp (fixed or Dynamic, any model, float or double). No heap, no
/// exceptions; at most settings.max_iterations interior-point iterations of three O(n) passes
/// each, plus at most twice settings.newton_passes O(n) passes: the solve's time is bounded by
/// about the fast path plus that many passes and 6x6 solves (docs/solve.md gives both per
/// contact count).
///
/// Fast path, always tried first: solve_range_space's unconstrained optimum; if every force is in
/// its cone with f_n > 0 and below its bound it is the answer (status Ok, iterations 0, fast_path
/// true). Otherwise, given `warm_multipliers` (the previous frame's `multipliers`: a 6-vector, so
/// the contact count may change between frames), Newton's method on the dual starts from them
/// for settings.newton_passes passes and answers if it converges; if not, its multipliers
/// reversed are tested as a certificate (on a slip they grow along one). Otherwise the
/// interior-point method decides: it finds the optimum or a certificate that none exists; short
/// of both (its bound, or a numerical failure) it leaves its last iterate. Newton refines the
/// optimum, or that iterate, from its multipliers to the tolerance. Wrenches are measured in the
/// equilibrium norm |(f, m)|_L = |(f, m / L)|, L = max_i |r_i| (1 m if every contact is at the
/// reference point), so that every verdict is the same in every unit of length; `residual`
/// reports |G x + w_ext|.
///
/// Statuses and numbers:
/// - Ok, refined (the usual case): |G x + w_ext|_L <= tolerance (|w_ext|_L + |x| + max_i s_i) (the
///   squeezing forces' size counts: a grasp whose optimum sits at the cones' apexes has |x| near
///   0), and `forces` are the projections x_i(lambda) at `multipliers`, so the KKT conditions of
///   every contact hold exactly. Ok, not refined (where Newton's refinement does not converge:
///   soft fingers with bounds, a soft finger's torsion at micrometres, G nearly of rank < 6): an
///   answer to ScalarTraits::interior_tolerance (residual as above, and the duality gap relative
///   to F2): Newton's least-residual iterate (projections, the exact optimum for the load -G x)
///   where it meets it, else the interior-point method's. `objective` is F2.
/// - Infeasible: no forces in the cones (and bounds) balance w_ext: the grasp slips.
///   `certificate` proves it (see ConstrainedSolution). `forces` are the minimiser of
///   |G x + w_ext|_L^2/2 + delta F2(x) over the cones (delta = least_residual_weight times the
///   largest diagonal entry of G W^-1 G^T in |.|_L's units): the forces that come closest to
///   balancing w_ext, ties broken by F2, to the interior-point method's tolerance. `multipliers`
///   are zero.
/// - IterationLimit: settings.max_iterations reached first (or a numerical failure); `forces` are
///   the last iterate's, in the cones, `multipliers` its, `residual` what is left.
/// - InvalidInput: incomplete grasp, bad w_ext, bad settings or a non-finite warm start: zeros.
/// A grasp matrix of rank < 6 is not an error here: the answer is Ok if the wrench can still be
/// balanced inside the cones, Infeasible (with a certificate) otherwise; a wrench with a part
/// outside G's range is Infeasible before any Newton pass or interior-point iteration (its
/// certificate in closed form: detail/certificate.hpp), then the least-residual forces.
template <class GraspT>
ConstrainedSolution<GraspT> solve_constrained(const GraspT& grasp, const Wrench<typename GraspT::ScalarType>& w_ext,
                                              const ConstrainedSettings<typename GraspT::ScalarType>& settings =
                                                  ConstrainedSettings<typename GraspT::ScalarType>{});

/// As above, warm-started from `warm_multipliers` (the previous frame's solution.multipliers).
template <class GraspT>
ConstrainedSolution<GraspT> solve_constrained(const GraspT& grasp, const Wrench<typename GraspT::ScalarType>& w_ext,
                                              const ConstrainedSettings<typename GraspT::ScalarType>& settings,
                                              const Wrench<typename GraspT::ScalarType>& warm_multipliers);

/// As above, from the previous frame's answer: its multipliers (as above), or its certificate.
/// A certificate is tested first, after the fast path, against the definition of
/// ConstrainedSolution::certificate (one O(n) pass): if it still holds, the answer is Infeasible
/// with it (scaled to dual norm 1) and the least-residual forces, without Newton's passes or the
/// first interior-point run; else the solve goes on as above. InvalidInput also for a given
/// certificate or multipliers not finite.
template <class GraspT>
ConstrainedSolution<GraspT> solve_constrained(const GraspT& grasp, const Wrench<typename GraspT::ScalarType>& w_ext,
                                              const ConstrainedSettings<typename GraspT::ScalarType>& settings,
                                              const ConstrainedWarmStart<typename GraspT::ScalarType>& warm);

// ---------------------------------------------------------------------------------------------
// Definitions.

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

/// True when the unknowns x_i of contact c keep its bound: f_n <= max_normal_force.
template <class Model, class S, class V>
bool within_bound(const Contact<S>& c, const V& x) {
  if (!(c.max_normal_force < std::numeric_limits<S>::infinity())) return true;
  if constexpr (Model::dim == 1) {
    return x(0) <= c.max_normal_force;
  } else {
    return c.normal.dot(x.template head<3>()) <= c.max_normal_force;
  }
}

/// The fast path: the unconstrained optimum (solve_range_space's first factorisation only:
/// RankFallback::decline leaves Singular with zero multipliers), returned as the answer when
/// every force is in its cone with f_n > 0 and below its bound (a feasible minimiser of the
/// relaxed problem solves the constrained one). Writes it into `sol` and the diagonal of
/// G W^-1 G^T into `gram_diagonal`; returns true if it is the answer (status Ok, fast_path true).
template <class GraspT>
EIGEN_DONT_INLINE bool constrained_fast_path(const GraspT& grasp, const Wrench<typename GraspT::ScalarType>& w_ext,
                                             ConstrainedSolution<GraspT>& sol,
                                             Wrench<typename GraspT::ScalarType>& gram_diagonal) {
  using S = typename GraspT::ScalarType;
  using M = typename GraspT::ModelType;
  using Cone = ExactConeT<M, S>;
  constexpr int d = GraspT::dim;
  Wrench<S> rhs, res;
  if (!range_space_solve<RankFallback::decline>(grasp, w_ext, sol, rhs, res, &gram_diagonal, true)) return false;
  bool inside = sol.status == Status::Ok;
  if constexpr (std::is_same<Cone, CoulombCone<S>>::value) {
    inside = inside && detail::coulomb_all_inside_grasp(grasp, sol.forces);
  } else {
    for (int i = 0; i < grasp.size() && inside; ++i) {
      const Cone cone = Cone::from_contact(grasp.contact(i));
      const typename Cone::Vector x = sol.forces.template segment<d>(i * d);
      inside = cone.normal_part(x) > S(0) && !cone.slips(x, S(0));
    }
  }
  for (int i = 0; i < grasp.size() && inside; ++i)
    inside = within_bound<M>(grasp.contact(i), sol.forces.template segment<d>(i * d));
  if (!inside) return false;
  const Wrench<S>& lambda = sol.multipliers;
  // F2(x) = 1/2 lambda^T M lambda = 1/2 lambda.(rhs + res); the dual is F2 - lambda.res.
  const S l_rhs = lambda.dot(rhs), l_res = lambda.dot(res);
  sol.objective = S(0.5) * (l_rhs + l_res);
  sol.dual_objective = S(0.5) * (l_rhs - l_res);
  sol.iterations = 0;
  sol.fast_path = true;
  sol.refined = true;
  return true;
}

/// Writes the dual Newton iterate into `sol` as an Ok answer.
template <class GraspT>
void take_newton(const DualNewton<GraspT>& newton, ConstrainedSolution<GraspT>& sol) {
  newton.engine().store(newton.forces(), sol.forces);
  sol.multipliers = newton.lambda();
  sol.residual = stable_norm(newton.sums().residual);
  sol.objective = newton.sums().f2;
  sol.dual_objective = newton.sums().dual;
  sol.status = Status::Ok;
  sol.refined = true;
}

template <class GraspT>
EIGEN_DONT_INLINE void solve_constrained_iterate(const GraspT& grasp, const Wrench<typename GraspT::ScalarType>& w_ext,
                                                 const ConstrainedSettings<typename GraspT::ScalarType>& settings,
                                                 const Wrench<typename GraspT::ScalarType>* warm,
                                                 const Wrench<typename GraspT::ScalarType>* warm_certificate,
                                                 const Wrench<typename GraspT::ScalarType>& gram_diagonal,
                                                 ConstrainedSolution<GraspT>& sol) {
  using S = typename GraspT::ScalarType;
  using Problem = ForceProblem<GraspT>;
  const int m = grasp.unknowns();
  const bool singular = sol.status == Status::Singular;  // the fast path's verdict on G W^-1 G^T
  sol.forces.resize(m);
  sol.certificate.setZero();
  sol.dual_objective = S(0);
  sol.fast_path = false;
  sol.refined = false;
  sol.iterations = 0;
  sol.passes = 0;
  // Bounds: Newton projects onto the truncated cones, one contact at a time; a soft finger's has no
  // closed form, so a grasp of bounded soft fingers is the interior-point method's alone.
  bool bounded = false;
  for (int i = 0; i < grasp.size(); ++i)
    bounded = bounded || grasp.contact(i).max_normal_force < std::numeric_limits<S>::infinity();
  const int newton_passes = bounded && GraspT::dim == 4 ? 0 : settings.newton_passes;
  typename Problem::Lanes k(grasp.size());
  Problem problem;
  // 0. The previous frame's certificate, where it still proves that the grasp slips; where G has
  // rank < 6 (the fast path declined it), the load's part outside G's range (certificate.hpp).
  Wrench<S> y_unit;
  if ((warm_certificate != nullptr &&
       is_infeasibility_certificate(grasp, w_ext, *warm_certificate, settings.certificate_tolerance, y_unit)) ||
      (singular && range_certificate(grasp, w_ext, settings.certificate_tolerance, y_unit))) {
    answer_slip(grasp, w_ext, settings, gram_diagonal, y_unit, 0, k, problem, sol);
    return;
  }
  DualNewton<GraspT> newton(grasp, w_ext, gram_diagonal, settings.tolerance, bounded);
  // 1. Newton from the warm start, or from the unconstrained optimum's multipliers: the answer
  // when it converges; an infeasible grasp's multipliers may grow along a certificate meanwhile.
  if (newton_passes > 0) {
    const bool done = newton.run(warm != nullptr ? *warm : sol.multipliers, newton_passes);
    sol.passes = newton.passes();
    if (done) {
      take_newton(newton, sol);
      return;
    }
    // Short of convergence on a grasp that slips, the multipliers have grown along a certificate
    // (the dual function rises without bound along one): reversed, they may prove the slip
    // already (one O(n) test, O(1) where -lambda . w_ext <= 0), and the interior-point method's
    // first run is not needed.
    if (is_infeasibility_certificate(grasp, w_ext, Wrench<S>(-newton.lambda()), settings.certificate_tolerance,
                                     y_unit)) {
      answer_slip(grasp, w_ext, settings, gram_diagonal, y_unit, 0, k, problem, sol);
      return;
    }
  }
  // 2. The interior-point method: the optimum (to the handover tolerance, or its own: Newton's
  // refinement gives the solve's), or a certificate that there is none; one iteration is kept
  // for the least-residual problem.
  problem.fill(grasp, w_ext, k, S(1));
  InteriorPointSettings<S> ip;
  const S interior = std::max(S(ScalarTraits<S>::interior_tolerance), settings.tolerance);
  // With Newton's refinement to follow, the method hands over at the looser interior_handover (the
  // gap; the residuals to its square): from there Newton's projections already have their
  // regions (it converges in a few passes), and the last interior-point iterations are saved.
  const S handover = S(ScalarTraits<S>::interior_handover);
  ip.tolerance = newton_passes > 0 ? std::max(interior, handover) : interior;
  ip.feasibility_tolerance = newton_passes > 0 ? std::max(interior, handover * handover) : interior;
  ip.certificate_tolerance = settings.certificate_tolerance;
  // The certificate's slack relative to y's angle with the load, as ConstrainedSettings states it
  // (relative to |b^T y| alone, a load far below the squeezing forces would shrink it by |b|).
  ip.certificate_scale = problem.load_scale;
  ip.max_iterations = settings.max_iterations - 1;
  ip.boundary_answer = newton_passes == 0;  // not at the handover: Newton refines from there
  ip.cost_offset = problem.cost_offset(grasp);
  ip.residual_floor = problem.squeeze_scale(grasp);
  InteriorPointResult<S> r = interior_point(k, problem.b, problem.q_norm, ip);
  sol.iterations = r.iterations;
  sol.passes += 3 * r.iterations + 1 - 2 * r.backtracks;
  if (r.status != Status::Infeasible && newton_passes > 0) {
    // 3. Refined by Newton from the interior-point multipliers, also where the method stopped
    // short (its bound, or a numerical failure): projections, KKT exact.
    const int before = newton.passes();
    const bool done = newton.run(problem.multipliers(r.y, r.tau), before + newton_passes);
    sol.passes += newton.passes() - before;
    if (done) {
      take_newton(newton, sol);
      return;
    }
    // Short of the tolerance: Newton's least-residual iterate is still the exact optimum for the
    // load -G x; within the interior-point tolerance of w_ext, and its duality gap lambda.(G x +
    // w_ext) within that of F2 (the interior-point answer's own test), it is the unrefined answer.
    newton.restore_best();
    const ConstrainedPass<S>& best = newton.sums();
    if (newton.meets(interior) && std::abs(best.f2 - best.dual) <= interior * best.f2) {
      take_newton(newton, sol);
      sol.refined = false;
      return;
    }
  }
  if (r.status == Status::Ok && (ip.tolerance > interior || ip.feasibility_tolerance > interior)) {
    // 4. Not refined from the handover: the interior-point method goes on to its own tolerance.
    ip.tolerance = ip.feasibility_tolerance = interior;
    ip.boundary_answer = true;
    const int before = r.iterations, back = r.backtracks;
    r = interior_point(k, problem.b, problem.q_norm, ip, &r);
    sol.iterations = r.iterations;
    sol.passes += 3 * (r.iterations - before) + 1 - 2 * (r.backtracks - back);
  }
  // An infeasible grasp (found by the first run, or by the resumed one: near the boundary of
  // feasibility the handover gap is reached before the certificate is clear): the certificate,
  // and the least-residual forces.
  if (r.status == Status::Infeasible) {
    answer_slip(grasp, w_ext, settings, gram_diagonal, problem.certificate(r.y), r.iterations, k, problem, sol);
    return;
  }
  // The interior-point answer, not refined (a soft finger with a bound, a soft finger's torsion at
  // micrometres, G nearly of rank < 6): Ok to the interior-point method's tolerance, else its last
  // iterate (IterationLimit).
  problem.forces(grasp, k, r.tau, sol.forces);
  keep_within_bounds(grasp, sol.forces);
  sol.multipliers = problem.multipliers(r.y, r.tau);
  sol.status = Status::IterationLimit;
  const Wrench<S> res = grasp.wrench(sol.forces) + w_ext;
  sol.residual = stable_norm(res);
  sol.objective = objective_f2(grasp, sol.forces);
  const EquilibriumNorm<S>& norm = problem.norm;
  S squeeze(0);
  for (int i = 0; i < grasp.size(); ++i) squeeze = std::max(squeeze, grasp.contact(i).squeeze);
  if (r.status == Status::Ok && norm(res) <= interior * (norm(w_ext) + sol.forces.norm() + squeeze)) {
    sol.status = Status::Ok;
    sol.dual_objective = problem.in_f2_units(r.dual_cost);
  }
  if (!sol.forces.allFinite() || !sol.multipliers.allFinite() || !std::isfinite(sol.objective)) {
    sol.forces.setZero(m);
    sol.multipliers.setZero();
    sol.residual = stable_norm(w_ext);
    sol.objective = objective_f2(grasp, sol.forces);
    if (sol.status == Status::Ok) sol.status = Status::IterationLimit;
  }
}

template <class GraspT>
ConstrainedSolution<GraspT> solve_constrained_impl(
    const GraspT& grasp, const Wrench<typename GraspT::ScalarType>& w_ext,
    const ConstrainedSettings<typename GraspT::ScalarType>& settings, const Wrench<typename GraspT::ScalarType>* warm,
    const Wrench<typename GraspT::ScalarType>* warm_certificate = nullptr) {
  using S = typename GraspT::ScalarType;
  const int m = grasp.unknowns();
  ConstrainedSolution<GraspT> sol;
  if (!grasp.complete() || validate(w_ext) != Status::Ok || !valid_settings(settings) ||
      (warm != nullptr && !(detail::all_in_range(*warm))) ||
      (warm_certificate != nullptr && !(detail::all_in_range(*warm_certificate)))) {
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
  Wrench<S> gram_diagonal = Wrench<S>::Zero();  // of G W^-1 G^T, from the fast path's solve
  if (constrained_fast_path(grasp, w_ext, sol, gram_diagonal)) return sol;
  solve_constrained_iterate(grasp, w_ext, settings, warm, warm_certificate, gram_diagonal, sol);
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

template <class GraspT>
ConstrainedSolution<GraspT> solve_constrained(const GraspT& grasp, const Wrench<typename GraspT::ScalarType>& w_ext,
                                              const ConstrainedSettings<typename GraspT::ScalarType>& settings,
                                              const ConstrainedWarmStart<typename GraspT::ScalarType>& warm) {
  return detail::solve_constrained_impl(grasp, w_ext, settings, warm.has_multipliers ? &warm.multipliers : nullptr,
                                        warm.has_certificate ? &warm.certificate : nullptr);
}

}  // namespace grip
