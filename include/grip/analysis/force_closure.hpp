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
/// The second condition is decided by the conic problem (exact cones)
///     margin = max t  s.t.  G x = 0,  x_i - t e_i in K_i,  sum_i e_i . x_i = 1,
/// e_i the unit normal direction of contact i. Read `margin` as: the largest t such that
/// some internal force with total normal force 1 keeps every contact force inside its cone
/// after taking t off its normal component (t <= 1/n; for a hard finger x_n - |x_t|/mu >= t).
/// Its dual is
///     min zeta  s.t.  G_i^T u + zeta e_i in K_i^*,  n zeta + (G e) . u = 1,
/// whose optimum equals the margin (strong duality: u = 0, zeta = 1/n is strictly feasible).
/// Both are solved together by the interior-point method of solve_constrained (a homogeneous
/// embedding with Nesterov-Todd scaling and Mehrotra steps, solve/detail/interior_point.hpp), on
/// the margin problem with t eliminated (detail/conic_analysis.hpp): u is T y for the
/// multipliers y of its six rows.
/// When the margin is <= 0 the dual solution u != 0 has G_i^T u in K_i^* for every i
/// (G_i^T u = (G_i^T u + margin e_i) - margin e_i, and e_i in K_i^*): every wrench the contacts
/// can apply satisfies u . w >= 0, so the external wrench w_ext = u (and any with
/// u . w_ext > 0) cannot be resisted. When no internal force has normal forces summing to 1 at
/// all (six frictionless points of rank 6, two soft fingers whose normals make equal angles with
/// the line through them), the margin problem is infeasible and the method returns a
/// certificate y: b^T y < 0 and A_i^T y in Q for every contact (A_i, b its rows). For the margin
/// problem this reads zeta e_i + G_i^T u in K_i^* with zeta = b^T y / n < 0, u = T y; as e_i is
/// in K_i^* and -zeta > 0, G_i^T u = (zeta e_i + G_i^T u) + (-zeta) e_i is in K_i^* too (inside
/// it by -zeta along e_i, which covers the certificate's slack, certificate_tolerance |b^T y|,
/// while that tolerance is below 1/n): u is again an unresisted wrench.
/// Nguyen, "Constructing force-closure grasps", IJRR 7(3), 1988, gives the two-finger
/// geometric test that the tests check this against.

#include <algorithm>
#include <cmath>
#include <type_traits>

#include "grip/analysis/detail/analysis_cones.hpp"
#include "grip/analysis/detail/conic_analysis.hpp"
#include "grip/contact/cone_support.hpp"
#include "grip/core/scalar_traits.hpp"
#include "grip/core/status.hpp"
#include "grip/core/types.hpp"
#include "grip/grasp/grasp.hpp"
#include "grip/solve/detail/interior_point.hpp"
#include "grip/solve/symmetric_solve.hpp"

namespace grip {

/// Tolerances and bounds of the conic analyses (force closure, largest resistible wrench).
template <class Scalar>
struct ConicAnalysisSettings {
  /// Stopping tolerance of the interior-point method (solve/detail/interior_point.hpp): its
  /// residuals (relative to the data and the iterate) and the gap between the primal and dual
  /// objectives (relative to the objective, or for force closure to n where that is larger: the
  /// margin problem's objective is 1 - n margin) below it, so that the scale is within about
  /// tolerance times itself of the optimum. Force closure's margin is Ok only once an internal
  /// force achieves it and the multipliers bound it from above within tolerance (1 + |margin|).
  /// Also the certificates' slack (relative), and the decision threshold: force closure is
  /// reported only when margin > 10 * tolerance. In double, 1e-6: the method's iterates reach
  /// about 1e-8 on the margin problem and 1e-7 on the wrench problem before rounding stalls them.
  Scalar tolerance{ScalarTraits<Scalar>::is_single_precision ? Scalar(1e-4) : Scalar(1e-6)};
  /// Bound on interior-point iterations (each three O(n) passes over the contacts and two 6x6
  /// factorisations' worth of solves): the worst-case time. Typical solves take 6 to 12.
  int max_iterations{50};
};

/// True when `settings` can be used: tolerance finite and > 0, max_iterations >= 1 (else the
/// analyses answer InvalidInput).
template <class Scalar>
bool valid_settings(const ConicAnalysisSettings<Scalar>& settings) {
  return settings.tolerance > Scalar(0) && std::isfinite(settings.tolerance) && settings.max_iterations >= 1;
}

/// The outcome of force_closure().
///
/// Ok: decided (closure true/false with the numbers below). IterationLimit: the iteration
/// bound was hit; `margin` is an upper bound on the margin (from the last multipliers), closure
/// false. InvalidInput: incomplete or empty grasp, bad settings; everything zero.
template <class GraspT>
struct ForceClosure {
  using Scalar = typename GraspT::ScalarType;  ///< The grasp's scalar type.
  bool closure{false};                         ///< Force closure, decided with margin > 10 * settings.tolerance.
  /// The margin above (dimensionless): when the method converged, the one `internal_force`
  /// achieves (a witnessed lower bound, within the tolerance of the optimum), or the upper bound
  /// the multipliers give if that is less; <= 0 or tiny when not in closure; 0 when the rank test
  /// fails; cone_margin_floor() (-ScalarTraits::max_magnitude) when no internal force has normal
  /// forces summing to 1 (the margin problem is infeasible); an upper bound at IterationLimit.
  Scalar margin{0};
  /// A unit wrench direction u (force; moment in N m) that cannot be resisted, when the status is
  /// Ok and there is no closure: G_i^T u in K_i^* for all i (to the tolerance), so no contact
  /// forces inside the cones balance w_ext = u. Zero when closure holds or at IterationLimit.
  Wrench<Scalar> unresisted{Wrench<Scalar>::Zero()};
  /// An internal force (G x = 0 to round-off, see `residual`; sum e_i.x_i = 1) achieving the
  /// margin: x_i - margin e_i inside K_i. The method's cone variables are corrected onto the null
  /// space of G (least squares on the cone spans). Zero when the rank test fails or the margin
  /// problem is infeasible; at IterationLimit the last iterate's, not corrected.
  typename GraspT::ForceVector internal_force;
  Scalar residual{0};                   ///< |G internal_force| (N and N m).
  int rank{0};                          ///< Rank of G restricted to the cone spans (6 needed).
  int iterations{0};                    ///< interior-point iterations used.
  Status status{Status::InvalidInput};  ///< Ok, IterationLimit or InvalidInput (see above).
};

/// Decides force closure of `grasp` with its exact cones (see the file comment), returning
/// the margin when it holds and an unresisted wrench direction when it does not. No heap;
/// at most settings.max_iterations interior-point iterations of O(n) each.
template <class GraspT>
ForceClosure<GraspT> force_closure(const GraspT& grasp,
                                   const ConicAnalysisSettings<typename GraspT::ScalarType>& settings = {}) {
  using S = typename GraspT::ScalarType;
  using Analysis = detail::ConicAnalysis<GraspT>;
  using W = typename Analysis::W;  // the scalar of the computation (ScalarTraits<S>::Wide)
  using M = typename GraspT::ModelType;
  constexpr int D = GraspT::dim;
  using XW = Eigen::Matrix<W, GraspT::unknowns_at_compile_time, 1, Eigen::ColMajor, GraspT::max_unknowns, 1>;
  ForceClosure<GraspT> out;
  out.internal_force.setZero(grasp.unknowns());
  const int n = grasp.size();
  if (!grasp.complete() || n == 0 || !valid_settings(settings)) return out;
  auto contact = [&](int i) -> decltype(auto) { return detail::wide_contact<W>(grasp.contact(i)); };
  Analysis problem(grasp);
  const Wrench<W> dsc = problem.norm().weights();

  // 1. Rank of G on the cone spans: gram = D (sum G_i P_i G_i^T) D, P_i the span projector
  // (the closed forms of the model when P_i = I).
  GramAccumulator<W> acc;
  for (int i = 0; i < n; ++i) {
    const auto& c = contact(i);
    if (detail::full_span<M>(c)) {
      M::accumulate(acc, c, W(1));
    } else {
      const Eigen::Matrix<W, 6, D> b = M::basis(c);
      acc.extra.noalias() += b * detail::cone_span<M>(c) * b.transpose();
    }
  }
  const Matrix6<W> gram = dsc.asDiagonal() * acc.matrix() * dsc.asDiagonal();
  // Rank: the eigenvalues of gram above rank_tolerance times the largest. Full rank is
  // certain, and the eigen decomposition not needed, when the least eigenvalue's lower bound
  // 1 / tr(gram^-1) (from a pivoted LDL^T with positive pivots) exceeds the cut even against
  // tr(gram), an upper bound on the largest; the factorisation then also serves the
  // least-squares correction below.
  detail::SmallLdlt<6, W> chol;
  const W trace = gram.trace();
  bool full = false;
  const auto fill_gram = [&gram](W(&f)[6][6]) {
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

  // 2. The margin problem (detail/conic_analysis.hpp). Its objective is 1 - n t, so a gap of
  // tolerance max(|objective|, n) is one of tolerance (1 + |t|) in the margin t; the rows'
  // residuals are measured against the forces' scale, normal forces of 1 on average.
  typename Analysis::Lanes k(n);
  const Wrench<W> b = problem.margin_problem(grasp, k);
  const W inv_n = W(1) / W(n), tol = W(settings.tolerance);
  auto st = Analysis::settings(tol, settings.max_iterations, W(1), W(n));
  detail::InteriorPointResult<W> r = detail::interior_point(k, b, std::sqrt(inv_n), st);
  if (r.status == Status::Infeasible) {
    // No internal force with sum e.x = 1: T y is unresisted (see the file comment).
    const Wrench<W> u = dsc.cwiseProduct(r.y);
    out.iterations = r.iterations;
    out.margin = cone_margin_floor<S>();
    out.unresisted = (u / u.norm()).template cast<S>();
    out.status = Status::Ok;
    return out;
  }
  // The margin between two bounds: above, the one the multipliers' direction T y gives
  // (margin_bound); below, the one an internal force achieves: x = s + t e from the cone
  // variables (s_i = M_i u_i / (n tau), t = (1 - sum e.s) / n), which balance only to the
  // method's tolerance, made internal to round-off by the least-squares correction on the cone
  // spans, x_i -= P_i (D G_i)^T z with (sum (D G_i) P_i (D G_i)^T) z = D G x (rank 6 here).
  // Ok once the two are within tolerance (1 + |margin|) of each other: the method goes on at a
  // tenth of its tolerance while they are not (its primal iterate, and so the lower bound, can
  // lag behind the gap's test), at most twice.
  XW x(grasp.unknowns());
  W upper(0), achieved(0);
  Wrench<W> u = Wrench<W>::Zero(), gx = Wrench<W>::Zero();
  bool corrected = false;
  for (int round = 0;; ++round) {
    u = dsc.cwiseProduct(r.y);
    upper = problem.margin_bound(grasp, u);
    W es(0);
    for (int i = 0; i < n; ++i) {
      x.template segment<D>(i * D) = problem.force(k, i) * (inv_n / r.tau);
      es += detail::cone_axis<M>(contact(i)).dot(x.template segment<D>(i * D));
    }
    const W t = (W(1) - es) / W(n);
    gx.setZero();
    for (int i = 0; i < n; ++i) {
      const auto& ci = contact(i);
      x.template segment<D>(i * D) += t * detail::cone_axis<M>(ci);
      gx += M::wrench(ci, Eigen::Matrix<W, D, 1>(x.template segment<D>(i * D)));
    }
    if (!x.allFinite()) x.setZero(grasp.unknowns());
    corrected = false;
    if (r.status != Status::Ok) break;
    const Wrench<W> res = dsc.cwiseProduct(gx);
    Wrench<W> z;
    if (full) {
      W col[6];
      for (int j = 0; j < 6; ++j) col[j] = res(j);
      chol.solve(col);
      for (int j = 0; j < 6; ++j) z(j) = col[j];
    } else {
      z = vecs * (vecs.transpose() * res).cwiseQuotient(ev);
    }
    const Wrench<W> dz = dsc.cwiseProduct(z);  // (D G_i)^T z = G_i^T (D z)
    W sum(0);
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
    corrected = x.allFinite() && std::isfinite(achieved);
    if (!corrected) {
      x.setZero(grasp.unknowns());
      r.status = Status::IterationLimit;
      break;
    }
    if (upper - achieved <= tol * (W(1) + std::abs(achieved))) break;
    if (round == 2 || r.iterations >= settings.max_iterations) {
      r.status = Status::IterationLimit;
      break;
    }
    st.tolerance /= W(10);
    st.feasibility_tolerance /= W(10);
    r = detail::interior_point(k, b, std::sqrt(inv_n), st, &r);
    if (r.status == Status::Infeasible) r.status = Status::IterationLimit;  // not after an optimum
  }
  out.iterations = r.iterations;
  out.status = r.status == Status::Ok ? Status::Ok : Status::IterationLimit;
  // Ok: the witnessed lower bound (within the tolerance of the upper one). IterationLimit: the
  // upper bound.
  out.margin = S(out.status == Status::Ok ? std::min(upper, achieved) : upper);
  out.internal_force = x.template cast<S>();
  if (!corrected || !std::is_same<S, W>::value) {  // |G x| of the reported (rounded) force
    gx.setZero();
    for (int i = 0; i < n; ++i)
      gx += M::wrench(contact(i),
                      Eigen::Matrix<W, D, 1>(out.internal_force.template segment<D>(i * D).template cast<W>()));
  }
  out.residual = S(gx.norm());
  out.closure = out.status == Status::Ok && out.margin > S(10) * settings.tolerance;
  if (out.status == Status::Ok && !out.closure) {
    const W nu = u.norm();
    if (nu > W(0) && std::isfinite(nu)) out.unresisted = (u / nu).template cast<S>();
  }
  return out;
}

}  // namespace grip
