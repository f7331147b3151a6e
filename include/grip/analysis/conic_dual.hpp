#pragma once
/// \file
/// A small interior-point solver for the 7-variable dual conic problems of grasp analysis
/// (force closure, largest resistible wrench): exact friction cones, fixed size, no heap.
///
/// Each contact i has its exact cone K_i and interior direction e_i (the unit normal a_i, or
/// (a_i, 0), or 1), described in detail/analysis_cones.hpp.
///
/// The solver minimises c . q over q = (y, zeta) in R^6 x R subject to one linear equality
/// `a . q = 1`, `zeta e_i - G_i^T y in K_i^*` for every contact, and optionally zeta >= 0.
/// Each dual cone is mapped onto the standard second-order cone Q (cone_map: K_i^* = {v :
/// L_i v in Q}), so the problem is the conic program
///     min c . q  s.t.  a . q = 1,  u_i = F_i q in Q  (F_i = L_i [-G_i^T, e_i]),
/// whose Lagrange dual is  max t  s.t.  sum_i F_i^T z_i + t a = c,  z_i in Q; the contact
/// unknowns x_i = L_i^T z_i then lie in K_i. Both are solved together by a primal-dual
/// interior-point method (Mehrotra predictor-corrector, Nesterov-Todd scaling of each cone,
/// detail/cone_lanes.hpp), started from the strictly feasible q0 and z_i = e: each
/// iteration is O(n) to form the 7x7 matrix H = sum F_i^T W_i^-2 F_i plus its LDL^T
/// factorisation and two solves. The O(n) work runs on the contacts in SIMD lanes, 8 or 4 at
/// a time. It stops when the dual residual, the primal residual, the complementarity
/// gap sum s_i . z_i and the difference of the two objectives are below the tolerance
/// (relative to 1 + |objective|); q stays feasible throughout, so c . q is an upper bound on
/// the optimum at every iteration, and the dual objective t a lower bound at the end.
/// G's moment rows are divided by a length rho (the largest |r_i|) to balance the units.
/// References: L. Vandenberghe, "The CVXOPT linear and quadratic cone program solvers"
/// (2010); S. Mehrotra, "On the implementation of a primal-dual interior point method",
/// SIAM J. Optim. 2(4), 1992; Nesterov & Todd, "Primal-dual interior-point methods for
/// self-scaled cones", SIAM J. Optim. 8(2), 1998.

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>


#include "grip/analysis/detail/analysis_cones.hpp"
#include "grip/analysis/detail/cone_lanes.hpp"
#include "grip/contact/contact_model.hpp"
#include "grip/core/scalar_traits.hpp"
#include "grip/core/status.hpp"
#include "grip/core/types.hpp"
#include "grip/grasp/grasp.hpp"
#include "grip/solve/symmetric_solve.hpp"

namespace grip {
namespace detail {

/// Outcome of solve_conic_dual.
template <class GraspT>
struct ConicDualResult {
  using S = typename GraspT::ScalarType;
  Wrench<S> y{Wrench<S>::Zero()};  ///< y in scaled coordinates (moment part times rho).
  S zeta{0};
  S objective{0};                       ///< c . q at the returned point: an upper bound on the optimum.
  S lower{0};                           ///< the dual objective: a lower bound once the dual residual vanishes.
  S gap_bound{0};                       ///< objective - lower.
  typename GraspT::ForceVector primal;  ///< x_i = L_i^T z_i, each inside K_i: the multipliers of the cones.
  S zeta_primal{0};                     ///< the multiplier of zeta >= 0, if used.
  Status status{Status::InvalidInput};  ///< Ok, IterationLimit, or Infeasible (objective below `floor`).
  int iterations{0};                    ///< interior-point iterations (each O(n) plus a 7x7 factorisation).
};

/// Minimises c . q (q = (y, zeta)) s.t. a . q = 1, zeta e_i - (D G_i)^T y in K_i^*, and
/// zeta >= 0 if `zeta_nonneg`; q0 must be strictly feasible (else InvalidInput). `rho` the
/// row scaling; at most `max_iterations` iterations; stops with Infeasible once the objective
/// (an upper bound on the optimum) falls below `floor`. See the file comment for the method.
template <class GraspT>
ConicDualResult<GraspT> solve_conic_dual(const GraspT& grasp, typename GraspT::ScalarType rho,
                                         const Eigen::Matrix<typename GraspT::ScalarType, 7, 1>& c_in,
                                         const Eigen::Matrix<typename GraspT::ScalarType, 7, 1>& a_in,
                                         const Eigen::Matrix<typename GraspT::ScalarType, 7, 1>& q0, bool zeta_nonneg,
                                         typename GraspT::ScalarType tol_in, int max_iterations,
                                         typename GraspT::ScalarType floor_in) {
  using T = typename GraspT::ScalarType;
  using S = typename ScalarTraits<T>::Wide;  // the scalar of the computation
  using M = typename GraspT::ModelType;
  constexpr int D = GraspT::dim;
  using V7 = Eigen::Matrix<S, 7, 1>;
  using M7 = Eigen::Matrix<S, 7, 7>;
  ConicDualResult<GraspT> out;
  out.primal.setZero(grasp.unknowns());
  const int n = grasp.size();
  const Wrench<S> dsc = row_scaling(S(rho));
  const V7 c = c_in.template cast<S>(), a = a_in.template cast<S>();
  const S tol = S(tol_in);

  // The cones, in SIMD lanes: u_i = F_i q in Q with F_i = L_i [-(D G_i)^T, e_i]; the optional
  // zeta >= 0 is one more (1-dimensional) cone u = q_6, kept apart in `h`. s: the slacks u,
  // z: their multipliers.
  ConeLanes<S, D, GraspT::capacity> k(n);
  std::array<Eigen::Matrix<S, D, D>, GraspT::capacity> L;  // cone_map of each contact
  for (int i = 0; i < n; ++i) {
    const auto& ci = wide_contact<S>(grasp.contact(i));
    const Eigen::Matrix<S, D, 1> axis = cone_axis<M>(ci);
    const Eigen::Matrix<S, D, D>& li = L[static_cast<std::size_t>(i)] = cone_map<M>(ci);
    for (int r = 0; r < D; ++r) {  // row r of L_i [-(D G_i)^T, e_i]: (-(D G_i l_r)^T, l_r . e_i)
      const Eigen::Matrix<S, D, 1> lr = li.row(r).transpose();
      Eigen::Matrix<S, 7, 1> row;
      row.template head<6>() = -dsc.cwiseProduct(M::wrench(ci, lr));
      row(6) = lr.dot(axis);
      k.set_map(i, r, row);
    }
  }
  struct Half {  // the zeta >= 0 cone, scalars
    S s{1}, z{1}, rc{0}, ds{0}, dz{0}, dsa{0}, dza{0}, lambda{1}, d{0};
  } h;

  V7 q = q0.template cast<S>();
  S y(0);
  if (!k.start(q)) return out;
  if (zeta_nonneg) {
    h.s = q(6);
    if (!(h.s > S(0))) return out;
  }
  const S degree = S(n + (zeta_nonneg ? 1 : 0));
  const S floor = S(floor_in);
  const S eps = std::numeric_limits<S>::epsilon();
  constexpr int max_refinements = 4;

  // Solves the Newton system for the complementarity right-hand sides d (per cone, in the
  // scaled space): W dz + W^-1 ds = d, F dq - ds = -rc, F^T dz + a dy = rd, a . dq = rp.
  // Eliminating ds and dz leaves H dq - a dy = r1, a . dq = rp with H = sum F^T W^-2 F.
  SmallLdlt<7, S> ldlt;  // of H, in natural order (pivoted as a fall-back)
  auto solve_h = [&](const V7& r) {
    S x[7];
    for (int j = 0; j < 7; ++j) x[j] = r(j);
    ldlt.solve(x);
    return V7(Eigen::Map<const V7>(x));
  };
  V7 hia;
  S aha(1);
  V7 rd;
  S rp(0);
  V7 dq;
  S dy(0);
  // One solve of the reduced system with the factorisation of (regularised) H.
  auto reduced = [&](const V7& r1, S r2, V7& x, S& t) {
    const V7 hr = solve_h(r1);
    t = (r2 - a.dot(hr)) / aha;
    x = hr + t * hia;
  };
  S step_bound(0);  // the cones' largest step along the last directions (k.recover)
  // ds and dz from dq: ds = F dq + rc, dz = W^-1 (d - W^-1 ds) = g - W^-1 (W^-1 F) dq with
  // g = W^-1 (d - W^-1 rc); returns the dual equation's residual rd - F^T dz - a dy.
  auto recover = [&]() {
    V7 res = rd - dy * a;
    step_bound = k.recover(dq, res);
    if (zeta_nonneg) {
      const S om = std::sqrt(h.s / h.z);
      h.ds = dq(6) + h.rc;
      h.dz = (h.d - h.ds / om) / om;
      res(6) -= h.dz;
    }
    return res;
  };
  auto newton = [&](bool affine, S sm) {
    V7 r1 = -rd;
    k.newton_rhs(r1, affine, sm);
    if (zeta_nonneg) {
      const S om = std::sqrt(h.s / h.z);
      r1(6) += (h.d - h.rc / om) / om;
    }
    reduced(r1, rp, dq, dy);
    // Iterative refinement: H is ill-conditioned near the optimum (W^-2 spans many orders of
    // magnitude) and regularised; correct dq, dy by the residual of the unreduced equations.
    for (int r = 0;; ++r) {
      const V7 res = recover();
      const S res_p = rp - a.dot(dq);
      if (r == max_refinements || res.norm() + std::abs(res_p) <= S(0.01) * tol) break;
      V7 cq;
      S cy;
      reduced(-res, res_p, cq, cy);
      dq += cq;
      dy += cy;
    }
  };
  // The largest step in [0, 1] keeping s and z in the cones (fraction `f` of the way).
  auto step = [&](S f) {
    S t = step_bound;
    if (zeta_nonneg) {
      if (h.ds < S(0)) t = std::min(t, -h.s / h.ds);
      if (h.dz < S(0)) t = std::min(t, -h.z / h.dz);
    }
    return std::min(S(1), f * t);
  };

  out.status = Status::IterationLimit;
  int it = 0;
  S alpha(0);  // the last step, taken by k.advance at the top of the next iteration
  for (;; ++it) {
    // The step, the residuals, the stopping test, and the scalings with H, in one pass.
    rd = c - y * a;
    S pres = std::abs(S(1) - a.dot(q));
    rp = S(1) - a.dot(q);
    M7 H = M7::Zero();
    bool scaled = true;
    S gap = k.advance(alpha, q, rd, pres, H, scaled);
    if (zeta_nonneg) {
      h.s += alpha * h.ds;
      h.z += alpha * h.dz;
      rd(6) -= h.z;
      h.rc = q(6) - h.s;
      gap += h.s * h.z;
    }
    const S pcost = c.dot(q);
    const S scale = S(1) + std::abs(pcost);
    if (rd.norm() <= tol && pres <= tol && gap <= tol * scale && std::abs(pcost - y) <= tol * scale) {
      out.status = Status::Ok;
      break;
    }
    if (pcost < floor) {
      out.status = Status::Infeasible;
      break;
    }
    if (it >= max_iterations || !scaled) break;

    // The factorisation of H.
    if (zeta_nonneg) {
      H(6, 6) += h.z / h.s;
      h.lambda = std::sqrt(h.s * h.z);
    }
    // Regularised by eps times its largest diagonal entry, or by sqrt(eps) when rounding
    // leaves that indefinite near the optimum; the refinement in `newton` corrects for it.
    const S hmax = H.diagonal().maxCoeff();
    H.diagonal().array() += eps * hmax;
    const auto fill_h = [&H](S (&f)[7][7]) {
      for (int r = 0; r < 7; ++r)
        for (int j = 0; j < 7; ++j) f[r][j] = H(r, j);
    };
    if (!ldlt.factor(fill_h, hmax, S(0))) {
      H.diagonal().array() += std::sqrt(eps) * hmax;
      if (!ldlt.factor(fill_h, hmax, S(0))) break;
    }
    hia = solve_h(a);
    aha = a.dot(hia);
    if (!(std::abs(aha) > S(0)) || !std::isfinite(aha)) break;

    // Predictor (affine scaling): d = -lambda.
    h.d = -h.lambda;
    newton(true, S(0));
    const S alpha_a = step(S(1));
    S gap_a = k.affine_gap(alpha_a);  // also prepares the corrector's right-hand side
    if (zeta_nonneg) {
      gap_a += (h.s + alpha_a * h.ds) * (h.z + alpha_a * h.dz);
      h.dsa = h.ds;
      h.dza = h.dz;
    }
    const S mu = gap / degree;
    const S ratio = std::max(S(0), std::min(S(1), gap_a / gap));
    const S sigma = ratio * ratio * ratio;

    // Corrector (Mehrotra): lambda o d = sigma mu e - lambda o lambda - (W^-1 ds_a) o (W dz_a).
    if (zeta_nonneg) h.d = (sigma * mu - h.lambda * h.lambda - h.dsa * h.dza) / h.lambda;
    newton(false, sigma * mu);
    alpha = step(S(0.99));
    if (!(alpha > S(0))) break;
    q += alpha * dq;
    y += alpha * dy;
  }
  out.iterations = it;
  out.y = q.template head<6>().template cast<T>();
  out.zeta = T(q(6));
  out.objective = T(c.dot(q));
  out.lower = T(y);
  out.gap_bound = T(c.dot(q) - y);
  for (int i = 0; i < n; ++i)
  {
    Eigen::Matrix<S, D, 1> zi;
    for (int r = 0; r < D; ++r) zi(r) = k.at(k.z, r, i);
    out.primal.template segment<D>(i * D) =
        (L[static_cast<std::size_t>(i)].transpose() * zi).template cast<T>();
  }
  out.zeta_primal = T(h.z);
  if (!out.primal.allFinite()) out.primal.setZero(grasp.unknowns());
  return out;
}

}  // namespace detail
}  // namespace grip
