#pragma once
/// \file
/// The interior-point method of grip's conic problems (namespace grip::detail): a primal-dual
/// method on a homogeneous embedding, with Nesterov-Todd scaling and Mehrotra's
/// predictor-corrector steps. The contacts' work lives in ConicLanes (conic_lanes.hpp); this is
/// the driver, with the 6 x 6 systems between the passes.
///
/// The problem (ConicLanes): minimise 1/2 x^T P x + q^T x subject to A x = b tau-free rows and
/// per-contact cones; in the soft form the rows are replaced by the term 1/2 |A u - b|^2 (a free
/// variable r = A u - b with P_r = I). Its homogeneous embedding (Goulart and Chen, for a
/// quadratic objective) is
///     P x + A^T y - z + q tau = 0,      A x - b tau = 0,      u_i = its own cone slack,
///     kappa = -q^T x - b^T y - x^T P x / tau,      x, z in the cones, tau, kappa >= 0,
/// solved from x = z = theta e, y = 0, tau = 1, kappa = theta^2 (theta = start_scale, 1 unless the
/// caller knows the solution's scale: the first iterations then need not shrink the iterate to it;
/// every pair's complementarity, and so mu, starts at theta^2). A solution with tau > 0 gives the optimum
/// x / tau with multipliers y / tau; tau -> 0 with b^T y < 0 gives y as a certificate that no x
/// in the cones satisfies A x = b (A_i^T y in Q for every contact). Each iteration: the passes
/// and systems of ConicLanes, a predictor to the boundary (its step alpha_a sets the centring
/// sigma = (1 - alpha_a)^3) and a corrector with Mehrotra's second-order term, whose step is
/// ScalarTraits::interior_step (0.99 in double, 0.95 in float) of the largest that keeps every
/// variable in its cone. A cone pair outside the wide neighbourhood of the central path (its
/// smallest scaled eigenvalue squared below gamma mu, gamma = ScalarTraits::interior_neighbourhood)
/// is centred toward max(sigma, gamma) mu (ConeBlock::recentre_part): without it, a pair driven
/// to its boundary early can hold every later step to a sliver of its length.
///
/// It stops at the first iterate that is optimal to the tolerance (the residuals relative to the
/// data and the iterate, and the gap relative to the objective, all below it); with
/// `boundary_answer`, at one that meets the residual tolerances while tau has fallen below
/// ScalarTraits::interior_boundary times its largest value (Ok: a load on the boundary of the
/// feasible set, where no strictly feasible point exists, sends tau and kappa both toward zero
/// and the dual iterate along an unbounded ray, so that the gap stops closing), its rows'
/// residual relative to the data alone, b and residual_floor (an infeasible problem's x / tau
/// grows without bound, and a residual relative to it would pass); or, in the hard
/// form, at one that carries an infeasibility certificate to `certificate_tolerance`: b^T y < 0 with
/// min_i margin(A_i^T y) >= -certificate_tolerance |b^T y| / certificate_scale, so that no x in
/// the cones with sum_i |u_i| below about certificate_scale / certificate_tolerance (the
/// problem's data being normalised to 1) satisfies A x = b. With certificate_scale = |b| the
/// slack is relative to the angle between y and b alone, and the bound on x relative to |b|.
///
/// References: P. J. Goulart and Y. Chen, "Clarabel: An interior-point solver for conic programs
/// with quadratic objectives", arXiv:2405.12762 (2024), sections 2-3 (the embedding and its
/// Newton step); L. Vandenberghe, "The CVXOPT linear and quadratic cone program solvers" (2010)
/// (scaling); S. Mehrotra, "On the implementation of a primal-dual interior point method", SIAM J.
/// Optim. 2(4), 1992; S. J. Wright, "Primal-Dual Interior-Point Methods", SIAM (1997), chapter 5
/// (the wide neighbourhood).

#include <algorithm>
#include <cmath>
#include <limits>

#include "grip/core/scalar_traits.hpp"
#include "grip/core/status.hpp"
#include "grip/core/simd.hpp"
#include "grip/core/types.hpp"
#include "grip/solve/detail/conic_lanes.hpp"

namespace grip {
namespace detail {

/// How the interior-point method runs.
template <class S>
struct InteriorPointSettings {
  S tolerance{S(1e-8)};              ///< the gap, relative to the objective (see the file comment)
  S feasibility_tolerance{S(1e-8)};  ///< the residuals, relative to the data and the iterate
  S certificate_tolerance{S(1e-8)};  ///< the certificate's slack, relative to |b^T y| / certificate_scale
  int max_iterations{40};            ///< iterations (three passes over the contacts each)
  bool soft{false};                  ///< the soft form: 1/2 |A u - b|^2 instead of A u = b
  S cost_offset{0};                  ///< a constant of the objective (the gap's relative test counts it)
  S residual_floor{0};               ///< added to |b| + |x| as the rows' residual scale (the targets' size)
  S objective_floor{0};              ///< the gap's scale is max(|objective|, objective_floor) (an absolute floor)
  bool boundary_answer{false};       ///< hard form: stop Ok on the boundary of feasibility (see the file comment)
  S start_scale{1};                  ///< theta of a fresh run's start (see the file comment): finite, > 0
  S certificate_scale{1};            ///< see certificate_tolerance and the file comment: finite, > 0
};

/// What the interior-point method returns.
template <class S>
struct InteriorPointResult {
  /// Ok (optimal to the tolerance), Infeasible (certificate found; hard form only) or
  /// IterationLimit (the bound, or a numerical failure: a scaling or a solve not finite).
  Status status{Status::IterationLimit};
  int iterations{0};               ///< iterations made
  Wrench<S> y{Wrench<S>::Zero()};  ///< the multipliers of the rows (not divided by tau)
  Wrench<S> r{Wrench<S>::Zero()};  ///< the soft form's r (not divided by tau)
  S tau{1};                        ///< the embedding's tau: the solution is x / tau
  S kappa{1};                      ///< the embedding's kappa
  S alpha{0};                      ///< the last step's length, taken at the next iteration's start
  S dual_cost{0};     ///< the dual objective at the last iterate, cost_offset - (b^T y + x^T P x / 2 tau) / tau
  int backtracks{0};  ///< steps halved back into the cones (one pass each, counted in iterations)
  S tau_max{1};       ///< the largest tau of the run so far (the boundary test; a resumed run goes on from it)
};

/// LDL^T of the symmetric positive (semi)definite 6 x 6 matrix m in natural order, with pivots
/// floored at `floor` (a pivot at or below it, from rank deficiency or rounding, is replaced by
/// it: the solve then stays finite and the iteration's next residuals correct the direction).
/// Where the build optimises for speed, every loop unrolls into straight-line code (GRIP_UNROLL);
/// for size (-Os) they stay loops.
template <class S>
struct Ldlt6 {
  S l[6][6];   ///< L below the diagonal (unit diagonal)
  S d[6];      ///< D
  S inv_d[6];  ///< 1 / D
  /// Factors m (full storage). False if a pivot is not finite.
  GRIP_ALWAYS_INLINE bool factor(const Matrix6<S>& m, S floor) {
    GRIP_UNROLL(6)
    for (int j = 0; j < 6; ++j) {
      S w[6];  // L(j, k) d_k for k < j
      S dj = m(j, j);
      for (int k = 0; k < j; ++k) {
        w[k] = l[j][k] * d[k];
        dj -= w[k] * l[j][k];
      }
      if (!(dj > floor)) dj = floor;
      d[j] = dj;
      inv_d[j] = S(1) / dj;
      for (int i = j + 1; i < 6; ++i) {
        S v = m(i, j);
        for (int k = 0; k < j; ++k) v -= l[i][k] * w[k];
        l[i][j] = v * inv_d[j];
      }
    }
    // A NaN pivot is floored above (the comparison fails), so only +inf is left to catch.
    return std::isfinite(d[0] + d[1] + d[2] + d[3] + d[4] + d[5]);
  }
  /// m^-1 b.
  GRIP_ALWAYS_INLINE Wrench<S> solve(const Wrench<S>& b) const {
    S x[6] = {b(0), b(1), b(2), b(3), b(4), b(5)};
    GRIP_UNROLL(6)
    for (int i = 1; i < 6; ++i)
      for (int k = 0; k < i; ++k) x[i] -= l[i][k] * x[k];
    for (int i = 0; i < 6; ++i) x[i] *= inv_d[i];
    GRIP_UNROLL(6)
    for (int i = 4; i >= 0; --i)
      for (int k = i + 1; k < 6; ++k) x[i] -= l[k][i] * x[k];
    Wrench<S> out;
    for (int i = 0; i < 6; ++i) out(i) = x[i];
    return out;
  }
};

/// Runs the interior-point method on the problem in `k` with rows' right-hand side b (see the file
/// comment); `k` is left at the last iterate (u, z, and the bounds' s, t). `q_norm` = |q|.
/// `resume`: the result of an earlier run on the same lanes, to go on from (with, say, a tighter
/// tolerance; its iterations count toward st.max_iterations); nullptr for a fresh run from
/// st.start_scale times the cones' centres.
template <class Lanes, class S>
InteriorPointResult<S> interior_point(Lanes& k, const Wrench<S>& b, S q_norm, const InteriorPointSettings<S>& st,
                                      const InteriorPointResult<S>* resume = nullptr) {
  InteriorPointResult<S> out;
  if (resume != nullptr) {
    out = *resume;
  } else if (st.start_scale != S(1)) {
    k.start(st.start_scale);
    out.kappa = st.start_scale * st.start_scale;
  }
  out.status = Status::IterationLimit;
  const S eps = std::numeric_limits<S>::epsilon();
  const S b_norm = b.norm();
  const S slack = st.certificate_tolerance / st.certificate_scale;  // the certificate's, per unit of |b^T y|
  const S nu = S(k.degree() + 1);
  Wrench<S>& y = out.y;
  Wrench<S>& r = out.r;
  S& tau = out.tau;
  S& kappa = out.kappa;
  S& alpha = out.alpha;
  Ldlt6<S> ldlt;
  // The last step's direction: a step that rounding carries out of a cone (the step lengths are
  // computed, so in float near the boundary they can overshoot) is halved back, at most
  // max_backtracks times; each is one pass and counts as an iteration.
  Wrench<S> last_dy = Wrench<S>::Zero(), last_dr = Wrench<S>::Zero();
  S last_dtau(0), last_dkappa(0);
  constexpr int max_backtracks = 4;
  S& tau_max = out.tau_max;
  if (resume == nullptr) tau_max = tau;
  for (int it = out.iterations;; ++it) {
    out.iterations = it;
    AssembleSums<S> a = k.assemble(alpha, y, tau);
    for (int back = 0; !a.ok && alpha > S(0) && back < max_backtracks && it < st.max_iterations; ++back) {
      out.iterations = ++it;
      alpha *= S(0.5);
      y -= alpha * last_dy;
      r -= alpha * last_dr;
      tau -= alpha * last_dtau;
      kappa -= alpha * last_dkappa;
      ++out.backtracks;
      a = k.assemble(-alpha, y, tau);
    }
    if (!a.ok && alpha > S(0)) {
      // Out of backtracks (or of iterations for them): back to the last iterate, which is inside
      // the cones, and stop there.
      y -= alpha * last_dy;
      r -= alpha * last_dr;
      tau -= alpha * last_dtau;
      kappa -= alpha * last_dkappa;
      (void)k.assemble(-alpha, y, tau);
      alpha = S(0);
      break;
    }
    alpha = S(0);  // taken
    if (!a.ok || !(tau > S(0)) || !std::isfinite(tau) || !std::isfinite(kappa)) break;
    // Residuals and the stopping tests (in the solution's units: divided by tau).
    const S xpx = a.upu + (st.soft ? r.squaredNorm() : S(0));
    const Wrench<S> r_eq = a.au - b * tau - (st.soft ? r : Wrench<S>::Zero());
    const Wrench<S> rr = st.soft ? Wrench<S>(r - y) : Wrench<S>::Zero();
    const S by = b.dot(y);
    const S r_tau = kappa + a.qu + a.ct + by + xpx / tau;
    const S pcost = (a.qu + S(0.5) * xpx / tau) / tau + st.cost_offset;
    const S dcost = (-by - a.ct - S(0.5) * xpx / tau) / tau + st.cost_offset;
    out.dual_cost = dcost;
    const S xn = std::sqrt(a.x2 + (st.soft ? r.squaredNorm() : S(0))) / tau, zn = std::sqrt(a.z2) / tau;
    // The rows relative to the load, the forces and residual_floor, the bound rows relative to
    // the bounds and the forces.
    const S tiny = std::numeric_limits<S>::min();
    const S rows = r_eq.norm() / tau, bound_rows = std::sqrt(a.rb2) / tau;
    const S res_p = std::max(rows / std::max(b_norm + xn + st.residual_floor, tiny),
                             bound_rows / std::max(k.bound_scale() + xn, tiny));
    const S res_d = std::sqrt(a.rx2 + rr.squaredNorm()) / tau / std::max(S(1), q_norm + xn + zn);
    // The gap relative to the objective itself (F2 >= 0, its constant counted: cost_offset), not
    // to max(1, objective): F2 in the problem's units spans many orders of magnitude.
    const S gap = std::abs(pcost - dcost) /
                  std::max(std::max(std::abs(pcost), std::abs(dcost)), std::max(st.objective_floor, eps));
    tau_max = std::max(tau_max, tau);
    // The boundary's rows against the data alone (see the file comment).
    const bool boundary = st.boundary_answer && !st.soft && tau <= S(ScalarTraits<S>::interior_boundary) * tau_max &&
                          rows <= st.feasibility_tolerance * std::max(b_norm + st.residual_floor, tiny) &&
                          bound_rows <= st.feasibility_tolerance * std::max(k.bound_scale(), tiny);
    if (res_p <= st.feasibility_tolerance && res_d <= st.feasibility_tolerance && (gap <= st.tolerance || boundary)) {
      out.status = Status::Ok;
      break;
    }
    // A certificate: b^T y (+ the bounds' c^T t) < 0 with every A_i^T y (+ e t_i) in Q to within
    // certificate_tolerance |b^T y| / certificate_scale: then no x in the cones with sum_i |u_i|
    // below about certificate_scale / certificate_tolerance satisfies A x = b, whether y lies in
    // the range of A or along a null space of A^T (contacts that cannot resist some wrench at
    // all, rank(G) < 6). |b^T y| must stand above y's round-off: at least rho |b| |y|, with
    // rho = min(certificate_tolerance, 64 eps / certificate_tolerance) (in double far below the
    // tolerance; in float, where the two meet, the tolerance).
    const S byc = by + a.ct;
    const S rho = std::min(st.certificate_tolerance, S(64) * eps / st.certificate_tolerance);
    if (!st.soft && byc < S(0) && a.certificate >= slack * byc && -byc >= rho * b_norm * y.norm()) {
      out.status = Status::Infeasible;
      break;
    }
    if (it >= st.max_iterations) break;
    const S mu = (a.gap + tau * kappa) / nu;

    // The systems: S (+ I in the soft form), floored at eps times its largest diagonal entry.
    Matrix6<S> m = a.schur;
    if (st.soft) m.diagonal().array() += S(1);
    const S mmax = m.diagonal().maxCoeff();
    if (!ldlt.factor(m, std::max(eps * mmax, std::numeric_limits<S>::min()))) break;
    const Wrench<S> y2 = ldlt.solve(Wrench<S>(a.a_bq - b));
    const Wrench<S> r2 = y2;  // soft: r2 - y2 = 0
    const Wrench<S> two_r = S(2) / tau * r;

    // Predictor. The embedding's tau row (Goulart and Chen, section 3), in its linear form from
    // assemble's sums: den = -kappa / tau + c^T u2 + b^T y2 - x^T P x / tau^2 - sum c_i^2 t_i / s_i,
    // with c^T u = c^T B^-1 g - h^T y for a solution u = B^-1 (g - A^T y). It is minus a sum of
    // squares, at most -kappa / tau: `resolved` when it lies below that by more than its rounding,
    // 64 eps of its terms; otherwise the corrector takes the sum of squares (below), and the
    // predictor -kappa / tau.
    const S c_u2 = a.c_bq - a.h.dot(y2), b_y2 = b.dot(y2), r_r2 = st.soft ? two_r.dot(r2) : S(0);
    const S den_lin = -kappa / tau + c_u2 + r_r2 + b_y2 - xpx / (tau * tau) - a.cc_hb;
    const S den_size = std::abs(c_u2) + std::abs(r_r2) + std::abs(b_y2) + xpx / (tau * tau) + a.cc_hb;
    const bool resolved = den_lin + kappa / tau < -S(64) * eps * den_size;
    const S den = resolved ? den_lin : -kappa / tau;
    const Wrench<S> y1 = ldlt.solve(Wrench<S>(a.a_bp + r_eq + rr));
    const Wrench<S> r1 = y1 - rr;
    const S num = -r_tau + kappa + a.kp - (a.c_bp - a.h.dot(y1)) - (st.soft ? two_r.dot(r1) : S(0)) - b.dot(y1);
    S dtau = num / den;
    if (!std::isfinite(dtau)) break;
    Wrench<S> dy = y1 + dtau * y2;
    S dkappa = -kappa - kappa * dtau / tau;
    const S root_gamma_mu = std::sqrt(S(ScalarTraits<S>::interior_neighbourhood) * mu);
    const PredictSums<S> pr = k.predict(y1, y2, dtau, dy, tau, root_gamma_mu);
    const auto limit = [&](S step, S dt, S dk) {
      S t = std::min(S(1), step);
      if (dt < S(0)) t = std::min(t, -tau / dt);
      if (dk < S(0)) t = std::min(t, -kappa / dk);
      return t;
    };
    const S alpha_a = limit(pr.step, dtau, dkappa);
    const S sigma = (S(1) - alpha_a) * (S(1) - alpha_a) * (S(1) - alpha_a);
    const S sm = sigma * mu;

    // Corrector.
    const S d_kappa = tau * kappa + dtau * dkappa - sm;
    const S keep = S(1) - sigma;
    // The pairs outside the wide neighbourhood toward at least gamma mu (ConeBlock::recentre_part).
    const S em = std::max(S(ScalarTraits<S>::interior_neighbourhood) - sigma, S(0)) * mu;
    const S part[4] = {S(1), sigma, sm, em};  // the weights of the corrector's parts
    Wrench<S> rhs = keep * (r_eq + rr);
    S cbg(0);
    for (int j = 0; j < 4; ++j) {
      rhs += part[j] * pr.a_bg[j];
      cbg += part[j] * pr.c_bg[j];
    }
    const Wrench<S> y1c = ldlt.solve(rhs);
    const Wrench<S> r1c = y1c - keep * rr;
    // Unresolved, the denominator as minus a sum of squares (the predictor's pass; the soft form's
    // r adds |r2 - r / tau|^2) less e2 . y2, e2 = A u2 - b the constant system's residual (large
    // only where the floored factorisation stands in for a singular S). The predictor's dtau only
    // shapes the centring and the second-order term.
    const Wrench<S> e2 = (a.a_bq - b) - m * y2;
    const S den_c =
        resolved ? den_lin : -(kappa / tau + pr.den + (st.soft ? (r2 - r / tau).squaredNorm() : S(0))) - e2.dot(y2);
    const S numc = -keep * r_tau + d_kappa / tau + (pr.k[0] + sigma * pr.k[1] + sm * pr.k[2]) - (cbg - a.h.dot(y1c)) -
                   (st.soft ? two_r.dot(r1c) : S(0)) - b.dot(y1c);
    dtau = numc / den_c;
    if (!std::isfinite(dtau)) break;
    dy = y1c + dtau * y2;
    dkappa = -(d_kappa + kappa * dtau) / tau;
    const Wrench<S> dr = r1c + dtau * r2;
    const S step = k.correct(y1c, dtau, dy, sigma, sm, root_gamma_mu, em);
    alpha = S(ScalarTraits<S>::interior_step) * limit(step, dtau, dkappa);
    if (!(alpha > S(0))) break;
    y += alpha * dy;
    r += alpha * dr;
    tau += alpha * dtau;
    kappa += alpha * dkappa;
    last_dy = dy;
    last_dr = dr;
    last_dtau = dtau;
    last_dkappa = dkappa;
  }
  return out;
}

}  // namespace detail
}  // namespace grip
