#pragma once
/// \file
/// A small interior-point solver for the 7-variable dual conic problems of grasp analysis
/// (force closure, largest resistible wrench): exact friction cones, fixed size, no heap.
///
/// Each contact i has its exact cone K_i in its unknown space (dim = 1, 3 or 4):
/// - HardFinger: the Coulomb cone {|f_t| <= mu f_n} (eq. 4-5); mu = 0 leaves the ray f = f_n a;
/// - SoftFinger: the elliptic cone {|f_t|^2 / mu^2 + m^2 / mu_t^2 <= f_n^2} (mu_t in m);
///   a zero coefficient removes that direction;
/// - FrictionlessPoint: {x >= 0}.
/// and its interior direction e_i (the unit normal a_i, or (a_i, 0), or 1). The dual cone
/// is K_i^* = {v : v_n >= sqrt(sum mu_k^2 v_k^2)} (the Coulomb cone with 1/mu).
///
/// The solver minimises c . q over q = (y, zeta) in R^6 x R subject to one linear equality
/// `a . q = 1`, `zeta e_i - G_i^T y in K_i^*` for every contact, and optionally zeta >= 0,
/// by a primal barrier path-following method on the (6-dimensional after eliminating the
/// equality) problem: Newton steps on tau c.q - sum log(barrier_i), tau multiplied by 8
/// until the barrier bound theta / tau (theta = 2 per second-order cone, 1 per half-space)
/// is below the tolerance. Each Newton step is O(n) plus one 6x6 solve.
/// G's moment rows are divided by a length rho (the largest |r_i|) to balance the units.
/// Reference: Boyd & Vandenberghe, "Convex Optimization" (2004), sections 11.2-11.5 and
/// 11.6 (generalised inequalities, barrier -log(v_n^2 - |v_t|^2) of the second-order cone).

#include <cmath>
#include <limits>
#include <type_traits>

#include <Eigen/Cholesky>

#include "grip/contact/contact_model.hpp"
#include "grip/core/scalar_traits.hpp"
#include "grip/core/status.hpp"
#include "grip/core/types.hpp"
#include "grip/grasp/grasp.hpp"
#include "grip/solve/symmetric_solve.hpp"

namespace grip {
namespace detail {

/// The exact cone of one contact, described for the barrier of its dual.
template <class S, int D>
struct ExactConeData {
  Eigen::Matrix<S, D, 1> axis;  ///< e_i, unit.
  Eigen::Matrix<S, D, D> quad;  ///< A: v^T A v = v_n^2 - sum mu_k^2 v_k^2.
  Eigen::Matrix<S, D, D> span;  ///< orthogonal projector onto the linear span of K_i.
  bool halfspace{false};        ///< K_i is the ray along axis: K_i^* = {axis . v >= 0}.
};

/// The exact cone of contact c for contact model Model.
template <class Model, class S>
ExactConeData<S, Model::dim> exact_cone(const Contact<S>& c) {
  constexpr int D = Model::dim;
  ExactConeData<S, D> k;
  if constexpr (D == 1) {
    k.axis.setConstant(S(1));
    k.quad.setConstant(S(1));
    k.span.setConstant(S(1));
    k.halfspace = true;
  } else {
    const Vector3<S> a = c.normal / c.normal.norm();
    const Matrix3<S> aa = a * a.transpose();
    const Matrix3<S> tt = Matrix3<S>::Identity() - aa;
    k.axis.setZero();
    k.axis.template head<3>() = a;
    k.quad.setZero();
    k.quad.template topLeftCorner<3, 3>() = aa - (c.friction * c.friction) * tt;
    k.span.setZero();
    k.span.template topLeftCorner<3, 3>() = c.friction > S(0) ? Matrix3<S>::Identity() : aa;
    bool ray = !(c.friction > S(0));
    if constexpr (D == 4) {
      k.quad(3, 3) = -(c.torsional_friction * c.torsional_friction);
      k.span(3, 3) = c.torsional_friction > S(0) ? S(1) : S(0);
      ray = ray && !(c.torsional_friction > S(0));
    }
    k.halfspace = ray;
  }
  return k;
}

/// The largest t with x - t e in K (e the cone's axis), for a force x of contact c: x_n - |x_t|/mu
/// (hard finger), x_n - sqrt(|x_t|^2/mu^2 + m^2/mu_t^2) (soft finger), x (frictionless). Terms
/// with a zero coefficient are left out (the span projection has removed those components).
template <class Model, class S>
S normal_margin(const Contact<S>& c, const Eigen::Matrix<S, Model::dim, 1>& x) {
  if constexpr (Model::dim == 1) {
    return x(0);
  } else {
    const Vector3<S> a = c.normal / c.normal.norm();
    const S xn = a.dot(x.template head<3>());
    S q(0);
    if (c.friction > S(0)) q += (x.template head<3>() - xn * a).squaredNorm() / (c.friction * c.friction);
    if constexpr (Model::dim == 4)
      if (c.torsional_friction > S(0)) q += x(3) * x(3) / (c.torsional_friction * c.torsional_friction);
    return xn - std::sqrt(q);
  }
}

/// Barrier -log of the dual cone at v: value, gradient and Hessian. False if v is not in
/// the interior of K^*.
template <class S, int D>
bool dual_barrier(const ExactConeData<S, D>& k, const Eigen::Matrix<S, D, 1>& v, S& value,
                  Eigen::Matrix<S, D, 1>& grad, Eigen::Matrix<S, D, D>& hess) {
  const S vn = k.axis.dot(v);
  if (!(vn > S(0))) return false;
  if (k.halfspace) {
    value = -std::log(vn);
    grad = -k.axis / vn;
    hess = (k.axis * k.axis.transpose()) / (vn * vn);
    return true;
  }
  const Eigen::Matrix<S, D, 1> av = k.quad * v;
  const S s = v.dot(av);
  if (!(s > S(0))) return false;
  value = -std::log(s);
  grad = (S(-2) / s) * av;
  hess = (S(-2) / s) * k.quad + (S(4) / (s * s)) * (av * av.transpose());
  return true;
}

/// The primal point -grad / tau of the barrier (inside K_i): the estimate of the contact
/// unknowns that the dual iterate certifies.
template <class S, int D>
Eigen::Matrix<S, D, 1> dual_barrier_primal(const ExactConeData<S, D>& k, const Eigen::Matrix<S, D, 1>& v, S tau) {
  const S vn = k.axis.dot(v);
  if (k.halfspace) return k.axis / (vn * tau);
  const Eigen::Matrix<S, D, 1> av = k.quad * v;
  return (S(2) / (v.dot(av) * tau)) * av;
}

/// Barrier parameter of one cone (2 for a second-order cone, 1 for a half-space).
template <class S, int D>
int dual_barrier_theta(const ExactConeData<S, D>& k) {
  return k.halfspace ? 1 : 2;
}

/// The torque scale used internally: the largest |r_i|, or 1 when all are 0.
template <class GraspT>
typename GraspT::ScalarType internal_torque_scale(const GraspT& grasp) {
  using S = typename GraspT::ScalarType;
  S rho(0);
  for (int i = 0; i < grasp.size(); ++i) rho = std::max(rho, grasp.contact(i).position.norm());
  return rho > S(0) ? rho : S(1);
}

/// diag(1, 1, 1, 1/rho x 3).
template <class S>
Wrench<S> row_scaling(S rho) {
  Wrench<S> d;
  d << S(1), S(1), S(1), S(1) / rho, S(1) / rho, S(1) / rho;
  return d;
}

/// Outcome of solve_conic_dual.
template <class GraspT>
struct ConicDualResult {
  using S = typename GraspT::ScalarType;
  Wrench<S> y{Wrench<S>::Zero()};  ///< y in scaled coordinates (moment part times rho).
  S zeta{0};
  S objective{0};                       ///< c . q at the returned point (within theta/tau of optimal).
  S gap_bound{0};                       ///< theta / tau: objective - optimum <= gap_bound.
  typename GraspT::ForceVector primal;  ///< s_i = -grad barrier_i / tau, each inside K_i.
  S zeta_primal{0};                     ///< the multiplier estimate of zeta >= 0, if used.
  Status status{Status::InvalidInput};  ///< Ok, IterationLimit, or Infeasible (objective below -1/tol: unbounded).
  int iterations{0};                    ///< Newton steps.
};

/// Minimises c . q (q = (y, zeta)) s.t. a . q = 1, zeta e_i - (D G_i)^T y in K_i^*, and
/// zeta >= 0 if `zeta_nonneg`; q0 must be strictly feasible. `rho` the row scaling.
template <class GraspT>
ConicDualResult<GraspT> solve_conic_dual(const GraspT& grasp, typename GraspT::ScalarType rho,
                                         const Eigen::Matrix<typename GraspT::ScalarType, 7, 1>& c,
                                         const Eigen::Matrix<typename GraspT::ScalarType, 7, 1>& a,
                                         const Eigen::Matrix<typename GraspT::ScalarType, 7, 1>& q0, bool zeta_nonneg,
                                         typename GraspT::ScalarType tol, int max_newton) {
  using S = typename GraspT::ScalarType;
  using M = typename GraspT::ModelType;
  constexpr int D = GraspT::dim;
  using V7 = Eigen::Matrix<S, 7, 1>;
  using M7 = Eigen::Matrix<S, 7, 7>;
  using CV = Eigen::Matrix<S, D, 1>;
  using CM = Eigen::Matrix<S, D, D>;
  using J = Eigen::Matrix<S, D, 7>;
  ConicDualResult<GraspT> out;
  out.primal.setZero(grasp.unknowns());
  const Wrench<S> dsc = row_scaling(rho);
  const int n = grasp.size();

  // Jacobian of lambda_i = zeta e_i - (D G_i)^T y with respect to q.
  auto jacobian = [&](int i, const ExactConeData<S, D>& k) {
    J j;
    j.template leftCols<6>() = -(M::basis(grasp.contact(i)).transpose() * dsc.asDiagonal());
    j.col(6) = k.axis;
    return j;
  };
  // Barrier value (and optionally derivatives) at q; false if q is not strictly feasible.
  auto evaluate = [&](const V7& q, S tau, S& f, V7* g, M7* h) {
    f = tau * c.dot(q);
    if (g) *g = tau * c;
    if (h) h->setZero();
    for (int i = 0; i < n; ++i) {
      const ExactConeData<S, D> k = exact_cone<M>(grasp.contact(i));
      const J j = jacobian(i, k);
      const CV v = j * q;
      S phi;
      CV gr;
      CM he;
      if (!dual_barrier(k, v, phi, gr, he)) return false;
      f += phi;
      if (g) g->noalias() += j.transpose() * gr;
      if (h) h->noalias() += j.transpose() * he * j;
    }
    if (zeta_nonneg) {
      if (!(q(6) > S(0))) return false;
      f -= std::log(q(6));
      if (g) (*g)(6) -= S(1) / q(6);
      if (h) (*h)(6, 6) += S(1) / (q(6) * q(6));
    }
    return std::isfinite(f);
  };

  // Eliminate the equality: q = q0 + N p with N spanning a^perp (a coordinate basis with
  // the pivot column of a solved for).
  int piv = 0;
  a.cwiseAbs().maxCoeff(&piv);
  Eigen::Matrix<S, 7, 6> nb = Eigen::Matrix<S, 7, 6>::Zero();
  for (int k = 0, col = 0; k < 7; ++k) {
    if (k == piv) continue;
    nb(k, col) = S(1);
    nb(piv, col) = -a(k) / a(piv);
    ++col;
  }

  int theta = zeta_nonneg ? 1 : 0;
  for (int i = 0; i < n; ++i) theta += dual_barrier_theta(exact_cone<M>(grasp.contact(i)));
  V7 q = q0;
  S tau(1);
  S f;
  if (!evaluate(q, tau, f, nullptr, nullptr)) return out;
  const S unbounded = S(1) / tol;
  int it = 0;
  out.status = Status::IterationLimit;
  for (int outer = 0; outer < 64 && it < max_newton; ++outer) {
    // Centering: damped Newton.
    for (int inner = 0; inner < 50 && it < max_newton; ++inner, ++it) {
      V7 g;
      M7 h;
      evaluate(q, tau, f, &g, &h);
      const Wrench<S> gr = nb.transpose() * g;
      const Matrix6<S> hr = nb.transpose() * h * nb;
      Wrench<S> dp;
      solve_symmetric_6x6(hr, Wrench<S>(-gr), dp);
      const S dec2 = -gr.dot(dp);
      if (!(dec2 > std::numeric_limits<S>::epsilon())) break;
      const V7 dq = nb * dp;
      S step(1);
      bool moved = false;
      for (int ls = 0; ls < 60; ++ls, step *= S(0.5)) {
        S fn;
        if (evaluate(q + step * dq, tau, fn, nullptr, nullptr) && fn <= f - S(0.25) * step * dec2) {
          q += step * dq;
          moved = true;
          break;
        }
      }
      if (!moved || c.dot(q) < -unbounded) break;
      if (dec2 < S(1e-3) * tol) {
        ++it;
        break;
      }
    }
    const S obj = c.dot(q);
    if (obj < -unbounded) {
      out.status = Status::Infeasible;
      break;
    }
    if (S(theta) / tau <= tol * (S(1) + std::abs(obj))) {
      out.status = Status::Ok;
      break;
    }
    tau *= S(8);
  }
  out.iterations = it;
  out.y = q.template head<6>();
  out.zeta = q(6);
  out.objective = c.dot(q);
  out.gap_bound = S(theta) / tau;
  for (int i = 0; i < n; ++i) {
    const ExactConeData<S, D> k = exact_cone<M>(grasp.contact(i));
    const CV v = jacobian(i, k) * q;
    out.primal.template segment<D>(i * D) = dual_barrier_primal(k, v, tau);
  }
  if (zeta_nonneg) out.zeta_primal = S(1) / (q(6) * tau);
  if (!out.primal.allFinite()) out.primal.setZero(grasp.unknowns());
  return out;
}

/// Sum_i (D G_i) P_i (D G_i)^T: the Gram matrix of G restricted to the spans of the cones
/// (a contact with mu = 0 contributes only its normal column).
template <class GraspT>
Matrix6<typename GraspT::ScalarType> cone_span_gram(const GraspT& grasp, typename GraspT::ScalarType rho) {
  using S = typename GraspT::ScalarType;
  using M = typename GraspT::ModelType;
  constexpr int D = GraspT::dim;
  const Wrench<S> dsc = row_scaling(rho);
  Matrix6<S> m = Matrix6<S>::Zero();
  for (int i = 0; i < grasp.size(); ++i) {
    const Eigen::Matrix<S, 6, D> b = dsc.asDiagonal() * M::basis(grasp.contact(i));
    m.noalias() += b * exact_cone<M>(grasp.contact(i)).span * b.transpose();
  }
  return m;
}

}  // namespace detail
}  // namespace grip
