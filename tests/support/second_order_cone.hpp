#pragma once
// The second-order cone Q = {u in R^m : u_0 >= |(u_1, ..., u_{m-1})|} one cone at a time, as
// the definitions of grip/analysis/detail/cone_lanes.hpp read (m = 1 is the half-line
// u_0 >= 0): the reference that conic_dual.test checks the solver's lane-wise algebra against,
// itself checked against the defining identities there.

#include <algorithm>
#include <cmath>
#include <limits>

#include <Eigen/Core>

namespace grip_test {

template <class S, int M>
using SocVector = Eigen::Matrix<S, M, 1>;

// |(u_1, ..., u_{m-1})|.
template <class S, int M>
S soc_tail_norm(const SocVector<S, M>& u) {
  if constexpr (M > 1) return u.template tail<M - 1>().norm();
  else return S(0);
}

// u^T J u = u_0^2 - |u_1|^2, computed as (u_0 - |u_1|)(u_0 + |u_1|) to keep its relative
// accuracy near the boundary.
template <class S, int M>
S soc_det(const SocVector<S, M>& u) {
  const S t = soc_tail_norm(u);
  return (u(0) - t) * (u(0) + t);
}

// u in the interior of Q.
template <class S, int M>
bool soc_interior(const SocVector<S, M>& u) {
  return u(0) > soc_tail_norm(u) && std::isfinite(u(0));
}

// J u.
template <class S, int M>
SocVector<S, M> soc_reflect(const SocVector<S, M>& u) {
  SocVector<S, M> r = -u;
  r(0) = u(0);
  return r;
}

// The Jordan product u o v.
template <class S, int M>
SocVector<S, M> soc_product(const SocVector<S, M>& u, const SocVector<S, M>& v) {
  SocVector<S, M> r = u(0) * v + v(0) * u;
  r(0) = u.dot(v);
  return r;
}

// The d with lambda o d = r, for lambda in int Q: d_0 = (lambda_0 r_0 - lambda_1 . r_1) /
// det(lambda), d_1 = (r_1 - d_0 lambda_1) / lambda_0.
template <class S, int M>
SocVector<S, M> soc_divide(const SocVector<S, M>& lambda, const SocVector<S, M>& r) {
  SocVector<S, M> d;
  const S l1r1 = lambda.dot(r) - lambda(0) * r(0);
  d(0) = (lambda(0) * r(0) - l1r1) / soc_det(lambda);
  if constexpr (M > 1) d.template tail<M - 1>() = (r.template tail<M - 1>() - d(0) * lambda.template tail<M - 1>()) / lambda(0);
  return d;
}

// The largest step a >= 0 with u + a d in Q, for u in int Q (infinity when the ray stays
// inside): the least positive root of det(u + a d) = A a^2 + 2 B a + C, with C = det(u) > 0,
// and at most -u_0 / d_0 when d_0 < 0 (u_0 + a d_0 >= 0 is necessary). The second bound also
// decides the rays along which det has a double root that rounding can hide (d parallel to
// the axis, as for a cone whose tangential rows are zero).
template <class S, int M>
S soc_max_step(const SocVector<S, M>& u, const SocVector<S, M>& d) {
  const S inf = std::numeric_limits<S>::infinity();
  S best = d(0) < S(0) ? -u(0) / d(0) : inf;
  if constexpr (M > 1) {
    const S A = soc_det(d), C = soc_det(u);
    const S B = u(0) * d(0) - u.template tail<M - 1>().dot(d.template tail<M - 1>());
    const S disc = B * B - A * C;
    if (A == S(0)) {
      if (B < S(0)) best = std::min(best, -C / (S(2) * B));
    } else if (disc >= S(0)) {
      // Roots (-B -+ sqrt(disc)) / A; the cancellation-free pair q / A and C / q.
      const S q = -(B + std::copysign(std::sqrt(disc), B));
      if (q != S(0)) {
        const S r1 = q / A, r2 = C / q;
        if (r1 > S(0)) best = std::min(best, r1);
        if (r2 > S(0)) best = std::min(best, r2);
      }
    }  // disc < 0 (A > 0): no real root; the ray stays inside the cone's interior
  }
  return best;
}

// The Nesterov-Todd scaling of a pair s, z in int Q (see the file comment).
template <class S, int M>
struct SocScaling {
  S beta{1};
  S inv_beta{1};  // 1 / beta
  SocVector<S, M> v{SocVector<S, M>::Unit(0)};

  // False if s or z is not in the interior.
  bool set(const SocVector<S, M>& s, const SocVector<S, M>& z) {
    const S ds = soc_det(s), dz = soc_det(z);
    if (!(ds > S(0)) || !(dz > S(0)) || !(s(0) > S(0)) || !(z(0) > S(0))) return false;
    const SocVector<S, M> sn = s / std::sqrt(ds), zn = z / std::sqrt(dz);
    const S gamma = std::sqrt((S(1) + zn.dot(sn)) / S(2));
    SocVector<S, M> w = (sn + soc_reflect(zn)) / (S(2) * gamma);
    const S w0 = w(0);
    w(0) += S(1);
    v = w / std::sqrt(S(2) * (w0 + S(1)));
    beta = std::sqrt(std::sqrt(ds / dz));
    inv_beta = S(1) / beta;
    return std::isfinite(beta) && std::isfinite(inv_beta) && v.allFinite();
  }
  // W u.
  SocVector<S, M> apply(const SocVector<S, M>& u) const { return beta * (S(2) * v.dot(u) * v - soc_reflect(u)); }
  // W^-1 u.
  SocVector<S, M> apply_inverse(const SocVector<S, M>& u) const {
    const SocVector<S, M> jv = soc_reflect(v);
    return inv_beta * (S(2) * jv.dot(u) * jv - soc_reflect(u));
  }
  // W^-1 A for a matrix A of M rows, into out: (2 Jv (Jv^T A) - J A) / beta.
  template <int C>
  void apply_inverse_to(const Eigen::Matrix<S, M, C>& A, Eigen::Matrix<S, M, C>& out) const {
    const SocVector<S, M> jv = soc_reflect(v);
    const Eigen::Matrix<S, 1, C> r = (S(2) * inv_beta) * (jv.transpose() * A);
    out.noalias() = jv * r;
    out.row(0) -= inv_beta * A.row(0);
    if constexpr (M > 1) out.template bottomRows<M - 1>() += inv_beta * A.template bottomRows<M - 1>();
  }
};

}  // namespace grip_test
