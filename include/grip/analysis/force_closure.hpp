#pragma once
/// \file
/// Force closure with a certificate, for the exact friction cones, without convex hulls.
///
/// A grasp is in force closure when forces inside the contact cones can balance every
/// external wrench: G (K_1 x ... x K_n) = R^6. Theorem (Murray, Li & Sastry 1994,
/// Prop. 5.2; Salisbury & Roth 1983): with cones that are full-dimensional in their own
/// span, this holds iff G restricted to those spans has rank 6 and some internal force
/// (G x = 0) lies in the relative interior of every cone.
///
/// The second condition is decided by the conic problem (exact cones, see conic_dual.hpp)
///     margin = max t  s.t.  G x = 0,  x_i - t e_i in K_i,  sum_i e_i . x_i = 1,
/// e_i the unit normal direction of contact i. Read `margin` as: the largest t such that
/// some internal force with total normal force 1 keeps every contact force inside its cone
/// after taking t off its normal component (t <= 1/n; for a hard finger x_n - |x_t|/mu >= t).
/// It is solved through its 7-variable dual,
///     min z  s.t.  z e_i - G_i^T y in K_i^*,  n z - (G e) . y = 1,
/// whose optimum equals the margin (strong duality: y = 0, z = 1/n is strictly feasible).
/// When the margin is <= 0 the dual solution gives the certificate u = -y != 0 with
/// G_i^T u in K_i^* for every i: every wrench the contacts can apply satisfies u . w >= 0,
/// so the external wrench w_ext = u (and any with u . w_ext > 0) cannot be resisted.
/// Nguyen, "Constructing force-closure grasps", IJRR 7(3), 1988, gives the two-finger
/// geometric test that the tests check this against.

#include <cmath>

#include "grip/analysis/conic_dual.hpp"
#include "grip/core/scalar_traits.hpp"
#include "grip/core/status.hpp"
#include "grip/core/types.hpp"
#include "grip/grasp/grasp.hpp"
#include "grip/solve/symmetric_solve.hpp"

namespace grip {

/// Tolerances and bounds of the conic analyses (force closure, largest resistible wrench).
template <class Scalar>
struct ConicAnalysisSettings {
  /// Barrier bound theta/tau at which the solver stops (relative to 1 + |objective|); the
  /// reported margin/scale is within this of the exact optimum. Also the decision threshold:
  /// force closure is reported only when margin > 10 * tolerance.
  Scalar tolerance{ScalarTraits<Scalar>::is_single_precision ? Scalar(1e-4) : Scalar(1e-9)};
  /// Bound on Newton steps (each O(n) plus a 6x6 solve): the worst-case time.
  int max_newton_steps{400};
};

/// True when `settings` can be used: tolerance finite and > 0, max_newton_steps >= 1 (else the
/// analyses answer InvalidInput).
template <class Scalar>
bool valid_settings(const ConicAnalysisSettings<Scalar>& settings) {
  return settings.tolerance > Scalar(0) && std::isfinite(settings.tolerance) && settings.max_newton_steps >= 1;
}

/// The outcome of force_closure().
///
/// Ok: decided (closure true/false with the numbers below). IterationLimit: the Newton
/// bound was hit; `margin` is the last dual value (an upper bound on the margin), closure
/// false. InvalidInput: incomplete or empty grasp, bad settings; everything zero.
template <class GraspT>
struct ForceClosure {
  using Scalar = typename GraspT::ScalarType;  ///< The grasp's scalar type.
  bool closure{false};   ///< Force closure, decided with margin > 10 * settings.tolerance.
  /// The margin above (dimensionless): when the solver converged, the one `internal_force`
  /// achieves (a witnessed lower bound, within the tolerance of the optimum); <= 0 or tiny
  /// when not in closure (0 when the rank test fails).
  Scalar margin{0};
  /// A unit wrench direction u (force; moment in N m) that cannot be resisted when not in
  /// closure: G_i^T u in K_i^* for all i (to the tolerance), so no contact forces inside the
  /// cones balance w_ext = u. Zero when closure holds.
  Wrench<Scalar> unresisted{Wrench<Scalar>::Zero()};
  /// An internal force (G x = 0 to round-off, see `residual`; sum e_i.x_i = 1) achieving the
  /// margin: x_i - margin e_i inside K_i. The barrier's primal point is corrected onto the null
  /// space of G (least squares on the cone spans). Zero when the rank test fails.
  typename GraspT::ForceVector internal_force;
  Scalar residual{0};   ///< |G internal_force| (N and N m).
  int rank{0};          ///< Rank of G restricted to the cone spans (6 needed).
  int iterations{0};    ///< Newton steps used.
  Status status{Status::InvalidInput};  ///< Ok, IterationLimit or InvalidInput (see above).
};

/// Decides force closure of `grasp` with its exact cones (see the file comment), returning
/// the margin when it holds and an unresisted wrench direction when it does not. No heap;
/// at most settings.max_newton_steps Newton steps of O(n) each.
template <class GraspT>
ForceClosure<GraspT> force_closure(const GraspT& grasp,
                                   const ConicAnalysisSettings<typename GraspT::ScalarType>& settings = {}) {
  using S = typename GraspT::ScalarType;
  using M = typename GraspT::ModelType;
  constexpr int D = GraspT::dim;
  ForceClosure<GraspT> out;
  out.internal_force.setZero(grasp.unknowns());
  const int n = grasp.size();
  if (!grasp.complete() || n == 0 || !valid_settings(settings))
    return out;
  const S rho = detail::internal_torque_scale(grasp);
  const Wrench<S> dsc = detail::row_scaling(rho);

  // 1. Rank of G on the cone spans.
  Wrench<S> ev;  // ascending
  Matrix6<S> vecs;
  detail::symmetric_eigen_6x6_sorted(detail::cone_span_gram(grasp, rho), ev, vecs);
  const S cut = ScalarTraits<S>::rank_tolerance * ev(5);
  out.rank = 0;
  for (int k = 0; k < 6; ++k)
    if (ev(k) > cut && ev(k) > S(0)) ++out.rank;
  if (out.rank < 6) {
    // Any y in the kernel: G_i^T y vanishes on the span of K_i, so it is in K_i^*.
    const Wrench<S> u = dsc.cwiseProduct(vecs.col(0));
    out.unresisted = u / u.norm();
    out.status = Status::Ok;
    return out;
  }

  // 2. The margin problem through its dual.
  Eigen::Matrix<S, 7, 1> c = Eigen::Matrix<S, 7, 1>::Zero(), a, q0 = Eigen::Matrix<S, 7, 1>::Zero();
  c(6) = S(1);
  Wrench<S> ge = Wrench<S>::Zero();
  for (int i = 0; i < n; ++i) {
    const auto k = detail::exact_cone<M>(grasp.contact(i));
    ge.noalias() += dsc.asDiagonal() * (M::basis(grasp.contact(i)) * k.axis);
  }
  a.template head<6>() = -ge;
  a(6) = S(n);
  q0(6) = S(1) / S(n);
  const auto r = detail::solve_conic_dual(grasp, rho, c, a, q0, false, settings.tolerance, settings.max_newton_steps);
  out.iterations = r.iterations;
  out.margin = r.status == Status::Infeasible ? S(-1) : r.objective;
  // Internal force x = s + t e with t = (1 - sum e.s) / n (the primal point of the barrier).
  S es(0);
  for (int i = 0; i < n; ++i)
    es += detail::exact_cone<M>(grasp.contact(i)).axis.dot(r.primal.template segment<D>(i * D));
  const S t = (S(1) - es) / S(n);
  for (int i = 0; i < n; ++i)
    out.internal_force.template segment<D>(i * D) =
        r.primal.template segment<D>(i * D) + t * detail::exact_cone<M>(grasp.contact(i)).axis;
  if (!out.internal_force.allFinite()) out.internal_force.setZero(grasp.unknowns());
  if (r.status == Status::Ok) {
    // The barrier's primal point is internal only up to its centering; make it internal to
    // round-off by the least-squares correction on the cone spans, x_i -= P_i (D G_i)^T z with
    // (sum (D G_i) P_i (D G_i)^T) z = D G x (rank 6 here), then report the margin this x
    // achieves: a witnessed lower bound, within the tolerance of the dual's upper bound.
    const Wrench<S> res = dsc.cwiseProduct(grasp.wrench(out.internal_force));
    const Wrench<S> z = vecs * (vecs.transpose() * res).cwiseQuotient(ev);
    S sum(0), achieved(0);
    for (int i = 0; i < n; ++i) {
      const auto k = detail::exact_cone<M>(grasp.contact(i));
      const Eigen::Matrix<S, 6, D> b = dsc.asDiagonal() * M::basis(grasp.contact(i));
      out.internal_force.template segment<D>(i * D) -= k.span * (b.transpose() * z);
      sum += k.axis.dot(out.internal_force.template segment<D>(i * D));
    }
    out.internal_force /= sum;
    for (int i = 0; i < n; ++i) {
      const Eigen::Matrix<S, D, 1> xi = out.internal_force.template segment<D>(i * D);
      const S ti = detail::normal_margin<M>(grasp.contact(i), xi);
      achieved = i == 0 ? ti : std::min(achieved, ti);
    }
    if (out.internal_force.allFinite() && std::isfinite(achieved))
      out.margin = std::min(out.margin, achieved);
    else
      out.internal_force.setZero(grasp.unknowns());
  }
  out.residual = grasp.wrench(out.internal_force).norm();
  out.status = r.status == Status::IterationLimit ? Status::IterationLimit : Status::Ok;
  out.closure = out.status == Status::Ok && out.margin > S(10) * settings.tolerance;
  if (!out.closure) {
    const Wrench<S> u = -dsc.cwiseProduct(r.y);
    const S nu = u.norm();
    if (nu > S(0) && std::isfinite(nu)) out.unresisted = u / nu;
  }
  return out;
}

}  // namespace grip
