#pragma once
// The second-order cone Q = {u in R^m : u_0 >= |(u_1, ..., u_{m-1})|} one cone at a time, as
// the definitions of grip/solve/detail/cone_packs.hpp read (m = 1 is the half-line u_0 >= 0):
// the reference that solve/cone_packs.test checks the lane-wise algebra against, beside the
// defining identities.

#include <cmath>

#include <Eigen/Core>

namespace grip_test {

template <class S, int M>
using SocVector = Eigen::Matrix<S, M, 1>;

// |(u_1, ..., u_{m-1})|.
template <class S, int M>
S soc_tail_norm(const SocVector<S, M>& u) {
  if constexpr (M > 1)
    return u.template tail<M - 1>().norm();
  else
    return S(0);
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
  if constexpr (M > 1)
    d.template tail<M - 1>() = (r.template tail<M - 1>() - d(0) * lambda.template tail<M - 1>()) / lambda(0);
  return d;
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
};

}  // namespace grip_test
