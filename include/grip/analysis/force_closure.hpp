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
#include <type_traits>

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
  /// Stopping tolerance of the interior-point solver (conic_dual.hpp): the duality gap, the
  /// residuals and the difference of the primal and dual objectives below it (relative to
  /// 1 + |objective|), so the reported margin/scale is within it of the exact optimum. Also
  /// the decision threshold: force closure is reported only when margin > 10 * tolerance.
  Scalar tolerance{ScalarTraits<Scalar>::is_single_precision ? Scalar(1e-4) : Scalar(1e-9)};
  /// Bound on interior-point iterations (each O(n) plus a 7x7 factorisation and two solves):
  /// the worst-case time. Typical solves take 7 to 20.
  int max_newton_steps{100};
  /// Force closure stops once the margin's upper bound falls below this (dimensionless, < 0):
  /// the grasp is then far from closure (every internal force needs tangential components of
  /// -margin times its normal ones), and `margin` reports that bound, not the optimum.
  /// Grasps with no internal force at all (an unbounded dual) end there too.
  Scalar margin_floor{-1000};
};

/// True when `settings` can be used: tolerance finite and > 0, max_newton_steps >= 1,
/// margin_floor finite and < 0 (else the analyses answer InvalidInput).
template <class Scalar>
bool valid_settings(const ConicAnalysisSettings<Scalar>& settings) {
  return settings.tolerance > Scalar(0) && std::isfinite(settings.tolerance) && settings.max_newton_steps >= 1 &&
         settings.margin_floor < Scalar(0) && std::isfinite(settings.margin_floor);
}

/// The outcome of force_closure().
///
/// Ok: decided (closure true/false with the numbers below). IterationLimit: the iteration
/// bound was hit; `margin` is the last dual value (an upper bound on the margin), closure
/// false. InvalidInput: incomplete or empty grasp, bad settings; everything zero.
template <class GraspT>
struct ForceClosure {
  using Scalar = typename GraspT::ScalarType;  ///< The grasp's scalar type.
  bool closure{false};   ///< Force closure, decided with margin > 10 * settings.tolerance.
  /// The margin above (dimensionless): when the solver converged, the one `internal_force`
  /// achieves (a witnessed lower bound, within the tolerance of the optimum); <= 0 or tiny
  /// when not in closure (0 when the rank test fails; an upper bound below
  /// settings.margin_floor when the search stopped there).
  Scalar margin{0};
  /// A unit wrench direction u (force; moment in N m) that cannot be resisted when not in
  /// closure: G_i^T u in K_i^* for all i (to the tolerance), so no contact forces inside the
  /// cones balance w_ext = u. Zero when closure holds.
  Wrench<Scalar> unresisted{Wrench<Scalar>::Zero()};
  /// An internal force (G x = 0 to round-off, see `residual`; sum e_i.x_i = 1) achieving the
  /// margin: x_i - margin e_i inside K_i. The solver's cone multipliers are corrected onto the null
  /// space of G (least squares on the cone spans). Zero when the rank test fails.
  typename GraspT::ForceVector internal_force;
  Scalar residual{0};   ///< |G internal_force| (N and N m).
  int rank{0};          ///< Rank of G restricted to the cone spans (6 needed).
  int iterations{0};    ///< interior-point iterations used.
  Status status{Status::InvalidInput};  ///< Ok, IterationLimit or InvalidInput (see above).
};

/// Decides force closure of `grasp` with its exact cones (see the file comment), returning
/// the margin when it holds and an unresisted wrench direction when it does not. No heap;
/// at most settings.max_newton_steps interior-point iterations of O(n) each.
template <class GraspT>
ForceClosure<GraspT> force_closure(const GraspT& grasp,
                                   const ConicAnalysisSettings<typename GraspT::ScalarType>& settings = {}) {
  using S = typename GraspT::ScalarType;
  using W = typename ScalarTraits<S>::Wide;  // the scalar of the computation (conic_dual.hpp)
  using M = typename GraspT::ModelType;
  constexpr int D = GraspT::dim;
  using XW = Eigen::Matrix<W, GraspT::unknowns_at_compile_time, 1, Eigen::ColMajor, GraspT::max_unknowns, 1>;
  ForceClosure<GraspT> out;
  out.internal_force.setZero(grasp.unknowns());
  const int n = grasp.size();
  if (!grasp.complete() || n == 0 || !valid_settings(settings))
    return out;
  auto contact = [&](int i) -> decltype(auto) { return detail::wide_contact<W>(grasp.contact(i)); };
  const W rho = W(detail::internal_torque_scale(grasp));
  const Wrench<W> dsc = detail::row_scaling(rho);

  // 1. Rank of G on the cone spans: gram = D (sum G_i P_i G_i^T) D, P_i the span projector
  // (the closed forms of the model when P_i = I).
  GramAccumulator<W> acc;
  Wrench<W> ge = Wrench<W>::Zero();  // D G e: sum of the scaled normal columns
  for (int i = 0; i < n; ++i) {
    const auto& c = contact(i);
    if (detail::full_span<M>(c)) {
      M::accumulate(acc, c, W(1));
    } else {
      const Eigen::Matrix<W, 6, D> b = M::basis(c);
      acc.extra.noalias() += b * detail::cone_span<M>(c) * b.transpose();
    }
    ge += M::wrench(c, detail::cone_axis<M>(c));
  }
  const Matrix6<W> gram = dsc.asDiagonal() * acc.matrix() * dsc.asDiagonal();
  ge = dsc.cwiseProduct(ge);
  // Rank: the eigenvalues of gram above rank_tolerance times the largest. Full rank is
  // certain, and the eigen decomposition not needed, when the least eigenvalue's lower bound
  // 1 / tr(gram^-1) (from a pivoted LDL^T with positive pivots) exceeds the cut even against
  // tr(gram), an upper bound on the largest; the factorisation then also serves the
  // least-squares correction below.
  detail::SmallLdlt<6, W> chol;
  const W trace = gram.trace();
  bool full = false;
  const auto fill_gram = [&gram](W (&f)[6][6]) {
    for (int r = 0; r < 6; ++r)
      for (int k = 0; k < 6; ++k) f[r][k] = gram(r, k);
  };
  if (trace > W(0) && std::isfinite(trace) && chol.factor_pivoted(fill_gram, W(0))) {
    W inv_trace(0);
    for (int k = 0; k < 6; ++k) {
      W col[6] = {W(0), W(0), W(0), W(0), W(0), W(0)};
      col[k] = W(1);
      chol.solve(col);
      inv_trace += col[k];
    }
    full = inv_trace > W(0) && W(1) / inv_trace > W(ScalarTraits<S>::rank_tolerance) * trace;
  }
  Wrench<W> ev = Wrench<W>::Ones();  // ascending (when computed)
  Matrix6<W> vecs = Matrix6<W>::Identity();
  out.rank = 6;
  if (!full) {
    detail::symmetric_eigen_6x6_sorted(gram, ev, vecs);
    const W cut = W(ScalarTraits<S>::rank_tolerance) * ev(5);
    out.rank = 0;
    for (int k = 0; k < 6; ++k)
      if (ev(k) > cut && ev(k) > W(0)) ++out.rank;
  }
  if (out.rank < 6) {
    // Any y in the kernel: G_i^T y vanishes on the span of K_i, so it is in K_i^*.
    const Wrench<W> u = dsc.cwiseProduct(vecs.col(0));
    out.unresisted = (u / u.norm()).template cast<S>();
    out.status = Status::Ok;
    return out;
  }

  // 2. The margin problem through its dual.
  Eigen::Matrix<S, 7, 1> c = Eigen::Matrix<S, 7, 1>::Zero(), a, q0 = Eigen::Matrix<S, 7, 1>::Zero();
  c(6) = S(1);
  a.template head<6>() = -ge.template cast<S>();
  a(6) = S(n);
  q0(6) = S(1) / S(n);
  const auto r = detail::solve_conic_dual(grasp, S(rho), c, a, q0, false, settings.tolerance,
                                          settings.max_newton_steps, settings.margin_floor);
  out.iterations = r.iterations;
  W margin = W(r.objective);  // below margin_floor when the solver stopped there (Infeasible)
  // Internal force x = s + t e with t = (1 - sum e.s) / n (s the cone multipliers).
  XW x = r.primal.template cast<W>();
  if (!x.allFinite()) x.setZero(grasp.unknowns());
  W es(0);
  for (int i = 0; i < n; ++i) es += detail::cone_axis<M>(contact(i)).dot(x.template segment<D>(i * D));
  const W t = (W(1) - es) / W(n);
  Wrench<W> gx = Wrench<W>::Zero();  // G x
  for (int i = 0; i < n; ++i) {
    const auto& ci = contact(i);
    x.template segment<D>(i * D) += t * detail::cone_axis<M>(ci);
    gx += M::wrench(ci, Eigen::Matrix<W, D, 1>(x.template segment<D>(i * D)));
  }
  bool measured = false;  // out.residual set from x below
  if (r.status == Status::Ok) {
    // The multipliers balance only to the solver's tolerance; make x internal to round-off
    // by the least-squares correction on the cone spans, x_i -= P_i (D G_i)^T z with
    // (sum (D G_i) P_i (D G_i)^T) z = D G x (rank 6 here), then report the margin this x
    // achieves: a witnessed lower bound, within the tolerance of the dual's upper bound.
    const Wrench<W> res = dsc.cwiseProduct(gx);
    Wrench<W> z;
    if (full) {
      W col[6];
      for (int k = 0; k < 6; ++k) col[k] = res(k);
      chol.solve(col);
      for (int k = 0; k < 6; ++k) z(k) = col[k];
    } else {
      z = vecs * (vecs.transpose() * res).cwiseQuotient(ev);
    }
    const Wrench<W> dz = dsc.cwiseProduct(z);  // (D G_i)^T z = G_i^T (D z)
    W sum(0), achieved(0);
    for (int i = 0; i < n; ++i) {
      const auto& ci = contact(i);
      Eigen::Matrix<W, D, 1> step = M::wrench_transpose(ci, dz);
      if (!detail::full_span<M>(ci)) step = detail::cone_span<M>(ci) * step;
      x.template segment<D>(i * D) -= step;
      sum += detail::cone_axis<M>(ci).dot(x.template segment<D>(i * D));
    }
    x /= sum;
    gx.setZero();
    for (int i = 0; i < n; ++i) {
      const auto& ci = contact(i);
      const Eigen::Matrix<W, D, 1> xi = x.template segment<D>(i * D);
      const W ti = detail::normal_margin<M>(ci, xi);
      achieved = i == 0 ? ti : std::min(achieved, ti);
      gx += M::wrench(ci, xi);
    }
    measured = std::is_same<S, W>::value;
    if (x.allFinite() && std::isfinite(achieved)) {
      margin = std::min(margin, achieved);
    } else {
      x.setZero(grasp.unknowns());
      measured = false;
    }
  }
  out.margin = S(margin);
  out.internal_force = x.template cast<S>();
  if (!measured) {  // |G x| of the reported (rounded) force
    gx.setZero();
    for (int i = 0; i < n; ++i)
      gx += M::wrench(contact(i), Eigen::Matrix<W, D, 1>(out.internal_force.template segment<D>(i * D).template cast<W>()));
  }
  out.residual = S(gx.norm());
  out.status = r.status == Status::IterationLimit ? Status::IterationLimit : Status::Ok;
  out.closure = out.status == Status::Ok && out.margin > S(10) * settings.tolerance;
  if (!out.closure) {
    const Wrench<W> u = -dsc.cwiseProduct(r.y.template cast<W>());
    const W nu = u.norm();
    if (nu > W(0) && std::isfinite(nu)) out.unresisted = (u / nu).template cast<S>();
  }
  return out;
}

}  // namespace grip
