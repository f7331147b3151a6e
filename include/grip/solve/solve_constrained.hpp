#pragma once
/// \file
/// The exact optimum of the weighted F2 with every contact force inside its exact friction
/// cone (the paper's section 4 problem, eq. 3-5 with eq. 7), in O(n) per iteration.
///
/// Problem: minimise F2(x) = 1/2 sum_i w_i |x_i - t_i|^2 subject to G x + w_ext = 0 and
/// x_i in K_i, with K_i = ExactConeT<Model, Scalar> of contact i (Coulomb cone for a hard
/// finger, the elliptic soft-finger cone, f_n >= 0 for a frictionless point).
///
/// Method: semi-smooth Newton ascent on the 6-dimensional dual. For multipliers lambda the
/// Lagrangian L(x, lambda) = F2(x) - lambda.(G x + w_ext) is minimised over the cones by
/// x_i(lambda) = P_i(v_i), v_i = t_i + w_i^-1 G_i^T lambda (P_i: Euclidean projection onto
/// K_i; the weight is a scalar, so the weighted projection is the Euclidean one). The dual
/// function q(lambda) = L(x(lambda), lambda) is concave and C^1 with gradient
/// -(G x(lambda) + w_ext); its generalised Hessian is -sum_i w_i^-1 G_i J_i G_i^T with J_i a
/// generalised Jacobian of P_i (projection_jacobian.hpp). Each iteration: one pass over the
/// contacts for the 6x6 matrix, a regularised 6x6 Cholesky solve, and an Armijo line search on
/// q (one pass per trial). Every x(lambda) lies in the cones and satisfies stationarity and
/// complementarity exactly; only the equilibrium residual is driven to zero.
///
/// Passes: hard fingers copy the grasp once per solve (after the fast path) into columns and
/// run every pass over them in SIMD packs (detail::CoulombPassTable, coulomb_pass.hpp: 8
/// contacts per step with AVX-512, 4 with AVX2, one otherwise); soft fingers and frictionless
/// points go contact by contact through the cone's projection (detail::ContactPasses).

#include <cmath>
#include <cstddef>
#include <limits>
#include <type_traits>

#include <Eigen/Geometry>

#include "grip/contact/contact.hpp"
#include "grip/contact/coulomb_kernel.hpp"
#include "grip/contact/exact_cone.hpp"
#include "grip/grasp/grasp.hpp"
#include "grip/solve/constrained_settings.hpp"
#include "grip/solve/coulomb_pass.hpp"
#include "grip/solve/projection_jacobian.hpp"
#include "grip/solve/solution.hpp"
#include "grip/solve/solve_range_space.hpp"
#include "grip/solve/symmetric_solve.hpp"

namespace grip {

/// What solve_constrained returns: a Solution plus the numbers that certify it.
///
/// Every number is finite whatever the status; `forces` always lie inside their cones
/// (they are projections), except under InvalidInput, where everything is zero.
template <class GraspT>
struct ConstrainedSolution : Solution<GraspT> {
  /// The grasp's scalar type (float or double).
  using Scalar = typename GraspT::ScalarType;
  /// Infeasible: a unit 6-vector y with G_i^T y in the dual cone K_i^* for every contact (its
  /// distance to K_i^* at most ConstrainedSettings::certificate_tolerance (1 + |r_i|)) and
  /// y.w_ext > 0. It proves that no forces in
  /// the cones balance w_ext: for x_i in K_i, y.(G x) >= 0, so y.(G x + w_ext) > 0. Zero otherwise.
  Wrench<Scalar> certificate{Wrench<Scalar>::Zero()};
  /// F2 at `forces`: 1/2 sum_i w_i |x_i - t_i|^2.
  Scalar objective{0};
  /// The dual function q at `multipliers`, F2(x) - lambda.(G x + w_ext): a lower bound on the
  /// optimum whenever the problem is feasible.
  Scalar dual_objective{0};
  /// True when the unconstrained optimum was inside every cone (f_n > 0) and was returned at once.
  bool fast_path{false};
};

namespace detail {

/// The cone's own projection, except a Coulomb cone with mu = 0 (the ray {f_n a, f_n >= 0}):
/// there CoulombCone::project keeps f = f_n a with f_n < 0 (reported to the cone's owner), so
/// the ray's projection max(f.a, 0) a is used.
template <class Cone, class V>
V project_onto(const Cone& k, const V& v) {
  return k.project(v);
}
template <class Scalar>
Vector3<Scalar> project_onto(const CoulombCone<Scalar>& k, const Vector3<Scalar>& v) {
  if (k.mu > Scalar(0)) return k.project(v);
  const Scalar n = v.dot(k.normal);
  return n > Scalar(0) && detail::cone_input_valid(v) ? Vector3<Scalar>(n * k.normal) : Vector3<Scalar>::Zero();
}

/// Hard finger, fused: x = P(v) onto the Coulomb cone of c (exactly project_onto's value) and,
/// when `acc` is given, k G_i J G_i^T added to it with J = dP/dv (projection_jacobian's
/// formulas and regions), from one evaluation of v.a, v_t and |v_t|. On the boundary part
/// J = beta I + [a e] C [a e]^T with C = [[k_u - beta, k_u mu], [k_u mu, k_u mu^2 - beta]],
/// k_u = 1/(1 + mu^2), beta = |x_t|/|v_t|, so G_i J G_i^T = beta G_i G_i^T (closed form) plus
/// W C W^T, W = [G_i a, G_i e] (6x2): two cross products and a rank-2 update instead of the
/// 6x3 by 3x3 by 3x6 product of the generic path.
template <class S>
EIGEN_ALWAYS_INLINE Vector3<S> coulomb_project_accumulate(const Contact<S>& c, S k, const Vector3<S>& v, GramAccumulator<S>* acc) {
  const Vector3<S>& a = c.normal;
  const Vector3<S>& r = c.position;
  const S mu = c.friction;
  if (!cone_input_valid(v)) return Vector3<S>::Zero();  // Polar for the Jacobian: no term
  // Branch-free in the region (which depends on the square root, so a branch would stall every
  // contact on a misprediction): one formula covers the boundary part and, with |v_t| = mu n,
  // the boundary itself (sn = n, beta = 1: x = v), and mu = 0 (the ray: beta = 0, x = n a);
  // selects pick v (interior) and 0 (polar cone).
  const S n = v.dot(a);
  const Vector3<S> ftv = v - n * a;
  const S ft = ftv.norm();
  const bool inside = ft < mu * n;                 // J = I
  // J = 0 (projection_jacobian's regions): for mu > 0 the polar cone, and v_t = 0 outside the
  // interior (v = 0, or mu n underflowing); for mu = 0 (the ray) n <= 0.
  const bool polar = mu > S(0) ? (n <= -mu * ft || !(ft > S(0))) : !(n > S(0));
  const S ku = S(1) / (S(1) + mu * mu);
  const S sn = (n + mu * ft) * ku;  // alpha of projection_jacobian
  // beta = mu sn / |v_t| lies in [0, 1] on the boundary part.
  const S beta = ft > S(0) ? (sn * mu) / ft : S(0);
  const bool boundary = !inside & !polar;
  if (acc != nullptr) {
    if (inside) {
      acc->add_point_force(k, r);
    } else if (boundary) {
      // v_t = 0 on the boundary part only for mu = 0 (the ray), where e has no weight.
      const Vector3<S> e = ft > S(0) ? Vector3<S>(ftv / ft) : Vector3<S>::Zero();
      Wrench<S> wa, we;
      wa.template head<3>() = a;
      wa.template tail<3>() = r.cross(a);
      we.template head<3>() = e;
      we.template tail<3>() = r.cross(e);
      const S caa = k * (ku - beta), cae = k * ku * mu, cee = k * (ku * mu * mu - beta);
      const Wrench<S> za = caa * wa + cae * we, ze = cae * wa + cee * we;
      if (beta > S(0)) acc->add_point_force(k * beta, r);
      for (int j = 0; j < 6; ++j)  // extra += za wa^T + ze we^T (symmetric: C is)
        for (int i = 0; i < 6; ++i) acc->extra(i, j) += za(i) * wa(j) + ze(i) * we(j);
    }
  }
  const S keep = inside ? S(1) : S(0);
  const S sb = boundary ? sn : S(0);
  const S bb = boundary ? beta : S(0);
  return keep * v + sb * a + bb * ftv;
}

/// x_i = P_i(v) and, when `acc` is given, k G_i J_i G_i^T added to it, J_i the generalised
/// Jacobian of the projection at v: the contact's block of minus the dual's generalised Hessian.
/// Hard fingers take the fused kernel above; the other models the cone's projection and
/// projection_jacobian.
template <class GraspT>
typename GraspT::ContactVector project_accumulate(const typename GraspT::ContactType& c, typename GraspT::ScalarType k,
                                                  const typename GraspT::ContactVector& v,
                                                  GramAccumulator<typename GraspT::ScalarType>* acc) {
  using S = typename GraspT::ScalarType;
  using M = typename GraspT::ModelType;
  constexpr int d = GraspT::dim;
  if constexpr (std::is_same<M, HardFinger>::value) {
    return coulomb_project_accumulate(c, k, v, acc);
  } else {
    const auto cone = ExactConeT<M, S>::from_contact(c);
    const typename GraspT::ContactVector xi = project_onto(cone, v);
    if (acc != nullptr) {
      const auto j = projection_jacobian(cone, v, xi);
      if (j.region == ProjectionRegion::Interior) {
        M::accumulate(*acc, c, k);
      } else if (j.region == ProjectionRegion::Boundary) {
        const Eigen::Matrix<S, 6, d> g = M::basis(c);
        const Eigen::Matrix<S, 6, d> gj = k * (g * j.matrix);
        acc->extra.noalias() += gj * g.transpose();
      }
    }
    return xi;
  }
}

/// x_i = P_i(t_i + w_i^-1 G_i^T lambda) for every contact, with the sums of ConstrainedPass;
/// with `hessian` given, also sum_i w_i^-1 G_i J_i G_i^T at lambda in the same pass (so that an
/// accepted line-search point needs no second pass for the next Newton step).
template <class GraspT, class Vec>
ConstrainedPass<typename GraspT::ScalarType> constrained_pass(const GraspT& grasp,
                                                              const Wrench<typename GraspT::ScalarType>& w_ext,
                                                              const Wrench<typename GraspT::ScalarType>& lambda,
                                                              Vec& x,
                                                              GramAccumulator<typename GraspT::ScalarType>* hessian = nullptr) {
  using S = typename GraspT::ScalarType;
  using M = typename GraspT::ModelType;
  using CV = typename GraspT::ContactVector;
  constexpr int d = GraspT::dim;
  ConstrainedPass<S> p;
  p.residual = w_ext;
  if (hessian != nullptr) *hessian = GramAccumulator<S>{};
  S xx = S(0);
  for (int i = 0; i < grasp.size(); ++i) {
    const auto& c = grasp.contact(i);
    const CV t = M::target(c);
    const CV v = t + grasp.inverse_weight(i) * M::wrench_transpose(c, lambda);
    const CV xi = project_accumulate<GraspT>(c, grasp.inverse_weight(i), v, hessian);
    x.template segment<d>(i * d) = xi;
    p.residual += M::wrench(c, xi);
    p.f2 += S(0.5) * c.weight * (xi - t).squaredNorm();
    xx += xi.squaredNorm();
  }
  p.scale = w_ext.norm() + std::sqrt(xx);
  p.dual = p.f2 - lambda.dot(p.residual);
  return p;
}

/// The passes of solve_constrained contact by contact, through the model's functions (soft
/// fingers, frictionless points); hard fingers take CoulombPassTable, the same pass over a
/// structure of arrays. Both offer Forces, make_forces, pass and store.
template <class GraspT>
class ContactPasses {
 public:
  using Scalar = typename GraspT::ScalarType;
  using Forces = typename GraspT::ForceVector;
  explicit ContactPasses(const GraspT& grasp) : grasp_(grasp) {}
  Forces make_forces() const { return Forces(grasp_.unknowns()); }
  ConstrainedPass<Scalar> pass(const Wrench<Scalar>& w_ext, const Wrench<Scalar>& lambda, Forces& x,
                               GramAccumulator<Scalar>* hessian) const {
    return constrained_pass(grasp_, w_ext, lambda, x, hessian);
  }
  template <class Vec>
  void store(const Forces& x, Vec& out) const {
    out = x;
  }

 private:
  const GraspT& grasp_;
};

/// The pass engine of solve_constrained for a grasp type.
template <class GraspT>
using ConstrainedPasses = typename std::conditional<std::is_same<typename GraspT::ModelType, HardFinger>::value,
                                                    CoulombPassTable<GraspT>, ContactPasses<GraspT>>::type;

/// True when y (unit) certifies infeasibility: y.w_ext > 0 and G_i^T y in K_i^* for all i, up
/// to `tol`: the distance from G_i^T y to K_i^* is at most tol (1 + |r_i|) (|r_i| in m: the
/// scale of G_i^T y for a unit y).
template <class GraspT>
bool is_infeasibility_certificate(const GraspT& grasp, const Wrench<typename GraspT::ScalarType>& w_ext,
                                  const Wrench<typename GraspT::ScalarType>& y,
                                  typename GraspT::ScalarType tol) {
  using S = typename GraspT::ScalarType;
  using M = typename GraspT::ModelType;
  using Cone = ExactConeT<M, S>;
  // The guard y.w_ext > tol |w_ext| keeps round-off directions out. In float it is tol/10
  // (2e-4 |w_ext|, still 1000 times float round-off): a nearly feasible grasp (cvxopt reference
  // instance 195: least residual 8e-4 |w_ext|) has a genuine certificate with y.w_ext of
  // 7.5e-4 |w_ext|, below the float tol of 2e-3.
  const S wtol = ConstrainedSettings<S>::is_float ? tol * S(0.1) : tol;
  if (!(y.dot(w_ext) > wtol * w_ext.norm())) return false;
  for (int i = 0; i < grasp.size(); ++i) {
    const auto& c = grasp.contact(i);
    const typename GraspT::ContactVector z = M::wrench_transpose(c, y);
    const auto dual = Cone::from_contact(c).dual();
    if (!((z - dual.project(z)).norm() <= tol * (S(1) + c.position.norm()))) return false;
  }
  return true;
}

/// Solves A y = b for a symmetric 6x6 A known to satisfy A >= floor I (here: a Jacobi-scaled
/// M + el I) by Cholesky with every pivot raised to at least `floor`, so that round-off can
/// neither break the factorisation nor hide the directions that only the floor keeps.
template <class Scalar>
Wrench<Scalar> solve_floored_6x6(const Matrix6<Scalar>& a, const Wrench<Scalar>& b, Scalar floor) {
  Matrix6<Scalar> l = a;
  Wrench<Scalar> inv;  // 1 / l(j, j): one division per pivot
  for (int j = 0; j < 6; ++j) {
    Scalar p = l(j, j);
    for (int k = 0; k < j; ++k) p -= l(j, k) * l(j, k);
    if (!(p > floor)) p = floor;
    p = std::sqrt(p);
    l(j, j) = p;
    inv(j) = Scalar(1) / p;
    for (int i = j + 1; i < 6; ++i) {
      Scalar t = l(i, j);
      for (int k = 0; k < j; ++k) t -= l(i, k) * l(j, k);
      l(i, j) = t * inv(j);
    }
  }
  Wrench<Scalar> z = b;
  for (int i = 0; i < 6; ++i) {
    for (int k = 0; k < i; ++k) z(i) -= l(i, k) * z(k);
    z(i) *= inv(i);
  }
  for (int i = 5; i >= 0; --i) {
    for (int k = i + 1; k < 6; ++k) z(i) -= l(k, i) * z(k);
    z(i) *= inv(i);
  }
  return z;
}

/// Solves A y = b for the symmetric positive definite Newton matrix A (6x6, Jacobi-scaled) by
/// 3x3 blocks: A = [[P, Q], [Q^T, R]], P^-1 and the Schur complement T = R - Q^T P^-1 Q inverted
/// by their adjugates (two divisions, no square root: the floored Cholesky's six square roots
/// and divisions form one chain of latencies). Taken in double only, and only when both 3x3
/// determinants exceed 1e-4 times the product of their diagonals and T's diagonal keeps 1e-4
/// of A's (no cancellation), so that the answer loses at most about 1e8 eps (backward error);
/// otherwise (and always in float, and for any non-finite input) solve_floored_6x6(a, b, floor).
template <class S>
Wrench<S> solve_newton_6x6(const Matrix6<S>& a, const Wrench<S>& b, S floor) {
  if constexpr (!std::is_same<S, double>::value) return solve_floored_6x6(a, b, floor);
  const S hadamard = S(1e-4);
  const S p00 = a(0, 0), p01 = a(0, 1), p02 = a(0, 2), p11 = a(1, 1), p12 = a(1, 2), p22 = a(2, 2);
  // adj(P) (symmetric) and det(P)
  const S c00 = p11 * p22 - p12 * p12, c01 = p02 * p12 - p01 * p22, c02 = p01 * p12 - p02 * p11,
          c11 = p00 * p22 - p02 * p02, c12 = p01 * p02 - p00 * p12, c22 = p00 * p11 - p01 * p01;
  const S dp = p00 * c00 + p01 * c01 + p02 * c02;
  if (!(dp > hadamard * p00 * p11 * p22) || !(p00 > S(0) && p11 > S(0) && p22 > S(0)))
    return solve_floored_6x6(a, b, floor);
  const S ip = S(1) / dp;
  // X = P^-1 Q (Q = rows 0-2, columns 3-5), then the Schur complement T = R - Q^T X.
  S x[3][3];
  for (int j = 0; j < 3; ++j) {
    const S q0 = a(0, 3 + j), q1 = a(1, 3 + j), q2 = a(2, 3 + j);
    x[0][j] = (c00 * q0 + c01 * q1 + c02 * q2) * ip;
    x[1][j] = (c01 * q0 + c11 * q1 + c12 * q2) * ip;
    x[2][j] = (c02 * q0 + c12 * q1 + c22 * q2) * ip;
  }
  const auto t = [&](int i, int j) {
    return a(3 + i, 3 + j) - (a(0, 3 + i) * x[0][j] + a(1, 3 + i) * x[1][j] + a(2, 3 + i) * x[2][j]);
  };
  const S t00 = t(0, 0), t01 = t(0, 1), t02 = t(0, 2), t11 = t(1, 1), t12 = t(1, 2), t22 = t(2, 2);
  const S d00 = t11 * t22 - t12 * t12, d01 = t02 * t12 - t01 * t22, d02 = t01 * t12 - t02 * t11,
          d11 = t00 * t22 - t02 * t02, d12 = t01 * t02 - t00 * t12, d22 = t00 * t11 - t01 * t01;
  const S dt = t00 * d00 + t01 * d01 + t02 * d02;
  // T's diagonal must not have cancelled (t_ii against a_ii), nor its determinant against its
  // diagonal.
  if (!(dt > hadamard * t00 * t11 * t22) || !(t00 > hadamard * a(3, 3) && t11 > hadamard * a(4, 4) &&
                                               t22 > hadamard * a(5, 5)))
    return solve_floored_6x6(a, b, floor);
  const S it = S(1) / dt;
  // u = P^-1 b_1; y_2 = T^-1 (b_2 - Q^T u); y_1 = u - X y_2.
  const S u0 = (c00 * b(0) + c01 * b(1) + c02 * b(2)) * ip, u1 = (c01 * b(0) + c11 * b(1) + c12 * b(2)) * ip,
          u2 = (c02 * b(0) + c12 * b(1) + c22 * b(2)) * ip;
  const S r0 = b(3) - (a(0, 3) * u0 + a(1, 3) * u1 + a(2, 3) * u2);
  const S r1 = b(4) - (a(0, 4) * u0 + a(1, 4) * u1 + a(2, 4) * u2);
  const S r2 = b(5) - (a(0, 5) * u0 + a(1, 5) * u1 + a(2, 5) * u2);
  Wrench<S> y;
  y(3) = (d00 * r0 + d01 * r1 + d02 * r2) * it;
  y(4) = (d01 * r0 + d11 * r1 + d12 * r2) * it;
  y(5) = (d02 * r0 + d12 * r1 + d22 * r2) * it;
  y(0) = u0 - (x[0][0] * y(3) + x[0][1] * y(4) + x[0][2] * y(5));
  y(1) = u1 - (x[1][0] * y(3) + x[1][1] * y(4) + x[1][2] * y(5));
  y(2) = u2 - (x[2][0] * y(3) + x[2][1] * y(4) + x[2][2] * y(5));
  return y;
}

/// Phase 1: forces in the cones that come closest to equilibrium. Solves
///   min over x in the cones of 1/2 |G x + w_ext|^2 + delta/2 sum_i w_i |x_i - t_i|^2
/// (delta small: the least residual, ties broken by F2) through its strongly concave dual
///   phi(l) = -1/2 |l|^2 + l.(G x(l) + w_ext) + delta F2(x(l)), x_i(l) = P_i(t_i - G_i^T l/(delta w_i)),
/// by the same semi-smooth Newton method (Hessian -(I + sum G_i J_i G_i^T/(delta w_i))). At its
/// maximiser l = G x + w_ext. For ANY l, x_i(l) is a projection, so G_i^T l + delta w_i (x_i - t_i)
/// lies in K_i^* exactly: l/|l| is an infeasibility certificate up to delta w_i |x_i - t_i| / |l|.
/// Writes the forces into x, the multipliers into lambda, and returns the iterations used (at
/// most settings.max_iterations).
template <class Passes>
int least_residual(const Passes& passes, const Wrench<typename Passes::Scalar>& w_ext, typename Passes::Scalar delta,
                   const ConstrainedSettings<typename Passes::Scalar>& settings, typename Passes::Forces& x,
                   Wrench<typename Passes::Scalar>& lambda, typename Passes::Scalar& f2) {
  using S = typename Passes::Scalar;
  const S eps = std::numeric_limits<S>::epsilon();
  typename Passes::Forces xt = passes.make_forces();
  // The Hessian sums at the current point and at the line-search point, from their passes.
  GramAccumulator<S> cur_h, trial_h;
  lambda.setZero();
  // Continuation: delta starts at delta_max (a well-scaled problem) and drops 100-fold each
  // time the current problem is solved, down to the requested delta (warm-started each time).
  S dl = delta;
  const S delta_max = delta / settings.least_residual_weight;
  while (dl * S(100) <= delta_max) dl *= S(100);
  const auto phi = [&](const ConstrainedPass<S>& p, const Wrench<S>& l) {
    return -S(0.5) * l.squaredNorm() + l.dot(p.residual) + dl * p.f2;
  };
  ConstrainedPass<S> cur = passes.pass(w_ext, Wrench<S>(-lambda / dl), x, &cur_h);
  S cur_phi = phi(cur, lambda);
  // The forces returned are the best point met by the requested problem's objective
  // |r|^2/2 + delta F2: at the last, tiny delta, x(l) is so sensitive to l that the last
  // iterate's forces can lie far from the least residual even though l itself is right.
  typename Passes::Forces best = passes.make_forces();
  S best_objective = std::numeric_limits<S>::infinity(), best_f2 = S(0);
  const auto keep = [&]() {
    const S p = S(0.5) * cur.residual.squaredNorm() + delta * cur.f2;
    if (p < best_objective) {
      best_objective = p;
      best_f2 = cur.f2;
      best = x;
    }
  };
  keep();
  // The next stage of the continuation, from the current l: false when this one was the last.
  const auto next_stage = [&]() {
    if (!(dl > delta)) return false;
    dl = dl / S(100) < delta ? delta : dl / S(100);
    cur = passes.pass(w_ext, Wrench<S>(-lambda / dl), x, &cur_h);
    cur_phi = phi(cur, lambda);
    keep();
    return true;
  };
  int it = 0;
  for (; it < settings.max_iterations; ++it) {
    const Wrench<S> g = cur.residual - lambda;  // grad phi
    if (g.norm() <= settings.tolerance * cur.scale || (dl > delta && g.norm() <= S(1e-3f) * cur.scale)) {
      if (!next_stage()) break;
      continue;
    }
    Matrix6<S> h = cur_h.matrix();
    h.diagonal().array() += dl;
    const Wrench<S> e = h.diagonal().cwiseSqrt().cwiseInverse();
    const Matrix6<S> hs = e.asDiagonal() * h * e.asDiagonal();
    const Wrench<S> dir = e.cwiseProduct(solve_newton_6x6(hs, Wrench<S>(dl * e.cwiseProduct(g)), S(16) * eps));
    const S slope = g.dot(dir);
    if (dir.norm() <= S(4) * eps * (lambda.norm() + cur.scale) || !(slope > S(0))) {  // at round-off
      if (!next_stage()) break;
      continue;
    }
    if (!dir.allFinite()) break;  // slope > 0 here: the branch above took the rest
    bool accepted = false;
    S alpha = S(1);
    Wrench<S> lt;
    ConstrainedPass<S> trial;
    S trial_phi = cur_phi;
    for (int ls = 0; ls < settings.max_line_search; ++ls, alpha *= S(0.5)) {
      lt = lambda + alpha * dir;
      trial = passes.pass(w_ext, Wrench<S>(-lt / dl), xt, &trial_h);
      trial_phi = phi(trial, lt);
      const S slack = S(16) * eps * (std::abs(cur_phi) + std::abs(trial_phi) + lt.squaredNorm());
      if (trial_phi >= cur_phi + S(1e-4f) * alpha * slope - slack) {
        accepted = true;
        break;
      }
    }
    if (!accepted) {
      if (!next_stage()) break;
      continue;
    }
    lambda = lt;
    x = xt;
    cur_h = trial_h;
    cur = trial;
    cur_phi = trial_phi;
    keep();
  }
  x = best;
  f2 = best_f2;
  return it;
}

template <class Scalar>
bool valid_settings(const ConstrainedSettings<Scalar>& s) {
  const auto pos = [](Scalar v) { return std::isfinite(v) && v > Scalar(0); };
  return pos(s.tolerance) && pos(s.gap_tolerance) && pos(s.regularisation) && pos(s.certificate_tolerance) &&
         pos(s.least_residual_weight) &&
         s.max_iterations >= 1 && s.max_line_search >= 1;
}

template <class GraspT>
void fill_invalid(ConstrainedSolution<GraspT>& sol, int unknowns) {
  sol.forces.setZero(unknowns);
  sol.multipliers.setZero();
  sol.status = Status::InvalidInput;
  sol.residual = std::numeric_limits<typename GraspT::ScalarType>::max();
  sol.iterations = 0;
}

/// The fast path: the unconstrained optimum (solve_range_space's), returned as the answer when
/// every force is in its cone with f_n > 0 (a feasible minimiser of the relaxed problem solves
/// the constrained one). Writes it into `sol` and its multipliers into `lambda`; returns true
/// if it is the answer (status Ok, fast_path true). One solve_range_space plus one
/// square-root-free cone test per contact (Cone::slips with zero slack; for hard fingers all
/// contacts at once by detail::coulomb_all_inside, vectorised where compiled in). The diagonal
/// of G W^-1 G^T goes to `gram_diagonal` (see range_space_solve).
template <class GraspT>
bool constrained_fast_path(const GraspT& grasp, const Wrench<typename GraspT::ScalarType>& w_ext,
                           ConstrainedSolution<GraspT>& sol, Wrench<typename GraspT::ScalarType>& lambda,
                           Wrench<typename GraspT::ScalarType>& gram_diagonal) {
  using S = typename GraspT::ScalarType;
  using Cone = ExactConeT<typename GraspT::ModelType, S>;
  constexpr int d = GraspT::dim;
  Wrench<S> rhs, res;
  // solve_constrained_impl has checked the grasp and w_ext.
  if (!range_space_solve(grasp, w_ext, sol, rhs, res, &gram_diagonal, true)) return false;
  lambda = sol.multipliers;
  bool inside = sol.status == Status::Ok;
  if constexpr (std::is_same<Cone, CoulombCone<S>>::value) {
    // All contacts at once (SIMD where compiled in; see coulomb_kernel.hpp), zero slack.
    inside = inside && detail::coulomb_all_inside_grasp(grasp, sol.forces);
  } else {
    for (int i = 0; i < grasp.size() && inside; ++i) {
      const Cone cone = Cone::from_contact(grasp.contact(i));
      const typename Cone::Vector x = sol.forces.template segment<d>(i * d);
      inside = cone.normal_part(x) > S(0) && !cone.slips(x, S(0));
    }
  }
  if (!inside) return false;
  // F2(x) = 1/2 lambda^T M lambda = 1/2 lambda.(rhs + res); the dual is F2 - lambda.res.
  const S l_rhs = lambda.dot(rhs), l_res = lambda.dot(res);
  sol.objective = S(0.5) * (l_rhs + l_res);
  sol.dual_objective = S(0.5) * (l_rhs - l_res);
  sol.iterations = 0;
  sol.fast_path = true;
  return true;
}

/// solve_constrained's iteration, after the fast path failed: `lambda` and `gram_diagonal` as
/// constrained_fast_path left them, every field of `sol` written. Kept out of line so that
/// the fast path (the common case of a real-time loop) does not pay for its frame.
template <class GraspT>
EIGEN_DONT_INLINE void constrained_iterate(const GraspT& grasp, const Wrench<typename GraspT::ScalarType>& w_ext,
                                           const ConstrainedSettings<typename GraspT::ScalarType>& settings,
                                           const Wrench<typename GraspT::ScalarType>* warm,
                                           Wrench<typename GraspT::ScalarType> lambda,
                                           const Wrench<typename GraspT::ScalarType>& gram_diagonal,
                                           ConstrainedSolution<GraspT>& sol) {
  using S = typename GraspT::ScalarType;
  using FV = typename GraspT::ForceVector;
  const int m = grasp.unknowns();
  const S eps = std::numeric_limits<S>::epsilon();
  fill_invalid(sol, m);
  lambda = warm != nullptr ? *warm : (lambda.allFinite() ? lambda : Wrench<S>::Zero());
  Wrench<S> jacobi = gram_diagonal;
  // Jacobi scaling D of the Levenberg-Marquardt term: the unconstrained Gram diagonal, floored.
  const S jmax = jacobi.maxCoeff();
  for (int k = 0; k < 6; ++k) jacobi(k) = jacobi(k) > S(1e-6f) * jmax ? jacobi(k) : S(1e-6f) * jmax;
  const Wrench<S> dinv = jacobi.cwiseSqrt().cwiseInverse();

  const ConstrainedPasses<GraspT> passes(grasp);  // hard fingers: copied into columns once
  typename ConstrainedPasses<GraspT>::Forces x = passes.make_forces(), xt = passes.make_forces();
  GramAccumulator<S> cur_h, trial_h;  // the Hessian sums at lambda and at the line-search point
  ConstrainedPass<S> cur = passes.pass(w_ext, lambda, x, &cur_h);
  const S armijo = S(1e-4f);
  const S reg = settings.regularisation;
  S damping = S(1);  // Levenberg-Marquardt state: /10 after a full step, *4 after a cut one
  Status status = Status::IterationLimit;
  int it = 0;
  int stall = 0;
  int phase1_iterations = 0;  // counted apart: the Newton budget stays max_iterations
  bool phase1_done = false;
  // Phase 1: the least-residual forces; Infeasible (with those forces and multipliers) if the
  // direction of its multipliers checks out as a certificate. The verdict is kept pending in
  // `p_*` and applied by apply_infeasible().
  Wrench<S> p_cert = Wrench<S>::Zero(), p_y = Wrench<S>::Zero(), p_r = Wrench<S>::Zero();
  S p_f2 = S(0);
  typename ConstrainedPasses<GraspT>::Forces p_x = passes.make_forces();
  Wrench<S> p_lambda = Wrench<S>::Zero();
  const auto decide_infeasible = [&]() {
    Wrench<S> y;
    S f2 = S(0);
    S delta = settings.least_residual_weight * jacobi.maxCoeff();
    // y is (to delta) the least residual: a feasible problem leaves only round-off there. The
    // bar is 1000 tolerance |w_ext| in double, but 10 tolerance |w_ext| (1e-4 relative) in
    // float: there least residuals of 1e-3 |w_ext| (below 1000 tolerance = 1e-2) are genuine
    // (cvxopt reference instances), while round-off stays near 1e-6.
    const S bar = (ConstrainedSettings<S>::is_float ? S(10) : S(1000)) * settings.tolerance * w_ext.norm();
    bool ok = false;
    // The certificate's error is delta w_i |x_i - t_i| / |y|; nearly infeasible grasps need large
    // least-residual forces, so in float (where delta is 1e-6) the solve is retried with delta
    // 100 and 10^4 times smaller when the first certificate misses the tolerance.
    const int tries = ConstrainedSettings<S>::is_float ? 3 : 1;
    phase1_iterations = 0;
    // The tries share one budget of settings.max_iterations iterations.
    ConstrainedSettings<S> budget = settings;
    for (int k = 0; k < tries && !ok && phase1_iterations < settings.max_iterations; ++k, delta *= S(0.01)) {
      budget.max_iterations = settings.max_iterations - phase1_iterations;
      phase1_iterations += least_residual(passes, w_ext, delta, budget, p_x, y, f2);
      p_lambda = -y / delta;  // the penalty estimate of the multipliers (x(p_lambda) = p_x)
      const S rn = y.norm();
      if (rn > bar) {
        p_cert = y / rn;
        ok = is_infeasibility_certificate(grasp, w_ext, p_cert, settings.certificate_tolerance);
      }
    }
    // Second candidate: the direction -lambda of the diverging Newton multipliers. x_i(lambda) is a
    // projection, so -G_i^T lambda lies in K_i^* up to w_i |x_i - t_i| / |lambda|: a certificate
    // when |lambda| has grown large (float phase-1 solves can stop short of the tolerance).
    const S ln = lambda.norm();
    // Used in float only: the double results are validated with the phase-1 certificate alone.
    if (ConstrainedSettings<S>::is_float && !ok && ln > S(0) && lambda.allFinite()) {
      p_cert = -lambda / ln;
      ok = is_infeasibility_certificate(grasp, w_ext, p_cert, settings.certificate_tolerance);
    }
    if (!ok) return false;
    p_y = y;
    p_f2 = f2;
    FV forces(m);
    passes.store(p_x, forces);
    p_r = grasp.wrench(forces) + w_ext;
    return true;
  };
  const auto apply_infeasible = [&]() {
    status = Status::Infeasible;
    sol.certificate = p_cert;
    x = p_x;
    lambda = p_y;
    cur.residual = p_r;
    cur.f2 = p_f2;
    cur.dual = p_f2 - lambda.dot(p_r);
  };
  // Float only: a certificate found on a stall is applied only if Newton has not converged
  // within `grace` more iterations (a nearly infeasible feasible instance can stall early and
  // pass the float certificate tolerance, 2e-3). Double keeps the immediate verdict.
  bool pending = false;
  int grace = ConstrainedSettings<S>::is_float ? 12 : 0;
  for (;; ++it) {
    const S rn = cur.residual.norm();
    const S floor = S(16) * eps * cur.scale;
    if (rn <= floor ||
        (rn <= settings.tolerance * cur.scale && std::abs(lambda.dot(cur.residual)) <= settings.gap_tolerance * cur.f2)) {
      status = Status::Ok;
      break;
    }
    if (it >= settings.max_iterations) break;
    // Newton direction: (H + mu D) d = -r, H = sum w^-1 G J G^T, solved Jacobi-scaled;
    // mu = min(damping, |r|/scale) + reg: quadratic convergence near the optimum, and steps
    // that grow geometrically along a direction of unbounded ascent (infeasible problems).
    Matrix6<S> h = cur_h.matrix();
    const S rel = cur.scale > S(0) ? rn / cur.scale : S(1);
    const S mu = (damping < rel ? damping : rel) + reg;
    h.diagonal() += mu * jacobi;
    const Matrix6<S> hs = dinv.asDiagonal() * h * dinv.asDiagonal();
    const Wrench<S> dir = dinv.cwiseProduct(solve_newton_6x6(hs, Wrench<S>(-dinv.cwiseProduct(cur.residual)), mu));
    const S slope = -cur.residual.dot(dir);  // q'(0) along dir, > 0
    bool accepted = false;
    ConstrainedPass<S> trial;
    Wrench<S> lt;
    int cuts = 0;
    if (slope > S(0) && dir.allFinite()) {
      S alpha = S(1);
      for (; cuts < settings.max_line_search; ++cuts, alpha *= S(0.5)) {
        lt = lambda + alpha * dir;
        trial = passes.pass(w_ext, lt, xt, &trial_h);
        const S slack = S(16) * eps * (std::abs(trial.dual) + std::abs(cur.dual) + std::abs(cur.f2));
        if (trial.dual >= cur.dual + armijo * alpha * slope - slack) {
          accepted = true;
          break;
        }
      }
    }
    if (!accepted) {  // no ascent left at round-off
      if (rn <= settings.tolerance * cur.scale) status = Status::Ok;
      break;
    }
    damping = cuts == 0 ? damping * S(0.1) : (damping * S(4) < S(1) ? damping * S(4) : S(1));
    if (damping < reg) damping = reg;
    lambda = lt;
    x = xt;
    cur_h = trial_h;
    const S rn_new = trial.residual.norm();
    cur = trial;
    // Slow progress (the residual no longer halves) suggests that no forces in the cones
    // balance w_ext: decide it once by the least-residual problem. After 8 such iterations in
    // a row, not 3: feasible instances whose active set is still settling (nearly infeasible
    // ones, with forces of 1000 N for a 5 N load) stall for 3 to 7 and then converge, and the
    // least-residual solve spent on them cost 20 to 30 iterations (bench_constrained's
    // instances: mean iterations 21.7 -> 10.0 at n = 3, worst 39 -> 8 at n = 20).
    constexpr int stall_limit = 8;
    stall = rn_new > S(0.5) * rn ? stall + 1 : 0;
    if (stall >= stall_limit && !phase1_done) {
      phase1_done = true;
      if (decide_infeasible()) {
        pending = true;
        if (grace <= 0) break;
      } else if (p_lambda.allFinite()) {
        // Feasible after all: the least-residual solve is a penalty approximation of this
        // problem, so -y/delta estimates the multipliers; continue from it if the dual is higher.
        ConstrainedPass<S> alt = passes.pass(w_ext, p_lambda, xt, &trial_h);
        if (alt.dual > cur.dual && std::isfinite(alt.dual)) {
          lambda = p_lambda;
          x = xt;
          cur_h = trial_h;
          cur = alt;
          stall = 0;
        }
      }
    } else if (pending && --grace <= 0) {
      break;
    }
  }
  if (status == Status::IterationLimit) {
    if (pending || (!phase1_done && decide_infeasible())) apply_infeasible();
  }
  passes.store(x, sol.forces);
  sol.multipliers = lambda;
  sol.residual = stable_norm(cur.residual);
  sol.objective = cur.f2;
  sol.dual_objective = cur.dual;
  sol.iterations = it + phase1_iterations;
  sol.status = status;
  if (!sol.forces.allFinite() || !sol.multipliers.allFinite() || !std::isfinite(sol.dual_objective)) {
    sol.forces.setZero(m);
    sol.multipliers.setZero();
    sol.residual = stable_norm(w_ext);
    sol.objective = S(0);
    sol.dual_objective = S(0);
    if (sol.status == Status::Ok) sol.status = Status::IterationLimit;
  }
}

template <class GraspT>
ConstrainedSolution<GraspT> solve_constrained_impl(const GraspT& grasp,
                                                   const Wrench<typename GraspT::ScalarType>& w_ext,
                                                   const ConstrainedSettings<typename GraspT::ScalarType>& settings,
                                                   const Wrench<typename GraspT::ScalarType>* warm) {
  using S = typename GraspT::ScalarType;
  const int m = grasp.unknowns();
  ConstrainedSolution<GraspT> sol;
  if (!grasp.complete() || validate(w_ext) != Status::Ok || !valid_settings(settings) ||
      (warm != nullptr && !(detail::all_in_range(*warm)))) {
    fill_invalid(sol, m);
    return sol;
  }

  if (grasp.size() == 0) {  // nothing can push: feasible only for w_ext = 0
    fill_invalid(sol, m);
    sol.residual = stable_norm(w_ext);
    if (sol.residual == S(0)) {
      sol.status = Status::Ok;
    } else {
      sol.status = Status::Infeasible;
      sol.certificate = w_ext / sol.residual;
    }
    return sol;
  }

  // Start: the unconstrained optimum (returned at once if strictly inside), or the warm start.
  // The fast path writes every field of sol that an Ok answer documents (the rest keep their
  // constructed values); constrained_iterate resets it for any other outcome.
  Wrench<S> lambda = Wrench<S>::Zero();
  Wrench<S> gram_diagonal = Wrench<S>::Zero();  // of G W^-1 G^T, from the fast path's solve
  if (constrained_fast_path(grasp, w_ext, sol, lambda, gram_diagonal)) return sol;
  constrained_iterate(grasp, w_ext, settings, warm, lambda, gram_diagonal, sol);
  return sol;
}

}  // namespace detail

/// The exact optimum of min 1/2 sum_i w_i |x_i - t_i|^2 s.t. G x + w_ext = 0, x_i in K_i
/// (K_i = ExactConeT<Model, Scalar>, see exact_cone.hpp), for any Grasp (fixed or Dynamic,
/// any model, float or double). No heap, no exceptions; at most settings.max_iterations
/// Newton iterations of O(n) each, each with at most settings.max_line_search O(n) passes, plus
/// (only when infeasibility is suspected) as many again for the least-residual problem;
/// `iterations` counts both.
///
/// Fast path, always tried first: solve_range_space's unconstrained optimum; if every force is
/// in its cone with f_n > 0 it is the answer (status Ok, iterations 0, fast_path true).
/// Otherwise the iteration starts from that optimum's multipliers (cold start), or from the
/// previous frame's `multipliers` when given (warm start: a 6-vector, so the contact count may
/// change between frames).
///
/// Statuses and numbers:
/// - Ok: |G x + w_ext| <= tolerance (|w_ext| + |x|) with duality gap |lambda.(G x + w_ext)| <=
///   gap_tolerance F2 (or the residual is at round-off). `forces` are in their cones, the KKT
///   conditions of every contact hold exactly (x_i is a projection), `objective` is F2.
/// - Infeasible: no forces in the cones balance w_ext (the grasp slips). `certificate` holds y
///   (see ConstrainedSolution). `forces` come closest: the best point, by the least-residual
///   objective |G x + w_ext|_2^2/2 + delta F2(x), that its solve over the cones meets (delta =
///   least_residual_weight times the largest Jacobi entry of G W^-1 G^T), i.e. about the
///   smallest equilibrium residual (Euclidean, N and N m mixed as in `residual`), ties broken
///   by F2; within 1e-5 (double) and 1e-2 (float) of the forces' scale of it on the cvxopt
///   reference instances.
///   `multipliers` are then that problem's (y = multipliers/|multipliers|).
///   Decided when the Newton iteration stalls (the residual fails to halve 8 times in a row) or
///   at its iteration bound; the least-residual solve has its own max_iterations bound. In
///   float the least-residual solve is retried with a 100 and 10^4 times smaller delta (within
///   that one bound) if its certificate misses the tolerance, the direction of the diverging
///   Newton multipliers is tried as a second certificate, and a certificate found on a stall is
///   used only if Newton has not converged within 12 more iterations.
/// - IterationLimit: the bound was reached (or the line search stalled) before the tolerance;
///   `forces` = x(lambda) of the last iterate (in the cones), `residual` what is left.
/// - InvalidInput: incomplete grasp, bad w_ext, bad settings or a non-finite warm start: zeros.
/// A grasp matrix of rank < 6 is not an error here: the answer is Ok if the wrench can still be
/// balanced inside the cones, Infeasible (with a certificate) otherwise.
template <class GraspT>
ConstrainedSolution<GraspT> solve_constrained(
    const GraspT& grasp, const Wrench<typename GraspT::ScalarType>& w_ext,
    const ConstrainedSettings<typename GraspT::ScalarType>& settings = ConstrainedSettings<typename GraspT::ScalarType>{}) {
  return detail::solve_constrained_impl(grasp, w_ext, settings, nullptr);
}

/// As above, warm-started from `warm_multipliers` (the previous frame's solution.multipliers).
template <class GraspT>
ConstrainedSolution<GraspT> solve_constrained(const GraspT& grasp, const Wrench<typename GraspT::ScalarType>& w_ext,
                                              const ConstrainedSettings<typename GraspT::ScalarType>& settings,
                                              const Wrench<typename GraspT::ScalarType>& warm_multipliers) {
  return detail::solve_constrained_impl(grasp, w_ext, settings, &warm_multipliers);
}

}  // namespace grip
